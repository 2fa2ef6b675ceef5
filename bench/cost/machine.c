/* This machine's limits for the operations a particle-step is made of (docs/performance.md, "Cost
 * model"), one core: the clock (a chain of dependent integer adds, one per cycle), the throughput
 * of double divisions and square roots (eight independent chains, so latency is hidden), and the
 * memory bandwidth of a stream triad a[i] = b[i] + s c[i] over arrays far larger than the caches.
 * Each figure is the best of five repetitions. Build: cc -O2 -o machine bench/cost/machine.c -lm */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static volatile double sink;

static double clock_ghz(void) {
  long n = 1000000000L, x = 0;
  double t0 = now();
  for (long i = 0; i < n; ++i) __asm__ volatile("add $1, %0"
                                                : "+r"(x));
  double t = now() - t0;
  sink = (double)x;
  return (double)n / t * 1e-9;
}

/* ns per operation, 8 independent chains */
static double divisions(long n) {
  double a[8], d = 1.0000001;
  for (int k = 0; k < 8; ++k) a[k] = 1.0 + k;
  double t0 = now();
  for (long i = 0; i < n; ++i)
    for (int k = 0; k < 8; ++k) a[k] = a[k] / d;
  double t = now() - t0;
  sink = a[0] + a[7];
  return t / (8.0 * (double)n) * 1e9;
}

static double square_roots(long n) {
  double a[8];
  for (int k = 0; k < 8; ++k) a[k] = 2.0 + k;
  double t0 = now();
  for (long i = 0; i < n; ++i)
    for (int k = 0; k < 8; ++k) a[k] = sqrt(a[k]) + 1.0; /* stays near 2.6 */
  double t = now() - t0;
  sink = a[0] + a[7];
  return t / (8.0 * (double)n) * 1e9;
}

/* GB/s counting 24 bytes per element (two reads, one write) */
static double triad(size_t n) {
  double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
  if (!a || !b || !c) return 0.0;
  for (size_t i = 0; i < n; ++i) a[i] = 0.0, b[i] = 1.0, c[i] = 2.0;
  double t = 1e9;
  for (int pass = 0; pass < 3; ++pass) { /* the best pass: the arrays are in memory by then */
    double t0 = now();
    for (size_t i = 0; i < n; ++i) a[i] = b[i] + 3.0 * c[i];
    t = fmin(t, now() - t0);
  }
  sink = a[n / 2];
  free(a), free(b), free(c);
  return 24.0 * (double)n / t * 1e-9;
}

int main(void) {
  double ghz = 0.0, div = 1e9, sq = 1e9, bw = 0.0;
  for (int r = 0; r < 5; ++r) {
    ghz = fmax(ghz, clock_ghz());
    div = fmin(div, divisions(50000000L));
    sq = fmin(sq, square_roots(50000000L));
    bw = fmax(bw, triad(20000000));
  }
  printf("clock                %.2f GHz\n", ghz);
  printf("division (double)    %.2f ns = %.1f cycles each, independent\n", div, div * ghz);
  printf("square root (double) %.2f ns = %.1f cycles each, independent (an add included)\n", sq, sq * ghz);
  printf("memory, stream triad %.1f GB/s (one core, 480 MB of arrays)\n", bw);
  return 0;
}
