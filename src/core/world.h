/* Internal layout of the world. Hot per-particle data in structure-of-arrays form; contacts in
 * flat arrays. Only library modules and tests include this. */
#ifndef ADEM_WORLD_INTERNAL_H
#define ADEM_WORLD_INTERNAL_H

#include <stdbool.h>
#include "adem/adem.h"
#include "mesh_contact.h"
#include "mesh.h"
#include "motion.h"
#include "pairs.h"
#include "stream.h"
#include "particles.h"
#include "adem/vec3.h"

/* A material after derivation: the real values plus those the contact laws use. */
typedef struct adem_material {
  adem_material_def def;
  double young_mod;   /* E_mod = f E (H24) */
  double shear_mod;   /* G_mod = E_mod / (2(1+nu)) */
} adem_material;

/* Everything about a pair of materials that does not depend on the particles (H2, H12, H15). */
typedef struct adem_interaction {
  adem_normal_model normal;
  adem_rolling_model rolling;
  double E;       /* effective Young's modulus 1/E = sum (1-nu^2)/E_k, modified stiffness */
  double G;       /* effective shear modulus, 1/G = sum (2-nu_k)/G_k (H15) */
  double E_real;  /* effective modulus of the real material (f = 1) */
  double G_real;
  double restitution;
  double beta;    /* ln e / sqrt(ln^2 e + pi^2) <= 0 (H12) */
  double friction;
  double gamma;     /* effective surface energy for JKR, modified (H24) */
  double gamma_real;
  double hysteresis;
  double rolling_friction_a, rolling_friction_b; /* eta_r of each side (BROF uses both) */
  double rolling_damping;
  bool set_restitution, set_friction; /* overridden by an interaction entry */
  bool dtk_rolling_modification;      /* see adem_interaction_def */
} adem_interaction;

typedef struct adem_group {
  char name[ADEM_NAME_MAX];
  adem_vec3 external_force; /* N per particle, constant (H3) */
} adem_group;

typedef struct adem_plane {
  adem_plane_def def;      /* point and unit normal where the plane is now */
  adem_vec3 point0, normal0; /* at time 0 */
  adem_motion motion;      /* prescribed motion (def.velocity makes a constant one) */
  bool inactive;           /* switched off (walls[].active: false, or a stage): no contacts */
} adem_plane;

typedef struct adem_neighbors {
  double skin;           /* absolute skin distance, m */
  double skin_fraction;  /* skin as a fraction of the largest diameter */
  bool brute_force;      /* O(N^2) search, for tests */
  /* cell grid */
  adem_vec3 origin;
  double cell_size;
  int dims[3];
  size_t ncells;
  size_t *cell_start;    /* ncells + 1; particles are sorted by cell */
  size_t cell_cap;
  /* mesh triangles binned into the cells their box, grown by the largest reach, overlaps */
  size_t *tri_cell_start; /* ncells + 1 */
  uint32_t *tri_cell;
  size_t tri_cell_start_cap, tri_cell_cap;
  /* per-particle gather lists: entries (pair index << 1 | side) for pp; pair index for pw */
  size_t *pp_start, *pw_start;
  uint32_t *pp_entries, *pw_entries;
  size_t pp_start_cap, pw_start_cap, pp_entries_cap, pw_entries_cap;
  uint64_t rebuilds;
  double time_at_build;  /* moving walls use up the skin from then on */
} adem_neighbors;

/* One mesh wall: the groups one STL file made (several for an ASCII file with several solids),
 * for its whole-file loads. */
typedef struct adem_mesh_wall {
  char name[ADEM_NAME_MAX]; /* the group's name, or the prefix of its groups' names */
  int first, count;         /* its groups */
  adem_vec3 ref0;           /* point its total torque is taken about, at time 0 */
} adem_mesh_wall;

/* Every field that changes while stepping must also be saved and restored in checkpoint.c
 * (tests/golden/test_restart.c fails otherwise). */
struct adem_world {
  adem_particles p;
  adem_material *materials;
  int nmaterials;
  adem_interaction *interactions; /* nmaterials x nmaterials, symmetric */
  adem_interaction_def *interaction_defs;
  int ninteraction_defs;
  adem_group *groups;
  int ngroups;
  adem_plane *planes;
  int nplanes;

  adem_vec3 gravity;
  double dt, time;
  uint64_t step;
  uint64_t next_id;
  int nthreads;
  size_t parallel_min; /* fewer particles than this run on one thread (waking a team costs more) */

  adem_neighbors nb;
  adem_pair_list pp, pw;

  /* triangle-mesh walls: one group per STL file (mesh.h) */
  adem_mesh mesh;
  adem_motion *mesh_motion; /* per mesh group (moving groups have their own vertices) */
  double *mesh_reach;       /* per group: farthest reference vertex from its rotation centre */
  adem_vec3 *mesh_vert0;    /* vertices at time 0 */
  adem_vec3 *mesh_normal0;  /* triangle normals at time 0 */
  double wall_time;         /* time the walls are placed at (the time of the forces) */
  double *face_force;       /* 3 per triangle: force of the particles on it, last force pass */
  uint8_t *mesh_inactive;   /* per group < mesh_inactive_n, 1: switched off (no contacts) */
  int mesh_inactive_n;
  double *face_torque;      /* 3 per triangle: its moment about its group's reference point */
  adem_vec3 *mesh_ref0;     /* per group: the point its torque is taken about, at time 0 */
  adem_vec3 *mesh_ref;      /* per group: that point where the group's motion has it now */
  adem_mesh_wall *mesh_walls; /* one per STL file loaded */
  int nmesh_walls;
  adem_mesh_pairs pm;

