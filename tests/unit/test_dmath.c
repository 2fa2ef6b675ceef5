/* Claims: adem's elementary functions (src/laws/dmath.c) are within 1 ulp of glibc's over wide
 * ranges (glibc's own are within 1 ulp of the correctly rounded value; dmath's were correctly
 * rounded on all 3.4 million arguments checked against MPFR when it was written), cbrt within 3
 * ulp (glibc's cbrt is only that close), exact where the value is a double, and follow C99 on
 * special values; and the build evaluates doubles as written: FLT_EVAL_METHOD 0, no contraction
 * of a * b - c into an FMA (which would break the double-double arithmetic and change bits
 * between hosts). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "dmath.h"

_Static_assert(FLT_EVAL_METHOD == 0, "doubles must be evaluated as doubles");

static uint64_t rng_state = 88172645463325252ull;
static double urand(void) {
  rng_state ^= rng_state << 13;
  rng_state ^= rng_state >> 7;
  rng_state ^= rng_state << 17;
  return (double)(rng_state >> 11) * 0x1p-53;
}

/* distance in ulps between two finite doubles (0 for two NaNs) */
static double ulps(double a, double b) {
  if (a == b || (isnan(a) && isnan(b))) return 0.0;
  if (isnan(a) || isnan(b)) return INFINITY;
  int64_t x, y;
  memcpy(&x, &a, sizeof x);
  memcpy(&y, &b, sizeof y);
  if (x < 0) x = INT64_MIN - x;
  if (y < 0) y = INT64_MIN - y;
  return x > y ? (double)(uint64_t)((uint64_t)x - (uint64_t)y)
               : (double)((uint64_t)y - (uint64_t)x);
}

typedef double (*fn1)(double);

/* Largest ulp distance from libm over N arguments uniform in [lo, hi] (log: log-uniform in
 * [lo, hi], both signs when sign is set). */
static double worst(fn1 f, fn1 ref, double lo, double hi, int logscale, int sign, int n,
                    double *where) {
  double w = 0.0;
  for (int i = 0; i < n; ++i) {
    double u = urand();
    double x = logscale ? exp(log(lo) + u * (log(hi) - log(lo))) : lo + u * (hi - lo);
    if (sign && urand() < 0.5) x = -x;
    double d = ulps(f(x), ref(x));
    if (d > w) {
      w = d;
      *where = x;
    }
  }
  return w;
}

static void check_range(const char *name, fn1 f, fn1 ref, double lo, double hi, int logscale,
                        int sign, double tol) {
  double at = 0.0, w = worst(f, ref, lo, hi, logscale, sign, 100000, &at);
  printf("# %-5s on [%g, %g]%s: largest difference from libm %g ulp (x = %a)\n", name, lo, hi,
         logscale ? " (log-uniform)" : "", w, at);
  if (w > tol) fail_msg("%s(%a) is %g ulp from libm (allowed %g)", name, at, w, tol);
}

static double pow04(double x) { return adem_dmath_pow(x, 0.4); }
static double lpow04(double x) { return pow(x, 0.4); }
static double pow02(double x) { return adem_dmath_pow(x, 0.2); }
static double lpow02(double x) { return pow(x, 0.2); }
static double pow_mixed(double x) { return adem_dmath_pow(1.0 + 0.01 * x, 7.3 * (x - 50.0)); }
static double lpow_mixed(double x) { return pow(1.0 + 0.01 * x, 7.3 * (x - 50.0)); }

static void test_within_one_ulp_of_libm(void **state) {
  (void)state;
  check_range("exp", adem_dmath_exp, exp, -745.0, 709.7, 0, 0, 1.0);
  check_range("exp", adem_dmath_exp, exp, 1e-20, 2.0, 1, 1, 1.0);
  check_range("log", adem_dmath_log, log, 1e-300, 1e300, 1, 0, 1.0);
  check_range("log", adem_dmath_log, log, 0.5, 2.0, 0, 0, 1.0);
  check_range("log", adem_dmath_log, log, 4.9e-324, 2e-308, 1, 0, 1.0);
  check_range("log1p", adem_dmath_log1p, log1p, 1e-300, 1e300, 1, 0, 1.0);
  check_range("log1p", adem_dmath_log1p, log1p, -0.999, 1.0, 0, 0, 1.0);
  check_range("sin", adem_dmath_sin, sin, 0.0, 10.0, 0, 1, 1.0);
  check_range("sin", adem_dmath_sin, sin, 1e-300, 1e300, 1, 1, 1.0);
  check_range("cos", adem_dmath_cos, cos, 0.0, 10.0, 0, 1, 1.0);
  check_range("cos", adem_dmath_cos, cos, 1e-300, 1e300, 1, 1, 1.0);
  check_range("tan", adem_dmath_tan, tan, 0.0, 10.0, 0, 1, 1.0);
  check_range("tan", adem_dmath_tan, tan, 1e-300, 1e300, 1, 1, 1.0);
  check_range("cbrt", adem_dmath_cbrt, cbrt, 4.9e-324, 1.7e308, 1, 1, 3.0);
  check_range("x^0.4", pow04, lpow04, 1e-300, 1e300, 1, 0, 1.0);
  check_range("x^0.2", pow02, lpow02, 1e-300, 1e300, 1, 0, 1.0);
  check_range("pow", pow_mixed, lpow_mixed, 0.0, 100.0, 0, 0, 1.0);
}

