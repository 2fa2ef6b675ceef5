/* Benchmark: a settled dense bed of 5 mm glass-like spheres (E = 1e7 Pa, friction 0.5, gravity),
 * timed over a fixed number of steps after settling, for 1 and 2 threads.
 *   bench_bed [N ...]          default: 10000 100000
 *   ADEM_BENCH_STEPS=1000      steps timed per thread count
 * Prints particle-steps per second, contacts per particle and peak memory per particle. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>

#include "adem/adem.h"
#include "adem/vec3.h"

/* A uniform number in [0, 1) (splitmix64): the bed's jitter, the same on every platform. */
static double uniform(uint64_t *s) {
  uint64_t z = (*s += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Spheres on a loose jittered lattice in a square box, dropped and settled. */
static adem_world *settled_bed(int n, double *settle_seconds) {
  adem_world *w = adem_world_create();
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "glass");
  m.density = 2500.0;
  m.young = 1e7;
  m.poisson = 0.25;
  m.restitution = 0.3;
  m.friction = 0.5;
  adem_error err;
  int glass = 0;
  adem_world_add_material(w, &m, &glass, &err);
  double r = 2.5e-3, h = 2.2 * r;
  int side = (int)ceil(sqrt(n / 20.0)); /* about 20 layers high */
  double L = side * h;
  adem_world_add_box(w, "box", v3(0, 0, 0), v3(L, L, 100.0 * L), glass, NULL, &err);
  uint64_t rng = 1;
  for (int k = 0; k < n; ++k) {
    int ix = k % side, iy = (k / side) % side, iz = k / (side * side);
    adem_particle_def p = adem_default_particle_def();
    p.material = glass;
    p.radius = r;
    p.position = v3((ix + 0.5) * h + 0.1 * r * (uniform(&rng) - 0.5),
                    (iy + 0.5) * h + 0.1 * r * (uniform(&rng) - 0.5), (iz + 0.5) * h);
    adem_world_add_particle(w, &p, NULL, &err);
  }
  adem_step_estimate est = adem_world_estimate_step(w, 1.0);
  adem_world_set_dt(w, est.dt);
  double t0 = now();
  if (adem_world_prepare(w, &err) != ADEM_OK) {
    fprintf(stderr, "prepare: %s\n", err.message);
    exit(1);
  }
  /* fall through a few diameters and come to rest: 0.25 s of simulated time */
  if (adem_world_step(w, (uint64_t)(0.25 / est.dt), &err) != ADEM_OK) {
    fprintf(stderr, "settle: %s\n", err.message);
    exit(1);
  }
  *settle_seconds = now() - t0;
  return w;
}

int main(int argc, char **argv) {
  int sizes[8] = {10000, 100000};
  int nsizes = 2;
  if (argc > 1) {
    nsizes = 0;
    for (int k = 1; k < argc && nsizes < 8; ++k) sizes[nsizes++] = atoi(argv[k]);
  }
  const char *s = getenv("ADEM_BENCH_STEPS");
  uint64_t steps = s ? (uint64_t)atoll(s) : 1000;
  printf("# adem %s bench_bed: settled bed, 5 mm spheres, E = 1e7 Pa, mu = 0.5, %llu steps timed\n",
         ADEM_VERSION_STRING, (unsigned long long)steps);
  printf("%9s %8s %14s %16s %12s %14s\n", "N", "threads", "settle_s", "particle-steps/s",
         "contacts/p", "peak_B/particle");
  for (int k = 0; k < nsizes; ++k) {
    double settle;
    adem_world *w = settled_bed(sizes[k], &settle);
    for (int threads = 1; threads <= 2; ++threads) {
      adem_world_set_threads(w, threads);
      adem_error err;
      double t0 = now();
      if (adem_world_step(w, steps, &err) != ADEM_OK) {
        fprintf(stderr, "step: %s\n", err.message);
        return 1;
      }
      double elapsed = now() - t0;
      adem_diagnostics d = adem_world_diagnostics(w);
      struct rusage ru;
      getrusage(RUSAGE_SELF, &ru);
      double n = (double)adem_world_particle_count(w);
      printf("%9d %8d %14.1f %16.3e %12.2f %14.0f\n", sizes[k], threads, settle,
             n * (double)steps / elapsed, 2.0 * (double)d.contacts_pp / n + (double)d.contacts_pw / n,
             (double)ru.ru_maxrss * 1024.0 / n);
      fflush(stdout);
    }
    adem_world_free(w);
  }
  return 0;
}
