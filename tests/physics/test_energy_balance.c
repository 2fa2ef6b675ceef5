/* The energy balance of a run: initial + wall work = current + dissipated (+ balance error),
 * with the dissipated energy and the wall work accumulated every step contact by contact
 * (docs/models.md, "Energy bookkeeping"). What is left, the balance error, is the energy error of
 * the time integration (the trapezoid error of the elastic forces' work), second order in the
 * step, and the energy a law creates. Claims checked:
 *  - a damped, rubbing impact on a fixed plane closes the balance to the integration error, which
 *    falls as dt^2 (ratio ~4 per halving);
 *  - a moving plane's work is counted: a piston that hits a sphere (e = 1) gives it the kinetic
 *    energy the balance says; a turntable that spins a sphere up by friction gives it kinetic
 *    energy plus what friction dissipated;
 *  - with the total-displacement tangential law the balance shows the energy that law creates in
 *    a sticking oblique impact, far above the integration error of the incremental law. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "adem/adem.h"
#include "adem/vec3.h"

typedef struct scene {
  double e, mu;
  adem_tangential_model tangential;
  adem_vec3 velocity, spin; /* of the sphere */
  adem_vec3 gravity;
  adem_vec3 plane_velocity; /* piston */
  double plane_spin;        /* turntable, rad/s about +z */
  double start_height;      /* centre above the plane, in radii */
  double offset;            /* centre from the turntable axis, m */
  double steps_per_tc;
  double duration; /* in t_c */
} scene;

typedef struct balance {
  double initial, current, dissipated, wall_work, error, ke_end;
} balance;

static balance run(const scene *sc) {
  adem_world *w = adem_world_create();
  adem_world_set_gravity(w, sc->gravity);
  adem_world_set_threads(w, 1);
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "grain");
  m.young = 1e7;
  m.restitution = sc->e;
  m.friction = sc->mu;
  int grain = -1, floor = -1;
  assert_int_equal(adem_world_add_material(w, &m, &grain, NULL), ADEM_OK);
  m.rigid = 1;
  snprintf(m.name, sizeof m.name, "floor");
  assert_int_equal(adem_world_add_material(w, &m, &floor, NULL), ADEM_OK);
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = grain;
  it.material_b = floor;
  it.tangential = sc->tangential;
  assert_int_equal(adem_world_set_interaction(w, &it, NULL), ADEM_OK);
  adem_plane_def pl = adem_default_plane_def();
  snprintf(pl.name, sizeof pl.name, "floor");
  pl.material = floor;
  int plane = -1;
  assert_int_equal(adem_world_add_plane(w, &pl, &plane, NULL), ADEM_OK);
  if (v3_norm2(sc->plane_velocity) > 0.0 || sc->plane_spin != 0.0) {
    double t0 = 0.0;
    adem_motion_def md = {0};
    md.n = v3_norm2(sc->plane_velocity) > 0.0 ? 1 : 0;
    md.time = &t0;
    md.velocity = &sc->plane_velocity;
    md.axis = v3(0.0, 0.0, 1.0);
    md.angular_speed = sc->plane_spin;
    assert_int_equal(adem_world_set_plane_motion(w, plane, &md, NULL), ADEM_OK);
  }
  const double r = 1e-3;
  adem_particle_def p = adem_default_particle_def();
  p.material = grain;
  p.radius = r;
  p.position = v3(sc->offset, 0.0, sc->start_height * r);
  p.velocity = sc->velocity;
  p.angular_velocity = sc->spin;
  assert_int_equal(adem_world_add_particle(w, &p, NULL, NULL), ADEM_OK);
  adem_step_estimate est = adem_world_estimate_step(w, 1.0);
  adem_world_set_dt(w, est.t_collision / sc->steps_per_tc);
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  uint64_t n = (uint64_t)(sc->duration * sc->steps_per_tc);
  assert_int_equal(adem_world_step(w, n, &err), ADEM_OK);
  adem_diagnostics d = adem_world_diagnostics(w);
  balance b = {d.initial, d.kinetic + d.rotational + d.potential + d.elastic, d.dissipated,
               d.wall_work, d.balance_error, d.kinetic + d.rotational};
  adem_world_free(w);
  return b;
}

