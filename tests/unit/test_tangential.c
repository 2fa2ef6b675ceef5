/* The tangential laws over a closed load path, called directly (src/laws/tangential.h): normal
 * load up, tangential displacement, normal load up further, tangential displacement back to zero,
 * unload. The work the driver does on the contact over the closed path is the energy the contact
 * took out of the motion: a passive contact never gives energy out (W >= 0). Claims checked:
 *  - the incremental law (Mindlin-Deresiewicz, the default) gives W = (S2 - S1) s0^2/2 >= 0
 *    when it sticks, and W >= 0 when it slips; its own bookkeeping (stored + dissipated) accounts
 *    for W to round-off;
 *  - the total-displacement law of H14 gives W = (S1 - S2) s0^2/2 < 0: it creates energy (the
 *    expert review's finding, docs/models.md). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "laws_kernels.h"

/* A 5 mm glass-like sphere on a rigid wall: Hertz S_t = 8 G sqrt(R delta). */
static const double R = 5e-3, E = 3.0e7, G = 1.2e7;
enum { N = 2000 }; /* steps per leg: quasi-static */

typedef adem_tangential_input tin;
typedef void law_fn(const adem_tangential_input *, adem_vec3 *, double *, adem_tangential_output *);

typedef struct path_result {
  double work;       /* driver's tangential work over the path, J */
  double normal;     /* driver's normal work over the path (trapezoid; ~0, Hertz is elastic), J */
  double dissipated; /* the law's own sum, J */
  double elastic;    /* stored at the end, J */
  double s1, s2;     /* S_t at the two loads */
  int slid;          /* steps slipping before the unloading leg */
} path_result;

/* Drives one contact through the path; mu the friction coefficient, s0 the tangential travel.
 * Driver work: normal, the trapezoid of F_n d delta; tangential, -(F_old + F_new)/2 . ds (the
 * contact's force on i is F_t, the driver moves i by ds against it). */
static path_result run_path(law_fn *law, double d1, double d2, double s0, double mu) {
  path_result r;
  memset(&r, 0, sizeof r);
  adem_vec3 hist = v3_zero(), f_old = v3_zero();
  double aux = 0.0, delta = 0.0, s = 0.0, fn_old = 0.0;
  const double dt = 1e-4;
  adem_vec3 n = v3(0.0, 0.0, 1.0);
  /* legs: (delta target, s target) */
  const double legs[5][2] = {{d1, 0.0}, {d1, s0}, {d2, s0}, {d2, 0.0}, {0.0, 0.0}};
  for (int leg = 0; leg < 5; ++leg) {
    double d_from = delta, s_from = s;
    for (int k = 1; k <= N; ++k) {
      double d_new = d_from + (legs[leg][0] - d_from) * k / N;
      double s_new = s_from + (legs[leg][1] - s_from) * k / N;
      if (leg == 4 && k == N) d_new = 1e-12 * d1; /* the last step just before the contact opens */
      double a = sqrt(R * d_new);
      double fn = adem_hertz_force(E, a, d_new);
      adem_vec3 vt = v3((s_new - s) / dt, 0.0, 0.0);
      tin in = {n, vt, vt, dt, adem_hertz_tangential_stiffness(G, a), 0.0,
                mu * fn, 0.0};
      adem_tangential_output out;
      law(&in, &hist, &aux, &out);
      r.normal += 0.5 * (fn_old + fn) * (d_new - delta);
      r.work -= 0.5 * v3_dot(v3_add(f_old, out.force), v3((s_new - s), 0.0, 0.0));
      r.dissipated += out.dissipated;
      r.elastic = out.elastic;
      if (leg < 4) r.slid += out.sliding; /* unloading slips at the end: mu F_n ~ delta^1.5 */
      f_old = out.force;
      fn_old = fn;
      delta = d_new;
      s = s_new;
      if (leg == 0 && k == N) r.s1 = in.stiffness;
      if (leg == 2 && k == N) r.s2 = in.stiffness;
    }
  }
  return r;
}

static void test_sticking_path(void **state) {
  (void)state;
  const double d1 = 2e-6, d2 = 8e-6, s0 = 1e-7, mu = 10.0; /* mu large: it sticks throughout */
  path_result inc = run_path(adem_tangential_incremental_law, d1, d2, s0, mu);
  path_result tot = run_path(adem_tangential_total_law, d1, d2, s0, mu);
  double scale = 0.5 * inc.s1 * s0 * s0; /* the spring energy after the first displacement */
  double theory_inc = 0.5 * (inc.s2 - inc.s1) * s0 * s0, theory_tot = -theory_inc;
  printf("# S1 = %.6g N/m, S2 = %.6g N/m, s0 = %g m, scale S1 s0^2/2 = %.6g J\n", inc.s1, inc.s2,
         s0, scale);
  printf("# normal work over the path (trapezoid) %.3g J\n", inc.normal);
  printf("# incremental: W = %.6g J (theory (S2-S1) s0^2/2 = %.6g), dissipated %.6g J, left "
         "%.3g J, slid %d\n",
         inc.work, theory_inc, inc.dissipated, inc.elastic, inc.slid);
  printf("# total:       W = %.6g J (theory (S1-S2) s0^2/2 = %.6g), dissipated %.6g J, left "
         "%.3g J, slid %d\n",
         tot.work, theory_tot, tot.dissipated, tot.elastic, tot.slid);
  assert_int_equal(inc.slid, 0);
  assert_int_equal(tot.slid, 0);
  assert_true(inc.work >= 0.0);
  assert_true(fabs(inc.work / theory_inc - 1.0) < 1e-3); /* the path is quasi-static: N steps */
  /* the law's own bookkeeping accounts for the work */
  assert_true(fabs(inc.dissipated + inc.elastic - inc.work) < 1e-9 * scale);
  assert_true(tot.work < 0.0);
  assert_true(fabs(tot.work / theory_tot - 1.0) < 1e-3);
}

/* With a friction coefficient that lets the contact slip on the tangential legs, the incremental
 * law's work is still >= 0 and its bookkeeping closes. */
static void test_slipping_path(void **state) {
  (void)state;
  const double d1 = 2e-6, d2 = 8e-6, s0 = 2e-6;
  for (int k = 0; k < 3; ++k) {
    double mu = (double[]){0.1, 0.3, 0.6}[k];
    path_result inc = run_path(adem_tangential_incremental_law, d1, d2, s0, mu);
    path_result tot = run_path(adem_tangential_total_law, d1, d2, s0, mu);
    double scale = 0.5 * inc.s1 * s0 * s0;
    printf("# mu %.1f: incremental W = %.6g J (slid %d steps, dissipated %.6g, left %.3g); "
           "total W = %.6g J (slid %d)\n",
           mu, inc.work, inc.slid, inc.dissipated, inc.elastic,
           tot.work, tot.slid);
    assert_true(inc.slid > 0);
    assert_true(inc.work > 0.0);
    assert_true(fabs(inc.dissipated + inc.elastic - inc.work) < 1e-9 * scale);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sticking_path),
      cmocka_unit_test(test_slipping_path),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
