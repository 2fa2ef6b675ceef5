/* adem calibrate (src/studies/calibrate.c, app/cmd_calibrate.c): it recovers a value from a
 * target that adem itself produced, writes its four outputs, resumes without running again, and
 * names a bad --vary key or --target. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdbool.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "case_file.h"
#include "cli_run.h"

/* Eight glass spheres of 5 mm radius at rest on a floor (placed touching it), soft and damped so
 * that the load settles within a tenth of the run: the floor's steady load is their weight,
 * 8 rho (4/3) pi r^3 g, proportional to the density, the value varied. */
#define load_case case_file_text("calibrate-load") /* tests/cases/calibrate-load.yaml */

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_calibrate");
}

/* Mean of a CSV column over the rows with time in [t0, t1]. */
static double csv_mean(const char *path, const char *name, double t0, double t1) {
  double sum = 0.0;
  int n = 0;
  for (int row = 1; row < 100000; ++row) {
    FILE *f = fopen(path, "r");
    int lines = 0;
    char line[1 << 14];
    while (fgets(line, sizeof line, f)) ++lines;
    fclose(f);
    if (row >= lines) break;
    double t = csv_value(path, row, "time_s");
    if (t >= t0 && t <= t1) {
      sum += csv_value(path, row, name);
      ++n;
    }
  }
  assert_true(n > 2);
  return sum / n;
}

/* Claim: with the floor load of a run at density 2345 kg/m^3 as the target (tolerance 0.2 %),
 * adem calibrate over 1000..4000 finds 2345 within 0.3 % (the load is proportional to the
 * density: 0.2 % of load is 0.2 % of density, plus the transient's trace in the window), writes
 * runs.csv, response.png, best.yaml (which loads, with the density found) and summary.md, and a
 * second call with --resume reads every run back instead of running it. */
static void test_recovers_density(void **state) {
  (void)state;
  char *path = write_case("load.yaml", load_case);
  char *out;
  assert_int_equal(adem(&out, "run '%s' --quiet --set materials.glass.density=2345 --out '%s/ref'",
                        path, tmpdir),
                   0);
  char *csv = path_in_tmp("ref/timeseries.csv");
  double load = csv_mean(csv, "floor_fz_N", 0.15, 0.2);
  double weight = 8 * 2345 * 4.0 / 3.0 * 3.14159265358979 * 0.005 * 0.005 * 0.005 * 9.81;
  printf("# reference load %.6f N (weight %.6f N)\n", load, weight);
  /* at rest the load is the weight (the CSV has the force on the wall: downwards) */
  assert_true(fabs(-load - weight) < 1e-3 * weight);
  free(csv);
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=1000:4000 --target "
                              "load:floor.z=%.9g+-%.9g --jobs 2 --out '%s/cal'",
                        path, load, -0.002 * load, tmpdir),
                   0);
  assert_true(mentions(out, "found"));
  char *runs = path_in_tmp("cal/runs.csv");
  int nrun = 0;
  double best = NAN, bestd = INFINITY;
  for (int row = 1; row < 50; ++row) {
    FILE *f = fopen(runs, "r");
    char line[4096];
    int lines = 0;
    while (fgets(line, sizeof line, f)) ++lines;
    fclose(f);
    if (row >= lines) break;
    ++nrun;
    double x = csv_value(runs, row, "value"), y = csv_value(runs, row, "measured");
    printf("#   run %d: density %.6f -> load %.6f N\n", row, x, y);
    if (fabs(y - load) < bestd) {
      bestd = fabs(y - load);
      best = x;
    }
  }
  printf("# found density %.4f (target 2345) in %d runs\n", best, nrun);
  assert_true(fabs(best - 2345.0) < 0.003 * 2345.0);
  assert_true(nrun >= 3 && nrun <= 12);
  char *png = path_in_tmp("cal/response.png"), *yaml = path_in_tmp("cal/best.yaml"),
       *md = path_in_tmp("cal/summary.md");
  FILE *f = fopen(md, "r");
  assert_non_null(f);
  fclose(f);
  if (system("command -v gnuplot > /dev/null 2>&1") == 0) {
    f = fopen(png, "r");
    assert_non_null(f);
    fclose(f);
  }
  /* best.yaml loads (run from the folder of the case: it names no file) */
  assert_int_equal(adem(&out, "check '%s'", yaml), 0);
  /* resume: every run read back, none run again, the same answer */
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=1000:4000 --target "
                              "load:floor.z=%.9g+-%.9g --jobs 2 --out '%s/cal' --resume",
                        path, load, -0.002 * load, tmpdir),
                   0);
  assert_true(mentions(out, "measured before"));
  assert_false(mentions(out, "calibrate: run 1: "));
  /* without --resume the folder is refused */
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=1000:4000 --target "
                              "load:floor.z=%.9g+-%.9g --out '%s/cal'",
                        path, load, -0.002 * load, tmpdir),
                   2);
  assert_true(mentions(out, "--resume"));
  free(runs);
  free(png);
  free(yaml);
  free(md);
  free(path);
}

