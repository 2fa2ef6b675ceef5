/* Claims: (a) a plane plate under servo control (target F along +z) coming down on a single
 * sphere that rests on a floor, without gravity, settles where the particles push on it with F,
 * and the sphere's two overlaps are the Hertz overlap at F, (3 F / (4 E* sqrt(R)))^(2/3) with
 * E* = E / (1 - nu^2) against a rigid wall; (d) the case file's servo keys are checked like the
 * rest of the schema: the message names file:line:column, the key and what is allowed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "case_file.h"
#include "case_text.h"
#include "world_internal.h"

static const double E = 1.0e8, NU = 0.3, R = 0.01, F = 50.0;

/* The plate starts 0.1 mm above the sphere; gain 2e-3 m/s/N against a stiffness of about 1.6e5
 * N/m (the two Hertz contacts in series at 50 N) is a time constant of 3 ms, gain K dt = 7e-4. */
#define plate_case case_file_text("servo-plate") /* tests/cases/servo-plate.yaml */

static void test_plate_on_sphere(void **state) {
  (void)state;
  adem_case *c = case_file_load("servo-plate", NULL, 0);
  adem_error err;
  adem_world *w = c->world;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  uint64_t n = (uint64_t)llround(0.1 / w->dt); /* 33 time constants */
  if (adem_world_step(w, n, &err)) fail_msg("%s", err.message);
  adem_vec3 f[2];
  adem_world_plane_forces(w, f);
  const adem_motion *m = &w->walls.planes[1].motion;
  double estar = E / (1.0 - NU * NU);
  double delta_hertz = pow(3.0 * F / (4.0 * estar * sqrt(R)), 2.0 / 3.0);
  /* the sphere's two contacts, floor and plate */
  double delta[2] = {0, 0};
  for (size_t k = 0; k < w->pw.n; ++k)
    if (w->pw.touching[k]) delta[w->pw.b[k]] = w->pw.res[k].overlap_ratio * R;
  printf("# plate: F_z = %.12g N (servo %.12g N), floor %.12g N; overlaps %.9g, %.9g m, Hertz "
         "%.9g m; servo travel %.9g m\n",
         f[1].z, m->servo_force, f[0].z, delta[0], delta[1], delta_hertz, m->servo_u);
  /* After 33 time constants the error left is e^-33 of the 50 N start: round-off. */
  assert_true(fabs(f[1].z - F) < 1e-6 * F);
  assert_true(fabs(f[0].z + F) < 1e-6 * F);
  /* At rest the dashpots carry nothing: the overlaps are Hertz's to round-off (F ~ delta^1.5,
   * so 1e-6 in F is 7e-7 in delta). */
  assert_true(fabs(delta[0] - delta_hertz) < 1e-6 * delta_hertz);
  assert_true(fabs(delta[1] - delta_hertz) < 1e-6 * delta_hertz);
  /* the plate came down the 0.1 mm gap and the two overlaps */
  assert_true(fabs(m->servo_u + (1e-4 + 2.0 * delta_hertz)) < 1e-9);
  adem_case_free(c);
}

/* The message of the case with one replacement, checked for words. */
static void expect_bad(const char *from, const char *to, const char *const *words) {
  char *text = replaced(plate_case, from, to);
  adem_case *c = NULL;
  adem_error err;
  adem_status st = adem_case_load_string(text, "test.yaml", NULL, 0, &c, &err);
  free(text);
  if (st == ADEM_OK) fail_msg("'%s' was accepted", to);
  printf("# %s\n", err.message);
  for (; *words; ++words) assert_mentions(err.message, *words);
}
#define WORDS(...) ((const char *const[]){__VA_ARGS__, NULL})

static void test_schema_errors(void **state) {
  (void)state;
  const char *servo = "servo: {axis: [0, 0, 1], target_force: 50, gain: 2.0e-3, max_speed: 0.05}";
  expect_bad(servo, "servo: {axis: [0, 0, 1], target_force: 50, max_speed: 0.05}",
             WORDS("test.yaml:18:14", "walls[1].motion.servo", "gain", "required"));
  expect_bad("gain: 2.0e-3", "gain: -2.0e-3",
             WORDS("test.yaml:18:56", "walls[1].motion.servo.gain", "> 0"));
  expect_bad("axis: [0, 0, 1], target", "axis: [0, 0, 0], target",
             WORDS("test.yaml:18:21", "walls[1].motion.servo.axis", "non-zero"));
  expect_bad("target_force: 50", "target_force: heavy",
             WORDS("test.yaml:18:46", "walls[1].motion.servo.target_force", "number", "heavy"));
  expect_bad(servo, "servo: 5", WORDS("test.yaml:18:14", "walls[1].motion.servo", "mapping"));
  expect_bad("max_speed: 0.05}", "max_speed: 0.05, gian: 1}",
             WORDS("test.yaml:18", "gian", "gain"));
  expect_bad("max_speed: 0.05}", "max_speed: 0.05, travel: [0.01, 0.02]}",
             WORDS("test.yaml:18", "walls[1].motion.servo.travel", "min <= 0 <= max"));
  expect_bad("max_speed: 0.05}", "max_speed: 0.05, groups: [a]}",
             WORDS("test.yaml:18", "walls[1].motion.servo.groups", "mesh walls only"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plate_on_sphere),
      cmocka_unit_test(test_schema_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
