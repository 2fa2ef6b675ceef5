/* Rolling resistance laws (notes section 4). Pure functions: each returns the torque on particle
 * i; particle j (or the wall) takes the opposite couple, except BROF, which Irazabal et al. define
 * per particle. omega_rel = (omega_i - omega_j) with its component along n removed. */
#ifndef ADEM_CONTACT_ROLLING_H
#define ADEM_CONTACT_ROLLING_H

#include "law_inline.h"

#include <math.h>
#include <stdbool.h>
#include "tangential.h"
#include "adem/vec3.h"

/* Model A, constant directional torque (I7-I8): -e_c |F_n| omega_rel/|omega_rel|, e_c = eta_r R_r.
 * It flips sign with omega_rel, so a sphere at rest sees it oscillate: that is the known flaw. */
ADEM_LAW adem_vec3 adem_rolling_model_a(adem_vec3 omega_rel, double e_c, double f_normal) {
  double norm = v3_norm(omega_rel);
  if (norm == 0.0) return v3_zero();
  return v3_scale(omega_rel, -e_c * fabs(f_normal) / norm);
}

/* Model C (Ai et al. 2011): elastic-plastic spring plus a dashpot that works only while the
 * spring is below its limit. spring: the spring torque on i (history, kept in the tangent plane);
 * k_old: the k_r it was stored with (history); k_r = 2.25 k_n eta_r^2 R_r^2, limit
 * eta_r R_r |F_n|, damping C_r = delta_r 2 sqrt(I_r k_r) on omega_damp (the relative spin
 * predicted at the full step; the spring turns by omega_rel dt). When k_r falls (the contact
 * unloads) the stored torque is first scaled by k_r/k_old, when it rises it is kept: the rule of
 * the incremental tangential law (LAMMPS mindlin_rescale), without which a spring that keeps its
 * torque while its stiffness falls gives out more work than it took (docs/models.md).
 * *dissipated: the work the relative turn did on the spring in the step, -(M_old + M_new)/2 .
 * omega_rel dt (the trapezoid the integrator's kicks follow), less the change of the stored
 * energy M^2/(2 k_r): the limit's plastic turn and what a fall of k_r releases. */
ADEM_LAW adem_vec3 adem_rolling_model_c(adem_vec3 *spring, double *k_old, adem_vec3 n,
                                        adem_vec3 omega_rel, adem_vec3 omega_damp, double dt,
                                        double k_r, double limit, double c_r,
                                        double *dissipated) {
  adem_vec3 m_prev = *spring;
  double k0 = *k_old;
  double u_prev = k0 > 0.0 ? 0.5 * v3_norm2(m_prev) / k0 : 0.0;
  adem_vec3 m0 = adem_tangential_project(m_prev, n);
  if (k0 > k_r) m0 = v3_scale(m0, k_r / k0); /* unloading: the turn is kept, not the torque */
  adem_vec3 m = v3_axpy(m0, -k_r * dt, omega_rel);
  double mag2 = v3_norm2(m);
  bool limited = mag2 > limit * limit;
  if (limited) m = v3_scale(m, limit / sqrt(mag2)); /* full mobilisation: plastic, no damping */
  *spring = m;
  *k_old = k_r;
  double u = k_r > 0.0 ? 0.5 * v3_norm2(m) / k_r : 0.0;
  *dissipated = -0.5 * dt * v3_dot(v3_add(m_prev, m), omega_rel) - (u - u_prev);
  return limited ? m : v3_axpy(m, -c_r, omega_damp);
}

/* Model C with the total torque bounded: spring + dashpot limited to eta_r R_r |F_n| (the cap
 * LIGGGHTS applies when the spring is fully mobilised, here applied to the sum as well), so that
 * no rolling torque exceeds the bound of models A and BROF. */
ADEM_LAW adem_vec3 adem_rolling_model_c_capped(adem_vec3 *spring, double *k_old, adem_vec3 n,
                                               adem_vec3 omega_rel, adem_vec3 omega_damp,
                                               double dt, double k_r, double limit,
                                               double c_r, double *dissipated) {
  adem_vec3 m = adem_rolling_model_c(spring, k_old, n, omega_rel, omega_damp, dt, k_r, limit, c_r,
                                     dissipated);
  double mag2 = v3_norm2(m);
  if (mag2 > limit * limit) m = v3_scale(m, limit / sqrt(mag2));
  return m;
}

