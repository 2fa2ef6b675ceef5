/* Particle insertion: size distributions, regions, random fills and pours (see insert.h). */
#include "insert.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cylinder.h"
#include "mesh_contact.h"
#include "dmath.h"
#include "log.h"
#include "adem/vec3.h"
#include "stl.h"
#include "world_internal.h"

/* ---------------------------------------------------------------- size distributions */

/* Standard normal 0.1 % quantile: the step estimate takes radii down to it. */
#define Z_SMALL 3.09

static void lognormal_params(const adem_size_dist *d, double *mu, double *sigma) {
  double s2 = adem_dmath_log1p(d->std * d->std / (d->mean * d->mean));
  *sigma = sqrt(s2);
  *mu = adem_dmath_log(d->mean) - 0.5 * s2;
}

adem_status adem_insert_draw_radius(const adem_size_dist *d, adem_rng *rng, double *r,
                                    adem_error *err) {
  switch (d->kind) {
    case ADEM_SIZE_CONSTANT: *r = d->value; return ADEM_OK;
    case ADEM_SIZE_UNIFORM: *r = d->min + (d->max - d->min) * adem_rng_uniform(rng); return ADEM_OK;
    case ADEM_SIZE_DISCRETE: {
      double u = adem_rng_uniform(rng) * d->cumulative[d->n - 1];
      size_t lo = 0, hi = d->n - 1; /* first k with cumulative[k] > u */
      while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (d->cumulative[mid] > u) hi = mid;
        else lo = mid + 1;
      }
      *r = d->values[lo];
      return ADEM_OK;
    }
    case ADEM_SIZE_NORMAL:
    case ADEM_SIZE_LOGNORMAL: break;
  }
  bool lognormal = d->kind == ADEM_SIZE_LOGNORMAL;
  double mu = 0.0, sigma = 0.0;
  if (lognormal) lognormal_params(d, &mu, &sigma);
  for (int tries = 0; tries < 1000; ++tries) {
    double z = adem_rng_normal(rng);
    double x = lognormal ? adem_dmath_exp(mu + sigma * z) : d->mean + d->std * z;
    if (x > 0 && x <= d->limit) {
      *r = x;
      return ADEM_OK;
    }
  }
  return adem_error_set(err, ADEM_ERR_INPUT,
                        "could not draw a radius in (0, %g m] in 1000 tries; the distribution "
                        "does not fit",
                        d->limit);
}

double adem_insert_dist_smallest(const adem_size_dist *d) {
  switch (d->kind) {
    case ADEM_SIZE_CONSTANT: return d->value;
    case ADEM_SIZE_UNIFORM: return d->min;
    case ADEM_SIZE_DISCRETE: {
      double r = INFINITY;
      for (size_t k = 0; k < d->n; ++k) r = fmin(r, d->values[k]);
      return r;
    }
    case ADEM_SIZE_NORMAL: return fmax(d->mean - Z_SMALL * d->std, 0.1 * d->mean);
    case ADEM_SIZE_LOGNORMAL: {
      double mu, sigma;
      lognormal_params(d, &mu, &sigma);
      return adem_dmath_exp(mu - Z_SMALL * sigma);
    }
  }
  return 0.0;
}

double adem_insert_dist_largest(const adem_size_dist *d) {
  switch (d->kind) {
    case ADEM_SIZE_CONSTANT: return d->value;
    case ADEM_SIZE_UNIFORM: return d->max;
    case ADEM_SIZE_DISCRETE: {
      double r = 0.0;
      for (size_t k = 0; k < d->n; ++k) r = fmax(r, d->values[k]);
      return r;
    }
    case ADEM_SIZE_NORMAL: return fmin(d->mean + Z_SMALL * d->std, d->limit);
    case ADEM_SIZE_LOGNORMAL: {
      double mu, sigma;
      lognormal_params(d, &mu, &sigma);
      return fmin(adem_dmath_exp(mu + Z_SMALL * sigma), d->limit);
    }
  }
  return 0.0;
}

void adem_insert_dist_moments(const adem_size_dist *d, double *mean, double *std) {
  switch (d->kind) {
    case ADEM_SIZE_CONSTANT: *mean = d->value; *std = 0.0; return;
    case ADEM_SIZE_UNIFORM:
      *mean = 0.5 * (d->min + d->max);
      *std = (d->max - d->min) / sqrt(12.0);
      return;
    case ADEM_SIZE_DISCRETE: {
      double total = d->cumulative[d->n - 1], m = 0.0, m2 = 0.0, prev = 0.0;
      for (size_t k = 0; k < d->n; ++k) {
        double p = (d->cumulative[k] - prev) / total;
        prev = d->cumulative[k];
        m += p * d->values[k];
        m2 += p * d->values[k] * d->values[k];
      }
      *mean = m;
      *std = sqrt(fmax(m2 - m * m, 0.0));
      return;
    }
    case ADEM_SIZE_NORMAL:
    case ADEM_SIZE_LOGNORMAL: *mean = d->mean; *std = d->std; return;
  }
}

void adem_insert_dist_free(adem_size_dist *d) {
  free(d->values);
  free(d->cumulative);
  d->values = d->cumulative = NULL;
  d->n = 0;
}

/* ---------------------------------------------------------------- regions */

void adem_insert_region_box(adem_region *r, adem_vec3 lo, adem_vec3 hi) {
  memset(r, 0, sizeof *r);
  r->kind = ADEM_REGION_BOX;
  r->lo = lo;
  r->hi = hi;
  r->volume = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
}

adem_status adem_insert_region_cylinder(adem_region *r, adem_vec3 start, adem_vec3 end,
                                        double radius, adem_error *err) {
  memset(r, 0, sizeof *r);
  adem_vec3 d = v3_sub(end, start);
  double len = v3_norm(d);
  if (!(len > 0.0) || !isfinite(len))
    return adem_error_set(err, ADEM_ERR_INPUT, "the cylinder's two ends are at the same point");
  if (!(radius > 0.0) || !isfinite(radius))
    return adem_error_set(err, ADEM_ERR_INPUT, "the cylinder's radius must be > 0");
  r->kind = ADEM_REGION_CYLINDER;
  r->start = start;
  r->axis = v3_scale(d, 1.0 / len);
  r->length = len;
  r->radius = radius;
  /* e1, e2: any orthonormal pair across the axis */
  adem_vec3 a = r->axis;
  adem_vec3 t = fabs(a.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0);
  r->e1 = v3_scale(v3_cross(a, t), 1.0 / v3_norm(v3_cross(a, t)));
  r->e2 = v3_cross(a, r->e1);
  /* bounding box of the two end discs: extent radius sqrt(1 - a_k^2) across each axis k */
  double ex = radius * sqrt(fmax(0.0, 1.0 - a.x * a.x));
  double ey = radius * sqrt(fmax(0.0, 1.0 - a.y * a.y));
  double ez = radius * sqrt(fmax(0.0, 1.0 - a.z * a.z));
  r->lo = v3(fmin(start.x, end.x) - ex, fmin(start.y, end.y) - ey, fmin(start.z, end.z) - ez);
  r->hi = v3(fmax(start.x, end.x) + ex, fmax(start.y, end.y) + ey, fmax(start.z, end.z) + ez);
  r->volume = ADEM_PI * radius * radius * len;
  return ADEM_OK;
}

