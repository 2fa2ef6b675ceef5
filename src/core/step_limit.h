/* The step at which a contact's fastest mode reaches the integrator's stability limit, linearised
 * at the peak Hertz stiffness of a collision (docs/models.md, "Time step"): the normal mode, the
 * tangential spring acting through the contact point's mass m-star/3.5 together with a rolling
 * spring (models C and DTK), and the dashpots that act on the predicted velocity explicitly
 * (the normal one, model C's): each lowers its mode's limit. The tangential dashpot is implicit
 * in its own contact (contact_force.h) and does not. */
#ifndef ADEM_CORE_STEP_LIMIT_H
#define ADEM_CORE_STEP_LIMIT_H

#include "materials.h"

/* omega_peak t_c of a Hertz collision: with S_n = 2 E sqrt(R delta_max), delta_max =
 * (15 m* v^2/(16 E sqrt R))^(2/5), sqrt(S_n/m*) t_c = 4.0303 whatever m*, R, E and v. */
#define ADEM_HERTZ_PEAK_OMEGA_TC 4.030251571628248
/* The share of the linear limit allowed (tests/physics/test_step_stability.c measures where the
 * nonlinear collision starts to ring). */
#define ADEM_STEP_LIMIT_MARGIN 0.7

/* Largest stable step of the pair: t_c its collision time (a wall: m_j = r_j = 0 and
 * infinite mass), its particles' masses m_i, m_j and radii r_i, r_j. */
double adem_step_limit_pair(const adem_interaction *it, double t_c, double m_i, double r_i,
                            double m_j, double r_j);

/* Largest omega dt of a spring-dashpot of damping ratio zeta whose dashpot takes the velocity
 * predicted with the last step's force (explicit): 2 (sqrt(4 zeta^2 + 1) - 2 zeta) (the Jury
 * condition P(-1) < 0 of z^3 + (W^2 + 3 W zeta - 2) z^2 + (1 - 4 W zeta) z + W zeta). */
double adem_step_limit_explicit(double zeta);

#endif
