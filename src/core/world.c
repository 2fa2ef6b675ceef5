/* The world: set-up, adding things, reading the state, and velocity-Verlet stepping (H3-H4). Its
 * checks are in world_checks.c, the servos in world_servo.c, the diagnostics in world_diag.c,
 * checkpoints in world_save.c, step and memory estimates in world_estimate.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fpenv.h"
#include "hertz.h"
#include "history_switch.h"
#include "jkr.h"
#include "log.h"
#include "parallel.h"
#include "rng.h"
#include "step_limit.h"
#include "world_internal.h"
#include "world_parts.h"
#include "cylinder.h"
#include "mesh_periodic.h"

adem_world *adem_world_create(void) {
  adem_world *w = calloc(1, sizeof *w);
  if (!w) return NULL;
  w->gravity = v3(0.0, 0.0, -9.81);
  w->nthreads = adem_default_threads();
  w->parallel_min = 512;
  w->nb.skin_fraction = 0.2;
  w->max_overlap_ratio = 0.2;
  w->second_order = true;
  w->energy_balance = true;
  w->next_id = 0;
  adem_world_add_group(w, "default", v3_zero(), NULL, NULL);
  w->pair_blocks = true;
  w->pp.sparse = true; /* particle pairs keep state only for those that touch (pairs.h) */
  return w;
}

void adem_world_free(adem_world *w) {
  if (!w) return;
  adem_particles_free(&w->p);
  adem_pairs_free(&w->pp);
  adem_pairs_free(&w->pw);
  adem_mesh_pairs_free(&w->pm);
  free(w->predicted);
  adem_walls_free(&w->walls);
  free(w->insert_rmin);
  adem_neighbors_free(&w->nb);
  adem_materials_free(&w->mat);
  free(w->groups);
  free(w->id_map);
  free(w);
}

adem_particle_def adem_default_particle_def(void) {
  adem_particle_def d;
  memset(&d, 0, sizeof d);
  d.radius = 0.0;
  return d;
}

/* The index convention of the modules (-1 with err set) as the API's status. */
static adem_status indexed(int k, int *out, adem_error *err) {
  if (k < 0) return err && err->status != ADEM_OK ? err->status : ADEM_ERR_INPUT;
  if (out) *out = k;
  return ADEM_OK;
}

adem_status adem_world_add_material(adem_world *w, const adem_material_def *def, int *index,
                                    adem_error *err) {
  if (err) err->status = ADEM_OK;
  int k = adem_materials_add(&w->mat, def, err);
  if (k >= 0) w->prepared = false;
  return indexed(k, index, err);
}

int adem_world_material_count(const adem_world *w) { return w->mat.n; }

const adem_material_def *adem_world_material(const adem_world *w, int index) {
  return index >= 0 && index < w->mat.n ? &w->mat.m[index].def : NULL;
}

int adem_world_find_material(const adem_world *w, const char *name) {
  return adem_materials_find(&w->mat, name);
}

adem_status adem_world_set_interaction(adem_world *w, const adem_interaction_def *def,
                                       adem_error *err) {
  if (err) err->status = ADEM_OK;
  int k = adem_materials_set_interaction(&w->mat, def, err);
  if (k >= 0) w->prepared = false;
  return indexed(k, NULL, err);
}

adem_status adem_world_add_plane(adem_world *w, const adem_plane_def *def, int *index,
                                 adem_error *err) {
  if (err) err->status = ADEM_OK;
  int k = adem_walls_add_plane(&w->walls, def, w->mat.n, err);
  if (k >= 0) w->prepared = false;
  return indexed(k, index, err);
}

adem_status adem_world_add_box(adem_world *w, const char *name, adem_vec3 lo, adem_vec3 hi,
                               int material, int *first, adem_error *err) {
  if (err) err->status = ADEM_OK;
  int k = adem_walls_add_box(&w->walls, name, lo, hi, material, w->mat.n, err);
  if (k >= 0) w->prepared = false;
  return indexed(k, first, err);
}

