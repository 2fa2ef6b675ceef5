/* Rolling models from a case file: bad input is refused with a clear message, output.track
 * writes the rolling state of chosen particles, VTU frames carry the rolling torque, and the quick
 * irazabal-fig5 reproduction passes its claim. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>
#include <unistd.h>

#include "adem/adem.h"
#include "case_file.h"
#include "case_text.h"
#include "tmpdir.h"
#include "adem/studies.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_rolling");
}

/* A Table 1 sphere rolling on a rigid floor and a second one at rest; line numbers below refer to
 * this text. */
#define base case_file_text("rolling-input") /* tests/cases/rolling-input.yaml */

/* Loads text expecting ADEM_ERR_INPUT with every word in the message. */
static void refused(const char *text, const char *const *words, int nwords) {
  adem_case *c = NULL;
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_status st = adem_case_load_string(text, "rolling.yaml", NULL, 0, &c, &err);
  printf("# %s\n", err.message);
  assert_int_equal(st, ADEM_ERR_INPUT);
  assert_null(c);
  for (int k = 0; k < nwords; ++k) assert_contains(err.message, words[k]);
}

/* Claim: rolling parameters out of their physical range (eta_r < 0, delta_r < 0), and a rolling
 * model that needs what the normal model does not provide (DTK needs the JKR pull-off force and
 * contact radius), are refused at load with file:line:column, the key and what is allowed. */
static void test_bad_input(void **state) {
  (void)state;
  char *t = replaced(base, "rolling_friction: 0.2\n", "rolling_friction: -0.1\n");
  const char *w1[] = {"rolling.yaml:8:23", "materials[0].rolling_friction", "-0.1", ">= 0"};
  refused(t, w1, 4);
  free(t);
  t = replaced(base, "rolling_damping: 0.3\n", "rolling_damping: -0.3\n");
  const char *w2[] = {"rolling.yaml:9:22", "materials[0].rolling_damping", "-0.3", ">= 0"};
  refused(t, w2, 4);
  free(t);
  t = replaced(base, "rolling: brof", "rolling: dtk");
  const char *w3[] = {"rolling.yaml:12:44", "interactions[0].rolling", "`dtk`", "normal: jkr"};
  refused(t, w3, 4);
  free(t);
  t = replaced(base, "rolling: brof", "rolling: model_b");
  const char *w4[] = {"rolling.yaml:12:44", "model_a, model_c, model_c_capped, brof"};
  refused(t, w4, 2);
  free(t);
}

/* Claim: output.track names existing particles only, each once, as integers. */
static void test_track_input(void **state) {
  (void)state;
  const char *cases[4][2] = {{"track: [1, 0]", "track: [1, 2]"}, {"track: [1, 0]", "track: [0, 0]"}, {"track: [1, 0]", "track: [-1]"}, {"track: [1, 0]", "track: 3"}};
  const char *words[4] = {"there is no particle 2: the case creates 2 (ids 0 to 1)",
                          "particle 0 is listed twice", "expected a particle id (an integer >= 0)",
                          "output.track: expected a list [id, ...] of particle ids"};
  for (int k = 0; k < 4; ++k) {
    char *t = replaced(base, cases[k][0], cases[k][1]);
    const char *w[] = {"rolling.yaml:24:", words[k]};
    refused(t, w, 2);
    free(t);
  }
}

/* Claim: with output.track the CSV has, for each listed particle, its rolling resistance torque,
 * angular velocity and distance from its initial centre, and the VTU frames carry the rolling
 * torque of every particle. Sphere 0 rolls at 1 m/s under BROF (eta_r = 0.2): at 0.2 s its torque
 * is -eta_r r m g about y (8.67e-5 N m, I7; tolerance 1 % for the contact's compliance), its
 * spin about y is v/r, and it has covered v0 t - (5/7) eta_r g t^2 / 2 = 0.1720 m (1 %). Sphere 1
 * rests: zero torque, zero spin, zero distance. */
