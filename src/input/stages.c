/* Staged runs (see stages.h): stage configurations loaded through the case loader, and the
 * changes carried into the running world where a stage begins. */
#include "stages.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "insert.h"
#include "log.h"
#include "schedule.h"
#include "world.h"

/* ---------------------------------------------------------------- building */

adem_status adem_stages_add(adem_stages **ps, const char *name, double duration, const char *where,
                            adem_error *err) {
  if (!*ps) {
    *ps = calloc(1, sizeof **ps);
    if (!*ps) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  adem_stages *s = *ps;
  adem_stage *st = realloc(s->s, (size_t)(s->n + 1) * sizeof *st);
  if (!st) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  s->s = st;
  adem_stage *g = &st[s->n++];
  memset(g, 0, sizeof *g);
  snprintf(g->name, sizeof g->name, "%s", name);
  snprintf(g->where, sizeof g->where, "%s", where);
  g->duration = duration;
  return ADEM_OK;
}

adem_status adem_stages_add_set(adem_stages *s, const char *set, adem_error *err) {
  adem_stage *g = &s->s[s->n - 1];
  char **sets = realloc(g->sets, (size_t)(g->nsets + 1) * sizeof *sets);
  if (!sets) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  g->sets = sets;
  size_t n = strlen(set) + 1;
  g->sets[g->nsets] = malloc(n);
  if (!g->sets[g->nsets]) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  memcpy(g->sets[g->nsets++], set, n);
  return ADEM_OK;
}

/* First segment of a path (and the second for output), against what a stage may change. */
const char *adem_stages_check_path(const char *path) {
  static const char *const allowed[] = {"materials", "interactions", "groups", "walls",
                                        "gravity", "limits", "neighbor"};
  static const char *const outputs[] = {"frame_interval", "csv_interval", "checkpoint_interval"};
  static const char *const why =
      "a stage may set only materials, interactions, groups, walls, gravity, limits, neighbor "
      "and output.frame_interval, output.csv_interval, output.checkpoint_interval (particles, "
      "pours, time, seed and the domain are fixed for the whole run)";
  size_t n = strcspn(path, ".");
  for (size_t k = 0; k < sizeof allowed / sizeof *allowed; ++k)
    if (strlen(allowed[k]) == n && !strncmp(path, allowed[k], n)) return NULL;
  if (n == 6 && !strncmp(path, "output", 6) && path[6] == '.')
    for (size_t k = 0; k < sizeof outputs / sizeof *outputs; ++k)
      if (!strcmp(path + 7, outputs[k])) return NULL;
  return why;
}

static adem_status motion_copy(adem_motion *dst, const adem_motion *src, adem_error *err) {
  adem_motion_def d = {src->n, src->time, src->velocity, src->axis, src->omega, src->center};
  adem_status st = adem_motion_init(dst, &d, err);
  if (!st) dst->t0 = src->t0;
  return st;
}

/* The same motion table, axis and centre (t0 aside). */
static bool motion_same(const adem_motion *a, const adem_motion *b) {
  if (a->n != b->n || a->omega != b->omega) return false;
  if (memcmp(&a->axis, &b->axis, sizeof a->axis) || memcmp(&a->center, &b->center, sizeof a->center))
    return false;
  return a->n == 0 || (!memcmp(a->time, b->time, a->n * sizeof *a->time) &&
                       !memcmp(a->velocity, b->velocity, a->n * sizeof *a->velocity));
}

static void config_free(adem_stage_config *g) {
  for (int k = 0; k < g->nplanes; ++k) adem_motion_free(&g->planes[k].motion);
  for (int k = 0; k < g->nmeshes; ++k) adem_motion_free(&g->meshes[k].motion);
  free(g->materials);
  free(g->interactions);
  free(g->group_force);
  free(g->planes);
  free(g->meshes);
  memset(g, 0, sizeof *g);
}

static adem_status config_extract(adem_stage_config *g, const adem_case *c, adem_error *err) {
  const adem_world *w = c->world;
  memset(g, 0, sizeof *g);
  g->nmaterials = w->mat.n;
  g->ninteractions = w->mat.ndefs;
  g->ngroups = w->ngroups;
  g->nplanes = w->walls.nplanes;
  g->nmeshes = w->walls.mesh.ngroups;
  g->materials = calloc((size_t)g->nmaterials + 1, sizeof *g->materials);
  g->interactions = calloc((size_t)g->ninteractions + 1, sizeof *g->interactions);
  g->group_force = calloc((size_t)g->ngroups + 1, sizeof *g->group_force);
  g->planes = calloc((size_t)g->nplanes + 1, sizeof *g->planes);
  g->meshes = calloc((size_t)g->nmeshes + 1, sizeof *g->meshes);
  if (!g->materials || !g->interactions || !g->group_force || !g->planes || !g->meshes) {
    config_free(g);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  for (int k = 0; k < g->nmaterials; ++k) g->materials[k] = w->mat.m[k].def;
  for (int k = 0; k < g->ninteractions; ++k) g->interactions[k] = w->mat.defs[k];
  for (int k = 0; k < g->ngroups; ++k) g->group_force[k] = w->groups[k].external_force;
  adem_status st = ADEM_OK;
  for (int k = 0; k < g->nplanes && !st; ++k) {
    const adem_plane *pl = &w->walls.planes[k];
    g->planes[k].def = pl->def;
    g->planes[k].point0 = pl->point0;
    g->planes[k].normal0 = pl->normal0;
    g->planes[k].inactive = pl->inactive;
    st = motion_copy(&g->planes[k].motion, &pl->motion, err);
  }
  for (int k = 0; k < g->nmeshes && !st; ++k) {
    g->meshes[k].material = w->walls.mesh.groups[k].material;
    g->meshes[k].inactive = !adem_world_mesh_active(w, (uint32_t)k);
    st = motion_copy(&g->meshes[k].motion, &w->walls.mesh_motion[k], err);
  }
  g->gravity = w->gravity;
  g->frame_interval = c->output.frame_interval;
  g->csv_interval = c->output.csv_interval;
  g->checkpoint_interval = c->output.checkpoint_interval;
  g->max_overlap_ratio = w->max_overlap_ratio;
  g->skin_fraction = w->nb.skin_fraction;
  g->dt_proposed = c->estimate.dt;
  if (st) config_free(g);
  return st;
}

void adem_stages_free(adem_stages *s) {
  if (!s) return;
  for (int k = 0; k < s->n; ++k) {
    for (int j = 0; j < s->s[k].nsets; ++j) free(s->s[k].sets[j]);
    free(s->s[k].sets);
    config_free(&s->s[k].config);
  }
  config_free(&s->base);
  free(s->s);
  free(s);
}

/* The stage's configuration describes the same world: same materials, groups and walls. */
static adem_status check_same_world(const adem_case *c, const adem_case *sc, const adem_stage *g,
                                    adem_error *err) {
  const adem_world *w = c->world, *v = sc->world;
  const char *what = NULL;
  if (v->mat.n != w->mat.n) what = "materials";
  for (int k = 0; !what && k < w->mat.n; ++k)
    if (strcmp(v->mat.m[k].def.name, w->mat.m[k].def.name)) what = "materials";
  if (!what && v->ngroups != w->ngroups) what = "groups";
  for (int k = 0; !what && k < w->ngroups; ++k)
    if (strcmp(v->groups[k].name, w->groups[k].name)) what = "groups";
  if (!what && v->walls.nplanes != w->walls.nplanes) what = "walls";
  for (int k = 0; !what && k < w->walls.nplanes; ++k)
    if (strcmp(v->walls.planes[k].def.name, w->walls.planes[k].def.name)) what = "walls";
  if (!what && (v->walls.mesh.ngroups != w->walls.mesh.ngroups || v->walls.mesh.nverts != w->walls.mesh.nverts ||
                v->walls.mesh.ntris != w->walls.mesh.ntris))
    what = "walls";
  if (!what && v->p.n != w->p.n) what = "particles";
  if (what)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: stage `%s` changes which %s there are; a stage may change their "
                          "properties, not add or remove them (switch a wall off with `active: "
                          "false`)",
                          g->where, g->name, what);
  if (w->walls.mesh.nverts > 0 &&
      memcmp(v->walls.mesh_vert0, w->walls.mesh_vert0, w->walls.mesh.nverts * sizeof *w->walls.mesh_vert0) != 0)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: stage `%s` changes the shape or placement of a mesh wall; a stage "
                          "may change a mesh wall's motion, material and `active` only",
                          g->where, g->name);
  for (int k = 0; k < w->walls.mesh.ngroups; ++k)
    if (v->walls.mesh_motion[k].moving && !w->walls.mesh.groups[k].own_vertices)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "%s: stage `%s` sets mesh wall `%s` moving, but it was loaded sharing "
                            "its vertices with other walls; give it a motion (it may be at rest) "
                            "in the case itself",
                            g->where, g->name, w->walls.mesh.groups[k].name);
  return ADEM_OK;
}

