/* The stability limit of the step from the modes of a contact (step_limit.h). */
#include <math.h>

#include "laws_kernels.h"
#include "step_limit.h"

double adem_step_limit_explicit(double zeta) {
  return 2.0 * (sqrt(4.0 * zeta * zeta + 1.0) - 2.0 * zeta);
}

double adem_step_limit_pair(const adem_interaction *it, double t_c, double m_i, double r_i,
                            double m_j, double r_j) {
  const adem_pair_params *pp = &it->pp;
  if (!(t_c > 0.0) || !isfinite(t_c)) return INFINITY;
  bool wall = !(m_j > 0.0);
  double mstar = wall ? m_i : m_i * m_j / (m_i + m_j);
  double R = wall ? r_i : r_i * r_j / (r_i + r_j);
  double w_n = ADEM_HERTZ_PEAK_OMEGA_TC / t_c; /* the normal mode at the collision's peak */
  double Sn = w_n * w_n * mstar;
  double a = Sn / (2.0 * pp->E); /* the Hertz contact radius there (S_n = 2 E a, H13) */
  /* tangential spring S_t = 8 G a (H14) through the contact point's mass m* / 3.5 (spheres) */
  double w_t2 = 3.5 * 8.0 * pp->G * a / mstar;
  /* a rolling spring on the relative spin: couple k_theta theta, theta = (omega_i - omega_j) t */
  double inv_I = 1.0 / (0.4 * m_i * r_i * r_i) + (wall ? 0.0 : 1.0 / (0.4 * m_j * r_j * r_j));
  const double *pa = pp->param_a, *pb = pp->param_b;
  int kf = ADEM_PARAM_ROLLING_FRICTION;
  double eta = wall ? pa[kf] : 0.5 * (pa[kf] + pb[kf]);
  /* the rolling law's mode (its hook: model C's spring and dashpot, DTK's H20 spring) */
  adem_law_mode_input mode = {pp, Sn, a, R, eta, m_i, r_i, m_j, r_j, inv_I};
  double k_theta, zeta_r;
  adem_laws_rolling_mode(adem_interaction_laws(it), &mode, &k_theta, &zeta_r);
  double w_r2 = k_theta * inv_I;
  /* the normal dashpot on the predicted velocity (explicit), damping ratio sqrt(5/6) |beta| (H11;
   * the damping law's own: the clamped law's refitted beta) */
  double beta = adem_laws_normal_beta(adem_interaction_laws(it), pp);
  double dt = adem_step_limit_explicit(sqrt(5.0 / 6.0) * fabs(beta)) / w_n;
  /* the tangential and rolling springs act on the same two bodies: the largest eigenvalue of the
   * pair is at most the trace of M^-1 K, w_t^2 + w_r^2; the tangential dashpot is implicit in
   * its contact (contact_force.h) and leaves velocity Verlet's omega dt < 2 */
  dt = fmin(dt, 2.0 / sqrt(w_t2 + w_r2));
  if (zeta_r > 0.0 && w_r2 > 0.0) dt = fmin(dt, adem_step_limit_explicit(zeta_r) / sqrt(w_r2));
  /* the linear limits at the peak stiffness; a sticking oblique impact rings from 0.78-0.91 of
   * them on (the stiffness and the slip change within the collision): a margin */
  return ADEM_STEP_LIMIT_MARGIN * dt;
}