/* Values that are doubles come out exactly; the famous hard reduction sin(1e22) too. */
static void test_exact_values(void **state) {
  (void)state;
  assert_true(adem_dmath_exp(0.0) == 1.0);
  assert_true(adem_dmath_log(1.0) == 0.0);
  assert_true(ulps(adem_dmath_log(0x1p-1074), log(0x1p-1074)) <= 1.0);
  assert_true(adem_dmath_pow(2.0, 10.0) == 1024.0);
  assert_true(adem_dmath_pow(9.0, 0.5) == 3.0);
  assert_true(adem_dmath_pow(0.25, -1.5) == 8.0);
  assert_true(adem_dmath_pow(-2.0, 3.0) == -8.0);
  assert_true(adem_dmath_pow(1.7, 1.0) == 1.7);
  assert_true(adem_dmath_cbrt(27.0) == 3.0);
  assert_true(adem_dmath_cbrt(-0.125) == -0.5);
  assert_true(adem_dmath_cbrt(0x1p-1071) == 0x1p-357);
  assert_true(adem_dmath_cos(0.0) == 1.0);
  /* sin(1e22) = -0.8522008497671888... (the reduction needs 2/pi to 140 bits past 1e22's) */
  assert_true(ulps(adem_dmath_sin(1e22), -0.8522008497671888) <= 1.0);
  assert_true(ulps(adem_dmath_cos(1e22), 0.5232147853951389) <= 1.0);
}

static void test_special_values(void **state) {
  (void)state;
  const double inf = INFINITY;
  assert_true(adem_dmath_exp(-inf) == 0.0 && adem_dmath_exp(inf) == inf);
  assert_true(adem_dmath_exp(710.0) == inf && adem_dmath_exp(-746.0) == 0.0);
  assert_true(isnan(adem_dmath_exp(NAN)));
  assert_true(adem_dmath_log(0.0) == -inf && adem_dmath_log(inf) == inf);
  assert_true(isnan(adem_dmath_log(-1.0)) && isnan(adem_dmath_log(NAN)));
  assert_true(adem_dmath_log1p(-1.0) == -inf && isnan(adem_dmath_log1p(-2.0)));
  assert_true(signbit(adem_dmath_log1p(-0.0)) && adem_dmath_log1p(0x1p-1074) == 0x1p-1074);
  assert_true(signbit(adem_dmath_sin(-0.0)) && signbit(adem_dmath_tan(-0.0)));
  assert_true(isnan(adem_dmath_sin(inf)) && isnan(adem_dmath_cos(-inf)) &&
              isnan(adem_dmath_tan(inf)));
  assert_true(adem_dmath_cbrt(-inf) == -inf && signbit(adem_dmath_cbrt(-0.0)));
  assert_true(adem_dmath_pow(NAN, 0.0) == 1.0 && adem_dmath_pow(1.0, NAN) == 1.0);
  assert_true(isnan(adem_dmath_pow(-2.0, 0.5)) && isnan(adem_dmath_pow(NAN, 2.0)));
  assert_true(adem_dmath_pow(0.0, -1.0) == inf && adem_dmath_pow(-0.0, -1.0) == -inf);
  assert_true(adem_dmath_pow(-0.0, 3.0) == 0.0 && signbit(adem_dmath_pow(-0.0, 3.0)));
  assert_true(adem_dmath_pow(0.5, inf) == 0.0 && adem_dmath_pow(2.0, inf) == inf);
  assert_true(adem_dmath_pow(-1.0, inf) == 1.0 && adem_dmath_pow(-1.0, 0x1p1023) == 1.0);
  assert_true(adem_dmath_pow(-inf, 3.0) == -inf && adem_dmath_pow(inf, -2.0) == 0.0);
  assert_true(adem_dmath_pow(10.0, 400.0) == inf && adem_dmath_pow(10.0, -400.0) == 0.0);
}

/* The library's a * b - c, compiled with the project's flags, is not fused: 1 + 2^-26 + 2^-54
 * rounds to 1 + 2^-26 unfused, so the probe is 0; an FMA gives 2^-54. So is this file's. */
static void test_no_contraction(void **state) {
  (void)state;
  volatile double a = 1.0 + 0x1p-27, c = 1.0 + 0x1p-26;
  double lib = adem_dmath_contraction_probe(a, a, c);
  double here = a * a - c;
  printf("# a * b - c: %a in the library, %a in the test (0 unless fused into an FMA)\n", lib,
         here);
  assert_true(lib == 0.0);
  assert_true(here == 0.0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_within_one_ulp_of_libm),
      cmocka_unit_test(test_exact_values),
      cmocka_unit_test(test_special_values),
      cmocka_unit_test(test_no_contraction),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
