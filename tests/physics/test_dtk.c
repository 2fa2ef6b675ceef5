/* DTK adhesive rolling resistance (H18-H22, notes section 4) in the engine: the rolling velocity
 * of pure rolling and pure sliding, the torque law at a = a0 with and without the rolling
 * modification (H section 3.2), and that the rolling couple never gives back more energy than
 * its spring stored. Worlds are built through the public API; the history is read from the pair
 * lists (world.h). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "adem/studies.h"
#include "jkr.h"
#include "world_internal.h"

#define RADIUS 1e-6
#define RHO 1000.0
#define YOUNG 1e7 /* effective modulus of the pair, Pa */
#define NU 0.3
#define GAMMA (RHO * RADIUS / 3.0) /* Ad = 1 at 1 m/s */

/* JKR + DTK material of the spheres (E_i chosen so that the sphere-sphere pair has YOUNG) and a
 * rigid wall material of the same surface energy and hysteresis. */
static void add_materials(adem_world *w, double f, double hysteresis, double friction,
                          bool pair, int *ms, int *mw) {
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "sphere");
  m.density = RHO;
  m.poisson = NU;
  m.restitution = 0.5;
  m.friction = friction;
  m.param[ADEM_PARAM_SURFACE_ENERGY] = GAMMA;
  m.param[ADEM_PARAM_ADHESION_HYSTERESIS] = hysteresis;
  m.young = (pair ? 2.0 : 1.0) * (1.0 - NU * NU) * YOUNG;
  m.stiffness_factor = f;
  adem_error err;
  assert_int_equal(adem_world_add_material(w, &m, ms, &err), ADEM_OK);
  snprintf(m.name, sizeof m.name, "wall");
  m.rigid = 1;
  assert_int_equal(adem_world_add_material(w, &m, mw, &err), ADEM_OK);
  assert_true(*ms >= 0 && *mw >= 0);
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = *ms;
  it.material_b = pair ? *ms : *mw;
  it.normal = ADEM_NORMAL_JKR;
  it.rolling = ADEM_ROLLING_DTK;
  assert_int_equal(adem_world_set_interaction(w, &it, &err), ADEM_OK);
}

static adem_world *new_world(void) {
  adem_world *w = adem_world_create();
  adem_world_set_threads(w, 1);
  adem_world_set_gravity(w, v3_zero());
  adem_world_use_brute_force(w, 1);
  adem_world_set_max_overlap_ratio(w, 1.0);
  return w;
}

/* Equilibrium overlap a0^2/(3R) of the modified contact (notes section 2). */
static double equilibrium_overlap(double f, double R, double E) {
  double a0 = adem_jkr_a0(GAMMA * pow(f, 0.4), R, f * E);
  return a0 * a0 / (3.0 * R);
}

/* A sphere resting on the plane z = 0 at the JKR equilibrium, moving with v and spinning with
 * omega; dt a fraction of the oscillation period about the equilibrium. */
static adem_world *sphere_on_wall(double f, double hysteresis, double friction, adem_vec3 v,
                                  adem_vec3 omega, double *dt) {
  adem_world *w = new_world();
  int ms, mw;
  add_materials(w, f, hysteresis, friction, false, &ms, &mw);
  adem_error err;
  adem_plane_def pl = adem_default_plane_def();
  pl.material = mw;
  assert_int_equal(adem_world_add_plane(w, &pl, NULL, &err), ADEM_OK);
  adem_particle_def p = adem_default_particle_def();
  p.material = ms;
  p.radius = RADIUS;
  p.position = v3(0.0, 0.0, RADIUS - equilibrium_overlap(f, RADIUS, YOUNG));
  p.velocity = v;
  p.angular_velocity = omega;
  assert_int_equal(adem_world_add_particle(w, &p, NULL, &err), ADEM_OK);
  double mass = RHO * 4.0 / 3.0 * ADEM_PI * pow(RADIUS, 3);
  double a0 = adem_jkr_a0(GAMMA * pow(f, 0.4), RADIUS, f * YOUNG);
  *dt = 2.0 * ADEM_PI * sqrt(mass / (1.2 * f * YOUNG * a0)) / 400.0;
  adem_world_set_dt(w, *dt);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  return w;
}

