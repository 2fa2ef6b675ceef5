/* The adem command on deposition with DTK rolling resistance (H section 5.3): `adem collide`
 * with a force along the wall and the outcome columns, --critical-lambda (H25), bad options,
 * and the quick DTK validations. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char tmpdir[256];

static char *path_in_tmp(const char *name) {
  size_t n = strlen(tmpdir) + strlen(name) + 2;
  char *p = malloc(n);
  assert_non_null(p);
  snprintf(p, n, "%s/%s", tmpdir, name);
  return p;
}

/* Runs `adem ARGS` with stdout and stderr captured; returns the exit status, *out the text. */
static int adem(char **out, const char *fmt, ...) {
  char args[4096], cmd[8192];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(args, sizeof args, fmt, ap);
  va_end(ap);
  char *log = path_in_tmp("output.txt");
  snprintf(cmd, sizeof cmd, "'%s' %s > '%s' 2>&1 < /dev/null", ADEM_BINARY, args, log);
  int status = system(cmd);
  assert_true(status != -1 && WIFEXITED(status));
  FILE *f = fopen(log, "r");
  assert_non_null(f);
  static char buf[1 << 17];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  buf[n] = '\0';
  fclose(f);
  free(log);
  *out = buf;
  printf("# adem %s -> %d\n#   %.*s\n", args, WEXITSTATUS(status), (int)strcspn(buf, "\n"), buf);
  return WEXITSTATUS(status);
}

static int mentions(const char *text, const char *word) {
  size_t n = strlen(word);
  for (const char *s = text; *s; ++s) {
    size_t k = 0;
    while (k < n && s[k] && tolower((unsigned char)s[k]) == tolower((unsigned char)word[k])) ++k;
    if (k == n) return 1;
  }
  return 0;
}

#define assert_mentions(text, word)                                     \
  do {                                                                  \
    if (!mentions(text, word)) fail_msg("'%s' not in: %s", word, text); \
  } while (0)

static int setup(void **state) {
  (void)state;
  snprintf(tmpdir, sizeof tmpdir, "/tmp/adem_dtk_cli_XXXXXX");
  return mkdtemp(tmpdir) ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  return system(cmd) == 0 ? 0 : -1;
}

/* Cell `name` of CSV row `row` (1 = first data row), as text. */
static const char *csv_cell(const char *path, int row, const char *name) {
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  static char line[1 << 14], cell[256];
  int col = -1;
  assert_non_null(fgets(line, sizeof line, f));
  int k = 0;
  for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), ++k)
    if (!strcmp(tok, name)) col = k;
  if (col < 0) fail_msg("no column %s in %s", name, path);
  for (int r = 1; r <= row; ++r) assert_non_null(fgets(line, sizeof line, f));
  fclose(f);
  cell[0] = '\0';
  k = 0;
  for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), ++k)
    if (k == col) snprintf(cell, sizeof cell, "%s", tok);
  return cell;
}

static double csv_value(const char *path, int row, const char *name) {
  return strtod(csv_cell(path, row, name), NULL);
}

/* Claim: `adem collide --at-rest --dtk` classifies a resting PSL sphere pushed along quartz with
 * F_hat = 0.9 as stuck and 1.1 as rolling at f = 1 and 0.01 (H section 5.3 with H24 and the
 * rolling modification), rows in list order, F_ext = F_hat F_yield with F_yield =
 * 4 F_C xi_crit / r (1.10e-9 N for PSL, delta_gamma/gamma = 0.5). */
static void test_collide_at_rest(void **state) {
  (void)state;
  char *out, *csv = path_in_tmp("rest.csv");
  assert_int_equal(adem(&out, "collide --at-rest --dtk --hysteresis 0.5 --force-hat 0.9,1.1 "
                              "--stiffness-factor 1,0.01 --threads 2 --out '%s'", csv), 0);
  assert_mentions(out, "2 rolling, 2 at rest");
  /* rows: (0.9, f 1), (0.9, f 0.01), (1.1, f 1), (1.1, f 0.01) */
  const char *expect[4] = {"stuck", "stuck", "rolling", "rolling"};
  for (int r = 1; r <= 4; ++r) assert_string_equal(csv_cell(csv, r, "outcome"), expect[r - 1]);
  /* F_yield = 4 (3 pi gamma r) (a0/12 x 0.5) / r, a0 = (9 pi gamma r^2/E)^(1/3) */
  double r = 0.635e-6, g = 0.11, a0 = cbrt(9.0 * 3.14159265358979 * g * r * r / 271e6);
  double fy = 4.0 * 3.0 * 3.14159265358979 * g * r * (a0 / 24.0) / r;
  printf("# F_ext row 3: %.6g N, 1.1 F_yield = %.6g N\n", csv_value(csv, 3, "F_ext_N"), 1.1 * fy);
  assert_true(fabs(csv_value(csv, 3, "F_ext_N") / (1.1 * fy) - 1.0) < 1e-9);
  assert_true(fabs(csv_value(csv, 1, "F_hat") - 0.9) < 1e-12);
  assert_true(csv_value(csv, 1, "t_rest_s") > 0.0);
  assert_true(csv_value(csv, 1, "roll_distance_m") < 20.0 * csv_value(csv, 1, "xi_crit_m"));
  free(csv);
}