/* Edge function of p against the edge u -> v (twice the signed area of u, v, p), evaluated with
 * the edge's end points in a fixed order: the two triangles sharing an edge then get exactly
 * opposite values, so a point on the edge is never counted twice or missed. */
static double edge_fn(adem_vec3 u, adem_vec3 v, adem_vec3 p) {
  bool swap = u.x > v.x || (u.x == v.x && u.y > v.y);
  adem_vec3 s = swap ? v : u, t = swap ? u : v;
  double e = (t.x - s.x) * (p.y - s.y) - (t.y - s.y) * (p.x - s.x);
  return swap ? -e : e;
}

/* Top-left rule for a counter-clockwise triangle (y up): a point exactly on an edge belongs to
 * the triangle when the edge goes down, or is horizontal and goes left. */
static bool edge_holds(double e, adem_vec3 u, adem_vec3 v) {
  if (e != 0.0) return e > 0.0;
  return v.y < u.y || (v.y == u.y && v.x < u.x);
}

static void column_of(const adem_region *r, double x, double y, int c[2]) {
  double a = floor((x - r->lo.x) / r->col_size), b = floor((y - r->lo.y) / r->col_size);
  c[0] = a < 0 ? 0 : a >= r->cols[0] ? r->cols[0] - 1 : (int)a;
  c[1] = b < 0 ? 0 : b >= r->cols[1] ? r->cols[1] - 1 : (int)b;
}

/* True when the vertical ray up from p crosses triangle abc above p. Triangles seen edge-on from
 * above are skipped: their neighbours decide. */
static bool ray_crosses(adem_vec3 a, adem_vec3 b, adem_vec3 d, adem_vec3 p) {
  double area = edge_fn(a, b, d);
  if (area == 0.0) return false;
  if (area < 0.0) {
    adem_vec3 t = b;
    b = d;
    d = t;
  }
  double wa = edge_fn(b, d, p), wb = edge_fn(d, a, p), wd = edge_fn(a, b, p);
  if (!edge_holds(wa, b, d) || !edge_holds(wb, d, a) || !edge_holds(wd, a, b)) return false;
  return (wa * a.z + wb * b.z + wd * d.z) / (wa + wb + wd) > p.z;
}

/* Ray parity along +z: the number of triangles the vertical ray from p crosses above p. */
static bool mesh_inside(const adem_region *r, adem_vec3 p) {
  if (p.x < r->lo.x || p.x > r->hi.x || p.y < r->lo.y || p.y > r->hi.y) return false;
  int c[2];
  column_of(r, p.x, p.y, c);
  size_t col = (size_t)c[1] * (size_t)r->cols[0] + (size_t)c[0];
  const adem_mesh *m = &r->mesh;
  int crossings = 0;
  for (size_t e = r->col_start[col]; e < r->col_start[col + 1]; ++e) {
    const uint32_t *v = m->tri[r->col_tri[e]];
    crossings += ray_crosses(m->vert[v[0]], m->vert[v[1]], m->vert[v[2]], p);
  }
  return crossings & 1;
}

/* True when some triangle is closer to x than radius. */
static bool mesh_near(const adem_region *r, adem_vec3 x, double radius) {
  int c0[2], c1[2];
  column_of(r, x.x - radius, x.y - radius, c0);
  column_of(r, x.x + radius, x.y + radius, c1);
  const adem_mesh *m = &r->mesh;
  double r2 = radius * radius;
  for (int cy = c0[1]; cy <= c1[1]; ++cy)
    for (int cx = c0[0]; cx <= c1[0]; ++cx) {
      size_t col = (size_t)cy * (size_t)r->cols[0] + (size_t)cx;
      for (size_t e = r->col_start[col]; e < r->col_start[col + 1]; ++e) {
        adem_vec3 q;
        adem_triangle_feature f;
        if (adem_triangle_distance2(m, r->col_tri[e], x, &q, &f) < r2) return true;
      }
    }
  return false;
}

/* Checks that r->mesh encloses a volume and indexes its triangles in columns for the ray test;
 * path names it in messages. Frees r on failure. */
static adem_status index_mesh_region(adem_region *r, const char *path, adem_error *err) {
  const adem_mesh *m = &r->mesh;
  size_t open = 0;
  for (size_t t = 0; t < m->ntris; ++t)
    for (int k = 0; k < 3; ++k) open += m->edge_kind[t][k] == ADEM_MESH_EDGE_BORDER;
  if (m->ntris == 0 || open > 0 || m->nonmanifold_edges > 0) {
    size_t ntris = m->ntris, nonmanifold = m->nonmanifold_edges;
    adem_insert_region_free(r);
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s does not enclose a volume: %zu triangles, %zu open edges, %zu edges "
                          "shared by more than two triangles (a region needs a closed surface)",
                          path, ntris, open, nonmanifold);
  }
  double vol = 0.0; /* divergence theorem: sum of signed tetrahedra from the origin */
  for (size_t t = 0; t < m->ntris; ++t) {
    adem_vec3 a = m->vert[m->tri[t][0]], b = m->vert[m->tri[t][1]], c = m->vert[m->tri[t][2]];
    vol += v3_dot(a, v3_cross(b, c)) / 6.0;
  }
  r->volume = fabs(vol);
  adem_mesh_bounds(m, &r->lo, &r->hi);
  /* columns: about one per triangle, at most 1024 a side */
  double ex = r->hi.x - r->lo.x, ey = r->hi.y - r->lo.y;
  double h = sqrt(fmax(ex * ey, 1e-300) / (double)m->ntris);
  h = fmax(h, fmax(ex, ey) / 1024.0);
  if (!(h > 0.0)) h = 1.0;
  r->col_size = h;
  r->cols[0] = (int)floor(ex / h) + 1;
  r->cols[1] = (int)floor(ey / h) + 1;
  size_t ncols = (size_t)r->cols[0] * (size_t)r->cols[1];
  r->col_start = calloc(ncols + 1, sizeof *r->col_start);
  if (!r->col_start) goto nomem;
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t t = 0; t < m->ntris; ++t) {
      adem_vec3 a = m->vert[m->tri[t][0]], b = m->vert[m->tri[t][1]], c = m->vert[m->tri[t][2]];
      int c0[2], c1[2];
      column_of(r, fmin(a.x, fmin(b.x, c.x)), fmin(a.y, fmin(b.y, c.y)), c0);
      column_of(r, fmax(a.x, fmax(b.x, c.x)), fmax(a.y, fmax(b.y, c.y)), c1);
      for (int cy = c0[1]; cy <= c1[1]; ++cy)
        for (int cx = c0[0]; cx <= c1[0]; ++cx) {
          size_t col = (size_t)cy * (size_t)r->cols[0] + (size_t)cx;
          if (pass == 0) r->col_start[col + 1]++;
          else r->col_tri[r->col_start[col]++] = (uint32_t)t;
        }
    }
    if (pass == 0) {
      for (size_t k = 0; k < ncols; ++k) r->col_start[k + 1] += r->col_start[k];
      r->col_tri = malloc((r->col_start[ncols] + 1) * sizeof *r->col_tri);
      if (!r->col_tri) goto nomem;
    }
  }
  for (size_t k = ncols; k > 0; --k) r->col_start[k] = r->col_start[k - 1];
  r->col_start[0] = 0;
  return ADEM_OK;
