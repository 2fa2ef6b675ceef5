/* Staged runs (see stages.h): stage configurations loaded through the case loader, and the
 * changes carried into the running world where a stage begins. */
#include "stages.h"

#include "outlets.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "insert.h"
#include "log.h"
#include "schedule.h"
#include "world_internal.h"

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
  uint64_t *start = realloc(s->start, (size_t)(s->n + 1) * sizeof *start);
  if (!start) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  s->start = start;
  start[s->n] = 0;
  adem_stage *g = &st[s->n++];
  memset(g, 0, sizeof *g);
  snprintf(g->name, sizeof g->name, "%s", name);
  snprintf(g->where, sizeof g->where, "%s", where);
  g->duration = duration;
  return ADEM_OK;
}

adem_status adem_stages_set_until(adem_stages *s, const adem_until_def *def, adem_error *err) {
  adem_stage *g = &s->s[s->n - 1];
  if (!g->until && !(g->until = malloc(sizeof *g->until)))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_until_init(g->until, def);
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

void adem_stage_config_free(adem_stage_config *g) {
  for (int k = 0; k < g->nplanes; ++k) adem_motion_free(&g->planes[k].motion);
  for (int k = 0; k < g->nmeshes; ++k) adem_motion_free(&g->meshes[k].motion);
  free(g->materials);
  free(g->interactions);
  free(g->group_force);
  free(g->planes);
  free(g->meshes);
  memset(g, 0, sizeof *g);
}

void adem_stages_free(adem_stages *s) {
  if (!s) return;
  for (int k = 0; k < s->n; ++k) {
    for (int j = 0; j < s->s[k].nsets; ++j) free(s->s[k].sets[j]);
    free(s->s[k].sets);
    free(s->s[k].until);
    adem_stage_config_free(&s->s[k].config);
  }
  adem_stage_config_free(&s->base);
  free(s->s);
  free(s->start);
  free(s);
}

/* ---------------------------------------------------------------- running */

static double stage_start_time(const adem_stages *s, int k) {
  double t = 0.0;
  for (int j = 0; j < k; ++j) t += s->s[j].duration;
  return t;
}

uint64_t adem_stages_start_step(const adem_case *c, int k) {
  const adem_stages *s = c->stages;
  if (!s || k <= 0) return 0;
  if (k >= s->n) return UINT64_MAX;
  if (k < s->nrecorded) return s->start[k];
  if (!s->cut) return (uint64_t)llround(stage_start_time(s, k) / c->world->dt);
  int a = s->nrecorded - 1; /* planned from the last stage begun */
  double t = 0.0;
  for (int j = a; j < k; ++j) t += s->s[j].duration;
  return s->start[a] + (uint64_t)llround(t / c->world->dt);
}

int adem_stages_current(const adem_case *c) { return c->stages ? c->stages->current : 0; }

uint64_t adem_stages_next_step(const adem_case *c, uint64_t step) {
  uint64_t next = adem_pours_next_step(c->pours, c->world->dt, step);
  uint64_t out = adem_outlets_next_step(c->outlets, c->world->dt, step);
  if (out < next) next = out;
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

/* Puts stage k in force at its start. live: during a run (energy balance kept, neighbour lists
 * rebuilt); otherwise the configuration only (at load, or replaying for a checkpoint). */
adem_status adem_stages_enter(adem_case *c, int k, bool live, adem_error *err) {
  adem_stages *s = c->stages;
  adem_world *w = c->world;
  const adem_stage_config *prev = k == 0 ? &s->base : &s->s[k - 1].config;
  const adem_stage_config *next = &s->s[k].config;
  uint64_t start = adem_stages_start_step(c, k);
  if (k >= s->nrecorded) {
    s->start[k] = start;
    s->nrecorded = k + 1;
  }
  double t_s = (double)start * w->dt;
  double before = live ? total_energy(w) : 0.0;
  adem_status st = adem_world_change_walls(w, prev->planes, next->planes, prev->meshes,
                                           next->meshes, t_s, err);
  if (!st) st = adem_world_change_materials(w, next->materials, next->interactions,
                                            next->ninteractions, err);
  if (st) return st;
  for (int j = 0; j < w->ngroups; ++j) adem_world_set_group_force(w, j, next->group_force[j]);
  adem_world_set_gravity(w, next->gravity);
  adem_world_set_max_overlap_ratio(w, next->max_overlap_ratio);
  adem_world_change_skin(w, next->skin_fraction);
  c->output.frame_interval = next->frame_interval;
  c->output.csv_interval = next->csv_interval;
  c->output.checkpoint_interval = next->checkpoint_interval;
  s->current = k;
  if (!live) return ADEM_OK;
  if (s->s[k].until) adem_until_reset(s->s[k].until); /* its streaks count from its start */
  /* Work done by the change (gravity, group forces) is not dissipation: shift the balance. */
  adem_world_add_external_work(w, total_energy(w) - before);
  if (w->step >= adem_schedule_total_steps(c->end_time, w->dt)) /* as the load warned: no step */
    adem_log(ADEM_LOG_INFO, "t = %.9g s (step %llu): stage `%s` is set up at the end time; it runs "
                            "only if the run goes on to a later end",
             w->time, (unsigned long long)w->step,
             s->s[k].name);
  else
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
    adem_status st = adem_stages_enter(c, s->current + 1, w->prepared, err);
    if (st) return st;
  }
  adem_status st = adem_outlets_run(c, err); /* before a batch: it never removes new ones */
  return st ? st : adem_pours_run(c->pours, w, err);
}

adem_status adem_stages_resume(adem_case *c, int current, adem_error *err) {
  adem_stages *s = c->stages;
  int n = s ? s->n : 0;
  if (current < 0 || (current >= n && !(n == 0 && current == 0)))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "it is in stage %d, but its own case text has %d stage%s", current, n,
                          n == 1 ? "" : "s");
  for (int k = 1; k <= current; ++k) {
    adem_status st = adem_stages_enter(c, k, false, err);
    if (st) return st;
  }
  return ADEM_OK;
}

