/* The world: set-up, velocity-Verlet stepping (H3-H4), safety checks and diagnostics. */
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
#include "world.h"
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
  adem_neighbor_scope s = {&w->p,     &w->pp,      &w->pw,
                           &w->pm,    &w->walls,   &w->periodic,
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

/* A random permutation of 0 .. n-1 (Fisher-Yates; the modulo's bias does not matter here). */
static void random_permutation(size_t *perm, size_t n, adem_rng *r) {
  for (size_t k = 0; k < n; ++k) perm[k] = k;
  for (size_t k = n; k > 1; --k) {
    size_t j = (size_t)(adem_rng_next(r) % k), t = perm[k - 1];
    perm[k - 1] = perm[j];
    perm[j] = t;
  }
}

adem_status adem_world_shuffle_storage(adem_world *w, uint64_t seed, adem_error *err) {
  if (w->admit_pending)
    return adem_error_set(err, ADEM_ERR_INPUT, "particles wait to be admitted: step first");
  adem_particles *p = &w->p;
  adem_mesh_pairs *pm = &w->pm;
  size_t n = p->n, m = w->pp.n;
  if (w->pw.n > m) m = w->pw.n;
  if (pm->l.n > m) m = pm->l.n;
  size_t *perm = malloc((n + 1) * sizeof *perm), *inv = malloc((n + 1) * sizeof *inv);
  size_t *pairs = malloc((m + 1) * sizeof *pairs), *start = malloc((n + 1) * sizeof *start);
  adem_status st = perm && inv && pairs && start ? ADEM_OK : ADEM_ERR_NOMEM;
  adem_rng r = adem_rng_seed(seed);
  if (!st) {
    random_permutation(perm, n, &r);
    for (size_t k = 0; k < n; ++k) inv[perm[k]] = k;
    st = adem_particles_permute(p, perm);
  }
  adem_pair_list *lists[2] = {&w->pp, &w->pw};
  for (int s = 0; s < 2 && !st; ++s) {
    adem_pair_list *l = lists[s];
    random_permutation(pairs, l->n, &r);
    st = adem_pairs_permute(l, pairs);
    for (size_t k = 0; k < l->n && !st; ++k) {
      l->a[k] = (uint32_t)inv[l->a[k]];
      if (s == 0) l->b[k] = (uint32_t)inv[l->b[k]]; /* a keeps the lower id */
    }
  }
  /* mesh slots: each particle's range moves with it, its slots in their order */
  if (!st && pm->start && pm->l.n > 0) {
    size_t q = 0;
    start[0] = 0;
    for (size_t k = 0; k < n; ++k) {
      for (size_t e = pm->start[perm[k]]; e < pm->start[perm[k] + 1]; ++e) pairs[q++] = e;
      start[k + 1] = q;
    }
    st = adem_mesh_pairs_permute(pm, pairs);
    if (!st) {
      memcpy(pm->start, start, (n + 1) * sizeof *start);
      for (size_t k = 0; k < pm->l.n; ++k) pm->l.a[k] = (uint32_t)inv[pm->l.a[k]];
    }
  }
  free(perm);
  free(inv);
  free(pairs);
  free(start);
  if (!st) st = adem_world_gather(w);
  if (st) return adem_error_set(err, st, "out of memory shuffling the particles");
  return ADEM_OK;
}

/* Makes the lists keep their balance records exactly while the balance is on (pairs.h). */
static adem_status sync_balance_records(adem_world *w) {
  adem_pair_list *lists[3] = {&w->pp, &w->pw, &w->pm.l};
  for (int s = 0; s < 3; ++s)
    if (adem_pairs_keep_balance(lists[s], w->energy_balance)) return ADEM_ERR_NOMEM;
  return ADEM_OK;
}

/* energy: the pass computes the normal laws' stored energies, which only the diagnostics read
 * (a JKR contact's costs a cbrt and four pow): the last pass of a call to adem_world_step and
 * the pass of prepare, after which the diagnostics can be read. */
static void compute_forces(adem_world *w, bool energy, bool hold_history) {
  /* the balance's terms need their records: adem_world_step and prepare report a failure to
   * allocate them before they get here */
  bool balance = w->energy_balance && sync_balance_records(w) == ADEM_OK;
  if (w->predicted_cap < w->p.n) { /* without it the pass predicts per contact: the same bits */
    free(w->predicted);
    size_t cap = w->p.n + w->p.n / 8;
    w->predicted = malloc(2 * cap * sizeof *w->predicted);
    w->predicted_cap = w->predicted ? cap : 0;
  }
  adem_force_scope s = {&w->p,     &w->pp,   &w->pw,      &w->pm, &w->walls,
                        &w->nb,    &w->mat,  w->groups,   w->gravity,
                        w->dt,     adem_world_threads(w), w->second_order, energy,
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
  size_t cleared = st ? 0 : adem_history_switch_all(mt, old, &w->p, &w->pp, &w->pw, &w->pm,
                                                     &w->walls, w->energy_balance);
  free(old);
  if (cleared > 0)
    adem_log(ADEM_LOG_INFO, "t = %.9g s: %zu contact histories cleared (their tangential or "
             "rolling law changed, with no exact conversion; docs/models.md)", w->time, cleared);
  return st;
}

void adem_world_set_group_force(adem_world *w, int group, adem_vec3 force) {
  if (group >= 0 && group < w->ngroups) w->groups[group].external_force = force;
}

void adem_world_change_skin(adem_world *w, double skin_fraction) { w->nb.skin_fraction = skin_fraction; }

static adem_status check_periodic(const adem_world *w, adem_error *err);

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
                         p->ext_force[i]);
    adem_particles_set_loads(p, i, f, v3_zero(), v3_zero(), 0);
    energy += 0.5 * v3_norm2(p->vel[i]) * m + 0.5 * v3_norm2(p->omega[i]) / p->inv_inertia[i] -
              v3_dot(f, p->pos[i]);
  }
  w->energy_initial += energy;
  adem_status st = check_periodic(w, err); /* a poured sphere may be the largest */
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
                   "rigid", m->name);
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
      for (int d = 0; d < 3; ++d) out[d] = p->image[i].n[d];
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
 * The force pass makes the lists agree with the flag (sync_balance_records). */
void adem_world_set_energy_balance(adem_world *w, bool on) { w->energy_balance = on; }
bool adem_world_energy_balance(const adem_world *w) { return w->energy_balance; }
double adem_world_dt(const adem_world *w) { return w->dt; }
double adem_world_time(const adem_world *w) { return w->time; }
uint64_t adem_world_step_count(const adem_world *w) { return w->step; }
size_t adem_world_particle_count(const adem_world *w) { return w->p.n; }

/* Collision time of a material pair (notes section 6). A simplified JKR contact speeds the
 * spheres up to sqrt(v_ref^2 + 2|U_min|/m*) as it pulls them in (U_min the JKR energy at
 * equilibrium, H7-H10), and once captured they oscillate about the equilibrium with the period
 * 2 pi sqrt(m* / (1.2 E a0)) (dF/d delta = 6 E a0/5 there): the shortest of t_c at that speed and
 * half that period. */
