/* Prescribed wall motion: the exact integral of a piecewise-linear velocity and rigid rotation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "helpers.h"
#include "motion.h"
#include "adem/vec3.h"
#include "world_internal.h"

static const double T[3] = {0.0, 1.0, 3.0};
static const adem_vec3 V[3] = {{1.0, 0.0, 0.0}, {3.0, 0.0, -2.0}, {3.0, 1.0, 0.0}};

/* Claim: the displacement is the exact integral of the table (trapezoids per segment) and the
 * velocity is its derivative (central differences agree to round-off on a linear segment). */
static void test_piecewise_linear(void **state) {
  (void)state;
  adem_motion m;
  adem_motion_def d = {.n = 3, .time = T, .velocity = V};
  adem_error err;
  assert_int_equal(adem_motion_init(&m, &d, &err), ADEM_OK);
  /* by hand: 0..1: (1+3)/2 = 2 in x, -1 in z; 1..2: 3 in x, y 0.5, z -1 (half of 1..3 averaged) */
  adem_vec3 d2 = adem_motion_displacement(&m, 2.0);
  assert_true(fabs(d2.x - 5.0) < 1e-15 && fabs(d2.y - 0.25) < 1e-15 && fabs(d2.z + 2.5) < 1e-15);
  adem_vec3 d5 = adem_motion_displacement(&m, 5.0); /* past the table: constant last velocity */
  assert_true(fabs(d5.x - 14.0) < 1e-14 && fabs(d5.y - 3.0) < 1e-14 && fabs(d5.z + 3.0) < 1e-14);
  for (double t = 0.05; t < 4.0; t += 0.1) {
    double h = 1e-6;
    adem_vec3 fd = v3_scale(v3_sub(adem_motion_displacement(&m, t + h),
                                   adem_motion_displacement(&m, t - h)),
                            0.5 / h);
    assert_true(v3_norm(v3_sub(fd, adem_motion_velocity(&m, t))) < 1e-8);
  }
  adem_motion_free(&m);
}

/* Claim: a rotating wall turns rigidly about its axis through a travelling centre, and the
 * velocity at a point is the time derivative of that point's place. */
static void test_rotation(void **state) {
  (void)state;
  adem_vec3 v = {0.5, 0.0, 0.0};
  double t0 = 0.0;
  adem_motion_def d = {.n = 1, .time = &t0, .velocity = &v, .axis = {0, 0, 2}, .angular_speed = 3.14159265358979323846, .center = {1, 0, 0}};
  adem_motion m;
  adem_error err;
  assert_int_equal(adem_motion_init(&m, &d, &err), ADEM_OK);
  adem_vec3 x = adem_motion_place(&m, 0.5, v3(2, 0, 0)); /* quarter turn, centre moved by 0.25 */
  assert_true(fabs(x.x - 1.25) < 1e-15 && fabs(x.y - 1.0) < 1e-15 && fabs(x.z) < 1e-15);
  double h = 1e-6;
  adem_vec3 fd = v3_scale(v3_sub(adem_motion_place(&m, 0.5 + h, v3(2, 0, 0)),
                                 adem_motion_place(&m, 0.5 - h, v3(2, 0, 0))),
                          0.5 / h);
  assert_true(v3_norm(v3_sub(fd, adem_motion_point_velocity(&m, 0.5, x))) < 1e-8);
  adem_vec3 n = adem_motion_turn(&m, 0.5, v3(1, 0, 0));
  assert_true(fabs(n.x) < 1e-15 && fabs(n.y - 1.0) < 1e-15);
  adem_motion_free(&m);
}

/* Claim: a table of positions puts the wall exactly (bit for bit) at each knot's displacement
 * at its time, moves it at each segment's constant slope in between (the velocity is the
 * derivative of the place), and holds it before the first knot and after the last (it stops). */
