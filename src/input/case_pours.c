/* Case files: size distributions and regions (shared by random sets, pours and outputs) and
 * `pours`. */
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

/* ---- insertion: size distributions, regions, random fills ---- */

/* A list [a, b, ...] of numbers under key (absent: *n = 0, *node NULL), each in the entry's
 * range; a fresh array in *out. */
adem_status adem_case_get_numbers(case_ctx *ctx, const map_cursor *m, const char *key, double **out,
                                  size_t *n, yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  *out = NULL;
  *n = 0;
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st || !v) return st;
  if (v->type != YAML_SEQUENCE_NODE) return adem_yaml_wrong_type(ctx, e, v, path);
  size_t count = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
  if (count == 0) return adem_yaml_fail(ctx, v, path, "needs at least one number");
  *out = malloc(count * sizeof **out);
  if (!*out) return adem_yaml_nomem(ctx);
  for (size_t k = 0; k < count; ++k) {
    yaml_node_t *item = adem_yaml_node_at(ctx, v->data.sequence.items.start[k]);
    char p[KEY_PATH_MAX + 24];
    snprintf(p, sizeof p, "%s[%zu]", path, k);
    if ((st = adem_yaml_read_number(ctx, e, item, p, &(*out)[k]))) {
      free(*out);
      *out = NULL;
      return st;
    }
  }
  *n = count;
  return ADEM_OK;
}

/* `radius` of a random set or a pour: the distribution, checked against the largest radius the
 * region holds (fit, called `fit_what` of the `region_word` in messages). */
adem_status adem_case_read_dist(case_ctx *ctx, const map_cursor *m, double fit, const char *fit_what,
                                const char *region_word, adem_size_dist *d, map_cursor *dm) {
  memset(d, 0, sizeof *d);
  adem_status st = adem_yaml_get_map(ctx, m, "radius", dm);
  if (st) return st;
  char path[KEY_PATH_MAX];
  yaml_node_t *node;
  d->limit = fit;
  if (!strcmp(dm->variant, "constant")) {
    d->kind = ADEM_SIZE_CONSTANT;
    if ((st = adem_yaml_get_number(ctx, dm, "value", &d->value, &node))) return st;
    adem_yaml_join(path, sizeof path, dm->path, "value");
    if (d->value > fit)
      return adem_yaml_fail(ctx, node, path, "radius %g m does not fit the %s (%s is %g m)", d->value,
                            region_word, fit_what, fit);
  } else if (!strcmp(dm->variant, "uniform")) {
    d->kind = ADEM_SIZE_UNIFORM;
    if ((st = adem_yaml_get_number(ctx, dm, "min", &d->min, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, dm, "max", &d->max, &node))) return st;
    adem_yaml_join(path, sizeof path, dm->path, "max");
    if (!(d->max > d->min)) return adem_yaml_fail(ctx, node, path, "must be greater than `min` (%g m)", d->min);
    if (d->max > fit)
      return adem_yaml_fail(ctx, node, path, "radius %g m does not fit the %s (%s is %g m)", d->max,
                            region_word, fit_what, fit);
  } else if (!strcmp(dm->variant, "discrete")) {
    d->kind = ADEM_SIZE_DISCRETE;
    double *weights = NULL;
    size_t nw = 0;
    yaml_node_t *wnode;
    if ((st = adem_case_get_numbers(ctx, dm, "values", &d->values, &d->n, &node))) return st;
    if ((st = adem_case_get_numbers(ctx, dm, "weights", &weights, &nw, &wnode))) return st;
    d->cumulative = malloc(d->n * sizeof *d->cumulative);
    if (!d->cumulative) {
      free(weights);
      return adem_yaml_nomem(ctx);
    }
    double sum = 0.0;
    for (size_t k = 0; k < d->n; ++k) {
      sum += wnode ? (k < nw ? weights[k] : 0.0) : 1.0;
      d->cumulative[k] = sum;
    }
    free(weights);
    adem_yaml_join(path, sizeof path, dm->path, "weights");
    if (wnode && nw != d->n)
      return adem_yaml_fail(ctx, wnode, path, "has %zu weights for %zu values; give one weight per value", nw,
                            d->n);
    if (!(sum > 0.0)) return adem_yaml_fail(ctx, wnode, path, "the weights are all 0");
    adem_yaml_join(path, sizeof path, dm->path, "values");
    for (size_t k = 0; k < d->n; ++k)
      if (d->values[k] > fit)
        return adem_yaml_fail(ctx, node, path, "radius %g m does not fit the %s (%s is %g m)", d->values[k],
                              region_word, fit_what, fit);
  } else {
    d->kind = !strcmp(dm->variant, "lognormal") ? ADEM_SIZE_LOGNORMAL : ADEM_SIZE_NORMAL;
    if ((st = adem_yaml_get_number(ctx, dm, "mean", &d->mean, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, dm, "std", &d->std, NULL))) return st;
  }
  return ADEM_OK;
}

