/* The coarse-grained fields' exact identities (src/fields/fields.c, docs/fields.md), on random
 * particles and contacts, Gaussian and Lucy kernels, in 3-D and averaged over one or two axes:
 * - mass: the grid integral of the density is the particles' total mass to 1e-10 (relative),
 *   particles whose kernel the grid's edge cuts included (they keep their whole weight inside);
 * - Love-Weber: the grid integral of the contact stress is sum f (x) l over the contacts to
 *   1e-10 (relative to the largest component), wall contacts and contacts near the edge included;
 * - the momentum and velocity of a uniformly moving set: V is the set's velocity and the kinetic
 *   stress vanishes (to rounding) wherever there is mass.
 * Perturbed once each (docs/fields.md): the Gaussian normalised analytically (h / (sqrt(2 pi) w)
 * per axis) instead of on the grid gives mass errors 5.2e-2 (3-D: kernels the edge cuts lose
 * weight) and 5.6e-3 (profiles); a particle pair's f (x) l taken with half the branch (the
 * centre-to-contact-point arm of one particle only) gives a Love-Weber error of 0.50. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "adem/fields.h"

enum { NP = 300,
       NC = 500 };

static double rnd(uint64_t *s) { /* xorshift64*, uniform in [0, 1) */
  *s ^= *s >> 12;
  *s ^= *s << 25;
  *s ^= *s >> 27;
  return (double)((*s * 2685821657736338717ull) >> 11) * 0x1.0p-53;
}

typedef struct sample {
  double pos[3 * NP], vel[3 * NP], mass[NP], radius[NP];
  int64_t id[NP];
  double p0[3 * NC], p1[3 * NC], force[3 * NC];
  int32_t kind[NC];
  int64_t ida[NC], idb[NC];
} sample;

/* Particles in [0, 1]^3 m (some within a width of the faces of the grid [0, 1]^3), contacts
 * between random pairs and, one in five, to a wall point. */
static void make_sample(sample *s, uint64_t seed, int moving) {
  uint64_t r = seed;
  for (int i = 0; i < NP; ++i) {
    for (int a = 0; a < 3; ++a) {
      s->pos[3 * i + a] = 0.02 + 0.96 * rnd(&r);
      s->vel[3 * i + a] = moving ? (a == 0 ? 0.3 : a == 1 ? -0.2
                                                          : 0.1)
                                 : rnd(&r) - 0.5;
    }
    s->mass[i] = 0.5 + rnd(&r);
    s->radius[i] = 0.01 + 0.02 * rnd(&r);
    s->id[i] = 1000 + 3 * i; /* not 0..n-1: found by id */
  }
  for (int k = 0; k < NC; ++k) {
    int i = (int)(rnd(&r) * NP), j = (int)(rnd(&r) * NP);
    if (j == i) j = (i + 1) % NP;
    int wall = k % 5 == 0;
    s->kind[k] = wall ? 1 : 0;
    s->ida[k] = s->id[i];
    s->idb[k] = wall ? 0 : s->id[j];
    for (int a = 0; a < 3; ++a) {
      s->p0[3 * k + a] = s->pos[3 * i + a];
      s->p1[3 * k + a] = wall ? s->pos[3 * i + a] + 0.05 * (rnd(&r) - 0.5) : s->pos[3 * j + a];
      s->force[3 * k + a] = rnd(&r) - 0.5;
    }
  }
}

static void check_identities(adem_fields_kernel kernel, const int avg[3], double width,
                             double cell) {
  static sample s;
  make_sample(&s, 12345u + (uint64_t)(1000 * width), 0);
  adem_fields_options o = adem_fields_default_options();
  o.kernel = kernel;
  o.width = width;
  o.cell = cell;
  for (int a = 0; a < 3; ++a) {
    o.lo[a] = 0.0;
    o.hi[a] = 1.0;
    o.average[a] = avg[a];
  }
  adem_fields *f = NULL;
  adem_error err;
  memset(&err, 0, sizeof err);
  assert_int_equal(adem_fields_create(&o, &f, &err), ADEM_OK);
  adem_fields_particles P = {NP, s.pos, s.vel, s.mass, s.radius, s.id};
  adem_fields_contacts C = {NC, s.p0, s.p1, s.force, s.kind, s.ida, s.idb};
  assert_int_equal(adem_fields_add(f, &P, &C, &err), ADEM_OK);
  /* mass */
  double M = 0.0, m = 0.0;
  for (int i = 0; i < NP; ++i) M += s.mass[i];
  assert_int_equal(adem_fields_integral(f, ADEM_CG_DENSITY, &m, &err), ADEM_OK);
  double em = fabs(m - M) / M;
  /* Love-Weber: sum f (x) (p0 - p1) */
  double lw[9] = {0}, g[9];
  for (int k = 0; k < NC; ++k)
    for (int u = 0; u < 3; ++u)
      for (int v = 0; v < 3; ++v)
        lw[3 * u + v] += s.force[3 * k + u] * (s.p0[3 * k + v] - s.p1[3 * k + v]);
  assert_int_equal(adem_fields_integral(f, ADEM_CG_CONTACT_STRESS, g, &err), ADEM_OK);
  double big = 0.0, el = 0.0;
  for (int u = 0; u < 9; ++u) big = fmax(big, fabs(lw[u]));
  for (int u = 0; u < 9; ++u) el = fmax(el, fabs(g[u] - lw[u]) / big);
  printf("%s w %.3g cell %.3g avg %d%d%d: mass error %.2e, Love-Weber error %.2e\n",
         kernel == ADEM_KERNEL_LUCY ? "lucy" : "gauss", width, cell, avg[0], avg[1], avg[2], em,
         el);
  assert_true(em < 1e-10);
  assert_true(el < 1e-10);
  adem_fields_free(f);
}

