/* Order of convergence of simplified-JKR collisions in the time step (issue 11; docs/models.md,
 * "Time step"). Two things made them first order: the force jumps by -(8/9) F_C where a contact
 * forms and breaks at delta = 0, and applied at the force pass after the crossing the impulse is
 * off by up to F dt/2 at each jump; and the dashpots took the half step's velocity, half a step
 * behind where their force acts. ADEM_CONTACTS_FIRST_ORDER is that scheme; the default
 * ADEM_CONTACTS_SECOND_ORDER applies the jumps at the crossing time interpolated in the overlap
 * and gives the dashpots the velocity predicted at the full step. The first touch is placed 1.3
 * steps away (not 1.5, where the crossing falls exactly half a step before a pass and the
 * formation's error vanishes by accident). Claims checked, with the errors against the same
 * collision at 3200 (e_eff) or 1600 (lambda_crit) steps per collision time:
 *  - e_eff of PSL on quartz at 2.5-10 m/s (rms): order ~1 first order, ~2 second order;
 *  - lambda_crit of a normal wall impact, e = 0.3, Ad = 100: the same orders; with the step the
 *    engine used to propose (t_c/50 at the impact speed, no adhesive speed-up) and the first
 *    order scheme it was 7% off (the review's 7.3%, 15.5% at t_c/25), with the proposal now
 *    (t_c at sqrt(v^2 + 2|U_min|/m*), second order) 0.2%. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "adem/adem.h"
#include "adem/vec3.h"

enum { NN = 4 };
static const double steps[NN] = {25.0, 50.0, 100.0, 200.0};

static adem_collide_spec psl(double v) {
  adem_collide_spec s = adem_default_collide_spec();
  assert_int_equal(adem_collide_psl_quartz(&s, NULL), ADEM_OK);
  s.speed = v;
  s.approach_steps = 1.3;
  return s;
}

static double order(double e1, double e2) { return log(fabs(e1 / e2)) / log(2.0); }

/* e_eff over several speeds (the phase of the crossings within a step changes with the speed,
 * so one speed alone gives a noisy error): root mean square against 3200 steps per t_c. */
enum { NV = 6 };
static const double speeds[NV] = {2.5, 3.0, 4.0, 5.0, 7.0, 10.0};

static double rms_error(adem_contact_scheme scheme, double n, const double *ref) {
  double sum = 0.0;
  for (int v = 0; v < NV; ++v) {
    adem_collide_spec s = psl(speeds[v]);
    s.scheme = scheme;
    s.steps_per_tc = n;
    adem_collide_result r = adem_collide(&s);
    assert_int_equal(r.status, ADEM_OK);
    sum += (r.e_eff - ref[v]) * (r.e_eff - ref[v]);
  }
  return sqrt(sum / NV);
}

static void test_e_eff_order(void **state) {
  (void)state;
  double ref[NV];
  for (int v = 0; v < NV; ++v) {
    adem_collide_spec s = psl(speeds[v]);
    s.steps_per_tc = 3200.0;
    ref[v] = adem_collide(&s).e_eff;
  }
  printf("# PSL on quartz, e_eff at 3200 steps per t_c for v = 2.5 ... 10 m/s: %.6f ... %.6f\n",
         ref[0], ref[NV - 1]);
  double err[2][NN];
  for (int m = 0; m < 2; ++m) {
    adem_contact_scheme scheme = m ? ADEM_CONTACTS_SECOND_ORDER : ADEM_CONTACTS_FIRST_ORDER;
    for (int k = 0; k < NN; ++k) {
      err[m][k] = rms_error(scheme, steps[k], ref);
      printf("# %-12s %4.0f steps: rms e_eff error %.3e\n", m ? "second order" : "first order",
             steps[k], err[m][k]);
    }
    printf("# %-12s observed orders %.2f %.2f %.2f\n", m ? "second order" : "first order",
           order(err[m][0], err[m][1]), order(err[m][1], err[m][2]), order(err[m][2], err[m][3]));
  }
  double first = order(err[0][0], err[0][3]) / 3.0, second = order(err[1][0], err[1][2]) / 2.0;
  assert_true(first > 0.6 && first < 1.5);
  assert_true(second > 1.6);
  assert_true(err[1][1] < 0.2 * err[0][1]); /* at 50 steps */
}

