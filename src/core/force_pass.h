/* The force pass: every candidate pair's force and torques into the pair lists, then the sums per
 * particle in a fixed order (the same for any thread count or storage order), BROF included.
 * force_pass.c holds the loops over pairs and walls, contact_force.h one contact's force,
 * pair_blocks.c the packed blocks, force_sums.c the ordered per-particle sums. */
#ifndef ADEM_FORCE_PASS_H
#define ADEM_FORCE_PASS_H

#include "adem/base.h"
#include "materials.h"
#include "neighbors.h"
#include "pairs.h"
#include "particles.h"
#include "periodic.h"
#include "walls.h"

/* What a force pass reads and writes. */
typedef struct adem_force_scope {
  adem_particles *p;       /* force, torque, rolling torque, held are written */
  adem_pair_list *pp, *pw; /* results and history are written */
  adem_mesh_pairs *pm;
  adem_walls *walls;        /* face loads are written */
  const adem_neighbors *nb; /* gather lists */
  const adem_materials *mat;
  const adem_group *groups;
  adem_vec3 gravity;
  double dt;
  int nthreads;
  bool second_order;             /* predicted dashpot velocities, adhesive jumps at the interpolated crossing
                                  * time (force_pass.c) */
  bool energy;                   /* the normal laws' stored energies are wanted (diagnostics after the pass) */
  bool balance;                  /* accumulate the dissipation and wall work (the energy balance) */
  const adem_periodic *periodic; /* particle separations are minimum images (periodic.h) */
  double overlap_limit;          /* a contact whose overlap ratio exceeds it sets ... */
  int *overlap_exceeded;         /* ... this flag (the step's check then finds which) */
  adem_vec3 *predicted;          /* 2 per particle, the pass's scratch for each particle's predicted
                                  * velocity and spin; NULL: predicted per contact (the same bits) */
  bool pair_blocks;              /* touching particle pairs of the common laws in block kernels */
  uint64_t *block_pairs;         /* counts the pairs they took */
  size_t pair_chunk;             /* pairs per chunk of the pair pass (force_pass.c sets it) */
  int *break_forces;             /* the pass sets it when a pair that opened carries a break correction;
                                  * only then do the sums read the forces of pairs apart (force_pass.c sets
                                  * it up: callers leave it NULL) */
  bool hold_history;             /* a pass that advances no history (prepare, adem_world_compute_forces):
                                  * the laws see a step of length 0, the forces of the state as it is */
} adem_force_scope;

void adem_force_pass_run(const adem_force_scope *s);

#endif
