/* The adem command on bad input and on a failing run: the exit status says what kind of failure
 * it was (2 bad input, 3 run failed) and the message names the problem, so that a user can fix
 * the case without reading the source. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdbool.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "case_file.h"
#include "cli_run.h"

/* A valid case: two glass spheres above a floor. Tests derive bad cases by replacing text. */
#define base_case case_file_text("cli-two-spheres") /* tests/cases/cli-two-spheres.yaml */

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_cli");
}

/* Runs `adem check` and `adem run` on a case made from base_case by one replacement; both must
 * exit 2 and name the problem. */
static void expect_bad_case(const char *from, const char *to, const char *word1, const char *word2) {
  char *text = replaced(base_case, from, to);
  char *path = write_case("bad.yaml", text);
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 2);
  assert_mentions(out, "error");
  assert_mentions(out, word1);
  if (word2) assert_mentions(out, word2);
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_bad'", path, tmpdir), 2);
  assert_mentions(out, word1);
  free(text);
  free(path);
}

/* Claim: the valid base case passes check and runs (exit 0), so the failures below come from
 * the one change each makes. */
static void test_valid_case(void **state) {
  (void)state;
  char *path = strdup(case_file_path("cli-two-spheres"));
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  assert_mentions(out, "collision time");
  assert_mentions(out, "rayleigh");
  assert_mentions(out, "glass-glass");
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_ok'", path, tmpdir), 0);
  char *f = path_in_tmp("out_ok/frames/particles_000000.vtu");
  assert_true(file_exists(f));
  free(f);
  f = path_in_tmp("out_ok/particles.pvd");
  assert_true(file_exists(f));
  free(f);
  f = path_in_tmp("out_ok/timeseries.csv");
  assert_true(file_exists(f));
  free(f);
  f = path_in_tmp("out_ok/checkpoint");
  assert_true(file_exists(f));
  free(f);
  /* and it resumes from its final checkpoint without doing anything */
  assert_int_equal(adem(&out, "run --quiet --resume '%s/out_ok/checkpoint'", tmpdir), 0);
  /* or goes on to a later end; other keys are refused, naming those that may change */
  assert_int_equal(adem(&out, "run --resume '%s/out_ok' --set time.end=0.002", tmpdir), 0);
  assert_mentions(out, "done: t = 0.002");
  f = path_in_tmp("out_ok/timeseries.csv");
  assert_true(fabs(csv_value(f, 22, "time_s") - 0.002) < 1e-5); /* the last step: at or just after */
  free(f);
  assert_int_equal(adem(&out, "run --resume '%s/out_ok' --set materials.glass.friction=0.1", tmpdir), 2);
  assert_mentions(out, "may change only time.end");
  assert_int_equal(adem(&out, "run --resume '%s/out_ok' --set time.end=0.0015", tmpdir), 2);
  assert_mentions(out, "later end");
  /* a run that may end early on its condition says so in its ETA and in its last line */
  assert_int_equal(adem(&out, "run '%s' --out '%s/out_until' --set time.end=0.5 "
                              "--set 'time.until={kinetic_energy_per_particle: 1.0e-3, for: 0.001}'",
                        path, tmpdir),
                   0);
  assert_mentions(out, "fewer if time.until is met");
  assert_mentions(out, "until: E_k "); /* the last progress line: the value against the threshold */
  assert_mentions(out, "J/particle");
  assert_mentions(out, "time.until met: kinetic energy per particle");
  assert_mentions(out, "the run ends");
  free(path);
}

static void test_help_and_version(void **state) {
  (void)state;
  char *out;
  assert_int_equal(adem(&out, "--help"), 0);
  assert_mentions(out, "exit status");
  assert_mentions(out, "triangle-mesh walls");
  assert_mentions(out, "adem run");
  assert_int_equal(adem(&out, "run --help"), 0);
  assert_mentions(out, "--resume");
  assert_mentions(out, "--threads");
  assert_int_equal(adem(&out, "check --help"), 0);
  assert_mentions(out, "rayleigh");
  assert_int_equal(adem(&out, "--version"), 0);
  assert_mentions(out, "adem 0.");
  assert_int_equal(adem(&out, "frobnicate"), 2);
  assert_mentions(out, "unknown command");
  assert_int_equal(adem(&out, "run --no-such-option x.yaml"), 2);
  assert_mentions(out, "--no-such-option");
  assert_int_equal(adem(&out, "run x.yaml --threads zero"), 2);
  assert_mentions(out, "--threads");
}

