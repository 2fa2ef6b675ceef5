/* Angle of repose of a pile of spheres: surface-particle fit and slice equivalent radii. See
 * pile.h for the definitions. */
#include "adem/pile.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

static adem_status fail(adem_error *err, adem_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static adem_status fail(adem_error *err, adem_status st, const char *fmt, ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    err->status = st;
  }
  return st;
}

adem_pile_options adem_pile_default_options(void) {
  adem_pile_options o;
  memset(&o, 0, sizeof o);
  o.floor_z = 0.0;
  o.axis_given = 0;
  o.band_lo = 0.25;
  o.band_hi = 0.75;
  o.cell_arc = 2.0;
  o.bin_width = 0.0;
  o.rays = 720;
  o.slice_step = 0.0;
  o.slice_radius = ADEM_PILE_MEAN_RADIUS;
  o.zmax = 0.0;
  o.rmax = 0.0;
  o.ring_lo = 0.2;
  o.ring_hi = 0.8;
  o.lab_sectors = 8;
  o.skirt_level = 0.0;
  return o;
}

void adem_pile_result_free(adem_pile_result *res) {
  if (!res) return;
  free(res->surface_pts);
  free(res->slice_pts);
  free(res->ring_pts);
  memset(res, 0, sizeof *res);
}

/* Line through the points with used = 1. FIT_ORTHO: orthogonal least squares (the principal
 * axis of the points, minimising their distances to the line) of z against rho, for the surface
 * particles, which scatter across the slope: ordinary least squares of z on rho would take the
 * scatter in rho as signal and flatten the slope by about var(scatter) / (var(along) cos^2)
 * (1 to 2 degrees on a ballast pile). FIT_RHO_ON_Z: ordinary least squares of rho on z, for the
 * slices, whose heights are exact. FIT_Z_ON_RHO: ordinary least squares of z on rho, for the ring
 * tops, whose radii are the rings' (exact). r2 is the squared correlation of rho and z. Centred
 * sums, so that offsets of metres cost no digits. */
enum { FIT_ORTHO = 0,
       FIT_RHO_ON_Z = 1,
       FIT_Z_ON_RHO = 2 };
static adem_pile_fit fit_line(const adem_pile_point *p, size_t n, int mode) {
  const int swap = mode == FIT_RHO_ON_Z;
  adem_pile_fit f = {0, 0.0, 0.0, 0.0};
  double sx = 0.0, sy = 0.0;
  size_t m = 0;
  for (size_t i = 0; i < n; ++i)
    if (p[i].used) {
      sx += swap ? p[i].z : p[i].rho;
      sy += swap ? p[i].rho : p[i].z;
      ++m;
    }
  f.n = m;
  if (m < 2) return f;
  double mx = sx / (double)m, my = sy / (double)m, sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (size_t i = 0; i < n; ++i)
    if (p[i].used) {
      double dx = (swap ? p[i].z : p[i].rho) - mx, dy = (swap ? p[i].rho : p[i].z) - my;
      sxx += dx * dx;
      sxy += dx * dy;
      syy += dy * dy;
    }
  if (sxx <= 0.0) return f;
  if (mode != FIT_ORTHO || sxy == 0.0) {
    f.slope = sxy / sxx;
  } else {
    /* direction of the largest eigenvector of [[sxx, sxy], [sxy, syy]] */
    double dd = 0.5 * (syy - sxx);
    f.slope = (dd + sqrt(dd * dd + sxy * sxy)) / sxy;
  }
  f.intercept = my - f.slope * mx;
  f.r2 = syy > 0.0 ? (sxy * sxy) / (sxx * syy) : 1.0;
  return f;
}

/* A particle of the pile, relative to the axis. */
typedef struct pp {
  double dx, dy, z, r; /* z: centre height above the floor */
  double rho;
  uint64_t key; /* radial bin * 2^12 + sector, method (a) */
} pp;

static int cmp_key(const void *a, const void *b) {
  const pp *x = a, *y = b;
  if (x->key != y->key) return x->key < y->key ? -1 : 1;
  /* highest first within a bin; ties by place, so that the order is total */
  if (x->z != y->z) return x->z > y->z ? -1 : 1;
  if (x->dx != y->dx) return x->dx < y->dx ? -1 : 1;
  return (x->dy > y->dy) - (x->dy < y->dy);
}

