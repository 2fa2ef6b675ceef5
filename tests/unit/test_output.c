/* What a run's CSV looks like to the programs that read it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include <math.h>

#include "adem/adem.h"
#include "case_file.h"
#include "cli_run.h"
#include "output.h"

/* A box wall (planes bin.xmin ... bin.zmax) around one sphere: tests/cases/output-box.yaml. */

/* Claim: every column name of the CSV header is one numpy's genfromtxt(names=True) keeps as it
 * is (letters, digits and `_` only): the dot of `bin.xmin` becomes `__`. */
static void test_csv_names_survive_numpy(void **state) {
  (void)state;
  adem_case *c = case_file_load("output-box", NULL, 0);
  char *header = adem_output_csv_header(c->world, NULL, NULL);
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

/* 27 spheres in a lattice 5..7 cm above a floor, falling onto it: tests/cases/output-fall.yaml. */

/* Claim: output.regions counts the particles whose centre is in each region, and their mass, in
 * every CSV row: 27 spheres start in `top` and end, fallen, in the cylinder and the closed mesh
 * (a 0.1 m cube around the floor), with mass 27 m. */
static void test_region_counts(void **state) {
  (void)state;
  if (tmpdir_make("adem_output")) fail_msg("no tmpdir");
  adem_case *c = case_file_load("output-fall", NULL, 0);
  adem_error err;
  snprintf(c->output.dir, sizeof c->output.dir, "%s/fall", tmpdir);
  assert_int_equal(adem_world_particle_count(c->world), 27);
  if (adem_run(c, NULL, &err)) fail_msg("%s", err.message);
  adem_case_free(c);
  char *csv = path_in_tmp("fall/timeseries.csv");
  double m = 2500.0 * 4.0 / 3.0 * 3.14159265358979323846 * 0.004 * 0.004 * 0.004;
  printf("# first row: top %g, cylinder %g, cube %g; last row: %g %g %g (mass %g kg, 27 m = %g)\n",
         csv_value(csv, 1, "top_count"), csv_value(csv, 1, "low_cyl_count"),
         csv_value(csv, 1, "cube_count"), csv_value(csv, 21, "top_count"),
         csv_value(csv, 21, "low_cyl_count"), csv_value(csv, 21, "cube_count"),
         csv_value(csv, 21, "cube_mass_kg"), 27 * m);
  assert_true(csv_value(csv, 1, "top_count") == 27.0);
  assert_true(fabs(csv_value(csv, 1, "top_mass_kg") / (27 * m) - 1.0) < 1e-12);
  assert_true(csv_value(csv, 1, "low_cyl_count") == 0.0);
  assert_true(csv_value(csv, 1, "cube_count") == 0.0);
  assert_true(csv_value(csv, 21, "top_count") == 0.0);
  assert_true(csv_value(csv, 21, "low_cyl_count") == 27.0);
  assert_true(csv_value(csv, 21, "cube_count") == 27.0);
  assert_true(fabs(csv_value(csv, 21, "cube_mass_kg") / (27 * m) - 1.0) < 1e-12);
  free(csv);
  tmpdir_remove();
}

/* Claim: bad regions are refused naming the key: an open surface, a duplicate name, a key of
 * another shape. */
static void test_region_errors(void **state) {
  (void)state;
  const char *bad[3][2] = {
      {"output.regions.cube.name=top", "duplicate region name `top`"},
      {"output.regions.low_cyl.min=[0, 0, 0]", "`min` does not apply to shape `cylinder`"},
      {"output.regions.cube.file=" ADEM_SOURCE_DIR "/tests/data/two_solids.stl",
       "does not enclose a volume"}};
  for (int k = 0; k < 3; ++k) {
    adem_case *c = NULL;
    adem_error err;
    assert_int_equal(adem_case_load_file(case_file_path("output-fall"), bad[k], 1, &c, &err),
                     ADEM_ERR_INPUT);
    printf("# %s\n", err.message);
    assert_contains(err.message, bad[k][1]);
    assert_contains(err.message, "output.regions[");
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_csv_names_survive_numpy),
      cmocka_unit_test(test_region_counts),
      cmocka_unit_test(test_region_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
