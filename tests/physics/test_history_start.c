/* Contact histories at the start of a run and under a force pass that moves nothing (issue 25,
 * item 7): prepare and adem_world_compute_forces evaluate the forces of the state as it is; only
 * a step advances the springs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "helpers.h"
#include "world_internal.h"

/* A sphere (radius 1 mm, E 1e7 Pa, mu 1) pressed 1 um into a plane, launched along x at v
 * without spin or gravity. */
static adem_world *launched(adem_tangential_model tangential, adem_rolling_model rolling,
                            double v) {
  adem_world *w = adem_world_create();
  adem_world_set_gravity(w, v3(0, 0, 0));
  int glass = test_material(w, "glass", 1e7, 0.3, 0.5, 1.0);
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "steel");
  m.rigid = 1;
  m.friction = 1.0;
  m.param[ADEM_PARAM_ROLLING_FRICTION] = 0.1;
  adem_error err;
  int steel = -1;
  assert_int_equal(adem_world_add_material(w, &m, &steel, &err), ADEM_OK);
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = glass;
  it.material_b = steel;
  it.tangential = tangential;
  it.rolling = rolling;
  it.param[ADEM_PARAM_ROLLING_FRICTION] = 0.1;
  assert_int_equal(adem_world_set_interaction(w, &it, &err), ADEM_OK);
  adem_plane_def pl = adem_default_plane_def();
  snprintf(pl.name, sizeof pl.name, "floor");
  pl.material = steel;
  assert_int_equal(adem_world_add_plane(w, &pl, NULL, &err), ADEM_OK);
  test_particle(w, glass, v3(0, 0, 1e-3 - 1e-6), v3(v, 0, 0), 1e-3);
  adem_world_set_dt(w, 1e-6);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  return w;
}

static adem_contact_info the_contact(const adem_world *w) {
  adem_contact_info c;
  assert_int_equal(adem_world_contacts(w, &c, 1), 1);
  return c;
}

/* Claim (issue 25, item 7): prepare leaves the tangential spring empty (the sphere has not moved
 * yet), and step 1 puts in exactly one increment, -S_t w_t dt with the half step's slip velocity
 * w = v + r omega x n and S_t = 8 G sqrt(R delta) at the step's overlap (to 1e-12). Before,
 * prepare's pass advanced the spring by one step of the initial velocity, and step 1 held two
 * increments (ratio 2.0). A second call of adem_world_compute_forces changes no history. */
static void test_spring_empty_after_prepare(void **state) {
  (void)state;
  adem_world *w = launched(ADEM_TANGENTIAL_INCREMENTAL, ADEM_ROLLING_NONE, 0.1);
  adem_particles *p = &w->p;
  adem_contact_info c0 = the_contact(w);
  printf("# after prepare: spring force (%.3e, %.3e, %.3e) N\n", c0.tangential_history.x,
         c0.tangential_history.y, c0.tangential_history.z);
  /* the half step's velocity and spin, as the opening kick of step 1 makes them */
  double dt = adem_world_dt(w);
  adem_vec3 vh = v3_axpy(p->vel[0], 0.5 * dt * p->inv_mass[0], p->force[0]);
  adem_vec3 oh = v3_axpy(p->omega[0], 0.5 * dt * p->inv_inertia[0], p->torque[0]);
  adem_error err;
  assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
  adem_vec3 n = v3(0, 0, -1);
  adem_vec3 wv = v3_add(vh, v3_cross(v3_scale(oh, 1e-3), n));
  adem_vec3 wt = v3_axpy(wv, -v3_dot(wv, n), n);
  double delta = 1e-3 - p->pos[0].z, R = 1e-3;
  double St = 8.0 * adem_world_interaction(w, 0, 1)->pp.G * sqrt(R * delta);
  adem_vec3 expect = v3_scale(wt, -St * dt);
  adem_contact_info c1 = the_contact(w);
  double ratio = c1.tangential_history.x / expect.x;
  printf("# after step 1: spring %.9e N, one increment -S_t w_t dt = %.9e N (ratio %.12f)\n",
         c1.tangential_history.x, expect.x, ratio);
  assert_true(c0.tangential_history.x == 0.0 && c0.tangential_history.y == 0.0 &&
              c0.tangential_history.z == 0.0);
  assert_true(fabs(ratio - 1.0) < 1e-12);
  assert_true(v3_norm(v3_sub(c1.tangential_history, expect)) <= 1e-12 * v3_norm(expect));
  adem_world_compute_forces(w);
  adem_world_compute_forces(w);
  adem_contact_info c2 = the_contact(w);
  assert_memory_equal(&c2.tangential_history, &c1.tangential_history, sizeof(adem_vec3));
  adem_world_free(w);
}

/* Claim (issue 25, item 7): the same for the other histories: the total-displacement spring and
 * model C's rolling spring are empty after prepare, and after step 1 the total law's holds one
 * step of slip, w_t dt (to 1e-12; launched at 1 mm/s, so that the dashpot, which the total law's
 * Coulomb limit counts, leaves it sticking). Before: xi held one step of the launch speed after
 * prepare. */
static void test_other_springs_empty_after_prepare(void **state) {
  (void)state;
  adem_world *w = launched(ADEM_TANGENTIAL_TOTAL, ADEM_ROLLING_C, 1e-3);
  adem_particles *p = &w->p;
  adem_contact_info c0 = the_contact(w);
  printf("# after prepare: total-law xi %.3e m, model C torque %.3e N m\n",
         v3_norm(c0.tangential_history), v3_norm(c0.rolling_history));
  assert_true(v3_norm(c0.tangential_history) == 0.0);
  assert_true(v3_norm(c0.rolling_history) == 0.0);
  double dt = adem_world_dt(w);
  adem_vec3 vh = v3_axpy(p->vel[0], 0.5 * dt * p->inv_mass[0], p->force[0]);
  adem_vec3 oh = v3_axpy(p->omega[0], 0.5 * dt * p->inv_inertia[0], p->torque[0]);
  adem_error err;
  assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
  adem_vec3 n = v3(0, 0, -1);
  adem_vec3 wv = v3_add(vh, v3_cross(v3_scale(oh, 1e-3), n));
  adem_vec3 wt = v3_axpy(wv, -v3_dot(wv, n), n);
  adem_contact_info c1 = the_contact(w);
  printf("# after step 1: xi %.9e m, w_t dt %.9e m\n", c1.tangential_history.x, wt.x * dt);
  assert_true(fabs(c1.tangential_history.x / (wt.x * dt) - 1.0) < 1e-12);
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_spring_empty_after_prepare),
      cmocka_unit_test(test_other_springs_empty_after_prepare),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