  /* smallest radius per material of particles inserted while running (pours), INFINITY for
   * none; NULL when nothing is poured. The step estimate counts them as present. */
  double *insert_rmin;

  /* safety limits */
  double max_overlap_ratio;   /* stop when a contact overlaps more than this fraction */
  bool has_domain;
  adem_vec3 domain_lo, domain_hi;

  /* energy bookkeeping */
  double energy_initial;      /* E_total at prepare */
  bool prepared;
};

/* Threads for the per-step loops; the results do not depend on it. */
static inline int adem_world_threads(const adem_world *w) {
  return w->p.n < w->parallel_min ? 1 : w->nthreads;
}

/* Derives materials and the pair table (materials.c). */
adem_status adem_materials_derive(adem_world *w, adem_error *err);
static inline const adem_interaction *adem_world_interaction(const adem_world *w, int a, int b) {
  return &w->interactions[(size_t)a * (size_t)w->nmaterials + (size_t)b];
}

/* Checks what adding a mesh wall needs before its file is read: the transform's material exists,
 * and a moving mesh (velocity != 0) has its own vertices. */
adem_status adem_world_check_mesh(const adem_world *w, const char *path,
                                  const adem_mesh_transform *tf, adem_vec3 velocity,
                                  adem_error *err);
/* Adds the blocks of a triangle soup (read from the file `path`, see input/stl.h) as one mesh
 * wall: one group per block, moving with velocity (non-zero needs tf->own_vertices). */
adem_status adem_world_add_mesh_soup(adem_world *w, const adem_mesh_soup *s,
                                     const adem_mesh_transform *tf, const char *path, int ascii,
                                     const char *name, adem_vec3 velocity, adem_error *err);
/* Point (at time 0) the torques of mesh wall `wall` (adem_world_add_mesh's order) and of each of
 * its groups are taken about; by default each group's area centroid and the file's. */
adem_status adem_world_set_mesh_torque_point(adem_world *w, int wall, adem_vec3 point,
                                             adem_error *err);
/* Force and torque of the particles on each mesh group (ngroups entries each) and on each mesh
 * wall (nmesh_walls entries; either pair of pointers may be NULL): sums of face_force and
 * face_torque in face order, so the same for any thread count. Torques are about the reference
 * points where the walls' motion has them now. */
void adem_world_mesh_loads(const adem_world *w, adem_vec3 *group_force, adem_vec3 *group_torque,
                           adem_vec3 *wall_force, adem_vec3 *wall_torque);
/* Prescribed motion of a mesh group (loaded with own vertices) or of a plane. */
adem_status adem_world_set_mesh_motion(adem_world *w, int group, const adem_motion_def *def,
                                       adem_error *err);
adem_status adem_world_set_plane_motion(adem_world *w, int plane, const adem_motion_def *def,
                                        adem_error *err);
/* Frees planes, mesh motions and reference geometry (walls.c). */
void adem_walls_free(adem_world *w);
/* Puts planes and mesh groups where their motion has them at time t (walls.c). */
void adem_world_place_walls(adem_world *w, double t);
/* Switches a plane or a mesh group on or off (walls.c); the neighbour lists need a rebuild. */
adem_status adem_world_set_plane_active(adem_world *w, int plane, bool active, adem_error *err);
adem_status adem_world_set_mesh_active(adem_world *w, int group, bool active, adem_error *err);
static inline bool adem_world_mesh_active(const adem_world *w, uint32_t group) {
  return (int)group >= w->mesh_inactive_n || !w->mesh_inactive[group];
}
/* Largest distance a moving wall has travelled since the last neighbour build. */
double adem_world_wall_shift(const adem_world *w);

/* Neighbour search (neighbors.c). */
adem_status adem_neighbors_build(adem_world *w, adem_error *err);
bool adem_neighbors_need_rebuild(const adem_world *w);
/* Rebuilds the per-particle gather lists from the pair lists (after a build or a checkpoint load). */
adem_status adem_neighbors_gather(adem_world *w);
void adem_neighbors_free(adem_neighbors *nb);

/* Forces (contacts.c): fills the pair lists' per-pair results and sums p.force / p.torque. */
void adem_contacts_compute(adem_world *w);

/* Checkpoints: the world's dynamic state, each module saving and loading its own part. The
 * static set-up (materials, walls, meshes) comes from the case and must match. A damaged or
 * mismatching state gives ADEM_ERR_INPUT with the reason as the message ("its walls do not
 * match its own case text"). */
void adem_world_save(adem_writer *wr, const adem_world *w);
/* The first byte: whether the world had been prepared (else nothing follows). */
adem_status adem_world_load_prepared(adem_reader *rd, bool *prepared,
                                     adem_error *err);
/* The rest, into a world prepared from the same case. */
adem_status adem_world_load(adem_reader *rd, adem_world *w, adem_error *err);

/* Deterministic sum: fixed blocks, independent of the thread count. */
double adem_sum(const double *x, size_t n);

#endif