static double pair_collision_time(const adem_interaction *it, double m_eff, double r_eff,
                                  double v_ref) {
  const adem_pair_params *pp = &it->pp;
  if (it->normal != ADEM_NORMAL_JKR || !(pp->gamma > 0.0))
    return adem_hertz_collision_time(m_eff, r_eff, pp->E, v_ref);
  double a0 = adem_jkr_a0(pp->gamma, r_eff, pp->E);
  double u_min = adem_jkr_energy(pp->gamma, r_eff, pp->E, a0); /* < 0 */
  double v = sqrt(v_ref * v_ref - 2.0 * u_min / m_eff);
  double t_osc = 2.0 * ADEM_PI * sqrt(m_eff / (1.2 * pp->E * a0));
  return fmin(adem_hertz_collision_time(m_eff, r_eff, pp->E, v), 0.5 * t_osc);
}

adem_step_estimate adem_world_estimate_step(const adem_world *w, double v_ref) {
  adem_step_estimate est = {v_ref, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};
  adem_world *mw = (adem_world *)w; /* derive the pair table if the caller has not prepared */
  if (!w->mat.pairs) adem_materials_derive(&mw->mat, NULL);
  int nm = w->mat.n;
  /* Smallest particle of each material sets the shortest times (t_c and t_R scale with r). */
  double *rmin = malloc((size_t)(nm > 0 ? nm : 1) * sizeof *rmin);
  if (!rmin) return est;
  for (int k = 0; k < nm; ++k) rmin[k] = INFINITY;
  for (size_t i = 0; i < w->p.n; ++i)
    rmin[w->p.material[i]] = fmin(rmin[w->p.material[i]], w->p.radius[i]);
  if (w->insert_rmin) /* particles poured later count as present */
    for (int k = 0; k < nm; ++k) rmin[k] = fmin(rmin[k], w->insert_rmin[k]);
  for (int a = 0; a < nm; ++a) {
    if (!isfinite(rmin[a])) continue;
    const adem_material *ma = &w->mat.m[a];
    double r = rmin[a];
    double m = ma->def.density * (4.0 / 3.0) * ADEM_PI * r * r * r;
    /* Rayleigh time with the modified shear modulus (notes section 6). */
    double tR = ADEM_PI * r * sqrt(ma->def.density / ma->shear_mod) /
                (0.1631 * ma->def.poisson + 0.8766);
    est.t_rayleigh = fmin(est.t_rayleigh, tR);
    for (int b = 0; b < nm; ++b) {
      const adem_interaction *it = adem_world_interaction(w, a, b);
      if (isfinite(rmin[b])) {
        double rb = rmin[b];
        double mb = w->mat.m[b].def.density * (4.0 / 3.0) * ADEM_PI * rb * rb * rb;
        double tc = pair_collision_time(it, m * mb / (m + mb), r * rb / (r + rb), v_ref);
        est.t_collision = fmin(est.t_collision, tc);
        est.dt_stable = fmin(est.dt_stable, adem_step_limit_pair(it, tc, m, r, mb, rb));
      }
    }
    for (int k = 0; k < w->walls.nplanes; ++k) {
      const adem_interaction *it = adem_world_interaction(w, a, w->walls.planes[k].def.material);
      double tc = pair_collision_time(it, m, r, v_ref);
      est.t_collision = fmin(est.t_collision, tc);
      est.dt_stable = fmin(est.dt_stable, adem_step_limit_pair(it, tc, m, r, 0.0, 0.0));
    }
    for (int k = 0; k < w->walls.mesh.ngroups; ++k) {
      const adem_interaction *it = adem_world_interaction(w, a, w->walls.mesh.groups[k].material);
      double tc = pair_collision_time(it, m, r, v_ref);
      est.t_collision = fmin(est.t_collision, tc);
      est.dt_stable = fmin(est.dt_stable, adem_step_limit_pair(it, tc, m, r, 0.0, 0.0));
    }
  }
  free(rmin);
  est.dt = fmin(est.t_collision / 50.0, 0.2 * est.t_rayleigh); /* about 50 steps a collision */
  /* and a fifth of the stability limit: the rolling spring DTK keeps real under reduced
   * stiffness outruns the normal mode below f ~ 1e-2 (docs/models.md, "Time step") */
  est.dt = fmin(est.dt, 0.2 * est.dt_stable);
  est.dt_limit = fmin(est.t_collision / ADEM_STEP_LIMIT_DIVISOR, est.dt_stable);
  return est;
}

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

static double total_energy(const adem_diagnostics *d) {
  return d->kinetic + d->rotational + d->potential + d->elastic;
}

/* Rejects particles that cut into a mesh face at the start, naming the first by index (as the
 * pp check does): a wall cannot push a particle out gently, it would shoot it off. */
static adem_status check_initial_mesh(const adem_world *w, adem_error *err) {
  const adem_particles *p = &w->p;
  const adem_mesh_pairs *pm = &w->pm;
  if (w->walls.mesh.ntris == 0 || !pm->start) return ADEM_OK;
  for (size_t i = 0; i < p->n; ++i)
    for (size_t k = pm->start[i]; k < pm->start[i + 1]; ++k) {
      uint32_t t = pm->l.b[k];
      adem_vec3 q;
      adem_triangle_feature f;
      double d = sqrt(adem_triangle_distance2(&w->walls.mesh, t, p->pos[i], &q, &f));
      double overlap = p->radius[i] - d;
      if (overlap > fmax(1e-9, w->initial_overlap) * p->radius[i])
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "particle id %llu at (%g, %g, %g) overlaps mesh group '%s' (triangle "
                              "%u) by %g m (%.3g of its radius, allowed %.3g by "
                              "limits.initial_overlap) at the start; move it off the wall or shrink "
                              "it. Particles from another run's checkpoint (`type: state`) keep "
                              "their places but the walls start where this case puts them: a wall "
                              "that moved or turned in that run is back at its file placement",
                              (unsigned long long)p->id[i], p->pos[i].x, p->pos[i].y, p->pos[i].z,
                              w->walls.mesh.groups[w->walls.mesh.group[t]].name, t, overlap,
                              overlap / p->radius[i], w->initial_overlap);
    }
  return ADEM_OK;
}

/* Rejects overlapping particles and particles behind a wall, naming them. */
static adem_status check_initial_state(const adem_world *w, adem_error *err) {
  const adem_particles *p = &w->p;
  for (size_t k = 0; k < w->pp.n; ++k) {
    size_t i = w->pp.a[k], j = w->pp.b[k];
    double dist = v3_norm(adem_periodic_min_image(&w->periodic, v3_sub(p->pos[j], p->pos[i])));
    double overlap = p->radius[i] + p->radius[j] - dist;
    double tol = fmax(1e-9, w->initial_overlap) * fmin(p->radius[i], p->radius[j]);
    if (overlap > tol)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "initial particles overlap: id %llu at (%g, %g, %g) and id %llu at "
                            "(%g, %g, %g) overlap by %g m (%.3g of the smaller radius, allowed "
                            "%.3g); move them apart or shrink them, or allow overlaps from a "
                            "settled bed with limits.initial_overlap",
                            (unsigned long long)p->id[i], p->pos[i].x, p->pos[i].y, p->pos[i].z,
                            (unsigned long long)p->id[j], p->pos[j].x, p->pos[j].y, p->pos[j].z,
                            overlap, overlap / fmin(p->radius[i], p->radius[j]), w->initial_overlap);
  }
  for (size_t i = 0; i < p->n; ++i)
    for (int k = 0; k < w->walls.nplanes; ++k) {
      const adem_plane_def *pl = &w->walls.planes[k].def;
      if (w->walls.planes[k].inactive || p->frozen[i]) continue; /* a frozen one is wall */
      adem_wall_near near = adem_wall_nearest(pl, p->pos[i]);
      double d = near.live ? near.gap : 0.0;
      if (d < 0.0)
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "particle id %llu at (%g, %g, %g) is outside wall '%s' (its centre "
                              "is %g m behind its surface)",
                              (unsigned long long)p->id[i], p->pos[i].x, p->pos[i].y, p->pos[i].z,
                              pl->name, -d);
    }
  return check_initial_mesh(w, err);
}

