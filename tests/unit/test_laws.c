/* Every contact law called directly, slot by slot (src/laws/laws_kernels.h): one contact seen
 * from i (n from i to j) and from j (n from j to i) must give equal and opposite forces and
 * couples, and the same energies and scalar results. The loops run over the rows of
 * include/adem/laws.h, so a law added as a row is checked here without editing this file.
 * Claim checked: Newton's third law for each kernel (notes section 4: "equal and opposite
 * couples"); BROF's capacity e_c |F_n| is the same from both sides (I9). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "laws_kernels.h"

/* Two spheres of different size and material in contact, moving and spinning. */
typedef struct body {
  adem_vec3 x, v, omega;
  double r, m, inertia;
} body;

static const body A = {{0.0, 0.0, 0.0}, {0.3, -0.2, 0.5}, {4.0, -7.0, 2.0}, 0.010, 0.0084, 3.4e-7};
static const body B = {{0.0121, 0.0052, -0.0083}, {-0.1, 0.4, -0.6}, {-3.0, 5.0, 6.0}, 0.006, 0.0018, 2.6e-8};

static adem_pair_params params(bool swapped) {
  adem_pair_params pp;
  memset(&pp, 0, sizeof pp);
  pp.E = pp.E_real = 2.0e8;
  pp.G = pp.G_real = 7.0e7;
  pp.restitution = 0.4;
  pp.beta = adem_damping_beta(0.4);
  pp.beta_clamped = adem_damping_beta_clamped(0.4);
  pp.friction = 0.5;
  pp.gamma = pp.gamma_real = 0.05;
  pp.dtk_rolling_modification = true;
  /* different values on the two sides, so that a law mixing them wrongly shows */
  for (int k = 0; k < ADEM_PARAM_COUNT; ++k) {
    double a = 0.2 + 0.1 * k, b = 0.35 + 0.05 * k;
    pp.param_a[k] = swapped ? b : a;
    pp.param_b[k] = swapped ? a : b;
    pp.param[k] = adem_law_param_get((adem_law_param_id)k)->mixing == ADEM_MIX_GEOMETRIC
                      ? sqrt(a * b)
                      : 0.5 * (a + b);
  }
  return pp;
}

/* The contact as the force pass sets it up (core/contact_force.h), from i's side. */
static adem_contact_geometry geometry(const body *i, const body *j) {
  adem_contact_geometry g;
  adem_vec3 d = v3_sub(j->x, i->x);
  double dist = v3_norm(d);
  g.n = v3_scale(d, 1.0 / dist);
  g.delta = i->r + j->r - dist;
  g.R = i->r * j->r / (i->r + j->r);
  g.mstar = i->m * j->m / (i->m + j->m);
  adem_vec3 spin = v3_add(v3_scale(i->omega, i->r), v3_scale(j->omega, j->r));
  g.w = v3_add(v3_sub(i->v, j->v), v3_cross(spin, g.n));
  adem_vec3 om = v3_sub(i->omega, j->omega);
  g.omega_rel = v3_axpy(om, -v3_dot(om, g.n), g.n);
  g.w_pred = g.w;
  g.omega_pred = g.omega_rel;
  g.ri = i->r;
  g.rj = j->r;
  double Ici = i->inertia + i->m * i->r * i->r, Icj = j->inertia + j->m * j->r * j->r;
  g.inertia_r = Ici * Icj / (Ici + Icj);
  g.energy = true;
  g.packed = false;
  return g;
}

static void assert_opposite(adem_vec3 a, adem_vec3 b, double scale, const char *what) {
  double err = v3_norm(v3_add(a, b));
  if (!(err <= 1e-12 * scale))
    fail_msg("%s: (%g, %g, %g) and (%g, %g, %g) are not opposite (|sum| %g)", what, a.x, a.y, a.z,
             b.x, b.y, b.z, err);
}

/* "model_c capacity": a row's name and what is checked of it. */
static const char *label(char buf[64], const char *name, const char *what) {
  snprintf(buf, 64, "%s%s", name, what);
  return buf;
}

static void assert_same(double a, double b, const char *what) {
  if (!(fabs(a - b) <= 1e-12 * fmax(fabs(a), fabs(b)) + 1e-300))
    fail_msg("%s: %.17g and %.17g differ", what, a, b);
}

