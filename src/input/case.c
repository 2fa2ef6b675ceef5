/* Case files: YAML read with libyaml, --set overrides grafted onto the document, every key checked
 * against the schema table (schema.c), then the world built from it. */
#include "adem/case.h"
#include "adem/laws.h"
#include "adem/world.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "adem/files.h"
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

/* ---- sections ---- */

adem_status adem_case_check_box(case_ctx *ctx, adem_vec3 lo, adem_vec3 hi, const yaml_node_t *hi_node,
                                const map_cursor *m) {
  const double a[3] = {lo.x, lo.y, lo.z}, b[3] = {hi.x, hi.y, hi.z};
  for (int k = 0; k < 3; ++k)
    if (!(a[k] < b[k])) {
      char path[KEY_PATH_MAX];
      adem_yaml_join(path, sizeof path, m->path, "max");
      return adem_yaml_fail(ctx, hi_node ? hi_node : m->at, path,
                            "must be greater than `min` in every component (%c: max %g <= min %g)", "xyz"[k],
                            b[k], a[k]);
    }
  return ADEM_OK;
}

/* Case name from a file name: no directory, no extension. */
static void file_stem(const char *file, char *buf, size_t n) {
  const char *base = strrchr(file, '/');
  base = base ? base + 1 : file;
  const char *dot = strrchr(base, '.');
  size_t len = dot && dot != base ? (size_t)(dot - base) : strlen(base);
  if (len >= n) len = n - 1;
  if (len == 0) {
    snprintf(buf, n, "case");
    return;
  }
  memcpy(buf, base, len);
  buf[len] = '\0';
}

/* domain.periodic: each periodic length at least 2 (largest diameter + skin), so that a pair
 * touches through one image at most; no plane wall with a component of its normal along a
 * periodic axis and no box wall (its faces cut every axis). */
static adem_status check_periodic(case_ctx *ctx, const map_cursor *root, adem_vec3 lo, adem_vec3 hi,
                                  const bool per[3], yaml_node_t *const per_items[3],
                                  double skin_fraction) {
  const double a[3] = {lo.x, lo.y, lo.z}, b[3] = {hi.x, hi.y, hi.z};
  double dmax = 2.0 * ctx->rmax, skin = skin_fraction * dmax, need = 2.0 * (dmax + skin);
  char path[KEY_PATH_MAX], where[LOC_MAX];
  for (int d = 0; d < 3; ++d) {
    if (!per[d] || b[d] - a[d] >= need) continue;
    snprintf(path, sizeof path, "domain.periodic[%d]", d);
    return adem_yaml_fail(ctx, per_items[d], path,
                          "the domain is %g m long along %c; a periodic axis needs at least 2 "
                          "(largest diameter + skin) = 2 (%g + %g) = %g m for the minimum image: "
                          "lengthen the domain along %c or make it non-periodic",
                          b[d] - a[d], "xyz"[d], dmax, skin, need, "xyz"[d]);
  }
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "walls", &l);
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    int d = per[0] ? 0 : per[1] ? 1
                                : 2;
    if (!strcmp(m.variant, "box")) {
      adem_yaml_where_short(ctx, per_items[d], where, sizeof where);
      adem_yaml_join(path, sizeof path, m.path, "type");
      return adem_yaml_fail(ctx, adem_yaml_map_get(ctx, m.node, "type"), path,
                            "a box wall has faces across every axis, and %c is periodic "
                            "(domain.periodic at %s); use plane walls parallel to the periodic "
                            "axes",
                            "xyz"[d], where);
    }
    if (strcmp(m.variant, "plane")) continue;
    adem_vec3 n;
    yaml_node_t *node;
    if ((st = adem_yaml_get_vec3(ctx, &m, "normal", &n, &node))) break;
    const double c[3] = {n.x, n.y, n.z};
    for (d = 0; d < 3; ++d) {
      if (!per[d] || !(fabs(c[d]) > 1e-12 * v3_norm(n))) continue;
      adem_yaml_where_short(ctx, per_items[d], where, sizeof where);
      adem_yaml_join(path, sizeof path, m.path, "normal");
      return adem_yaml_fail(ctx, node, path,
                            "the plane's normal [%g, %g, %g] has a component along %c, a periodic "
                            "axis (domain.periodic at %s): a plane would cut the periodic box; it "
                            "must be parallel to every periodic axis",
                            c[0], c[1], c[2], "xyz"[d], where);
    }
  }
  return st;
}

