/* Case files: `stages`, each stage's configuration being the case loaded again with the sets of
 * the stages up to it; stages.c carries them into the running world. */
#include "adem/case.h"
#include "adem/world.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "stl.h"
#include "log.h"
#include "rng.h"
#include "schedule.h"
#include "insert.h"
#include "outlets.h"
#include "case_yaml.h"
#include "case_build.h"
#include "case_walls.h"
#include "schema.h"
#include "stages.h"
#include "adem/vec3.h"
#include "world_internal.h"

/* ---- stages ---- */

/* Appends text to a growing string. */
static bool emit_text(char **buf, size_t *len, size_t *cap, const char *s, size_t n) {
  if (*len + n + 1 > *cap) {
    size_t c = 2 * (*len + n + 1);
    char *b = realloc(*buf, c);
    if (!b) return false;
    *buf = b;
    *cap = c;
  }
  memcpy(*buf + *len, s, n);
  *len += n;
  (*buf)[*len] = '\0';
  return true;
}

/* A YAML value written back as flow-style text that --set's parser reads as the same value:
 * plain scalars stay plain (numbers, booleans, `auto`), others are double-quoted. */
static bool emit_node(case_ctx *ctx, yaml_node_t *v, char **buf, size_t *len, size_t *cap,
                      int depth) {
  if (depth > 64) return false;
  if (v->type == YAML_SCALAR_NODE) {
    const char *s = adem_yaml_sval(v);
    size_t n = v->data.scalar.length;
    if (adem_yaml_is_null(v)) return emit_text(buf, len, cap, "~", 1);
    if (adem_yaml_is_plain(v) && !strpbrk(s, ",[]{}#:\"'\n") && s[0] != ' ' && s[0] != '&' && s[0] != '*' &&
        s[0] != '!' && s[0] != '|' && s[0] != '>' && s[0] != '%' && s[0] != '@' && s[0] != '`')
      return emit_text(buf, len, cap, s, n);
    if (!emit_text(buf, len, cap, "\"", 1)) return false;
    for (size_t k = 0; k < n; ++k) {
      char esc[8];
      unsigned char ch = (unsigned char)s[k];
      if (ch == '"' || ch == '\\') snprintf(esc, sizeof esc, "\\%c", ch);
      else if (ch < 0x20) snprintf(esc, sizeof esc, "\\x%02x", ch);
      else snprintf(esc, sizeof esc, "%c", ch);
      if (!emit_text(buf, len, cap, esc, strlen(esc))) return false;
    }
    return emit_text(buf, len, cap, "\"", 1);
  }
  bool seq = v->type == YAML_SEQUENCE_NODE;
  if (!emit_text(buf, len, cap, seq ? "[" : "{", 1)) return false;
  if (seq) {
    for (yaml_node_item_t *it = v->data.sequence.items.start; it < v->data.sequence.items.top; ++it)
      if ((it > v->data.sequence.items.start && !emit_text(buf, len, cap, ", ", 2)) ||
          !emit_node(ctx, adem_yaml_node_at(ctx, *it), buf, len, cap, depth + 1))
        return false;
  } else {
    for (yaml_node_pair_t *p = v->data.mapping.pairs.start; p < v->data.mapping.pairs.top; ++p)
      if ((p > v->data.mapping.pairs.start && !emit_text(buf, len, cap, ", ", 2)) ||
          !emit_node(ctx, adem_yaml_node_at(ctx, p->key), buf, len, cap, depth + 1) ||
          !emit_text(buf, len, cap, ": ", 2) ||
          !emit_node(ctx, adem_yaml_node_at(ctx, p->value), buf, len, cap, depth + 1))
        return false;
  }
  return emit_text(buf, len, cap, seq ? "]" : "}", 1);
}

