/* Coarse-grained fields (adem/fields.h): kernels, the grid, particle and contact deposits.
 *
 * Normalisation. Every kernel is normalised on the grid itself: a particle's weights over the
 * nodes it reaches sum, times the cell volume, to exactly one (rounding aside), and so do the
 * weights of each point of a contact's branch line. The grid integral of the density is then the
 * particles' mass and that of the contact stress the sum of f (x) l over the contacts, whatever
 * the kernel's width against the cell (Goldhirsch 2010 eq. 2: int phi = 1). A kernel the grid's
 * edge cuts keeps its whole weight on the nodes inside; the default grid of adem_fields_run
 * reaches a cut-off beyond every centre, so that nothing is cut.
 *
 * Contacts. Weinhart et al. (2012) eq. 9: the contact stress is sum f_ij (x) r_ij psi_ij, psi_ij
 * the line integral of phi from r_i to r_j (r_ij = r_i - r_j), whose divergence is
 * f_ij (phi(r - r_j) - phi(r - r_i)): the contact forces' density, so that the stress balances
 * the momentum. With the compressive-positive sign used here it is + f (x) l. The line integral
 * is an n-point Gauss-Legendre sum along the branch, n = ceil(2 |l| / w) + 1 (at most 32), each
 * point's kernel normalised on the grid. */
#include "adem/fields.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CG_PI 3.14159265358979323846

enum {
  /* per-node particle accumulators */
  Q_RHO = 0,
  Q_NU = 1,
  Q_J = 2,
  Q_MVV = 5, /* 6: xx yy zz xy xz yz */
  Q_Z = 11,
  Q_CNT = 12,
  Q_FAB = 13, /* 6 */
  Q_N = 19,
  /* contact stress: 9 per node, in its own array */
  GL_MAX = 32
};

struct adem_fields {
  adem_fields_options o;
  size_t n[3], nodes;
  double origin[3], h;
  double vol;      /* a node's cell volume, an averaged axis counting its whole length */
  double csupport; /* the kernel's reach along an axis from its centre, m */
  double *acc;     /* nodes x Q_N */
  double *cst;     /* nodes x 9 */
  size_t frames;
  /* scratch: a stencil's weights over a box of nodes, and a line's */
  double *w, *wl;
  size_t wcap, wlcap;
  double *g[3]; /* a Gaussian's 1-D weights per axis */
  size_t gcap;
  double gl_x[GL_MAX + 1][GL_MAX], gl_w[GL_MAX + 1][GL_MAX]; /* Gauss-Legendre on [0, 1] */
};

static const struct {
  const char *name;
  int ncomp;
} field_def[ADEM_CG_COUNT_] = {
    {"density", 1}, {"solid_fraction", 1}, {"momentum", 3}, {"velocity", 3}, {"kinetic_stress", 9}, {"contact_stress", 9}, {"stress", 9}, {"pressure", 1}, {"coordination", 1}, {"fabric", 9}, {"temperature", 1}};

int adem_cg_field_components(adem_cg_field f) {
  return f >= 0 && f < ADEM_CG_COUNT_ ? field_def[f].ncomp : 0;
}
const char *adem_cg_field_name(adem_cg_field f) {
  return f >= 0 && f < ADEM_CG_COUNT_ ? field_def[f].name : "";
}

adem_fields_options adem_fields_default_options(void) {
  adem_fields_options o;
  memset(&o, 0, sizeof o);
  o.kernel = ADEM_KERNEL_GAUSSIAN;
  o.width = 0.0;
  o.cutoff = 3.0;
  o.cell = 0.0;
  return o;
}

/* Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n from the Chebyshev guesses). */
static void gauss_legendre(int n, double *x, double *w) {
  for (int i = 0; i < n; ++i) {
    double z = cos(CG_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p1 = z, p0 = 1.0;
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      double dz = p1 / dp;
      z -= dz;
      if (fabs(dz) < 1e-16) break;
    }
    x[i] = 0.5 * (1.0 - z);
    w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
  }
  /* the weights sum to one exactly up to rounding; make them sum to one as summed */
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += w[i];
  for (int i = 0; i < n; ++i) w[i] /= s;
}

