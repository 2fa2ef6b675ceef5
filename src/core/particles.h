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
#include "adem/vec3.h"
#include "periodic.h"
#include "soa.h"
#include "stream.h"

/* A named group of particles with a constant external force (H3). */
typedef struct adem_group {
  char name[ADEM_NAME_MAX];
  adem_vec3 external_force; /* N per particle, constant (H3) */
} adem_group;

/* Which runs allocate a field. ADEM_PART_ALWAYS: every run. Each other kind is optional: its
 * arrays are NULL (absent) until adem_particles_keep allocates them, and an absent field reads as
 * all zeros (the accessors below, or a check of the pointer); a writer keeps the kind first. */
typedef enum adem_particle_kind {
  ADEM_PART_ALWAYS = 0,
  ADEM_PART_BALANCE,  /* while the world keeps the energy balance (world.c, sync_optional_fields) */
  ADEM_PART_BROF,     /* once an interaction has a per-particle rolling law (BROF) */
  ADEM_PART_FROZEN,   /* once a particle is frozen (frozen.c); the frozen flag itself is always */
  ADEM_PART_EXTERNAL, /* once an external force is set through the API (world_bulk.c) */
  ADEM_PART_PERIODIC, /* once the neighbour build wraps into a periodic box */
  ADEM_PART_KINDS
} adem_particle_kind;

/* X(type, name, kind, what it holds): hot fields first. */
// clang-format off
#define ADEM_PARTICLE_FIELDS(X)                                                       \
  X(adem_vec3, pos, ADEM_PART_ALWAYS, "centre, m")                                    \
  X(adem_vec3, vel, ADEM_PART_ALWAYS, "velocity, m/s")                                \
  X(adem_vec3, omega, ADEM_PART_ALWAYS, "angular velocity, rad/s")                    \
  X(adem_vec3, force, ADEM_PART_ALWAYS, "total force at the current positions, N (force pass)") \
  X(adem_vec3, torque, ADEM_PART_ALWAYS, "total torque at the current positions, N m (force pass)") \
  X(double, radius, ADEM_PART_ALWAYS, "radius, m")                                    \
  X(double, inv_mass, ADEM_PART_ALWAYS, "1 / mass, 1/kg")                             \
  X(double, inv_inertia, ADEM_PART_ALWAYS, "1 / moment of inertia, 1/(kg m^2)")       \
  X(uint64_t, id, ADEM_PART_ALWAYS, "stable id: the order of creation")               \
  X(uint16_t, material, ADEM_PART_ALWAYS, "material index")                           \
  X(uint16_t, group, ADEM_PART_ALWAYS, "external-force group index")                  \
  X(adem_vec3, pos_at_build, ADEM_PART_ALWAYS, "centre when the neighbour list was built (skin check)") \
  X(adem_image, image, ADEM_PART_PERIODIC, "periodic faces crossed along x, y, z (unwrapped = pos + image len)") \
  X(adem_vec3, rolling_torque, ADEM_PART_ALWAYS, "rolling resistance torque of the last force pass") \
  X(uint8_t, held, ADEM_PART_ALWAYS, "1: BROF holds the spin at exactly zero this step (force pass)") \
  X(double, path_length, ADEM_PART_ALWAYS, "distance the centre has travelled, sum of |v| dt") \
  X(double, dissipated, ADEM_PART_BALANCE, "energy dissipated in its contacts (half of a pair's) to the last closing kick, J") \
  X(double, dissipated_next, ADEM_PART_BALANCE, "of the last force pass, what the next opening kick dissipates, J") \
  X(double, wall_work, ADEM_PART_BALANCE, "energy moving walls gave through its contacts to the last closing kick, J") \
  X(double, wall_work_next, ADEM_PART_BALANCE, "of the last force pass, what the next opening kick receives, J") \
  X(adem_vec3, ext_force, ADEM_PART_EXTERNAL, "external force set through the API (adem_world_set_particles), kept " \
    "until changed, N")                                                               \
  X(adem_vec3, brof_impulse, ADEM_PART_BROF, "angular impulse of BROF's share from particle contacts, which no "  \
    "partner takes back (I9-I10 act per particle), N m s") \
  X(uint8_t, frozen, ADEM_PART_ALWAYS, "1: fixed to a wall (or to space): not integrated, placed by the wall's motion") \
  X(int32_t, attach, ADEM_PART_FROZEN, "the wall a frozen particle moves with: 0 none, k + 1 mesh group k, -(k + 1) plane k") \
  X(adem_vec3, anchor, ADEM_PART_FROZEN, "a frozen particle's centre where its wall's motion starts (at the motion's t0)")
// clang-format on

typedef struct adem_particles {
  size_t n, cap;
#define ADEM_X(type, name, kind, doc) type *name;
  ADEM_PARTICLE_FIELDS(ADEM_X)
#undef ADEM_X
} adem_particles;

/* The table of ADEM_PARTICLE_FIELDS. */
adem_soa_layout adem_particles_layout(void);

adem_status adem_particles_reserve(adem_particles *p, size_t cap);
void adem_particles_free(adem_particles *p);
/* Makes the arrays of an optional kind present, zero up to the capacity (absent ones only); they
 * then grow, reorder and save with the others. */
adem_status adem_particles_keep(adem_particles *p, adem_particle_kind kind);
/* Frees the arrays of an optional kind: its fields read as zero from then on. */
void adem_particles_drop(adem_particles *p, adem_particle_kind kind);
/* Whether the arrays of a kind are present. */
bool adem_particles_has(const adem_particles *p, adem_particle_kind kind);
/* Bytes per particle of a kind's arrays (memory estimates). */
size_t adem_particles_kind_bytes(adem_particle_kind kind);
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
 * image, which it keeps (called by the neighbour build, before the sort). */
adem_status adem_particles_wrap(adem_particles *p, const adem_periodic *pb, int nthreads);
/* Records the positions at a neighbour build. */
void adem_particles_mark_build(adem_particles *p);

/* Optional fields as they read, zero while absent. */
static inline adem_vec3 adem_particles_ext_force(const adem_particles *p, size_t i) {
  return p->ext_force ? p->ext_force[i] : v3_zero();
}
static inline adem_image adem_particles_image(const adem_particles *p, size_t i) {
  adem_image none = {{0, 0, 0}};
  return p->image ? p->image[i] : none;
}
static inline int32_t adem_particles_attach(const adem_particles *p, size_t i) {
  return p->attach ? p->attach[i] : 0;
}
static inline double adem_particles_dissipated(const adem_particles *p, size_t i) {
  return p->dissipated ? p->dissipated[i] : 0.0;
}
static inline double adem_particles_wall_work(const adem_particles *p, size_t i) {
  return p->wall_work ? p->wall_work[i] : 0.0;
}
static inline adem_vec3 adem_particles_brof_impulse(const adem_particles *p, size_t i) {
  return p->brof_impulse ? p->brof_impulse[i] : v3_zero();
}

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