/* The history of the only touching pair of list l. */
static const adem_contact_history *touching_history(const adem_pair_list *l) {
  for (size_t k = 0; k < l->n; ++k)
    if (l->touching[k]) return &l->hist[k];
  fail_msg("no contact");
  return NULL;
}

/* Claim (notes section 4): with Marshall's rolling velocity and n into the wall, pure rolling of
 * a sphere on a flat wall gives |v_L| equal to the centre's speed, along the velocity. One
 * advancing force pass (prepare's advances nothing) integrates xi = v_L dt from a state of exact
 * pure rolling (contact point at rest), so |xi|/dt must be |v| to round-off (1e-12), here in a
 * direction 30 degrees off the axes. */
static void test_pure_rolling_on_wall(void **state) {
  (void)state;
  double s = 1e-3, c = cos(ADEM_PI / 6.0), sn = sin(ADEM_PI / 6.0);
  adem_vec3 v = v3(s * c, s * sn, 0.0);
  /* contact point velocity v + omega x (-r z) = 0 */
  adem_vec3 omega = v3(-v.y / RADIUS, v.x / RADIUS, 0.0);
  double dt;
  adem_world *w = sphere_on_wall(1.0, 100.0, 0.5, v, omega, &dt);
  adem_world_advance_histories(w);
  adem_vec3 xi = touching_history(&w->pw)->rolling;
  double speed = v3_norm(xi) / dt;
  double cosang = v3_dot(xi, v) / (v3_norm(xi) * v3_norm(v));
  printf("# pure rolling: |v_L| = %.15g m/s, centre %.15g m/s, cos(angle) = %.15f\n", speed,
         v3_norm(v), cosang);
  assert_true(fabs(speed / v3_norm(v) - 1.0) < 1e-12);
  assert_true(fabs(cosang - 1.0) < 1e-12);
  adem_world_free(w);
}

/* Two equal spheres (radius RADIUS, centres on the x axis) brought together at 1 mm/s, captured
 * by adhesion, and left for 40 periods of the normal oscillation (e = 0.5: its energy falls by
 * more than 1e-20), so that the contact sits at the JKR equilibrium, a = a0. */
static adem_world *settled_pair(double friction, double *dt) {
  adem_world *w = new_world();
  int ms, mw;
  add_materials(w, 1.0, 0.5, friction, true, &ms, &mw);
  double R = 0.5 * RADIUS;
  double mstar = 0.5 * RHO * 4.0 / 3.0 * ADEM_PI * pow(RADIUS, 3);
  double t_osc = 2.0 * ADEM_PI * sqrt(mstar / (1.2 * YOUNG * adem_jkr_a0(GAMMA, R, YOUNG)));
  *dt = t_osc / 400.0;
  adem_error err;
  adem_particle_def p = adem_default_particle_def();
  p.material = ms;
  p.radius = RADIUS;
  p.velocity = v3(0.5e-3, 0.0, 0.0);
  assert_int_equal(adem_world_add_particle(w, &p, NULL, &err), ADEM_OK);
  p.position = v3(2.0 * RADIUS + 1e-3 * *dt, 0.0, 0.0);
  p.velocity = v3(-0.5e-3, 0.0, 0.0);
  assert_int_equal(adem_world_add_particle(w, &p, NULL, &err), ADEM_OK);
  adem_world_set_dt(w, *dt);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  assert_int_equal(adem_world_step(w, 40 * 400, &err), ADEM_OK);
  assert_true(w->pp.n == 1 && w->pp.touching[0]);
  return w;
}

/* Claim (notes section 4): for equal spheres the size term of v_L vanishes, so two equal
 * spheres sliding past each other at 0.4 m/s (no spin to start with, friction 0.5) accumulate no
 * rolling displacement: friction spins both the same way, omega_i - omega_j stays zero. Checked
 * over 3000 steps with the spheres sliding (relative travel > 100 xi_crit, spins > 0): |xi|
 * exactly 0 (tolerance 1e-12 xi_crit for round-off). */