/* Claim: --critical-lambda finds lambda_crit for each Ad and restitution, writes c =
 * lambda_crit/Ad^(5/2), and prints the fit lambda_crit = c Ad^k per restitution with k = 2.5
 * (H25); wall c(0.3) = 149.8 at 200 steps per collision time (sqrt 2 times the head-on pair's). */
static void test_critical_lambda(void **state) {
  (void)state;
  char *out, *csv = path_in_tmp("crit.csv");
  assert_int_equal(adem(&out, "collide --radius 1e-6 --density 1000 --ad 100,1000 --restitution "
                              "0.3,0.7 --critical-lambda 1e3:1e13:1e-4 --threads 2 --out '%s'",
                        csv), 0);
  assert_mentions(out, "4 critical lambdas");
  assert_mentions(out, "e = 0.3: lambda_crit = 149.8");
  assert_mentions(out, "Ad^2.5000");
  double c1 = csv_value(csv, 1, "c"), c2 = csv_value(csv, 2, "c"), c3 = csv_value(csv, 3, "c");
  printf("# c(0.3) at Ad 100, 1000: %.6g, %.6g; c(0.7): %.6g\n", c1, c2, c3);
  assert_true(fabs(c1 / c2 - 1.0) < 2e-4);
  assert_true(fabs(c1 / 149.83 - 1.0) < 2e-3);
  assert_true(c3 < c1);
  free(csv);
}

/* Claim: options that do not make sense together are refused with exit status 2 and a message
 * naming the option. */
static void test_bad_options(void **state) {
  (void)state;
  char *out;
  assert_int_equal(adem(&out, "collide --force-hat 0.5"), 2);
  assert_mentions(out, "--force-hat needs --dtk");
  assert_int_equal(adem(&out, "collide --dtk"), 2);
  assert_mentions(out, "--hysteresis");
  assert_int_equal(adem(&out, "collide --kind pair --dtk --hysteresis 0.5"), 2);
  assert_mentions(out, "wall impacts");
  assert_int_equal(adem(&out, "collide --dtk --hysteresis 0.5 --force-hat 1 --force-ext 1e-9"), 2);
  assert_mentions(out, "not both");
  assert_int_equal(adem(&out, "collide --lambda 1e5 --critical-lambda 1e3:1e9"), 2);
  assert_mentions(out, "--critical-lambda");
  assert_int_equal(adem(&out, "collide --critical-lambda 1e9:1e3"), 2);
  assert_mentions(out, "LO:HI");
  assert_int_equal(adem(&out, "collide --restitution 0,0.5"), 2);
  assert_mentions(out, "--restitution");
  assert_int_equal(adem(&out, "collide --help"), 0);
  assert_mentions(out, "--critical-lambda");
}

/* Claim: the quick versions of the DTK validations (H Figs. 4, 10, 11, 12 and the invariance of
 * deposition under H24) pass and write their CSVs. */
static void test_validate_quick(void **state) {
  (void)state;
  char *out;
  assert_int_equal(adem(&out, "validate haervig-fig4 haervig-fig10 haervig-fig11 haervig-fig12 "
                              "haervig-rolling-invariance --quick --threads 2 --out '%s/v'",
                        tmpdir), 0);
  assert_mentions(out, "5 of 5 validations passed");
  const char *names[5] = {"haervig-fig4", "haervig-fig10", "haervig-fig11", "haervig-fig12",
                          "haervig-rolling-invariance"};
  for (int k = 0; k < 5; ++k) {
    char rel[128];
    snprintf(rel, sizeof rel, "v/%s.csv", names[k]);
    char *p = path_in_tmp(rel);
    struct stat st;
    assert_true(stat(p, &st) == 0 && st.st_size > 0);
    free(p);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_collide_at_rest),
      cmocka_unit_test(test_critical_lambda),
      cmocka_unit_test(test_bad_options),
      cmocka_unit_test(test_validate_quick),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