adem_status adem_world_add_mesh(adem_world *w, const adem_vec3 *corners, size_t ntri,
                                const char *name, const adem_mesh_transform *tf, adem_error *err) {
  adem_mesh_transform def = adem_default_mesh_transform();
  if (!tf) tf = &def;
  const char *nm = name && *name ? name : "mesh";
  adem_status st = adem_walls_check_mesh(w->mat.n, nm, tf, v3_zero(), err);
  if (!st) st = adem_mesh_check_transform(tf, nm, err);
  if (st) return st;
  if (adem_mesh_find_group(&w->walls.mesh, nm) >= 0)
    return adem_error_set(err, ADEM_ERR_INPUT, "mesh group name '%s' is already used", nm);
  adem_mesh_soup s;
  memset(&s, 0, sizeof s);
  if (!adem_mesh_soup_block_open(&s, nm, 0)) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  for (size_t t = 0; t < ntri && !st; ++t) {
    if (!adem_mesh_soup_push(&s, &corners[3 * t], v3_zero(), t))
      st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    else
      s.blocks[0].count++;
  }
  if (!st) st = adem_world_add_mesh_soup(w, &s, tf, nm, 0, nm, v3_zero(), err);
  adem_mesh_soup_free(&s);
  return st;
}

int adem_world_plane_count(const adem_world *w) { return w->walls.nplanes; }

const adem_plane_def *adem_world_plane(const adem_world *w, int index) {
  return index >= 0 && index < w->walls.nplanes ? &w->walls.planes[index].def : NULL;
}

int adem_world_mesh_group_count(const adem_world *w) { return w->walls.mesh.ngroups; }

const char *adem_world_mesh_group_name(const adem_world *w, int group) {
  return group >= 0 && group < w->walls.mesh.ngroups ? w->walls.mesh.groups[group].name : NULL;
}

int adem_world_find_mesh_group(const adem_world *w, const char *name) {
  return adem_mesh_find_group(&w->walls.mesh, name);
}

int adem_world_mesh_wall_count(const adem_world *w) { return w->walls.nmesh_walls; }

adem_status adem_world_check_mesh(const adem_world *w, const char *path,
                                  const adem_mesh_transform *tf, adem_vec3 velocity,
                                  adem_error *err) {
  return adem_walls_check_mesh(w->mat.n, path, tf, velocity, err);
}

adem_status adem_world_add_mesh_soup(adem_world *w, const adem_mesh_soup *s,
                                     const adem_mesh_transform *tf, const char *path, int ascii,
                                     const char *name, adem_vec3 velocity, adem_error *err) {
  adem_status st =
      adem_walls_add_mesh_soup(&w->walls, w->mat.n, s, tf, path, ascii, name, velocity, err);
  if (!st) w->prepared = false;
  return st;
}

adem_status adem_world_set_mesh_torque_point(adem_world *w, int wall, adem_vec3 point,
                                             adem_error *err) {
  return adem_walls_set_mesh_torque_point(&w->walls, wall, point, err);
}

void adem_world_mesh_loads(const adem_world *w, adem_vec3 *group_force, adem_vec3 *group_torque,
                           adem_vec3 *wall_force, adem_vec3 *wall_torque) {
  adem_walls_mesh_loads(&w->walls, group_force, group_torque, wall_force, wall_torque);
  adem_world_frozen_mesh_loads(w, group_force, group_torque, wall_force, wall_torque);
}

adem_status adem_world_set_mesh_motion(adem_world *w, int group, const adem_motion_def *def,
                                       adem_error *err) {
  return adem_walls_set_mesh_motion(&w->walls, group, def, err);
}

adem_status adem_world_set_plane_motion(adem_world *w, int plane, const adem_motion_def *def,
                                        adem_error *err) {
  return adem_walls_set_plane_motion(&w->walls, plane, def, err);
}

/* Switched in a running world (between steps, through the API), a wall's candidate pairs
 * change now: the neighbour lists are rebuilt (a wall's pairs are made only at a build). */
static adem_status rebuild_for_wall(adem_world *w, adem_status st, adem_error *err) {
  if (!st && w->prepared && !w->split && !w->admit_pending) st = adem_world_build_neighbors(w, err);
  return st;
}

adem_status adem_world_set_plane_active(adem_world *w, int plane, int active, adem_error *err) {
  return rebuild_for_wall(w, adem_walls_set_plane_active(&w->walls, plane, active != 0, err), err);
}

adem_status adem_world_set_mesh_active(adem_world *w, int group, int active, adem_error *err) {
  return rebuild_for_wall(w, adem_walls_set_mesh_active(&w->walls, group, active != 0, err), err);
}

void adem_world_place_walls(adem_world *w, double t) { adem_walls_place(&w->walls, t); }

double adem_world_wall_shift(const adem_world *w) {
  return adem_walls_shift(&w->walls, w->nb.time_at_build, w->has_domain, w->domain_lo, w->domain_hi);
}

static adem_neighbor_scope neighbor_scope(adem_world *w) {
  adem_neighbor_scope s = {&w->p, &w->pp, &w->pw,
                           &w->pm, &w->walls, &w->periodic,
                           adem_world_threads(w)};
  return s;
}