/* `stages`: names, durations and the `set` of each, as "path=value" strings for the loader. */
adem_status adem_case_build_stages(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "stages", &l);
  if (st || l.n == 0) return st;
  adem_case *c = ctx->c;
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    char name[ADEM_NAME_MAX], path[KEY_PATH_MAX], loc[LOC_MAX];
    yaml_node_t *name_node, *duration_node, *v;
    const adem_schema_entry *e;
    double duration = -1.0;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    if ((st = adem_yaml_get_string(ctx, &m, "name", name, sizeof name, &name_node))) break;
    if (!name_node) snprintf(name, sizeof name, "stage%zu", i);
    for (int k = 0; c->stages && k < c->stages->n && !st; ++k)
      if (!strcmp(c->stages->s[k].name, name)) {
        adem_yaml_join(path, sizeof path, m.path, "name");
        st = adem_yaml_fail(ctx, name_node ? name_node : m.node, path, "duplicate stage name `%s`", name);
      }
    if (st) break;
    if ((st = adem_yaml_get_number(ctx, &m, "duration", &duration, &duration_node))) break;
    if (!duration_node) duration = -1.0;
    adem_yaml_where(ctx, m.node, loc, sizeof loc);
    adem_error werr = {ADEM_OK, ""};
    if (adem_stages_add(&c->stages, name, duration, loc, &werr)) {
      st = adem_yaml_nomem(ctx);
      break;
    }
    adem_until_def ud;
    bool has_until = false;
    if ((st = adem_case_read_until(ctx, &m, &ud, &has_until))) break;
    if (has_until && adem_stages_set_until(c->stages, &ud, &werr)) {
      st = adem_yaml_nomem(ctx);
      break;
    }
    if ((st = adem_yaml_lookup(ctx, &m, "set", &e, &v, path))) break;
    if (!v || adem_yaml_is_null(v)) continue;
    if (v->type != YAML_MAPPING_NODE) {
      st = adem_yaml_wrong_type(ctx, e, v, path);
      break;
    }
    for (yaml_node_pair_t *p = v->data.mapping.pairs.start; p < v->data.mapping.pairs.top && !st; ++p) {
      yaml_node_t *k = adem_yaml_node_at(ctx, p->key);
      char kp[KEY_PATH_MAX];
      if (k->type != YAML_SCALAR_NODE || adem_yaml_is_null(k)) {
        st = adem_yaml_fail(ctx, k, path, "a key must be a key path such as materials.glass.friction");
        break;
      }
      adem_yaml_join(kp, sizeof kp, path, adem_yaml_sval(k));
      const char *why = adem_stages_check_path(adem_yaml_sval(k));
      if (why) {
        st = adem_yaml_fail(ctx, k, kp, "cannot change in a stage: %s", why);
        break;
      }
      char *text = NULL;
      size_t len = 0, cap = 0;
      bool ok = emit_text(&text, &len, &cap, adem_yaml_sval(k), strlen(adem_yaml_sval(k))) &&
                emit_text(&text, &len, &cap, "=", 1) &&
                emit_node(ctx, adem_yaml_node_at(ctx, p->value), &text, &len, &cap, 0);
      if (!ok || adem_stages_add_set(c->stages, text, &werr)) st = adem_yaml_nomem(ctx);
      free(text);
    }
  }
  return st;
}

/* ---- stages: each stage's configuration is the case loaded again with the sets of the stages
 * up to it; stages.c carries them into the running world ---- */

