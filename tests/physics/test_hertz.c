/* Binary collisions against the closed forms of Hertz contact (notes sections 2 and 6). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "helpers.h"
#include "world.h"

enum { E_MOD = 100000000 };
static const double RADIUS = 1e-3, NU = 0.3, RHO = 2500.0;

typedef struct collision {
  double rebound_speed; /* relative speed after separation */
  double duration;      /* contact time, interpolated at the zero crossings of the gap */
  double momentum_error; /* |sum m v (after) - sum m v (before)| / sum m |v| */
} collision;

static double effective_modulus(void) { return E_MOD / (2.0 * (1.0 - NU * NU)); }

/* Closed form Hertz contact time for two equal spheres at relative speed v (notes section 6). */
static double hertz_duration(double v) {
  double m = test_sphere_mass(RADIUS, RHO);
  double mstar = 0.5 * m, R = 0.5 * RADIUS, E = effective_modulus();
  return 2.86827 * pow(mstar * mstar / (R * E * E * v), 0.2);
}

/* Two equal spheres approaching head-on along x at relative speed v. */
static collision head_on(double v, double e, double steps_per_collision, double mass_ratio) {
  adem_world *w = adem_world_create();
  adem_world_set_gravity(w, v3(0, 0, 0));
  int mat = test_material(w, "glass", E_MOD, NU, e, 0.0);
  double gap = 0.02 * RADIUS;
  test_particle(w, mat, v3(-RADIUS - gap, 0, 0), v3(0.5 * v, 0, 0), RADIUS);
  double rb = RADIUS * cbrt(mass_ratio);
  test_particle(w, mat, v3(rb + gap, 0, 0), v3(-0.5 * v, 0, 0), rb);
  double dt = hertz_duration(v) / steps_per_collision;
  adem_world_set_dt(w, dt);
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  adem_particles *p = &w->p;
  double p0 = 0.0, scale = 0.0;
  for (size_t i = 0; i < 2; ++i) {
    p0 += p->vel[i].x / p->inv_mass[i];
    scale += fabs(p->vel[i].x) / p->inv_mass[i];
  }
  double prev_gap = INFINITY, t_in = -1.0, t_out = -1.0;
  for (int s = 0; s < 10 * (int)steps_per_collision + 100000; ++s) {
    assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
    size_t a = p->id[0] == 0 ? 0 : 1, b = 1 - a;
    double g = p->pos[b].x - p->pos[a].x - p->radius[a] - p->radius[b];
    double t = adem_world_time(w);
    if (t_in < 0 && g < 0 && prev_gap >= 0) t_in = t - dt * g / (g - prev_gap);
    if (t_in >= 0 && g >= 0 && prev_gap < 0) {
      t_out = t - dt * g / (g - prev_gap);
      break;
    }
    prev_gap = g;
  }
  assert_true(t_out > 0);
  adem_world_step(w, 5, &err);
  collision c;
  c.rebound_speed = fabs(p->vel[1].x - p->vel[0].x);
  c.duration = t_out - t_in;
  double p1 = 0.0;
  for (size_t i = 0; i < 2; ++i) p1 += p->vel[i].x / p->inv_mass[i];
  c.momentum_error = fabs(p1 - p0) / scale;
  adem_world_free(w);
  return c;
}

/* Claim: without damping a Hertz collision is elastic and lasts 2.86827 (m*^2/(R E^2 v))^(1/5). */
static void test_elastic_head_on(void **state) {
  (void)state;
  double speeds[] = {0.1, 1.0, 10.0};
  for (int k = 0; k < 3; ++k) {
    collision c = head_on(speeds[k], 1.0, 2000.0, 1.0);
    double tc = hertz_duration(speeds[k]);
    printf("# v = %g m/s: rebound/impact = %.9f, duration/closed form = %.6f\n", speeds[k],
           c.rebound_speed / speeds[k], c.duration / tc);
    assert_true(fabs(c.rebound_speed / speeds[k] - 1.0) < 1e-6);
    assert_true(fabs(c.duration / tc - 1.0) < 0.005);
  }
}

/* Claim: the damping of H11-H13 gives a restitution independent of the impact speed, close to e. */
static void test_restitution_speed_independent(void **state) {
  (void)state;
  double es[] = {0.3, 0.5, 0.9};
  double speeds[] = {0.1, 1.0, 10.0};
  for (int a = 0; a < 3; ++a) {
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 3; ++k) {
      collision c = head_on(speeds[k], es[a], 1000.0, 1.0);
      double eff = c.rebound_speed / speeds[k];
      printf("# e = %.2f, v = %5.2f m/s: e_eff = %.6f\n", es[a], speeds[k], eff);
      lo = fmin(lo, eff);
      hi = fmax(hi, eff);
    }
    /* The scaled equation of motion has no speed in it: only discretisation differs. */
    assert_true(hi - lo < 3e-4);
    /* With the sqrt(5/6) factor of H11 the measured restitution matches the input closely. */
    assert_true(fabs(0.5 * (lo + hi) - es[a]) < 0.005);
  }
}

/* Claim: particle-particle forces are equal and opposite, so momentum is conserved to round-off
 * (unequal masses, damped). */
static void test_momentum_conserved(void **state) {
  (void)state;
  collision c = head_on(2.0, 0.5, 200.0, 3.0);
  printf("# relative momentum change: %.3e\n", c.momentum_error);
  assert_true(c.momentum_error < 1e-14);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_elastic_head_on),
      cmocka_unit_test(test_restitution_speed_independent),
      cmocka_unit_test(test_momentum_conserved),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