static scene base(void) {
  scene s = {0};
  s.e = 0.5;
  s.mu = 0.3;
  s.tangential = ADEM_TANGENTIAL_INCREMENTAL;
  s.velocity = v3(0.6, 0.2, -1.0);
  s.spin = v3(0.0, 300.0, 0.0);
  s.start_height = 1.02;
  s.offset = 2e-4;
  s.steps_per_tc = 50.0;
  s.duration = 30.0;
  return s;
}

static void test_rubbing_impact_converges(void **state) {
  (void)state;
  scene s = base();
  s.gravity = v3(0.0, 0.0, -9.81);
  double err[3];
  for (int k = 0; k < 3; ++k) {
    s.steps_per_tc = 50.0 * (1 << k);
    balance b = run(&s);
    err[k] = b.error / b.initial;
    printf("# %4.0f steps per t_c: initial %.6g J, dissipated %.6g J, balance error %.3e of the "
           "initial energy\n",
           s.steps_per_tc, b.initial, b.dissipated, err[k]);
    assert_true(b.dissipated > 0.3 * b.initial);
  }
  assert_true(fabs(err[0]) < 2e-3);
  /* second order: the integration error, not a missing term (which would not fall) */
  assert_true(fabs(err[0] / err[1]) > 3.0 && fabs(err[1] / err[2]) > 3.0);
}

static void test_piston(void **state) {
  (void)state;
  scene s = base();
  s.e = 1.0;
  s.mu = 0.0;
  s.velocity = v3(0.0, 0.0, 0.0);
  s.spin = v3(0.0, 0.0, 0.0);
  s.plane_velocity = v3(0.0, 0.0, 1.0); /* the plane comes up at 1 m/s */
  s.duration = 20.0;
  s.steps_per_tc = 200.0;
  balance b = run(&s);
  /* the sphere leaves at 2 V: kinetic energy 2 m V^2, all of it from the plane */
  double m = 1e7 * 0.0 + 2500.0 * 4.0 / 3.0 * ADEM_PI * 1e-9;
  printf("# piston: wall work %.8g J, kinetic energy %.8g J (2 m V^2 = %.8g), balance error %.2e\n",
         b.wall_work, b.ke_end, 2.0 * m, b.error);
  assert_true(fabs(b.wall_work / (2.0 * m) - 1.0) < 1e-4);
  assert_true(fabs(b.error) < 1e-5 * b.wall_work);
}

static void test_turntable(void **state) {
  (void)state;
  scene s = base();
  s.gravity = v3(0.0, 0.0, -9.81);
  s.velocity = v3(0.0, 0.0, 0.0);
  s.spin = v3(0.0, 0.0, 0.0);
  s.plane_spin = 20.0; /* the floor turns under the sphere: friction drags it along */
  s.offset = 0.01;
  s.start_height = 1.0 - 2.1e-4;
  s.duration = 2000.0;
  balance b = run(&s);
  printf("# turntable: wall work %.6g J, kinetic energy gained %.6g J, dissipated %.6g J, balance "
         "error %.2e\n",
         b.wall_work, b.ke_end, b.dissipated, b.error);
  assert_true(b.wall_work > 0.0 && b.ke_end > 0.0);
  assert_true(fabs(b.error) < 1e-3 * b.wall_work);
}

static void test_total_law_shows_in_balance(void **state) {
  (void)state;
  scene s = base();
  s.e = 1.0;
  s.mu = 10.0;
  s.velocity = v3(0.866, 0.0, -0.5);
  s.spin = v3(0.0, 0.0, 0.0);
  s.steps_per_tc = 200.0;
  balance inc = run(&s);
  s.tangential = ADEM_TANGENTIAL_TOTAL;
  balance tot = run(&s);
  printf("# sticking impact, e = 1, mu = 10: balance error / initial: incremental %.2e (dissipated "
         "%.4f of it), total %.2e (dissipated %.4f)\n",
         inc.error / inc.initial,
         inc.dissipated / inc.initial, tot.error / tot.initial, tot.dissipated / tot.initial);
  assert_true(fabs(inc.error) < 1e-4 * inc.initial);
  assert_true(fabs(tot.error) > 10.0 * fabs(inc.error));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rubbing_impact_converges),
      cmocka_unit_test(test_piston),
      cmocka_unit_test(test_turntable),
      cmocka_unit_test(test_total_law_shows_in_balance),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
