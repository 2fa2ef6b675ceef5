/* Seeded, platform-independent random numbers: splitmix64 seeding a xoshiro256** stream. */
#ifndef ADEM_RNG_H
#define ADEM_RNG_H

#include <math.h>
#include <stdint.h>

#include "dmath.h"

typedef struct adem_rng {
  uint64_t s[4];
} adem_rng;

static inline uint64_t adem_rng_splitmix(uint64_t *x) {
  uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

static inline adem_rng adem_rng_seed(uint64_t seed) {
  adem_rng r;
  for (int k = 0; k < 4; ++k) r.s[k] = adem_rng_splitmix(&seed);
  return r;
}

static inline uint64_t adem_rng_rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static inline uint64_t adem_rng_next(adem_rng *r) {
  uint64_t *s = r->s;
  uint64_t result = adem_rng_rotl(s[1] * 5, 7) * 9;
  uint64_t t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = adem_rng_rotl(s[3], 45);
  return result;
}

/* Uniform in [0, 1). */
static inline double adem_rng_uniform(adem_rng *r) {
  return (double)(adem_rng_next(r) >> 11) * 0x1.0p-53;
}

/* Standard normal (Box-Muller, one value per call). */
static inline double adem_rng_normal(adem_rng *r) {
  double u1 = adem_rng_uniform(r);
  double u2 = adem_rng_uniform(r);
  if (u1 < 1e-300) u1 = 1e-300;
  return sqrt(-2.0 * adem_dmath_log(u1)) * adem_dmath_cos(6.283185307179586 * u2);
}

#endif