/* The kernel's reach from its centre along an axis. */
static double support(const adem_fields_options *o) {
  return o->kernel == ADEM_KERNEL_LUCY ? sqrt(12.0) * o->width : o->cutoff * o->width;
}

adem_status adem_fields_create(const adem_fields_options *opt, adem_fields **out, adem_error *err) {
  *out = NULL;
  const adem_fields_options *o = opt;
  if (o->kernel != ADEM_KERNEL_GAUSSIAN && o->kernel != ADEM_KERNEL_LUCY)
    return adem_error_set(err, ADEM_ERR_INPUT, "unknown kernel %d", (int)o->kernel);
  if (!(o->width > 0.0 && isfinite(o->width)))
    return adem_error_set(err, ADEM_ERR_INPUT, "kernel width %g m: must be > 0", o->width);
  if (o->kernel == ADEM_KERNEL_GAUSSIAN && !(o->cutoff >= 1.0 && o->cutoff <= 10.0))
    return adem_error_set(err, ADEM_ERR_INPUT, "Gaussian cut-off %g widths: must be in [1, 10]", o->cutoff);
  if (!(o->cell > 0.0 && isfinite(o->cell)))
    return adem_error_set(err, ADEM_ERR_INPUT, "cell size %g m: must be > 0", o->cell);
  int navg = 0;
  size_t n[3], nodes = 1;
  for (int a = 0; a < 3; ++a) {
    if (!(isfinite(o->lo[a]) && isfinite(o->hi[a]) && o->lo[a] < o->hi[a]))
      return adem_error_set(err, ADEM_ERR_INPUT, "grid extent along %c: %g .. %g (needs lo < hi)", 'x' + a,
                            o->lo[a], o->hi[a]);
    navg += o->average[a] != 0;
    double c = o->average[a] ? 1.0 : ceil((o->hi[a] - o->lo[a]) / o->cell - 1e-9);
    if (c < 1.0) c = 1.0;
    if (c > (double)ADEM_FIELDS_MAX_NODES)
      return adem_error_set(err, ADEM_ERR_INPUT, "grid of more than %zu nodes", ADEM_FIELDS_MAX_NODES);
    n[a] = (size_t)c;
    nodes *= n[a];
    if (nodes > ADEM_FIELDS_MAX_NODES)
      return adem_error_set(err, ADEM_ERR_INPUT, "grid of more than %zu nodes (cell %g m): use a coarser "
                                                 "cell, a smaller box or average over an axis",
                            ADEM_FIELDS_MAX_NODES, o->cell);
  }
  if (navg > 2) return adem_error_set(err, ADEM_ERR_INPUT, "averaging over all three axes leaves no grid");
  adem_fields *f = calloc(1, sizeof *f);
  if (!f) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  f->o = *o;
  f->h = o->cell;
  f->vol = 1.0;
  for (int a = 0; a < 3; ++a) {
    f->n[a] = n[a];
    f->origin[a] = o->average[a] ? 0.5 * (o->lo[a] + o->hi[a]) : o->lo[a] + 0.5 * o->cell;
    f->vol *= o->average[a] ? o->hi[a] - o->lo[a] : o->cell;
  }
  f->nodes = nodes;
  f->csupport = support(o);
  f->acc = calloc(nodes * Q_N, sizeof *f->acc);
  f->cst = calloc(nodes * 9, sizeof *f->cst);
  if (!f->acc || !f->cst) {
    adem_fields_free(f);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for a grid of %zu nodes", nodes);
  }
  for (int k = 1; k <= GL_MAX; ++k) gauss_legendre(k, f->gl_x[k], f->gl_w[k]);
  *out = f;
  return ADEM_OK;
}

void adem_fields_free(adem_fields *f) {
  if (!f) return;
  free(f->acc);
  free(f->cst);
  free(f->w);
  free(f->wl);
  for (int a = 0; a < 3; ++a) free(f->g[a]);
  free(f);
}

size_t adem_fields_frames(const adem_fields *f) { return f->frames; }