/* `limits`, and `neighbor.skin` (it sets the candidate pairs of the memory estimate); first of
 * the particles: an explicit list may overlap by what limits.initial_overlap accepts. */
static adem_status build_limits(case_ctx *ctx, const map_cursor *root, map_cursor *limits,
                                double *skin) {
  map_cursor nb;
  double overlap, initial = 0.0;
  adem_status st;
  if ((st = adem_yaml_get_map(ctx, root, "limits", limits))) return st;
  if ((st = adem_yaml_get_number(ctx, limits, "max_overlap_ratio", &overlap, NULL))) return st;
  adem_world_set_max_overlap_ratio(ctx->w, overlap);
  if ((st = adem_yaml_get_number(ctx, limits, "initial_overlap", &initial, NULL))) return st;
  adem_world_set_initial_overlap(ctx->w, initial);
  ctx->initial_overlap = initial;
  if ((st = adem_yaml_get_auto(ctx, limits, "max_memory", &ctx->memory_auto, &ctx->max_memory, NULL)))
    return st;
  if ((st = adem_yaml_get_bool(ctx, limits, "allow_large_step", &ctx->allow_large_step))) return st;
  if ((st = adem_yaml_get_map(ctx, root, "neighbor", &nb))) return st;
  if ((st = adem_yaml_get_number(ctx, &nb, "skin", skin, NULL))) return st;
  adem_world_set_skin(ctx->w, *skin);
  return ADEM_OK;
}

/* `time.until`: read once the walls and gravity are known. */
static adem_status build_until(case_ctx *ctx, const map_cursor *time) {
  adem_until_def ud;
  bool has_until = false;
  adem_status st = adem_case_read_until(ctx, time, &ud, &has_until);
  if (st || !has_until) return st;
  if (!(ctx->c->until = malloc(sizeof *ctx->c->until))) return adem_yaml_nomem(ctx);
  adem_until_init(ctx->c->until, &ud);
  return ADEM_OK;
}

/* `domain` (periodic or not), or without it an escape box around all that was made. */
static adem_status build_domain(case_ctx *ctx, const map_cursor *root, double skin, adem_vec3 g) {
  map_cursor domain;
  adem_status st;
  if ((st = adem_yaml_get_map(ctx, root, "domain", &domain))) return st;
  if (domain.node) {
    adem_vec3 lo, hi;
    yaml_node_t *hi_node;
    if ((st = adem_yaml_get_vec3(ctx, &domain, "min", &lo, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &domain, "max", &hi, &hi_node))) return st;
    if ((st = adem_case_check_box(ctx, lo, hi, hi_node, &domain))) return st;
    bool per[3];
    yaml_node_t *per_items[3];
    if ((st = adem_yaml_get_bool3(ctx, &domain, "periodic", per, per_items))) return st;
    unsigned axes = (per[0] ? 1u : 0u) | (per[1] ? 2u : 0u) | (per[2] ? 4u : 0u);
    if (axes) {
      if ((st = check_periodic(ctx, root, lo, hi, per, per_items, skin))) return st;
      adem_error werr = {ADEM_OK, ""};
      if (adem_world_set_periodic(ctx->w, lo, hi, axes, &werr))
        return adem_yaml_fail(ctx, domain.node, domain.path, "%s", werr.message);
    } else {
      adem_world_set_domain(ctx->w, lo, hi);
    }
  } else if (ctx->has_box) {
    /* Wide enough for free flight over the whole run, so only a blow-up trips it. */
    adem_vec3 ext = v3_sub(ctx->box_hi, ctx->box_lo);
    double t = ctx->c->end_time;
    double margin = fmax(fmax(ext.x, fmax(ext.y, ext.z)), 20.0 * ctx->rmax);
    margin = fmax(margin, ctx->vmax * t + 0.5 * v3_norm(g) * t * t);
    adem_world_set_domain(ctx->w, v3_sub(ctx->box_lo, v3(margin, margin, margin)),
                          v3_add(ctx->box_hi, v3(margin, margin, margin)));
  }
  return ADEM_OK;
}

