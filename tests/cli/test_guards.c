/* The guards a user meets in long runs (docs/reliability.md): a case whose memory estimate
 * exceeds limits.max_memory or what the machine has is refused before anything is allocated;
 * a time step above min(t_collision/5, the contacts' stability limit) is refused unless limits.allow_large_step;
 * a particle that moves more than its radius in a step next to a mesh wall is reported. Each
 * guard has a case that fires it and one that does not. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdbool.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "case_file.h"
#include "cli_run.h"

/* Two glass spheres (r = 1 mm) meeting head-on at 2 m/s, no gravity: the two-sphere collision
 * the step limit was measured on. */
#define pair_case case_file_text("guards-pair") /* tests/cases/guards-pair.yaml */


static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_guards");
}

/* The Hertz collision time `adem check` prints for a case. */
static double collision_time(const char *path) {
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  const char *at = strstr(out, "Hertz collision time t_c");
  assert_non_null(at);
  double tc = 0.0;
  assert_int_equal(sscanf(at, "Hertz collision time t_c %lf", &tc), 1);
  assert_true(tc > 0.0);
  return tc;
}

/* Restitution of the pair run with time.step = dt (and the extra --set): the speed after the
 * collision over the speed before, from the kinetic energy of the first and last CSV rows. */
static double restitution_at(const char *path, double dt, const char *extra) {
  char *out;
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_e' --set time.step=%.9g %s", path,
                        tmpdir, dt, extra),
                   0);
  char *csv = path_in_tmp("out_e/timeseries.csv");
  double k0 = csv_value(csv, 1, "kinetic_J");
  int rows = 0;
  FILE *f = fopen(csv, "r");
  assert_non_null(f);
  char line[4096];
  while (fgets(line, sizeof line, f)) rows++;
  fclose(f);
  double k1 = csv_value(csv, rows - 1, "kinetic_J");
  free(csv);
  return sqrt(k1 / k0);
}

/* Claim: a step up to t_c/5 is accepted with a warning that gives the factor between the
 * proposal and the limit, and keeps the restitution of the collision within 2 % of the
 * material's 0.9 (measured worst 1.6 % over seven contact phases); a step above it is refused
 * with exit 2 and a message naming the file, line, column, key, the limit and the way out; with
 * limits.allow_large_step it runs, and at t_c/2 the collision is off by more than 5 % (which is
 * what the limit keeps out); a stage whose materials are stiffer is checked against its own
 * limit. */
static void test_step_limit(void **state) {
  (void)state;
  char *path = strdup(case_file_path("guards-pair"));
  double tc = collision_time(path);
  char *out;
  /* below the limit: runs, warns with both factors */
  double e5 = restitution_at(path, tc / 5.0 * 0.999, "");
  assert_true(fabs(e5 - 0.9) < 0.02 * 0.9);
  assert_int_equal(adem(&out, "check '%s' --set time.step=%.9g", path, tc / 5.0 * 0.999), 0);
  assert_mentions(out, "the limit t_collision/5");
  assert_mentions(out, "10.0x the proposal");
  /* above it: refused, in the case file and from --set */
  char *text = replaced(pair_case, "  reference_speed: 2\n", "  reference_speed: 2\n  step: 6.0e-5\n");
  char *big = write_case("big_step.yaml", text);
  assert_int_equal(adem(&out, "check '%s'", big), 2);
  assert_mentions(out, "big_step.yaml:23:9");
  assert_mentions(out, "time.step");
  assert_mentions(out, "limit t_collision/5");
  assert_mentions(out, "limits.allow_large_step: true");
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_big'", big, tmpdir), 2);
  assert_mentions(out, "limit t_collision/5");
  assert_int_equal(adem(&out, "check '%s' --set time.step=%.9g", path, tc / 2.0), 2);
  assert_mentions(out, "--set time.step");
  /* allowed: runs with a warning, and the collision is visibly wrong */
  assert_int_equal(adem(&out, "check '%s' --set limits.allow_large_step=true", big), 0);
  assert_mentions(out, "above it (limits.allow_large_step)");
  double e2 = restitution_at(path, tc / 2.0, "--set limits.allow_large_step=true");
  assert_true(fabs(e2 - 0.9) > 0.05 * 0.9);
  /* a stage that makes the pair 100 times stiffer (t_c 6.3 times shorter) under the same step */
  assert_int_equal(adem(&out, "check '%s' --set time.step=3e-5 --set 'stages=[{name: soft, "
                              "duration: 0.001}, {name: stiff, set: {materials.glass.youngs_modulus: "
                              "1.0e9}}]'",
                        path),
                   2);
  assert_mentions(out, "stages[1] (`stiff`)");
  assert_mentions(out, "5.33x the limit t_collision/5");
  /* strict validation of the key */
  assert_int_equal(adem(&out, "check '%s' --set limits.allow_large_step=3", path), 2);
  assert_mentions(out, "limits.allow_large_step");
  assert_mentions(out, "true or false");
  free(text);
  free(big);
  free(path);
}