adem_status adem_world_build_neighbors(adem_world *w, adem_error *err) {
  adem_neighbor_scope s = neighbor_scope(w);
  return adem_neighbors_build(&w->nb, &s, err);
}

adem_status adem_world_gather(adem_world *w) {
  return adem_neighbors_gather(&w->nb, &w->p, &w->pp, &w->pw, adem_world_threads(w));
}

/* Makes the lists keep their balance records, and the particles their balance fields, exactly
 * while the balance is on (pairs.h, particles.h); and the particles their BROF impulses once a
 * law needs them (kept after: the impulse is a running total the diagnostics report). */
static adem_status sync_optional_fields(adem_world *w) {
  adem_pair_list *lists[3] = {&w->pp, &w->pw, &w->pm.l};
  for (int s = 0; s < 3; ++s)
    if (adem_pairs_keep_balance(lists[s], w->energy_balance)) return ADEM_ERR_NOMEM;
  if (!w->energy_balance) adem_particles_drop(&w->p, ADEM_PART_BALANCE);
  else if (adem_particles_keep(&w->p, ADEM_PART_BALANCE)) return ADEM_ERR_NOMEM;
  if (adem_materials_per_particle_rolling(&w->mat) && adem_particles_keep(&w->p, ADEM_PART_BROF))
    return ADEM_ERR_NOMEM;
  return ADEM_OK;
}

/* energy: the pass computes the normal laws' stored energies, which only the diagnostics read
 * (a JKR contact's costs a cbrt and four pow): the last pass of a call to adem_world_step and
 * the pass of prepare, after which the diagnostics can be read. */
static void compute_forces(adem_world *w, bool energy, bool hold_history) {
  /* the balance's terms need their records: adem_world_step and prepare report a failure to
   * allocate them before they get here */
  bool balance = sync_optional_fields(w) == ADEM_OK && w->energy_balance;
  if (w->predicted_cap < w->p.n) { /* without it the pass predicts per contact: the same bits */
    free(w->predicted);
    size_t cap = w->p.n + w->p.n / 8;
    w->predicted = malloc(2 * cap * sizeof *w->predicted);
    w->predicted_cap = w->predicted ? cap : 0;
  }
  adem_force_scope s = {&w->p, &w->pp, &w->pw, &w->pm, &w->walls,
                        &w->nb, &w->mat, w->groups, w->gravity,
                        w->dt, adem_world_threads(w), w->second_order, energy,
                        balance, &w->periodic, w->max_overlap_ratio,
                        &w->overlap_exceeded, w->predicted, w->pair_blocks,
                        &w->pair_block_pairs, 0, NULL, hold_history};
  w->overlap_exceeded = 0;
  adem_force_pass_run(&s);
}

/* The pass of prepare and of the public call: the forces of the state as it is, every history
 * left as it was (a step advances them). */
void adem_world_compute_forces(adem_world *w) { compute_forces(w, true, true); }
void adem_world_advance_histories(adem_world *w) { compute_forces(w, true, false); }

adem_status adem_world_change_walls(adem_world *w, const adem_plane_setting *prev_planes,
                                    const adem_plane_setting *next_planes,
                                    const adem_mesh_setting *prev_meshes,
                                    const adem_mesh_setting *next_meshes, double t_s,
                                    adem_error *err) {
  adem_status st =
      adem_walls_change(&w->walls, prev_planes, next_planes, prev_meshes, next_meshes, t_s, err);
  if (!st) adem_world_restart_anchors(w, t_s);
  return st;
}

