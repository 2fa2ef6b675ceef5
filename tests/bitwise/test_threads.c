/* Claims: the result does not depend on the number of threads, bit for bit (per-contact forces
 * first, per-particle sums second in a fixed order; no atomics on doubles); and the energy
 * balance is bookkeeping only: switched off, the motion is bit for bit the same. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "bitwise/settle_case.h"
#include "world_internal.h"

static adem_case *run_as(int nthreads, bool balance) {
  adem_case *c = settle_load(NULL, 0);
  adem_error err;
  adem_world_set_energy_balance(c->world, balance);
  adem_world_set_threads(c->world, nthreads);
  c->world->parallel_min = 0; /* small systems would otherwise stay on one thread */
  if (adem_world_prepare(c->world, &err)) fail_msg("%s", err.message);
  if (adem_world_step(c->world, SETTLE_STEPS, &err)) fail_msg("%s", err.message);
  return c;
}

static adem_case *run_with_threads(int nthreads) { return run_as(nthreads, true); }

static void test_one_vs_two_threads(void **state) {
  (void)state;
  adem_case *one = run_with_threads(1);
  adem_case *two = run_with_threads(2);
  adem_case *three = run_with_threads(3);
  printf("# %zu loaded contacts after %d steps\n", settle_loaded_contacts(one->world), SETTLE_STEPS);
  assert_true(settle_loaded_contacts(one->world) > 100);
  const char *what = "";
  if (!settle_same_state(one->world, two->world, &what)) fail_msg("2 threads differ in %s", what);
  if (!settle_same_state(one->world, three->world, &what)) fail_msg("3 threads differ in %s", what);
  adem_case_free(one);
  adem_case_free(two);
  adem_case_free(three);
}

/* The switch must leave every force and motion as it is (the bookkeeping only reads them), and
 * the balance must then say it is not kept (NaN) rather than report a zero dissipation. A
 * bookkeeping that fed back into the forces, or a sum that skipped a force along with the
 * dissipation, fails the bitwise comparison. */
static void test_energy_balance_off_changes_no_motion(void **state) {
  (void)state;
  adem_case *on = run_as(1, true);
  adem_case *off = run_as(1, false);
  adem_case *off2 = run_as(2, false);
  const char *what = "";
  if (!settle_same_state(on->world, off->world, &what)) fail_msg("balance off differs in %s", what);
  if (!settle_same_state(on->world, off2->world, &what))
    fail_msg("balance off, 2 threads, differs in %s", what);
  adem_diagnostics d_on = adem_world_diagnostics(on->world);
  adem_diagnostics d_off = adem_world_diagnostics(off->world);
  printf("# dissipated %.6e J of %.6e J; balance error %.3e J; off: %g\n", d_on.dissipated,
         d_on.initial, d_on.balance_error, d_off.dissipated);
  assert_true(d_on.dissipated > 0.0 && isfinite(d_on.balance_error));
  assert_true(isnan(d_off.dissipated) && isnan(d_off.wall_work) && isnan(d_off.balance_error));
  assert_true(d_off.kinetic == d_on.kinetic);
  adem_case_free(on);
  adem_case_free(off);
  adem_case_free(off2);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_one_vs_two_threads),
      cmocka_unit_test(test_energy_balance_off_changes_no_motion),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