static adem_status check_options(const adem_pile_options *o, adem_error *err) {
  if (!isfinite(o->floor_z) || !(o->band_lo >= 0.0 && o->band_lo < o->band_hi && o->band_hi <= 1.0))
    return fail(err, ADEM_ERR_INPUT,
                "pile: the fit band [%g, %g] of the height must satisfy 0 <= lo < hi <= 1",
                o->band_lo, o->band_hi);
  if (!(o->cell_arc >= 0.5 && o->cell_arc <= 100.0) || o->rays < 8 || o->rays > 1000000)
    return fail(err, ADEM_ERR_INPUT, "pile: cell_arc %g must be in 0.5..100 and rays %d in 8..1e6",
                o->cell_arc, o->rays);
  if (!isfinite(o->bin_width) || !isfinite(o->slice_step) || !isfinite(o->zmax) ||
      !isfinite(o->rmax) ||
      (o->slice_radius != ADEM_PILE_MEAN_RADIUS && o->slice_radius != ADEM_PILE_AREA_RADIUS) ||
      (o->axis_given && !(isfinite(o->axis_x) && isfinite(o->axis_y))))
    return fail(err, ADEM_ERR_INPUT, "pile: an option is not a finite number");
  if (!(o->ring_lo >= 0.0 && o->ring_lo < o->ring_hi && o->ring_hi <= 1.0) ||
      !(o->lab_sectors >= 1 && o->lab_sectors <= 360) || !isfinite(o->skirt_level))
    return fail(err, ADEM_ERR_INPUT,
                "pile: the ring-top band [%g, %g] must satisfy 0 <= lo < hi <= 1, lab_sectors %d "
                "must be in 1..360 and the skirt level finite",
                o->ring_lo, o->ring_hi,
                o->lab_sectors);
  return ADEM_OK;
}

/* Equivalent radius of the footprint of the plane at height zs (above the floor). The boundary
 * is, along each of nr rays from the axis, the farthest edge of a cross-section the ray crosses;
 * the radius is the boundary's mean distance from the axis (ADEM_PILE_MEAN_RADIUS) or
 * sqrt(A / pi) of the area inside it (ADEM_PILE_AREA_RADIUS). The two agree for a circle; for a
 * boundary drawn through particles, rough on the scale of a diameter, sqrt(A / pi) =
 * sqrt(mean R^2) exceeds the mean by about var(R) / (2 R), which weighs more in the narrow upper
 * slices and steepens the fitted angle (by 0.2 to 0.45 degrees on the synthetic cones of
 * tests/unit/test_pile.c, 24 and 15 diameters wide; the mean radius: 0.03 to 0.2). reach[] is
 * scratch of nr doubles. */
static double slice_req(const pp *q, size_t n, double zs, int nr, adem_pile_slice_radius kind,
                        double *reach) {
  for (int j = 0; j < nr; ++j) reach[j] = 0.0;
  const double dphi = 2.0 * PI / nr;
  for (size_t i = 0; i < n; ++i) {
    double dz = q[i].z - zs;
    if (fabs(dz) >= q[i].r) continue;
    double a = sqrt(q[i].r * q[i].r - dz * dz); /* cross-section radius */
    double rho = q[i].rho;
    int j0, j1;
    if (rho <= a) { /* the section covers the axis: every ray crosses it */
      j0 = 0;
      j1 = nr - 1;
    } else {
      double phi = atan2(q[i].dy, q[i].dx), half = asin(a / rho);
      j0 = (int)floor((phi - half) / dphi) - 1;
      j1 = (int)ceil((phi + half) / dphi) + 1;
      if (j1 - j0 >= nr) {
        j0 = 0;
        j1 = nr - 1;
      }
    }
    for (int jj = j0; jj <= j1; ++jj) {
      int j = ((jj % nr) + nr) % nr;
      double c = cos(j * dphi), s = sin(j * dphi);
      double t = q[i].dx * c + q[i].dy * s;  /* along the ray */
      double e = -q[i].dx * s + q[i].dy * c; /* across it */
      if (fabs(e) >= a) continue;
      double far = t + sqrt(a * a - e * e);
      if (far > reach[j]) reach[j] = far;
    }
  }
  double sum = 0.0, sum2 = 0.0;
  for (int j = 0; j < nr; ++j) {
    sum += reach[j];
    sum2 += reach[j] * reach[j];
  }
  return kind == ADEM_PILE_AREA_RADIUS ? sqrt(sum2 / nr) : sum / nr; /* A = pi sum2 / nr */
}