adem_status adem_world_change_materials(adem_world *w, const adem_material_def *defs,
                                        const adem_interaction_def *interactions, int ninteractions,
                                        adem_error *err) {
  adem_materials *mt = &w->mat;
  adem_interaction_def *d = malloc(((size_t)ninteractions + 1) * sizeof *d);
  int *old = adem_history_laws(mt); /* live contacts' histories follow a change of laws */
  if (!d || !old) {
    free(d);
    free(old);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  memcpy(d, interactions, (size_t)ninteractions * sizeof *d);
  for (int j = 0; j < mt->n; ++j) adem_material_def_store(&mt->m[j].def, &defs[j]);
  free(mt->defs);
  mt->defs = d;
  mt->ndefs = ninteractions;
  adem_status st = adem_materials_derive(mt, err);
  /* the energy a switch loses goes to the particles' balance fields, present while it is on */
  bool balance = w->energy_balance && adem_particles_keep(&w->p, ADEM_PART_BALANCE) == ADEM_OK;
  size_t cleared = st ? 0 : adem_history_switch_all(mt, old, &w->p, &w->pp, &w->pw, &w->pm, &w->walls, balance);
  free(old);
  if (cleared > 0)
    adem_log(ADEM_LOG_INFO, "t = %.9g s: %zu contact histories cleared (their tangential or "
                            "rolling law changed, with no exact conversion; docs/models.md)",
             w->time, cleared);
  return st;
}

void adem_world_set_group_force(adem_world *w, int group, adem_vec3 force) {
  if (group >= 0 && group < w->ngroups) w->groups[group].external_force = force;
}

void adem_world_change_skin(adem_world *w, double skin_fraction) { w->nb.skin_fraction = skin_fraction; }

adem_status adem_world_admit_particles(adem_world *w, size_t first, adem_error *err) {
  /* The new particles start with their body forces (nothing touches them), their energy joins
   * the balance, and the neighbour lists take them in; the forces of the others stay those of
   * the last force pass, whose history must not be advanced twice. */
  adem_particles *p = &w->p;
  w->admit_pending = false;
  double energy = 0.0;
  for (size_t i = first; i < p->n; ++i) {
    double m = 1.0 / p->inv_mass[i];
    adem_vec3 f = v3_add(v3_add(v3_scale(w->gravity, m), w->groups[p->group[i]].external_force),
                         adem_particles_ext_force(p, i));
    adem_particles_set_loads(p, i, f, v3_zero(), v3_zero(), 0);
    energy += 0.5 * v3_norm2(p->vel[i]) * m + 0.5 * v3_norm2(p->omega[i]) / p->inv_inertia[i] -
              v3_dot(f, p->pos[i]);
  }
  w->energy_initial += energy;
  adem_status st = adem_world_check_periodic(w, err); /* a poured sphere may be the largest */
  if (!st) st = adem_world_build_neighbors(w, err);
  if (!st) w->prepared = true;
  return st;
}

void adem_world_add_external_work(adem_world *w, double work) { w->energy_initial += work; }

adem_status adem_world_add_group(adem_world *w, const char *name, adem_vec3 external_force,
                                 int *index, adem_error *err) {
  int k = adem_world_find_group(w, name);
  if (k >= 0) {
    w->groups[k].external_force = external_force;
    if (index) *index = k;
    return ADEM_OK;
  }
  if (w->ngroups >= 65535) return adem_error_set(err, ADEM_ERR_INPUT, "too many groups");
  adem_group *g = realloc(w->groups, (size_t)(w->ngroups + 1) * sizeof *g);
  if (!g) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  w->groups = g;
  memset(&g[w->ngroups], 0, sizeof *g);
  snprintf(g[w->ngroups].name, sizeof g->name, "%s", name);
  g[w->ngroups].external_force = external_force;
  if (index) *index = w->ngroups;
  w->ngroups++;
  return ADEM_OK;
}

int adem_world_find_group(const adem_world *w, const char *name) {
  for (int k = 0; k < w->ngroups; ++k)
    if (strcmp(w->groups[k].name, name) == 0) return k;
  return -1;
}

adem_status adem_world_add_particle(adem_world *w, const adem_particle_def *def, uint64_t *id,
                                    adem_error *err) {
  if (!(def->radius > 0.0) || !isfinite(def->radius)) {
    return adem_error_set(err, ADEM_ERR_INPUT, "particle radius %g must be > 0", def->radius);
  }
  if (def->material < 0 || def->material >= w->mat.n) {
    return adem_error_set(err, ADEM_ERR_INPUT, "particle material %d does not exist", def->material);
  }
  const adem_material_def *m = &w->mat.m[def->material].def;
  if (!(m->density > 0.0) || m->rigid) {
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "material '%s' cannot make particles: it needs a density > 0 and must not be "
                          "rigid",
                          m->name);
  }
  if (def->group < 0 || def->group >= w->ngroups) {
    return adem_error_set(err, ADEM_ERR_INPUT, "particle group %d does not exist", def->group);
  }
  if (!v3_isfinite(def->position) || !v3_isfinite(def->velocity) ||
      !v3_isfinite(def->angular_velocity)) {
    return adem_error_set(err, ADEM_ERR_INPUT, "particle position and velocities must be finite");
  }
  adem_particles *p = &w->p;
  size_t i = adem_particles_append(p, w->next_id, def->position, def->velocity,
                                   def->angular_velocity, def->radius, m->density, def->material,
                                   def->group);
  if (i == SIZE_MAX) {
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory adding particles");
  }
  w->next_id++;
  /* a world that runs takes new particles in at its next step, without a new prepare */
  if (w->prepared && !w->admit_pending) {
    w->admit_pending = true;
    w->admit_from = i;
  }
  if (id) *id = p->id[i];
  return ADEM_OK;
}