/* The case file's sections in the order they are read: each needs those before it. */
static adem_status build(case_ctx *ctx) {
  adem_case *c = ctx->c;
  map_cursor root, time, limits, out;
  yaml_node_t *node;
  adem_status st;
  if ((st = adem_yaml_map_open(ctx, yaml_document_get_root_node(&ctx->doc), NULL, "", "", NULL, &root)))
    return st;
  if ((st = adem_yaml_get_string(ctx, &root, "name", c->name, sizeof c->name, &node))) return st;
  if (!node) file_stem(ctx->stem_of, c->name, sizeof c->name);
  if ((st = adem_yaml_get_uint(ctx, &root, "seed", &c->seed, NULL))) return st;
  if ((st = adem_yaml_get_map(ctx, &root, "time", &time))) return st; /* required: report it early */
  if ((st = adem_yaml_get_number(ctx, &time, "end", &c->end_time, NULL))) return st;
  if ((st = adem_case_build_materials(ctx, &root))) return st;
  if ((st = adem_case_build_interactions(ctx, &root))) return st;
  if (!adem_yaml_map_get(ctx, root.node, "stages")) /* with stages: once they are known */
    adem_case_warn_unused_law_params(ctx, ctx->file, &ctx->w->mat, NULL);
  if ((st = adem_case_build_groups(ctx, &root))) return st;
  if ((st = adem_case_build_walls(ctx, &root))) return st;
  if (!adem_yaml_map_get(ctx, root.node, "stages")) /* with stages: once they are known */
    adem_case_warn_brof_turning(ctx->file, ctx->w, NULL);
  double skin;
  if ((st = build_limits(ctx, &root, &limits, &skin))) return st;
  if ((st = adem_case_build_particles(ctx, &root))) return st;
  if ((st = adem_case_build_pours(ctx, &root))) return st;
  if ((st = adem_case_check_memory(ctx, 0.0, limits.node ? limits.node : root.at,
                                   limits.node ? "limits" : "")))
    return st;
  adem_vec3 g;
  if ((st = adem_yaml_get_vec3(ctx, &root, "gravity", &g, NULL))) return st;
  adem_world_set_gravity(ctx->w, g);
  if ((st = build_until(ctx, &time))) return st;
  if ((st = adem_case_build_output(ctx, &root, &out))) return st;
  if ((st = adem_case_build_stages(ctx, &root))) return st;
  if ((st = build_domain(ctx, &root, skin, g))) return st;
  if ((st = adem_outlets_read(ctx, &root, &out))) return st; /* regions and domain known */
  if ((st = adem_case_choose_step(ctx, &time, g))) return st;
  return adem_case_warn_pulling_forces(ctx);
}

static void ctx_free(case_ctx *ctx) {
  if (ctx->have_doc) yaml_document_delete(&ctx->doc);
  free(ctx->origin);
  free(ctx->mat_name);
  free(ctx->mat_node);
  free(ctx->mat_density);
  free(ctx->mat_rigid);
  free(ctx->group_name);
  free(ctx->group_node);
  free(ctx->pos);
  free(ctx->vel);
  free(ctx->omega);
  free(ctx->rad);
}

static char *copy_text(const char *s) {
  size_t n = strlen(s) + 1;
  char *t = malloc(n);
  if (t) memcpy(t, s, n);
  return t;
}

/* c->base_dir: dir made absolute, so that a checkpoint finds the case's files from any working
 * folder. */
static bool set_base_dir(adem_case *c, const char *dir) {
  if (dir[0] == '/') {
    snprintf(c->base_dir, sizeof c->base_dir, "%s", dir);
    return strlen(dir) < sizeof c->base_dir;
  }
  char cwd[ADEM_PATH_MAX];
  if (!getcwd(cwd, sizeof cwd)) return false;
  int n = strcmp(dir, ".") == 0 ? snprintf(c->base_dir, sizeof c->base_dir, "%s", cwd)
                                : snprintf(c->base_dir, sizeof c->base_dir, "%s/%s", cwd, dir);
  return n > 0 && (size_t)n < sizeof c->base_dir;
}

adem_status adem_case_load_string(const char *text, const char *name_for_messages,
                                  const char *const *sets, int nsets, adem_case **out,
                                  adem_error *err) {
  return adem_case_load_string_at(text, name_for_messages, NULL, sets, nsets, out, err);
}

adem_status adem_case_load_string_at(const char *text, const char *name_for_messages,
                                     const char *base_dir, const char *const *sets, int nsets,
                                     adem_case **out, adem_error *err) {
  return adem_case_load_string_flags(text, name_for_messages, base_dir, sets, nsets, 0, out, err);
}

