/* The step limit with damping and the tangential-rotational mode (issue 25; docs/models.md,
 * "Time step"). A sticking oblique impact: Irazabal Table 1's sphere (10 mm, rho 1056, E 4e7,
 * nu 0.49), e = 0.2, mu = 0.8, 45 degrees at 1 m/s on a rigid plane. The tangential spring acts
 * through the contact point's mass m/3.5 and oscillates sqrt(3.5 S_t/S_n) = 1.54 times faster than
 * the normal one; its dashpot has a damping ratio sqrt(3.5) times the normal one's. With the
 * tangential dashpot taken explicitly on the predicted velocity (the scheme before issue 25)
 * this contact rang from step to step from t_c/9.4 (e = 0.2) and t_c/13.7 (e = 0.1) on; at the
 * guard's limit below it gave 4 and 6 sign flips on consecutive steps and a spin 10.9 % and
 * 5.4 % too high. Claims checked, at e = 0.2 and 0.1 (damping ratio of the tangential mode
 * 0.78 and 1.01):
 *  - at the largest step the guard allows (adem_step_estimate's dt_limit: t_c/6.14 and
 *    t_c/7.34 here, set by the normal dashpot, docs/models.md), the tangential force never flips
 *    its sign on two consecutive steps (the signature of the two-step instability), and the
 *    rebound spin is within 2 % of the run at t_c/50 (measured -1.81 % and -0.93 %: the error of
 *    a step of a sixth of the collision, not an instability);
 *  - at t_c/10 the spin is within 1 % of it (-0.77 %, -0.48 %). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "adem/adem.h"
#include "adem/vec3.h"

static const double R = 0.01, RHO = 1056.0, E = 4.0e7, NU = 0.49, V = 1.0;

typedef struct impact_result {
  double spin;      /* omega_y after the impact, rad/s */
  double e_eff;     /* normal restitution */
  int flips;        /* sign changes of the tangential force while in contact */
  int double_flips; /* sign changes on two consecutive steps */
  double t_c, dt_limit, dt;
} impact_result;

/* steps > 0: dt = t_c/steps; steps = 0: the guard's limit. */
static impact_result impact(double e, double steps) {
  impact_result r = {0};
  adem_world *w = adem_world_create();
  adem_world_set_threads(w, 1);
  adem_world_set_gravity(w, v3_zero());
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "sphere");
  m.density = RHO;
  m.young = E;
  m.poisson = NU;
  m.restitution = e;
  m.friction = 0.8;
  int ms = -1, mw = -1;
  assert_int_equal(adem_world_add_material(w, &m, &ms, NULL), ADEM_OK);
  snprintf(m.name, sizeof m.name, "wall");
  m.rigid = 1;
  assert_int_equal(adem_world_add_material(w, &m, &mw, NULL), ADEM_OK);
  adem_plane_def pl = adem_default_plane_def();
  snprintf(pl.name, sizeof pl.name, "floor");
  pl.material = mw;
  assert_int_equal(adem_world_add_plane(w, &pl, NULL, NULL), ADEM_OK);
  double vn = V * sqrt(0.5);
  adem_particle_def p = adem_default_particle_def();
  p.material = ms;
  p.radius = R;
  p.position = v3(0.0, 0.0, R + 1e-6);
  p.velocity = v3(vn, 0.0, -vn);
  assert_int_equal(adem_world_add_particle(w, &p, NULL, NULL), ADEM_OK);
  adem_world_set_domain(w, v3(-1.0, -1.0, -1.0), v3(1.0, 1.0, 1.0));
  adem_step_estimate est = adem_world_estimate_step(w, vn);
  r.t_c = est.t_collision;
  r.dt_limit = est.dt_limit;
  r.dt = steps > 0.0 ? est.t_collision / steps : est.dt_limit;
  adem_world_set_dt(w, r.dt);
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  double f_old = 0.0;
  int flipped_last = 0;
  bool touched = false;
  double x[3], v[3], f[3], om[3];
  for (int k = 0; k < 100000; ++k) {
    assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
    adem_world_get_particles(w, ADEM_FIELD_POSITION, x, 3, NULL);
    adem_world_get_particles(w, ADEM_FIELD_FORCE, f, 3, NULL);
    bool in = x[2] < R;
    if (in) {
      touched = true;
      int flip = f_old != 0.0 && f[0] != 0.0 && (f[0] > 0.0) != (f_old > 0.0);
      r.flips += flip;
      r.double_flips += flip && flipped_last;
      flipped_last = flip;
      f_old = f[0];
    } else if (touched) {
      break;
    }
  }
  adem_world_get_particles(w, ADEM_FIELD_VELOCITY, v, 3, NULL);
  adem_world_get_particles(w, ADEM_FIELD_ANGULAR_VELOCITY, om, 3, NULL);
  r.spin = om[1];
  r.e_eff = v[2] / vn;
  adem_world_free(w);
  return r;
}

static void check(double e) {
  impact_result ref = impact(e, 50.0), lim = impact(e, 0.0);
  printf("# e = %.1f: t_c %.4g s, guard's limit t_c/%.2f; at t_c/50: spin %.6g rad/s, e_eff %.4f, "
         "%d flips; at the limit: spin %.6g rad/s (%+.3f%%), e_eff %.4f, %d flips, %d on "
         "consecutive steps\n",
         e, ref.t_c, ref.t_c / lim.dt_limit, ref.spin, ref.e_eff, ref.flips, lim.spin,
         100.0 * (lim.spin / ref.spin - 1.0), lim.e_eff, lim.flips, lim.double_flips);
  for (int k = 0; k < 7; ++k) {
    double n = (double[]){3.0, 4.0, 5.0, 7.0, 10.0, 12.0, 15.0}[k];
    impact_result s = impact(e, n);
    printf("#   t_c/%-4.0f spin %+.6g rad/s (%+.2f%%), e_eff %.4f, flips %d, consecutive %d\n", n,
           s.spin, 100.0 * (s.spin / ref.spin - 1.0), s.e_eff, s.flips, s.double_flips);
  }
  impact_result ten = impact(e, 10.0);
  assert_true(lim.dt_limit <= ref.t_c / 5.0);
  assert_int_equal(lim.double_flips, 0);
  assert_true(fabs(lim.spin / ref.spin - 1.0) < 0.02);
  assert_int_equal(ten.double_flips, 0);
  assert_true(fabs(ten.spin / ref.spin - 1.0) < 0.01);
}

static void test_sticking_oblique_e02(void **state) {
  (void)state;
  check(0.2);
}

static void test_sticking_oblique_e01(void **state) {
  (void)state;
  check(0.1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sticking_oblique_e02),
      cmocka_unit_test(test_sticking_oblique_e01),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