static void test_normal_laws(void **state) {
  (void)state;
  adem_contact_geometry gi = geometry(&A, &B), gj = geometry(&B, &A);
  adem_pair_params pi = params(false), pj = params(true);
  double ai = adem_hertz_radius(gi.R, gi.delta), aj = adem_hertz_radius(gj.R, gj.delta);
  int checked = 0;
#define ADEM_X(ID, kernel, hist, ...)                                                \
  {                                                                                  \
    const char *name = adem_law_get(ADEM_SLOT_NORMAL, ID)->name;                     \
    char w_[64];                                                                     \
    adem_normal_result ri = kernel(&pi, &gi, ai), rj = kernel(&pj, &gj, aj);         \
    printf("# normal %-8s F = %.6g N, U = %.6g J, a = %.6g m\n", name, ri.f_elastic, \
           ri.e_elastic, ri.a);                                                      \
    assert_same(ri.f_elastic, rj.f_elastic, label(w_, name, " force"));              \
    assert_same(ri.e_elastic, rj.e_elastic, label(w_, name, " energy"));             \
    assert_same(ri.a, rj.a, label(w_, name, " contact radius"));                     \
    assert_true(ri.f_elastic != 0.0);                                                \
    ++checked;                                                                       \
  }
  ADEM_NORMAL_LAWS(ADEM_X)
#undef ADEM_X
  assert_int_equal(checked, ADEM_NORMAL_COUNT);
}

static void test_damping_laws(void **state) {
  (void)state;
  adem_contact_geometry gi = geometry(&A, &B), gj = geometry(&B, &A);
  adem_pair_params pi = params(false), pj = params(true);
  double S = adem_hertz_normal_stiffness(pi.E, adem_hertz_radius(gi.R, gi.delta));
#define ADEM_X(ID, kernel, hist, ...)                                                                     \
  {                                                                                                       \
    const char *name = adem_law_get(ADEM_SLOT_DAMPING, ID)->name;                                         \
    char w_[64];                                                                                          \
    double St = adem_hertz_tangential_stiffness(pi.G, adem_hertz_radius(gi.R, gi.delta));                 \
    double vni = v3_dot(gi.w, gi.n), vnj = v3_dot(gj.w, gj.n);                                            \
    adem_damping_input ini = {S, St, gi.mstar, vni, 1.0, 0.0};                                            \
    adem_damping_input inj = {S, St, gj.mstar, vnj, 1.0, 0.0};                                            \
    adem_damping_output oi, oj;                                                                           \
    kernel(&pi, &ini, &oi);                                                                               \
    kernel(&pj, &inj, &oj);                                                                               \
    double ci = (oi.f_normal - 1.0) / vni;                                                                \
    printf("# damping %-12s c_n = %.6g N s/m, c_t = %.6g N s/m\n", name, ci, oi.ct);                      \
    assert_same(oi.f_normal, oj.f_normal, name);                                                          \
    assert_same(oi.ct, oj.ct, label(w_, name, " tangential"));                                            \
    assert_true(ci > 0.0 && oi.ct > 0.0); /* e = 0.4 < 1 dissipates */                                    \
    /* the normal force F_N n on i is the opposite of j's */                                              \
    assert_opposite(v3_scale(gi.n, -oi.f_normal), v3_scale(gj.n, -oj.f_normal), fabs(oi.f_normal), name); \
  }
  ADEM_DAMPING_LAWS(ADEM_X)
#undef ADEM_X
}

/* A few steps of one contact from both sides, each with its own history from zero: the
 * tangential forces on i and on j are opposite at every step, sticking and sliding. */
static void test_tangential_laws(void **state) {
  (void)state;
  adem_contact_geometry gi = geometry(&A, &B), gj = geometry(&B, &A);
  adem_pair_params pi = params(false);
  double a = adem_hertz_radius(gi.R, gi.delta);
  double St = adem_hertz_tangential_stiffness(pi.G, a);
  double ct = adem_damping_coefficient(pi.beta, St, gi.mstar);
  double limit = 0.5 * adem_hertz_force(pi.E, a, gi.delta);
#define ADEM_X(ID, kernel, hist, ...)                                              \
  {                                                                                \
    const char *name = adem_law_get(ADEM_SLOT_TANGENTIAL, ID)->name;               \
    char w_[64];                                                                   \
    adem_vec3 hi = v3_zero(), hj = v3_zero();                                      \
    double ai_ = 0.0, aj_ = 0.0;                                                   \
    int slid = 0;                                                                  \
    for (int s = 0; s < 40; ++s) {                                                 \
      adem_vec3 vti = v3_axpy(gi.w, -v3_dot(gi.w, gi.n), gi.n);                    \
      adem_vec3 vtj = v3_axpy(gj.w, -v3_dot(gj.w, gj.n), gj.n);                    \
      adem_tangential_input ini = {gi.n, vti, vti, 1e-5, St, ct, limit, 0.0};      \
      adem_tangential_input inj = {gj.n, vtj, vtj, 1e-5, St, ct, limit, 0.0};      \
      adem_tangential_output oi, oj;                                               \
      kernel(&ini, &hi, &ai_, &oi);                                                \
      kernel(&inj, &hj, &aj_, &oj);                                                \
      assert_opposite(oi.force, oj.force, limit, name);                            \
      assert_opposite(oi.dashpot, oj.dashpot, limit, label(w_, name, " dashpot")); \
      assert_same(oi.elastic, oj.elastic, label(w_, name, " energy"));             \
      assert_same(oi.dissipated, oj.dissipated, label(w_, name, " dissipated"));   \
      /* the incremental law never gives energy out; the total law may (H14) */    \
      if (ID != ADEM_TANGENTIAL_TOTAL) /* up to round-off while it sticks */       \
        assert_true(oi.dissipated >= -1e-12 * oi.elastic);                         \
      assert_int_equal(oi.sliding, oj.sliding);                                    \
      slid += oi.sliding;                                                          \
    }                                                                              \
    printf("# tangential %-11s sliding in %d of 40 steps\n", name, slid);          \
    assert_true(slid > 0 && slid < 40); /* both regimes were visited */            \
  }
  ADEM_TANGENTIAL_LAWS(ADEM_X)
#undef ADEM_X
}

