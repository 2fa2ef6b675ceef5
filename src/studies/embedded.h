/* Case files of cases/ that the studies read, embedded at build time (cmake/embed.cmake), so that
 * a value such as the PSL sphere's modulus has one home: the case file. */
#ifndef ADEM_STUDIES_EMBEDDED_H
#define ADEM_STUDIES_EMBEDDED_H

extern const char adem_case_haervig_psl_quartz_yaml[]; /* cases/haervig/psl-quartz.yaml */
extern const char adem_case_irazabal_pile_yaml[];      /* cases/irazabal/pile.yaml */
extern const char adem_case_irazabal_repose_yaml[];    /* cases/irazabal/repose.yaml */
/* cases/irazabal/meshes/repose_hopper.stl (ASCII) */
extern const char adem_case_irazabal_meshes_repose_hopper_stl[];

/* cases/irazabal/ballast/: the packing, the push and their meshes (full size and quick/) */
extern const char adem_case_irazabal_ballast_pack_yaml[];
extern const char adem_case_irazabal_ballast_push_yaml[];
#define ADEM_BALLAST_MESH(m)                                       \
  extern const char adem_case_irazabal_ballast_meshes_##m##_stl[]; \
  extern const char adem_case_irazabal_ballast_meshes_quick_##m##_stl[];
ADEM_BALLAST_MESH(container)
ADEM_BALLAST_MESH(sides)
ADEM_BALLAST_MESH(aux_slopes)
ADEM_BALLAST_MESH(aux_sleeper)
ADEM_BALLAST_MESH(fill_region)
ADEM_BALLAST_MESH(sleeper)
#undef ADEM_BALLAST_MESH

#endif
