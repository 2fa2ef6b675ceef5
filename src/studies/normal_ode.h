/* An independent reference for the collision validations: the 1-D normal equation of motion of
 * a simplified JKR (or Hertz) contact with the dashpot of H11-H13,
 *   m* delta'' = -(F_el(delta) + c(delta) delta'),
 *   F_el = 4 E a^3/(3R) - 4 sqrt(pi gamma E a^3),  delta = a^2/R - 2 sqrt(pi gamma a/E)  (H8-H10),
 *   c = -2 sqrt(5/6) beta sqrt(2 E sqrt(R delta) m*)  (H11-H13),
 * integrated from the touch (delta = 0, force -(8/9) F_C at once) by an adaptive Dormand-Prince
 * 5(4) method with the end located at delta = 0; a(delta) by Newton's method on H10, not the
 * engine's closed form; the stored energy integrated along (U' = F_el delta'). Nothing here
 * steps the engine: it is what the engine's collisions are measured against. */
#ifndef ADEM_STUDIES_NORMAL_ODE_H
#define ADEM_STUDIES_NORMAL_ODE_H

#include <stdbool.h>
#include <stddef.h>

#include "adem/studies.h"

typedef struct adem_normal_ode {
  double mstar, R; /* effective mass and radius */
  double E, gamma; /* effective modulus and surface energy of the law (modified); gamma 0: Hertz */
  double beta;     /* ln e / sqrt(ln^2 e + pi^2) (H12) */
} adem_normal_ode;

typedef struct adem_normal_ode_result {
  bool stuck;      /* the contact's energy fell below zero: it can never break */
  double e_eff;    /* separation / approach speed (0 when stuck) */
  double v_out;    /* separation speed, m/s */
  double duration; /* touch to separation, s (to the capture when stuck) */
  size_t steps;    /* accepted steps */
} adem_normal_ode_result;

/* Called after every accepted step: time since the touch, overlap, approach speed. */
typedef void adem_normal_ode_trace_fn(double t, double delta, double v, void *user);

/* One collision at approach speed v0 > 0 (relative tolerance rtol, e.g. 1e-10). */
adem_normal_ode_result adem_normal_ode_collide(const adem_normal_ode *p, double v0, double rtol,
                                               adem_normal_ode_trace_fn *trace, void *user);

/* The elastic force F_el(delta) (> 0 repulsive), from Newton's a(delta) on H10. */
double adem_normal_ode_force(const adem_normal_ode *p, double delta);

/* The ODE of a collision spec (its effective radius, mass, modified E and gamma, H12's beta). */
adem_normal_ode adem_normal_ode_of(const adem_collide_spec *s);

/* Sets the parameter x of a spec (as adem_collide_param_fn). */
typedef void adem_normal_ode_param_fn(adem_collide_spec *s, double x, void *user);

/* The value of x in [lo, hi] where the ODE's outcome changes between stuck and rebound, to a
 * relative width rel_tol (bisection in log x); NAN when lo and hi give the same outcome. */
double adem_normal_ode_threshold(const adem_collide_spec *base, adem_normal_ode_param_fn *set,
                                 void *user, double lo, double hi, double rel_tol);

#endif
