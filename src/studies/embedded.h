/* Case files of cases/ that the studies read, embedded at build time (cmake/embed.cmake), so that
 * a value such as the PSL sphere's modulus has one home: the case file. */
#ifndef ADEM_STUDIES_EMBEDDED_H
#define ADEM_STUDIES_EMBEDDED_H

extern const char adem_case_haervig_psl_quartz_yaml[]; /* cases/haervig/psl-quartz.yaml */
extern const char adem_case_irazabal_pile_yaml[];      /* cases/irazabal/pile.yaml */
extern const char adem_case_irazabal_repose_yaml[];    /* cases/irazabal/repose.yaml */
/* cases/irazabal/meshes/repose_hopper.stl (ASCII) */
extern const char adem_case_irazabal_meshes_repose_hopper_stl[];

#endif
