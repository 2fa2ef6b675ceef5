/* The run's ETA (adem_eta): from the recent rate, and flagged rough while it cannot hold. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "adem/adem.h"

/* A run like the pile: 4,000 steps/s while 2,000 spheres fall (no contacts) for 60 s,
 * contacts rising to 8,000 over the next 60 s while the rate drops to 2,300 steps/s, then a
 * dense bed at 2,300 steps/s. One sample a second. */
static double rate_at(double t) {
  if (t < 60.0) return 4000.0;
  if (t < 120.0) return 4000.0 - 1700.0 * (t - 60.0) / 60.0;
  return 2300.0;
}
static double contacts_at(double t) { return t < 60.0 ? 0.0 : t < 120.0 ? 8000.0 * (t - 60.0) / 60.0
                                                                        : 8000.0; }

/* Claim: once the rate has been steady for a window, the ETA is the steps left over the recent
 * rate (within 0.5 %), where the average since the start would be 25 % short; while the
 * contacts rise, and in the first seconds, it is flagged rough. */
static void test_recent_rate(void **state) {
  (void)state;
  adem_eta e;
  adem_eta_init(&e);
  const uint64_t total = 2000000;
  double steps = 0.0;
  int rough = -1;
  for (int t = 0; t <= 300; ++t) {
    adem_eta_add(&e, (double)t, (uint64_t)steps, (size_t)contacts_at(t), 2000);
    double eta = adem_eta_seconds(&e, total, &rough);
    if (t == 0) assert_true(eta < 0.0); /* one sample: no rate yet */
    if (t == 2) assert_int_equal(rough, ADEM_ETA_STARTING);
    if (t == 30) {
      assert_int_equal(rough, ADEM_ETA_STEADY);
      assert_true(fabs(adem_eta_rate(&e) - 4000.0) < 1.0);
    }
    if (t == 90) assert_int_equal(rough, ADEM_ETA_CONTACTS);
    if (t == 200) {
      double left = (double)total - steps;
      double average = steps / 200.0;
      printf("# t = 200 s: ETA %.1f s, truth %.1f s, from the average since the start %.1f s\n",
             eta, left / 2300.0, left / average);
      assert_int_equal(rough, ADEM_ETA_STEADY);
      assert_true(fabs(eta / (left / 2300.0) - 1.0) < 0.005);
      assert_true(left / average < 0.8 * left / 2300.0);
    }
    steps += rate_at(t);
  }
}

/* Claim: particles being added (a pour) make the ETA rough too; the samples kept stay bounded
 * over a long run. */
static void test_pour_and_long_runs(void **state) {
  (void)state;
  adem_eta e;
  adem_eta_init(&e);
  int rough = -1;
  for (int t = 0; t <= 20; ++t) adem_eta_add(&e, t, 1000u * (uint64_t)t, 0, 100 + 50 * (size_t)t);
  assert_true(adem_eta_seconds(&e, 100000, &rough) > 0.0);
  assert_int_equal(rough, ADEM_ETA_PARTICLES);
  for (int t = 21; t < 5000; ++t) adem_eta_add(&e, 0.5 * t, 1000u * (uint64_t)t, 0, 1100);
  assert_true(e.n <= ADEM_ETA_SAMPLES);
  assert_true(fabs(adem_eta_rate(&e) - 2000.0) < 1e-9);
  assert_true(e.wall[(e.head + e.n - 1) % ADEM_ETA_SAMPLES] - e.wall[e.head] >= ADEM_ETA_WINDOW);
  assert_true(adem_eta_seconds(&e, 4999000, &rough) == 0.0);
  assert_int_equal(rough, ADEM_ETA_STEADY);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_recent_rate),
      cmocka_unit_test(test_pour_and_long_runs),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