nomem:
  adem_insert_region_free(r);
  return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory indexing %s", path);
}

adem_status adem_insert_region_mesh(adem_region *r, const char *path,
                                    const adem_mesh_transform *tf, adem_error *err) {
  memset(r, 0, sizeof *r);
  r->kind = ADEM_REGION_MESH;
  adem_status st = adem_mesh_load_stl(path, tf, NULL, &r->mesh, err);
  if (st) return st;
  return index_mesh_region(r, path, err);
}

adem_status adem_insert_region_triangles(adem_region *r, const adem_vec3 *corners, size_t ntri,
                                         adem_error *err) {
  memset(r, 0, sizeof *r);
  r->kind = ADEM_REGION_MESH;
  adem_status st = adem_mesh_add_triangles(&r->mesh, corners, NULL, ntri, "surface", 0, 0, err);
  if (st) {
    adem_insert_region_free(r);
    return st;
  }
  return index_mesh_region(r, "the surface", err);
}

/* Round-off scale of a region: a billionth of its largest extent. */
static double region_eps(const adem_region *r) {
  adem_vec3 s = v3_sub(r->hi, r->lo);
  return 1e-9 * fmax(s.x, fmax(s.y, s.z));
}

bool adem_insert_region_contains(const adem_region *r, adem_vec3 x) {
  double eps = region_eps(r);
  switch (r->kind) {
    case ADEM_REGION_BOX:
      return x.x > r->lo.x + eps && x.y > r->lo.y + eps && x.z > r->lo.z + eps &&
             x.x < r->hi.x - eps && x.y < r->hi.y - eps && x.z < r->hi.z - eps;
    case ADEM_REGION_CYLINDER: {
      adem_vec3 d = v3_sub(x, r->start);
      double s = v3_dot(d, r->axis), a = v3_dot(d, r->e1), b = v3_dot(d, r->e2);
      double room = r->radius - eps;
      return s > eps && s < r->length - eps && a * a + b * b < room * room;
    }
    case ADEM_REGION_MESH:
      if (x.x <= r->lo.x || x.y <= r->lo.y || x.z <= r->lo.z || x.x >= r->hi.x ||
          x.y >= r->hi.y || x.z >= r->hi.z)
        return false;
      return mesh_inside(r, x) && !mesh_near(r, x, eps);
  }
  return false;
}

adem_vec3 adem_insert_region_centre(const adem_region *r) {
  adem_vec3 mid = v3_scale(v3_add(r->lo, r->hi), 0.5);
  if (r->kind == ADEM_REGION_CYLINDER) return v3_axpy(r->start, 0.5 * r->length, r->axis);
  if (r->kind != ADEM_REGION_MESH || adem_insert_region_contains(r, mid)) return mid;
  adem_vec3 s = v3_sub(r->hi, r->lo);
  for (int i = 1; i < 8; ++i)
    for (int j = 1; j < 8; ++j)
      for (int k = 1; k < 8; ++k) {
        adem_vec3 x = v3(r->lo.x + s.x * i / 8.0, r->lo.y + s.y * j / 8.0, r->lo.z + s.z * k / 8.0);
        if (adem_insert_region_contains(r, x)) return x;
      }
  return mid;
}

int adem_insert_region_plane_side(const adem_region *r, adem_vec3 point, adem_vec3 normal) {
  double lo = INFINITY, hi = -INFINITY;
  if (r->kind == ADEM_REGION_CYLINDER) {
    double c = v3_dot(normal, r->axis);
    double across = r->radius * sqrt(fmax(0.0, 1.0 - c * c));
    double d0 = v3_dot(v3_sub(r->start, point), normal);
    double d1 = d0 + r->length * c;
    lo = fmin(d0, d1) - across;
    hi = fmax(d0, d1) + across;
  } else if (r->kind == ADEM_REGION_MESH) {
    for (size_t v = 0; v < r->mesh.nverts; ++v) {
      double d = v3_dot(v3_sub(r->mesh.vert[v], point), normal);
      lo = fmin(lo, d);
      hi = fmax(hi, d);
    }
  } else {
    for (int k = 0; k < 8; ++k) {
      adem_vec3 x = v3(k & 1 ? r->hi.x : r->lo.x, k & 2 ? r->hi.y : r->lo.y, k & 4 ? r->hi.z : r->lo.z);
      double d = v3_dot(v3_sub(x, point), normal);
      lo = fmin(lo, d);
      hi = fmax(hi, d);
    }
  }
  double eps = region_eps(r);
  if (lo >= -eps) return 1;
  if (hi <= eps) return -1;
  return 0;
}

/* Separating-axis test of a triangle against a box (Akenine-Moeller 2001): true when they
 * overlap by more than eps (touching is not overlapping). */
