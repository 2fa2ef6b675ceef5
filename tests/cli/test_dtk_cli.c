/* The adem command on deposition with DTK rolling resistance (H section 5.3): `adem collide`
 * with a force along the wall and the outcome columns, --critical-lambda (H25), bad options,
 * and the quick DTK validations. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "cli_run.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_dtk_cli");
}

/* Claim: `adem collide --at-rest --dtk` classifies a resting PSL sphere pushed along quartz with
 * F_hat = 0.9 as stuck and 1.1 as rolling at f = 1 and 0.01 (H section 5.3 with H24 and the
 * rolling modification), rows in list order, F_ext = F_hat F_yield with F_yield =
 * 4 F_C xi_crit / r (1.10e-9 N for PSL, delta_gamma/gamma = 0.5). */
static void test_collide_at_rest(void **state) {
  (void)state;
  char *out, *csv = path_in_tmp("rest.csv");
  assert_int_equal(adem(&out, "collide --at-rest --dtk --hysteresis 0.5 --force-hat 0.9,1.1 "
                              "--stiffness-factor 1,0.01 --threads 2 --out '%s'",
                        csv),
                   0);
  assert_mentions(out, "2 rolling, 2 at rest");
  /* rows: (0.9, f 1), (0.9, f 0.01), (1.1, f 1), (1.1, f 0.01) */
  const char *expect[4] = {"stuck", "stuck", "rolling", "rolling"};
  for (int r = 1; r <= 4; ++r) assert_string_equal(csv_cell(csv, r, "outcome"), expect[r - 1]);
  /* F_yield = 4 (3 pi gamma r) (a0/12 x 0.5) / r, a0 = (9 pi gamma r^2/E)^(1/3) */
  double r = 0.635e-6, g = 0.11, a0 = cbrt(9.0 * 3.14159265358979 * g * r * r / 271e6);
  double fy = 4.0 * 3.0 * 3.14159265358979 * g * r * (a0 / 24.0) / r;
  printf("# F_ext row 3: %.6g N, 1.1 F_yield = %.6g N\n", csv_value(csv, 3, "F_ext_N"), 1.1 * fy);
  assert_true(fabs(csv_value(csv, 3, "F_ext_N") / (1.1 * fy) - 1.0) < 1e-9);
  assert_true(fabs(csv_value(csv, 1, "F_hat") - 0.9) < 1e-12);
  assert_true(csv_value(csv, 1, "t_rest_s") > 0.0);
  assert_true(csv_value(csv, 1, "roll_distance_m") < 20.0 * csv_value(csv, 1, "xi_crit_m"));
  free(csv);
}

/* Claim: --critical-lambda finds lambda_crit for each Ad and restitution, writes c =
 * lambda_crit/Ad^(5/2), and prints the fit lambda_crit = c Ad^k per restitution with k = 2.5
 * (H25); wall c(0.3) = 147.4 at 200 steps per collision time (sqrt 2 times the head-on pair's;
 * 149.8 with the first-order contact scheme of before, 147.2 converged). */
static void test_critical_lambda(void **state) {
  (void)state;
  char *out, *csv = path_in_tmp("crit.csv");
  assert_int_equal(adem(&out, "collide --radius 1e-6 --density 1000 --ad 100,1000 --restitution "
                              "0.3,0.7 --critical-lambda 1e3:1e13:1e-4 --threads 2 --out '%s'",
                        csv),
                   0);
  assert_mentions(out, "4 critical lambdas");
  assert_mentions(out, "e = 0.3: lambda_crit = 147.4");
  assert_mentions(out, "Ad^2.5000");
  double c1 = csv_value(csv, 1, "c"), c2 = csv_value(csv, 2, "c"), c3 = csv_value(csv, 3, "c");
  printf("# c(0.3) at Ad 100, 1000: %.6g, %.6g; c(0.7): %.6g\n", c1, c2, c3);
  assert_true(fabs(c1 / c2 - 1.0) < 2e-4);
  assert_true(fabs(c1 / 147.4 - 1.0) < 2e-3);
  assert_true(c3 < c1);
  free(csv);
}

/* Claim: options that do not make sense together are refused with exit status 2 and a message
 * naming the option. */
static void test_bad_options(void **state) {
  (void)state;
  char *out;
  assert_int_equal(adem(&out, "collide --force-hat 0.5"), 2);
  assert_mentions(out, "--force-hat needs --dtk");
  assert_int_equal(adem(&out, "collide --dtk"), 2);
  assert_mentions(out, "--hysteresis");
  assert_int_equal(adem(&out, "collide --kind pair --dtk --hysteresis 0.5"), 2);
  assert_mentions(out, "wall impacts");
  assert_int_equal(adem(&out, "collide --dtk --hysteresis 0.5 --force-hat 1 --force-ext 1e-9"), 2);
  assert_mentions(out, "not both");
  assert_int_equal(adem(&out, "collide --lambda 1e5 --critical-lambda 1e3:1e9"), 2);
  assert_mentions(out, "--critical-lambda");
  assert_int_equal(adem(&out, "collide --critical-lambda 1e9:1e3"), 2);
  assert_mentions(out, "LO:HI");
  assert_int_equal(adem(&out, "collide --restitution 0,0.5"), 2);
  assert_mentions(out, "--restitution");
  assert_int_equal(adem(&out, "collide --help"), 0);
  assert_mentions(out, "--critical-lambda");
}

/* Claim: the quick versions of the DTK validations (H Figs. 4, 10, 11, 12 and the invariance of
 * deposition under H24) pass and write their CSVs. */
static void test_validate_quick(void **state) {
  (void)state;
  char *out;
  assert_int_equal(adem(&out, "validate haervig-fig4 haervig-fig10 haervig-fig11 haervig-fig12 "
                              "haervig-rolling-invariance --quick --threads 2 --out '%s/v'",
                        tmpdir),
                   0);
  assert_mentions(out, "5 of 5 validations passed");
  const char *names[5] = {"haervig-fig4", "haervig-fig10", "haervig-fig11", "haervig-fig12",
                          "haervig-rolling-invariance"};
  for (int k = 0; k < 5; ++k) {
    char rel[128];
    snprintf(rel, sizeof rel, "v/%s.csv", names[k]);
    char *p = path_in_tmp(rel);
    assert_true(file_exists(p));
    free(p);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_collide_at_rest),
      cmocka_unit_test(test_critical_lambda),
      cmocka_unit_test(test_bad_options),
      cmocka_unit_test(test_validate_quick),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