/* Re-labels an error of loading stage k's configuration: where the stage (or the set entry
 * that caused it) is written. */
static adem_status stage_error(const adem_stage *g, int k, adem_status st, adem_error *err) {
  char inner[ADEM_MSG_MAX];
  snprintf(inner, sizeof inner, "%s", err ? err->message : "");
  const char *msg = inner;
  if (!strncmp(msg, "--set ", 6)) msg += 6;
  return adem_error_set(err, st, "%s: stages[%d] (`%s`).set: %s", g->where, k, g->name, msg);
}

static adem_status apply(adem_case *c, int k, bool live, adem_error *err);

adem_status adem_stages_prepare(adem_case *c, adem_error *err) {
  adem_stages *s = c->stages;
  if (!s || s->n == 0) return ADEM_OK;
  adem_status st = config_extract(&s->base, c, err);
  if (st) return st;
  int total = c->nsets;
  for (int k = 0; k < s->n; ++k) total += s->s[k].nsets;
  const char **sets = malloc((size_t)(total + 1) * sizeof *sets);
  if (!sets) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  int nsets = 0;
  for (int j = 0; j < c->nsets; ++j) sets[nsets++] = c->sets[j];
  for (int k = 0; k < s->n && !st; ++k) {
    adem_stage *g = &s->s[k];
    for (int j = 0; j < g->nsets; ++j) sets[nsets++] = g->sets[j];
    adem_case *sc = NULL;
    adem_log_mute(1);
    st = adem_case_load_string_flags(c->source, c->path, c->base_dir, sets, nsets,
                                     ADEM_CASE_LOAD_STAGE, &sc, err);
    adem_log_mute(0);
    if (st) {
      st = stage_error(g, k, st, err);
      break;
    }
    st = check_same_world(c, sc, g, err);
    if (!st) st = config_extract(&g->config, sc, err);
    adem_case_free(sc);
    if (st) break;
    double ratio = c->dt / g->config.dt_proposed;
    if (c->dt_auto && ratio > 1.0 && g->config.dt_proposed > 0.0) { /* the smallest of all */
      c->dt = g->config.dt_proposed;
      adem_world_set_dt(c->world, c->dt);
    } else if (ratio > 1.0 + 1e-12 && isfinite(ratio))
      adem_log(ADEM_LOG_WARN,
               "%s: stage `%s`: the time step %g s is %.2fx the step its materials propose (%g s)",
               g->where, g->name, c->dt, ratio, g->config.dt_proposed);
  }
  free(sets);
  if (st) return st;
  /* Durations: every stage but the last needs one; the last may run until time.end. */
  double t = 0.0;
  for (int k = 0; k < s->n; ++k) {
    adem_stage *g = &s->s[k];
    if (g->duration < 0.0 && k + 1 < s->n)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "%s: stages[%d] (`%s`): duration: required value is missing (every "
                            "stage but the last needs one)",
                            g->where, k, g->name);
    if (t >= c->end_time * (1.0 - 1e-12) && k > 0)
      adem_log(ADEM_LOG_WARN, "%s: stage `%s` begins at t = %g s, at or after time.end = %g s: it "
               "will not run", g->where, g->name, t, c->end_time);
    if (g->duration >= 0.0) t += g->duration;
  }
  const adem_stage *last = &s->s[s->n - 1];
  if (last->duration >= 0.0 && t < c->end_time * (1.0 - 1e-12))
    adem_log(ADEM_LOG_WARN, "%s: the stages end at t = %g s, before time.end = %g s: the last "
             "stage (`%s`) goes on until time.end", last->where, t, c->end_time, last->name);
  s->current = 0;
  return apply(c, 0, false, err);
}