void adem_world_set_gravity(adem_world *w, adem_vec3 g) { w->gravity = g; }
int adem_default_thread_count(void) { return adem_default_threads(); }

void adem_world_set_threads(adem_world *w, int nthreads) {
  w->nthreads = nthreads > 0 ? nthreads : adem_default_threads();
}
void adem_world_set_skin(adem_world *w, double skin_fraction) {
  w->nb.skin_fraction = skin_fraction;
  w->prepared = false;
}
void adem_world_set_max_overlap_ratio(adem_world *w, double ratio) { w->max_overlap_ratio = ratio; }
void adem_world_set_initial_overlap(adem_world *w, double ratio) {
  w->initial_overlap = ratio > 0.0 ? ratio : 0.0;
  w->prepared = false;
}
void adem_world_set_domain(adem_world *w, adem_vec3 lo, adem_vec3 hi) {
  w->has_domain = true;
  w->domain_lo = lo;
  w->domain_hi = hi;
}
adem_status adem_world_set_periodic(adem_world *w, adem_vec3 lo, adem_vec3 hi, unsigned axes,
                                    adem_error *err) {
  const double a[3] = {lo.x, lo.y, lo.z}, b[3] = {hi.x, hi.y, hi.z};
  if (axes > 7u) return adem_error_set(err, ADEM_ERR_INPUT, "periodic axes %u: allowed are the bits 1 (x), 2 (y), 4 (z)", axes);
  for (int d = 0; d < 3; ++d)
    if ((axes >> d) & 1u && !(isfinite(a[d]) && isfinite(b[d]) && a[d] < b[d]))
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "periodic box along %c: max %g must be finite and greater than min %g",
                            "xyz"[d], b[d], a[d]);
  adem_world_set_domain(w, lo, hi);
  memset(&w->periodic, 0, sizeof w->periodic);
  w->periodic.axes = axes;
  for (int d = 0; d < 3; ++d)
    if ((axes >> d) & 1u) {
      w->periodic.lo[d] = a[d];
      w->periodic.len[d] = b[d] - a[d];
    }
  w->prepared = false;
  return ADEM_OK;
}

adem_status adem_world_particle_image(const adem_world *w, uint64_t id, int32_t out[3],
                                      adem_error *err) {
  const adem_particles *p = &w->p;
  for (size_t i = 0; i < p->n; ++i)
    if (p->id[i] == id) {
      for (int d = 0; d < 3; ++d) out[d] = adem_particles_image(p, i).n[d];
      return ADEM_OK;
    }
  return adem_error_set(err, ADEM_ERR_INPUT, "no particle has id %llu", (unsigned long long)id);
}

void adem_world_set_neighbor_search(adem_world *w, adem_neighbor_search how) {
  adem_world_use_brute_force(w, how == ADEM_SEARCH_ALL_PAIRS);
}
void adem_world_use_brute_force(adem_world *w, int on) {
  w->nb.brute_force = on != 0;
  w->prepared = false;
}
void adem_world_set_dt(adem_world *w, double dt) { w->dt = dt; }
void adem_world_set_contact_scheme(adem_world *w, adem_contact_scheme scheme) {
  w->second_order = scheme == ADEM_CONTACTS_SECOND_ORDER;
}
/* The pair lists keep their balance records while the balance is on, and only then; switched
 * on, the balance finds fresh (zero) records: no lost spring energy of pairs that opened before.
 * The particles' balance fields (dissipated, wall work) do the same: switched on again, their
 * totals start from zero. The force pass makes both agree with the flag (sync_optional_fields). */
void adem_world_set_energy_balance(adem_world *w, bool on) { w->energy_balance = on; }
bool adem_world_energy_balance(const adem_world *w) { return w->energy_balance; }
double adem_world_dt(const adem_world *w) { return w->dt; }
double adem_world_time(const adem_world *w) { return w->time; }
uint64_t adem_world_step_count(const adem_world *w) { return w->step; }
size_t adem_world_particle_count(const adem_world *w) { return w->p.n; }

uint32_t *adem_world_id_order(const adem_world *w) {
  uint32_t *order = malloc((w->p.n + 1) * sizeof *order);
  if (order && adem_particles_id_order(&w->p, order)) {
    free(order);
    order = NULL;
  }
  return order;
}

double adem_sum(const double *x, size_t n) {
  adem_block_sum s = ADEM_BLOCK_SUM_START;
  for (size_t k = 0; k < n; ++k) adem_block_sum_add(&s, x[k]);
  return adem_block_sum_result(&s);
}