/* lambda_crit of a normal wall impact at Ad = 100, e = 0.3 (r = 1 um, rho = 1000, v = 1 m/s). */
typedef struct lambda_ctx {
  double steps; /* > 0: steps per collide's t_ref; 0: the old proposal below */
} lambda_ctx;

static void set_lambda(adem_collide_spec *s, double x, void *user) {
  const lambda_ctx *c = user;
  adem_collide_set_lambda(s, x);
  if (c->steps > 0.0) {
    s->steps_per_tc = c->steps;
    s->dt = 0.0;
  } else { /* what the engine proposed before: t_c/50 at the impact speed, no adhesion */
    adem_collide_params p = adem_collide_derive(s);
    s->dt = adem_hertz_collision_time(p.mstar, p.R, p.E_mod, p.v_n) / 50.0;
  }
}

static double lambda_crit(adem_contact_scheme scheme, double n) {
  adem_collide_spec s = adem_default_collide_spec();
  s.kind = ADEM_COLLIDE_WALL;
  s.radius = 1e-6;
  s.density = 1000.0;
  s.speed = 1.0;
  s.restitution = 0.3;
  s.scheme = scheme;
  s.approach_steps = 1.3;
  adem_collide_set_lambda(&s, 1.5e7);
  adem_collide_set_ad(&s, 100.0);
  lambda_ctx c = {n};
  double lc = NAN;
  adem_error err;
  assert_int_equal(adem_collide_threshold(&s, set_lambda, &c, 1e7, 2.5e7, 1e-7, 2, &lc, &err),
                   ADEM_OK);
  return lc;
}

static void test_lambda_crit_order(void **state) {
  (void)state;
  double ref = lambda_crit(ADEM_CONTACTS_SECOND_ORDER, 1600.0);
  printf("# lambda_crit (e = 0.3, Ad = 100, wall) = %.6e at 1600 steps per t_c\n", ref);
  double rel[2][NN];
  for (int m = 0; m < 2; ++m) {
    adem_contact_scheme on = m ? ADEM_CONTACTS_SECOND_ORDER : ADEM_CONTACTS_FIRST_ORDER;
    for (int k = 0; k < NN; ++k) {
      rel[m][k] = lambda_crit(on, steps[k]) / ref - 1.0;
      printf("# %-12s %4.0f steps: lambda_crit off by %+.3e\n", m ? "second order" : "first order",
             steps[k], rel[m][k]);
    }
    printf("# %-12s observed orders %.2f %.2f %.2f\n", m ? "second order" : "first order",
           order(rel[m][0], rel[m][1]), order(rel[m][1], rel[m][2]), order(rel[m][2], rel[m][3]));
  }
  double old = lambda_crit(ADEM_CONTACTS_FIRST_ORDER, 0.0) / ref - 1.0;
  double old_new = lambda_crit(ADEM_CONTACTS_SECOND_ORDER, 0.0) / ref - 1.0;
  printf("# the step proposed before (t_c/50 at v, no adhesive speed-up): off by %+.3e first "
         "order, %+.3e second order; proposed now (t_ref/50, second order): %+.3e\n",
         old,
         old_new, rel[1][1]);
  assert_true(old > 0.05);              /* the review's 7.3% */
  assert_true(fabs(rel[1][1]) < 0.005); /* now: within 0.5% */
  /* orders over 25 -> 200 (first) and 25 -> 100 (second: at 200 it reaches the ~5e-4 floor of
   * the outcome's sampling, whether the creeping sphere is past delta = 0 at a pass) */
  double first = order(rel[0][0], rel[0][3]) / 3.0, second = order(rel[1][0], rel[1][2]) / 2.0;
  assert_true(first > 0.8 && first < 1.2);
  assert_true(second > 1.7);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_e_eff_order),
      cmocka_unit_test(test_lambda_crit_order),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