/* ---------------------------------------------------------------- running */

static double stage_start_time(const adem_stages *s, int k) {
  double t = 0.0;
  for (int j = 0; j < k; ++j) t += s->s[j].duration;
  return t;
}

uint64_t adem_stages_start_step(const adem_case *c, int k) {
  if (!c->stages || k <= 0) return 0;
  if (k >= c->stages->n) return UINT64_MAX;
  return (uint64_t)llround(stage_start_time(c->stages, k) / c->world->dt);
}

int adem_stages_current(const adem_case *c) { return c->stages ? c->stages->current : 0; }

uint64_t adem_stages_next_step(const adem_case *c, uint64_t step) {
  uint64_t next = adem_pours_next_step(c->pours, c->world->dt, step);
  const adem_stages *s = c->stages;
  for (int k = s ? s->current + 1 : 0; s && k < s->n; ++k) {
    uint64_t b = adem_stages_start_step(c, k);
    if (b > step) {
      if (b < next) next = b;
      break;
    }
  }
  return next;
}

/* Total energy, as the diagnostics count it. */
static double total_energy(const adem_world *w) {
  adem_diagnostics d = adem_world_diagnostics(w);
  return d.kinetic + d.rotational + d.potential + d.elastic;
}

/* A wall that starts a new motion at t_s starts it from where it is: its reference placement
 * becomes the current one and the motion's clock starts at t_s. */