void adem_fields_grid(const adem_fields *f, size_t n[3], double origin[3], double *cell) {
  for (int a = 0; a < 3; ++a) {
    n[a] = f->n[a];
    origin[a] = f->origin[a];
  }
  *cell = f->h;
}

/* ---------------------------------------------------------------- stencils */

/* A box of nodes k0[a] .. k0[a] + m[a] - 1 (m[a] = 1 along an averaged axis) and its weights
 * (x fastest), normalised to sum to one. */
typedef struct stencil {
  long k0[3];
  size_t m[3], size;
} stencil;

static int grow(double **p, size_t *cap, size_t want) {
  if (want <= *cap) return 1;
  size_t c = *cap ? *cap : 256;
  while (c < want) c *= 2;
  double *q = realloc(*p, c * sizeof *q);
  if (!q) return 0;
  *p = q;
  *cap = c;
  return 1;
}

/* Lucy's kernel (1 + 3q)(1 - q)^3 in 3-D, and its marginals, up to a constant factor (the
 * weights are normalised on the grid). d2: squared distance over the axes kept, c: support. */
static double lucy3(double q) { return q < 1.0 ? (1.0 + 3.0 * q) * (1.0 - q) * (1.0 - q) * (1.0 - q) : 0.0; }
static double lucy_marginal(double d2, double c, int navg) {
  double q2 = d2 / (c * c);
  if (q2 >= 1.0) return 0.0;
  if (navg == 0) return lucy3(sqrt(q2));
  if (navg == 2) { /* 2 pi int_|z|^c phi(r) r dr, in units of c: int_q^1 (1+3s)(1-s)^3 s ds */
    double q = sqrt(q2);
    /* (1+3s)(1-s)^3 s = s - 6 s^3 + 8 s^4 - 3 s^5 */
    double F1 = 0.5 - 1.5 + 1.6 - 0.5;
    double Fq = 0.5 * q * q - 1.5 * q * q * q * q + 1.6 * q * q * q * q * q - 0.5 * q * q * q * q * q * q;
    return F1 - Fq;
  }
  /* one axis averaged: int phi(sqrt(rho^2 + x^2)) dx over |x| < sqrt(1 - rho^2), 16-point
   * Gauss-Legendre on the half (the integrand is smooth inside) */
  static const double x8[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
                               0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                               0.9445750230732326, 0.9894009349916499};
  static const double w8[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
                               0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
                               0.0622535239386479, 0.0271524594117541};
  double L = sqrt(1.0 - q2), s = 0.0;
  for (int k = 0; k < 8; ++k)
    for (int sg = -1; sg <= 1; sg += 2) {
      double x = 0.5 * L * (1.0 + sg * x8[k]);
      s += w8[k] * lucy3(sqrt(q2 + x * x));
    }
  return s * 0.5 * L;
}

/* The stencil of a kernel centred at y, its weights added (times scale) into buf at the place
 * of the box `into` (which must contain it); with into NULL the box is the stencil's own, buf is
 * overwritten. Returns 0 when no node is reached (the centre is outside the grid by more than
 * the kernel's reach) or memory runs out (*nomem). */
