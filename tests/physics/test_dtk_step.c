/* The step proposal and DTK's rolling spring under reduced stiffness (issue 25 item 9;
 * docs/models.md, "Time step"). DTK keeps F_C of the real material (H section 3.2), so its rolling
 * stiffness k_r = 4 F_C (a/a0)^(3/2) does not fall with E_mod = f E while the collision time
 * grows as f^(-2/5): at small f the rolling mode is the fastest. A 50 um PSL-like sphere (E* 271
 * MPa, gamma 0.11) resting at the JKR equilibrium on a rigid wall at f = 1e-5, set rocking
 * (xi far below xi_crit). Claims checked:
 *  - the stability limit includes the rolling mode (t_c/29.4 here, against t_c/4.9 at f = 1)
 *    and the proposal is at most a fifth of it (t_c/147 instead of t_c/50);
 *  - with it the rocking stays bounded: the largest spin over 4000 steps is below the initial
 *    one (0.986; 1.05 at min(t_c/50, 0.2 t_R), where the rolling mode is at 0.58 of the
 *    limit: the limit is conservative, from the peak stiffness of a 1 m/s impact). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "adem/adem.h"
#include "adem/vec3.h"

static const double R = 50e-6, RHO = 1026.0, ESTAR = 2.71e8, NU = 0.3, GAMMA = 0.11, F = 1e-5;

/* The sphere at rest on the wall spinning at omega0 about y; returns the largest |omega| over
 * the steps with step dt (0: the proposal), and the estimate. */
static double rock(double dt, double omega0, int steps, adem_step_estimate *est) {
  adem_world *w = adem_world_create();
  adem_world_set_threads(w, 1);
  adem_world_set_gravity(w, v3_zero());
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "psl");
  m.density = RHO;
  m.poisson = NU;
  m.young = (1.0 - NU * NU) * ESTAR; /* the wall is rigid: E* is the sphere's */
  m.stiffness_factor = F;
  m.restitution = 0.86;
  m.friction = 0.3;
  m.param[ADEM_PARAM_SURFACE_ENERGY] = GAMMA;
  m.param[ADEM_PARAM_ADHESION_HYSTERESIS] = 0.5;
  int ms = -1, mw = -1;
  assert_int_equal(adem_world_add_material(w, &m, &ms, NULL), ADEM_OK);
  snprintf(m.name, sizeof m.name, "quartz");
  m.rigid = 1;
  assert_int_equal(adem_world_add_material(w, &m, &mw, NULL), ADEM_OK);
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = ms;
  it.material_b = mw;
  it.normal = ADEM_NORMAL_JKR;
  it.rolling = ADEM_ROLLING_DTK;
  it.dtk_rolling_modification = 1;
  assert_int_equal(adem_world_set_interaction(w, &it, NULL), ADEM_OK);
  adem_plane_def pl = adem_default_plane_def();
  snprintf(pl.name, sizeof pl.name, "wall");
  pl.material = mw;
  assert_int_equal(adem_world_add_plane(w, &pl, NULL, NULL), ADEM_OK);
  /* the JKR equilibrium of the modified material: delta = a0^2/(3R), gamma_mod = gamma f^(2/5) */
  double E_mod = ESTAR * F, gamma_mod = GAMMA * pow(F, 0.4);
  double a0 = adem_law_jkr_a0(gamma_mod, R, E_mod);
  adem_particle_def p = adem_default_particle_def();
  p.material = ms;
  p.radius = R;
  p.position = v3(0.0, 0.0, R - a0 * a0 / (3.0 * R));
  p.angular_velocity = v3(0.0, omega0, 0.0);
  assert_int_equal(adem_world_add_particle(w, &p, NULL, NULL), ADEM_OK);
  adem_world_set_domain(w, v3(-1e-3, -1e-3, -1e-3), v3(1e-3, 1e-3, 1e-3));
  *est = adem_world_estimate_step(w, 1.0);
  adem_world_set_dt(w, dt > 0.0 ? dt : est->dt);
  adem_world_set_initial_overlap(w, 0.01); /* it starts at the JKR equilibrium */
  adem_error err;
  adem_status st = adem_world_prepare(w, &err);
  if (st) printf("# %s\n", err.message);
  if (st) return NAN;
  assert_int_equal(st, ADEM_OK);
  double most = 0.0, om[3];
  for (int k = 0; k < steps; ++k) {
    if (adem_world_step(w, 1, &err) != ADEM_OK) {
      most = INFINITY;
      break;
    }
    adem_world_get_particles(w, ADEM_FIELD_ANGULAR_VELOCITY, om, 3, NULL);
    most = fmax(most, sqrt(om[0] * om[0] + om[1] * om[1] + om[2] * om[2]));
    if (!isfinite(most) || most > 1e6 * omega0) break;
  }
  adem_world_free(w);
  return most;
}

static void test_proposal_includes_rolling_mode(void **state) {
  (void)state;
  const double omega0 = 1.0; /* rad/s: xi stays far below xi_crit */
  adem_step_estimate est, e2;
  double with = rock(0.0, omega0, 4000, &est);
  double old = rock(fmin(est.t_collision / 50.0, 0.2 * est.t_rayleigh), omega0, 4000, &e2);
  double old_dt = fmin(est.t_collision / 50.0, 0.2 * est.t_rayleigh);
  printf("# R %g m, f = %g: t_c %.4g s, 0.2 t_R %.4g s, stability limit %.4g s = t_c/%.1f, "
         "proposed %.4g s = t_c/%.0f (min(t_c/50, 0.2 t_R) = %.4g s)\n",
         R, F, est.t_collision,
         0.2 * est.t_rayleigh, est.dt_stable, est.t_collision / est.dt_stable, est.dt,
         est.t_collision / est.dt, old_dt);
  printf("# largest spin / initial over 4000 steps: %.6f at the proposal, %.6f at "
         "min(t_c/50, 0.2 t_R)\n",
         with / omega0, old / omega0);
  assert_true(est.dt <= 0.2 * est.dt_stable * (1.0 + 1e-12));
  assert_true(est.dt < 0.4 * old_dt); /* the rolling mode sets the proposal here */
  assert_true(with < 1.0 * omega0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_proposal_includes_rolling_mode),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