static bool triangle_box_overlap(adem_vec3 lo, adem_vec3 hi, adem_vec3 a, adem_vec3 b, adem_vec3 c,
                                 double eps) {
  adem_vec3 centre = v3_scale(v3_add(lo, hi), 0.5), half = v3_scale(v3_sub(hi, lo), 0.5);
  adem_vec3 v[3] = {v3_sub(a, centre), v3_sub(b, centre), v3_sub(c, centre)};
  adem_vec3 e[3] = {v3_sub(v[1], v[0]), v3_sub(v[2], v[1]), v3_sub(v[0], v[2])};
  adem_vec3 axes[13];
  int n = 0;
  axes[n++] = v3(1, 0, 0);
  axes[n++] = v3(0, 1, 0);
  axes[n++] = v3(0, 0, 1);
  axes[n++] = v3_cross(e[0], e[1]); /* the triangle's normal */
  for (int i = 0; i < 3; ++i) {
    adem_vec3 u = i == 0 ? v3(1, 0, 0) : i == 1 ? v3(0, 1, 0) : v3(0, 0, 1);
    for (int j = 0; j < 3; ++j) axes[n++] = v3_cross(u, e[j]);
  }
  for (int k = 0; k < n; ++k) {
    adem_vec3 ax = axes[k];
    double len = v3_norm(ax);
    if (!(len > 1e-300)) continue; /* parallel edges: no axis */
    ax = v3_scale(ax, 1.0 / len);
    double p0 = v3_dot(v[0], ax), p1 = v3_dot(v[1], ax), p2 = v3_dot(v[2], ax);
    double rad = half.x * fabs(ax.x) + half.y * fabs(ax.y) + half.z * fabs(ax.z);
    if (fmin(p0, fmin(p1, p2)) >= rad - eps || fmax(p0, fmax(p1, p2)) <= -rad + eps) return false;
  }
  return true;
}

bool adem_insert_region_cuts_triangle(const adem_region *r, adem_vec3 a, adem_vec3 b,
                                      adem_vec3 c) {
  double eps = region_eps(r);
  if (fmax(a.x, fmax(b.x, c.x)) <= r->lo.x + eps || fmin(a.x, fmin(b.x, c.x)) >= r->hi.x - eps ||
      fmax(a.y, fmax(b.y, c.y)) <= r->lo.y + eps || fmin(a.y, fmin(b.y, c.y)) >= r->hi.y - eps ||
      fmax(a.z, fmax(b.z, c.z)) <= r->lo.z + eps || fmin(a.z, fmin(b.z, c.z)) >= r->hi.z - eps)
    return false;
  if (r->kind == ADEM_REGION_BOX) return triangle_box_overlap(r->lo, r->hi, a, b, c, eps);
  /* points of the triangle no farther apart than an eighth of the region's smallest extent */
  adem_vec3 s = v3_sub(r->hi, r->lo);
  double spacing = fmin(s.x, fmin(s.y, s.z)) / 8.0;
  double longest = fmax(v3_norm(v3_sub(b, a)), fmax(v3_norm(v3_sub(c, b)), v3_norm(v3_sub(a, c))));
  double nd = ceil(longest / fmax(spacing, 1e-300));
  int n = nd < 1.0 ? 1 : nd > 256.0 ? 256 : (int)nd;
  adem_vec3 ab = v3_sub(b, a), ac = v3_sub(c, a);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      adem_vec3 x = v3_add(a, v3_add(v3_scale(ab, (double)i / n), v3_scale(ac, (double)j / n)));
      if (adem_insert_region_contains(r, x)) return true;
    }
  return false;
}

adem_status adem_regions_add(adem_regions **prs, const char *name, const char *where,
                             adem_region *region, adem_error *err) {
  if (!*prs && !(*prs = calloc(1, sizeof **prs)))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_regions *rs = *prs;
  adem_named_region *r = realloc(rs->r, (size_t)(rs->n + 1) * sizeof *r);
  if (!r) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  rs->r = r;
  adem_named_region *x = &r[rs->n++];
  memset(x, 0, sizeof *x);
  snprintf(x->name, sizeof x->name, "%s", name);
  snprintf(x->where, sizeof x->where, "%s", where);
  x->region = *region;
  memset(region, 0, sizeof *region);
  return ADEM_OK;
}

void adem_regions_free(adem_regions *rs) {
  if (!rs) return;
  for (int k = 0; k < rs->n; ++k) adem_insert_region_free(&rs->r[k].region);
  free(rs->r);
  free(rs);
}

void adem_regions_count(const adem_regions *rs, const adem_world *w, double *count,
                        double *mass) {
  /* the masses summed by id, as every sum over particles (order independence) */
  uint32_t *order = rs && rs->n > 0 ? adem_world_id_order(w) : NULL;
  for (int k = 0; rs && k < rs->n; ++k) {
    const adem_region *r = &rs->r[k].region;
    double n = 0.0, m = 0.0;
    for (size_t q = 0; order && q < w->p.n; ++q) {
      size_t i = order[q];
      if (!adem_insert_region_contains(r, w->p.pos[i])) continue;
      n += 1.0;
      m += 1.0 / w->p.inv_mass[i];
    }
    count[k] = order ? n : NAN; /* out of memory */
    mass[k] = order ? m : NAN;
  }
  free(order);
}

void adem_insert_region_free(adem_region *r) {
  adem_mesh_free(&r->mesh);
  free(r->col_start);
  free(r->col_tri);
  r->col_start = NULL;
  r->col_tri = NULL;
}

double adem_insert_region_fit(const adem_region *r, const char **what) {
  adem_vec3 s = v3_sub(r->hi, r->lo);
  double half_side = 0.5 * fmin(s.x, fmin(s.y, s.z));
  switch (r->kind) {
    case ADEM_REGION_CYLINDER:
      if (what) *what = "its radius or half its length";
      return fmin(r->radius, 0.5 * r->length);
    case ADEM_REGION_MESH:
      if (what) *what = "half the smallest side of its bounding box";
      return half_side;
    case ADEM_REGION_BOX:
    default:
      if (what) *what = "half its smallest side";
      return half_side;
  }
}

bool adem_insert_region_holds(const adem_region *r, adem_vec3 x, double radius) {
  switch (r->kind) {
    case ADEM_REGION_BOX:
      return x.x - radius >= r->lo.x && x.y - radius >= r->lo.y && x.z - radius >= r->lo.z &&
             x.x + radius <= r->hi.x && x.y + radius <= r->hi.y && x.z + radius <= r->hi.z;
    case ADEM_REGION_CYLINDER: {
      adem_vec3 d = v3_sub(x, r->start);
      double s = v3_dot(d, r->axis);
      if (s < radius || s > r->length - radius) return false;
      double a = v3_dot(d, r->e1), b = v3_dot(d, r->e2), room = r->radius - radius;
      return room >= 0.0 && a * a + b * b <= room * room;
    }
    case ADEM_REGION_MESH:
      if (x.x - radius < r->lo.x || x.y - radius < r->lo.y || x.z - radius < r->lo.z ||
          x.x + radius > r->hi.x || x.y + radius > r->hi.y || x.z + radius > r->hi.z)
        return false;
      return !mesh_near(r, x, radius) && mesh_inside(r, x);
  }
  return false;
}

