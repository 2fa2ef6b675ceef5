/* Claim: a run does not inherit flush-to-zero, denormals-are-zero or a rounding mode other than
 * to nearest from its process (a library built with -ffast-math sets FTZ/DAZ at load): preparing
 * a world resets them in the calling thread and in its OpenMP threads, with a warning, and a
 * subnormal then survives arithmetic again. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <fenv.h>
#include <string.h>
#if defined(__x86_64__)
#include <xmmintrin.h>
#endif

#include "fpenv.h"
#include "log_capture.h"
#include "world_internal.h"

static double halve(volatile double x) { return x * 0.5; }

static void test_prepare_resets_flush_and_rounding(void **state) {
  (void)state;
  assert_int_equal(adem_fpenv_faults(), 0u);
#if defined(__x86_64__)
  _mm_setcsr(_mm_getcsr() | 0x8040u);   /* FTZ | DAZ, as crtfastmath.o does */
  assert_true(halve(0x1p-1022) == 0.0); /* flushed */
  unsigned expect = 3u | 4u;
#else
  unsigned expect = 4u;
#endif
  fesetround(FE_UPWARD);
  assert_int_equal(adem_fpenv_faults(), expect);
  adem_world *w = adem_world_create();
  adem_world_set_threads(w, 2);
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  printf("# logged: %s", logged);
  assert_int_equal(adem_fpenv_faults(), 0u);
  assert_true(halve(0x1p-1022) == 0x1p-1023); /* subnormal kept */
  assert_non_null(strstr(logged, "W the floating-point environment"));
#if defined(__x86_64__)
  assert_non_null(strstr(logged, "flush-to-zero denormals-are-zero"));
#endif
  assert_non_null(strstr(logged, "rounding mode"));
  logged[0] = '\0';
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK); /* nothing to reset: silent */
  assert_null(strstr(logged, "floating-point"));
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_prepare_resets_flush_and_rounding, capture_setup,
                                      capture_teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