static adem_status stage_config_extract(adem_stage_config *g, const adem_case *c, adem_error *err) {
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
    adem_stage_config_free(g);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  for (int k = 0; k < g->nmaterials; ++k) g->materials[k] = w->mat.m[k].def;
  for (int k = 0; k < g->ninteractions; ++k) g->interactions[k] = w->mat.defs[k];
  for (int k = 0; k < g->ngroups; ++k) g->group_force[k] = w->groups[k].external_force;
  adem_status st = adem_walls_get_settings(&w->walls, g->planes, g->meshes, err);
  g->gravity = w->gravity;
  g->frame_interval = c->output.frame_interval;
  g->csv_interval = c->output.csv_interval;
  g->checkpoint_interval = c->output.checkpoint_interval;
  g->max_overlap_ratio = w->max_overlap_ratio;
  g->skin_fraction = w->nb.skin_fraction;
  g->dt_proposed = c->estimate.dt;
  if (st) adem_stage_config_free(g);
  return st;
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

adem_status adem_case_stages_prepare(adem_case *c, adem_error *err) {
  adem_stages *s = c->stages;
  if (!s || s->n == 0) return ADEM_OK;
  adem_status st = stage_config_extract(&s->base, c, err);
  if (st) return st;
  int total = c->nsets;
  for (int k = 0; k < s->n; ++k) total += s->s[k].nsets;
  const char **sets = malloc((size_t)(total + 1) * sizeof *sets);
  if (!sets) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  int nsets = 0;
  for (int j = 0; j < c->nsets; ++j) sets[nsets++] = c->sets[j];
  double proposed = s->base.dt_proposed > 0.0 ? s->base.dt_proposed : INFINITY;
  for (int k = 0; k < s->n && !st; ++k) {
    adem_stage *g = &s->s[k];
    for (int j = 0; j < g->nsets; ++j) sets[nsets++] = g->sets[j];
    adem_case *sc = NULL;
    adem_log_mute(1);
    st = adem_case_load_string_flags(c->source, c->path, c->base_dir, sets, nsets,
                                     LOAD_STAGE, &sc, err);
    adem_log_mute(0);
    if (st) {
      st = stage_error(g, k, st, err);
      break;
    }
    st = check_same_world(c, sc, g, err);
    if (!st) st = stage_config_extract(&g->config, sc, err);
    /* a wall the stage moves or servos gets its CSV columns from the start */
    if (!st) adem_walls_note_settings(&c->world->walls, g->config.planes, g->config.meshes);
    adem_case_free(sc);
    if (st) break;
    double ratio = adem_world_dt(c->world) / g->config.dt_proposed;
    /* warned once: by the case itself, or by the first stage that proposes a smaller step */
    bool stricter = g->config.dt_proposed < proposed * (1.0 - 1e-12);
    if (g->config.dt_proposed > 0.0 && g->config.dt_proposed < proposed)
      proposed = g->config.dt_proposed;
    if (c->dt_auto && ratio > 1.0 && g->config.dt_proposed > 0.0) { /* the smallest of all */
      adem_world_set_dt(c->world, g->config.dt_proposed);
    } else if (stricter && ratio > 1.0 + 1e-12 && isfinite(ratio))
      adem_log(ADEM_LOG_WARN,
               "%s: stage `%s`: the time step %g s is %.2fx the step its materials propose (%g s)",
               g->where, g->name, adem_world_dt(c->world), ratio, g->config.dt_proposed);
  }
  free(sets);
  if (st) return st;
  adem_case_warn_unused_law_params(NULL, c->path[0] ? c->path : c->name, &c->world->mat, s);
  adem_case_warn_brof_turning(c->path[0] ? c->path : c->name, c->world, s);
  /* Durations: every stage but the last needs one; the last may run until time.end. */
  double t = 0.0;
  bool earlier = false; /* a stage before may end early (its `until`) */
  for (int k = 0; k < s->n; ++k) {
    adem_stage *g = &s->s[k];
    if (g->duration < 0.0 && k + 1 < s->n)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "%s: stages[%d] (`%s`): duration: required value is missing (every "
                            "stage but the last needs one%s)",
                            g->where, k, g->name, g->until ? "; with `until` it is the most the "
                                                             "stage lasts"
                                                           : "");
    /* the step it begins on, as adem_stages_start_step plans it, against the run's last step */
    double dt = adem_world_dt(c->world);
    if (k > 0 && !earlier && llround(t / dt) >= (long long)adem_schedule_total_steps(c->end_time, dt))
      adem_log(ADEM_LOG_WARN, "%s: stage `%s` begins at t = %g s, at or after time.end = %g s: it "
                              "will not run (unless the run goes on to a later end: adem run --resume DIR --set "
                              "time.end=T)",
               g->where, g->name, t, c->end_time);
    if (g->until) earlier = true;
    if (g->duration >= 0.0) t += g->duration;
  }
  const adem_stage *last = &s->s[s->n - 1];
  if (last->duration >= 0.0 && t < c->end_time * (1.0 - 1e-12))
    adem_log(ADEM_LOG_WARN, "%s: the stages end at t = %g s, before time.end = %g s: the last "
                            "stage (`%s`) goes on until time.end",
             last->where, t, c->end_time, last->name);
  s->current = 0;
  return adem_stages_enter(c, 0, false, err);
}
