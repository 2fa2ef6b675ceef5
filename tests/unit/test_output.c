/* What a run's CSV looks like to the programs that read it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "adem/adem.h"
#include "output.h"

/* A box wall (planes bin.xmin ... bin.zmax) around one sphere. */
static const char *const box_case =
    "materials:\n"
    "  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}\n"
    "particles:\n"
    "  - type: list\n"
    "    material: glass\n"
    "    spheres: [{position: [0.5, 0.5, 0.5], radius: 0.01}]\n"
    "walls:\n"
    "  - {type: box, name: bin, material: glass, min: [0, 0, 0], max: [1, 1, 1]}\n"
    "  - {type: plane, name: lid-top, material: glass, point: [0, 0, 2], normal: [0, 0, -1]}\n"
    "time: {end: 0.01}\n";

/* Claim: every column name of the CSV header is one numpy's genfromtxt(names=True) keeps as it
 * is (letters, digits and `_` only): the dot of `bin.xmin` becomes `__`. */
static void test_csv_names_survive_numpy(void **state) {
  (void)state;
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_string(box_case, "box.yaml", NULL, 0, &c, &err)) fail_msg("%s", err.message);
  char *header = adem_output_csv_header(c->world, NULL);
  assert_non_null(header);
  printf("# %s", header);
  assert_non_null(strstr(header, ",bin__xmin_fx_N,bin__xmin_fy_N,bin__xmin_fz_N,"));
  assert_non_null(strstr(header, ",bin__zmax_fz_N"));
  assert_null(strchr(header, '.'));
  /* a `-` of a name is kept (names allow it); the docs say numpy drops it */
  assert_non_null(strstr(header, ",lid-top_fz_N"));
  free(header);
  adem_case_free(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_csv_names_survive_numpy),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
