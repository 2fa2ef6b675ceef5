/* The rolling springs over a closed load path, called directly (src/laws/rolling.h), as
 * test_tangential.c does for the tangential laws: load to a first level, turn by theta0, change
 * the load to a second level, turn back to zero, unload. The work the driver does on the contact
 * over the closed path is the energy the contact took out of the motion: a passive contact never
 * gives energy out (W >= 0). Both orders are driven: the load falls between the turns (a spring
 * that kept its torque while its stiffness fell gave out more than it took: model C) and the load
 * rises between them (a spring that kept its displacement while its stiffness rose: DTK).
 * Claims checked, for model C and DTK:
 *  - while the spring sticks, W = (k_hi - k_lo) theta0^2/2 >= 0 on both orders (k the angular
 *    stiffness of the turn: model C's k_r, DTK's k_r R), the spring's energy at the first turn's
 *    end being k_first theta0^2/2;
 *  - at the spring's limit (model C's eta_r R_r |F_n|, DTK's xi_crit) W > 0;
 *  - the law's own bookkeeping (stored + dissipated) accounts for W to round-off. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "laws_kernels.h"

/* A 5 mm sphere on a rigid wall. */
static const double R = 5e-3, E = 3.0e7;
enum { N = 2000 }; /* steps per leg: quasi-static */

typedef void law_fn(const adem_rolling_input *, adem_vec3 *, double *, adem_rolling_output *);

typedef struct path_result {
  double work;       /* driver's work over the path, J */
  double dissipated; /* the law's own sum, J */
  double elastic;    /* stored at the end, J */
  double first;      /* stored at the end of the first turn, J */
  double k1, k2;     /* angular stiffness of the first and the second turn, N m/rad */
} path_result;

static adem_pair_params pair_params(double eta, double hysteresis) {
  adem_pair_params pp;
  memset(&pp, 0, sizeof pp);
  pp.E = pp.E_real = E;
  pp.G = pp.G_real = 0.4 * E;
  pp.gamma = pp.gamma_real = 0.05;
  pp.dtk_rolling_modification = true;
  for (int s = 0; s < 3; ++s) {
    double *v = s == 0 ? pp.param : s == 1 ? pp.param_a
                                           : pp.param_b;
    v[ADEM_PARAM_ROLLING_FRICTION] = eta;
    v[ADEM_PARAM_ADHESION_HYSTERESIS] = hysteresis;
  }
  return pp;
}

/* Drives one contact through the path: load level x1, turn by theta0 about y, level x2, turn
 * back, unload (x: the overlap for model C, the contact radius for DTK). The law's couple on the
 * sphere is M; the driver turns it by d theta against it: W += -(M_old + M_new)/2 . d theta. */
static path_result run_path(law_fn *law, bool dtk, const adem_pair_params *pp, double x1,
                            double x2, double theta0) {
  path_result r;
  memset(&r, 0, sizeof r);
  adem_contact_geometry g;
  memset(&g, 0, sizeof g);
  g.n = v3(0.0, 0.0, -1.0);
  g.R = R;
  g.ri = R;
  g.mstar = 1e-3;
  adem_vec3 hist = v3_zero(), m_old = v3_zero();
  double aux = 0.0, x = 0.0, th = 0.0;
  const double dt = 1e-4;
  const double legs[5][2] = {{x1, 0.0}, {x1, theta0}, {x2, theta0}, {x2, 0.0}, {0.0, 0.0}};
  for (int leg = 0; leg < 5; ++leg) {
    double x_from = x, th_from = th;
    for (int k = 1; k <= N; ++k) {
      double x_new = x_from + (legs[leg][0] - x_from) * k / N;
      double th_new = th_from + (legs[leg][1] - th_from) * k / N;
      if (leg == 4 && k == N) x_new = 1e-6 * x1; /* the last step just before the contact opens */
      double delta = dtk ? x_new * x_new / R : x_new, a = dtk ? x_new : sqrt(R * x_new);
      g.delta = delta;
      g.omega_rel = g.omega_pred = v3(0.0, (th_new - th) / dt, 0.0);
      double load = adem_hertz_force(E, sqrt(R * delta), delta);
      adem_rolling_input in = {&g, pp, dt, load, a, adem_hertz_normal_stiffness(E, sqrt(R * delta))};
      adem_rolling_output out = {v3_zero(), v3_zero(), 0.0, 0.0, 0.0};
      law(&in, &hist, &aux, &out);
      r.work -= 0.5 * v3_dot(v3_add(m_old, out.torque), v3(0.0, th_new - th, 0.0));
      r.dissipated += out.dissipated;
      r.elastic = out.elastic;
      m_old = out.torque;
      x = x_new;
      th = th_new;
      /* the angular stiffness of each turn: model C's k_r, DTK's k_r R (torque k_r xi, xi = R theta) */
      if (leg == 1 && k == N) r.first = out.elastic;
      if ((leg == 1 || leg == 3) && k == 1) {
        double ratio = a / adem_jkr_a0(pp->gamma, R, pp->E);
        double k_ang = dtk ? 4.0 * adem_jkr_critical_force(pp->gamma, R) * ratio * sqrt(ratio) * R
                           : 2.25 * in.Sn * pow(pp->param[ADEM_PARAM_ROLLING_FRICTION] * R, 2);
        if (leg == 1) r.k1 = k_ang;
        else r.k2 = k_ang;
      }
    }
  }
  return r;
}