static void test_unknown_key(void **state) {
  (void)state;
  expect_bad_case("name: cli\n", "name: cli\ncolour: red\n", "colour", NULL);
  /* other codes' names for our keys get the key, where edit distance would not find it */
  expect_bad_case("    friction: 0.3\n", "    friction: 0.3\n    rolling_resistance: 0.2\n",
                  "rolling_resistance", "did you mean `rolling_friction`");
  expect_bad_case("    restitution: 0.5\n", "    coefficient_of_restitution: 0.5\n",
                  "coefficient_of_restitution", "did you mean `restitution`");
  expect_bad_case("    youngs_modulus: 1.0e7\n", "    youngs: 1.0e7\n", "youngs",
                  "did you mean `youngs_modulus`");
  /* a synonym is offered only where its key is allowed: `time` has no rolling_friction */
  char *text = replaced(base_case, "  end: 0.001\n", "  end: 0.001\n  rolling_resistance: 1\n");
  char *path = write_case("bad.yaml", text);
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 2);
  assert_false(mentions(out, "did you mean"));
  free(text);
  free(path);
}

static void test_wrong_type(void **state) {
  (void)state;
  expect_bad_case("  end: 0.001\n", "  end: soon\n", "end", "soon");
}

static void test_missing_required(void **state) {
  (void)state;
  expect_bad_case("  end: 0.001\n", "  step: auto\n", "end", NULL);
}

static void test_radius_not_positive(void **state) {
  (void)state;
  expect_bad_case("radius: 0.001}", "radius: -0.001}", "radius", NULL);
  expect_bad_case("radius: 0.001}", "radius: 0}", "radius", NULL);
}

static void test_density_not_positive(void **state) {
  (void)state;
  expect_bad_case("density: 2500", "density: 0", "density", NULL);
}

static void test_poisson_out_of_range(void **state) {
  (void)state;
  expect_bad_case("poisson_ratio: 0.3", "poisson_ratio: 0.6", "poisson", "0.6");
}

static void test_restitution_out_of_range(void **state) {
  (void)state;
  expect_bad_case("restitution: 0.5", "restitution: 0", "restitution", NULL);
  expect_bad_case("restitution: 0.5", "restitution: 1.5", "restitution", "1.5");
}

static void test_overlapping_particles(void **state) {
  (void)state;
  expect_bad_case("[0.005, 0, 0.01]", "[0.0015, 0, 0.01]", "overlap", NULL);
}

static void test_particle_outside_walls(void **state) {
  (void)state;
  expect_bad_case("[0.005, 0, 0.01]", "[0.005, 0, -0.01]", "outside", "floor");
}

static void test_missing_file(void **state) {
  (void)state;
  char *out;
  assert_int_equal(adem(&out, "check '%s/no_such_case.yaml'", tmpdir), 2);
  assert_mentions(out, "no_such_case.yaml");
  assert_int_equal(adem(&out, "run '%s/no_such_case.yaml'", tmpdir), 2);
  assert_mentions(out, "no_such_case.yaml");
  assert_int_equal(adem(&out, "run --resume '%s/no_such_folder/checkpoint'", tmpdir), 2);
  assert_mentions(out, "no_such_folder");
}

/* A file that is not a checkpoint, and a checkpoint cut short, are refused with exit 2. */
static void test_bad_checkpoint(void **state) {
  (void)state;
  char *path = strdup(case_file_path("cli-two-spheres"));
  char *out;
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_ck'", path, tmpdir), 0);
  assert_int_equal(adem(&out, "run --resume '%s'", path), 2);
  assert_mentions(out, "not a");
  char cmd[2048];
  snprintf(cmd, sizeof cmd, "head -c 300 '%s/out_ck/checkpoint' > '%s/out_ck/cut' && mv '%s/out_ck/cut' '%s/out_ck/checkpoint'",
           tmpdir, tmpdir, tmpdir, tmpdir);
  assert_int_equal(system(cmd), 0);
  assert_int_equal(adem(&out, "run --resume '%s/out_ck'", tmpdir), 2);
  assert_mentions(out, "truncated");
  free(path);
}

static void test_output_not_writable(void **state) {
  (void)state;
  char *path = strdup(case_file_path("cli-two-spheres"));
  char *out;
  assert_int_equal(adem(&out, "run '%s' --out /proc/adem_cannot_write", path), 2);
  assert_mentions(out, "/proc/adem_cannot_write");
  assert_mentions(out, "cannot be written");
  /* a folder below a regular file */
  assert_int_equal(adem(&out, "run '%s' --out '%s/sub'", path, path), 2);
  assert_mentions(out, "cannot be written");
  assert_mentions(out, "not a directory");
  free(path);
}

/* Claim: a run that blows up exits 3, names the particle and the time, and keeps the frames
 * and the checkpoint written before the failure. Two spheres meet head-on at 40 m/s with an
 * overlap limit of 0.1 % of the radius. */