static void test_pure_sliding_pair(void **state) {
  (void)state;
  double dt;
  adem_world *w = settled_pair(0.5, &dt);
  for (size_t i = 0; i < 2; ++i) w->p.vel[i] = v3(0.0, 0.0, w->p.id[i] == 0 ? 0.2 : -0.2);
  adem_error err;
  double a0 = adem_jkr_a0(GAMMA, 0.5 * RADIUS, YOUNG);
  double xi_crit = a0 / 12.0 * 0.5;
  double worst = 0.0;
  for (int k = 0; k < 3000; ++k) {
    assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
    worst = fmax(worst, v3_norm(touching_history(&w->pp)->rolling));
  }
  double slide = fabs(w->p.pos[0].z - w->p.pos[1].z);
  double spin = v3_norm(w->p.omega[0]);
  printf("# sliding pair: relative travel %.3e m = %.0f xi_crit, spin %.3g rad/s, largest "
         "|xi| %.3e m\n",
         slide, slide / xi_crit, spin, worst);
  assert_true(slide > 100.0 * xi_crit);
  assert_true(spin > 0.0);
  assert_true(worst <= 1e-12 * xi_crit);
  adem_world_free(w);
}

/* Claim (H18-H22, H section 3.2, notes sections 4-5): at a = a0 the engine's torque is
 * 4F_C min(xi, xi_crit); E reduced alone keeps the slope and lengthens xi_crit by f^(-1/3);
 * H24 without the rolling modification gives slope f^(2/5) and xi_crit f^(-1/5); H24 with it
 * gives the original law. f = 0.1, one force pass each, relative tolerance 1e-9 (round-off). */
static void test_torque_law_at_equilibrium(void **state) {
  (void)state;
  const double f = 0.1;
  adem_collide_spec s = adem_default_collide_spec();
  s.kind = ADEM_COLLIDE_WALL;
  s.radius = RADIUS;
  s.density = RHO;
  s.young = YOUNG;
  s.surface_energy = GAMMA;
  s.restitution = 0.5;
  s.friction = 0.3;
  s.dtk = true;
  s.hysteresis = 0.5;
  double f_c = adem_jkr_critical_force(GAMMA, RADIUS);
  double xi_c = adem_jkr_a0(GAMMA, RADIUS, YOUNG) / 12.0 * 0.5;
  struct {
    double f;
    bool keep_gamma, modification;
    double slope, xi_crit;
  } law[4] = {{1.0, false, true, 1.0, 1.0},
              {f, true, false, 1.0, pow(f, -1.0 / 3.0)},
              {f, false, false, pow(f, 0.4), pow(f, -0.2)},
              {f, false, true, 1.0, 1.0}};
  for (int k = 0; k < 4; ++k) {
    s.stiffness_factor = law[k].f;
    s.keep_gamma = law[k].keep_gamma;
    s.dtk_modification = law[k].modification;
    adem_error err;
    double m_small, m_big;
    assert_int_equal(adem_collide_dtk_torque(&s, 0.25 * xi_c, &m_small, &err), ADEM_OK);
    assert_int_equal(adem_collide_dtk_torque(&s, 10.0 * xi_c, &m_big, &err), ADEM_OK);
    double slope = m_small / (0.25 * xi_c) / (4.0 * f_c);
    double xi_crit = m_big / (slope * 4.0 * f_c) / xi_c;
    printf("# law %d: slope/4F_C %.12f (expected %.12f), xi_crit/xi_c %.12f (expected %.12f)\n",
           k, slope, law[k].slope, xi_crit, law[k].xi_crit);
    assert_true(fabs(slope / law[k].slope - 1.0) < 1e-9);
    assert_true(fabs(xi_crit / law[k].xi_crit - 1.0) < 1e-9);
  }
}

/* Work of the rolling couples and their spring energy over a run: the couple's work W(t) (Verlet
 * trapezoid with the half-step spins) plus the energy U_r = k_r |xi|^2/(2R) its spring holds
 * never exceeds zero when the couple only stores and dissipates. Returns max over t of
 * (W + U_r) / max U_r, and W at the end in *w_end. */