adem_status adem_world_prepare(adem_world *w, adem_error *err) {
  adem_fpenv_ensure(w->nthreads); /* FTZ/DAZ or another rounding would change bits (fpenv.h) */
  adem_status st = adem_materials_derive(&w->mat, err);
  if (st) return st;
  if (!(w->dt > 0.0)) {
    adem_step_estimate est = adem_world_estimate_step(w, 1.0);
    w->dt = isfinite(est.dt) ? est.dt : 1e-6;
  }
  adem_world_place_walls(w, w->time);
  adem_world_place_frozen(w, w->time);
  st = adem_world_check_periodic(w, err);
  if (st) return st;
  st = adem_world_build_neighbors(w, err);
  if (st) return st;
  st = adem_world_check_initial_state(w, err);
  if (st) return st;
  adem_world_default_domain(w);
  if (sync_optional_fields(w))
    return adem_error_set(err, ADEM_ERR_NOMEM,
                          "out of memory for the energy balance's records or the BROF impulses");
  adem_world_compute_forces(w);
  /* the balance starts here: what this pass dissipated belongs to no step (its opening-kick
   * share, held in *_next, does) */
  for (size_t i = 0; i < w->p.n; ++i) {
    if (w->p.dissipated) w->p.dissipated[i] = w->p.wall_work[i] = 0.0;
    if (w->p.brof_impulse) w->p.brof_impulse[i] = v3_zero();
  }
  adem_diagnostics d = adem_world_diagnostics(w);
  w->energy_initial = adem_world_total_energy(&d);
  w->prepared = true;
  return ADEM_OK;
}

/* The step's names for its run-time checks (world_checks.c) and the servos (world_servo.c). */
static void note_tunnelling(adem_world *w, double dt) { adem_world_note_tunnelling(w, dt); }
static adem_status servo_step(adem_world *w, double dt, adem_error *err) {
  return adem_world_servo_step(w, dt, err);
}
static adem_status check_state(const adem_world *w, adem_error *err) {
  return adem_world_check_state(w, err);
}

adem_status adem_world_step(adem_world *w, uint64_t nsteps, adem_error *err) {
  if (!w->prepared) {
    adem_status st = adem_world_prepare(w, err);
    if (st) return st;
  }
  if (w->admit_pending) {
    w->admit_pending = false;
    adem_status st = adem_world_admit_particles(w, w->admit_from, err);
    if (st) return st;
  }
  if (sync_optional_fields(w))
    return adem_error_set(err, ADEM_ERR_NOMEM,
                          "out of memory for the energy balance's records or the BROF impulses");
  double dt = w->dt;
  for (uint64_t s = 0; s < nsteps; ++s) {
    int nthreads = adem_world_threads(w);
    /* the opening kick and the drift in one sweep; the drift's largest excess over a radius is
     * all the step pays for the tunnelling check */
    if (adem_particles_kick_drift(&w->p, 0.5 * dt, dt, nthreads) > 0.0 && w->walls.mesh.ntris > 0)
      note_tunnelling(w, dt);
    const adem_world_split *sp = w->split;
    if (sp) {
      adem_status st = sp->refresh(sp->ctx, w, err);
      if (st) return st;
    }
    if (adem_walls_has_servo(&w->walls)) {
      adem_status st = servo_step(w, dt, err);
      if (st) return st;
    }
    adem_world_place_walls(w, (double)(w->step + 1) * dt);
    adem_world_place_frozen(w, (double)(w->step + 1) * dt);
    bool rebuild = adem_neighbors_need_rebuild(&w->nb, &w->p, adem_world_wall_shift(w), nthreads);
    if (sp) rebuild = sp->any(sp->ctx, rebuild); /* the largest displacement of all processes */
    if (rebuild) {
      adem_status st = sp ? sp->build(sp->ctx, w, err) : adem_world_build_neighbors(w, err);
      if (st) return st;
    }
    compute_forces(w, s + 1 == nsteps, false);
    if (sp && w->walls.mesh.ntris > 0 && adem_walls_has_servo(&w->walls)) {
      adem_status st = sp->mesh_loads(sp->ctx, w, err); /* the servos' next measure */
      if (st) return st;
    }
    adem_particles_kick(&w->p, 0.5 * dt, true, nthreads);
    w->step++;
    w->time = (double)w->step * dt;
    adem_status st = check_state(w, err);
    if (sp && sp->any(sp->ctx, st != ADEM_OK) && !st)
      st = adem_error_set(err, ADEM_ERR_RUNTIME, "another process stopped at t = %.9g s (step %llu)",
                          w->time, (unsigned long long)w->step);
    if (st) return st;
  }
  return ADEM_OK;
}
/* ---------------------------------------------------------------- reading the state */

