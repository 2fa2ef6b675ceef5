/* A change of the tangential or rolling law of live contacts (a stage's `interactions`, through
 * adem_world_change_materials; issue 25, item 8): histories are converted where the conversion is
 * exact, else cleared with their spring energy counted as dissipated. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "case_file.h"
#include "helpers.h"
#include "staged_run.h"
#include "world_internal.h"

static const double PI = 3.14159265358979323846;

/* A sphere (radius 1 mm, E 1e7 Pa, e 0.5, mu 1) at rest on a plane under gravity tilted by 10
 * degrees, held by friction and model C's rolling spring (eta_r 0.5 > tan 10 deg), settled. */
static adem_world *resting(void) {
  adem_world *w = adem_world_create();
  double th = 10.0 * PI / 180.0;
  adem_world_set_gravity(w, v3(9.81 * sin(th), 0, -9.81 * cos(th)));
  int glass = test_material(w, "glass", 1e7, 0.3, 0.5, 1.0);
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "steel");
  m.rigid = 1;
  m.friction = 1.0;
  adem_error err;
  int steel = -1;
  assert_int_equal(adem_world_add_material(w, &m, &steel, &err), ADEM_OK);
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = glass;
  it.material_b = steel;
  it.rolling = ADEM_ROLLING_C;
  it.param[ADEM_PARAM_ROLLING_FRICTION] = 0.5;
  assert_int_equal(adem_world_set_interaction(w, &it, &err), ADEM_OK);
  adem_plane_def pl = adem_default_plane_def();
  snprintf(pl.name, sizeof pl.name, "floor");
  pl.material = steel;
  assert_int_equal(adem_world_add_plane(w, &pl, NULL, &err), ADEM_OK);
  test_particle(w, glass, v3(0, 0, 1e-3 - 3.2e-6), v3(0, 0, 0), 1e-3);
  adem_world_set_dt(w, 2e-6);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  assert_int_equal(adem_world_step(w, 20000, &err), ADEM_OK);
  return w;
}

/* The world's materials with the glass-steel interaction's laws replaced. */
static void switch_laws(adem_world *w, adem_tangential_model tangential, adem_rolling_model rolling) {
  adem_material_def defs[2] = {w->mat.m[0].def, w->mat.m[1].def};
  adem_interaction_def it = w->mat.defs[0];
  it.tangential = tangential;
  it.rolling = rolling;
  adem_error err;
  assert_int_equal(adem_world_change_materials(w, defs, &it, 1, &err), ADEM_OK);
}

static adem_contact_info the_contact(const adem_world *w) {
  adem_contact_info c;
  assert_int_equal(adem_world_contacts(w, &c, 1), 1);
  return c;
}

/* The tangential part of the contact force on the sphere. */
static adem_vec3 tangential_force(const adem_world *w) {
  adem_vec3 f = the_contact(w).force;
  return v3(f.x, f.y, 0.0);
}

/* Claim (issue 25, item 8): switching the tangential law of a loaded, sticking contact from
 * `incremental` (history: the spring force, N) to `total` (the displacement, m) and back converts
 * the history exactly (xi = -F_s/S_t, F_s = -S_t xi, S_t the stiffness it was stored with): the
 * tangential force after the next step is that of a run that did not switch, to 1e-9, and so is
 * the sphere's velocity. Before, the force in newtons was read as metres (6.6 times the force
 * after the first switch). */
static void test_tangential_switch_converts(void **state) {
  (void)state;
  adem_world *w = resting(), *ref = resting();
  adem_error err;
  double f0 = v3_norm(tangential_force(w));
  switch_laws(w, ADEM_TANGENTIAL_TOTAL, ADEM_ROLLING_C);
  assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
  assert_int_equal(adem_world_step(ref, 1, &err), ADEM_OK);
  adem_vec3 f1 = tangential_force(w), r1 = tangential_force(ref);
  switch_laws(w, ADEM_TANGENTIAL_INCREMENTAL, ADEM_ROLLING_C);
  assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
  assert_int_equal(adem_world_step(ref, 1, &err), ADEM_OK);
  adem_vec3 f2 = tangential_force(w), r2 = tangential_force(ref);
  double d1 = v3_norm(v3_sub(f1, r1)) / v3_norm(r1), d2 = v3_norm(v3_sub(f2, r2)) / v3_norm(r2);
  printf("# tangential force %.9e N; after the switch to total %.9e N (%.2e from the run that "
         "did not switch), back to incremental %.9e N (%.2e)\n",
         f0, v3_norm(f1), d1,
         v3_norm(f2), d2);
  assert_true(d1 < 1e-9);
  assert_true(d2 < 1e-9);
  assert_true(v3_norm(v3_sub(w->p.vel[0], ref->p.vel[0])) <= 1e-9 * v3_norm(ref->p.vel[0]));
  adem_world_free(w);
  adem_world_free(ref);
}

