/* Speed of the coarse-grained fields (adem/fields.h, docs/fields.md): one frame of a synthetic
 * ballast-sized bed, 21,600 spheres of d 0.037-0.063 m (mean 0.05 m) on a jittered lattice of
 * 0.05 m in 0.6 x 4.5 x 1.0 m, with a contact between lattice neighbours whose spheres touch or
 * nearly (about 3 per sphere, as a packed bed) and one to the floor per sphere of the bottom
 * layer, on a 1 cm grid in 3-D. Prints the median of REPEAT runs of create + add for each width.
 *   bench_fields [REPEAT=5] [WIDTHS=0.5,1,2 (mean diameters)]
 * The real bed (cases/irazabal/ballast, 40 min of packing) has the same count, sizes and
 * about the same contacts per sphere; this one needs no run. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "adem/fields.h"

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}
/* the process's CPU time: on a shared machine the wall time counts the other jobs too */
static double cpu(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double rnd(uint64_t *s) {
  *s ^= *s >> 12;
  *s ^= *s << 25;
  *s ^= *s >> 27;
  return (double)((*s * 2685821657736338717ull) >> 11) * 0x1.0p-53;
}

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

int main(int argc, char **argv) {
  int repeat = argc > 1 ? atoi(argv[1]) : 5;
  if (repeat < 1) repeat = 1;
  const char *widths = argc > 2 ? argv[2] : "0.5,1,2";
  enum { NX = 12,
         NY = 90,
         NZ = 20 }; /* 21,600 spheres */
  const double a = 0.05;
  size_t n = (size_t)NX * NY * NZ;
  double *pos = malloc(3 * n * sizeof *pos), *vel = calloc(3 * n, sizeof *vel);
  double *mass = malloc(n * sizeof *mass), *rad = malloc(n * sizeof *rad);
  int64_t *id = malloc(n * sizeof *id);
  size_t cap = 4 * n;
  double *p0 = malloc(3 * cap * sizeof *p0), *p1 = malloc(3 * cap * sizeof *p1),
         *fc = malloc(3 * cap * sizeof *fc);
  int32_t *kind = malloc(cap * sizeof *kind);
  int64_t *ia = malloc(cap * sizeof *ia), *ib = malloc(cap * sizeof *ib);
  if (!pos || !vel || !mass || !rad || !id || !p0 || !p1 || !fc || !kind || !ia || !ib) return 1;
  uint64_t s = 2017;
  for (size_t k = 0; k < n; ++k) {
    size_t i = k % NX, j = (k / NX) % NY, l = k / (NX * NY);
    rad[k] = 0.0185 + 0.013 * rnd(&s);
    pos[3 * k] = a * (i + 0.5) + 0.004 * (rnd(&s) - 0.5);
    pos[3 * k + 1] = a * (j + 0.5) + 0.004 * (rnd(&s) - 0.5);
    pos[3 * k + 2] = rad[k] + a * l + 0.004 * (rnd(&s) - 0.5);
    mass[k] = 2700.0 * 4.0 / 3.0 * 3.14159265358979323846 * rad[k] * rad[k] * rad[k];
    id[k] = (int64_t)k;
  }
  size_t nc = 0;
  for (size_t k = 0; k < n; ++k) {
    size_t i = k % NX, j = (k / NX) % NY, l = k / (NX * NY);
    size_t nb[3] = {i + 1 < NX ? k + 1 : k, j + 1 < NY ? k + NX : k, l + 1 < NZ ? k + NX * NY : k};
    for (int q = 0; q < 3; ++q) {
      size_t m = nb[q];
      if (m == k) continue;
      double d[3], dd = 0.0;
      for (int u = 0; u < 3; ++u) d[u] = pos[3 * m + u] - pos[3 * k + u], dd += d[u] * d[u];
      if (sqrt(dd) > 1.01 * (rad[k] + rad[m])) continue; /* apart */
      for (int u = 0; u < 3; ++u) {
        p0[3 * nc + u] = pos[3 * k + u];
        p1[3 * nc + u] = pos[3 * m + u];
        fc[3 * nc + u] = -d[u] * 100.0 + (rnd(&s) - 0.5);
      }
      kind[nc] = 0, ia[nc] = (int64_t)k, ib[nc] = (int64_t)m;
      nc++;
    }
    if (l == 0) { /* the floor */
      for (int u = 0; u < 3; ++u) p0[3 * nc + u] = p1[3 * nc + u] = pos[3 * k + u], fc[3 * nc + u] = 0.0;
      p1[3 * nc + 2] = 0.0;
      fc[3 * nc + 2] = 50.0;
      kind[nc] = 1, ia[nc] = (int64_t)k, ib[nc] = 0;
      nc++;
    }
  }
  printf("synthetic bed: %zu spheres, %zu contacts (%.2f per sphere), 1 cm grid\n", n, nc,
         2.0 * (double)nc / (double)n);
  adem_fields_particles P = {n, pos, vel, mass, rad, id};
  adem_fields_contacts C = {nc, p0, p1, fc, kind, ia, ib};
  double *t = malloc((size_t)repeat * sizeof *t), *tc = malloc((size_t)repeat * sizeof *tc);
  for (const char *w = widths; w && *w;) {
    double wd = strtod(w, NULL);
    adem_fields_options o = adem_fields_default_options();
    o.width = wd * 0.05;
    o.cell = 0.01;
    double reach = o.cutoff * o.width + o.cell;
    double lo[3] = {-reach, -reach, -reach},
           hi[3] = {NX * a + reach, NY * a + reach, NZ * a + 0.05 + reach};
    memcpy(o.lo, lo, sizeof lo);
    memcpy(o.hi, hi, sizeof hi);
    size_t nodes = 0;
    for (int r = 0; r < repeat; ++r) {
      adem_fields *f = NULL;
      adem_error err;
      double t0 = now(), c0 = cpu();
      if (adem_fields_create(&o, &f, &err) || adem_fields_add(f, &P, &C, &err)) {
        fprintf(stderr, "bench_fields: %s\n", err.message);
        return 1;
      }
      t[r] = now() - t0;
      tc[r] = cpu() - c0;
      size_t nn[3];
      double org[3], h;
      adem_fields_grid(f, nn, org, &h);
      nodes = nn[0] * nn[1] * nn[2];
      adem_fields_free(f);
    }
    qsort(t, (size_t)repeat, sizeof *t, cmp);
    qsort(tc, (size_t)repeat, sizeof *tc, cmp);
    printf("width %.2g d (%.3g m, Gaussian cut off at 3 w): %zu nodes, median of %d: wall %.3f s "
           "(min %.3f, max %.3f), CPU %.3f s (min %.3f, max %.3f)\n",
           wd, o.width, nodes, repeat,
           t[repeat / 2], t[0], t[repeat - 1], tc[repeat / 2], tc[0], tc[repeat - 1]);
    fflush(stdout);
    w = strchr(w, ',');
    if (w) ++w;
  }
  free(t);
  free(tc);
  free(pos), free(vel), free(mass), free(rad), free(id);
  free(p0), free(p1), free(fc), free(kind), free(ia), free(ib);
  return 0;
}