static double couple_energy_balance(adem_world *w, const adem_pair_list *l, double R, double f_c,
                                    int steps, double *w_end) {
  adem_error err;
  const adem_interaction *it = adem_world_interaction(w, 0, l == &w->pw ? 1 : 0);
  double dt = adem_world_dt(w), work = 0.0, worst = -INFINITY, u_max = 0.0;
  size_t n = w->p.n;
  adem_vec3 t0[2];
  for (int k = 0; k < steps; ++k) {
    for (size_t i = 0; i < n; ++i) t0[w->p.id[i]] = w->p.rolling_torque[i];
    assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
    for (size_t i = 0; i < n; ++i) {
      adem_vec3 om = v3_axpy(w->p.omega[i], -0.5 * dt * w->p.inv_inertia[i], w->p.torque[i]);
      work += 0.5 * dt * v3_dot(v3_add(t0[w->p.id[i]], w->p.rolling_torque[i]), om);
    }
    double delta = l == &w->pw ? RADIUS - w->p.pos[0].z
                               : 2.0 * RADIUS - v3_norm(v3_sub(w->p.pos[1], w->p.pos[0]));
    double a = adem_jkr_contact_radius(it->pp.gamma, R, it->pp.E, delta) /
               adem_jkr_a0(it->pp.gamma, R, it->pp.E);
    double k_r = 4.0 * f_c * a * sqrt(a); /* H20, real F_C */
    double u = 0.5 * k_r / R * v3_norm2(touching_history(l)->rolling);
    u_max = fmax(u_max, u);
    worst = fmax(worst, work + u);
  }
  *w_end = work;
  return worst / u_max;
}

/* Claim (notes section 4: the couples "must never add energy"): two equal spheres at the JKR
 * equilibrium spinning against each other like gears (pure rolling, no slip) are braked by the
 * couple until xi saturates (the truncation H22 dissipates) and then oscillate on its spring.
 * Over 20000 steps the couple's work plus its spring energy stays <= 1e-9 of the spring energy
 * (zero up to round-off without truncation: the Verlet trapezoid telescopes), and the couple's
 * work ends negative. */
static void test_couple_never_adds_energy_pair(void **state) {
  (void)state;
  double dt, R = 0.5 * RADIUS;
  adem_world *w = settled_pair(0.5, &dt);
  for (size_t i = 0; i < 2; ++i) w->p.omega[i] = v3(0.0, w->p.id[i] == 0 ? 3e4 : -3e4, 0.0);
  double w_end;
  double worst = couple_energy_balance(w, &w->pp, R, adem_jkr_critical_force(GAMMA, R), 20000,
                                       &w_end);
  printf("# gears: max (W + U_r)/max U_r = %.3e, W at the end %.3e J\n", worst, w_end);
  assert_true(worst <= 1e-9);
  assert_true(w_end < 0.0);
  adem_world_free(w);
}

/* Claim (notes section 4) on a wall, in the case that tells: a sphere sliding without spin on
 * the wall at f = 0.01 (soft tangential spring, real rolling stiffness), 20 rolling periods:
 * max (W + U_r) <= 1e-9 of the spring energy. With Marshall's slip term in v_L
 * (1/2 v_S for a wall) xi follows the translation while the couple acts on the spin alone, a
 * circulatory law: measured W + U_r = +1.8 U_r here, the couple feeding energy into the
 * sphere; adem's v_L leaves the slip term out (docs/models.md), and this test guards that. */
static void test_couple_never_adds_energy_wall(void **state) {
  (void)state;
  const double f = 0.01;
  double dt;
  adem_world *w = sphere_on_wall(f, 0.5, 0.3, v3(0.01, 0.0, 0.0), v3_zero(), &dt);
  double mass = RHO * 4.0 / 3.0 * ADEM_PI * pow(RADIUS, 3);
  double f_c = adem_jkr_critical_force(GAMMA, RADIUS);
  double t_roll = 2.0 * ADEM_PI * sqrt(1.4 * mass * RADIUS / (4.0 * f_c));
  double w_end;
  double worst =
      couple_energy_balance(w, &w->pw, RADIUS, f_c, (int)(20.0 * t_roll / dt), &w_end);
  printf("# sliding on the wall, f = 0.01: max (W + U_r)/max U_r = %.3e, W at the end %.3e J\n",
         worst, w_end);
  adem_world_free(w);
  assert_true(worst <= 1e-9);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pure_rolling_on_wall),
      cmocka_unit_test(test_pure_sliding_pair),
      cmocka_unit_test(test_torque_law_at_equilibrium),
      cmocka_unit_test(test_couple_never_adds_energy_pair),
      cmocka_unit_test(test_couple_never_adds_energy_wall),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
