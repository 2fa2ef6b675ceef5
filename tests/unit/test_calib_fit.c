/* adem calibrate's response fit (adem_calib_fit_line, src/studies/calibrate.c): the value where
 * the least-squares line through the runs of a window meets the target, and its standard error,
 * which is what a calibration on a noisy response (a pile's angle) can claim. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "adem/calibrate.h"

/* splitmix64 and Box-Muller: a fixed stream of standard normal numbers */
static uint64_t rng_state = 2017;
static double uniform01(void) {
  uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return ((double)(z >> 11) + 0.5) * 0x1p-53;
}
static double normal01(void) {
  return sqrt(-2.0 * log(uniform01())) * cos(6.283185307179586 * uniform01());
}

/* Claim: on an exact line the fit meets the target where the line does (to rounding), with no
 * scatter; runs outside the window do not enter; two runs give the line but no scatter, one run
 * no line. */
static void test_exact_line(void **state) {
  (void)state;
  double x[6] = {0.1, 0.2, 0.25, 0.3, 0.4, 0.9}, y[6];
  for (int k = 0; k < 6; ++k) y[k] = 10.0 + 120.0 * x[k];
  y[5] = -50.0; /* outside the window [0.1, 0.4]: must not count */
  adem_calib_fit f = adem_calib_fit_line(x, y, 6, 0.1, 0.4, 40.0);
  assert_int_equal(f.n, 5);
  assert_true(fabs(f.x - 0.25) < 1e-12);
  assert_true(fabs(f.slope - 120.0) < 1e-9);
  assert_true(f.noise < 1e-9 && f.x_se < 1e-12);
  f = adem_calib_fit_line(x, y, 6, 0.15, 0.22, 40.0);
  assert_int_equal(f.n, 1);
  assert_true(isnan(f.x));
  f = adem_calib_fit_line(x, y, 6, 0.2, 0.25, 40.0);
  assert_int_equal(f.n, 2);
  assert_true(fabs(f.x - 0.25) < 1e-12 && isnan(f.noise) && isnan(f.x_se));
}

/* Claim: on a line with Gaussian scatter of sd 2 (slope 100 per unit, 8 runs evenly over
 * [0.1, 0.4], the target met at 0.37, near the window's end where the line's uncertainty is
 * largest), the true value lies within one standard error of the fit in 0.62-0.68 of 4,000
 * calibrations: the t distribution with 6 degrees of freedom gives 0.644, and a simulation of the
 * same estimator 0.650. The band is 4 standard deviations of a fraction of 4,000 draws (0.0075).
 * Wrong forms of the error fail it: without the line's leverage term (x - mean)^2 / Sxx 0.45,
 * the residuals over n instead of n - 2 0.59, one run's scatter instead of the error 0.88. The
 * scatter itself is estimated without bias: its mean square over the trials within 3 % of 4. */
static void test_coverage(void **state) {
  (void)state;
  const int n = 8, trials = 4000;
  double x[8], y[8];
  for (int k = 0; k < n; ++k) x[k] = 0.1 + 0.3 * k / (n - 1);
  int covered = 0;
  double noise2 = 0.0;
  for (int t = 0; t < trials; ++t) {
    for (int k = 0; k < n; ++k) y[k] = 5.0 + 100.0 * x[k] + 2.0 * normal01();
    adem_calib_fit f = adem_calib_fit_line(x, y, (size_t)n, 0.1, 0.4, 5.0 + 100.0 * 0.37);
    assert_int_equal(f.n, n);
    covered += fabs(f.x - 0.37) <= f.x_se;
    noise2 += f.noise * f.noise;
  }
  double frac = (double)covered / trials;
  printf("# coverage of one standard error: %.4f (t, 6 dof: 0.644); mean noise^2 %.4f (4)\n", frac,
         noise2 / trials);
  assert_true(frac >= 0.62 && frac <= 0.68);
  assert_true(fabs(noise2 / trials - 4.0) < 0.12);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_exact_line),
      cmocka_unit_test(test_coverage),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
