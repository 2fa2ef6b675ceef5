/* Insertion: regions (box, cylinder, closed mesh), their tests and sampling, and the named regions
 * whose particles the output counts. */
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
  c[0] = a < 0 ? 0 : a >= r->cols[0] ? r->cols[0] - 1
                                     : (int)a;
  c[1] = b < 0 ? 0 : b >= r->cols[1] ? r->cols[1] - 1
                                     : (int)b;
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
    adem_vec3 u = i == 0 ? v3(1, 0, 0) : i == 1 ? v3(0, 1, 0)
                                                : v3(0, 0, 1);
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
  int n = nd < 1.0 ? 1 : nd > 256.0 ? 256
                                    : (int)nd;
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
