/* The ballast lateral-resistance reproduction (I Figs 16-17) in its quick form: a packing of
 * 2,700 spheres twice the paper's size and two pushes at a tenth and a thirtieth of 17.7 GPa.
 * Claims: the quick irazabal-fig16 finds the initial slope lower at the lower E and the sleeper's
 * force equal to the sum of its face groups; the quick irazabal-fig17 finds the base's share
 * falling and the shoulder's rising. And the validation can fail: the same push with a
 * frictionless sleeper-ballast contact (the base can then carry no lateral force) fails
 * irazabal-fig17. `adem analyze push` (adem_push_shares_analyze) reads both pushes as the
 * validation does: the same binned shares. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "adem/adem.h"
#include "tmpdir.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_ballast");
}

static int teardown(void **state) {
  (void)state;
  return tmpdir_remove();
}

/* Prints the measured column of the summary's row that holds `key`. */
static void print_measured(const char *dir, const char *key) {
  char path[600];
  snprintf(path, sizeof path, "%s/summary.md", dir);
  char *text = NULL;
  size_t n = 0;
  adem_error err;
  if (adem_file_read_all(path, &text, &n, &err)) return;
  const char *m = strstr(text, key);
  const char *end = m ? strchr(m, '|') : NULL;
  printf("# %.*s\n", m ? (int)(end ? end - m : 400) : 9, m ? m : "(no row)");
  free(text);
}

/* The rows of adem_push_shares_analyze's CSV equal the validation's own CSV where its bins hold
 * rows (both print the same binned numbers): the analysis of one push is the validation's. */
static void check_push_analysis_matches(const char *push_dir, const char *fig17_csv) {
  adem_push_shares r;
  adem_error err;
  if (adem_push_shares_analyze(push_dir, &r, &err)) fail_msg("%s", err.message);
  FILE *a = fopen(r.csv, "r"), *b = fopen(fig17_csv, "r");
  assert_non_null(a);
  assert_non_null(b);
  char la[512], lb[512];
  int rows = 0;
  assert_non_null(fgets(la, sizeof la, a));
  assert_non_null(fgets(lb, sizeof lb, b));
  assert_string_equal(la, lb); /* the same header */
  while (fgets(la, sizeof la, a)) {
    do
      assert_non_null(fgets(lb, sizeof lb, b));
    while (strstr(lb, "nan")); /* a bin without a row: the analysis leaves it out */
    assert_string_equal(la, lb);
    ++rows;
  }
  fclose(a);
  fclose(b);
  printf("# adem analyze push: %d bins equal to irazabal-fig17.csv; base %.0f%% at 0-0.3 mm, "
         "shoulder %.0f%% at 3 mm\n",
         rows, 100 * r.share[0][0], 100 * r.share[2][2]);
  assert_true(rows > 50);
}

static void test_quick_figs_and_a_wrong_law(void **state) {
  (void)state;
  char good[512], bad[512];
  snprintf(good, sizeof good, "%s/good", tmpdir);
  snprintf(bad, sizeof bad, "%s/bad", tmpdir);
  adem_validation_context ctx = {good, 2, true, NULL, NULL};
  const char *names[] = {"irazabal-fig16", "irazabal-fig17"};
  int failed = -1;
  adem_error err;
  if (adem_validation_run(names, 2, &ctx, &failed, &err)) fail_msg("%s", err.message);
  print_measured(good, "Initial slope");
  print_measured(good, "E1.77: base");
  assert_int_equal(failed, 0);
  char push[600], csv[600];
  snprintf(push, sizeof push, "%s/irazabal-ballast/push-E1.77", good);
  snprintf(csv, sizeof csv, "%s/irazabal-fig17.csv", good);
  check_push_analysis_matches(push, csv);

  /* The wrong law: no friction between sleeper and ballast. The packing and the other push are
   * shared with the run above; the validation finds them finished. */
  char base[600], from[700], to[700];
  snprintf(base, sizeof base, "%s/irazabal-ballast", bad);
  assert_int_equal(adem_file_mkdir_p(base, &err), ADEM_OK);
  const char *shared[] = {"pack", "push-E0.59"};
  for (int k = 0; k < 2; ++k) {
    snprintf(from, sizeof from, "%s/irazabal-ballast/%s", good, shared[k]);
    snprintf(to, sizeof to, "%s/%s", base, shared[k]);
    assert_int_equal(symlink(from, to), 0);
  }
  char out[700], cas[700];
  snprintf(out, sizeof out, "output.dir=%s/push-E1.77", base);
  snprintf(cas, sizeof cas, "%s/irazabal-ballast/push.yaml", good);
  const char *sets[] = {out, "particles.0.file=pack/checkpoint",
                        "materials.ballast.youngs_modulus=6.5555555555555556e7",
                        "stages.stiffen-e9.set={materials.ballast.youngs_modulus: 1.9666666666666667e8}",
                        "stages.stiffen-e3.set={materials.ballast.youngs_modulus: 5.9e8}",
                        "stages.settle.set={materials.ballast.youngs_modulus: 1.77e9}",
                        "time.step=2.5e-5", "time.end=0.5", "walls.sleeper.motion.servo.gain=1e-6",
                        "walls.container.file=meshes/quick/container.stl",
                        "walls.sides.file=meshes/quick/sides.stl",
                        "walls.sleeper.file=meshes/quick/sleeper.stl", "output.frame_interval=0.5",
                        "interactions.2.friction=0"};
  adem_case *c = NULL;
  /* the case from the good run's folder, so pack/checkpoint and meshes/ resolve there */
  if (adem_case_load_file(cas, sets, (int)(sizeof sets / sizeof *sets), &c, &err)) fail_msg("%s", err.message);
  adem_run_options o = adem_default_run_options();
  o.nthreads = 2;
  if (adem_run(c, &o, &err)) fail_msg("%s", err.message);
  adem_case_free(c);
  adem_validation_context bctx = {bad, 2, true, NULL, NULL};
  const char *fig17[] = {"irazabal-fig17"};
  failed = -1;
  if (adem_validation_run(fig17, 1, &bctx, &failed, &err)) fail_msg("%s", err.message);
  print_measured(bad, "E1.77: base");
  assert_int_equal(failed, 1);
  /* the analysis reads the failing push as the validation does */
  char bad_csv[600];
  snprintf(out, sizeof out, "%s/push-E1.77", base);
  snprintf(bad_csv, sizeof bad_csv, "%s/irazabal-fig17.csv", bad);
  check_push_analysis_matches(out, bad_csv);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_quick_figs_and_a_wrong_law),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
