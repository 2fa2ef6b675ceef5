/* Case files: `particles`, the sets of spheres made at the start (lists, lattices, random fills,
 * a checkpoint's state, frozen sets), and the memory check of what they ask for. */
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

void adem_case_box_include(case_ctx *ctx, adem_vec3 lo, adem_vec3 hi) {
  if (!ctx->has_box) {
    ctx->box_lo = lo;
    ctx->box_hi = hi;
    ctx->has_box = true;
    return;
  }
  ctx->box_lo = v3(fmin(ctx->box_lo.x, lo.x), fmin(ctx->box_lo.y, lo.y), fmin(ctx->box_lo.z, lo.z));
  ctx->box_hi = v3(fmax(ctx->box_hi.x, hi.x), fmax(ctx->box_hi.y, hi.y), fmax(ctx->box_hi.z, hi.z));
}

static adem_status push_sphere(case_ctx *ctx, adem_vec3 x, double r, adem_vec3 v, adem_vec3 w) {
  if (ctx->n == ctx->cap) {
    size_t cap = ctx->cap ? 2 * ctx->cap : 256;
    adem_vec3 *pos = realloc(ctx->pos, cap * sizeof *pos);
    if (pos) ctx->pos = pos;
    adem_vec3 *vel = realloc(ctx->vel, cap * sizeof *vel);
    if (vel) ctx->vel = vel;
    adem_vec3 *omega = realloc(ctx->omega, cap * sizeof *omega);
    if (omega) ctx->omega = omega;
    double *rad = realloc(ctx->rad, cap * sizeof *rad);
    if (rad) ctx->rad = rad;
    if (!pos || !vel || !omega || !rad) return adem_yaml_nomem(ctx);
    ctx->cap = cap;
  }
  ctx->pos[ctx->n] = x;
  ctx->rad[ctx->n] = r;
  ctx->vel[ctx->n] = v;
  ctx->omega[ctx->n] = w;
  ctx->n++;
  return ADEM_OK;
}

/* Adds spheres [first, ctx->n) to the world. */
static adem_status flush_spheres(case_ctx *ctx, size_t first, int material, int group,
                                 const yaml_node_t *at, const char *path) {
  for (size_t i = first; i < ctx->n; ++i) {
    adem_particle_def d = adem_default_particle_def();
    d.position = ctx->pos[i];
    d.velocity = ctx->vel[i];
    d.angular_velocity = ctx->omega[i];
    d.radius = ctx->rad[i];
    d.material = material;
    d.group = group;
    adem_error werr = {ADEM_OK, ""};
    if (adem_world_add_particle(ctx->w, &d, NULL, &werr)) {
      if (werr.status == ADEM_ERR_NOMEM) return adem_yaml_nomem(ctx);
      return adem_yaml_fail(ctx, at, path, "%s", werr.message);
    }
    double r = ctx->rad[i];
    adem_case_box_include(ctx, v3_sub(d.position, v3(r, r, r)), v3_add(d.position, v3(r, r, r)));
    ctx->rmax = fmax(ctx->rmax, r);
    ctx->vmax = fmax(ctx->vmax, v3_norm(d.velocity));
  }
  return ADEM_OK;
}

/* limits.max_memory: refuses a case whose particles (those made so far, `extra` about to be
 * made and the pours' totals) would need more memory than the run may use, before they are
 * allocated. The message points at node, the set or pour asking for them. */
adem_status adem_case_check_memory(case_ctx *ctx, double extra, const yaml_node_t *node,
                                   const char *path) {
  adem_case *c = ctx->c;
  double n = (double)ctx->n + extra + ctx->poured;
  c->memory = adem_world_memory_estimate(ctx->w, n);
  c->memory_auto = ctx->memory_auto;
  c->memory_limit = ctx->memory_auto ? adem_memory_available() : ctx->max_memory;
  const adem_memory_estimate *e = &c->memory;
  if (!(c->memory_limit > 0.0) || e->total <= c->memory_limit) return ADEM_OK;
  const double mib = 1024.0 * 1024.0;
  return adem_yaml_fail(ctx, node, path,
                        "the run would need about %.4g MiB for %.4g particles (%.0f B each with their "
                        "%.3g candidate pairs, the neighbour grid and build included), more than the "
                        "%.4g MiB %s; make fewer particles, or set limits.max_memory (bytes, or auto)",
                        e->total / mib, n, e->total / fmax(n, 1.0), e->pairs / fmax(n, 1.0),
                        c->memory_limit / mib,
                        ctx->memory_auto ? "the machine has available (MemAvailable)"
                                         : "limits.max_memory allows");
}

