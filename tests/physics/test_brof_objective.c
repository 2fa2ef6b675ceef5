/* BROF in rotating equipment (issue 25 item 6; docs/models.md, "Rolling resistance"). Two
 * adhesive spheres stuck side by side (JKR, at their equilibrium overlap) on a floor that turns at
 * 3 rad/s about the vertical through their contact, set turning rigidly with it. BROF as I and
 * Kratos define it resists a particle's absolute spin through its particle contacts and the spin
 * relative to the wall through its wall contact: the target is Omega C_w/(C_w + C_p) and the pair
 * is braked and slips for ever. The objective row (`brof_objective`) takes the capacity-weighted
 * mean of all partners' spins as the target. Claims checked:
 *  - brof_objective: both spheres keep the table's spin to 1e-3 (0.99926 Omega after 0.5 s);
 *  - brof: the spin falls below 0.9 Omega (0.676) and the table's work is dissipated (5.0e-5 J,
 *    120 times the pair's kinetic energy): the defect, and the check's ability to fail;
 *  - both: the energy balance closes (to 1e-9 J). Not claimed: that brof_objective dissipates
 *    nothing. It is no couple either: the work of its torque towards a partner's spin has no
 *    reaction, and here the table's work (-3.7e-5 J) and the dissipated energy (-3.7e-5 J) are
 *    equal and negative: a steady torque about z that the objective target feeds. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "adem/adem.h"
#include "adem/vec3.h"

static const double R = 5e-3, RHO = 2500.0, ETA = 0.2, TABLE = 3.0, GAMMA = 0.5;

static int add_material(adem_world *w, const char *name, int rigid) {
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "%s", name);
  m.density = RHO;
  m.young = 1e7;
  m.restitution = 0.5;
  m.friction = 0.5;
  m.rigid = rigid;
  m.param[ADEM_PARAM_ROLLING_FRICTION] = ETA;
  int k = -1;
  assert_int_equal(adem_world_add_material(w, &m, &k, NULL), ADEM_OK);
  return k;
}

typedef struct turn_result {
  double spin[2];    /* omega_z of the two spheres, rad/s */
  double dissipated; /* J */
  double kinetic;    /* J, at the end */
} turn_result;

static turn_result turn(adem_rolling_model model, double t) {
  adem_world *w = adem_world_create();
  adem_world_set_threads(w, 1);
  adem_world_set_gravity(w, v3(0.0, 0.0, -9.81));
  int grain = add_material(w, "grain", 0), floor = add_material(w, "floor", 1);
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = grain;
  it.material_b = floor;
  it.rolling = model;
  assert_int_equal(adem_world_set_interaction(w, &it, NULL), ADEM_OK);
  it.material_b = grain;
  it.normal = ADEM_NORMAL_JKR;
  it.param[ADEM_PARAM_SURFACE_ENERGY] = GAMMA;
  assert_int_equal(adem_world_set_interaction(w, &it, NULL), ADEM_OK);
  adem_plane_def pl = adem_default_plane_def();
  snprintf(pl.name, sizeof pl.name, "table");
  pl.material = floor;
  int plane = -1;
  assert_int_equal(adem_world_add_plane(w, &pl, &plane, NULL), ADEM_OK);
  adem_motion_def md = {0};
  md.axis = v3(0.0, 0.0, 1.0);
  md.angular_speed = TABLE;
  assert_int_equal(adem_world_set_plane_motion(w, plane, &md, NULL), ADEM_OK);
  double m = RHO * 4.0 / 3.0 * ADEM_PI * R * R * R;
  double ewall = 1e7 / (1.0 - 0.25 * 0.25), epair = 0.5 * ewall;
  double dz = pow(3.0 * m * 9.81 / (4.0 * ewall * sqrt(R)), 2.0 / 3.0); /* static Hertz */
  double a0 = adem_law_jkr_a0(GAMMA, 0.5 * R, epair);
  double dx = a0 * a0 / (3.0 * 0.5 * R); /* JKR equilibrium overlap of the pair */
  for (int s = 0; s < 2; ++s) {
    double x = (s ? 1.0 : -1.0) * (R - 0.5 * dx);
    adem_particle_def p = adem_default_particle_def();
    p.material = grain;
    p.radius = R;
    p.position = v3(x, 0.0, R - dz);
    p.velocity = v3(0.0, TABLE * x, 0.0); /* turning rigidly with the table */
    p.angular_velocity = v3(0.0, 0.0, TABLE);
    assert_int_equal(adem_world_add_particle(w, &p, NULL, NULL), ADEM_OK);
  }
  adem_world_set_initial_overlap(w, 0.01);
  adem_world_set_dt(w, 2e-5);
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  assert_int_equal(adem_world_step(w, (uint64_t)llround(t / 2e-5), &err), ADEM_OK);
  double om[6];
  adem_world_get_particles(w, ADEM_FIELD_ANGULAR_VELOCITY, om, 6, NULL);
  adem_diagnostics d = adem_world_diagnostics(w);
  adem_world_free(w);
  printf("# wall work %.3g J, balance error %.3g J, elastic %.3g J\n", d.wall_work, d.balance_error, d.elastic);
  assert_true(fabs(d.balance_error) < 1e-9);
  turn_result r = {{om[2], om[5]}, d.dissipated, d.kinetic + d.rotational};
  return r;
}

static void test_turntable_pair(void **state) {
  (void)state;
  turn_result obj = turn(ADEM_ROLLING_BROF_OBJECTIVE, 0.5), abs_ = turn(ADEM_ROLLING_BROF, 0.5);
  printf("# brof_objective: spins %.6f, %.6f Omega after 0.5 s; dissipated %.3g J of kinetic "
         "%.3g J\n",
         obj.spin[0] / TABLE, obj.spin[1] / TABLE, obj.dissipated, obj.kinetic);
  printf("# brof:           spins %.6f, %.6f Omega after 0.5 s; dissipated %.3g J of kinetic "
         "%.3g J\n",
         abs_.spin[0] / TABLE, abs_.spin[1] / TABLE, abs_.dissipated, abs_.kinetic);
  for (int s = 0; s < 2; ++s) assert_true(fabs(obj.spin[s] / TABLE - 1.0) < 1e-3);
  for (int s = 0; s < 2; ++s) assert_true(abs_.spin[s] < 0.9 * TABLE);
  assert_true(abs_.dissipated > 0.1 * abs_.kinetic);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_turntable_pair),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