/* Claim (issue 25, item 8): switching the rolling law from model C (history: a torque, N m) to
 * one without a spring clears the history, and the spring energy it held is counted as
 * dissipated: the energy balance's error moves by less than 1e-3 of that energy (before: the
 * history stayed, and a later switch to DTK would read N m as m). C <-> C capped keep it (the same
 * spring torque). */
static void test_rolling_switch_clears(void **state) {
  (void)state;
  adem_world *w = resting();
  adem_error err;
  switch_laws(w, ADEM_TANGENTIAL_INCREMENTAL, ADEM_ROLLING_C_CAPPED);
  adem_contact_info c = the_contact(w);
  double m_c = v3_norm(c.rolling_history);
  assert_true(m_c > 0.0);
  adem_diagnostics d0 = adem_world_diagnostics(w);
  double elastic_rolling = 0.0;
  {
    /* model C's spring energy M^2/(2 k_r), k_r = 2.25 S_n eta^2 R^2, S_n = 2 E a */
    const adem_interaction *it = adem_world_interaction(w, 0, 1);
    double delta = 1e-3 - w->p.pos[0].z, a = sqrt(1e-3 * delta);
    double k_r = 2.25 * 2.0 * it->pp.E * a * 0.25 * 1e-6;
    elastic_rolling = 0.5 * m_c * m_c / k_r;
  }
  switch_laws(w, ADEM_TANGENTIAL_INCREMENTAL, ADEM_ROLLING_A);
  c = the_contact(w);
  printf("# after the switch to model A: rolling history %.4e (model C's torque was %.4e N m)\n",
         v3_norm(c.rolling_history), m_c);
  assert_true(v3_norm(c.rolling_history) == 0.0);
  assert_int_equal(adem_world_step(w, 10, &err), ADEM_OK);
  adem_diagnostics d1 = adem_world_diagnostics(w);
  double moved = d1.balance_error - d0.balance_error;
  printf("# model C torque %.4e N m, spring energy %.4e J; balance error %.3e -> %.3e J (moved "
         "%.2e of the spring energy)\n",
         m_c, elastic_rolling, d0.balance_error, d1.balance_error,
         fabs(moved) / elastic_rolling);
  assert_true(fabs(moved) < 1e-3 * elastic_rolling);
  adem_world_free(w);
}

/* The resting sphere as a case file (tests/cases/stage-law-switch.yaml) whose second stage, from
 * t = 0.04 s (step 20000), sets the interaction's tangential law. */
static adem_case *staged(const char *tangential) {
  char gravity[128], law[128];
  snprintf(gravity, sizeof gravity, "gravity=[%.17g, 0, %.17g]", 9.81 * sin(10.0 * PI / 180.0),
           -9.81 * cos(10.0 * PI / 180.0));
  snprintf(law, sizeof law, "stages.switch.set={interactions.0.tangential: %s}", tangential);
  const char *sets[] = {gravity, law};
  adem_case *c = case_file_load("stage-law-switch", sets, 2);
  adem_error err;
  if (staged_start(c, &err)) fail_msg("%s", err.message);
  if (staged_advance(c, 20001, 5000, &err)) fail_msg("%s", err.message);
  return c;
}

/* Claim (issue 25, item 8): the same through a case file's stages: a stage that sets
 * `tangential: total` on the live contact gives the tangential force of a run whose stage keeps
 * `incremental`, to 1e-9, one step after the stage begins. */
static void test_stage_switch_case(void **state) {
  (void)state;
  adem_case *a = staged("total"), *b = staged("incremental");
  assert_int_equal(adem_stages_current(a), 1);
  adem_vec3 fa = tangential_force(a->world), fb = tangential_force(b->world);
  double d = v3_norm(v3_sub(fa, fb)) / v3_norm(fb);
  printf("# stage switch to total: tangential force %.9e N, kept incremental %.9e N (%.2e)\n",
         v3_norm(fa), v3_norm(fb), d);
  assert_true(d < 1e-9);
  adem_case_free(a);
  adem_case_free(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_tangential_switch_converts),
      cmocka_unit_test(test_rolling_switch_clears),
      cmocka_unit_test(test_stage_switch_case),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