/* Spheres a solid fraction of a volume takes, with the distribution's mean r^3 (normal: mean^3
 * + 3 mean std^2; the others near it). */
double adem_case_spheres_for_volume(const adem_size_dist *d, double volume) {
  double mean, std;
  adem_insert_dist_moments(d, &mean, &std);
  double r3 = mean * mean * mean + 3.0 * mean * std * std;
  return r3 > 0.0 ? volume / ((4.0 / 3.0) * ADEM_PI * r3) : 0.0;
}

/* An explicit list of spheres; none of them may overlap another of the list unless
 * limits.initial_overlap accepts some overlap (then the world checks the depth at prepare). */
static adem_status build_list(case_ctx *ctx, const map_cursor *set, int mat, int group) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, set, "spheres", &l);
  if (st) return st;
  if ((st = adem_case_check_memory(ctx, (double)l.n, set->node, set->path))) return st;
  size_t first = ctx->n;
  double rmax = 0;
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    adem_vec3 x, v, w;
    double r = 0.0;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &m, "position", &x, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, &m, "radius", &r, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &m, "velocity", &v, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &m, "angular_velocity", &w, NULL))) return st;
    if ((st = push_sphere(ctx, x, r, v, w))) return st;
    rmax = fmax(rmax, r);
  }
  if (l.n > 1 && ctx->initial_overlap <= 0.0) {
    adem_vec3 lo = ctx->pos[first], hi = lo;
    for (size_t i = first; i < ctx->n; ++i) {
      adem_vec3 p = ctx->pos[i];
      lo = v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
      hi = v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    adem_sphere_grid g;
    if (adem_insert_grid_init(&g, lo, hi, 2.0 * rmax, rmax, l.n)) return adem_yaml_nomem(ctx);
    for (size_t i = first; i < ctx->n && !st; ++i) {
      int64_t j = adem_insert_grid_overlap(&g, ctx->pos, ctx->rad, ctx->pos[i], ctx->rad[i]);
      if (j >= 0) {
        size_t a = (size_t)j - first, b = i - first;
        yaml_node_t *na = adem_yaml_node_at(ctx, l.node->data.sequence.items.start[a]);
        yaml_node_t *nb = adem_yaml_node_at(ctx, l.node->data.sequence.items.start[b]);
        char pa[KEY_PATH_MAX], pb[KEY_PATH_MAX], first_at[LOC_MAX];
        snprintf(pa, sizeof pa, "%.240s[%zu]", l.path, a);
        snprintf(pb, sizeof pb, "%.240s[%zu]", l.path, b);
        adem_yaml_where_short(ctx, na, first_at, sizeof first_at);
        st = adem_yaml_fail(ctx, nb, pb,
                            "overlaps %s (at %s): centre distance %g m < sum of radii %g m (a settled "
                            "bed may overlap: set limits.initial_overlap)",
                            pa, first_at,
                            v3_norm(v3_sub(ctx->pos[i], ctx->pos[j])), ctx->rad[i] + ctx->rad[j]);
      } else if (adem_insert_grid_add(&g, ctx->pos, ctx->rad, i)) {
        st = adem_yaml_nomem(ctx);
      }
    }
    adem_insert_grid_free(&g);
    if (st) return st;
  }
  return flush_spheres(ctx, first, mat, group, set->node, set->path);
}

/* Number of lattice sites along one axis: centres at lo + r + k s up to hi - r. */
static double lattice_sites(double lo, double hi, double r, double s) {
  double room = hi - lo - 2.0 * r;
  if (room < -1e-12 * fabs(hi - lo)) return 0;
  return floor(fmax(room, 0.0) / s * (1.0 + 1e-12)) + 1.0; /* round-off must not lose a layer */
}