int adem_particle_field_components(adem_particle_field field) {
  return field <= ADEM_FIELD_ROLLING_TORQUE || field == ADEM_FIELD_EXTERNAL_FORCE ? 3 : 1;
}

/* Number of touching contacts of each particle index (particles and walls). */
static void count_contacts(const adem_world *w, double *count) {
  const adem_particles *p = &w->p;
  memset(count, 0, p->n * sizeof *count);
  for (size_t k = 0; k < w->pp.n; ++k)
    if (w->pp.touching[k]) {
      count[w->pp.a[k]] += 1.0;
      count[w->pp.b[k]] += 1.0;
    }
  for (size_t k = 0; k < w->pw.n; ++k)
    if (w->pw.touching[k]) count[w->pw.a[k]] += 1.0;
  for (size_t k = 0; k < w->pm.l.n; ++k)
    if (w->pm.l.touching[k]) count[w->pm.l.a[k]] += 1.0;
}

adem_status adem_world_get_particles(const adem_world *w, adem_particle_field field, double *out,
                                     size_t capacity, adem_error *err) {
  const adem_particles *p = &w->p;
  size_t n = p->n;
  int nc = adem_particle_field_components(field);
  if ((unsigned)field > ADEM_FIELD_EXTERNAL_FORCE)
    return adem_error_set(err, ADEM_ERR_INPUT, "unknown particle field %d", (int)field);
  if (capacity < n * (size_t)nc)
    return adem_error_set(err, ADEM_ERR_INPUT, "%zu particles need %zu doubles, the array has %zu",
                          n, n * (size_t)nc, capacity);
  double *count = NULL;
  if (field == ADEM_FIELD_CONTACTS) {
    count = malloc((n + 1) * sizeof *count);
    if (!count) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    count_contacts(w, count);
  }
  /* the k-th smallest id at k: the id itself while no particle has been removed */
  uint32_t *order = adem_world_id_order(w);
  if (!order) {
    free(count);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  for (size_t id = 0; id < n; ++id) {
    size_t i = order[id];
    const adem_vec3 *v = NULL;
    adem_vec3 ext;
    double s = 0.0;
    switch (field) {
      case ADEM_FIELD_POSITION: v = &p->pos[i]; break;
      case ADEM_FIELD_VELOCITY: v = &p->vel[i]; break;
      case ADEM_FIELD_ANGULAR_VELOCITY: v = &p->omega[i]; break;
      case ADEM_FIELD_FORCE: v = &p->force[i]; break;
      case ADEM_FIELD_TORQUE: v = &p->torque[i]; break;
      case ADEM_FIELD_ROLLING_TORQUE: v = &p->rolling_torque[i]; break;
      case ADEM_FIELD_RADIUS: s = p->radius[i]; break;
      case ADEM_FIELD_MASS: s = 1.0 / p->inv_mass[i]; break;
      case ADEM_FIELD_MATERIAL: s = p->material[i]; break;
      case ADEM_FIELD_CONTACTS: s = count[i]; break;
      case ADEM_FIELD_PATH_LENGTH: s = p->path_length[i]; break;
      case ADEM_FIELD_INVERSE_MASS: s = p->inv_mass[i]; break;
      case ADEM_FIELD_INVERSE_INERTIA: s = p->inv_inertia[i]; break;
      case ADEM_FIELD_EXTERNAL_FORCE:
        ext = adem_particles_ext_force(p, i);
        v = &ext;
        break;
    }
    if (v) {
      out[3 * id] = v->x;
      out[3 * id + 1] = v->y;
      out[3 * id + 2] = v->z;
    } else {
      out[id] = s;
    }
  }
  free(order);
  free(count);
  return ADEM_OK;
}

adem_status adem_world_set_particle(adem_world *w, uint64_t id, const adem_vec3 *position,
                                    const adem_vec3 *velocity, const adem_vec3 *angular_velocity,
                                    adem_error *err) {
  adem_particles *p = &w->p;
  size_t i = 0;
  if (!adem_world_particle_index(w, id, &i))
    return adem_error_set(err, ADEM_ERR_INPUT, "no particle has id %llu", (unsigned long long)id);
  if ((position && !v3_isfinite(*position)) || (velocity && !v3_isfinite(*velocity)) ||
      (angular_velocity && !v3_isfinite(*angular_velocity)))
    return adem_error_set(err, ADEM_ERR_INPUT, "particle position and velocities must be finite");
  adem_particles_set_state(p, i, position, velocity, angular_velocity);
  return ADEM_OK;
}

static void contact_from(adem_contact_info *c, adem_contact_kind kind, uint64_t a, uint64_t b,
                         const adem_pair_list *l, size_t k) {
  c->kind = kind;
  c->a = a;
  c->b = b;
  size_t s = adem_pairs_slot(l, k);
  c->force = l->res[s].force_a;
  c->overlap_ratio = l->res[s].overlap_ratio;
  c->elastic = l->elastic[s];
  c->tangential_history = l->hist[s].tangential;
  c->rolling_history = l->hist[s].rolling;
}

size_t adem_world_contacts(const adem_world *w, adem_contact_info *out, size_t capacity) {
  size_t n = 0;
  const uint64_t *id = w->p.id;
  for (size_t k = 0; k < w->pp.n; ++k)
    if (w->pp.touching[k] && n++ < capacity)
      contact_from(&out[n - 1], ADEM_CONTACT_PARTICLE, id[w->pp.a[k]], id[w->pp.b[k]], &w->pp, k);
  for (size_t k = 0; k < w->pw.n; ++k)
    if (w->pw.touching[k] && n++ < capacity)
      contact_from(&out[n - 1], ADEM_CONTACT_PLANE, id[w->pw.a[k]], w->pw.b[k], &w->pw, k);
  const adem_mesh_pairs *pm = &w->pm;
  for (size_t k = 0; k < pm->l.n; ++k)
    if (pm->l.touching[k] && n++ < capacity)
      contact_from(&out[n - 1], ADEM_CONTACT_MESH, id[pm->l.a[k]],
                   w->walls.mesh.group[pm->owner[k]], &pm->l, k);
  return n;
}

void adem_world_clear_history(adem_world *w) {
  adem_pair_list *lists[3] = {&w->pp, &w->pw, &w->pm.l};
  for (int s = 0; s < 3; ++s)
    for (size_t k = 0; k < lists[s]->n; ++k) {
      size_t q = adem_pairs_slot(lists[s], k); /* slot 0 of a sparse list: zeros already */
      memset(&lists[s]->hist[q], 0, sizeof lists[s]->hist[q]);
    }
}

adem_status adem_world_pair_info(adem_world *w, int a, int b, adem_pair_info *out,
                                 adem_error *err) {
  if (a < 0 || b < 0 || a >= w->mat.n || b >= w->mat.n)
    return adem_error_set(err, ADEM_ERR_INPUT, "material %d or %d does not exist", a, b);
  if (!w->mat.pairs) {
    adem_status st = adem_materials_derive(&w->mat, err);
    if (st) return st;
  }
  const adem_interaction *it = adem_world_interaction(w, a, b);
  const adem_pair_params *pp = &it->pp;
  memset(out, 0, sizeof *out);
  out->normal = it->normal;
  out->damping = it->damping;
  out->tangential = it->tangential;
  out->rolling = it->rolling;
  out->E = pp->E;
  out->G = pp->G;
  out->E_real = pp->E_real;
  out->G_real = pp->G_real;
  out->restitution = pp->restitution;
  out->beta = pp->beta;
  out->friction = pp->friction;
  out->gamma = pp->gamma;
  out->gamma_real = pp->gamma_real;
  for (int k = 0; k < ADEM_PARAM_COUNT; ++k) {
    out->param[k] = pp->param[k];
    out->param_a[k] = pp->param_a[k];
    out->param_b[k] = pp->param_b[k];
    out->set_param[k] = it->set_param[k];
  }
  out->set_restitution = it->set_restitution;
  out->set_friction = it->set_friction;
  return ADEM_OK;
}

void adem_world_plane_forces(const adem_world *w, adem_vec3 *out) {
  for (int k = 0; k < w->walls.nplanes; ++k) out[k] = v3_zero();
  const adem_pair_list *l = &w->pw;
  const adem_neighbors *nb = &w->nb;
  /* over the particles by id: the servos move by these sums (order independence) */
  for (size_t r = 0; r < nb->gathered; ++r) {
    size_t i = nb->id_order[r];
    for (size_t e = nb->pw_start[i]; e < nb->pw_start[i + 1]; ++e) {
      size_t k = nb->pw_entries[e];
      uint32_t wall = l->b[k];
      if (wall < (uint32_t)w->walls.nplanes) out[wall] = v3_sub(out[wall], l->res[k].force_a);
    }
  }
  adem_world_frozen_plane_forces(w, out);
}

uint64_t adem_world_neighbor_builds(const adem_world *w) { return w->nb.rebuilds; }