/* DTK rolling velocity with n from i to j: v_L = -R (omega_i - omega_j) x n. Marshall (2009) adds
 * 1/2 (r_j - r_i)/(r_i + r_j) v_S (v_S the slip velocity; 1/2 v_S on a wall); adem leaves it out
 * because it lets the couple do positive work on a wall when the tangential spring is soft
 * (docs/models.md). */
ADEM_LAW adem_vec3 adem_rolling_dtk_velocity(adem_vec3 omega_rel, adem_vec3 n, double R) {
  return v3_scale(v3_cross(omega_rel, n), -R);
}

/* DTK torque (H18-H22): xi += v_L dt in the tangent plane, |xi| <= xi_crit, torque on i
 * k_r (n x xi) with k_r = 4 F_C (a/a0)^(3/2) (H20; a/a0 of the modified material, section 3.2).
 * k_old: the k_r of the last step (history). When k_r rises (the contact loads) xi is first scaled
 * by k_old/k_r, so that the torque is kept; when it falls xi is kept and the torque falls with
 * k_r: the incremental tangential law's rule, without which a load that rises at a fixed xi
 * raises the torque for free and a closed load path gives out more work than it took
 * (docs/models.md). The limit xi_crit is kept. The torque's work over a turn is
 * -(k_r/R) xi . dxi, so the spring stores k_r |xi|^2/(2R); *dissipated is the work the turn did
 * on the spring, (k_old xi_old + k_r xi_new)/(2R) . v_L dt (the trapezoid the integrator's work
 * follows), less the change of the stored energy: the truncation and what a change of k_r
 * releases. */
ADEM_LAW adem_vec3 adem_rolling_dtk(adem_vec3 *xi, double *k_old, adem_vec3 n, adem_vec3 v_l,
                                    double dt, double k_r, double xi_crit, double R,
                                    double *dissipated) {
  double k0 = *k_old;
  adem_vec3 x_prev = adem_tangential_project(*xi, n);
  double u_prev = 0.5 * k0 * v3_norm2(x_prev) / R;
  adem_vec3 x0 = k_r > k0 && k0 > 0.0 ? v3_scale(x_prev, k0 / k_r) : x_prev; /* loading */
  adem_vec3 x = v3_axpy(x0, dt, v_l);
  double mag2 = v3_norm2(x);
  if (mag2 > xi_crit * xi_crit) /* H22 */
    x = mag2 > 0.0 ? v3_scale(x, xi_crit / sqrt(mag2)) : x;
  *xi = x;
  *k_old = k_r;
  double u = 0.5 * k_r * v3_norm2(x) / R;
  double work = 0.5 * dt * v3_dot(v3_add(v3_scale(x_prev, k0), v3_scale(x, k_r)), v_l) / R;
  *dissipated = work - (u - u_prev);
  return v3_scale(v3_cross(n, x), k_r);
}

/* BROF (I9-I10) for one particle: t_stop is the torque that would bring its spin to zero within
 * this step given every other torque on it; the resistance is t_stop itself when the available
 * resistance capacity (sum of e_c |F_n| over its BROF contacts) suffices, else the capacity along
 * t_stop. It never reverses the rotation and holds a particle at rest exactly. */
ADEM_LAW adem_vec3 adem_rolling_brof(adem_vec3 t_stop, double capacity) {
  double mag = v3_norm(t_stop);
  if (mag <= capacity) return t_stop;
  return v3_scale(t_stop, capacity / mag);
}

/* The cold-path hooks of the rolling laws (rolling.c), named by their rows (include/adem/laws.h;
 * law_hooks.h). */
extern const struct adem_law_hooks adem_rolling_dtk_hooks;
extern const struct adem_law_hooks adem_rolling_model_c_hooks;
extern const struct adem_law_hooks adem_rolling_brof_hooks;

#endif
