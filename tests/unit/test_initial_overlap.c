/* A case may start from overlapping positions (a bed settled by another code) only when it says
 * how much overlap it accepts: limits.initial_overlap, a fraction of the smaller radius. Two
 * spheres overlapping by 5% of their radius: refused by default (the message names the pair and
 * the key), accepted with 0.06, refused again with 0.04. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <string.h>

#include "adem/adem.h"
#include "case_file.h"
#include "case_text.h"

/* Two spheres overlapping by 5% of their radius: tests/cases/initial-overlap.yaml. */
static adem_status prepare_with(const char *set, adem_error *err) {
  adem_case *c = NULL;
  const char *sets[1] = {set};
  adem_status st = adem_case_load_file(case_file_path("initial-overlap"), sets, set ? 1 : 0, &c, err);
  if (!st) st = adem_world_prepare(c->world, err);
  if (!st) st = adem_world_step(c->world, 10, err); /* pushed apart, no blow-up */
  adem_case_free(c);
  return st;
}

static void test_initial_overlap(void **state) {
  (void)state;
  adem_error err;
  assert_int_equal(prepare_with(NULL, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_contains(err.message, "spheres[1]");
  assert_contains(err.message, "limits.initial_overlap");
  assert_int_equal(prepare_with("limits.initial_overlap=0.06", &err), ADEM_OK);
  assert_int_equal(prepare_with("limits.initial_overlap=0.04", &err), ADEM_ERR_INPUT);
  assert_int_equal(prepare_with("limits.initial_overlap=0.7", &err), ADEM_ERR_INPUT); /* > 0.5 */
  printf("# %s\n", err.message);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_initial_overlap)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