bool adem_insert_region_sample(const adem_region *r, adem_rng *rng, double radius, adem_vec3 *x) {
  if (r->kind == ADEM_REGION_CYLINDER) {
    double u = adem_rng_uniform(rng), a = adem_rng_uniform(rng), b = adem_rng_uniform(rng);
    double room = r->radius - radius;
    double s = radius + u * (r->length - 2.0 * radius);
    a = (2.0 * a - 1.0) * room;
    b = (2.0 * b - 1.0) * room;
    *x = v3_add(v3_add(v3_axpy(r->start, s, r->axis), v3_scale(r->e1, a)), v3_scale(r->e2, b));
    return a * a + b * b <= room * room;
  }
  /* box, and a mesh's bounding box: whole sphere inside the box */
  adem_vec3 size = v3_sub(r->hi, r->lo);
  double ux = adem_rng_uniform(rng), uy = adem_rng_uniform(rng), uz = adem_rng_uniform(rng);
  *x = v3(r->lo.x + radius + ux * (size.x - 2.0 * radius),
          r->lo.y + radius + uy * (size.y - 2.0 * radius),
          r->lo.z + radius + uz * (size.z - 2.0 * radius));
  return true;
}

/* ---------------------------------------------------------------- sphere grid */

adem_status adem_insert_grid_init(adem_sphere_grid *g, adem_vec3 lo, adem_vec3 hi, double h,
                                  double reach, size_t expected) {
  memset(g, 0, sizeof *g);
  double ext[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
  double limit = 8.0 * (double)expected + 4096.0; /* cells: about one per sphere */
  if (!(h > 0.0)) h = fmax(fmax(ext[0], ext[1]), fmax(ext[2], 1e-300));
  double cells;
  for (;;) {
    cells = 1.0;
    for (int k = 0; k < 3; ++k) cells *= floor(fmax(ext[k], 0.0) / h) + 1.0;
    if (cells <= limit) break;
    h *= 1.5;
  }
  for (int k = 0; k < 3; ++k) g->dims[k] = (int)(floor(fmax(ext[k], 0.0) / h) + 1.0);
  g->lo = lo;
  g->h = h;
  g->inv_h = 1.0 / h;
  g->reach = reach;
  size_t ncells = (size_t)cells;
  g->head = malloc(ncells * sizeof *g->head);
  if (!g->head) return ADEM_ERR_NOMEM;
  for (size_t c = 0; c < ncells; ++c) g->head[c] = -1;
  return ADEM_OK;
}

void adem_insert_grid_free(adem_sphere_grid *g) {
  free(g->head);
  free(g->next);
  free(g->sphere);
  memset(g, 0, sizeof *g);
}

static int grid_coord(const adem_sphere_grid *g, double x, double lo, int k) {
  double c = floor((x - lo) * g->inv_h);
  if (!(c > 0)) return 0; /* also NaN */
  if (c >= g->dims[k]) return g->dims[k] - 1;
  return (int)c;
}

static void grid_cell(const adem_sphere_grid *g, adem_vec3 p, int c[3]) {
  c[0] = grid_coord(g, p.x, g->lo.x, 0);
  c[1] = grid_coord(g, p.y, g->lo.y, 1);
  c[2] = grid_coord(g, p.z, g->lo.z, 2);
}

static size_t grid_index(const adem_sphere_grid *g, const int c[3]) {
  return ((size_t)c[2] * (size_t)g->dims[1] + (size_t)c[1]) * (size_t)g->dims[0] + (size_t)c[0];
}

adem_status adem_insert_grid_add(adem_sphere_grid *g, const adem_vec3 *pos, const double *rad,
                                 size_t i) {
  double e = fmax(0.0, rad[i] + g->reach - g->h);
  int a[3], b[3];
  grid_cell(g, v3_sub(pos[i], v3(e, e, e)), a);
  grid_cell(g, v3_add(pos[i], v3(e, e, e)), b);
  for (int z = a[2]; z <= b[2]; ++z)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int x = a[0]; x <= b[0]; ++x) {
        if (g->n == g->cap) {
          size_t cap = g->cap ? 2 * g->cap : 1024;
          int64_t *next = realloc(g->next, cap * sizeof *next);
          if (next) g->next = next;
          size_t *sphere = realloc(g->sphere, cap * sizeof *sphere);
          if (sphere) g->sphere = sphere;
          if (!next || !sphere) return ADEM_ERR_NOMEM;
          g->cap = cap;
        }
        int c[3] = {x, y, z};
        size_t cell = grid_index(g, c);
        g->sphere[g->n] = i;
        g->next[g->n] = g->head[cell];
        g->head[cell] = (int64_t)g->n;
        g->n++;
      }
  return ADEM_OK;
}

/* The query's own cell first: that is where a rejected try usually finds its overlap. */
int64_t adem_insert_grid_overlap(const adem_sphere_grid *g, const adem_vec3 *pos,
                                 const double *rad, adem_vec3 p, double r) {
  static const int order[27][3] = {
      {0, 0, 0},   {-1, 0, 0},  {1, 0, 0},   {0, -1, 0},  {0, 1, 0},   {0, 0, -1},  {0, 0, 1},
      {-1, -1, 0}, {1, -1, 0},  {-1, 1, 0},  {1, 1, 0},   {-1, 0, -1}, {1, 0, -1},  {0, -1, -1},
      {0, 1, -1},  {-1, 0, 1},  {1, 0, 1},   {0, -1, 1},  {0, 1, 1},   {-1, -1, -1}, {1, -1, -1},
      {-1, 1, -1}, {1, 1, -1},  {-1, -1, 1}, {1, -1, 1},  {-1, 1, 1},  {1, 1, 1}};
  int c[3];
  grid_cell(g, p, c);
  for (int k = 0; k < 27; ++k) {
    int q[3] = {c[0] + order[k][0], c[1] + order[k][1], c[2] + order[k][2]};
    if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= g->dims[0] || q[1] >= g->dims[1] ||
        q[2] >= g->dims[2])
      continue;
    for (int64_t e = g->head[grid_index(g, q)]; e >= 0; e = g->next[e]) {
      size_t j = g->sphere[e];
      double s = r + rad[j];
      adem_vec3 d = v3_sub(p, pos[j]);
      if (d.x * d.x + d.y * d.y + d.z * d.z < s * s) return (int64_t)j;
    }
  }
  return -1;
}

/* ---------------------------------------------------------------- walls */

/* Touching a wall within round-off is not overlapping it (as for the initial-state check). */
#define WALL_TOLERANCE 1e-9

/* The active planes and the active mesh triangles whose box comes within reach of a box. A mesh
 * wall is a surface: a closed one may be a container as well as a solid, so only touching it
 * counts (a sphere may be placed inside a closed mesh wall). */