/* A mapping with a `shape` (its variant) and that shape's keys: a box, a cylinder or the inside
 * of a closed STL surface. *word names its kind for messages. */
adem_status adem_case_read_region_map(case_ctx *ctx, const map_cursor *rm, adem_region *r,
                                      const char **word) {
  adem_error werr = {ADEM_OK, ""};
  char path[KEY_PATH_MAX];
  adem_vec3 lo, hi;
  yaml_node_t *hi_node;
  adem_status st;
  if (!strcmp(rm->variant, "box")) {
    *word = "box";
    if ((st = adem_yaml_get_vec3(ctx, rm, "min", &lo, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, rm, "max", &hi, &hi_node))) return st;
    if ((st = adem_case_check_box(ctx, lo, hi, hi_node, rm))) return st;
    adem_insert_region_box(r, lo, hi);
  } else if (!strcmp(rm->variant, "cylinder")) {
    *word = "cylinder";
    adem_vec3 a, b;
    double radius = 0.0;
    yaml_node_t *end_node;
    if ((st = adem_yaml_get_vec3(ctx, rm, "start", &a, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, rm, "end", &b, &end_node))) return st;
    if ((st = adem_yaml_get_number(ctx, rm, "radius", &radius, NULL))) return st;
    if (adem_insert_region_cylinder(r, a, b, radius, &werr)) {
      adem_yaml_join(path, sizeof path, rm->path, "end");
      return adem_yaml_fail(ctx, end_node, path, "%s", werr.message);
    }
  } else {
    *word = "mesh region";
    char file[ADEM_PATH_MAX];
    yaml_node_t *file_node;
    adem_mesh_transform tf = adem_default_mesh_transform();
    if ((st = adem_yaml_get_string(ctx, rm, "file", file, sizeof file, &file_node))) return st;
    if ((st = adem_yaml_get_number(ctx, rm, "scale", &tf.scale, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, rm, "translate", &tf.translation, NULL))) return st;
    char *resolved = adem_case_mesh_path(ctx, file);
    if (!resolved) return adem_yaml_nomem(ctx);
    st = adem_insert_region_mesh(r, resolved, &tf, &werr);
    free(resolved);
    adem_yaml_join(path, sizeof path, rm->path, "file");
    if (st) return werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, file_node, path, "%s", werr.message);
  }
  return ADEM_OK;
}

/* The region of a random set (`region`, or the box `min`/`max`: box_keys) or of a pour. *word
 * names its kind for messages. */