static double interval_of(const adem_stage_config *g, const adem_case *c, int which) {
  if (!g) return which == 0   ? c->output.frame_interval
                 : which == 1 ? c->output.csv_interval
                              : c->output.checkpoint_interval;
  return which == 0 ? g->frame_interval : which == 1 ? g->csv_interval
                                                     : g->checkpoint_interval;
}

bool adem_stages_output_on(const adem_case *c, int which) {
  double dt = c->world->dt;
  if (adem_schedule_period(interval_of(NULL, c, which), dt) > 0) return true;
  for (int k = 0; c->stages && k < c->stages->n; ++k)
    if (adem_schedule_period(interval_of(&c->stages->s[k].config, c, which), dt) > 0) return true;
  return false;
}

/* ---------------------------------------------------------------- run-until conditions */

static adem_until *stage_until(const adem_case *c) {
  const adem_stages *s = c->stages;
  return s && s->n > 0 ? s->s[s->current].until : NULL;
}

uint64_t adem_stages_until_next(const adem_case *c, uint64_t step) {
  uint64_t next = UINT64_MAX;
  double dt = c->world->dt;
  const adem_until *u = stage_until(c);
  if (u) next = adem_until_next_check(u, dt, step);
  if (c->until) {
    uint64_t t = adem_until_next_check(c->until, dt, step);
    if (t < next) next = t;
  }
  return next;
}