typedef struct wall_filter {
  const adem_world *w;
  uint32_t *tri;
  size_t ntri;
} wall_filter;

static adem_status walls_gather(wall_filter *f, const adem_world *w, adem_vec3 lo, adem_vec3 hi,
                                double reach) {
  memset(f, 0, sizeof *f);
  f->w = w;
  if (!w || w->walls.mesh.ntris == 0) return ADEM_OK;
  const adem_mesh *m = &w->walls.mesh;
  f->tri = malloc(m->ntris * sizeof *f->tri);
  if (!f->tri) return ADEM_ERR_NOMEM;
  for (size_t t = 0; t < m->ntris; ++t) {
    if (!adem_world_mesh_active(w, m->group[t])) continue;
    adem_vec3 a = m->vert[m->tri[t][0]], b = m->vert[m->tri[t][1]], c = m->vert[m->tri[t][2]];
    if (fmax(a.x, fmax(b.x, c.x)) < lo.x - reach || fmin(a.x, fmin(b.x, c.x)) > hi.x + reach ||
        fmax(a.y, fmax(b.y, c.y)) < lo.y - reach || fmin(a.y, fmin(b.y, c.y)) > hi.y + reach ||
        fmax(a.z, fmax(b.z, c.z)) < lo.z - reach || fmin(a.z, fmin(b.z, c.z)) > hi.z + reach)
      continue;
    f->tri[f->ntri++] = (uint32_t)t;
  }
  return ADEM_OK;
}

static bool walls_clear(const wall_filter *f, adem_vec3 x, double r) {
  const adem_world *w = f->w;
  if (!w) return true;
  double slack = r * (1.0 - WALL_TOLERANCE);
  for (int k = 0; k < w->walls.nplanes; ++k) {
    if (w->walls.planes[k].inactive) continue;
    const adem_plane_def *pl = &w->walls.planes[k].def;
    if (adem_wall_nearest(pl, x).gap < slack) return false; /* a plane: (x - p).n */
  }
  const adem_mesh *m = &w->walls.mesh;
  for (size_t e = 0; e < f->ntri; ++e) {
    adem_vec3 q;
    adem_triangle_feature feat;
    if (adem_triangle_distance2(m, f->tri[e], x, &q, &feat) < slack * slack) return false;
  }
  return true;
}

bool adem_insert_walls_clear(const adem_world *w, adem_vec3 x, double radius) {
  wall_filter f;
  bool ok = walls_gather(&f, w, x, x, radius) == ADEM_OK && walls_clear(&f, x, radius);
  free(f.tri);
  return ok;
}

/* ---------------------------------------------------------------- fills */

static int compare_descending(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x < y) - (x > y);
}

static double sphere_volume(double r) { return (4.0 / 3.0) * ADEM_PI * r * r * r; }

/* Appends r to a growing array. */
static adem_status push_radius(double **a, size_t *n, size_t *cap, double r) {
  if (*n == *cap) {
    size_t c = *cap ? 2 * *cap : 1024;
    double *b = realloc(*a, c * sizeof *b);
    if (!b) return ADEM_ERR_NOMEM;
    *a = b;
    *cap = c;
  }
  (*a)[(*n)++] = r;
  return ADEM_OK;
}

/* Places the radii (largest first) in the region; old spheres near it are obstacles. The placed
 * spheres are appended to pos/rad after the old ones copied there. Returns ADEM_ERR_NOMEM or OK;
 * *placed and *attempts say how it went. keep[k] (if not NULL) marks the radii placed. */
typedef struct placer {
  const adem_region *region;
  const adem_world *walls;
  uint64_t max_attempts; /* in all (per_particle false) or per particle */
  bool per_particle;
} placer;

static adem_status place(const placer *pl, adem_rng *rng, const double *radii, size_t count,
                         const adem_vec3 *old_pos, const double *old_rad, size_t nold,
                         adem_vec3 **pos_out, double **rad_out, bool *keep, size_t *placed,
                         uint64_t *attempts_out) {
  const adem_region *reg = pl->region;
  adem_vec3 lo = reg->lo, hi = reg->hi, size = v3_sub(hi, lo);
  double rnew = count ? radii[0] : 0.0;
  double h =
      fmax(2.0 * rnew, adem_dmath_cbrt(size.x * size.y * size.z / (double)(count ? count : 1)));
  /* Old spheres that reach the region's box, then the new ones, in one index space. */
  size_t near = 0;
  for (size_t i = 0; i < nold; ++i) {
    adem_vec3 p = old_pos[i];
    double e = old_rad[i] + rnew;
    near += p.x > lo.x - e && p.y > lo.y - e && p.z > lo.z - e && p.x < hi.x + e &&
            p.y < hi.y + e && p.z < hi.z + e;
  }
  adem_vec3 *pos = malloc((near + count + 1) * sizeof *pos);
  double *rad = malloc((near + count + 1) * sizeof *rad);
  adem_sphere_grid g;
  memset(&g, 0, sizeof g);
  wall_filter wf;
  memset(&wf, 0, sizeof wf);
  adem_status st = ADEM_OK;
  if (!pos || !rad ||
      adem_insert_grid_init(&g, v3_sub(lo, v3(h, h, h)), v3_add(hi, v3(h, h, h)), h, rnew,
                            near + count) ||
      walls_gather(&wf, pl->walls, lo, hi, rnew)) {
    st = ADEM_ERR_NOMEM;
    goto done;
  }
  size_t n = 0;
  for (size_t i = 0; i < nold && !st; ++i) {
    adem_vec3 p = old_pos[i];
    double e = old_rad[i] + rnew;
    if (!(p.x > lo.x - e && p.y > lo.y - e && p.z > lo.z - e && p.x < hi.x + e &&
          p.y < hi.y + e && p.z < hi.z + e))
      continue;
    pos[n] = p;
    rad[n] = old_rad[i];
    if (adem_insert_grid_add(&g, pos, rad, n)) st = ADEM_ERR_NOMEM;
    ++n;
  }
  size_t first = n;
  uint64_t attempts = 0;
  bool box = reg->kind == ADEM_REGION_BOX; /* a box sample is inside by construction */
  for (size_t k = 0; k < count && !st; ++k) {
    double r = radii[k];
    if (keep) keep[k] = false;
    uint64_t budget = pl->per_particle ? attempts + pl->max_attempts : pl->max_attempts;
    if (attempts >= budget) break;
    while (attempts < budget) {
      ++attempts;
      adem_vec3 p;
      if (!adem_insert_region_sample(reg, rng, r, &p)) continue;
      if (adem_insert_grid_overlap(&g, pos, rad, p, r) >= 0) continue;
      if (!box && !adem_insert_region_holds(reg, p, r)) continue;
      if (!walls_clear(&wf, p, r)) continue;
      pos[n] = p;
      rad[n] = r;
      if (adem_insert_grid_add(&g, pos, rad, n)) st = ADEM_ERR_NOMEM;
      ++n;
      if (keep) keep[k] = true;
      break;
    }
  }
  *placed = n - first;
  *attempts_out = attempts;
  if (!st) {
    memmove(pos, pos + first, (n - first) * sizeof *pos);
    memmove(rad, rad + first, (n - first) * sizeof *rad);
    *pos_out = pos;
    *rad_out = rad;
    pos = NULL;
    rad = NULL;
  }
done:
  adem_insert_grid_free(&g);
  free(wf.tri);
  free(pos);
  free(rad);
  return st;
}

