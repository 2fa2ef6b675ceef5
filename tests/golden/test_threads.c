/* Claim: the result does not depend on the number of threads, bit for bit (per-contact forces
 * first, per-particle sums second in a fixed order; no atomics on doubles). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "golden/settle_case.h"
#include "world.h"

static adem_case *run_with_threads(int nthreads) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_string(settle_case, "settle.yaml", NULL, 0, &c, &err))
    fail_msg("case does not load: %s", err.message);
  adem_world_set_threads(c->world, nthreads);
  c->world->parallel_min = 0; /* small systems would otherwise stay on one thread */
  if (adem_world_prepare(c->world, &err)) fail_msg("%s", err.message);
  if (adem_world_step(c->world, SETTLE_STEPS, &err)) fail_msg("%s", err.message);
  return c;
}

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

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_one_vs_two_threads),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
