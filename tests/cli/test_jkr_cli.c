/* The adem command on adhesive (JKR) cases: bad input is refused with file:line:column, `check`
 * prints what a JKR pair implies, a pulling group force is warned about, and the `collide` and
 * `validate` commands work from the command line. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "case_file.h"
#include "cli_run.h"

/* PSL spheres pulled away from a quartz floor; stiffness reduced 100 times. Line numbers below
 * refer to this text. */
#define jkr_case case_file_text("cli-jkr") /* tests/cases/cli-jkr.yaml */

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_jkr_cli");
}

/* `adem check` on jkr_case with one replacement exits 2 and names each word. */
static void expect_bad(const char *from, const char *to, const char *w1, const char *w2,
                       const char *w3) {
  char *text = replaced(jkr_case, from, to);
  char *path = write_case("bad.yaml", text);
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 2);
  assert_mentions(out, "error");
  assert_mentions(out, w1);
  if (w2) assert_mentions(out, w2);
  if (w3) assert_mentions(out, w3);
  free(text);
  free(path);
}

/* Claim: surface energy and hysteresis below 0 and a stiffness factor outside (0, 1] are refused
 * where they are written. */
static void test_bad_adhesion_values(void **state) {
  (void)state;
  expect_bad("surface_energy: 0.11\n    adhesion", "surface_energy: -0.11\n    adhesion",
             "bad.yaml:8:21", "materials[0].surface_energy", ">= 0");
  expect_bad("adhesion_hysteresis: 0.5", "adhesion_hysteresis: -0.5", "bad.yaml:9:26",
             "adhesion_hysteresis", ">= 0");
  expect_bad("stiffness_factor: 0.01", "stiffness_factor: 0", "bad.yaml:10:23", "stiffness_factor",
             "(0, 1]");
  expect_bad("stiffness_factor: 0.01", "stiffness_factor: 1.5", "bad.yaml:10:23",
             "stiffness_factor", "(0, 1]");
}

/* Claim: `normal: jkr` on a pair one of whose materials (here the wall's) has no surface energy
 * is refused at load time, naming the interaction and the material. */
static void test_jkr_without_surface_energy(void **state) {
  (void)state;
  expect_bad("    rigid: true\n    surface_energy: 0.11\n", "    rigid: true\n", "bad.yaml:17:13",
             "interactions[1].normal", "`quartz` (at line 11:5) has surface_energy 0");
  /* the other side too (the file is one line shorter) */
  expect_bad("    surface_energy: 0.11\n    adhesion", "    adhesion", "bad.yaml:15:13",
             "interactions[0].normal", "`psl`");
}

/* Claim: `adem check` prints, per JKR pair, real and modified E, gamma, a0, delta_eq, F_C, the
 * pull-off force, collision time and step, the speed-up (E/E_mod)^(2/5) = 100^0.4 = 6.31, the
 * Tabor parameter and the largest safe external force; and it warns when a group's force is
 * above 10% of a modified pull-off force. */
static void test_check_prints_jkr(void **state) {
  (void)state;
  char *path = strdup(case_file_path("cli-jkr"));
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  const char *words[] = {"simplified JKR", "a0 = (9 pi gamma R^2/E)^(1/3)", "delta_eq",
                         "F_C = 3 pi gamma R", "pull-off force (8/9) F_C", "Hertz t_c",
                         "t_c/50", "(E/E_mod)^(2/5) = 6.31", "Tabor parameter", "JKR valid",
                         "10% of the modified pull-off force", "psl-quartz (wall)"};
  for (size_t k = 0; k < sizeof words / sizeof words[0]; ++k) assert_mentions(out, words[k]);
  /* psl-psl, R = 0.3175 um: pull-off (8/9) 3 pi 0.11 R = 2.926e-07 N real */
  assert_mentions(out, "2.926e-07");
  assert_false(mentions(out, "external force of")); /* 1e-9 N is below 10% */
  free(path);

  /* 2e-8 N is 43% of the modified psl-psl pull-off force 4.637e-8 N */
  char *text = replaced(jkr_case, "external_force: [0, 0, 1e-9]", "external_force: [0, 0, 2e-8]");
  path = write_case("pulled.yaml", text);
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  assert_mentions(out, "pulled.yaml:20:11: group `pulled`");
  assert_mentions(out, "43% of the force that breaks a `psl`-`psl`");
  assert_mentions(out, "section 6.2");
  free(text);
  free(path);

  /* a stiff, weakly adhesive pair is outside the JKR range: lambda_T < 3 */
  text = replaced(jkr_case, "youngs_modulus: 2.5e8", "youngs_modulus: 7e10");
  char *t2 = replaced(text, "surface_energy: 0.11\n    adhesion", "surface_energy: 0.01\n    adhesion");
  path = write_case("stiff.yaml", t2);
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  assert_mentions(out, "below 3, JKR is outside its range");
  assert_mentions(out, "warning");
  free(text);
  free(t2);
  free(path);
}