/* Methods (c) and (d) of pile.h on the pile's particles q[0..m) (rings w wide). */
static adem_status ring_measures(const pp *q, size_t m, const adem_pile_options *o, double w,
                                 adem_pile_result *res, adem_error *err) {
  double dmin = INFINITY, dmax = 0.0, rho_max = 0.0;
  for (size_t i = 0; i < m; ++i) {
    if (2.0 * q[i].r < dmin) dmin = 2.0 * q[i].r;
    if (2.0 * q[i].r > dmax) dmax = 2.0 * q[i].r;
    if (q[i].rho > rho_max) rho_max = q[i].rho;
  }
  const double he = o->skirt_level > 0.0 ? o->skirt_level : 0.5 * (dmax + 1.8 * dmin);
  res->skirt_level = he;
  if (rho_max / w > 1e6)
    return fail(err, ADEM_ERR_INPUT, "pile: a sphere %g m from the axis is more than a million "
                                     "rings out: give rmax",
                rho_max);
  const size_t nring = (size_t)floor(rho_max / w) + 1;
  double *top = malloc(nring * sizeof *top);
  const int ns = o->lab_sectors;
  double *far = calloc((size_t)ns, sizeof *far);
  res->ring_pts = malloc(nring * sizeof *res->ring_pts);
  if (!top || !far || !res->ring_pts) {
    free(top);
    free(far);
    return fail(err, ADEM_ERR_NOMEM, "pile: out of memory");
  }
  for (size_t k = 0; k < nring; ++k) top[k] = -1.0; /* empty */
  for (size_t i = 0; i < m; ++i) {
    size_t k = (size_t)floor(q[i].rho / w);
    if (k >= nring) k = nring - 1;
    if (q[i].z + q[i].r > top[k]) top[k] = q[i].z + q[i].r;
  }
  size_t nb = 0; /* the continuous base: rings out to the first one whose top is below h_e */
  while (nb < nring && top[nb] >= he) ++nb;
  res->base_rings = nb;
  /* R_base: per sector the farthest base sphere whose top reaches h_e */
  for (size_t i = 0; i < m; ++i) {
    size_t k = (size_t)floor(q[i].rho / w);
    if (k >= nb || q[i].z + q[i].r < he) continue;
    double phi = atan2(q[i].dy, q[i].dx);
    int s = (int)floor((phi + PI) / (2.0 * PI) * ns);
    if (s < 0) s = 0;
    if (s >= ns) s = ns - 1;
    if (q[i].rho > far[s]) far[s] = q[i].rho;
  }
  double sum = 0.0, sum2 = 0.0;
  int got = 0;
  for (int s = 0; s < ns; ++s)
    if (far[s] > 0.0) {
      sum += far[s];
      sum2 += far[s] * far[s];
      ++got;
    }
  free(far);
  if (nb == 0 || 2 * got < ns) {
    /* no base two layers high around the axis in most directions (the spheres rolled away,
     * or a heap too flat): no laboratory angle (NaN); the other measures stand */
    res->lab_base_radius = res->lab_base_sd = NAN;
    res->angle_lab_deg = res->angle_lab_plain_deg = NAN;
  } else {
    res->lab_base_radius = sum / got;
    double var = got > 1 ? (sum2 - sum * sum / got) / (got - 1) : 0.0;
    res->lab_base_sd = var > 0.0 ? sqrt(var) : 0.0;
    res->angle_lab_deg = atan((res->height - he) / res->lab_base_radius) * 180.0 / PI;
    res->angle_lab_plain_deg = atan(res->height / res->lab_base_radius) * 180.0 / PI;
  }
  /* (d) the ring tops of the base inside the band */
  size_t np = 0;
  const double lo = o->ring_lo * res->height, hi = o->ring_hi * res->height;
  for (size_t k = 0; k < nring; ++k)
    if (top[k] >= 0.0)
      res->ring_pts[np++] = (adem_pile_point){(k + 0.5) * w, top[k],
                                              k < nb && top[k] >= lo && top[k] <= hi};
  res->n_ring_pts = np;
  free(top);
  res->ringtop = fit_line(res->ring_pts, np, FIT_Z_ON_RHO);
  /* too few rings in the band, or no descent: no line (NaN), the other measures stand */
  res->angle_ringtop_deg = res->ringtop.n >= 3 && res->ringtop.slope < 0.0
                               ? atan(-res->ringtop.slope) * 180.0 / PI
                               : NAN;
  return ADEM_OK;
}