/* Rolling laws: couples on i and on j opposite (per-contact laws), capacities equal (BROF), the
 * same stored energy, over steps with each side's own history. */
static void test_rolling_laws(void **state) {
  (void)state;
  adem_contact_geometry gi = geometry(&A, &B), gj = geometry(&B, &A);
  adem_pair_params pi = params(false), pj = params(true);
  double a = adem_jkr_contact_radius(pi.gamma, gi.R, pi.E, gi.delta);
  double Sn = adem_hertz_normal_stiffness(pi.E, adem_hertz_radius(gi.R, gi.delta));
  double load = fabs(adem_jkr_force(pi.gamma, gi.R, pi.E, a) + 2.0 * adem_jkr_critical_force(pi.gamma, gi.R));
  adem_rolling_input ini = {&gi, &pi, 1e-6, load, a, Sn}, inj = {&gj, &pj, 1e-6, load, a, Sn};
  int acting = 0;
#define ADEM_X(ID, kernel, hist, ...)                                                         \
  {                                                                                           \
    const char *name = adem_law_get(ADEM_SLOT_ROLLING, ID)->name;                             \
    char w_[64];                                                                              \
    adem_vec3 hi = v3_zero(), hj = v3_zero();                                                 \
    double auxi = 0.0, auxj = 0.0;                                                            \
    double most = 0.0;                                                                        \
    for (int s = 0; s < 40; ++s) {                                                            \
      adem_rolling_output oi = {v3_zero(), v3_zero(), 0.0, 0.0, 0.0};                         \
      adem_rolling_output oj = {v3_zero(), v3_zero(), 0.0, 0.0, 0.0};                         \
      kernel(&ini, &hi, &auxi, &oi);                                                          \
      kernel(&inj, &hj, &auxj, &oj);                                                          \
      double scale = fmax(v3_norm(oi.torque), 1e-30);                                         \
      assert_opposite(oi.torque, oj.torque, scale, name);                                     \
      assert_same(oi.capacity, oj.capacity, label(w_, name, " capacity"));                    \
      assert_same(oi.elastic, oj.elastic, label(w_, name, " energy"));                        \
      assert_same(oi.dissipated, oj.dissipated, label(w_, name, " dissipated"));              \
      assert_opposite(oi.dashpot, oj.dashpot, scale, label(w_, name, " dissipative couple")); \
      most = fmax(most, fmax(v3_norm(oi.torque), oi.capacity));                               \
    }                                                                                         \
    printf("# rolling %-8s largest couple or capacity %.4g N m\n", name, most);               \
    acting += most > 0.0;                                                                     \
  }
  ADEM_ROLLING_LAWS(ADEM_X)
#undef ADEM_X
  assert_int_equal(acting, ADEM_ROLLING_COUNT - 1); /* every law but `none` acts here */
}

/* The check above can fail: a rolling law that puts the same couple on both sides (not a couple)
 * is caught. */
static void test_symmetry_check_catches_a_wrong_law(void **state) {
  (void)state;
  adem_contact_geometry gi = geometry(&A, &B), gj = geometry(&B, &A);
  /* a wrong model A: the torque along +n x e_z, the same from both sides' point of view */
  adem_vec3 ti = v3_scale(v3_cross(gi.n, (adem_vec3){0, 0, 1}), 1e-4);
  adem_vec3 tj = v3_scale(v3_cross(v3_neg(gj.n), (adem_vec3){0, 0, 1}), 1e-4);
  assert_true(v3_norm(v3_add(ti, tj)) > 1e-6); /* assert_opposite would fail on it */
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_normal_laws),
      cmocka_unit_test(test_damping_laws),
      cmocka_unit_test(test_tangential_laws),
      cmocka_unit_test(test_rolling_laws),
      cmocka_unit_test(test_symmetry_check_catches_a_wrong_law),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