adem_until_outcome adem_stages_until(adem_case *c, char *msg, size_t n) {
  adem_world *w = c->world;
  adem_stages *s = c->stages;
  uint64_t step = w->step;
  /* a pour with particles still to come: nothing is at rest yet */
  bool waiting = step > 0 && adem_pours_next_step(c->pours, w->dt, step - 1) != UINT64_MAX;
  adem_until_outcome out = ADEM_UNTIL_NOTHING;
  char what[ADEM_MSG_MAX / 2];
  adem_until *u = stage_until(c);
  if (u && step > adem_stages_start_step(c, s->current) && step % adem_until_period(u, w->dt) == 0 &&
      adem_until_check(u, w, waiting)) {
    adem_until_describe(u, what, sizeof what);
    if (s->current + 1 < s->n) { /* the next stage begins now */
      s->start[s->current + 1] = step;
      s->nrecorded = s->current + 2;
      s->cut = true;
      out = ADEM_UNTIL_STAGE_ENDS;
      snprintf(msg, n, "stage `%s` ends: %s", s->s[s->current].name, what);
    } else {
      out = ADEM_UNTIL_RUN_ENDS;
      snprintf(msg, n, "the last stage, `%s`, ends: %s; the run ends", s->s[s->current].name, what);
    }
  }
  if (c->until && out != ADEM_UNTIL_RUN_ENDS && step % adem_until_period(c->until, w->dt) == 0 &&
      adem_until_check(c->until, w, waiting)) {
    adem_until_describe(c->until, what, sizeof what);
    snprintf(msg, n, "time.until met: %s; the run ends", what);
    out = ADEM_UNTIL_RUN_ENDS;
  }
  return out;
}

bool adem_stages_ended(const adem_case *c, char *msg, size_t n) {
  const adem_until *u = c->until;
  const adem_stages *s = c->stages;
  if (!(u && u->met_step != ADEM_UNTIL_NEVER) && s && s->n > 0 && s->current == s->n - 1)
    u = s->s[s->current].until;
  if (!u || u->met_step != c->world->step || u->met_step == ADEM_UNTIL_NEVER) return false;
  char what[ADEM_MSG_MAX / 2];
  adem_until_describe(u, what, sizeof what);
  snprintf(msg, n, "the run ended at t = %.9g s (step %llu), its condition met: %s", c->world->time,
           (unsigned long long)u->met_step, what);
  return true;
}

void adem_stages_until_status(const adem_case *c, char *buf, size_t n) {
  const adem_until *u = stage_until(c);
  if (!u) u = c->until;
  if (!u) {
    if (n) buf[0] = '\0';
    return;
  }
  adem_until_status(u, c->world->dt, c->world->step, buf, n);
}

void adem_stages_save(adem_writer *wr, const adem_case *c) {
  const adem_stages *s = c->stages;
  adem_put_u32(wr, s ? (uint32_t)s->nrecorded : 0u);
  adem_put_u8(wr, s && s->cut ? 1 : 0);
  for (int k = 0; s && k < s->nrecorded; ++k) adem_put_u64(wr, s->start[k]);
  if (c->until) adem_until_save(wr, c->until);
  for (int k = 0; s && k < s->n; ++k)
    if (s->s[k].until) adem_until_save(wr, s->s[k].until);
}

adem_status adem_stages_load(adem_reader *rd, adem_case *c, adem_error *err) {
  adem_stages *s = c->stages;
  uint32_t nrec = adem_get_u32(rd);
  bool cut = adem_get_u8(rd) != 0;
  if (rd->failed || nrec > (uint32_t)(s ? s->n : 0))
    return adem_error_set(err, ADEM_ERR_INPUT, "its stage starts do not match its own case text");
  for (uint32_t k = 0; k < nrec; ++k) s->start[k] = adem_get_u64(rd);
  if (s) {
    s->nrecorded = (int)nrec;
    s->cut = cut;
  }
  if (c->until) adem_until_load(rd, c->until);
  for (int k = 0; s && k < s->n; ++k)
    if (s->s[k].until) adem_until_load(rd, s->s[k].until);
  if (rd->failed) return adem_error_set(err, ADEM_ERR_INPUT, "its contents are cut short or damaged");
  return ADEM_OK;
}