static int stencil_of(adem_fields *f, const double y[3], stencil *s, int *nomem) {
  double h = f->h, c = f->csupport;
  s->size = 1;
  for (int a = 0; a < 3; ++a) {
    if (f->o.average[a]) {
      s->k0[a] = 0;
      s->m[a] = 1;
      continue;
    }
    double u = (y[a] - f->origin[a]) / h; /* node coordinate of the centre */
    double r = c / h;
    long lo = (long)ceil(u - r), hi = (long)floor(u + r);
    if (lo < 0) lo = 0;
    if (hi > (long)f->n[a] - 1) hi = (long)f->n[a] - 1;
    if (hi < lo) return 0;
    s->k0[a] = lo;
    s->m[a] = (size_t)(hi - lo + 1);
    s->size *= s->m[a];
  }
  if (!grow(&f->w, &f->wcap, s->size)) {
    *nomem = 1;
    return 0;
  }
  double sum = 0.0;
  if (f->o.kernel == ADEM_KERNEL_GAUSSIAN) {
    size_t gm = s->m[0] > s->m[1] ? s->m[0] : s->m[1];
    if (s->m[2] > gm) gm = s->m[2];
    if (gm > f->gcap) {
      for (int a = 0; a < 3; ++a) {
        double *q = realloc(f->g[a], gm * sizeof *q);
        if (!q) {
          *nomem = 1;
          return 0;
        }
        f->g[a] = q;
      }
      f->gcap = gm;
    }
    double inv2w2 = 0.5 / (f->o.width * f->o.width);
    for (int a = 0; a < 3; ++a) {
      if (f->o.average[a]) {
        f->g[a][0] = 1.0;
        continue;
      }
      double ga = 0.0;
      for (size_t k = 0; k < s->m[a]; ++k) {
        double d = f->origin[a] + (double)(s->k0[a] + (long)k) * h - y[a];
        double v = fabs(d) <= c ? exp(-d * d * inv2w2) : 0.0;
        f->g[a][k] = v;
        ga += v;
      }
      if (!(ga > 0.0)) return 0;
      for (size_t k = 0; k < s->m[a]; ++k) f->g[a][k] /= ga; /* each axis sums to one */
    }
    size_t q = 0;
    for (size_t k = 0; k < s->m[2]; ++k)
      for (size_t j = 0; j < s->m[1]; ++j) {
        double gyz = f->g[1][j] * f->g[2][k];
        for (size_t i = 0; i < s->m[0]; ++i) f->w[q++] = f->g[0][i] * gyz;
      }
    return 1;
  }
  int navg = f->o.average[0] + f->o.average[1] + f->o.average[2];
  size_t q = 0;
  for (size_t k = 0; k < s->m[2]; ++k)
    for (size_t j = 0; j < s->m[1]; ++j)
      for (size_t i = 0; i < s->m[0]; ++i) {
        size_t idx[3] = {i, j, k};
        double d2 = 0.0;
        for (int a = 0; a < 3; ++a) {
          if (f->o.average[a]) continue;
          double d = f->origin[a] + (double)(s->k0[a] + (long)idx[a]) * h - y[a];
          d2 += d * d;
        }
        double v = lucy_marginal(d2, c, navg);
        f->w[q++] = v;
        sum += v;
      }
  if (!(sum > 0.0)) return 0;
  for (size_t t = 0; t < s->size; ++t) f->w[t] /= sum;
  return 1;
}

static size_t node_index(const adem_fields *f, long i, long j, long k) {
  return ((size_t)k * f->n[1] + (size_t)j) * f->n[0] + (size_t)i;
}

/* ---------------------------------------------------------------- frames */

typedef struct id_at {
  int64_t id;
  size_t i;
} id_at;

static int id_cmp(const void *a, const void *b) {
  const id_at *p = a, *q = b;
  return p->id < q->id ? -1 : p->id > q->id;
}

static long find_id(const id_at *map, size_t n, int64_t id) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (map[mid].id < id) lo = mid + 1;
    else hi = mid;
  }
  return lo < n && map[lo].id == id ? (long)map[lo].i : -1;
}

