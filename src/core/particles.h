/* Particles: per-particle arrays in structure-of-arrays form, listed once in
 * ADEM_PARTICLE_FIELDS, and the integrator that moves them (velocity Verlet, H3-H4). Indices
 * change when particles are reordered by grid cell; the id never does. Every write to these
 * arrays goes through this module: particles.c (adding, integrating, reordering, loading) and the
 * inline setters below (the force pass's sums, the neighbour build's snapshot). */
#ifndef ADEM_PARTICLES_H
#define ADEM_PARTICLES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/base.h"
#include "adem/laws.h"
#include "periodic.h"
#include "soa.h"
#include "stream.h"

/* A named group of particles with a constant external force (H3). */
typedef struct adem_group {
  char name[ADEM_NAME_MAX];
  adem_vec3 external_force; /* N per particle, constant (H3) */
} adem_group;

/* X(type, name, what it holds): hot fields first. */
// clang-format off
#define ADEM_PARTICLE_FIELDS(X)                                                       \
  X(adem_vec3, pos, "centre, m")                                                      \
  X(adem_vec3, vel, "velocity, m/s")                                                  \
  X(adem_vec3, omega, "angular velocity, rad/s")                                      \
  X(adem_vec3, force, "total force at the current positions, N (force pass)")         \
  X(adem_vec3, torque, "total torque at the current positions, N m (force pass)")     \
  X(double, radius, "radius, m")                                                      \
  X(double, inv_mass, "1 / mass, 1/kg")                                               \
  X(double, inv_inertia, "1 / moment of inertia, 1/(kg m^2)")                         \
  X(uint64_t, id, "stable id: the order of creation")                                 \
  X(uint16_t, material, "material index")                                             \
  X(uint16_t, group, "external-force group index")                                    \
  X(adem_vec3, pos_at_build, "centre when the neighbour list was built (skin check)") \
  X(adem_image, image, "periodic faces crossed along x, y, z (unwrapped = pos + image len)") \
  X(adem_vec3, rolling_torque, "rolling resistance torque of the last force pass")    \
  X(uint8_t, held, "1: BROF holds the spin at exactly zero this step (force pass)")   \
  X(double, path_length, "distance the centre has travelled, sum of |v| dt")                \
  X(double, dissipated, "energy dissipated in its contacts (half of a pair's) to the last closing kick, J") \
  X(double, dissipated_next, "of the last force pass, what the next opening kick dissipates, J") \
  X(double, wall_work, "energy moving walls gave through its contacts to the last closing kick, J") \
  X(double, wall_work_next, "of the last force pass, what the next opening kick receives, J") \
  X(adem_vec3, ext_force, "external force set through the API (adem_world_set_particles), kept " \
    "until changed, N")                                                               \
  X(adem_vec3, brof_impulse, "angular impulse of BROF's share from particle contacts, which no "  \
    "partner takes back (I9-I10 act per particle), N m s") \
  X(uint8_t, frozen, "1: fixed to a wall (or to space): not integrated, placed by the wall's motion") \
  X(int32_t, attach, "the wall a frozen particle moves with: 0 none, k + 1 mesh group k, -(k + 1) plane k") \
  X(adem_vec3, anchor, "a frozen particle's centre where its wall's motion starts (at the motion's t0)")
// clang-format on

typedef struct adem_particles {
  size_t n, cap;
#define ADEM_X(type, name, doc) type *name;
  ADEM_PARTICLE_FIELDS(ADEM_X)
#undef ADEM_X
} adem_particles;

/* The table of ADEM_PARTICLE_FIELDS. */
adem_soa_layout adem_particles_layout(void);

adem_status adem_particles_reserve(adem_particles *p, size_t cap);
void adem_particles_free(adem_particles *p);
/* Reorders every per-particle array: new index k holds old particle perm[k]. */
adem_status adem_particles_permute(adem_particles *p, const size_t *perm);
/* The particles in increasing order of id: order[k] is the index of the k-th smallest id. Sums
 * over particles run in this order, which the storage order does not change. O(n) when the ids
 * are 0 .. n-1 (as adem_world_add_particle numbers them), a sort otherwise. */
adem_status adem_particles_id_order(const adem_particles *p, uint32_t *order);
/* Appends a particle with every field zero but these; returns its index (or SIZE_MAX when out of
 * memory). mass and inertia of a solid sphere of the given density. */
size_t adem_particles_append(adem_particles *p, uint64_t id, adem_vec3 pos, adem_vec3 vel,
                             adem_vec3 omega, double radius, double density, int material,
                             int group);

/* Velocity Verlet (H3-H4): a half kick of velocities and spins with the current forces; the
 * closing kick sets the spin of a particle that BROF holds to exactly zero. */
void adem_particles_kick(adem_particles *p, double h, bool closing, int nthreads);
/* The opening half kick (h) and the drift in one sweep: each particle's velocity and spin take
 * the kick, then its position moves by dt v and its path length grows by dt |v| (the same
 * arithmetic per particle as a kick and a drift in two sweeps). Returns the largest
 * dt |v| - radius: > 0 when some particle moved more than its radius (tunnelling check). */
double adem_particles_kick_drift(adem_particles *p, double h, double dt, int nthreads);
/* Wraps every centre into the periodic box along its periodic axes, counting the crossings in
 * image (called by the neighbour build, before the sort). */
void adem_particles_wrap(adem_particles *p, const adem_periodic *pb, int nthreads);
/* Records the positions at a neighbour build. */
void adem_particles_mark_build(adem_particles *p);

/* The force pass's result for particle i. */
static inline void adem_particles_set_loads(adem_particles *p, size_t i, adem_vec3 force,
                                            adem_vec3 torque, adem_vec3 rolling, uint8_t held) {
  p->held[i] = held;
  p->force[i] = force;
  p->torque[i] = torque;
  p->rolling_torque[i] = rolling;
}

/* Places particle i or sets its velocity or spin (NULL: keep). */
static inline void adem_particles_set_state(adem_particles *p, size_t i, const adem_vec3 *pos,
                                            const adem_vec3 *vel, const adem_vec3 *omega) {
  if (pos) p->pos[i] = *pos;
  if (vel) p->vel[i] = *vel;
  if (omega) p->omega[i] = *omega;
}

void adem_particles_save(adem_writer *wr, const adem_particles *p);
/* Replaces the particles with those saved. */
adem_status adem_particles_load(adem_reader *rd, adem_particles *p, adem_error *err);

#endif