static adem_status build_lattice(case_ctx *ctx, const map_cursor *m, int mat, int group) {
  double r = 0.0, s = 0.0;
  adem_vec3 lo, hi, v, w;
  uint64_t count;
  yaml_node_t *s_node, *hi_node, *count_node;
  adem_status st;
  char path[KEY_PATH_MAX];
  if ((st = adem_yaml_get_number(ctx, m, "radius", &r, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, m, "spacing", &s, &s_node))) return st;
  if (s < 2.0 * r) {
    adem_yaml_join(path, sizeof path, m->path, "spacing");
    return adem_yaml_fail(ctx, s_node, path,
                          "spacing %g m is less than the diameter 2 radius = %g m; neighbours would overlap", s,
                          2.0 * r);
  }
  if ((st = adem_yaml_get_vec3(ctx, m, "min", &lo, NULL))) return st;
  if ((st = adem_yaml_get_vec3(ctx, m, "max", &hi, &hi_node))) return st;
  if ((st = adem_case_check_box(ctx, lo, hi, hi_node, m))) return st;
  if ((st = adem_yaml_get_uint(ctx, m, "count", &count, &count_node))) return st;
  if ((st = adem_yaml_get_vec3(ctx, m, "velocity", &v, NULL))) return st;
  if ((st = adem_yaml_get_vec3(ctx, m, "angular_velocity", &w, NULL))) return st;
  double nx = lattice_sites(lo.x, hi.x, r, s), ny = lattice_sites(lo.y, hi.y, r, s),
         nz = lattice_sites(lo.z, hi.z, r, s);
  if (nx < 1 || ny < 1 || nz < 1) {
    adem_yaml_join(path, sizeof path, m->path, "max");
    return adem_yaml_fail(ctx, hi_node, path, "the box is narrower than one sphere (diameter %g m) along %c",
                          2.0 * r, nx < 1 ? 'x' : ny < 1 ? 'y'
                                                         : 'z');
  }
  double capacity = nx * ny * nz;
  double n = count > 0 ? fmin((double)count, capacity) : capacity;
  if (n > MAX_SET_SPHERES)
    return adem_yaml_fail(ctx, m->node, m->path, "would create %.3g spheres (at most %.0g per set)", n,
                          MAX_SET_SPHERES);
  if ((double)count > capacity)
    adem_log(ADEM_LOG_WARN, "%s: the lattice box holds %.0f spheres; count asks for %llu", m->path,
             capacity, (unsigned long long)count);
  if ((st = adem_case_check_memory(ctx, n, m->node, m->path))) return st;
  size_t first = ctx->n, total = (size_t)n, nxy = (size_t)nx * (size_t)ny;
  for (size_t k = 0; k < total; ++k) {
    size_t ix = k % (size_t)nx, iy = (k / (size_t)nx) % (size_t)ny, iz = k / nxy;
    adem_vec3 x = v3(lo.x + r + (double)ix * s, lo.y + r + (double)iy * s, lo.z + r + (double)iz * s);
    if ((st = push_sphere(ctx, x, r, v, w))) return st;
  }
  return flush_spheres(ctx, first, mat, group, m->node, m->path);
}

/* A random non-overlapping fill of a box, cylinder or closed mesh, up to a count or a solid
 * fraction; keeps clear of the walls built so far and of every earlier sphere. */