/* Periodic boxes the run cannot use: a length below 2 (largest diameter + skin), where a pair
 * could touch through two images at once, a plane cutting a periodic axis, a cylinder or plate
 * or a mesh within reach of a periodic face unless it is the same all along the axis. */
static adem_status check_periodic(const adem_world *w, adem_error *err) {
  const adem_periodic *pb = &w->periodic;
  if (!pb->axes) return ADEM_OK;
  double rmax = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) rmax = fmax(rmax, w->p.radius[i]);
  double dmax = 2.0 * rmax, skin = w->nb.skin_fraction * dmax;
  for (int d = 0; d < 3; ++d) {
    if (!((pb->axes >> d) & 1u)) continue;
    double need = 2.0 * (dmax + skin);
    if (pb->len[d] < need)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "the periodic box along %c is %g m long; the minimum image needs at "
                            "least 2 (largest diameter + skin) = 2 (%g + %g) = %g m",
                            "xyz"[d], pb->len[d], dmax, skin, need);
    for (int k = 0; k < w->walls.nplanes; ++k) {
      const adem_plane_def *pl = &w->walls.planes[k].def;
      if (pl->shape != ADEM_WALL_PLANE) { /* a cylinder or disc: cylinder.c */
        adem_status st = adem_wall_check_periodic(pl, d, pb->lo[d], pb->len[d], rmax + skin, err);
        if (st) return st;
        continue;
      }
      double n[3] = {pl->normal.x, pl->normal.y, pl->normal.z};
      if (fabs(n[d]) > 1e-12 * v3_norm(pl->normal))
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "plane wall '%s' (normal (%g, %g, %g)) cuts the periodic axis %c; a "
                              "plane in a periodic box must be parallel to its periodic axes",
                              pl->name, n[0], n[1], n[2], "xyz"[d]);
    }
  }
  /* meshes are not imaged: a shell the same along the axis past both faces, or kept inside them
   * (mesh_periodic.c) */
  for (int d = 0; d < 3; ++d)
    if ((pb->axes >> d) & 1u) {
      adem_status st = adem_mesh_check_periodic(&w->walls.mesh, d, pb->lo[d], pb->len[d],
                                                rmax + skin, err);
      if (st) return st;
    }
  return ADEM_OK;
}

/* Escape check box: the case's domain, or the initial extent of particles and wall points
 * widened generously on each side. */
static void default_domain(adem_world *w) {
  if (w->has_domain || w->p.n == 0) return;
  adem_vec3 lo = w->p.pos[0], hi = lo;
  double rmax = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) {
    adem_vec3 x = w->p.pos[i];
    lo = v3(fmin(lo.x, x.x), fmin(lo.y, x.y), fmin(lo.z, x.z));
    hi = v3(fmax(hi.x, x.x), fmax(hi.y, x.y), fmax(hi.z, x.z));
    rmax = fmax(rmax, w->p.radius[i]);
  }
  for (int k = 0; k < w->walls.nplanes; ++k) {
    adem_vec3 x0, x1; /* a plane's point; a cylinder's or a disc's box (cylinder.c) */
    adem_wall_bounds(&w->walls.planes[k].def, &x0, &x1);
    lo = v3(fmin(lo.x, x0.x), fmin(lo.y, x0.y), fmin(lo.z, x0.z));
    hi = v3(fmax(hi.x, x1.x), fmax(hi.y, x1.y), fmax(hi.z, x1.z));
  }
  if (w->walls.mesh.nverts > 0) { /* the meshes where they are now */
    adem_vec3 mlo, mhi;
    adem_mesh_bounds(&w->walls.mesh, &mlo, &mhi);
    lo = v3(fmin(lo.x, mlo.x), fmin(lo.y, mlo.y), fmin(lo.z, mlo.z));
    hi = v3(fmax(hi.x, mhi.x), fmax(hi.y, mhi.y), fmax(hi.z, mhi.z));
  }
  double ext = fmax(fmax(hi.x - lo.x, hi.y - lo.y), fmax(hi.z - lo.z, 100.0 * rmax));
  w->domain_lo = v3(lo.x - ext, lo.y - ext, lo.z - ext);
  w->domain_hi = v3(hi.x + ext, hi.y + ext, hi.z + ext);
  w->has_domain = true;
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
  st = check_periodic(w, err);
  if (st) return st;
  st = adem_world_build_neighbors(w, err);
  if (st) return st;
  st = check_initial_state(w, err);
  if (st) return st;
  default_domain(w);
  if (sync_balance_records(w))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the energy balance's pair records");
  adem_world_compute_forces(w);
  /* the balance starts here: what this pass dissipated belongs to no step (its opening-kick
   * share, held in *_next, does) */
  for (size_t i = 0; i < w->p.n; ++i) {
    w->p.dissipated[i] = w->p.wall_work[i] = 0.0;
    w->p.brof_impulse[i] = v3_zero();
  }
  adem_diagnostics d = adem_world_diagnostics(w);
  w->energy_initial = total_energy(&d);
  w->prepared = true;
  return ADEM_OK;
}

/* The box a particle must stay in, per axis: the domain's faces, or none (infinite) along a
 * periodic axis (crossing a periodic face is no escape), at an outlet face (leaving through it
 * is no escape either) or without a domain. */
typedef struct state_bounds {
  adem_vec3 lo, hi;
} state_bounds;
static state_bounds state_bounds_of(const adem_world *w) {
  unsigned per = w->has_domain ? w->periodic.axes : 7u, o = w->has_domain ? w->open_faces : 63u;
  state_bounds b;
  b.lo.x = (per & 1u) || (o & 1u) ? -INFINITY : w->domain_lo.x;
  b.hi.x = (per & 1u) || (o & 2u) ? INFINITY : w->domain_hi.x;
  b.lo.y = (per & 2u) || (o & 4u) ? -INFINITY : w->domain_lo.y;
  b.hi.y = (per & 2u) || (o & 8u) ? INFINITY : w->domain_hi.y;
  b.lo.z = (per & 4u) || (o & 16u) ? -INFINITY : w->domain_lo.z;
  b.hi.z = (per & 4u) || (o & 32u) ? INFINITY : w->domain_hi.z;
  return b;
}