static adem_status apply_walls(adem_world *w, const adem_stage_config *prev,
                               const adem_stage_config *next, double t_s, adem_error *err) {
  /* A plane at rest is at its reference place (a checkpoint has put where it is now). */
  for (int k = 0; k < w->walls.nplanes; ++k)
    if (!w->walls.planes[k].motion.moving) {
      w->walls.planes[k].def.point = w->walls.planes[k].point0;
      w->walls.planes[k].def.normal = w->walls.planes[k].normal0;
    }
  adem_world_place_walls(w, t_s);
  adem_status st = ADEM_OK;
  for (int k = 0; k < w->walls.nplanes && !st; ++k) {
    adem_plane *pl = &w->walls.planes[k];
    const adem_stage_wall *a = &prev->planes[k], *b = &next->planes[k];
    bool moved = memcmp(&a->point0, &b->point0, sizeof a->point0) ||
                 memcmp(&a->normal0, &b->normal0, sizeof a->normal0);
    bool new_motion = !motion_same(&a->motion, &b->motion);
    if (moved) { /* the stage puts the plane somewhere else */
      pl->point0 = b->point0;
      pl->normal0 = b->normal0;
      pl->def.point = b->point0;
      pl->def.normal = b->normal0;
    } else if (new_motion) {
      pl->point0 = pl->def.point;
      pl->normal0 = pl->def.normal;
    }
    if (moved || new_motion) {
      adem_motion m;
      if ((st = motion_copy(&m, &b->motion, err))) break;
      m.t0 = t_s;
      adem_motion_free(&pl->motion);
      pl->motion = m;
      pl->def.velocity = adem_motion_velocity(&pl->motion, t_s);
    }
    pl->def.material = b->def.material;
    pl->inactive = b->inactive;
  }
  adem_mesh *m = &w->walls.mesh;
  for (int g = 0; g < m->ngroups && !st; ++g) {
    const adem_stage_mesh *a = &prev->meshes[g], *b = &next->meshes[g];
    m->groups[g].material = b->material;
    if ((st = adem_world_set_mesh_active(w, g, !b->inactive, err))) break;
    if (motion_same(&a->motion, &b->motion)) continue;
    const adem_mesh_group *grp = &m->groups[g];
    for (uint32_t v = grp->vert_first; v < grp->vert_first + grp->vert_count; ++v)
      w->walls.mesh_vert0[v] = m->vert[v];
    for (uint32_t t = grp->first; t < grp->first + grp->count; ++t) w->walls.mesh_normal0[t] = m->normal[t];
    for (int k = 0; k < w->walls.nmesh_walls; ++k) /* a wall's torque point travels with its first group */
      if (w->walls.mesh_walls[k].first == g)
        w->walls.mesh_walls[k].ref0 = adem_motion_place(&w->walls.mesh_motion[g], t_s, w->walls.mesh_walls[k].ref0);
    w->walls.mesh_ref0[g] = w->walls.mesh_ref[g];
    adem_motion mo;
    if ((st = motion_copy(&mo, &b->motion, err))) break;
    mo.t0 = t_s;
    adem_motion_free(&w->walls.mesh_motion[g]);
    w->walls.mesh_motion[g] = mo;
    double reach = 0.0;
    for (uint32_t v = grp->vert_first; v < grp->vert_first + grp->vert_count; ++v)
      reach = fmax(reach, v3_norm(v3_sub(w->walls.mesh_vert0[v], mo.center)));
    w->walls.mesh_reach[g] = reach;
  }
  if (!st) adem_world_place_walls(w, t_s);
  return st;
}

/* Puts stage k in force at its start. live: during a run (energy balance kept, neighbour lists
 * rebuilt); otherwise the configuration only (at load, or replaying for a checkpoint). */