static adem_status build_random(case_ctx *ctx, const map_cursor *m, size_t set_index, int mat,
                                int group) {
  adem_region reg;
  adem_size_dist dist;
  memset(&reg, 0, sizeof reg);
  memset(&dist, 0, sizeof dist);
  const char *word = "box", *fit_what = "";
  uint64_t count = 0, max_attempts = 0;
  double fraction = 0.0;
  yaml_node_t *count_node, *fraction_node, *attempts_node;
  adem_vec3 v, w;
  map_cursor dm;
  char path[KEY_PATH_MAX];
  adem_fill_result res;
  memset(&res, 0, sizeof res);
  adem_status st = adem_case_read_region(ctx, m, true, &reg, &word);
  if (!st) st = adem_yaml_get_uint(ctx, m, "count", &count, &count_node);
  if (!st) st = adem_yaml_get_number(ctx, m, "solid_fraction", &fraction, &fraction_node);
  map_cursor fl; /* fill_level: the solid fraction of a bed to a level (case_walls.c) */
  if (!st) st = adem_yaml_get_map(ctx, m, "fill_level", &fl);
  if (!st && fl.node && (count_node || fraction_node))
    st = adem_yaml_fail(ctx, fl.node, fl.path, "give one of `count`, `solid_fraction`, `fill_level`");
  if (!st && fl.node && !(st = adem_case_fill_level(ctx, &fl, &reg, &fraction)))
    fraction_node = fl.node;
  if (!st && count_node && fraction_node) {
    adem_yaml_join(path, sizeof path, m->path, "solid_fraction");
    st = adem_yaml_fail(ctx, fraction_node, path, "give either `count` or `solid_fraction`, not both");
  }
  if (!st && !count_node && !fraction_node) {
    adem_yaml_join(path, sizeof path, m->path, "count");
    st = adem_yaml_missing(ctx, m, adem_schema_find(m->schema, "count", m->variant), path);
  }
  if (!st && (double)count > MAX_SET_SPHERES)
    st = adem_yaml_fail(ctx, m->node, m->path, "count %llu is more than %.0g spheres per set",
                        (unsigned long long)count, MAX_SET_SPHERES);
  if (!st) st = adem_yaml_get_uint(ctx, m, "max_attempts", &max_attempts, &attempts_node);
  if (!st && !attempts_node) max_attempts = 0;
  if (!st) st = adem_yaml_get_vec3(ctx, m, "velocity", &v, NULL);
  if (!st) st = adem_yaml_get_vec3(ctx, m, "angular_velocity", &w, NULL);
  double fit = adem_insert_region_fit(&reg, &fit_what);
  if (!st) st = adem_case_read_dist(ctx, m, fit, fit_what, word, &dist, &dm);
  if (!st)
    st = adem_case_check_memory(ctx, count_node ? (double)count : adem_case_spheres_for_volume(&dist, fraction * reg.volume),
                                m->node, m->path);
  if (!st) {
    /* Each set draws from its own stream, so editing one set leaves the others' spheres alone. */
    adem_rng rng = adem_rng_seed(ctx->c->seed ^ (0x9e3779b97f4a7c15ULL * (uint64_t)(set_index + 1)));
    adem_fill_def def = {&reg, &dist, count, fraction, max_attempts, ctx->w};
    adem_error werr = {ADEM_OK, ""};
    st = adem_insert_fill(&def, &rng, ctx->pos, ctx->rad, ctx->n, &res, &werr);
    if (st == ADEM_ERR_NOMEM) st = adem_yaml_nomem(ctx);
    else if (st) st = adem_yaml_fail(ctx, dm.node, dm.path, "%s the %s (%s is %g m)", werr.message, word,
                                     fit_what, fit);
  }
  size_t first = ctx->n;
  for (size_t k = 0; k < res.n && !st; ++k) st = push_sphere(ctx, res.pos[k], res.radius[k], v, w);
  if (!st && res.n < res.wanted) {
    char loc[LOC_MAX], frac[160] = "";
    adem_yaml_where(ctx, m->node, loc, sizeof loc);
    if (fraction_node)
      snprintf(frac, sizeof frac, " (solid fraction %.4g of the %.4g asked)",
               res.volume / reg.volume, fraction);
    adem_log(ADEM_LOG_WARN,
             "%s: %s: random fill placed %zu of %zu spheres before max_attempts (%llu) ran out%s; "
             "the %s may be too full",
             loc, m->path, res.n, res.wanted, (unsigned long long)res.attempts, frac, word);
  }
  adem_insert_fill_result_free(&res);
  adem_insert_dist_free(&dist);
  if (!st) { /* kept for `adem check`'s look at it against the walls */
    char where[KEY_PATH_MAX + 16];
    snprintf(where, sizeof where, "%s%s", m->path,
             adem_yaml_map_get(ctx, m->node, "region") ? ".region" : " (min, max)");
    adem_error werr = {ADEM_OK, ""};
    if (adem_regions_add(&ctx->c->fills, word, where, &reg, &werr)) st = adem_yaml_nomem(ctx);
  }
  adem_insert_region_free(&reg);
  if (st) return st;
  return flush_spheres(ctx, first, mat, group, m->node, m->path);
}

/* `type: state`: the particles of a checkpoint, in the order of their ids, with this case's
 * materials of the same names. */
