/* A new normal law gets its cold path from its row's hooks alone (src/laws/law_hooks.h):
 * `test_jkr_like` (tests/laws/test_law_rows.h) is simplified JKR under another name, added as
 * one row whose .hooks are JKR's, with no code outside its row and kernel that names it.
 * Claims: (1) the step proposal takes its adhesive collision time (notes section 6: JKR's
 * t_c at sqrt(v_ref^2 + 2|U_min|/m*), or half the oscillation period), bit for bit the `jkr`
 * pair's and not Hertz's; (2) a pair of it without surface energy on a material is refused at
 * load time, naming the key, the law and the material, as a `jkr` pair is; (3) a group force
 * above 10 % of its pull-off force is warned about (H section 6.2), as for `jkr`.
 * With the row's .hooks removed (NULL), (1) gives Hertz's t_c (ratio 1.000 instead of 0.647:
 * "ratio to hertz" below), and (2) and (3) find nothing: the checks fail. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "adem/adem.h"
#include "case_text.h"
#include "world_internal.h"

/* PSL spheres on a quartz floor, stiffness reduced 100 times (tests/cli/test_jkr_cli.c's case);
 * NORMAL is replaced by the law under test. */
static const char *const case_text =
    "materials:\n"
    "  - name: psl\n"
    "    density: 1026\n"
    "    youngs_modulus: 2.5e8\n"
    "    poisson_ratio: 0.3\n"
    "    restitution: 0.86\n"
    "    surface_energy: 0.11\n"
    "    stiffness_factor: 0.01\n"
    "  - name: quartz\n"
    "    rigid: true\n"
    "    surface_energy: 0.11\n"
    "interactions:\n"
    "  - {materials: [psl, psl], normal: NORMAL}\n"
    "  - {materials: [psl, quartz], normal: NORMAL}\n"
    "groups:\n"
    "  - {name: pulled, external_force: [0, 0, 2e-8]}\n"
    "particles:\n"
    "  - type: list\n"
    "    material: psl\n"
    "    group: pulled\n"
    "    spheres:\n"
    "      - {position: [0, 0, 1e-6], radius: 0.635e-6}\n"
    "      - {position: [3e-6, 0, 1e-6], radius: 0.635e-6}\n"
    "walls:\n"
    "  - {type: plane, name: floor, material: quartz, point: [0, 0, 0], normal: [0, 0, 1]}\n"
    "gravity: [0, 0, 0]\n"
    "time: {end: 1e-6}\n";

static char logged[8192];

static void capture(adem_log_level level, const char *msg, void *user) {
  (void)level;
  (void)user;
  size_t n = strlen(logged);
  snprintf(logged + n, sizeof logged - n, "%s\n", msg);
}

/* Loads the case with `normal: law` (and one more replacement, if from is not NULL). */
static adem_status load(const char *law, const char *from, const char *to, adem_case **c,
                        adem_error *err) {
  char *text = replaced(case_text, "normal: NORMAL}", "normal: X}");
  char *t2 = replaced(text, "normal: NORMAL}", "normal: X}");
  char with[64];
  snprintf(with, sizeof with, "normal: %s}", law);
  char *t3 = replaced(t2, "normal: X}", with);
  char *t4 = replaced(t3, "normal: X}", with);
  char *t5 = from ? replaced(t4, from, to) : t4;
  logged[0] = '\0';
  adem_log_set_hook(capture, NULL);
  memset(err, 0, sizeof *err);
  adem_status st = adem_case_load_string(t5, "hooks.yaml", NULL, 0, c, err);
  adem_log_set_hook(NULL, NULL);
  if (t5 != t4) free(t5);
  free(t4);
  free(t3);
  free(t2);
  free(text);
  return st;
}

static double t_collision(const char *law) {
  adem_case *c = NULL;
  adem_error err;
  if (load(law, NULL, NULL, &c, &err)) fail_msg("%s: %s", law, err.message);
  adem_step_estimate est = adem_world_estimate_step(c->world, 1.0);
  adem_case_free(c);
  return est.t_collision;
}

/* Claim (1). */
static void test_collision_time_is_jkr(void **state) {
  (void)state;
  double like = t_collision("test_jkr_like"), jkr = t_collision("jkr"),
         hertz = t_collision("hertz");
  printf("# t_collision at v_ref = 1 m/s: test_jkr_like %.9g s, jkr %.9g s, hertz %.9g s; "
         "ratio to hertz %.3f\n",
         like, jkr, hertz, like / hertz);
  assert_true(like == jkr); /* the same hook, the same bits */
  /* the adhesion shortens it well below Hertz's (0.647 here; Hertz's own would be 1) */
  assert_true(like < 0.9 * hertz);
}

/* Claim (2). */
static void test_checks_are_jkr(void **state) {
  (void)state;
  adem_case *c = NULL;
  adem_error err;
  const char *from = "    rigid: true\n    surface_energy: 0.11\n", *to = "    rigid: true\n";
  assert_int_equal(load("test_jkr_like", from, to, &c, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_contains(err.message, "interactions[1].normal");
  assert_contains(err.message, "`test_jkr_like` between `psl` and `quartz`");
  assert_contains(err.message, "`quartz` (at line 9:5) has surface_energy 0");
  /* the same refusal as a `jkr` pair's */
  assert_int_equal(load("jkr", from, to, &c, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "`quartz` (at line 9:5) has surface_energy 0");
  /* and hertz needs none */
  assert_int_equal(load("hertz", from, to, &c, &err), ADEM_OK);
  adem_case_free(c);
}

/* Claim (3): 2e-8 N is 43 % of the modified psl-psl pull-off force 4.637e-8 N. */
static void test_pulling_force_warned(void **state) {
  (void)state;
  adem_case *c = NULL;
  adem_error err;
  assert_int_equal(load("test_jkr_like", NULL, NULL, &c, &err), ADEM_OK);
  printf("# %s", logged);
  assert_contains(logged, "43% of the force that breaks a `psl`-`psl` `test_jkr_like` contact");
  adem_case_free(c);
  assert_int_equal(load("hertz", NULL, NULL, &c, &err), ADEM_OK);
  assert_false(mentions(logged, "the force that breaks"));
  adem_case_free(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_collision_time_is_jkr),
      cmocka_unit_test(test_checks_are_jkr),
      cmocka_unit_test(test_pulling_force_warned),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
