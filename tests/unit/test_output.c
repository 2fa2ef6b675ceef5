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
#include "cli_run.h"
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

/* 27 spheres in a lattice 5..7 cm above a floor, falling onto it. */
static const char *const fall_case =
    "materials:\n"
    "  - {name: glass, density: 2500, youngs_modulus: 1.0e6, poisson_ratio: 0.3, restitution: 0.2}\n"
    "particles:\n"
    "  - {type: lattice, material: glass, radius: 0.004, spacing: 0.01,\n"
    "     min: [0, 0, 0.05], max: [0.03, 0.03, 0.08]}\n"
    "walls:\n"
    "  - {type: plane, name: floor, material: glass, point: [0, 0, 0], normal: [0, 0, 1]}\n"
    "time: {end: 0.2}\n"
    "output:\n"
    "  csv_interval: 0.01\n"
    "  frame_interval: 0\n"
    "  regions:\n"
    "    - {name: top, shape: box, min: [-1, -1, 0.04], max: [1, 1, 1]}\n"
    "    - {name: low_cyl, shape: cylinder, start: [0.015, 0.015, 0], end: [0.015, 0.015, 0.035],\n"
    "       radius: 0.5}\n"
    "    - {name: cube, shape: mesh, file: %s/tests/data/cube_ascii.stl, scale: 0.1,\n"
    "       translate: [-0.02, -0.02, -0.05]}\n";

/* Claim: output.regions counts the particles whose centre is in each region, and their mass, in
 * every CSV row: 27 spheres start in `top` and end, fallen, in the cylinder and the closed mesh
 * (a 0.1 m cube around the floor), with mass 27 m. */
static void test_region_counts(void **state) {
  (void)state;
  if (tmpdir_make("adem_output")) fail_msg("no tmpdir");
  char text[2048];
  snprintf(text, sizeof text, fall_case, ADEM_SOURCE_DIR);
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_string(text, "fall.yaml", NULL, 0, &c, &err)) fail_msg("%s", err.message);
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
  char text[2048];
  snprintf(text, sizeof text, fall_case, ADEM_SOURCE_DIR);
  const char *bad[3][3] = {
      {"{name: cube,", "{name: top,", "duplicate region name `top`"},
      {"radius: 0.5}", "radius: 0.5, min: [0, 0, 0]}", "`min` does not apply to shape `cylinder`"},
      {"cube_ascii.stl", "two_solids.stl", "does not enclose a volume"}};
  for (int k = 0; k < 3; ++k) {
    char *t = replaced(text, bad[k][0], bad[k][1]);
    adem_case *c = NULL;
    adem_error err;
    assert_int_equal(adem_case_load_string(t, "bad.yaml", NULL, 0, &c, &err), ADEM_ERR_INPUT);
    printf("# %s\n", err.message);
    assert_contains(err.message, bad[k][2]);
    assert_contains(err.message, "output.regions[");
    free(t);
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