/* Claim: a bulk-density target (the region's mass over its volume, 0.08 x 0.04 x 0.01 m holding
 * the 8 spheres: 0.1309 rho) of 0.1309 x 2345 kg/m^3 +- 0.1 % is met at 2345 within 0.1 %. */
static void test_density_target(void **state) {
  (void)state;
  char *path = write_case("load3.yaml", load_case);
  char *out;
  double frac = 8 * 4.0 / 3.0 * 3.14159265358979 * 0.005 * 0.005 * 0.005 / (0.08 * 0.04 * 0.01);
  double target = frac * 2345.0;
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=1000:4000 --target "
                              "density:bed=%.9g+-%.9g --out '%s/dens'",
                        path, target,
                        0.001 * target, tmpdir),
                   0);
  char *runs = path_in_tmp("dens/runs.csv");
  double best = NAN;
  for (int row = 1; row < 20; ++row) {
    FILE *f = fopen(runs, "r");
    char line[4096];
    int lines = 0;
    while (fgets(line, sizeof line, f)) ++lines;
    fclose(f);
    if (row >= lines) break;
    if (csv_value(runs, row, "within") == 1.0) best = csv_value(runs, row, "value");
  }
  printf("# density target %.4f kg/m^3 (solid fraction %.4f): found %.4f\n", target, frac, best);
  assert_true(fabs(best - 2345.0) < 0.001 * 2345.0);
  free(runs);
  free(path);
}

/* Claim: a --vary key that is not in the case, a value out of range and a bad --target are
 * refused with exit 2 before any run, and the message names the key or the target. */
static void test_bad_options(void **state) {
  (void)state;
  char *path = write_case("load2.yaml", load_case);
  char *out;
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.densty=1000:4000 --target "
                              "load:floor.z=1+-0.1 --out '%s/bad1'",
                        path, tmpdir),
                   2);
  assert_true(mentions(out, "densty") && mentions(out, "--vary"));
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.sand.density=1000:4000 --target "
                              "load:floor.z=1+-0.1 --out '%s/bad2'",
                        path, tmpdir),
                   2);
  assert_true(mentions(out, "sand"));
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=-5:4000 --target "
                              "load:floor.z=1+-0.1 --out '%s/bad3'",
                        path, tmpdir),
                   2);
  assert_true(mentions(out, "density"));
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=1000:4000 --target "
                              "angle:floor=1+-0.1 --out '%s/bad4'",
                        path, tmpdir),
                   2);
  assert_true(mentions(out, "angle"));
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=1000:4000 --target "
                              "repose:steepest=40+-1 --out '%s/bad5'",
                        path, tmpdir),
                   2);
  assert_true(mentions(out, "steepest"));
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=4000:1000 --target "
                              "load:floor=1+-0.1 --out '%s/bad6'",
                        path, tmpdir),
                   2);
  assert_int_equal(adem(&out, "calibrate '%s' --vary materials.glass.density=1000:4000 --target "
                              "density:nowhere=1+-0.1 --out '%s/bad7'",
                        path, tmpdir),
                   2);
  assert_true(mentions(out, "nowhere"));
  free(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_recovers_density),
      cmocka_unit_test(test_density_target),
      cmocka_unit_test(test_bad_options),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