static adem_status build_state(case_ctx *ctx, const map_cursor *m, int group) {
  char file[ADEM_PATH_MAX], path[KEY_PATH_MAX];
  yaml_node_t *file_node;
  adem_status st = adem_yaml_get_string(ctx, m, "file", file, sizeof file, &file_node);
  if (st) return st;
  adem_yaml_join(path, sizeof path, m->path, "file");
  char *resolved = adem_case_mesh_path(ctx, file);
  if (!resolved) return adem_yaml_nomem(ctx);
  char *data = NULL;
  size_t len = 0;
  adem_error werr = {ADEM_OK, ""};
  adem_particles p;
  memset(&p, 0, sizeof p);
  char(*names)[ADEM_NAME_MAX] = NULL;
  int nmat = 0;
  size_t *order = NULL;
  adem_reader rd;
  st = adem_file_read_all(resolved, &data, &len, &werr);
  if (!st) st = adem_checkpoint_header_check(data, len, resolved, ADEM_CKPT_MAGIC,
                                             sizeof(adem_contact_history), &rd, &werr);
  if (!st) { /* the case section, skipped by its length */
    uint64_t skip = adem_get_u64(&rd);
    if (rd.failed || skip > (uint64_t)(rd.end - rd.at))
      st = adem_error_set(&werr, ADEM_ERR_INPUT, "%s is not a usable adem checkpoint: it is cut short", resolved);
    else
      rd.at += skip;
  }
  if (!st) {
    st = adem_world_read_particles(&rd, &p, &names, &nmat, &werr);
    if (st && st != ADEM_ERR_NOMEM) {
      char why[ADEM_MSG_MAX];
      snprintf(why, sizeof why, "%s", werr.message);
      adem_error_set(&werr, st, "%s is not a usable adem checkpoint: %s", resolved, why);
    }
  }
  if (st) {
    st = st == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, file_node, path, "%s", werr.message);
    goto done;
  }
  /* keep_inside: trim to the centres inside a box (a levelled bed) */
  bool trim = adem_yaml_map_get(ctx, m->node, "keep_inside") != NULL;
  adem_vec3 keep_lo = {0, 0, 0}, keep_hi = {0, 0, 0};
  if (trim) {
    map_cursor km;
    yaml_node_t *hi_node;
    if ((st = adem_yaml_get_map(ctx, m, "keep_inside", &km))) goto done;
    if ((st = adem_yaml_get_vec3(ctx, &km, "min", &keep_lo, NULL))) goto done;
    if ((st = adem_yaml_get_vec3(ctx, &km, "max", &keep_hi, &hi_node))) goto done;
    if ((st = adem_case_check_box(ctx, keep_lo, keep_hi, hi_node, &km))) goto done;
  }
  if ((st = adem_case_check_memory(ctx, (double)p.n, m->node, m->path))) goto done;
  /* by id (an outlet may have removed some: not always 0 .. n-1) */
  order = malloc((p.n + 1) * sizeof *order);
  uint32_t *by_id = malloc((p.n + 1) * sizeof *by_id);
  if (!order || !by_id || adem_particles_id_order(&p, by_id)) {
    free(by_id);
    st = adem_yaml_nomem(ctx);
    goto done;
  }
  for (size_t k = 0; k < p.n; ++k) order[k] = by_id[k];
  for (size_t k = 1; k < p.n && !st; ++k)
    if (p.id[order[k]] == p.id[order[k - 1]])
      st = adem_yaml_fail(ctx, file_node, path, "%s is not a usable adem checkpoint: particle id %llu is there twice", resolved, (unsigned long long)p.id[order[k]]);
  free(by_id);
  for (size_t k = 0; k < p.n && !st; ++k) {
    size_t i = order[k];
    adem_vec3 x = p.pos[i];
    if (trim && !(x.x >= keep_lo.x && x.x <= keep_hi.x && x.y >= keep_lo.y && x.y <= keep_hi.y &&
                  x.z >= keep_lo.z && x.z <= keep_hi.z))
      continue;
    const char *name = names[p.material[i]];
    int mat = -1;
    for (int j = 0; j < ctx->nmat && mat < 0; ++j)
      if (!strcmp(ctx->mat_name[j], name)) mat = j;
    if (mat < 0) {
      st = adem_yaml_fail(ctx, file_node, path,
                          "the particles of %s are made of material `%s`, which this case does not "
                          "have; add a material of that name",
                          resolved, name);
      break;
    }
    if (ctx->mat_rigid[mat] || !ctx->mat_density[mat]) {
      st = adem_yaml_fail(ctx, file_node, path,
                          "material `%s` of the particles of %s needs a `density` and must not be "
                          "rigid here",
                          name, resolved);
      break;
    }
    if ((st = push_sphere(ctx, p.pos[i], p.radius[i], p.vel[i], p.omega[i]))) break;
    st = flush_spheres(ctx, ctx->n - 1, mat, group, file_node, path);
  }