adem_status adem_insert_fill(const adem_fill_def *def, adem_rng *rng, const adem_vec3 *old_pos,
                             const double *old_rad, size_t nold, adem_fill_result *out,
                             adem_error *err) {
  memset(out, 0, sizeof *out);
  double *radii = NULL;
  size_t n = 0, cap = 0;
  adem_status st = ADEM_OK;
  if (def->count > 0) {
    if ((double)def->count > ADEM_INSERT_MAX_SPHERES)
      return adem_error_set(err, ADEM_ERR_INPUT, "%llu spheres is more than %.0g in one fill",
                            (unsigned long long)def->count, ADEM_INSERT_MAX_SPHERES);
    cap = (size_t)def->count;
    radii = malloc(cap * sizeof *radii);
    if (!radii) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %zu radii", cap);
    for (size_t k = 0; k < cap && !st; ++k) st = adem_insert_draw_radius(def->dist, rng, &radii[k], err);
    n = st ? 0 : cap;
  } else {
    /* Keep a sphere while the volume so far plus half its own stays within the target. */
    double target = def->solid_fraction * def->region->volume, volume = 0.0;
    for (;;) {
      double r;
      if ((st = adem_insert_draw_radius(def->dist, rng, &r, err))) break;
      double v = sphere_volume(r);
      if (volume + 0.5 * v > target) break;
      if ((double)n >= ADEM_INSERT_MAX_SPHERES) {
        st = adem_error_set(err, ADEM_ERR_INPUT,
                            "the solid fraction takes more than %.0g spheres in one fill",
                            ADEM_INSERT_MAX_SPHERES);
        break;
      }
      if (push_radius(&radii, &n, &cap, r)) {
        st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for radii");
        break;
      }
      volume += v;
    }
  }
  if (st) {
    free(radii);
    return st;
  }
  /* Largest first: the big spheres find room while the region is empty, the small fill gaps. */
  if (n > 1) qsort(radii, n, sizeof *radii, compare_descending); /* none: radii may be NULL */
  uint64_t attempts = def->max_attempts;
  if (attempts == 0) attempts = (uint64_t)n * 100 > 1000000 ? (uint64_t)n * 100 : 1000000;
  placer pl = {def->region, def->walls, attempts, false};
  out->wanted = n;
  st = place(&pl, rng, radii, n, old_pos, old_rad, nold, &out->pos, &out->radius, NULL, &out->n,
             &out->attempts);
  free(radii);
  if (st) {
    adem_insert_fill_result_free(out);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory while placing spheres");
  }
  for (size_t k = 0; k < out->n; ++k) out->volume += sphere_volume(out->radius[k]);
  return ADEM_OK;
}

void adem_insert_fill_result_free(adem_fill_result *res) {
  free(res->pos);
  free(res->radius);
  memset(res, 0, sizeof *res);
}

/* ---------------------------------------------------------------- pours */