/* A finite state inside the bounds. Without branches, so that the sweep over every particle
 * after each step is a few instructions a particle: x - x is +0 for a finite x and NaN for an
 * infinite or NaN one, and a NaN sum fails the compare (as does a NaN position any bound). */
static inline bool particle_ok(const adem_particles *p, const state_bounds *b, size_t i) {
  adem_vec3 x = p->pos[i], v = p->vel[i], o = p->omega[i];
  double z = (x.x - x.x) + (x.y - x.y) + (x.z - x.z) + (v.x - v.x) + (v.y - v.y) + (v.z - v.z) +
             (o.x - o.x) + (o.y - o.y) + (o.z - o.z);
  return (z == 0.0) & (x.x >= b->lo.x) & (x.x <= b->hi.x) & (x.y >= b->lo.y) & (x.y <= b->hi.y) &
         (x.z >= b->lo.z) & (x.z <= b->hi.z);
}

/* After a step: the first particle (lowest index) with a non-finite state, an overlap above the
 * limit, or a position outside the domain. Returns ADEM_OK when all is well. */
static adem_status check_state(const adem_world *w, adem_error *err) {
  const adem_particles *p = &w->p;
  size_t n = p->n;
  size_t bad = n;
  int nthreads = adem_world_threads(w);
  state_bounds sb = state_bounds_of(w);
  /* The lowest index found is the same for every thread count. */
  if (nthreads > 1) {
#ifdef ADEM_HAVE_OPENMP
#pragma omp parallel for schedule(static) num_threads(nthreads) reduction(min : bad)
#endif
    for (size_t i = 0; i < n; ++i)
      if (!particle_ok(p, &sb, i) && i < bad) bad = i;
  } else {
    /* blocks without an early exit (a loop the compiler can pack); the first bad one's found
     * again in its block */
    for (size_t i0 = 0; i0 < n && bad == n; i0 += 256) {
      size_t i1 = n - i0 < 256 ? n : i0 + 256;
      bool all = true;
      for (size_t i = i0; i < i1; ++i) all &= particle_ok(p, &sb, i);
      for (size_t i = i0; !all && i < i1; ++i)
        if (!particle_ok(p, &sb, i)) {
          bad = i;
          break;
        }
    }
  }
  if (bad < n) {
    adem_vec3 x = p->pos[bad];
    if (!v3_isfinite(x) || !v3_isfinite(p->vel[bad]) || !v3_isfinite(p->omega[bad]))
      return adem_error_set(err, ADEM_ERR_RUNTIME,
                            "particle id %llu has a non-finite position or velocity at t = %.9g s "
                            "(step %llu); reduce the time step",
                            (unsigned long long)p->id[bad], w->time, (unsigned long long)w->step);
    return adem_error_set(err, ADEM_ERR_RUNTIME,
                          "particle id %llu escaped the domain at t = %.9g s (step %llu): position "
                          "(%g, %g, %g)",
                          (unsigned long long)p->id[bad], w->time, (unsigned long long)w->step,
                          x.x, x.y, x.z);
  }
  if (!w->overlap_exceeded) return ADEM_OK; /* the force pass saw none above the limit */
  const adem_pair_list *lists[2] = {&w->pp, &w->pw};
  for (int s = 0; s < 2; ++s) {
    const adem_pair_list *l = lists[s];
    for (size_t k = 0; k < l->n; ++k) {
      if (!(l->res[k].overlap_ratio > w->max_overlap_ratio)) continue;
      const char *other = s == 0 ? "particle" : "wall";
      char name[ADEM_NAME_MAX + 32];
      if (s == 0)
        snprintf(name, sizeof name, "id %llu", (unsigned long long)p->id[l->b[k]]);
      else
        snprintf(name, sizeof name, "'%s'", w->walls.planes[l->b[k]].def.name);
      return adem_error_set(err, ADEM_ERR_RUNTIME,
                            "particle id %llu overlaps %s %s by %.3g of its radius (limit %.3g) at "
                            "t = %.9g s (step %llu); the time step is probably too large",
                            (unsigned long long)p->id[l->a[k]], other, name, l->res[k].overlap_ratio,
                            w->max_overlap_ratio, w->time, (unsigned long long)w->step);
    }
  }
  const adem_pair_list *lm = &w->pm.l;
  for (size_t k = 0; k < lm->n; ++k) {
    if (!(lm->res[k].overlap_ratio > w->max_overlap_ratio)) continue;
    return adem_error_set(err, ADEM_ERR_RUNTIME,
                          "particle id %llu overlaps mesh group '%s' by %.3g of its radius (limit "
                          "%.3g) at t = %.9g s (step %llu); the time step is probably too large",
                          (unsigned long long)p->id[lm->a[k]],
                          w->walls.mesh.groups[w->walls.mesh.group[w->pm.owner[k]]].name, lm->res[k].overlap_ratio,
                          w->max_overlap_ratio, w->time, (unsigned long long)w->step);
  }
  return ADEM_OK;
}

/* Particles that moved more than their radius in this step while they had candidate mesh
 * triangles (within radius + skin at the last build; the ranges still follow that build's
 * order): each may have passed through the wall between two force passes. */
static void note_tunnelling(adem_world *w, double dt) {
  const adem_particles *p = &w->p;
  const adem_mesh_pairs *pm = &w->pm;
  if (!pm->start) return;
  double t = (double)(w->step + 1) * dt;
  for (size_t i = 0; i < p->n; ++i) {
    double moved = dt * v3_norm(p->vel[i]);
    if (!(moved > p->radius[i]) || pm->start[i + 1] == pm->start[i]) continue;
    adem_tunnel_event e = {p->id[i], p->pos[i], t, moved, p->radius[i]};
    if (w->tunnel_count == 0) w->tunnel_first = e;
    if (w->tunnel_count < ADEM_TUNNEL_LOGGED)
      adem_log(ADEM_LOG_WARN,
               "particle id %llu moved %.3g m in one step (more than its radius %.3g m) next to a "
               "mesh wall at t = %.9g s, now at (%.6g, %.6g, %.6g) m: it may have passed through "
               "the wall; a smaller time.step avoids it",
               (unsigned long long)e.id, moved, e.radius, t, e.pos.x, e.pos.y, e.pos.z);
    w->tunnel_count++;
  }
}

uint64_t adem_world_tunnel_count(const adem_world *w) { return w->tunnel_count; }

const adem_tunnel_event *adem_world_tunnel_first(const adem_world *w) {
  return w->tunnel_count ? &w->tunnel_first : NULL;
}

/* Stiffness of a touching contact for the servo's stability rule: 1.5 F / delta, exact for Hertz
 * (F ~ delta^1.5), of the order for the other laws. */
static double contact_stiffness(const adem_pair_list *l, size_t k, const adem_particles *p) {
  double delta = l->res[k].overlap_ratio * p->radius[l->a[k]];
  return l->touching[k] && delta > 0.0 ? 1.5 * v3_norm(l->res[k].force_a) / delta : 0.0;
}

static void servo_warn(adem_motion *m, const char *name, double K, double dt) {
  double g = m->servo.gain * K * dt;
  if (m->servo_warned || !(g > 0.5)) return;
  m->servo_warned = true;
  adem_log(ADEM_LOG_WARN,
           "the servo of wall '%s' may be unstable: gain x stiffness x dt = %.3g x %.3g N/m x %.3g s "
           "= %.3g (> 0.5, the rule is < 1 with the stiffness of all it presses on, estimated "
           "from its contacts); lower the gain", name, m->servo.gain, K, dt, g);
}