static void check_sticking(const char *name, law_fn *law, bool dtk, const adem_pair_params *pp,
                           double lo, double hi, double theta0) {
  for (int order = 0; order < 2; ++order) {
    double x1 = order == 0 ? hi : lo, x2 = order == 0 ? lo : hi;
    path_result p = run_path(law, dtk, pp, x1, x2, theta0);
    double theory = 0.5 * fabs(p.k1 - p.k2) * theta0 * theta0;
    printf("# %s, load %s between the turns: W = %.6g J = %+.2f%% of the first stored %.6g J "
           "(theory (k_hi - k_lo) theta0^2/2 = %.6g); dissipated %.6g, left %.3g\n",
           name, order == 0 ? "falls" : "rises", p.work, 100.0 * p.work / p.first, p.first,
           theory, p.dissipated, p.elastic);
    assert_true(p.work >= 0.0);
    assert_true(fabs(p.work / theory - 1.0) < 2e-3); /* quasi-static: N steps a leg */
    assert_true(fabs(p.dissipated + p.elastic - p.work) < 1e-9 * p.first);
  }
}

static void test_model_c_sticking(void **state) {
  (void)state;
  adem_pair_params pp = pair_params(100.0, 0.0); /* eta_r large: the spring never reaches its limit */
  check_sticking("model C", adem_rolling_model_c_law, false, &pp, 2e-6, 8e-6, 5e-7);
  check_sticking("model C capped", adem_rolling_model_c_capped_law, false, &pp, 2e-6, 8e-6, 5e-7);
}

static void test_dtk_sticking(void **state) {
  (void)state;
  adem_pair_params pp = pair_params(0.0, 1e6); /* xi_crit large: no truncation */
  double a0 = adem_jkr_a0(pp.gamma, R, pp.E);
  check_sticking("DTK", adem_rolling_dtk_law, true, &pp, 0.8 * a0, 1.3 * a0, 1e-6);
}

/* Turns past the limits: work still >= 0, the bookkeeping still closes. */
static void test_at_the_limits(void **state) {
  (void)state;
  for (int law = 0; law < 2; ++law) {
    bool dtk = law == 1;
    adem_pair_params pp = dtk ? pair_params(0.0, 0.3) : pair_params(0.05, 0.0);
    double a0 = adem_jkr_a0(pp.gamma, R, pp.E);
    double lo = dtk ? 0.8 * a0 : 2e-6, hi = dtk ? 1.3 * a0 : 8e-6;
    double theta0 = dtk ? 2e-3 : 1e-2;
    for (int order = 0; order < 2; ++order) {
      path_result p = run_path(dtk ? adem_rolling_dtk_law : adem_rolling_model_c_law, dtk, &pp,
                               order == 0 ? hi : lo, order == 0 ? lo : hi, theta0);
      printf("# %s at its limit, load %s: W = %.6g J (first stored %.6g), dissipated %.6g, left "
             "%.3g\n",
             dtk ? "DTK" : "model C", order == 0 ? "falls" : "rises", p.work, p.first,
             p.dissipated, p.elastic);
      assert_true(p.work > 0.0);
      assert_true(fabs(p.dissipated + p.elastic - p.work) < 1e-9 * p.first);
    }
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_model_c_sticking),
      cmocka_unit_test(test_dtk_sticking),
      cmocka_unit_test(test_at_the_limits),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