adem_status adem_fields_add(adem_fields *f, const adem_fields_particles *p,
                            const adem_fields_contacts *c, adem_error *err) {
  size_t np = p->n, nc = c ? c->n : 0;
  id_at *map = malloc((np ? np : 1) * sizeof *map);
  double *pc = calloc(np ? np : 1, 7 * sizeof *pc); /* per particle: contacts, then n n (6) */
  if (!map || !pc) {
    free(map);
    free(pc);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %zu particles", np);
  }
  for (size_t i = 0; i < np; ++i) {
    if (!(p->mass[i] > 0.0 && isfinite(p->mass[i]))) {
      free(map);
      free(pc);
      return adem_error_set(err, ADEM_ERR_INPUT, "particle %zu: mass %g is not > 0", i, p->mass[i]);
    }
    map[i] = (id_at){p->id[i], i};
  }
  qsort(map, np, sizeof *map, id_cmp);
  adem_status st = ADEM_OK;
  /* each contact's line, unit normal for the fabric and the counts of its particles */
  for (size_t k = 0; k < nc && !st; ++k) {
    const double *a = c->p0 + 3 * k, *b = c->p1 + 3 * k;
    double l[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double len = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    double nn[6] = {0};
    if (len > 0.0) {
      double u[3] = {l[0] / len, l[1] / len, l[2] / len};
      nn[0] = u[0] * u[0], nn[1] = u[1] * u[1], nn[2] = u[2] * u[2];
      nn[3] = u[0] * u[1], nn[4] = u[0] * u[2], nn[5] = u[1] * u[2];
    }
    long ia = find_id(map, np, c->id_a[k]);
    long ib = c->kind[k] == 0 ? find_id(map, np, c->id_b[k]) : -2;
    if (ia < 0 || ib == -1) {
      st = adem_error_set(err, ADEM_ERR_INPUT, "contact %zu names particle %lld, which is not in the frame",
                          k, (long long)(ia < 0 ? c->id_a[k] : c->id_b[k]));
      break;
    }
    long who[2] = {ia, ib};
    for (int s = 0; s < 2; ++s) {
      if (who[s] < 0) continue;
      double *q = pc + 7 * (size_t)who[s];
      q[0] += 1.0;
      for (int t = 0; t < 6; ++t) q[1 + t] += nn[t];
    }
  }
  /* particles */
  int nomem = 0;
  double inv_vol = 1.0 / f->vol;
  for (size_t i = 0; i < np && !st; ++i) {
    stencil s;
    const double *x = p->pos + 3 * i;
    if (!stencil_of(f, x, &s, &nomem)) {
      if (nomem) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      continue; /* outside the grid's reach */
    }
    double m = p->mass[i], r = p->radius[i], V = 4.0 / 3.0 * CG_PI * r * r * r;
    double v[3] = {0, 0, 0};
    if (p->vel) v[0] = p->vel[3 * i], v[1] = p->vel[3 * i + 1], v[2] = p->vel[3 * i + 2];
    const double *q = pc + 7 * i;
    double val[Q_N] = {m, V, m * v[0], m * v[1], m * v[2],
                       m * v[0] * v[0], m * v[1] * v[1], m * v[2] * v[2],
                       m * v[0] * v[1], m * v[0] * v[2], m * v[1] * v[2],
                       q[0], 1.0, V * q[1], V * q[2], V * q[3], V * q[4], V * q[5], V * q[6]};
    size_t t = 0;
    for (size_t kk = 0; kk < s.m[2]; ++kk)
      for (size_t jj = 0; jj < s.m[1]; ++jj) {
        size_t node = node_index(f, s.k0[0], s.k0[1] + (long)jj, s.k0[2] + (long)kk);
        for (size_t ii = 0; ii < s.m[0]; ++ii, ++t) {
          double w = f->w[t] * inv_vol;
          if (w == 0.0) continue;
          double *acc = f->acc + (node + ii) * Q_N;
          for (int u = 0; u < Q_N; ++u) acc[u] += w * val[u];
        }
      }
  }
  /* contacts: f (x) l along the branch, l = p0 - p1 */
  for (size_t k = 0; k < nc && !st; ++k) {
    const double *a = c->p0 + 3 * k, *b = c->p1 + 3 * k, *fc = c->force + 3 * k;
    double l[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    double T[9];
    for (int u = 0; u < 3; ++u)
      for (int v = 0; v < 3; ++v) T[3 * u + v] = fc[u] * l[v];
    /* the line's length over the axes kept */
    double len2 = 0.0;
    for (int u = 0; u < 3; ++u)
      if (!f->o.average[u]) len2 += l[u] * l[u];
    int nq = (int)ceil(2.0 * sqrt(len2) / f->o.width) + 1;
    if (nq > GL_MAX) nq = GL_MAX;
    /* the union box of the points' stencils: the line's box widened by the reach */
    long U0[3];
    size_t Um[3], Usize = 1;
    int reach = 1;
    for (int u = 0; u < 3; ++u) {
      if (f->o.average[u]) {
        U0[u] = 0;
        Um[u] = 1;
        continue;
      }
      double lo = fmin(a[u], b[u]) - f->csupport, hi = fmax(a[u], b[u]) + f->csupport;
      long k0 = (long)ceil((lo - f->origin[u]) / f->h) - 1, k1 = (long)floor((hi - f->origin[u]) / f->h) + 1;
      if (k0 < 0) k0 = 0;
      if (k1 > (long)f->n[u] - 1) k1 = (long)f->n[u] - 1;
      if (k1 < k0) reach = 0;
      U0[u] = k0;
      Um[u] = reach ? (size_t)(k1 - k0 + 1) : 1;
      Usize *= Um[u];
    }
    if (!reach) continue;
    if (!grow(&f->wl, &f->wlcap, Usize)) {
      st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      break;
    }
    memset(f->wl, 0, Usize * sizeof *f->wl);
    int any = 0;
    for (int g = 0; g < nq; ++g) {
      double sg = f->gl_x[nq][g], wg = f->gl_w[nq][g];
      double y[3] = {a[0] - sg * l[0], a[1] - sg * l[1], a[2] - sg * l[2]}; /* p0 -> p1 */
      stencil s;
      if (!stencil_of(f, y, &s, &nomem)) {
        if (nomem) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
        continue;
      }
      any = 1;
      size_t t = 0;
      for (size_t kk = 0; kk < s.m[2]; ++kk)
        for (size_t jj = 0; jj < s.m[1]; ++jj) {
          size_t row = ((size_t)(s.k0[2] - U0[2] + (long)kk) * Um[1] +
                        (size_t)(s.k0[1] - U0[1] + (long)jj)) *
                           Um[0] +
                       (size_t)(s.k0[0] - U0[0]);
          double *dst = f->wl + row;
          for (size_t ii = 0; ii < s.m[0]; ++ii, ++t) dst[ii] += wg * f->w[t];
        }
    }
    if (!any) continue;
    size_t t = 0;
    for (size_t kk = 0; kk < Um[2]; ++kk)
      for (size_t jj = 0; jj < Um[1]; ++jj) {
        size_t node = node_index(f, U0[0], U0[1] + (long)jj, U0[2] + (long)kk);
        for (size_t ii = 0; ii < Um[0]; ++ii, ++t) {
          double w = f->wl[t] * inv_vol;
          if (w == 0.0) continue;
          double *acc = f->cst + (node + ii) * 9;
          for (int u = 0; u < 9; ++u) acc[u] += w * T[u];
        }
      }
  }
  free(map);
  free(pc);
  if (!st) f->frames++;
  return st;
}

/* ---------------------------------------------------------------- reading the fields */

/* The fields at one node, averaged over the frames. */
static void node_fields(const adem_fields *f, size_t node, adem_cg_field field, double *out) {
  double inv = f->frames ? 1.0 / (double)f->frames : 0.0;
  const double *A = f->acc + node * Q_N, *C = f->cst + node * 9;
  double rho = A[Q_RHO] * inv;
  double V[3];
  for (int u = 0; u < 3; ++u) V[u] = rho > 0.0 ? A[Q_J + u] * inv / rho : 0.0;
  static const int sym[9] = {0, 3, 4, 3, 1, 5, 4, 5, 2}; /* xx xy xz yx yy yz zx zy zz -> 6 */
  double K[9];
  for (int u = 0; u < 3; ++u)
    for (int v = 0; v < 3; ++v) K[3 * u + v] = A[Q_MVV + sym[3 * u + v]] * inv - rho * V[u] * V[v];
  switch (field) {
    case ADEM_CG_DENSITY: out[0] = rho; break;
    case ADEM_CG_SOLID_FRACTION: out[0] = A[Q_NU] * inv; break;
    case ADEM_CG_MOMENTUM:
      for (int u = 0; u < 3; ++u) out[u] = A[Q_J + u] * inv;
      break;
    case ADEM_CG_VELOCITY:
      for (int u = 0; u < 3; ++u) out[u] = V[u];
      break;
    case ADEM_CG_KINETIC_STRESS:
      for (int u = 0; u < 9; ++u) out[u] = K[u];
      break;
    case ADEM_CG_CONTACT_STRESS:
      for (int u = 0; u < 9; ++u) out[u] = C[u] * inv;
      break;
    case ADEM_CG_STRESS:
      for (int u = 0; u < 9; ++u) out[u] = K[u] + C[u] * inv;
      break;
    case ADEM_CG_PRESSURE: out[0] = (K[0] + K[4] + K[8] + (C[0] + C[4] + C[8]) * inv) / 3.0; break;
    case ADEM_CG_COORDINATION: out[0] = A[Q_CNT] > 0.0 ? A[Q_Z] / A[Q_CNT] : 0.0; break;
    case ADEM_CG_FABRIC:
      for (int u = 0; u < 9; ++u) out[u] = A[Q_FAB + sym[u]] * inv;
      break;
    case ADEM_CG_TEMPERATURE: out[0] = rho > 0.0 ? (K[0] + K[4] + K[8]) / (3.0 * rho) : 0.0; break;
    default: break;
  }
}

adem_status adem_fields_get(const adem_fields *f, adem_cg_field field, double *out, size_t capacity,
                            adem_error *err) {
  if (field < 0 || field >= ADEM_CG_COUNT_) return adem_error_set(err, ADEM_ERR_INPUT, "no field %d", (int)field);
  if (!f->frames) return adem_error_set(err, ADEM_ERR_INPUT, "no frame was added");
  size_t nc = (size_t)field_def[field].ncomp;
  if (capacity < f->nodes * nc)
    return adem_error_set(err, ADEM_ERR_INPUT, "%s needs %zu doubles, %zu given", field_def[field].name,
                          f->nodes * nc, capacity);
  for (size_t k = 0; k < f->nodes; ++k) node_fields(f, k, field, out + k * nc);
  return ADEM_OK;
}

adem_status adem_fields_integral(const adem_fields *f, adem_cg_field field, double *out,
                                 adem_error *err) {
  if (field < 0 || field >= ADEM_CG_COUNT_) return adem_error_set(err, ADEM_ERR_INPUT, "no field %d", (int)field);
  if (!f->frames) return adem_error_set(err, ADEM_ERR_INPUT, "no frame was added");
  int nc = field_def[field].ncomp;
  double v[9];
  for (int u = 0; u < nc; ++u) out[u] = 0.0;
  for (size_t k = 0; k < f->nodes; ++k) {
    node_fields(f, k, field, v);
    for (int u = 0; u < nc; ++u) out[u] += v[u] * f->vol;
  }
  return ADEM_OK;
}

/* ---------------------------------------------------------------- files */

static const char *const comp9[9] = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
static const char *const comp3[3] = {"x", "y", "z"};
static const char *const unit_of[ADEM_CG_COUNT_] = {"_kg_m3", "", "_kg_m2s", "_m_s", "_Pa",
                                                    "_Pa", "_Pa", "_Pa", "", "", "_m2_s2"};

static const char *byte_order(void) {
  const uint16_t one = 1;
  unsigned char b;
  memcpy(&b, &one, 1);
  return b == 1 ? "LittleEndian" : "BigEndian";
}

#include "adem/files.h"

adem_status adem_fields_write_vti(const adem_fields *f, const char *path, adem_error *err) {
  if (!f->frames) return adem_error_set(err, ADEM_ERR_INPUT, "no frame was added");
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  FILE *fp = af.f;
  double sp[3];
  for (int a = 0; a < 3; ++a) sp[a] = f->o.average[a] ? f->o.hi[a] - f->o.lo[a] : f->h;
  fprintf(fp,
          "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"%s\" header_type=\"UInt64\">\n"
          "  <ImageData WholeExtent=\"0 %zu 0 %zu 0 %zu\" Origin=\"%.17g %.17g %.17g\" "
          "Spacing=\"%.17g %.17g %.17g\">\n"
          "    <FieldData>\n"
          "      <DataArray type=\"Int64\" Name=\"frames\" NumberOfTuples=\"1\" format=\"ascii\">%zu"
          "</DataArray>\n"
          "    </FieldData>\n"
          "    <Piece Extent=\"0 %zu 0 %zu 0 %zu\">\n"
          "      <PointData Scalars=\"density\" Vectors=\"velocity\" Tensors=\"stress\">\n",
          byte_order(), f->n[0] - 1, f->n[1] - 1, f->n[2] - 1, f->origin[0], f->origin[1],
          f->origin[2], sp[0], sp[1], sp[2], f->frames, f->n[0] - 1, f->n[1] - 1, f->n[2] - 1);
  uint64_t off = 0;
  for (int q = 0; q < ADEM_CG_COUNT_; ++q) {
    fprintf(fp, "        <DataArray type=\"Float64\" Name=\"%s\" ", field_def[q].name);
    if (field_def[q].ncomp > 1) fprintf(fp, "NumberOfComponents=\"%d\" ", field_def[q].ncomp);
    fprintf(fp, "format=\"appended\" offset=\"%llu\"/>\n", (unsigned long long)off);
    off += 8 + (uint64_t)f->nodes * (uint64_t)field_def[q].ncomp * 8;
  }
  fprintf(fp, "      </PointData>\n    </Piece>\n  </ImageData>\n"
              "  <AppendedData encoding=\"raw\">\n   _");
  int ok = 1;
  double buf[9 * 512];
  for (int q = 0; q < ADEM_CG_COUNT_ && ok; ++q) {
    size_t nc = (size_t)field_def[q].ncomp;
    uint64_t nb = (uint64_t)f->nodes * nc * 8;
    ok = fwrite(&nb, 8, 1, fp) == 1;
    for (size_t k0 = 0; k0 < f->nodes && ok; k0 += 512) {
      size_t m = f->nodes - k0 < 512 ? f->nodes - k0 : 512;
      for (size_t k = 0; k < m; ++k) node_fields(f, k0 + k, (adem_cg_field)q, buf + k * nc);
      ok = fwrite(buf, 8, m * nc, fp) == m * nc;
    }
  }
  fprintf(fp, "\n  </AppendedData>\n</VTKFile>\n");
  if (!ok || ferror(fp)) {
    adem_file_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s", path);
  }
  return adem_file_commit(&af, err);
}

adem_status adem_fields_write_csv(const adem_fields *f, const char *path, adem_error *err) {
  if (!f->frames) return adem_error_set(err, ADEM_ERR_INPUT, "no frame was added");
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  FILE *fp = af.f;
  int first = 1;
  for (int a = 0; a < 3; ++a)
    if (!f->o.average[a]) {
      fprintf(fp, "%s%c_m", first ? "" : ",", 'x' + a);
      first = 0;
    }
  for (int q = 0; q < ADEM_CG_COUNT_; ++q) {
    int nc = field_def[q].ncomp;
    for (int u = 0; u < nc; ++u)
      fprintf(fp, ",%s%s%s%s", field_def[q].name, nc > 1 ? "_" : "",
              nc == 9 ? comp9[u] : nc == 3 ? comp3[u]
                                           : "",
              unit_of[q]);
  }
  fputc('\n', fp);
  double v[9];
  for (size_t k = 0; k < f->nodes; ++k) {
    size_t idx[3] = {k % f->n[0], (k / f->n[0]) % f->n[1], k / (f->n[0] * f->n[1])};
    first = 1;
    for (int a = 0; a < 3; ++a)
      if (!f->o.average[a]) {
        fprintf(fp, "%s%.10g", first ? "" : ",", f->origin[a] + (double)idx[a] * f->h);
        first = 0;
      }
    for (int q = 0; q < ADEM_CG_COUNT_; ++q) {
      node_fields(f, k, (adem_cg_field)q, v);
      for (int u = 0; u < field_def[q].ncomp; ++u) fprintf(fp, ",%.10g", v[u]);
    }
    fputc('\n', fp);
  }
  if (ferror(fp)) {
    adem_file_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s", path);
  }
  return adem_file_commit(&af, err);
}