static void test_track_output(void **state) {
  (void)state;
  adem_case *c = NULL;
  adem_error err;
  char dir[400];
  snprintf(dir, sizeof dir, "%s/track", tmpdir);
  char set[512];
  snprintf(set, sizeof set, "output.dir=%s", dir);
  const char *sets[1] = {set};
  c = case_file_load("rolling-input", sets, 1);
  assert_int_equal(c->output.ntrack, 2);
  assert_true(c->output.track[0] == 1 && c->output.track[1] == 0);
  assert_int_equal(adem_run(c, NULL, &err), ADEM_OK);
  adem_case_free(c);

  char path[512];
  snprintf(path, sizeof path, "%s/timeseries.csv", dir);
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  static char header[8192], line[8192], last[8192];
  assert_non_null(fgets(header, sizeof header, f));
  while (fgets(line, sizeof line, f)) memcpy(last, line, sizeof last);
  fclose(f);
  const char *cols[] = {"p1_rolling_torque_x_Nm", "p1_omega_z_rad_s", "p1_distance_m",
                        "p0_rolling_torque_y_Nm", "p0_omega_y_rad_s", "p0_distance_m"};
  for (int k = 0; k < 6; ++k) assert_contains(header, cols[k]);
  /* column index of each wanted field */
  int idx_t0 = -1, idx_w0 = -1, idx_d0 = -1, idx_t1 = -1, idx_d1 = -1, col = 0;
  for (char *tok = strtok(header, ",\n"); tok; tok = strtok(NULL, ",\n"), ++col) {
    if (!strcmp(tok, "p0_rolling_torque_y_Nm")) idx_t0 = col;
    if (!strcmp(tok, "p0_omega_y_rad_s")) idx_w0 = col;
    if (!strcmp(tok, "p0_distance_m")) idx_d0 = col;
    if (!strcmp(tok, "p1_rolling_torque_y_Nm")) idx_t1 = col;
    if (!strcmp(tok, "p1_distance_m")) idx_d1 = col;
  }
  double v[256];
  col = 0;
  for (char *tok = strtok(last, ",\n"); tok && col < 256; tok = strtok(NULL, ",\n"))
    v[col++] = atof(tok);
  double m = 1056.0 * 4.0 / 3.0 * 3.14159265358979323846 * 1e-6, t = v[0];
  double torque = 0.2 * 0.01 * m * 9.8, dist = t - 5.0 / 7.0 * 0.2 * 9.8 * t * t / 2.0;
  printf("# at t = %g s: sphere 0 torque %.6g N m (expected -%.6g), omega_y %.6g rad/s, distance "
         "%.6g m (expected %.6g); sphere 1 torque %.3g, distance %.3g\n",
         t, v[idx_t0], torque, v[idx_w0], v[idx_d0], dist, v[idx_t1], v[idx_d1]);
  assert_true(fabs(t - 0.2) < 1e-9);
  assert_true(fabs(v[idx_t0] / -torque - 1.0) < 0.01);
  assert_true(fabs(v[idx_d0] / dist - 1.0) < 0.01);
  assert_true(fabs(v[idx_w0] * 0.01 / (1.0 - 5.0 / 7.0 * 0.2 * 9.8 * t) - 1.0) < 0.01);
  assert_true(fabs(v[idx_t1]) < 1e-12 && fabs(v[idx_d1]) < 1e-6);

  snprintf(path, sizeof path, "%s/frames/particles_000001.vtu", dir);
  f = fopen(path, "rb");
  assert_non_null(f);
  size_t n = fread(line, 1, sizeof line - 1, f);
  line[n] = '\0';
  fclose(f);
  assert_contains(line, "Name=\"rolling_torque\" NumberOfComponents=\"3\"");
}

/* Claim: an interaction entry's rolling_friction is the eta_r BROF uses for a sphere on a wall
 * (neither the particle material's 0.2 nor the wall material's 0.9): the rolling sphere slows at
 * (5/7) 0.4 g; and `adem check` says which value each pair uses and why. */
static void test_pair_rolling_friction(void **state) {
  (void)state;
  char *t1 = replaced(base, "rolling_friction: 0.2}\n", "rolling_friction: 0.9}\n");
  char *t2 = replaced(t1, "{materials: [ballast, floor], rolling: brof}",
                      "{materials: [ballast, floor], rolling: brof, rolling_friction: 0.4}");
  char *t3 = replaced(t2, "interactions:\n", "interactions:\n"
                                             "  - {materials: [ballast, ballast], rolling: brof}\n");
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_string(t3, "rolling.yaml", NULL, 0, &c, &err)) fail_msg("%s", err.message);
  char *text = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&text, &len);
  assert_int_equal(adem_case_report(c, f, &err), ADEM_OK);
  fclose(f);
  printf("%s", text);
  assert_contains(text, "e_c = min(0.2 r_i, 0.2 r_j) (BROF, I9: `ballast`'s value)");
  assert_contains(text, "eta_r = 0.4, e_c = 0.4 r_i (the interaction entry's value");
  free(text);
  assert_int_equal(adem_world_prepare(c->world, &err), ADEM_OK);
  assert_int_equal(adem_world_step(c->world, 2000, &err), ADEM_OK); /* 0.1 s */
  double v[6];
  assert_int_equal(adem_world_get_particles(c->world, ADEM_FIELD_VELOCITY, v, 6, &err), ADEM_OK);
  double expected = 1.0 - 5.0 / 7.0 * 0.4 * 9.8 * 0.1;
  printf("# v after 0.1 s: %.6f m/s, (5/7) eta_r g t with eta_r = 0.4: %.6f m/s\n", v[0], expected);
  assert_true(fabs(v[0] / expected - 1.0) < 0.01);
  adem_case_free(c);
  free(t1);
  free(t2);
  free(t3);
}

/* Claim (I Fig. 5): the quick irazabal-fig5 reproduction passes: models A and BROF equal while
 * rolling at (5/7) eta_r g, model A flipping at rest, BROF at rest with zero spin. */
static void test_fig5_quick(void **state) {
  (void)state;
  const adem_validation *v = adem_validation_find("irazabal-fig5");
  assert_non_null(v);
  adem_validation_context ctx = {tmpdir, 1, true, NULL, NULL};
  adem_validation_report rep;
  memset(&rep, 0, sizeof rep);
  adem_error err;
  assert_int_equal(v->run(&ctx, v->name, &rep, &err), ADEM_OK);
  printf("# %s\n", rep.measured);
  assert_true(rep.pass);
  char path[400];
  snprintf(path, sizeof path, "%s/irazabal-fig5.csv", tmpdir);
  assert_int_equal(access(path, R_OK), 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bad_input),
      cmocka_unit_test(test_track_input),
      cmocka_unit_test(test_track_output),
      cmocka_unit_test(test_pair_rolling_friction),
      cmocka_unit_test(test_fig5_quick),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
