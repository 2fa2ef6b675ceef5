/* Bulk access to the particles in id order, the id -> index map, and the per-particle external
 * force (adem/world.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "world_internal.h"

/* The map is a cache: id_map[id] is where particle id was stored when it was last built. Every
 * look-up checks it against p.id, so a reordering (neighbour builds sort by cell, the MPI split
 * moves particles) makes it stale, never wrong; a stale entry rebuilds it once, O(n). */
static bool map_rebuild(adem_world *w) {
  const adem_particles *p = &w->p;
  uint64_t top = 0;
  for (size_t i = 0; i < p->n; ++i)
    if (p->id[i] + 1 > top) top = p->id[i] + 1;
  if (top > (uint64_t)SIZE_MAX / sizeof *w->id_map || p->n >= UINT32_MAX) return false;
  if (top > w->id_map_n || !w->id_map) {
    uint32_t *m = realloc(w->id_map, (size_t)(top ? top : 1) * sizeof *m);
    if (!m) return false;
    w->id_map = m;
  }
  w->id_map_n = (size_t)top;
  for (size_t k = 0; k < w->id_map_n; ++k) w->id_map[k] = UINT32_MAX;
  for (size_t i = 0; i < p->n; ++i) w->id_map[p->id[i]] = (uint32_t)i;
  return true;
}

static inline bool map_hit(const adem_world *w, uint64_t id, size_t *index) {
  if (id >= w->id_map_n) return false;
  uint32_t i = w->id_map[id];
  if (i >= w->p.n || w->p.id[i] != id) return false;
  *index = i;
  return true;
}

bool adem_world_particle_index(adem_world *w, uint64_t id, size_t *index) {
  if (map_hit(w, id, index)) return true;
  if (id >= w->next_id && w->id_map) return false; /* never made: no rebuild */
  return map_rebuild(w) && map_hit(w, id, index);
}

adem_status adem_world_get_ids(const adem_world *w, uint64_t *out, size_t capacity,
                               adem_error *err) {
  size_t n = w->p.n;
  if (capacity < n)
    return adem_error_set(err, ADEM_ERR_INPUT, "%zu particles need %zu ids, the array has %zu", n,
                          n, capacity);
  uint32_t *order = adem_world_id_order(w);
  if (!order) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  for (size_t k = 0; k < n; ++k) out[k] = w->p.id[order[k]];
  free(order);
  return ADEM_OK;
}

/* Work from outside when particle i's external force changes from old to new: the balance
 * counts the force as the potential -F . x (diagnostics), so E_initial takes -(new - old) . x.
 * A particle still waiting to be admitted has no energy in the balance yet. */
static double force_change_work(const adem_world *w, size_t i, adem_vec3 old, adem_vec3 new) {
  if (w->admit_pending && i >= w->admit_from) return 0.0;
  adem_vec3 x = adem_periodic_unwrap(&w->periodic, w->p.pos[i], adem_particles_image(&w->p, i));
  return -v3_dot(v3_sub(new, old), x);
}

/* The new force replaces the old one in the last pass's total too, so that the next step's
 * opening half kick feels it already: the step then sees one constant force, whose work is
 * exactly the change of -F . x (velocity Verlet), and the balance closes. The external forces
 * are kept (ADEM_PART_EXTERNAL) before the first change. */
static void change_force(adem_particles *p, size_t i, adem_vec3 f) {
  p->force[i] = v3_add(p->force[i], v3_sub(f, p->ext_force[i]));
  p->ext_force[i] = f;
}

