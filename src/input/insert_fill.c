/* Insertion: random non-overlapping fills of a region, on a grid of the spheres placed, clear of
 * the walls. */
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
      {0, 0, 0}, {-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}, {1, 1, 0}, {-1, 0, -1}, {1, 0, -1}, {0, -1, -1}, {0, 1, -1}, {-1, 0, 1}, {1, 0, 1}, {0, -1, 1}, {0, 1, 1}, {-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1}, {1, 1, 1}};
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

int adem_insert_compare_descending(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x < y) - (x > y);
}

static double sphere_volume(double r) { return (4.0 / 3.0) * ADEM_PI * r * r * r; }

adem_status adem_insert_push_radius(double **a, size_t *n, size_t *cap, double r) {
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

adem_status adem_insert_place(const adem_placer *pl, adem_rng *rng, const double *radii,
                              size_t count, const adem_vec3 *old_pos, const double *old_rad, size_t nold,
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
      if (adem_insert_push_radius(&radii, &n, &cap, r)) {
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
  if (n > 1) qsort(radii, n, sizeof *radii, adem_insert_compare_descending); /* none: radii may be NULL */
  uint64_t attempts = def->max_attempts;
  if (attempts == 0) attempts = (uint64_t)n * 100 > 1000000 ? (uint64_t)n * 100 : 1000000;
  adem_placer pl = {def->region, def->walls, attempts, false};
  out->wanted = n;
  st = adem_insert_place(&pl, rng, radii, n, old_pos, old_rad, nold, &out->pos, &out->radius,
                         NULL, &out->n, &out->attempts);
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