static void test_mass_and_love_weber_3d(void **state) {
  (void)state;
  const int none[3] = {0, 0, 0};
  check_identities(ADEM_KERNEL_GAUSSIAN, none, 0.04, 0.02);
  check_identities(ADEM_KERNEL_GAUSSIAN, none, 0.03, 0.045); /* width below the cell */
  check_identities(ADEM_KERNEL_LUCY, none, 0.03, 0.02);
}

static void test_mass_and_love_weber_averaged(void **state) {
  (void)state;
  const int xy[3] = {1, 1, 0}, y[3] = {0, 1, 0};
  check_identities(ADEM_KERNEL_GAUSSIAN, xy, 0.02, 0.005);
  check_identities(ADEM_KERNEL_LUCY, xy, 0.02, 0.005);
  check_identities(ADEM_KERNEL_GAUSSIAN, y, 0.03, 0.01);
  check_identities(ADEM_KERNEL_LUCY, y, 0.03, 0.01);
}

/* A set moving as one body: V = its velocity where there is mass, the kinetic stress ~ 0. */
static void test_uniform_motion(void **state) {
  (void)state;
  static sample s;
  make_sample(&s, 99, 1);
  adem_fields_options o = adem_fields_default_options();
  o.width = 0.05;
  o.cell = 0.05;
  for (int a = 0; a < 3; ++a) o.lo[a] = 0.0, o.hi[a] = 1.0;
  adem_fields *f = NULL;
  adem_error err;
  assert_int_equal(adem_fields_create(&o, &f, &err), ADEM_OK);
  adem_fields_particles P = {NP, s.pos, s.vel, s.mass, s.radius, s.id};
  assert_int_equal(adem_fields_add(f, &P, NULL, &err), ADEM_OK);
  size_t n[3];
  double origin[3], h;
  adem_fields_grid(f, n, origin, &h);
  size_t nodes = n[0] * n[1] * n[2];
  double *rho = malloc(nodes * sizeof *rho), *V = malloc(3 * nodes * sizeof *V),
         *K = malloc(9 * nodes * sizeof *K);
  assert_int_equal(adem_fields_get(f, ADEM_CG_DENSITY, rho, nodes, &err), ADEM_OK);
  assert_int_equal(adem_fields_get(f, ADEM_CG_VELOCITY, V, 3 * nodes, &err), ADEM_OK);
  assert_int_equal(adem_fields_get(f, ADEM_CG_KINETIC_STRESS, K, 9 * nodes, &err), ADEM_OK);
  double rmax = 0.0;
  for (size_t k = 0; k < nodes; ++k) rmax = fmax(rmax, rho[k]);
  double ev = 0.0, ek = 0.0;
  for (size_t k = 0; k < nodes; ++k) {
    if (rho[k] < 1e-6 * rmax) continue;
    ev = fmax(ev, fabs(V[3 * k] - 0.3) + fabs(V[3 * k + 1] + 0.2) + fabs(V[3 * k + 2] - 0.1));
    for (int u = 0; u < 9; ++u) ek = fmax(ek, fabs(K[9 * k + u]) / (rho[k] * 0.14));
  }
  printf("uniform motion: velocity error %.2e m/s, kinetic stress / (rho |v|^2) %.2e\n", ev, ek);
  assert_true(ev < 1e-12);
  assert_true(ek < 1e-9);
  free(rho);
  free(V);
  free(K);
  adem_fields_free(f);
}

static void test_refusals(void **state) {
  (void)state;
  adem_fields_options o = adem_fields_default_options();
  adem_fields *f = NULL;
  adem_error err;
  o.width = 0.0;
  o.cell = 0.1;
  for (int a = 0; a < 3; ++a) o.lo[a] = 0.0, o.hi[a] = 1.0;
  assert_int_equal(adem_fields_create(&o, &f, &err), ADEM_ERR_INPUT);
  assert_non_null(strstr(err.message, "width"));
  o.width = 0.1;
  o.average[0] = o.average[1] = o.average[2] = 1;
  assert_int_equal(adem_fields_create(&o, &f, &err), ADEM_ERR_INPUT);
  o.average[2] = 0;
  o.hi[2] = -1.0;
  assert_int_equal(adem_fields_create(&o, &f, &err), ADEM_ERR_INPUT);
  o.hi[2] = 1.0;
  assert_int_equal(adem_fields_create(&o, &f, &err), ADEM_OK);
  double pos[3] = {0.5, 0.5, 0.5}, m = 1.0, r = 0.01, pa[3] = {0.5, 0.5, 0.5}, pb[3] = {0.6, 0.5, 0.5},
         fc[3] = {1, 0, 0};
  int64_t id = 7, ida = 7, idb = 8;
  int32_t kind = 0;
  adem_fields_particles P = {1, pos, NULL, &m, &r, &id};
  adem_fields_contacts C = {1, pa, pb, fc, &kind, &ida, &idb};
  assert_int_equal(adem_fields_add(f, &P, &C, &err), ADEM_ERR_INPUT);
  assert_non_null(strstr(err.message, "particle 8"));
  double out;
  assert_int_equal(adem_fields_integral(f, ADEM_CG_DENSITY, &out, &err), ADEM_ERR_INPUT);
  adem_fields_free(f);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mass_and_love_weber_3d),
      cmocka_unit_test(test_mass_and_love_weber_averaged),
      cmocka_unit_test(test_uniform_motion),
      cmocka_unit_test(test_refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