static void test_runtime_failure(void **state) {
  (void)state;
  const char *path = case_file_path("cli-two-spheres");
  char *out;
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_boom' --set 'particles.0.spheres=["
                              "{position: [0, 0, 0.01], radius: 0.001, velocity: [20, 0, 0]}, "
                              "{position: [0.005, 0, 0.01], radius: 0.001, velocity: [-20, 0, 0]}]' "
                              "--set 'gravity=[0, 0, 0]' --set limits.max_overlap_ratio=0.001 "
                              "--set output.checkpoint_interval=0.00002 --set output.frame_interval=0.00002",
                        path, tmpdir),
                   3);
  assert_mentions(out, "error");
  assert_mentions(out, "particle id");
  assert_mentions(out, "t = ");
  char *f = path_in_tmp("out_boom/frames/particles_000000.vtu");
  assert_true(file_exists(f));
  free(f);
  f = path_in_tmp("out_boom/checkpoint");
  assert_true(file_exists(f));
  free(f);
  /* resuming replays the same failure: exit 3 again */
  assert_int_equal(adem(&out, "run --quiet --resume '%s/out_boom'", tmpdir), 3);
}

/* Claim: the README's first paragraph claims no more than `adem validate --list` reproduces:
 * every figure of the list is named there, and a result the list lacks (the angle of repose,
 * the ballast's lateral resistance) is said to be not reproduced yet wherever it is named. */
static void test_readme_claims(void **state) {
  (void)state;
  char readme[512];
  snprintf(readme, sizeof readme, "%s/README.md", ADEM_SOURCE_DIR);
  FILE *f = fopen(readme, "r");
  assert_non_null(f);
  static char text[1 << 16];
  text[fread(text, 1, sizeof text - 1, f)] = '\0';
  fclose(f);
  char *para = strstr(text, "\n\n"); /* after the title */
  assert_non_null(para);
  para += 2;
  char *end = strstr(para, "\n\n");
  assert_non_null(end);
  *end = '\0';
  for (char *c = para; *c; ++c)
    if (*c == '\n') *c = ' ';
  char *out;
  assert_int_equal(adem(&out, "validate --list"), 0);
  static char list[1 << 14];
  snprintf(list, sizeof list, "%s", out);
  /* every figure the list names is in the paragraph's figures of its paper */
  const char *papers[2][2] = {{"haervig-fig", "Hærvig"}, {"irazabal-fig", "Irazábal"}};
  for (int p = 0; p < 2; ++p) {
    const char *figs = strstr(para, papers[p][1]);
    assert_non_null(figs);
    figs = strstr(figs, "Figs ");
    assert_non_null(figs);
    char numbers[128];
    snprintf(numbers, sizeof numbers, "%.*s", (int)strcspn(figs, ")"), figs);
    for (const char *l = strstr(list, papers[p][0]); l; l = strstr(l + 1, papers[p][0])) {
      long fig = strtol(l + strlen(papers[p][0]), NULL, 10);
      bool named = false;
      for (const char *c = numbers; *c; ++c) /* every whole number written after "Figs " */
        if (*c >= '0' && *c <= '9' && (c == numbers || c[-1] < '0' || c[-1] > '9'))
          named |= strtol(c, NULL, 10) == fig;
      if (!named) fail_msg("the README does not name Fig. %ld of %s: %s", fig, papers[p][1], numbers);
    }
  }
  /* results the list lacks are named only as not reproduced yet */
  const char *topics[2][2] = {{"angle of repose", "repose"}, {"ballast lateral resistance", "ballast"}};
  for (int k = 0; k < 2; ++k) {
    if (mentions(list, topics[k][1])) continue;
    for (const char *at = strstr(para, topics[k][0]); at; at = strstr(at + 1, topics[k][0])) {
      char window[200];
      snprintf(window, sizeof window, "%.160s", at);
      if (!strstr(window, "not reproduced"))
        fail_msg("the README claims the %s, which adem validate --list lacks: %s", topics[k][0], at);
    }
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_valid_case),
      cmocka_unit_test(test_help_and_version),
      cmocka_unit_test(test_unknown_key),
      cmocka_unit_test(test_wrong_type),
      cmocka_unit_test(test_missing_required),
      cmocka_unit_test(test_radius_not_positive),
      cmocka_unit_test(test_density_not_positive),
      cmocka_unit_test(test_poisson_out_of_range),
      cmocka_unit_test(test_restitution_out_of_range),
      cmocka_unit_test(test_overlapping_particles),
      cmocka_unit_test(test_particle_outside_walls),
      cmocka_unit_test(test_missing_file),
      cmocka_unit_test(test_bad_checkpoint),
      cmocka_unit_test(test_output_not_writable),
      cmocka_unit_test(test_runtime_failure),
      cmocka_unit_test(test_readme_claims),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