/* Claim: `adem collide` runs the product of its lists in order, writes one CSV row each, gives
 * the same e_eff for f = 1 and 0.1 (H24), sticks below the capture speed, and refuses bad
 * values. */
static void test_collide_command(void **state) {
  (void)state;
  char *out;
  char *csv = path_in_tmp("c.csv");
  assert_int_equal(adem(&out, "collide --speed 1,5 --stiffness-factor 1,0.1 --out '%s' --threads 2",
                        csv),
                   0);
  assert_mentions(out, "4 collisions");
  /* rows: (f=1, 1 m/s), (f=1, 5 m/s), (f=0.1, 1 m/s), (f=0.1, 5 m/s) */
  assert_true(csv_value(csv, 1, "stuck") == 1.0);
  assert_true(csv_value(csv, 2, "stuck") == 0.0);
  double e1 = csv_value(csv, 2, "e_eff"), e2 = csv_value(csv, 4, "e_eff");
  printf("# e_eff at 5 m/s: f = 1 %.6f, f = 0.1 %.6f\n", e1, e2);
  assert_true(e1 > 0.6 && e1 < 0.86);
  assert_true(fabs(e1 - e2) < 1e-6);
  assert_true(csv_value(csv, 4, "stiffness_factor") == 0.1);
  double d1 = csv_value(csv, 2, "contact_duration_s"), d2 = csv_value(csv, 4, "contact_duration_s");
  assert_true(fabs(d2 / d1 / pow(10.0, 0.4) - 1.0) < 0.02);

  /* lambda and Ad of head-on pairs: Ad = 3 gamma/(rho v^2 r) */
  assert_int_equal(adem(&out, "collide --kind pair --radius 1e-6 --density 1000 --restitution 0.3 "
                              "--lambda log:1e2:1e6:3 --ad 10 --out '%s'",
                        csv),
                   0);
  assert_true(fabs(csv_value(csv, 1, "gamma_J_m2") - 10.0 * 1000.0 * 1e-6 / 3.0) < 1e-12);
  assert_true(fabs(csv_value(csv, 3, "E_Pa") - 1e9) < 1e-3);
  assert_true(csv_value(csv, 1, "stuck") == 1.0); /* lambda 1e2 << lambda_crit ~ 3.4e4 */
  assert_true(csv_value(csv, 3, "stuck") == 0.0);

  assert_int_equal(adem(&out, "collide --speed 0,1"), 2);
  assert_mentions(out, "--speed");
  assert_int_equal(adem(&out, "collide --stiffness-factor 2"), 2);
  assert_mentions(out, "(0, 1]");
  assert_int_equal(adem(&out, "collide --surface-energy -1"), 2);
  assert_mentions(out, "--surface-energy");
  assert_int_equal(adem(&out, "collide --kind pair --angle 45"), 2);
  assert_mentions(out, "--angle");
  assert_int_equal(adem(&out, "collide --speed log:0:1:5"), 2);
  assert_int_equal(adem(&out, "collide --help"), 0);
  assert_mentions(out, "log:lo:hi:n");
  free(csv);
}

/* Claim: the quick `adem validate haervig-fig5` passes its claim (H24 keeps e_eff and the capture
 * speed) and writes the CSV, the summaries and, with gnuplot, the PNG. */
static void test_validate_fig5_quick(void **state) {
  (void)state;
  char *out;
  assert_int_equal(adem(&out, "validate haervig-fig5 --quick --threads 2 --out '%s/v'", tmpdir), 0);
  assert_mentions(out, "1 of 1 validation passed");
  char *p = path_in_tmp("v/haervig-fig5.csv");
  assert_true(file_exists(p));
  FILE *f = fopen(p, "r");
  char head[256];
  assert_non_null(fgets(head, sizeof head, f));
  fclose(f);
  assert_mentions(head, "v_impact_m_s,e_eff_f1,e_eff_f0.1,e_eff_f0.01");
  free(p);
  p = path_in_tmp("v/summary.md");
  assert_true(file_exists(p));
  free(p);
  if (system("command -v gnuplot > /dev/null 2>&1") == 0) {
    p = path_in_tmp("v/haervig-fig5.png");
    assert_true(file_exists(p));
    free(p);
  }
  assert_int_equal(adem(&out, "validate haervig-fig99 --out '%s/v'", tmpdir), 2);
  assert_mentions(out, "unknown validation");
  assert_int_equal(adem(&out, "validate --list"), 0);
  assert_mentions(out, "haervig-fig13");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bad_adhesion_values),
      cmocka_unit_test(test_jkr_without_surface_energy),
      cmocka_unit_test(test_check_prints_jkr),
      cmocka_unit_test(test_collide_command),
      cmocka_unit_test(test_validate_fig5_quick),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
