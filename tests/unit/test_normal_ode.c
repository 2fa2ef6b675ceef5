/* The independent reference of the collision validations (src/studies/normal_ode.c): its force is
 * H8-H10 (the checkpoints of the physics notes, section 2), an undamped collision gives back its
 * energy and lasts the Hertz collision time (notes section 6), and the dashpot of H11-H13 makes a
 * Hertz collision's restitution e at any speed. Claims: the reference the validations measure
 * the engine against solves the paper's normal equation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>

#include "adem/adem.h"
#include "adem/vec3.h"
#include "normal_ode.h"

static adem_normal_ode ode(double gamma, double e) {
  double l = log(e);
  adem_normal_ode p = {1e-15, 0.635e-6, 271e6, gamma, l / sqrt(l * l + ADEM_PI * ADEM_PI)};
  return p;
}

/* F/F_C at delta/delta_c = 0, 0.5, 2, 10 (notes section 2; to 1e-9: the notes give 12 digits). */
static void test_force_checkpoints(void **state) {
  (void)state;
  adem_normal_ode p = ode(0.11, 1.0);
  double fc = 3.0 * ADEM_PI * p.gamma * p.R;
  double a0 = cbrt(9.0 * ADEM_PI * p.gamma * p.R * p.R / p.E);
  double dc = a0 * a0 / (2.0 * cbrt(6.0) * p.R);
  static const double x[4] = {0.0, 0.5, 2.0, 10.0};
  static const double f[4] = {-8.0 / 9.0, -0.605578135774, 0.885107268187, 17.559825151134};
  for (int k = 0; k < 4; ++k) {
    double got = adem_normal_ode_force(&p, x[k] * dc) / fc;
    printf("# x = %g: F/F_C = %.12f (notes %.12f)\n", x[k], got, f[k]);
    assert_true(fabs(got - f[k]) < 1e-9 * fmax(1.0, fabs(f[k])));
  }
  /* equilibrium a = a0 at delta = a0^2/(3R): F = 0 */
  assert_true(fabs(adem_normal_ode_force(&p, a0 * a0 / (3.0 * p.R))) < 1e-9 * fc);
}

/* Undamped: all the energy comes back (Hertz and JKR: the JKR force does no net work between
 * touch and break, both at delta = 0); the Hertz collision lasts
 * t_c = 2.86827 (m*^2/(R E^2 v))^(1/5) (the constant has 6 digits). */
static void test_undamped(void **state) {
  (void)state;
  for (int j = 0; j < 2; ++j) {
    adem_normal_ode p = ode(j ? 0.11 : 0.0, 1.0);
    double v = 5.0;
    adem_normal_ode_result r = adem_normal_ode_collide(&p, v, 1e-12, NULL, NULL);
    printf("# %s, undamped at %g m/s: e_eff = %.12f, %zu steps\n", j ? "JKR" : "Hertz", v, r.e_eff,
           r.steps);
    assert_false(r.stuck);
    assert_true(fabs(r.e_eff - 1.0) < 1e-9);
    if (!j) {
      double tc = 2.86827 * pow(p.mstar * p.mstar / (p.R * p.E * p.E * v), 0.2);
      printf("# duration %.9g s, t_c %.9g s\n", r.duration, tc);
      assert_true(fabs(r.duration / tc - 1.0) < 5e-6);
    }
  }
}

/* The dashpot of H11-H13 with a force that may pull makes a Hertz collision's e_eff equal e at
 * any speed (notes section 2). */
static void test_hertz_restitution(void **state) {
  (void)state;
  static const double e[3] = {0.2, 0.5, 0.86};
  static const double v[2] = {0.1, 10.0};
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 2; ++j) {
      adem_normal_ode p = ode(0.0, e[k]);
      adem_normal_ode_result r = adem_normal_ode_collide(&p, v[j], 1e-12, NULL, NULL);
      printf("# e = %g, v = %g: e_eff = %.10f\n", e[k], v[j], r.e_eff);
      assert_true(fabs(r.e_eff - e[k]) < 1e-8);
    }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_force_checkpoints),
      cmocka_unit_test(test_undamped),
      cmocka_unit_test(test_hertz_restitution),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