adem_status adem_case_load_string_flags(const char *text, const char *name_for_messages,
                                        const char *base_dir, const char *const *sets, int nsets,
                                        unsigned flags, adem_case **out, adem_error *err) {
  if (out) *out = NULL;
  if (!text || !out || nsets < 0 || (nsets > 0 && !sets))
    return adem_error_set(err, ADEM_ERR_INPUT, "adem_case_load_string: no case text");
  adem_case *c = calloc(1, sizeof *c);
  if (!c) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory loading a case");
  snprintf(c->path, sizeof c->path, "%s", name_for_messages ? name_for_messages : "<case>");
  case_ctx ctx;
  memset(&ctx, 0, sizeof ctx);
  ctx.file = c->path;
  ctx.stem_of = name_for_messages ? c->path : "case";
  ctx.err = err;
  ctx.c = c;
  adem_status st = ADEM_OK;
  char *dir = base_dir ? copy_text(base_dir) : adem_file_dirname(name_for_messages ? c->path : ".");
  if (!dir) st = adem_yaml_nomem(&ctx);
  else if (!set_base_dir(c, dir))
    st = adem_error_set(err, ADEM_ERR_INPUT, "%s: cannot tell the case's folder (%s): %s", c->path,
                        dir, strerror(errno ? errno : ENAMETOOLONG));
  ctx.base_dir = dir;
  if (!st) c->source = copy_text(text);
  c->sets = calloc((size_t)(nsets > 0 ? nsets : 1), sizeof *c->sets);
  if (!st && (!c->source || !c->sets)) st = adem_yaml_nomem(&ctx);
  for (int k = 0; k < nsets && !st; ++k) {
    if (!sets[k]) {
      st = adem_error_set(err, ADEM_ERR_INPUT, "--set: missing key.path=value");
      break;
    }
    c->sets[k] = copy_text(sets[k]);
    if (!c->sets[k]) st = adem_yaml_nomem(&ctx);
    c->nsets = k + 1;
  }
  ctx.sets = (const char *const *)c->sets;
  if (!st) st = adem_yaml_load_yaml(text, strlen(text), &ctx.doc, c->path, false, err);
  if (!st) {
    ctx.have_doc = true;
    ctx.nbase = (int)(ctx.doc.nodes.top - ctx.doc.nodes.start);
    st = adem_yaml_apply_sets(&ctx, nsets);
  }
  if (!st) {
    c->world = adem_world_create();
    ctx.w = c->world;
    st = c->world ? build(&ctx) : adem_yaml_nomem(&ctx);
  }
  ctx_free(&ctx);
  free(dir);
  /* Stage configurations are whole loads of the case: not for a stage's own load. */
  if (!st && !(flags & LOAD_STAGE)) st = adem_case_stages_prepare(c, err);
  if (st) {
    adem_case_free(c);
    return st;
  }
  *out = c;
  return ADEM_OK;
}

adem_status adem_case_load_file(const char *path, const char *const *sets, int nsets,
                                adem_case **out, adem_error *err) {
  if (out) *out = NULL;
  if (!path) return adem_error_set(err, ADEM_ERR_INPUT, "no case file given");
  FILE *f = fopen(path, "rb");
  if (!f) return adem_error_set(err, ADEM_ERR_INPUT, "%s: cannot open the case file: %s", path,
                                strerror(errno));
  size_t len = 0, cap = 4096;
  char *text = malloc(cap);
  while (text) {
    len += fread(text + len, 1, cap - 1 - len, f);
    if (len < cap - 1) break;
    char *t = realloc(text, 2 * cap);
    if (!t) {
      free(text);
      text = NULL;
      break;
    }
    text = t;
    cap *= 2;
  }
  int read_errno = errno;
  bool failed = ferror(f);
  fclose(f);
  if (!text) return adem_error_set(err, ADEM_ERR_NOMEM, "%s: out of memory reading the case", path);
  if (failed) {
    free(text);
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: cannot read the case file: %s", path,
                          strerror(read_errno));
  }
  text[len] = '\0';
  if (strlen(text) != len) {
    free(text);
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: the case file holds a NUL byte; is it text?",
                          path);
  }
  adem_status st = adem_case_load_string(text, path, sets, nsets, out, err);
  free(text);
  return st;
}

void adem_case_free(adem_case *c) {
  if (!c) return;
  adem_world_free(c->world);
  adem_pours_free(c->pours);
  adem_stages_free(c->stages);
  adem_regions_free(c->regions);
  adem_regions_free(c->fills);
  adem_outlets_free(c->outlets);
  free(c->until);
  free(c->source);
  if (c->sets)
    for (int k = 0; k < c->nsets; ++k) free(c->sets[k]);
  free(c->sets);
  free(c);
}

void adem_case_write_reference(FILE *f) { adem_schema_write_markdown(f); }