static void test_positions(void **state) {
  (void)state;
  const double t[3] = {0.2, 0.25, 0.5};
  const adem_vec3 x[3] = {{0.0, 0.0, 0.0}, {0.06, 0.0, 0.0}, {0.06, 0.01, -0.003}};
  adem_motion_def d = {.n = 3, .time = t, .position = x};
  adem_motion m;
  adem_error err;
  assert_int_equal(adem_motion_init(&m, &d, &err), ADEM_OK);
  assert_true(m.moving);
  for (int k = 0; k < 3; ++k) {
    adem_vec3 p = adem_motion_displacement(&m, t[k]);
    assert_memory_equal(&p, &x[k], sizeof p);
  }
  adem_vec3 before = adem_motion_displacement(&m, 0.1), after = adem_motion_displacement(&m, 7.0);
  assert_memory_equal(&before, &x[0], sizeof before);
  assert_memory_equal(&after, &x[2], sizeof after);
  assert_true(v3_norm(adem_motion_velocity(&m, 0.1)) == 0.0);
  assert_true(v3_norm(adem_motion_velocity(&m, 0.6)) == 0.0);
  adem_vec3 v = adem_motion_velocity(&m, 0.22);
  assert_true(fabs(v.x - 1.2) < 1e-12 && v.y == 0.0 && v.z == 0.0);
  adem_vec3 mid = adem_motion_displacement(&m, 0.225);
  assert_true(fabs(mid.x - 0.03) < 1e-15);
  for (double s = 0.205; s < 0.5; s += 0.02) { /* away from the knots: the derivative */
    double h = 1e-7;
    adem_vec3 fd = v3_scale(v3_sub(adem_motion_displacement(&m, s + h),
                                   adem_motion_displacement(&m, s - h)),
                            0.5 / h);
    assert_true(v3_norm(v3_sub(fd, adem_motion_velocity(&m, s))) < 1e-7);
  }
  /* a copy (as a stage makes) keeps the kind; a velocity table of the same numbers differs */
  adem_motion c;
  assert_int_equal(adem_motion_copy(&c, &m, &err), ADEM_OK);
  assert_true(c.positions && adem_motion_same(&c, &m));
  adem_motion_def dv = {.n = 3, .time = t, .velocity = x};
  adem_motion mv;
  assert_int_equal(adem_motion_init(&mv, &dv, &err), ADEM_OK);
  assert_false(adem_motion_same(&mv, &m));
  adem_motion_free(&m);
  adem_motion_free(&c);
  adem_motion_free(&mv);
}

/* Claim: a motion table out of time order is refused with a message naming the entries. */
static void test_unordered_table(void **state) {
  (void)state;
  const double t[3] = {0.0, 2.0, 1.0};
  adem_motion_def d = {.n = 3, .time = t, .velocity = V};
  adem_motion m;
  adem_error err;
  assert_int_equal(adem_motion_init(&m, &d, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "not ordered in time"));
  assert_non_null(strstr(err.message, "entry 2"));
}

/* Claim: a sphere at rest on a plate moving at V is dragged by friction until it rolls on it:
 * angular momentum about the contact point is conserved, so it ends at v = (2/7) V, omega r =
 * -(5/7) V (relative to the plate it rolls backwards). */
static void test_sphere_on_moving_plane(void **state) {
  (void)state;
  adem_world *w = adem_world_create();
  int mat = test_material(w, "m", 1e8, 0.3, 0.3, 0.4);
  adem_plane_def pl = adem_default_plane_def();
  snprintf(pl.name, sizeof pl.name, "belt");
  pl.material = mat;
  pl.velocity = v3(1.0, 0.0, 0.0);
  adem_error err;
  assert_int_equal(adem_world_add_plane(w, &pl, NULL, &err), ADEM_OK);
  double r = 5e-3;
  double E = 1.0 / (2.0 * (1.0 - 0.09) / 1e8);
  double delta = pow(3.0 * test_sphere_mass(r, 2500.0) * 9.81 / (4.0 * E * sqrt(r)), 2.0 / 3.0);
  test_particle(w, mat, v3(0, 0, r - delta), v3(0, 0, 0), r);
  adem_step_estimate est = adem_world_estimate_step(w, 1.0);
  adem_world_set_dt(w, est.dt);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  assert_int_equal(adem_world_step(w, (uint64_t)(0.3 / est.dt), &err), ADEM_OK);
  double v = w->p.vel[0].x, spin = w->p.omega[0].y * r;
  printf("# v/V = %.6f (2/7 = %.6f), omega r/V = %.6f (-5/7)\n", v, 2.0 / 7.0, spin);
  assert_true(fabs(v - 2.0 / 7.0) < 0.002);
  assert_true(fabs(spin + 5.0 / 7.0) < 0.002);
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_piecewise_linear),
      cmocka_unit_test(test_rotation),
      cmocka_unit_test(test_positions),
      cmocka_unit_test(test_unordered_table),
      cmocka_unit_test(test_sphere_on_moving_plane),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