static adem_status apply(adem_case *c, int k, bool live, adem_error *err) {
  adem_stages *s = c->stages;
  adem_world *w = c->world;
  const adem_stage_config *prev = k == 0 ? &s->base : &s->s[k - 1].config;
  const adem_stage_config *next = &s->s[k].config;
  double t_s = (double)adem_stages_start_step(c, k) * w->dt;
  double before = live ? total_energy(w) : 0.0;
  adem_status st = apply_walls(w, prev, next, t_s, err);
  if (st) return st;
  for (int j = 0; j < w->mat.n; ++j) w->mat.m[j].def = next->materials[j];
  adem_interaction_def *defs = malloc(((size_t)next->ninteractions + 1) * sizeof *defs);
  if (!defs) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  memcpy(defs, next->interactions, (size_t)next->ninteractions * sizeof *defs);
  free(w->mat.defs);
  w->mat.defs = defs;
  w->mat.ndefs = next->ninteractions;
  if ((st = adem_materials_derive(&w->mat, err))) return st;
  for (int j = 0; j < w->ngroups; ++j) w->groups[j].external_force = next->group_force[j];
  w->gravity = next->gravity;
  w->max_overlap_ratio = next->max_overlap_ratio;
  w->nb.skin_fraction = next->skin_fraction;
  c->output.frame_interval = next->frame_interval;
  c->output.csv_interval = next->csv_interval;
  c->output.checkpoint_interval = next->checkpoint_interval;
  s->current = k;
  if (!live) return ADEM_OK;
  /* Work done by the change (gravity, group forces) is not dissipation: shift the balance. */
  w->energy_initial += total_energy(w) - before;
  adem_log(ADEM_LOG_INFO, "t = %.9g s (step %llu): stage `%s` begins", w->time,
           (unsigned long long)w->step, s->s[k].name);
  /* Walls on or off, moved or with a new motion: the lists must see them from now on. */
  if ((st = adem_world_build_neighbors(w, err))) return st;
  return ADEM_OK;
}

adem_status adem_stages_events(adem_case *c, adem_error *err) {
  adem_stages *s = c->stages;
  adem_world *w = c->world;
  while (s && s->current + 1 < s->n && adem_stages_start_step(c, s->current + 1) <= w->step) {
    adem_status st = apply(c, s->current + 1, w->prepared, err);
    if (st) return st;
  }
  return adem_pours_run(c->pours, w, err);
}

adem_status adem_stages_resume(adem_case *c, int current, adem_error *err) {
  adem_stages *s = c->stages;
  int n = s ? s->n : 0;
  if (current < 0 || (current >= n && !(n == 0 && current == 0)))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "it is in stage %d, but its own case text has %d stage%s", current, n,
                          n == 1 ? "" : "s");
  for (int k = 1; k <= current; ++k) {
    adem_status st = apply(c, k, false, err);
    if (st) return st;
  }
  return ADEM_OK;
}

static double interval_of(const adem_stage_config *g, const adem_case *c, int which) {
  if (!g) return which == 0 ? c->output.frame_interval
                : which == 1 ? c->output.csv_interval : c->output.checkpoint_interval;
  return which == 0 ? g->frame_interval : which == 1 ? g->csv_interval : g->checkpoint_interval;
}

bool adem_stages_output_on(const adem_case *c, int which) {
  double dt = c->world->dt;
  if (adem_schedule_period(interval_of(NULL, c, which), dt) > 0) return true;
  for (int k = 0; c->stages && k < c->stages->n; ++k)
    if (adem_schedule_period(interval_of(&c->stages->s[k].config, c, which), dt) > 0) return true;
  return false;
}

uint64_t adem_stages_frames_done(const adem_case *c, uint64_t step) {
  double dt = c->world->dt;
  const adem_stages *s = c->stages;
  if (!s || s->n == 0) {
    uint64_t k = adem_schedule_period(c->output.frame_interval, dt);
    return k ? step / k + 1 : 0;
  }
  if (!adem_stages_output_on(c, 0)) return 0;
  /* Outputs at steps in (start_j, start_j+1] are written with stage j's interval (a stage is put
   * in force after the outputs of its first step). */
  uint64_t count = 1;
  for (int j = 0; j < s->n; ++j) {
    uint64_t a = adem_stages_start_step(c, j), b = adem_stages_start_step(c, j + 1);
    if (b > step) b = step;
    if (b <= a) continue;
    uint64_t k = adem_schedule_period(s->s[j].config.frame_interval, dt);
    if (k) count += b / k - a / k;
  }
  return count;
}