adem_status adem_pile_measure(const adem_vec3 *pos, const double *radius, size_t n,
                              const adem_pile_options *opt, adem_pile_result *res,
                              adem_error *err) {
  memset(res, 0, sizeof *res);
  adem_pile_options o = opt ? *opt : adem_pile_default_options();
  adem_status st = check_options(&o, err);
  if (st) return st;
  if (n == 0 || !pos || !radius) return fail(err, ADEM_ERR_INPUT, "pile: no particles");
  for (size_t i = 0; i < n; ++i)
    if (!(isfinite(pos[i].x) && isfinite(pos[i].y) && isfinite(pos[i].z) && isfinite(radius[i]) &&
          radius[i] > 0.0))
      return fail(err, ADEM_ERR_INPUT,
                  "pile: particle %zu has a non-finite centre or a radius that is not > 0", i);

  pp *q = malloc(n * sizeof *q);
  if (!q) return fail(err, ADEM_ERR_NOMEM, "pile: out of memory for %zu particles", n);

  /* The pile: centres above the floor and below zmax; then the axis; then within rmax. */
  size_t m = 0;
  double vx = 0.0, vy = 0.0, vol = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double z = pos[i].z - o.floor_z;
    if (z < 0.0 || (o.zmax > 0.0 && z > o.zmax)) continue;
    double v = radius[i] * radius[i] * radius[i];
    vx += v * pos[i].x;
    vy += v * pos[i].y;
    vol += v;
    q[m++] = (pp){pos[i].x, pos[i].y, z, radius[i], 0.0, 0};
  }
  if (m == 0) {
    free(q);
    return fail(err, ADEM_ERR_INPUT, "pile: no particle centre between the floor (z = %g) and "
                                     "zmax",
                o.floor_z);
  }
  res->axis_x = o.axis_given ? o.axis_x : vx / vol;
  res->axis_y = o.axis_given ? o.axis_y : vy / vol;
  size_t k = 0;
  double top = 0.0, dsum = 0.0;
  for (size_t i = 0; i < m; ++i) {
    pp p = q[i];
    p.dx -= res->axis_x;
    p.dy -= res->axis_y;
    p.rho = sqrt(p.dx * p.dx + p.dy * p.dy);
    if (o.rmax > 0.0 && p.rho > o.rmax) continue;
    if (p.z + p.r > top) top = p.z + p.r;
    dsum += 2.0 * p.r;
    q[k++] = p;
  }
  m = k;
  if (m < 3) {
    free(q);
    return fail(err, ADEM_ERR_INPUT, "pile: %zu particles in the pile, at least 3 are needed", m);
  }
  res->n_pile = m;
  res->height = top;
  res->mean_diameter = dsum / (double)m;
  res->band_zmin = o.band_lo * top;
  res->band_zmax = o.band_hi * top;
  const double w = o.bin_width > 0.0 ? o.bin_width : res->mean_diameter;
  const double step = o.slice_step > 0.0 ? o.slice_step : 0.25 * res->mean_diameter;

  /* (a) The highest centre of each cell. Ring b (rho in [b w, (b+1) w)) is cut into
   * max(1, floor(2 pi (b + 1/2) / cell_arc)) sectors, so that every cell has about the same
   * area (cell_arc w^2): the highest of a cell's particles then sits at the same depth under the
   * surface in every ring. Cells that grow with the radius (a fixed number of sectors) would hold
   * more candidates far out, whose highest lies higher, and flatten the fitted slope; cells that
   * are too narrow near the axis would miss the surface. */
  for (size_t i = 0; i < m; ++i) {
    double b = floor(q[i].rho / w);
    if (b > (double)((UINT64_C(1) << 40) - 1)) b = (double)((UINT64_C(1) << 40) - 1);
    double ns_ring = floor(2.0 * PI * (b + 0.5) / o.cell_arc);
    if (ns_ring > 4095.0) ns_ring = 4095.0;
    int nsec = ns_ring < 1.0 ? 1 : (int)ns_ring;
    double phi = atan2(q[i].dy, q[i].dx); /* [-pi, pi] */
    int s = (int)floor((phi + PI) / (2.0 * PI) * nsec);
    if (s < 0) s = 0;
    if (s >= nsec) s = nsec - 1;
    q[i].key = ((uint64_t)b << 12) | (uint64_t)s;
  }
  qsort(q, m, sizeof *q, cmp_key);
  res->surface_pts = malloc(m * sizeof *res->surface_pts);
  if (!res->surface_pts) {
    free(q);
    adem_pile_result_free(res);
    return fail(err, ADEM_ERR_NOMEM, "pile: out of memory");
  }
  size_t ns = 0;
  for (size_t i = 0; i < m; ++i)
    if (i == 0 || q[i].key != q[i - 1].key)
      res->surface_pts[ns++] = (adem_pile_point){q[i].rho, q[i].z, 0};
  res->n_surface_pts = ns;
  adem_pile_point *sp = res->surface_pts;
  /* Pass 1: the points in the height band. Pass 2: the points whose projection on that line
   * falls between the line's points at the band's edges: a selection along the slope, which
   * leaves the scatter across it, the fit's noise, untouched (a selection on z would trim it
   * at the band's edges and bias the slope). */
  for (size_t i = 0; i < ns; ++i) sp[i].used = sp[i].z >= res->band_zmin && sp[i].z <= res->band_zmax;
  adem_pile_fit f1 = fit_line(sp, ns, FIT_ORTHO);
  if (f1.n < 3 || !(f1.slope < 0.0)) {
    free(q);
    size_t got = f1.n;
    adem_pile_result_free(res);
    return fail(err, ADEM_ERR_INPUT,
                "pile: %zu surface particles in the band and no descending slope: not a pile", got);
  }
  {
    double tl = 1.0 / sqrt(1.0 + f1.slope * f1.slope), tz = f1.slope * tl; /* along the line */
    double rho_in = (res->band_zmax - f1.intercept) / f1.slope;
    double rho_out = (res->band_zmin - f1.intercept) / f1.slope;
    double u_in = rho_in * tl + res->band_zmax * tz, u_out = rho_out * tl + res->band_zmin * tz;
    for (size_t i = 0; i < ns; ++i) {
      double u = sp[i].rho * tl + sp[i].z * tz;
      sp[i].used = u >= u_in && u <= u_out;
    }
  }
  res->surface = fit_line(sp, ns, FIT_ORTHO);
  if (res->surface.n < 3 || !(res->surface.slope < 0.0)) {
    free(q);
    adem_pile_result_free(res);
    return fail(err, ADEM_ERR_INPUT, "pile: the surface fit has no descending slope");
  }
  res->angle_surface_deg = atan(-res->surface.slope) * 180.0 / PI;

  /* (b) Slices every `step` from half a step above the floor to the top. */
  size_t nz = (size_t)floor(top / step);
  if (nz > 100000) nz = 100000;
  double *reach = malloc((size_t)o.rays * sizeof *reach);
  res->slice_pts = malloc((nz ? nz : 1) * sizeof *res->slice_pts);
  if (!reach || !res->slice_pts) {
    free(q);
    free(reach);
    adem_pile_result_free(res);
    return fail(err, ADEM_ERR_NOMEM, "pile: out of memory");
  }
  for (size_t j = 0; j < nz; ++j) {
    double zs = (j + 0.5) * step;
    double req = slice_req(q, m, zs, o.rays, o.slice_radius, reach);
    res->slice_pts[j] = (adem_pile_point){req, zs, zs >= res->band_zmin && zs <= res->band_zmax};
  }
  res->n_slice_pts = nz;
  res->footprint_radius = slice_req(q, m, 0.5 * res->mean_diameter, o.rays, o.slice_radius, reach);
  free(reach);
  st = ring_measures(q, m, &o, w, res, err);
  free(q);
  if (st) {
    adem_pile_result_free(res);
    return st;
  }
  res->angle_footprint_deg = atan(res->height / res->footprint_radius) * 180.0 / PI;
  res->slices = fit_line(res->slice_pts, nz, FIT_RHO_ON_Z);
  if (res->slices.n < 3 || !(res->slices.slope < 0.0)) {
    size_t got = res->slices.n;
    adem_pile_result_free(res);
    return fail(err, ADEM_ERR_INPUT,
                "pile: %zu slices in the band and their radii do not shrink upwards: not a pile",
                got);
  }
  res->angle_slices_deg = atan(-1.0 / res->slices.slope) * 180.0 / PI;
  res->base_radius = res->slices.intercept;
  return ADEM_OK;
}