adem_status adem_world_set_particles(adem_world *w, adem_particle_field field, const double *in,
                                     size_t count, adem_error *err) {
  adem_particles *p = &w->p;
  size_t n = p->n;
  adem_vec3 *dst;
  switch (field) {
    case ADEM_FIELD_POSITION: dst = p->pos; break;
    case ADEM_FIELD_VELOCITY: dst = p->vel; break;
    case ADEM_FIELD_ANGULAR_VELOCITY: dst = p->omega; break;
    case ADEM_FIELD_EXTERNAL_FORCE: dst = NULL; break; /* change_force sets them */
    default:
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "particle field %d cannot be set: position (0), velocity (1), "
                            "angular_velocity (2) and external_force (13) can",
                            (int)field);
  }
  if (count != n)
    return adem_error_set(err, ADEM_ERR_INPUT, "%zu rows given for %zu particles", count, n);
  for (size_t k = 0; k < 3 * n; ++k)
    if (!isfinite(in[k]))
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "row %zu (particle of the %zu-th smallest id) is not finite: nothing "
                            "was set",
                            k / 3, k / 3);
  if (field == ADEM_FIELD_EXTERNAL_FORCE && adem_particles_keep(p, ADEM_PART_EXTERNAL))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the external forces");
  uint32_t *order = adem_world_id_order(w);
  if (!order && n) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  if (field == ADEM_FIELD_EXTERNAL_FORCE) {
    /* the balance's external work, summed in id order (the same bits for any storage) */
    adem_block_sum work = ADEM_BLOCK_SUM_START;
    for (size_t k = 0; k < n; ++k) {
      size_t i = order[k];
      adem_vec3 f = v3(in[3 * k], in[3 * k + 1], in[3 * k + 2]);
      adem_block_sum_add(&work, force_change_work(w, i, p->ext_force[i], f));
      change_force(p, i, f);
    }
    adem_world_add_external_work(w, adem_block_sum_result(&work));
  } else {
    for (size_t k = 0; k < n; ++k) dst[order[k]] = v3(in[3 * k], in[3 * k + 1], in[3 * k + 2]);
  }
  free(order);
  return ADEM_OK;
}

adem_status adem_world_set_external_force(adem_world *w, uint64_t id, adem_vec3 force,
                                          adem_error *err) {
  size_t i = 0;
  if (!adem_world_particle_index(w, id, &i))
    return adem_error_set(err, ADEM_ERR_INPUT, "no particle has id %llu", (unsigned long long)id);
  if (!v3_isfinite(force))
    return adem_error_set(err, ADEM_ERR_INPUT, "the external force of particle %llu must be finite",
                          (unsigned long long)id);
  if (adem_particles_keep(&w->p, ADEM_PART_EXTERNAL))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the external forces");
  adem_world_add_external_work(w, force_change_work(w, i, w->p.ext_force[i], force));
  change_force(&w->p, i, force);
  return ADEM_OK;
}

adem_status adem_world_add_particles(adem_world *w, size_t n, const double *pos, const double *vel,
                                     const double *omega, const double *radius,
                                     const int *material, const int *group, uint64_t *ids,
                                     adem_error *err) {
  /* every row is checked first, so that a bad one adds nothing */
  for (size_t k = 0; k < n; ++k) {
    int m = material ? material[k] : 0, g = group ? group[k] : 0;
    bool finite = true;
    for (int d = 0; d < 3; ++d)
      finite = finite && isfinite(pos[3 * k + d]) && (!vel || isfinite(vel[3 * k + d])) &&
               (!omega || isfinite(omega[3 * k + d]));
    if (!(radius[k] > 0.0) || !isfinite(radius[k]))
      return adem_error_set(err, ADEM_ERR_INPUT, "row %zu: particle radius %g must be > 0 "
                                                 "(no particle was added)",
                            k, radius[k]);
    if (!finite)
      return adem_error_set(err, ADEM_ERR_INPUT, "row %zu: particle position and velocities must "
                                                 "be finite (no particle was added)",
                            k);
    if (m < 0 || m >= w->mat.n || !(w->mat.m[m].def.density > 0.0) || w->mat.m[m].def.rigid)
      return adem_error_set(err, ADEM_ERR_INPUT, "row %zu: material %d does not exist or cannot "
                                                 "make particles (no particle was added)",
                            k, m);
    if (g < 0 || g >= w->ngroups)
      return adem_error_set(err, ADEM_ERR_INPUT, "row %zu: group %d does not exist (no particle "
                                                 "was added)",
                            k, g);
  }
  if (adem_particles_reserve(&w->p, w->p.n + n))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %zu more particles", n);
  for (size_t k = 0; k < n; ++k) {
    adem_particle_def d = adem_default_particle_def();
    d.position = v3(pos[3 * k], pos[3 * k + 1], pos[3 * k + 2]);
    if (vel) d.velocity = v3(vel[3 * k], vel[3 * k + 1], vel[3 * k + 2]);
    if (omega) d.angular_velocity = v3(omega[3 * k], omega[3 * k + 1], omega[3 * k + 2]);
    d.radius = radius[k];
    d.material = material ? material[k] : 0;
    d.group = group ? group[k] : 0;
    uint64_t id = 0;
    adem_status st = adem_world_add_particle(w, &d, &id, err);
    if (st) return st; /* out of memory only: the rows were checked */
    if (ids) ids[k] = id;
  }
  return ADEM_OK;
}
