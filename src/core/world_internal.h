/* The world: the composition of the core's modules (particles, materials, walls, neighbour lists,
 * contacts) and the scalars of a run. Its functions hand each module what it needs; no module
 * includes this header. Only library layers above the core and tests include it. */
#ifndef ADEM_WORLD_INTERNAL_H
#define ADEM_WORLD_INTERNAL_H

#include <stdbool.h>

#include "adem/world.h"
#include "adem/vec3.h"
#include "force_pass.h"
#include "materials.h"
#include "mesh.h"
#include "mesh_contact.h"
#include "motion.h"
#include "neighbors.h"
#include "pairs.h"
#include "particles.h"
#include "stream.h"
#include "walls.h"

/* A term of a sum over particles in id order: particle id (and index here), its place among the
 * particle's terms, the sum it belongs to (slot) and its value. */
typedef struct adem_id_term {
  uint64_t id;
  uint32_t i, seq, slot, pad;
  double v;
} adem_id_term;

/* A world that holds one part of a system split over processes (src/mpi): its own particles and
 * copies of the others' near its part. adem_world_step calls these at fixed points of every
 * step, on every process alike; the library without MPI never sets them. */
typedef struct adem_world_split {
  void *ctx;
  /* after the drift: the copies take their owners' state (position, velocity, spin, and the
   * last pass's force, torque and hold that the predicted velocities read) */
  adem_status (*refresh)(void *ctx, adem_world *w, adem_error *err);
  /* true on every process when it is true on one (a rebuild, a failed step) */
  bool (*any)(void *ctx, bool yes);
  /* the neighbour build: particles go to their new owners and copies first */
  adem_status (*build)(void *ctx, adem_world *w, adem_error *err);
  /* the whole system's plane forces, the serial sum (adem_world_plane_forces: over the
   * particles by id), on every process: the servos move by them */
  adem_status (*plane_forces)(void *ctx, const adem_world *w, adem_vec3 *out, adem_error *err);
  /* after the force pass of a world with meshes and servos: the face loads (walls.face_force,
   * face_torque) become the whole system's, the serial sum, on every process */
  adem_status (*mesh_loads)(void *ctx, adem_world *w, adem_error *err);
  /* sums out[0 .. nout) of the terms of this process's own particles and of every other
   * process's, each added in the order of (id, seq): the serial sums (the servo stability
   * warning's stiffnesses) */
  adem_status (*sum_terms)(void *ctx, const adem_world *w, const adem_id_term *t, size_t n,
                           double *out, int nout, adem_error *err);
} adem_world_split;

/* Every field that changes while stepping is saved by adem_world_save (tests/bitwise/test_restart.c
 * fails otherwise). */
struct adem_world {
  adem_particles p;
  adem_materials mat;
  adem_group *groups;
  int ngroups;
  adem_walls walls;

  adem_vec3 gravity;
  double dt, time;
  uint64_t step;
  uint64_t next_id;
  int nthreads;
  size_t parallel_min; /* fewer particles than this run on one thread (waking a team costs more) */

  adem_neighbors nb;
  adem_pair_list pp, pw;
  adem_mesh_pairs pm;
  /* scratch of the force pass: each particle's predicted velocity and spin (force_pass.c), 2 per
   * particle for predicted_cap particles; not saved (every pass writes it before reading) */
  adem_vec3 *predicted;
  size_t predicted_cap;
  /* the force pass takes touching particle pairs of the common laws in block kernels (pair_blocks.c);
   * false: every pair one at a time, the same bits (tests/bitwise/test_pair_blocks.c compares) */
  bool pair_blocks;
  uint64_t pair_block_pairs; /* pairs the block kernels took, since the world was made (not saved) */

  /* smallest radius per material of particles inserted while running (pours), INFINITY for
   * none; NULL when nothing is poured. The step estimate counts them as present. */
  double *insert_rmin;

  /* safety limits */
  double max_overlap_ratio; /* stop when a contact overlaps more than this fraction */
  int overlap_exceeded;     /* the last force pass saw an overlap above it (force_pass.c) */
  double initial_overlap;   /* overlap allowed at prepare, fraction of the smaller radius */
  bool has_domain;
  adem_vec3 domain_lo, domain_hi;
  /* periodic axes of the domain box (periodic.h); axes 0: none */
  adem_periodic periodic;
  /* faces of the domain box a particle may leave through (an outlet removes it later): bit 2d
   * the face at domain_lo along axis d, bit 2d + 1 the one at domain_hi */
  unsigned open_faces;
  /* some particle is (or was) frozen (frozen.c): the per-step placement runs only then */
  bool frozen_any;