/* The mesh wall (index among the mesh walls) whose measuring servo group g is, or -1. */
static int measuring_wall(const adem_walls *wl, int g) {
  if (!wl->mesh_motion[g].servo.on || wl->mesh_motion[g].servo.unmeasured) return -1;
  for (int k = 0; k < wl->nmesh_walls; ++k)
    if (g >= wl->mesh_walls[k].first && g < wl->mesh_walls[k].first + wl->mesh_walls[k].count)
      return k;
  return -1;
}

/* Warns once per servo whose gain K dt exceeds 0.5, K the sum of its contacts' stiffnesses:
 * slot k of the sums a plane's, nplanes + k mesh wall k's, each over the particles by id and
 * their contacts in order, as every sum (order independence); a split world adds the terms of
 * every process so (adem_world_split.sum_terms). */
static void servo_check(adem_world *w) {
  adem_walls *wl = &w->walls;
  int np = wl->nplanes, ns = np + wl->nmesh_walls;
  adem_motion **lead = calloc((size_t)ns + 1, sizeof *lead);
  double *K = calloc((size_t)ns + 1, sizeof *K);
  size_t n = 0, cap = 64;
  adem_id_term *t = malloc(cap * sizeof *t);
  bool ok = lead && K && t;
  for (int k = 0; ok && k < ns; ++k) {
    adem_motion *m = k < np ? &wl->planes[k].motion
                            : (adem_motion *)adem_walls_mesh_wall_servo(wl, k - np);
    lead[k] = m && m->servo.on && !m->servo_warned ? m : NULL;
  }
  for (size_t r = 0; ok && r < w->nb.gathered; ++r) {
    size_t i = w->nb.id_order[r];
    uint32_t seq = 0;
    size_t e0 = w->nb.pw_start[i], e1 = w->nb.pw_start[i + 1];
    size_t j0 = w->pm.start ? w->pm.start[i] : 0, j1 = w->pm.start ? w->pm.start[i + 1] : 0;
    for (size_t e = e0; ok && e < e1 + (j1 - j0); ++e) {
      int slot;
      double v;
      if (e < e1) { /* a plane contact */
        size_t j = w->nb.pw_entries[e];
        slot = w->pw.b[j] < (uint32_t)np ? (int)w->pw.b[j] : -1;
        v = slot >= 0 && lead[slot] ? contact_stiffness(&w->pw, j, &w->p) : 0.0;
      } else { /* a mesh slot: the touching ones come first */
        size_t j = j0 + (e - e1);
        if (!w->pm.l.touching[j]) break;
        int k = measuring_wall(wl, (int)wl->mesh.group[w->pm.owner[j]]);
        slot = k < 0 ? -1 : np + k;
        v = slot >= 0 && lead[slot] ? contact_stiffness(&w->pm.l, j, &w->p) : 0.0;
      }
      if (slot < 0 || !lead[slot]) continue;
      if (n == cap) {
        adem_id_term *q = realloc(t, 2 * cap * sizeof *q);
        if (!q) {
          ok = false;
          break;
        }
        t = q;
        cap *= 2;
      }
      t[n++] = (adem_id_term){w->p.id[i], (uint32_t)i, seq++, (uint32_t)slot, 0, v};
    }
  }
  const adem_world_split *sp = w->split;
  if (sp) { /* every process, even one out of memory: the sums are collective */
    adem_error ignored;
    if (sp->sum_terms(sp->ctx, w, ok ? t : NULL, ok ? n : 0, K, ns, &ignored)) ok = false;
  } else {
    for (size_t k = 0; ok && k < n; ++k) K[t[k].slot] += t[k].v;
  }
  for (int k = 0; ok && k < ns; ++k)
    if (lead[k])
      servo_warn(lead[k], k < np ? wl->planes[k].def.name : wl->mesh_walls[k - np].name, K[k], w->dt);
  free(lead);
  free(K);
  free(t);
}