adem_status adem_pours_add(adem_pours **ps, adem_pour_def *def, double density, adem_error *err) {
  if (!*ps) {
    *ps = calloc(1, sizeof **ps);
    if (!*ps) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  adem_pours *s = *ps;
  adem_pour *p = realloc(s->p, (size_t)(s->n + 1) * sizeof *p);
  if (!p) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  s->p = p;
  adem_pour *q = &p[s->n++];
  memset(q, 0, sizeof *q);
  q->def = *def;
  q->density = density;
  q->rng = adem_rng_seed(def->seed);
  memset(&def->region, 0, sizeof def->region); /* moved */
  memset(&def->dist, 0, sizeof def->dist);
  return ADEM_OK;
}

void adem_pours_free(adem_pours *ps) {
  if (!ps) return;
  for (int k = 0; k < ps->n; ++k) {
    adem_insert_region_free(&ps->p[k].def.region);
    adem_insert_dist_free(&ps->p[k].def.dist);
  }
  free(ps->p);
  free(ps);
}

double adem_pour_total(const adem_pour *p) {
  double window = p->def.end - p->def.start;
  return p->def.rate > 0.0 ? (double)llround(p->def.rate * window) : p->def.mass_rate * window;
}

/* Batch schedule on step counts: batch j at step s_a + j k, for j < nbatches; it brings the total
 * to the fraction min(1, (j + 1) k / (s_b - s_a)) of the pour. */
typedef struct pour_steps {
  uint64_t s_a, s_b, k, nbatches;
} pour_steps;

static pour_steps steps_of(const adem_pour *p, double dt) {
  pour_steps s;
  s.s_a = (uint64_t)llround(p->def.start / dt);
  s.s_b = (uint64_t)llround(p->def.end / dt);
  if (s.s_b < s.s_a) s.s_b = s.s_a;
  double k = round(p->def.interval / dt);
  s.k = k < 1.0 ? 1 : (uint64_t)k;
  uint64_t span = s.s_b - s.s_a;
  s.nbatches = span == 0 ? 1 : (span + s.k - 1) / s.k;
  return s;
}

uint64_t adem_pours_next_step(const adem_pours *ps, double dt, uint64_t step) {
  uint64_t next = UINT64_MAX;
  for (int i = 0; ps && i < ps->n; ++i) {
    const adem_pour *p = &ps->p[i];
    pour_steps s = steps_of(p, dt);
    uint64_t j = p->next_batch;
    if (j >= s.nbatches) continue;
    if (s.s_a + j * s.k <= step) j = step < s.s_a ? 0 : (step - s.s_a) / s.k + 1;
    if (j < s.nbatches && s.s_a + j * s.k < next) next = s.s_a + j * s.k;
  }
  return next;
}

/* Mass of a sphere, computed as the world computes it. */
static double pour_mass(const adem_pour *p, double r) {
  return p->density * (4.0 / 3.0) * ADEM_PI * r * r * r;
}

/* One batch: radii for the batch, placed among the world's particles and walls. */
static adem_status pour_batch(adem_pour *p, adem_world *w, const pour_steps *s, adem_error *err) {
  uint64_t j = p->next_batch;
  p->density = w->mat.m[p->def.material].def.density; /* a stage may have changed it */
  uint64_t span = s->s_b - s->s_a;
  double frac = span == 0 ? 1.0 : fmin(1.0, (double)((j + 1) * s->k) / (double)span);
  if (j + 1 >= s->nbatches) frac = 1.0;
  double *radii = NULL;
  size_t n = 0, cap = 0;
  adem_status st = ADEM_OK;
  if (p->def.rate > 0.0) {
    double target = j + 1 >= s->nbatches ? adem_pour_total(p) : (double)llround(adem_pour_total(p) * frac);
    double need = target - (double)p->inserted;
    for (double k = 0; k < need && !st; ++k) {
      double r;
      if ((st = adem_insert_draw_radius(&p->def.dist, &p->rng, &r, err))) break;
      if (push_radius(&radii, &n, &cap, r)) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    }
  } else {
    double target = adem_pour_total(p) * frac, planned = 0.0;
    while (!st) {
      double r;
      if ((st = adem_insert_draw_radius(&p->def.dist, &p->rng, &r, err))) break;
      double m = pour_mass(p, r);
      if (p->mass + planned + 0.5 * m > target) break;
      if ((double)n >= ADEM_INSERT_MAX_SPHERES) break;
      if (push_radius(&radii, &n, &cap, r)) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      planned += m;
    }
  }
  if (st) {
    char why[ADEM_MSG_MAX];
    snprintf(why, sizeof why, "%s", err ? err->message : "");
    free(radii);
    return adem_error_set(err, st, "pour `%s`: %s", p->def.name, why);
  }
  if (n > 1) qsort(radii, n, sizeof *radii, compare_descending); /* none: radii may be NULL */
  adem_vec3 *pos = NULL;
  double *rad = NULL;
  size_t placed = 0;
  uint64_t attempts = 0;
  bool *keep = malloc((n + 1) * sizeof *keep);
  placer pl = {&p->def.region, w, p->def.max_attempts, true};
  if (!keep) st = ADEM_ERR_NOMEM;
  if (!st)
    st = place(&pl, &p->rng, radii, n, w->p.pos, w->p.radius, w->p.n, &pos, &rad, keep, &placed,
               &attempts);
  if (st) {
    free(radii);
    free(keep);
    return adem_error_set(err, ADEM_ERR_NOMEM, "pour `%s`: out of memory", p->def.name);
  }
  for (size_t k = 0; k < placed && !st; ++k) {
    adem_particle_def d = adem_default_particle_def();
    d.position = pos[k];
    d.radius = rad[k];
    d.velocity = p->def.velocity;
    d.angular_velocity = p->def.angular_velocity;
    d.material = p->def.material;
    d.group = p->def.group;
    st = adem_world_add_particle(w, &d, NULL, err);
    if (!st) p->mass += pour_mass(p, rad[k]);
  }
  p->inserted += placed;
  if (placed < n) p->short_batches++;
  bool last = j + 1 >= s->nbatches;
  if (!st && last && placed < n) {
    if (p->def.rate > 0.0)
      adem_log(ADEM_LOG_WARN,
               "pour `%s`: inserted %llu of %.0f particles by t = %g s: the region had no room for "
               "the rest within max_attempts (%llu per particle); %d of %llu batches fell short",
               p->def.name, (unsigned long long)p->inserted, adem_pour_total(p), w->time,
               (unsigned long long)p->def.max_attempts, p->short_batches,
               (unsigned long long)s->nbatches);
    else
      adem_log(ADEM_LOG_WARN,
               "pour `%s`: inserted %.6g of %.6g kg (%llu particles) by t = %g s: the region had "
               "no room for the rest within max_attempts (%llu per particle); %d of %llu batches "
               "fell short",
               p->def.name, p->mass, adem_pour_total(p), (unsigned long long)p->inserted, w->time,
               (unsigned long long)p->def.max_attempts, p->short_batches,
               (unsigned long long)s->nbatches);
  }
  free(radii);
  free(keep);
  free(pos);
  free(rad);
  return st;
}

adem_status adem_pours_run(adem_pours *ps, adem_world *w, adem_error *err) {
  if (!ps || ps->n == 0) return ADEM_OK;
  bool prepared = w->prepared;
  size_t first = w->p.n;
  adem_status st = ADEM_OK;
  for (int i = 0; i < ps->n && !st; ++i) {
    adem_pour *p = &ps->p[i];
    pour_steps s = steps_of(p, w->dt);
    while (!st && p->next_batch < s.nbatches && s.s_a + p->next_batch * s.k <= w->step) {
      st = pour_batch(p, w, &s, err);
      p->next_batch++;
    }
  }
  if (st || w->p.n == first || !prepared) return st;
  return adem_world_admit_particles(w, first, err);
}

unsigned char *adem_pours_pack(const adem_pours *ps, size_t *len) {
  int n = ps ? ps->n : 0;
  size_t bytes = 8 + (size_t)n * 8 * 8;
  unsigned char *b = malloc(bytes);
  if (!b) return NULL;
  uint64_t v = (uint64_t)n;
  memcpy(b, &v, 8);
  for (int k = 0; k < n; ++k) {
    const adem_pour *p = &ps->p[k];
    uint64_t rec[8] = {p->rng.s[0], p->rng.s[1], p->rng.s[2], p->rng.s[3], p->inserted, 0,
                       p->next_batch, (uint64_t)p->short_batches};
    memcpy(&rec[5], &p->mass, 8);
    memcpy(b + 8 + (size_t)k * 64, rec, 64);
  }
  *len = bytes;
  return b;
}

adem_status adem_pours_unpack(adem_pours *ps, const unsigned char *buf, size_t len,
                              adem_error *err) {
  uint64_t n = 0;
  if (len >= 8) memcpy(&n, buf, 8);
  int have = ps ? ps->n : 0;
  if (len < 8 || n != (uint64_t)have || len != 8 + n * 64)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "its pour state does not match the pours of its own case text");
  for (int k = 0; k < have; ++k) {
    adem_pour *p = &ps->p[k];
    uint64_t rec[8];
    memcpy(rec, buf + 8 + (size_t)k * 64, 64);
    for (int i = 0; i < 4; ++i) p->rng.s[i] = rec[i];
    p->inserted = rec[4];
    memcpy(&p->mass, &rec[5], 8);
    p->next_batch = rec[6];
    p->short_batches = (int)rec[7];
  }
  return ADEM_OK;
}