adem_status adem_case_read_region(case_ctx *ctx, const map_cursor *m, bool box_keys, adem_region *r,
                                  const char **word) {
  map_cursor rm;
  memset(&rm, 0, sizeof rm);
  adem_status st = ADEM_OK;
  /* absent from a random set: the box keys are used (an absent mapping with a `shape` to
   * choose would be reported missing) */
  if (!box_keys || adem_yaml_map_get(ctx, m->node, "region")) st = adem_yaml_get_map(ctx, m, "region", &rm);
  if (st) return st;
  char path[KEY_PATH_MAX];
  adem_vec3 lo, hi;
  yaml_node_t *lo_node = NULL, *hi_node = NULL;
  if (box_keys) {
    if ((st = adem_yaml_get_vec3(ctx, m, "min", &lo, &lo_node))) return st;
    if ((st = adem_yaml_get_vec3(ctx, m, "max", &hi, &hi_node))) return st;
    if (rm.node && (lo_node || hi_node)) {
      adem_yaml_join(path, sizeof path, m->path, lo_node ? "min" : "max");
      return adem_yaml_fail(ctx, lo_node ? lo_node : hi_node, path,
                            "give either the box `min`/`max` or a `region`, not both");
    }
    if (!rm.node) {
      *word = "box";
      if (!lo_node || !hi_node) {
        const char *key = lo_node ? "max" : "min";
        adem_yaml_join(path, sizeof path, m->path, key);
        return adem_yaml_missing(ctx, m, adem_schema_find(m->schema, key, m->variant), path);
      }
      if ((st = adem_case_check_box(ctx, lo, hi, hi_node, m))) return st;
      adem_insert_region_box(r, lo, hi);
      return ADEM_OK;
    }
  }
  return adem_case_read_region_map(ctx, &rm, r, word);
}

/* ---- pours ---- */

/* Material of a set or pour that makes particles: exists, not rigid, has a density. */
static adem_status particle_material(case_ctx *ctx, const map_cursor *m, int *mat) {
  char material[ADEM_NAME_MAX], path[KEY_PATH_MAX];
  yaml_node_t *mat_node;
  adem_status st = adem_yaml_get_string(ctx, m, "material", material, sizeof material, &mat_node);
  if (st) return st;
  adem_yaml_join(path, sizeof path, m->path, "material");
  if ((st = adem_case_find_material(ctx, material, mat_node, path, mat))) return st;
  if (ctx->mat_rigid[*mat])
    return adem_yaml_fail(ctx, mat_node, path, "material `%s` is rigid; rigid materials are for walls only",
                          material);
  if (!ctx->mat_density[*mat]) {
    char at[LOC_MAX];
    adem_yaml_where_short(ctx, ctx->mat_node[*mat], at, sizeof at);
    return adem_yaml_fail(ctx, mat_node, path,
                          "material `%s` (at %s) has no `density`; materials of particles need one", material,
                          at);
  }
  return ADEM_OK;
}