done:
  free(order);
  free(names);
  adem_particles_free(&p);
  free(data);
  free(resolved);
  return st;
}

/* particles[].frozen / attach: the set's spheres (from index n0) become part of a wall
 * (src/core/frozen.c), a plane or a mesh group by name, or are fixed in space. */
static adem_status freeze_set(case_ctx *ctx, const map_cursor *m, size_t n0) {
  bool frozen = false;
  char name[ADEM_NAME_MAX] = "", path[KEY_PATH_MAX];
  yaml_node_t *node;
  adem_status st = adem_yaml_get_bool(ctx, m, "frozen", &frozen);
  if (!st) st = adem_yaml_get_string(ctx, m, "attach", name, sizeof name, &node);
  if (st || (!frozen && !node)) return st;
  int32_t attach = 0;
  if (node) {
    adem_yaml_join(path, sizeof path, m->path, "attach");
    int g = adem_world_find_mesh_group(ctx->w, name);
    for (int k = 0; g < 0 && k < adem_world_plane_count(ctx->w) && !attach; ++k)
      if (!strcmp(adem_world_plane(ctx->w, k)->name, name)) attach = -(k + 1);
    if (g >= 0) attach = g + 1;
    if (!attach)
      return adem_yaml_fail(ctx, node, path, "no plane or mesh group named `%s` to attach to "
                                             "(a box's planes are NAME.xmin ...)",
                            name);
  }
  for (size_t i = n0; i < ctx->w->p.n; ++i) {
    adem_error werr = {ADEM_OK, ""};
    if (adem_world_freeze_particle(ctx->w, ctx->w->p.id[i], attach, &werr))
      return adem_yaml_fail(ctx, node ? node : m->node, node ? path : m->path, "%s", werr.message);
  }
  return ADEM_OK;
}

adem_status adem_case_build_particles(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "particles", &l);
  if (st) return st;
  if (l.n == 0 && !adem_yaml_map_get(ctx, root->node, "pours")) { /* a case needs something to move */
    if (!l.node) return adem_yaml_missing(ctx, root, l.e, l.path);
    return adem_yaml_fail(ctx, l.node, l.path, "needs at least 1 item (or give `pours`)");
  }
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    char material[ADEM_NAME_MAX], group_name[ADEM_NAME_MAX], path[KEY_PATH_MAX];
    yaml_node_t *mat_node, *group_node;
    int mat, group;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) return st;
    if (!strcmp(m.variant, "state")) {
      if ((st = adem_yaml_get_string(ctx, &m, "group", group_name, sizeof group_name, &group_node))) return st;
      adem_yaml_join(path, sizeof path, m.path, "group");
      if ((st = adem_case_find_group(ctx, group_name, group_node ? group_node : m.node, path, &group))) return st;
      if ((st = build_state(ctx, &m, group))) return st;
      continue;
    }
    if ((st = adem_yaml_get_string(ctx, &m, "material", material, sizeof material, &mat_node))) return st;
    adem_yaml_join(path, sizeof path, m.path, "material");
    if ((st = adem_case_find_material(ctx, material, mat_node, path, &mat))) return st;
    if (ctx->mat_rigid[mat])
      return adem_yaml_fail(ctx, mat_node, path, "material `%s` is rigid; rigid materials are for walls only",
                            material);
    if (!ctx->mat_density[mat]) {
      char at[LOC_MAX];
      adem_yaml_where_short(ctx, ctx->mat_node[mat], at, sizeof at);
      return adem_yaml_fail(ctx, mat_node, path,
                            "material `%s` (at %s) has no `density`; materials of particles need one", material,
                            at);
    }
    if ((st = adem_yaml_get_string(ctx, &m, "group", group_name, sizeof group_name, &group_node))) return st;
    adem_yaml_join(path, sizeof path, m.path, "group");
    if ((st = adem_case_find_group(ctx, group_name, group_node ? group_node : m.node, path, &group))) return st;
    size_t n0 = ctx->w->p.n;
    if (!strcmp(m.variant, "list"))
      st = build_list(ctx, &m, mat, group);
    else if (!strcmp(m.variant, "lattice"))
      st = build_lattice(ctx, &m, mat, group);
    else
      st = build_random(ctx, &m, i, mat, group);
    if (!st) st = freeze_set(ctx, &m, n0);
    if (st) return st;
  }
  return ADEM_OK;
}