/* The servos move by their laws from the last force pass's loads, before the walls are placed. */
static adem_status servo_step(adem_world *w, double dt, adem_error *err) {
  const adem_world_split *sp = w->split;
  if (w->step % 64 == 0) servo_check(w); /* a warning: now and then is enough */
  adem_vec3 *f = malloc((size_t)(w->walls.nplanes > 0 ? w->walls.nplanes : 1) * sizeof *f);
  adem_status st = ADEM_OK;
  if (sp) st = sp->plane_forces(sp->ctx, w, f, err); /* the whole system's (collective) */
  else if (f) adem_world_plane_forces(w, f);
  if (!f && !st) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  if (!st) adem_walls_servo_step(&w->walls, f, dt);
  free(f);
  return st;
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
  if (sync_balance_records(w))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the energy balance's pair records");
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

/* The stored energies of the contacts, in an order the storage does not change: particles by id
 * (as at the last gather, which the lists follow), and each one's pairs as its gather list has
 * them, a particle pair under its lower id; mesh slots by key. Summed as streams (no array of
 * every pair's term: the diagnostics would add it to a run's peak memory). */
static void sum_elastic(const adem_world *w, double out[3]) {
  const adem_neighbors *nb = &w->nb;
  const adem_mesh_pairs *pm = &w->pm;
  adem_block_sum b[3] = {ADEM_BLOCK_SUM_START, ADEM_BLOCK_SUM_START, ADEM_BLOCK_SUM_START};
  for (size_t r = 0; r < nb->gathered; ++r) {
    size_t i = nb->id_order[r];
    for (size_t e = nb->pp_start[i]; e < nb->pp_start[i + 1]; ++e)
      if (!(nb->pp_entries[e] & 1u)) adem_block_sum_add(&b[0], w->pp.elastic[nb->pp_entries[e] >> 1]);
    for (size_t e = nb->pw_start[i]; e < nb->pw_start[i + 1]; ++e)
      adem_block_sum_add(&b[1], w->pw.elastic[nb->pw_entries[e]]);
    for (size_t k = pm->start ? pm->start[i] : 0; pm->start && k < pm->start[i + 1]; ++k)
      adem_block_sum_add(&b[2], pm->l.elastic[k]);
  }
  for (int s = 0; s < 3; ++s) out[s] = adem_block_sum_result(&b[s]);
}

/* Every sum over particles or contacts runs in order of id (docs/architecture.md, "Order
 * independence"): the same bits whatever the storage order or the thread count. */
adem_diagnostics adem_world_diagnostics(const adem_world *w) {
  adem_diagnostics d;
  memset(&d, 0, sizeof d);
  d.time = w->time;
  const adem_particles *p = &w->p;
  size_t n = p->n;
  uint32_t *order = adem_world_id_order(w);
  if (!order) return d;
  /* one walk over the particles by id, each sum a stream of its own (adem_block_sum) */
  enum { KINETIC, ROTATIONAL, POTENTIAL, DISSIPATED, WALL_WORK, MOMENTUM, IMPULSE = MOMENTUM + 3,
         SUMS = IMPULSE + 3 };
  adem_block_sum sum[SUMS];
  for (int k = 0; k < SUMS; ++k) sum[k] = (adem_block_sum)ADEM_BLOCK_SUM_START;
  for (size_t r = 0; r < n; ++r) {
    size_t i = order[r];
    adem_block_sum_add(&sum[KINETIC], 0.5 * v3_norm2(p->vel[i]) / p->inv_mass[i]);
    adem_block_sum_add(&sum[ROTATIONAL], 0.5 * v3_norm2(p->omega[i]) / p->inv_inertia[i]);
    /* Potential of the body forces: -(m g + F_group + F_ext) . x (a change of F_ext is
     * external work: adem_world_set_particles) */
    adem_vec3 f = v3_add(v3_add(v3_scale(w->gravity, 1.0 / p->inv_mass[i]),
                                w->groups[p->group[i]].external_force),
                         p->ext_force[i]);
    adem_vec3 xi = adem_periodic_unwrap(&w->periodic, p->pos[i], p->image[i]);
    adem_block_sum_add(&sum[POTENTIAL], -v3_dot(f, xi));
    /* accumulated per particle every step (force_sums.c): the dissipative forces' work and the
     * laws' own losses, and the work of moving walls */
    adem_block_sum_add(&sum[DISSIPATED], p->dissipated[i]);
    adem_block_sum_add(&sum[WALL_WORK], p->wall_work[i]);
    adem_vec3 l = v3_add(v3_scale(v3_cross(xi, p->vel[i]), 1.0 / p->inv_mass[i]),
                         v3_scale(p->omega[i], 1.0 / p->inv_inertia[i]));
    adem_vec3 b = p->brof_impulse[i];
    double c[6] = {l.x, l.y, l.z, b.x, b.y, b.z};
    for (int a = 0; a < 6; ++a) adem_block_sum_add(&sum[MOMENTUM + a], c[a]);
  }
  free(order);
  double total[SUMS];
  for (int k = 0; k < SUMS; ++k) total[k] = adem_block_sum_result(&sum[k]);
  d.kinetic = total[KINETIC];
  d.rotational = total[ROTATIONAL];
  d.potential = total[POTENTIAL];
  d.dissipated = total[DISSIPATED];
  d.wall_work = total[WALL_WORK];
  d.angular_momentum = v3(total[MOMENTUM], total[MOMENTUM + 1], total[MOMENTUM + 2]);
  d.brof_impulse = v3(total[IMPULSE], total[IMPULSE + 1], total[IMPULSE + 2]);
  double elastic[3];
  sum_elastic(w, elastic);
  d.elastic = elastic[0] + elastic[1] + elastic[2];
  for (size_t k = 0; k < w->pp.n; ++k) {
    d.contacts_pp += w->pp.touching[k];
    d.max_overlap_ratio = fmax(d.max_overlap_ratio, w->pp.res[k].overlap_ratio);
  }
  for (size_t k = 0; k < w->pw.n; ++k) {
    d.contacts_pw += w->pw.touching[k];
    d.max_overlap_ratio = fmax(d.max_overlap_ratio, w->pw.res[k].overlap_ratio);
  }
  for (size_t k = 0; k < w->pm.l.n; ++k) { /* mesh contacts count as wall contacts */
    d.contacts_pw += w->pm.l.touching[k];
    d.max_overlap_ratio = fmax(d.max_overlap_ratio, w->pm.l.res[k].overlap_ratio);
  }
  d.balance_error = w->prepared ? total_energy(&d) + d.dissipated - w->energy_initial - d.wall_work : 0.0;
  if (!w->energy_balance) d.dissipated = d.wall_work = d.balance_error = NAN;
  d.initial = w->prepared ? w->energy_initial : total_energy(&d);
  return d;
}

/* ---------------------------------------------------------------- checkpoints */

void adem_world_save(adem_writer *wr, const adem_world *w) {
  adem_put_u8(wr, w->prepared ? 1 : 0);
  adem_put_f64(wr, w->time);
  adem_put_u64(wr, w->step);
  adem_put_f64(wr, w->dt);
  adem_put_u64(wr, w->next_id);
  adem_put_f64(wr, w->energy_initial);
  adem_put_vec(wr, w->gravity);
  adem_put_f64(wr, w->max_overlap_ratio);
  adem_put_u8(wr, w->has_domain ? 1 : 0);
  adem_put_vec(wr, w->domain_lo);
  adem_put_vec(wr, w->domain_hi);
  adem_put_u32(wr, w->periodic.axes);
  for (int d = 0; d < 3; ++d) {
    adem_put_f64(wr, w->periodic.lo[d]);
    adem_put_f64(wr, w->periodic.len[d]);
  }
  adem_put_u32(wr, w->open_faces);
  adem_put_f64(wr, w->nb.skin);
  adem_put_f64(wr, w->nb.skin_fraction);
  adem_put_u8(wr, w->nb.brute_force ? 1 : 0);
  adem_put_u64(wr, w->nb.rebuilds);
  adem_put_f64(wr, w->nb.time_at_build);
  adem_put_u32(wr, (uint32_t)w->mat.n);
  for (int k = 0; k < w->mat.n; ++k) adem_put_str(wr, w->mat.m[k].def.name);
  adem_put_u32(wr, (uint32_t)w->ngroups);
  for (int k = 0; k < w->ngroups; ++k) adem_put_vec(wr, w->groups[k].external_force);
  adem_put_u32(wr, (uint32_t)w->walls.nplanes);
  for (int k = 0; k < w->walls.nplanes; ++k) {
    const adem_plane_def *d = &w->walls.planes[k].def;
    adem_put_str(wr, d->name);
    adem_put_vec(wr, d->point);
    adem_put_vec(wr, d->normal);
    adem_put_vec(wr, d->velocity);
    adem_put_i32(wr, d->material);
  }
  adem_particles_save(wr, &w->p);
  adem_pairs_save(wr, &w->pp);
  adem_pairs_save(wr, &w->pw);
  adem_mesh_pairs_save(wr, &w->pm, w->p.n);
  size_t nf = 3 * w->walls.mesh.ntris;
  adem_put_array(wr, w->walls.face_force, nf, sizeof *w->walls.face_force);
  adem_put_array(wr, w->walls.face_torque, nf, sizeof *w->walls.face_torque);
  adem_walls_save_state(wr, &w->walls);
}

static adem_status damaged(adem_error *err, const char *why);

/* Reads past what adem_world_save writes before the particles: keep the two in step (the state
 * import test, tests/unit/test_state.c, fails when they are not). */
adem_status adem_world_read_particles(adem_reader *rd, adem_particles *p,
                                      char (**names)[ADEM_NAME_MAX], int *nmat, adem_error *err) {
  const char *cut = "its contents are cut short or damaged";
  *names = NULL;
  *nmat = 0;
  if (!adem_get_u8(rd) || rd->failed)
    return damaged(err, "it was written before the first step (its particles are its case's)");
  (void)adem_get_f64(rd); /* time */
  (void)adem_get_u64(rd); /* step */
  for (int k = 0; k < 3; ++k) (void)adem_get_f64(rd); /* dt, next id, initial energy */
  (void)adem_get_vec(rd);                               /* gravity */
  (void)adem_get_f64(rd);                               /* overlap limit */
  (void)adem_get_u8(rd);                                /* domain */
  (void)adem_get_vec(rd);
  (void)adem_get_vec(rd);
  (void)adem_get_u32(rd); /* periodic axes, then lo and length per axis */
  for (int d = 0; d < 6; ++d) (void)adem_get_f64(rd);
  (void)adem_get_u32(rd); /* open faces */
  (void)adem_get_f64(rd); /* skin */
  (void)adem_get_f64(rd);
  (void)adem_get_u8(rd);
  (void)adem_get_u64(rd);
  (void)adem_get_f64(rd);
  uint32_t nm = adem_get_u32(rd);
  if (rd->failed || nm > 65535) return damaged(err, cut);
  *names = calloc((size_t)nm + 1, sizeof **names);
  if (!*names) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  *nmat = (int)nm;
  for (uint32_t k = 0; k < nm; ++k) adem_get_str_into(rd, (*names)[k], sizeof **names);
  uint32_t ng = adem_get_u32(rd);
  for (uint32_t k = 0; k < ng && !rd->failed; ++k) (void)adem_get_vec(rd);
  uint32_t np = adem_get_u32(rd);
  for (uint32_t k = 0; k < np && !rd->failed; ++k) {
    char name[ADEM_NAME_MAX];
    adem_get_str_into(rd, name, sizeof name);
    for (int j = 0; j < 3; ++j) (void)adem_get_vec(rd);
    (void)adem_get_i32(rd);
  }
  adem_status st = rd->failed ? ADEM_OK : adem_particles_load(rd, p, err);
  if (!st && rd->failed) st = damaged(err, cut);
  for (size_t i = 0; !st && i < p->n; ++i)
    if (p->material[i] >= nm || !(p->radius[i] > 0.0) || !isfinite(p->radius[i]) ||
        !v3_isfinite(p->pos[i]) || !v3_isfinite(p->vel[i]) || !v3_isfinite(p->omega[i]))
      st = damaged(err, "its particles' materials, radii or positions are out of range");
  if (st) {
    free(*names);
    *names = NULL;
    *nmat = 0;
  }
  return st;
}

static adem_status damaged(adem_error *err, const char *why) {
  return adem_error_set(err, ADEM_ERR_INPUT, "%s", why);
}

adem_status adem_world_load_prepared(adem_reader *rd, bool *prepared,
                                     adem_error *err) {
  *prepared = adem_get_u8(rd) != 0;
  if (rd->failed) return damaged(err, "its contents are cut short or damaged");
  return ADEM_OK;
}

adem_status adem_world_load(adem_reader *rd, adem_world *w, adem_error *err) {
  const char *cut = "its contents are cut short or damaged";
  w->time = adem_get_f64(rd);
  w->step = adem_get_u64(rd);
  w->dt = adem_get_f64(rd);
  w->next_id = adem_get_u64(rd);
  w->energy_initial = adem_get_f64(rd);
  w->gravity = adem_get_vec(rd);
  w->max_overlap_ratio = adem_get_f64(rd);
  w->has_domain = adem_get_u8(rd) != 0;
  w->domain_lo = adem_get_vec(rd);
  w->domain_hi = adem_get_vec(rd);
  w->periodic.axes = adem_get_u32(rd);
  for (int d = 0; d < 3; ++d) {
    w->periodic.lo[d] = adem_get_f64(rd);
    w->periodic.len[d] = adem_get_f64(rd);
  }
  w->open_faces = adem_get_u32(rd);
  w->nb.skin = adem_get_f64(rd);
  w->nb.skin_fraction = adem_get_f64(rd);
  w->nb.brute_force = adem_get_u8(rd) != 0;
  w->nb.rebuilds = adem_get_u64(rd);
  w->nb.time_at_build = adem_get_f64(rd);
  uint32_t nmat = adem_get_u32(rd);
  if (rd->failed) return damaged(err, cut);
  if (nmat != (uint32_t)w->mat.n) return damaged(err, "its materials do not match its own case text");
  for (int k = 0; k < w->mat.n; ++k) {
    char name[ADEM_NAME_MAX];
    adem_get_str_into(rd, name, sizeof name);
    if (!rd->failed && strcmp(name, w->mat.m[k].def.name))
      return damaged(err, "its materials do not match its own case text");
  }
  uint32_t ngroups = adem_get_u32(rd);
  if (rd->failed) return damaged(err, cut);
  if (ngroups != (uint32_t)w->ngroups)
    return damaged(err, "its materials or groups do not match its own case text");
  for (int k = 0; k < w->ngroups; ++k) w->groups[k].external_force = adem_get_vec(rd);
  uint32_t nplanes = adem_get_u32(rd);
  if (rd->failed) return damaged(err, cut);
  if (nplanes != (uint32_t)w->walls.nplanes) return damaged(err, "its walls do not match its own case text");
  for (int k = 0; k < w->walls.nplanes; ++k) {
    adem_plane_def *d = &w->walls.planes[k].def;
    adem_get_str_into(rd, d->name, sizeof d->name);
    d->point = adem_get_vec(rd);
    d->normal = adem_get_vec(rd);
    d->velocity = adem_get_vec(rd);
    d->material = adem_get_i32(rd);
  }
  adem_status st = adem_particles_load(rd, &w->p, err);
  if (!st) w->frozen_any = adem_world_has_frozen(w);
  if (!st) st = adem_pairs_load(rd, &w->pp, err);
  if (!st) st = adem_pairs_load(rd, &w->pw, err);
  if (!st && !rd->failed) {
    adem_pairs_clear_apart(&w->pp);
    adem_pairs_clear_apart(&w->pw);
  }
  if (!st) st = adem_mesh_pairs_load(rd, &w->pm, w->p.n, err);
  if (st) return st;
  size_t nf = 3 * w->walls.mesh.ntris;
  adem_get_array(rd, w->walls.face_force, nf, sizeof *w->walls.face_force);
  adem_get_array(rd, w->walls.face_torque, nf, sizeof *w->walls.face_torque);
  adem_walls_load_state(rd, &w->walls);
  if (rd->failed) return damaged(err, cut);
  /* Indices must be in range before the gather lists and the stepper use them. */
  const char *bad = "its particle, pair or wall indices are out of range";
  const adem_particles *p = &w->p;
  for (size_t k = 0; k < w->pp.n; ++k)
    if (w->pp.a[k] >= p->n || w->pp.b[k] >= p->n) return damaged(err, bad);
  for (size_t k = 0; k < w->pw.n; ++k)
    if (w->pw.a[k] >= p->n || w->pw.b[k] >= (uint32_t)w->walls.nplanes) return damaged(err, bad);
  if (!adem_mesh_pairs_consistent(&w->pm, p->n, w->walls.mesh.ntris)) return damaged(err, bad);
  for (size_t i = 0; i < p->n; ++i)
    if (p->material[i] >= w->mat.n || (w->ngroups > 0 && p->group[i] >= w->ngroups))
      return damaged(err, bad);
  for (int k = 0; k < w->walls.nplanes; ++k)
    if (w->walls.planes[k].def.material < 0 || w->walls.planes[k].def.material >= w->mat.n)
      return damaged(err, "its particle, pair or wall indices are out of range");
  /* What sizes the cell grid and the step must be finite and positive (a zero cell size would
   * never fit the grid), as the case loader requires of them. */
  const char *nonfinite = "its time step, skin, radii or positions are not finite and positive";
  if (!(w->dt > 0.0) || !isfinite(w->dt) || !(w->nb.skin_fraction > 0.0) ||
      !isfinite(w->nb.skin_fraction) || !(w->nb.skin >= 0.0) || !isfinite(w->nb.skin))
    return damaged(err, nonfinite);
  for (size_t i = 0; i < p->n; ++i)
    if (!(p->radius[i] > 0.0) || !isfinite(p->radius[i]) || !v3_isfinite(p->pos[i]))
      return damaged(err, nonfinite);
  if (w->periodic.axes > 7u) return damaged(err, "its periodic axes are not valid");
  for (int d = 0; d < 3; ++d)
    if ((w->periodic.axes >> d) & 1u && !(w->periodic.len[d] > 0.0 && isfinite(w->periodic.len[d])))
      return damaged(err, nonfinite);
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
      case ADEM_FIELD_EXTERNAL_FORCE: v = &p->ext_force[i]; break;
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
  c->force = l->res[k].force_a;
  c->overlap_ratio = l->res[k].overlap_ratio;
  c->elastic = l->elastic[k];
  c->tangential_history = l->hist[k].tangential;
  c->rolling_history = l->hist[k].rolling;
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
    for (size_t k = 0; k < lists[s]->n; ++k) memset(&lists[s]->hist[k], 0, sizeof lists[s]->hist[k]);
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

size_t adem_world_bytes_per_particle(void) {
  /* the particle table, the per-particle entries of the neighbour and mesh-slot ranges and the
   * order by id */
  return adem_soa_item_bytes(adem_particles_layout()) + 2 * sizeof(size_t) + sizeof(size_t) +
         sizeof(uint32_t);
}

size_t adem_world_bytes_per_pair(const adem_world *w) {
  /* the pair table and the gather entries (two for a particle pair) */
  return adem_pairs_item_bytes(w->energy_balance) + 2 * sizeof(uint32_t);
}

/* Capacity appending grows a table of n to: doubling from 64 (adem_particles_append). */
static double grown_capacity(double n) {
  double cap = 64.0;
  while (cap < n) cap *= 2.0;
  return cap;
}

adem_memory_estimate adem_world_memory_estimate(const adem_world *w, double n) {
  adem_memory_estimate e;
  memset(&e, 0, sizeof e);
  if (!(n >= 0.0)) n = 0.0;
  e.particles = n;
  double f = w->nb.skin_fraction;
  double pp = ADEM_PAIRS_PER_PARTICLE * (1.0 + f) * (1.0 + f) * (1.0 + f) * n;
  double pw = w->walls.nplanes > 0 ? n : 0.0;
  double pm = w->walls.mesh.ntris > 0 ? ADEM_MESH_SLOTS_PER_PARTICLE * n : 0.0;
  e.pairs = pp + pw + pm;
  e.particle_bytes = grown_capacity(n) * (double)adem_soa_item_bytes(adem_particles_layout()) +
                     (n + 1.0) * (double)sizeof(size_t) + /* mesh slot ranges */
                     1.125 * n * 2.0 * (double)sizeof(adem_vec3); /* the predicted velocities */
  /* the lists keep a quarter more than they hold (adem_pairs_reserve) */
  e.pair_bytes = 1.25 * (e.pairs * (double)adem_pairs_item_bytes(w->energy_balance) +
                         pm * (double)adem_mesh_pairs_slot_bytes());
  adem_neighbors_estimate_bytes(n, e.pairs, w->walls.mesh.ntris > 0, &e.grid_bytes, &e.build_bytes);
  e.total = e.particle_bytes + e.pair_bytes + e.grid_bytes + e.build_bytes;
  return e;
}

/* ---------------------------------------------------------------- set-up in checkpoints */

void adem_world_save_setup(adem_writer *wr, const adem_world *w) {
  adem_put_vec(wr, w->gravity);
  adem_put_f64(wr, w->dt);
  adem_put_f64(wr, w->nb.skin_fraction);
  adem_put_u8(wr, w->nb.brute_force ? 1 : 0);
  adem_put_f64(wr, w->max_overlap_ratio);
  adem_put_u64(wr, w->parallel_min);
  adem_put_u8(wr, w->second_order ? 1 : 0);
  adem_put_u8(wr, w->energy_balance ? 1 : 0);
  adem_put_u32(wr, (uint32_t)w->mat.n);
  for (int k = 0; k < w->mat.n; ++k) adem_put(wr, &w->mat.m[k].def, sizeof w->mat.m[k].def);
  adem_put_u32(wr, (uint32_t)w->mat.ndefs);
  adem_put(wr, w->mat.defs, (size_t)w->mat.ndefs * sizeof *w->mat.defs);
  adem_put_u32(wr, (uint32_t)w->ngroups);
  for (int k = 0; k < w->ngroups; ++k) {
    adem_put_str(wr, w->groups[k].name);
    adem_put_vec(wr, w->groups[k].external_force);
  }
  adem_walls_save_setup(wr, &w->walls);
}

adem_status adem_world_load_setup(adem_reader *rd, adem_world *w, adem_error *err) {
  const char *cut = "its contents are cut short or damaged";
  w->gravity = adem_get_vec(rd);
  w->dt = adem_get_f64(rd);
  w->nb.skin_fraction = adem_get_f64(rd);
  w->nb.brute_force = adem_get_u8(rd) != 0;
  w->max_overlap_ratio = adem_get_f64(rd);
  w->parallel_min = (size_t)adem_get_u64(rd);
  w->second_order = adem_get_u8(rd) != 0;
  w->energy_balance = adem_get_u8(rd) != 0;
  uint32_t nm = adem_get_u32(rd);
  adem_status st = ADEM_OK;
  for (uint32_t k = 0; k < nm && !st && !rd->failed; ++k) {
    adem_material_def d;
    adem_get(rd, &d, sizeof d);
    d.name[ADEM_NAME_MAX - 1] = '\0';
    if (!rd->failed) st = adem_world_add_material(w, &d, NULL, err);
  }
  uint32_t nd = adem_get_u32(rd);
  for (uint32_t k = 0; k < nd && !st && !rd->failed; ++k) {
    adem_interaction_def d;
    adem_get(rd, &d, sizeof d);
    if (!rd->failed) st = adem_world_set_interaction(w, &d, err);
  }
  uint32_t ng = adem_get_u32(rd);
  for (uint32_t k = 0; k < ng && !st && !rd->failed; ++k) {
    char name[ADEM_NAME_MAX];
    adem_get_str_into(rd, name, sizeof name);
    adem_vec3 f = adem_get_vec(rd);
    if (!rd->failed) st = adem_world_add_group(w, name, f, NULL, err);
  }
  if (!st && !rd->failed) st = adem_walls_load_setup(rd, &w->walls, w->mat.n, err);
  if (st) return st == ADEM_ERR_NOMEM ? st : damaged(err, err ? err->message : cut);
  if (rd->failed) return damaged(err, cut);
  w->prepared = false;
  return ADEM_OK;
}