adem_status adem_case_build_pours(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "pours", &l);
  if (st || l.n == 0) return st;
  adem_world *w = ctx->w;
  if (!w->insert_rmin) {
    w->insert_rmin = malloc((size_t)(w->mat.n > 0 ? w->mat.n : 1) * sizeof *w->insert_rmin);
    if (!w->insert_rmin) return adem_yaml_nomem(ctx);
    for (int k = 0; k < w->mat.n; ++k) w->insert_rmin[k] = INFINITY;
  }
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m, dm;
    adem_pour_def d;
    memset(&d, 0, sizeof d);
    char path[KEY_PATH_MAX], group_name[ADEM_NAME_MAX];
    yaml_node_t *name_node, *group_node, *rate_node, *mass_node, *end_node, *interval_node;
    const char *word = "", *fit_what = "";
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    if ((st = adem_yaml_get_string(ctx, &m, "name", d.name, sizeof d.name, &name_node))) break;
    if (!name_node) snprintf(d.name, sizeof d.name, "pour%zu", i);
    for (int k = 0; ctx->c->pours && k < ctx->c->pours->n && !st; ++k)
      if (!strcmp(ctx->c->pours->p[k].def.name, d.name)) {
        adem_yaml_join(path, sizeof path, m.path, "name");
        st = adem_yaml_fail(ctx, name_node ? name_node : m.node, path, "duplicate pour name `%s`", d.name);
      }
    if (st) break;
    if ((st = particle_material(ctx, &m, &d.material))) break;
    if ((st = adem_yaml_get_string(ctx, &m, "group", group_name, sizeof group_name, &group_node))) break;
    adem_yaml_join(path, sizeof path, m.path, "group");
    if ((st = adem_case_find_group(ctx, group_name, group_node ? group_node : m.node, path, &d.group))) break;
    if ((st = adem_yaml_get_number(ctx, &m, "rate", &d.rate, &rate_node))) break;
    if ((st = adem_yaml_get_number(ctx, &m, "mass_rate", &d.mass_rate, &mass_node))) break;
    if (rate_node && mass_node) {
      adem_yaml_join(path, sizeof path, m.path, "mass_rate");
      st = adem_yaml_fail(ctx, mass_node, path, "give either `rate` (particles/s) or `mass_rate` (kg/s), not both");
      break;
    }
    if (!rate_node && !mass_node) {
      adem_yaml_join(path, sizeof path, m.path, "rate");
      st = adem_yaml_missing(ctx, &m, adem_schema_find("pours[]", "rate", NULL), path);
      break;
    }
    if ((st = adem_yaml_get_number(ctx, &m, "start", &d.start, NULL))) break;
    if ((st = adem_yaml_get_number(ctx, &m, "end", &d.end, &end_node))) break;
    if (!(d.end > d.start)) {
      adem_yaml_join(path, sizeof path, m.path, "end");
      st = adem_yaml_fail(ctx, end_node, path, "the window ends (%g s) before it starts (`start`: %g s)",
                          d.end, d.start);
      break;
    }
    if (d.end > ctx->c->end_time) {
      char loc[LOC_MAX];
      adem_yaml_where(ctx, end_node, loc, sizeof loc);
      adem_log(ADEM_LOG_WARN, "%s: %s.end: the pour ends at t = %g s, after time.end = %g s: the "
                              "run stops before it is complete",
               loc, m.path, d.end, ctx->c->end_time);
    }
    d.interval = (d.end - d.start) / 20.0;
    if ((st = adem_yaml_get_number(ctx, &m, "interval", &d.interval, &interval_node))) break;
    if ((st = adem_yaml_get_vec3(ctx, &m, "velocity", &d.velocity, NULL))) break;
    if ((st = adem_yaml_get_vec3(ctx, &m, "angular_velocity", &d.angular_velocity, NULL))) break;
    if ((st = adem_yaml_get_uint(ctx, &m, "max_attempts", &d.max_attempts, NULL))) break;
    if ((st = adem_case_read_region(ctx, &m, false, &d.region, &word))) break;
    double fit = adem_insert_region_fit(&d.region, &fit_what);
    if ((st = adem_case_read_dist(ctx, &m, fit, fit_what, word, &d.dist, &dm))) {
      adem_insert_region_free(&d.region);
      adem_insert_dist_free(&d.dist);
      break;
    }
    double window = d.end - d.start;
    ctx->poured += d.rate > 0.0 ? d.rate * window
                                : adem_case_spheres_for_volume(&d.dist, d.mass_rate * window /
                                                                            w->mat.m[d.material].def.density);
    if ((st = adem_case_check_memory(ctx, 0.0, m.node, m.path))) {
      adem_insert_region_free(&d.region);
      adem_insert_dist_free(&d.dist);
      break;
    }
    d.seed = ctx->c->seed ^ (0xd1b54a32d192ed03ULL * (uint64_t)(i + 1));
    w->insert_rmin[d.material] = fmin(w->insert_rmin[d.material], adem_insert_dist_smallest(&d.dist));
    adem_case_box_include(ctx, d.region.lo, d.region.hi);
    ctx->vmax = fmax(ctx->vmax, v3_norm(d.velocity));
    ctx->rmax = fmax(ctx->rmax, adem_insert_dist_largest(&d.dist));
    adem_error werr = {ADEM_OK, ""};
    if (adem_pours_add(&ctx->c->pours, &d, w->mat.m[d.material].def.density, &werr)) {
      adem_insert_region_free(&d.region);
      adem_insert_dist_free(&d.dist);
      st = adem_yaml_nomem(ctx);
    }
  }
  return st;
}
