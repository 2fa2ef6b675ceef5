/* Case files: `output`, its tracked particles and counted regions. */
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

/* output.track: ids of particles already created (ids count from 0 in order of creation, so
 * particle id k was made from ctx->pos[k]), without repeats. */
static adem_status read_track(case_ctx *ctx, const map_cursor *out) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_output_settings *o = &ctx->c->output;
  o->ntrack = 0;
  adem_status st = adem_yaml_lookup(ctx, out, "track", &e, &v, path);
  if (st || !v || adem_yaml_is_null(v)) return st;
  if (v->type != YAML_SEQUENCE_NODE) return adem_yaml_wrong_type(ctx, e, v, path);
  size_t n = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
  if ((double)n > e->hi)
    return adem_yaml_fail(ctx, v, path, "lists %zu particles; at most %g can be tracked", n, e->hi);
  for (size_t k = 0; k < n; ++k) {
    yaml_node_t *item = adem_yaml_node_at(ctx, v->data.sequence.items.start[k]);
    char p[KEY_PATH_MAX + 24], t[128];
    snprintf(p, sizeof p, "%s[%zu]", path, k);
    uint64_t id;
    if (!adem_yaml_parse_uint(item, &id)) {
      adem_yaml_node_text(item, t, sizeof t);
      return adem_yaml_fail(ctx, item, p, "expected a particle id (an integer >= 0), got %s", t);
    }
    if (id >= ctx->n)
      return adem_yaml_fail(ctx, item, p, "there is no particle %llu: the case creates %zu (ids 0 to %zu)",
                            (unsigned long long)id, ctx->n, ctx->n ? ctx->n - 1 : 0);
    for (int j = 0; j < o->ntrack; ++j)
      if (o->track[j] == id)
        return adem_yaml_fail(ctx, item, p, "particle %llu is listed twice", (unsigned long long)id);
    o->track[o->ntrack] = id;
    o->ntrack++;
  }
  return ADEM_OK;
}

/* output.regions: named regions whose particles each CSV row counts. */
static adem_status read_output_regions(case_ctx *ctx, const map_cursor *out) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, out, "regions", &l);
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    char name[ADEM_NAME_MAX], path[KEY_PATH_MAX];
    yaml_node_t *name_node;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    if ((st = adem_yaml_get_string(ctx, &m, "name", name, sizeof name, &name_node))) break;
    for (int k = 0; ctx->c->regions && k < ctx->c->regions->n; ++k)
      if (!strcmp(ctx->c->regions->r[k].name, name)) {
        adem_yaml_join(path, sizeof path, m.path, "name");
        return adem_yaml_fail(ctx, name_node, path, "duplicate region name `%s` (also %s)", name,
                              ctx->c->regions->r[k].where);
      }
    adem_region reg;
    memset(&reg, 0, sizeof reg);
    const char *word = "";
    if ((st = adem_case_read_region_map(ctx, &m, &reg, &word))) break;
    adem_error werr = {ADEM_OK, ""};
    if (adem_regions_add(&ctx->c->regions, name, m.path, &reg, &werr)) st = adem_yaml_nomem(ctx);
    adem_insert_region_free(&reg);
  }
  return st;
}

/* `output`: folder, intervals, what is written; tracked particles and counted regions. */
adem_status adem_case_build_output(case_ctx *ctx, const map_cursor *root, map_cursor *out) {
  adem_case *c = ctx->c;
  adem_output_settings *o = &c->output;
  yaml_node_t *node;
  adem_status st;
  if ((st = adem_yaml_get_map(ctx, root, "output", out))) return st;
  if ((st = adem_yaml_get_string(ctx, out, "dir", o->dir, sizeof o->dir, &node))) return st;
  if (!node) snprintf(o->dir, sizeof o->dir, "out/%s", c->name);
  o->frame_interval = c->end_time / 100.0;
  o->csv_interval = c->end_time / 1000.0;
  o->checkpoint_interval = c->end_time / 10.0;
  bool plot;
  if ((st = adem_yaml_get_number(ctx, out, "frame_interval", &o->frame_interval, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, out, "csv_interval", &o->csv_interval, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, out, "checkpoint_interval", &o->checkpoint_interval, NULL))) return st;
  if ((st = adem_yaml_get_bool(ctx, out, "plot", &plot))) return st;
  o->plot = plot;
  if ((st = adem_yaml_get_bool(ctx, out, "plot_loads", &plot))) return st;
  o->plot_loads = plot;
  if ((st = adem_yaml_get_bool(ctx, out, "pieces", &plot))) return st;
  o->pieces = plot;
  if ((st = adem_yaml_get_bool(ctx, out, "contacts", &plot))) return st;
  uint64_t every = 1;
  if ((st = adem_yaml_get_uint(ctx, out, "contacts_every", &every, NULL))) return st;
  o->contacts_every = plot ? (int)(every < INT32_MAX ? every : INT32_MAX) : 0;
  if ((st = adem_yaml_get_bool(ctx, out, "contacts_csv", &plot))) return st;
  o->contacts_csv = plot;
  bool balance;
  if ((st = adem_yaml_get_bool(ctx, out, "energy_balance", &balance))) return st;
  adem_world_set_energy_balance(ctx->w, balance);
  if ((st = read_track(ctx, out))) return st;
  return read_output_regions(ctx, out);
}