/* Claim: `adem check` prints the estimate and the limit it was held against; a case whose
 * estimate exceeds limits.max_memory is refused (exit 2) before its particles are made, naming
 * the set, the figure and the limit; so is a pour whose total exceeds what the machine has (10^12
 * particles, some 10^15 bytes: more than any machine); the key itself is validated strictly. */
static void test_memory_limit(void **state) {
  (void)state;
  char *path = strdup(case_file_path("guards-pair"));
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  assert_mentions(out, "memory       ");
  assert_mentions(out, "2 particles");
  assert_mentions(out, "available on this machine");
  /* the two spheres need some 30 KiB: a limit of 10^6 B passes, 10^4 B does not */
  assert_int_equal(adem(&out, "check '%s' --set limits.max_memory=1e6", path), 0);
  assert_mentions(out, "(limits.max_memory)");
  char *text = replaced(pair_case, "  max_overlap_ratio: 0.5\n", "  max_overlap_ratio: 0.5\n  max_memory: 1.0e4\n");
  char *small = write_case("mem_small.yaml", text);
  assert_int_equal(adem(&out, "check '%s'", small), 2);
  assert_mentions(out, "mem_small.yaml:12:5: particles[0]");
  assert_mentions(out, "the run would need about");
  assert_mentions(out, "limits.max_memory allows");
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_mem'", small, tmpdir), 2);
  assert_mentions(out, "limits.max_memory");
  /* a random fill is refused before it is filled: 10^6 spheres asked in a box, 1 MB allowed */
  assert_int_equal(adem(&out, "check '%s' --set limits.max_memory=1e6 --set "
                              "'particles=[{type: random, material: glass, count: 1000000, radius: "
                              "{distribution: constant, value: 0.0001}, min: [0, 0, 0], max: [1, 1, 1]}]'",
                        path),
                   2);
  assert_mentions(out, "particles[0]");
  assert_mentions(out, "1e+06 particles");
  /* a pour of 10^12 particles against what the machine has */
  assert_int_equal(adem(&out, "check '%s' --set 'pours=[{material: glass, rate: 1.0e12, end: 1, "
                              "radius: {distribution: constant, value: 0.0001}, region: {shape: box, "
                              "min: [0, 0, 0], max: [0.01, 0.01, 0.01]}}]'",
                        path),
                   2);
  assert_mentions(out, "pours[0]");
  assert_mentions(out, "MemAvailable");
  /* strict validation */
  assert_int_equal(adem(&out, "check '%s' --set limits.max_memory=lots", path), 2);
  assert_mentions(out, "limits.max_memory");
  assert_mentions(out, "expected `auto` or a number > 0");
  assert_int_equal(adem(&out, "check '%s' --set limits.max_memory=-1", path), 2);
  assert_mentions(out, "out of range");
  free(text);
  free(small);
  free(path);
}

/* Claim: a sphere that moves twice its radius in a step through a mesh wall is reported: a
 * warning with its id, position and time, and a summary line at the end of the run; the same
 * sphere at a tenth of the speed (0.4 mm a step, bouncing off the wall) is not. */
static void test_tunnelling(void **state) {
  (void)state;
  char *path = strdup(case_file_path("guards-tunnel"));
  char *out;
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_tunnel'", path, tmpdir), 0);
  assert_mentions(out, "particle id 0 moved 0.004 m in one step");
  assert_mentions(out, "next to a mesh wall at t = 0.00026 s");
  assert_mentions(out, "tunnelling: 2 times");
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_slow' --set time.end=0.004 --set "
                              "'particles.0.spheres=[{position: [0.05, 0.05, 0.05], radius: 0.002, "
                              "velocity: [20, 0, 0]}]'",
                        path, tmpdir),
                   0);
  assert_null(strstr(out, "tunnelling"));
  assert_null(strstr(out, "moved"));
  /* it did hit the wall (t = 2.5 ms), losing energy in the contact */
  char *csv = path_in_tmp("out_slow/timeseries.csv");
  assert_true(csv_value(csv, 40, "dissipated_J") > 0.0);
  free(csv);
  free(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_step_limit),
      cmocka_unit_test(test_memory_limit),
      cmocka_unit_test(test_tunnelling),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