  /* contact forces in the step: second order (predicted dashpot velocities, JKR jumps at the
   * interpolated crossing time; the default) or first order (as before) */
  bool second_order;
  /* the per-contact dissipation and wall work are accumulated (the energy balance) */
  bool energy_balance;

  /* steps in which a particle moved more than its radius next to a mesh wall (not saved) */
  uint64_t tunnel_count;
  adem_tunnel_event tunnel_first;

  /* energy bookkeeping */
  double energy_initial; /* E_total at prepare */
  bool prepared;
  /* a part of a split system (not saved: the process layer sets it) or NULL */
  const adem_world_split *split;
  /* particles added through the API to a prepared world, taken in at the next step */
  bool admit_pending;
  size_t admit_from;
  /* id -> storage index (world_bulk.c): a cache, checked at every look-up against p.id and
   * rebuilt when a reordering made it stale (not saved) */
  uint32_t *id_map;
  size_t id_map_n;
};

/* All-pairs search instead of the grid (tests compare the two). */
void adem_world_use_brute_force(adem_world *w, int on);

/* Threads for the per-step loops; the results do not depend on it. */
static inline int adem_world_threads(const adem_world *w) {
  return w->p.n < w->parallel_min ? 1 : w->nthreads;
}

static inline const adem_interaction *adem_world_interaction(const adem_world *w, int a, int b) {
  return adem_materials_pair(&w->mat, a, b);
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
/* Point (at time 0) the torques of mesh wall `wall` and of each of its groups are taken about;
 * by default each group's area centroid and the file's. */
adem_status adem_world_set_mesh_torque_point(adem_world *w, int wall, adem_vec3 point,
                                             adem_error *err);
/* Puts planes and mesh groups where their motion has them at time t. */
void adem_world_place_walls(adem_world *w, double t);
static inline bool adem_world_mesh_active(const adem_world *w, uint32_t group) {
  return adem_walls_mesh_active(&w->walls, group);
}
/* Largest distance a moving wall has travelled since the last neighbour build. */
double adem_world_wall_shift(const adem_world *w);

/* What a stage changes in a running world (input/stages.c), without a new prepare: walls go from
 * one setting to the next at time t_s (walls.h), materials and interaction entries are replaced
 * and the pair table derived again, a group's force, the skin (used from the next build). */
adem_status adem_world_change_walls(adem_world *w, const adem_plane_setting *prev_planes,
                                    const adem_plane_setting *next_planes,
                                    const adem_mesh_setting *prev_meshes,
                                    const adem_mesh_setting *next_meshes, double t_s,
                                    adem_error *err);
adem_status adem_world_change_materials(adem_world *w, const adem_material_def *defs,
                                        const adem_interaction_def *interactions, int ninteractions,
                                        adem_error *err);
void adem_world_set_group_force(adem_world *w, int group, adem_vec3 force);
void adem_world_change_skin(adem_world *w, double skin_fraction);
/* Energy put in from outside (a stage's change of gravity or group forces): kept out of the
 * dissipated energy of the balance. */
void adem_world_add_external_work(adem_world *w, double work);

/* Takes particles first..n-1, added to a prepared world while it runs (pours), into the run. */
adem_status adem_world_admit_particles(adem_world *w, size_t first, adem_error *err);

/* Removes the particles i with gone[i] != 0 (storage order) between steps, with their pairs and
 * mesh slots, and builds the neighbour lists again (the others keep their contacts' history).
 * The energy they carried leaves the balance's initial energy, so that balance_error does not
 * jump. The others' forces stay those of the last force pass (a removed particle's push on a
 * neighbour acts for that half kick). *removed: how many went. src/core/remove.c. */
adem_status adem_world_remove_particles(adem_world *w, const uint8_t *gone, size_t *removed,
                                        adem_error *err);

/* Frozen particles (src/core/frozen.c): particle id becomes part of a wall, attach 0 (fixed in
 * space), k + 1 (mesh group k) or -(k + 1) (plane k), moving with the wall's prescribed motion
 * from where it is now; not a servo wall. */
adem_status adem_world_freeze_particle(adem_world *w, uint64_t id, int32_t attach,
                                       adem_error *err);
/* Puts the frozen particles where their walls' motions have them at t, with their walls'
 * velocity and spin. */
void adem_world_place_frozen(adem_world *w, double t);
/* After a stage changed motions at t_s: the anchors of the frozen particles whose wall's motion
 * begins there are where they are. */
void adem_world_restart_anchors(adem_world *w, double t_s);
/* Adds the contact forces on the frozen particles (by id) to their planes' forces, and forces
 * and torques to their mesh groups' and mesh walls' loads (any pointer may be NULL). */
void adem_world_frozen_plane_forces(const adem_world *w, adem_vec3 *out);
void adem_world_frozen_mesh_loads(const adem_world *w, adem_vec3 *group_force,
                                  adem_vec3 *group_torque, adem_vec3 *wall_force,
                                  adem_vec3 *wall_torque);
bool adem_world_has_frozen(const adem_world *w);
/* The wall layer's slip (src/core/slip.c): per plane and per mesh group, the mean over the
 * particles touching it (or a frozen particle attached to it) of the tangential speed of their
 * centre relative to the wall's material there, m/s; NaN when none touches. Either may be NULL. */
void adem_world_wall_slip(const adem_world *w, double *plane_slip, double *group_slip);

/* Neighbour search over the whole world (neighbors.h). */
adem_status adem_world_build_neighbors(adem_world *w, adem_error *err);
/* The gather lists after a checkpoint load. */
adem_status adem_world_gather(adem_world *w);
/* Stores the particles in a random order (seeded), with the pair lists in a random order too
 * and every pair, slot and history moved along: the state is the same, only where it is
 * stored changes (tests/bitwise/test_storage_order.c; an MPI rank stores its particles in its
 * own order). Not while particles wait to be admitted. */
adem_status adem_world_shuffle_storage(adem_world *w, uint64_t seed, adem_error *err);

/* Checkpoints: the world's dynamic state, each module saving and loading its own part. The
 * static set-up (materials, walls, meshes) comes from the case and must match. A damaged or
 * mismatching state gives ADEM_ERR_INPUT with the reason as the message ("its walls do not
 * match its own case text"). */
void adem_world_save(adem_writer *wr, const adem_world *w);
/* The first byte: whether the world had been prepared (else nothing follows). */
adem_status adem_world_load_prepared(adem_reader *rd, bool *prepared, adem_error *err);
/* The rest, into a world prepared from the same case. */
adem_status adem_world_load(adem_reader *rd, adem_world *w, adem_error *err);

/* From a world section adem_world_save wrote: its particles (into p, empty) and its materials'
 * names (*names, free it), the rest skipped; for a case that starts from another run's state. */
adem_status adem_world_read_particles(adem_reader *rd, adem_particles *p,
                                      char (**names)[ADEM_NAME_MAX], int *nmat, adem_error *err);

/* The storage index of particle id (world_bulk.c): O(1) through the id map, which is rebuilt
 * (O(n)) when a reordering made it stale. false: no particle has that id. */
bool adem_world_particle_index(adem_world *w, uint64_t id, size_t *index);

/* The whole set-up of a world made through the API (settings, materials, interactions, groups,
 * walls), before its dynamic state: loading it into a fresh world remakes that world. */
void adem_world_save_setup(adem_writer *wr, const adem_world *w);
adem_status adem_world_load_setup(adem_reader *rd, adem_world *w, adem_error *err);

/* The particles in order of id (adem_particles_id_order) in a new array (free it), NULL when
 * out of memory: sums over particles run in this order (docs/architecture.md, "Order
 * independence"). */
uint32_t *adem_world_id_order(const adem_world *w);

/* Deterministic sum: fixed blocks of ADEM_SUM_BLOCK terms, each summed in order from 0.0 and added
 * in order to the total; independent of the thread count. */
double adem_sum(const double *x, size_t n);

/* adem_sum as a stream, term by term: the same additions in the same order (the same bits),
 * without an array of the terms. Start from ADEM_BLOCK_SUM_START. */
enum { ADEM_SUM_BLOCK = 4096 };
typedef struct adem_block_sum {
  double total, part; /* the finished blocks; the block under way */
  size_t count;       /* terms in the block under way */
} adem_block_sum;
#define ADEM_BLOCK_SUM_START \
  { 0.0, 0.0, 0 }
static inline void adem_block_sum_add(adem_block_sum *s, double x) {
  s->part += x;
  if (++s->count == ADEM_SUM_BLOCK) {
    s->total += s->part;
    s->part = 0.0;
    s->count = 0;
  }
}
static inline double adem_block_sum_result(const adem_block_sum *s) {
  return s->count ? s->total + s->part : s->total;
}

#endif
