/* `walls[].type: cylinder` and `plate`: analytic curved and holed walls (core/cylinder.h), built
 * as planes of another shape so that motion, stages and loads are the planes'. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "adem/vec3.h"
#include "case_walls.h"
#include "cylinder.h"

static adem_status add(case_ctx *ctx, const map_cursor *m, adem_plane_def *d) {
  adem_error werr = {ADEM_OK, ""};
  if (adem_world_add_plane(ctx->w, d, NULL, &werr))
    return werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx)
                                         : adem_yaml_fail(ctx, m->node, m->path, "%s", werr.message);
  return ADEM_OK;
}

/* A unit vector from the key (any length > 0). */
static adem_status unit(case_ctx *ctx, const map_cursor *m, const char *key, adem_vec3 *a) {
  yaml_node_t *node;
  adem_status st = adem_yaml_get_vec3(ctx, m, key, a, &node);
  if (st) return st;
  double len = v3_norm(*a);
  if (!(len > 0.0) || !isfinite(len)) {
    char path[KEY_PATH_MAX];
    adem_yaml_join(path, sizeof path, m->path, key);
    return adem_yaml_fail(ctx, node, path, "must be a non-zero vector");
  }
  *a = v3_scale(*a, 1.0 / len);
  return ADEM_OK;
}

adem_status adem_case_curved_wall(case_ctx *ctx, const map_cursor *m, const char *name, int mat,
                                  bool cylinder, double *reach) {
  adem_plane_def d = adem_default_plane_def();
  snprintf(d.name, sizeof d.name, "%s", name);
  d.material = mat;
  adem_status st = adem_yaml_get_vec3(ctx, m, "point", &d.point, NULL);
  if (st) return st;
  if (!cylinder) { /* a two-sided plate, bounded by `radius`, holed by `hole_radius` */
    if ((st = unit(ctx, m, "normal", &d.normal))) return st;
    d.shape = ADEM_WALL_DISC;
    d.flags = ADEM_WALL_TWO_SIDED;
    if ((st = adem_yaml_get_number(ctx, m, "radius", &d.radius, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, m, "hole_radius", &d.hole_radius, NULL))) return st;
    *reach = fmax(d.radius, d.hole_radius);
    return add(ctx, m, &d);
  }
  if ((st = unit(ctx, m, "axis", &d.normal))) return st;
  d.shape = ADEM_WALL_CYLINDER;
  int contact = 0;
  bool caps = false;
  yaml_node_t *radius_node;
  if ((st = adem_yaml_get_number(ctx, m, "radius", &d.radius, &radius_node))) return st;
  if (!radius_node || !(d.radius > 0.0)) {
    char path[KEY_PATH_MAX];
    adem_yaml_join(path, sizeof path, m->path, "radius");
    return adem_yaml_fail(ctx, radius_node ? radius_node : m->node, path,
                          "a cylinder needs a radius > 0");
  }
  if ((st = adem_yaml_get_number(ctx, m, "length", &d.length, NULL))) return st;
  if ((st = adem_yaml_get_enum(ctx, m, "contact", &contact))) return st;
  if ((st = adem_yaml_get_bool(ctx, m, "caps", &caps))) return st;
  if (caps && d.length <= 0.0)
    return adem_yaml_fail(ctx, m->node, m->path, "`caps: true` needs a finite `length`");
  d.flags = (contact == 1 ? ADEM_WALL_OUTSIDE : 0) | (caps ? ADEM_WALL_CAPPED : 0);
  *reach = d.radius + d.length;
  if ((st = add(ctx, m, &d))) return st;
  /* end caps: one-sided discs facing the particles' side, NAME.cap0 at point, NAME.cap1 at the
   * far end; inside the drum they face inwards, outside a closed cylinder outwards */
  for (int e = 0; caps && e < 2; ++e) {
    adem_plane_def c = adem_default_plane_def();
    snprintf(c.name, sizeof c.name, "%.55s.cap%d", name, e);
    c.material = mat;
    c.shape = ADEM_WALL_DISC;
    c.radius = d.radius;
    c.point = v3_axpy(d.point, e ? d.length : 0.0, d.normal);
    bool plus = (e == 0) != (contact == 1); /* faces +axis */
    c.normal = plus ? d.normal : v3_neg(d.normal);
    if ((st = add(ctx, m, &c))) return st;
  }
  return ADEM_OK;
}

/* ---- particles[].fill_level: a fill sized by the bed it makes ---- */

/* Volume of the region below height z: the region's volume times the share of an 80^3 grid of
 * its bounding box's cell centres inside it that lie below z (exact for a box; a cylinder or a
 * mesh to about a grid cell's share of its boundary). */
static double volume_below(const adem_region *r, double z) {
  if (r->kind == ADEM_REGION_BOX) {
    double h = fmin(fmax(z - r->lo.z, 0.0), r->hi.z - r->lo.z);
    return (r->hi.x - r->lo.x) * (r->hi.y - r->lo.y) * h;
  }
  enum { N = 80 };
  size_t in = 0, below = 0;
  adem_vec3 d = v3_sub(r->hi, r->lo);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      for (int k = 0; k < N; ++k) {
        adem_vec3 x = v3(r->lo.x + d.x * (i + 0.5) / N, r->lo.y + d.y * (j + 0.5) / N,
                         r->lo.z + d.z * (k + 0.5) / N);
        if (!adem_insert_region_contains(r, x)) continue;
        ++in;
        below += x.z < z;
      }
  return in ? r->volume * (double)below / (double)in : 0.0;
}

adem_status adem_case_fill_level(case_ctx *ctx, const map_cursor *fl, const adem_region *reg,
                                 double *fraction) {
  double level = NAN, share = NAN, packing = 0.6;
  yaml_node_t *level_node, *share_node, *packing_node;
  adem_status st = adem_yaml_get_number(ctx, fl, "level", &level, &level_node);
  if (!st) st = adem_yaml_get_number(ctx, fl, "fraction", &share, &share_node);
  if (!st) st = adem_yaml_get_number(ctx, fl, "packing", &packing, &packing_node);
  if (st) return st;
  if (!level_node == !share_node)
    return adem_yaml_fail(ctx, fl->node, fl->path, "give either `level` or `fraction`");
  double bulk = level_node ? volume_below(reg, level) : share * reg->volume;
  *fraction = packing * bulk / reg->volume;
  if (!(*fraction > 0.0) || *fraction >= 0.45)
    return adem_yaml_fail(ctx, fl->node, fl->path,
                          "asks for a solid fraction of %.3g of the region (a bed of %.3g m^3 at "
                          "packing %.3g in %.3g m^3): a random fill places spheres up to about 0.4; "
                          "use a larger region (the bed settles to its level) or a lower level",
                          *fraction, bulk, packing, reg->volume);
  return ADEM_OK;
}
