/* The force that starts a resting adhesive sphere rolling on a wall (H section 5.3, notes
 * section 4): F_yield = k_r xi_crit / R with k_r = 4 F_C at a = a0, so F_ext/F_yield = 1; kept by
 * H24 with the rolling modification (H section 3.2) at every stiffness, moved without it. Each
 * case is adem_collide's world: a sphere at the JKR equilibrium, JKR + DTK, no gravity, a constant
 * force through the centre along the wall from t = 0. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "adem/studies.h"

static const double stiffness[3] = {1.0, 0.1, 0.01};

/* r = 1 um, rho = 1000 kg/m^3, E = 1e7 Pa, gamma from Ad = 1 at 1 m/s, e = 0.5, mu = 0.3,
 * delta_gamma/gamma = 0.5. 50 steps per half oscillation period: the rolling period is 3 to 60
 * times longer. */
static adem_collide_spec resting(double f, double fhat) {
  adem_collide_spec s = adem_default_collide_spec();
  s.kind = ADEM_COLLIDE_WALL;
  s.radius = 1e-6;
  s.density = 1000.0;
  s.restitution = 0.5;
  s.friction = 0.3;
  s.speed = 1.0;
  adem_collide_set_lambda(&s, 1e4);
  adem_collide_set_ad(&s, 1.0);
  s.stiffness_factor = f;
  s.dtk = true;
  s.hysteresis = 0.5;
  s.at_rest = true;
  s.force_hat = fhat;
  s.steps_per_tc = 50.0;
  return s;
}

static void set_force_hat(adem_collide_spec *s, double x, void *user) {
  (void)user;
  s->force_hat = x;
}

static double threshold(const adem_collide_spec *base, double lo, double hi) {
  double x = NAN;
  adem_error err;
  adem_status st = adem_collide_threshold_split(base, set_force_hat, NULL, ADEM_SPLIT_REST, lo, hi,
                                                2e-3, 2, &x, &err);
  if (st) fail_msg("%s", err.message);
  return x;
}

/* Claim (H section 5.3: F_hat < 1 comes to a halt, F_hat >= 1 keeps rolling), at f = 1, 0.1 and
 * 0.01 with H24 and the rolling modification: F_hat = 0.9 comes to rest within a few rolling
 * distances xi_crit and stays there for 10 rolling periods (|xi| < xi_crit, slow); F_hat = 1.1
 * keeps rolling with the torque saturated and the speed growing; the threshold found by
 * multisection (to 0.2%) is 1 within 2%. */
static void test_threshold_at_rest(void **state) {
  (void)state;
  for (int k = 0; k < 3; ++k) {
    adem_collide_spec s = resting(stiffness[k], 0.9);
    s.rest_periods = 10.0;
    adem_collide_result held = adem_collide(&s);
    assert_int_equal(held.status, ADEM_OK);
    s = resting(stiffness[k], 1.1);
    adem_collide_result rolls = adem_collide(&s);
    assert_int_equal(rolls.status, ADEM_OK);
    double fc = threshold(&s, 0.8, 1.25);
    printf("# f = %g: F_hat 0.9 %s after %.3g T_r, %.2f xi_crit; F_hat 1.1 %s, %.1f xi_crit, "
           "v %.3g m/s; threshold F_hat = %.4f\n",
           stiffness[k], adem_collide_outcome_name(held.outcome), held.t_rest / held.t_roll,
           held.roll_distance / held.xi_crit, adem_collide_outcome_name(rolls.outcome),
           rolls.roll_distance / rolls.xi_crit, rolls.v_end, fc);
    assert_int_equal(held.outcome, ADEM_OUTCOME_STUCK);
    assert_false(held.undecided);
    assert_true(held.roll_distance < 20.0 * held.xi_crit);
    assert_int_equal(rolls.outcome, ADEM_OUTCOME_ROLLING);
    assert_false(rolls.undecided);
    assert_true(rolls.roll_distance > 10.0 * rolls.xi_crit);
    assert_true(fabs(fc - 1.0) < 0.02);
  }
}

/* Claim (H section 3.2, Fig. 4; notes section 5): reducing E alone (gamma kept, no rolling
 * modification) keeps F_C but grows a0 and xi_crit = a0/12 delta_gamma/gamma as f^(-1/3), so the
 * force that starts rolling, in units of the real F_yield, moves to f^(-1/3) = 2.154 (f = 0.1)
 * and 4.642 (f = 0.01); H24 without the modification moves it to f^(2/5) f^(-1/5) = f^(1/5) =
 * 0.631 and 0.398. Both within 2%, printed with the shift. */
static void test_threshold_without_modification(void **state) {
  (void)state;
  for (int k = 1; k < 3; ++k) {
    double f = stiffness[k];
    adem_collide_spec s = resting(f, 1.0);
    s.keep_gamma = true;
    s.dtk_modification = false;
    double th_e = pow(f, -1.0 / 3.0), fc_e = threshold(&s, 0.7 * th_e, 1.4 * th_e);
    s = resting(f, 1.0);
    s.dtk_modification = false;
    double th_h = pow(f, 0.2), fc_h = threshold(&s, 0.7 * th_h, 1.4 * th_h);
    printf("# f = %g: E reduced alone: threshold F_hat = %.4f (moved by x%.4f; f^(-1/3) = %.4f); "
           "H24 without the modification: %.4f (x%.4f; f^(1/5) = %.4f)\n",
           f, fc_e, fc_e, th_e, fc_h, fc_h, th_h);
    assert_true(fabs(fc_e / th_e - 1.0) < 0.02);
    assert_true(fabs(fc_h / th_h - 1.0) < 0.02);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_threshold_at_rest),
      cmocka_unit_test(test_threshold_without_modification),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
