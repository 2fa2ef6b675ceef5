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
  double k_theta = 0.0, zeta_r = 0.0;
  const double *pa = pp->param_a, *pb = pp->param_b;
  int kf = ADEM_PARAM_ROLLING_FRICTION;
  double eta = wall ? pa[kf] : 0.5 * (pa[kf] + pb[kf]);
  switch (it->rolling) {
    case ADEM_ROLLING_C:
    case ADEM_ROLLING_C_CAPPED: {
      k_theta = 2.25 * Sn * eta * eta * R * R; /* Ai et al. 2011 */
      /* its dashpot delta_r 2 sqrt(I_r k_r), I_r about the contact points, on the predicted spin */
      double Ic_i = 1.4 * m_i * r_i * r_i, Ic_j = wall ? INFINITY : 1.4 * m_j * r_j * r_j;
      double I_r = 1.0 / (1.0 / Ic_i + 1.0 / Ic_j);
      zeta_r = pp->param[ADEM_PARAM_ROLLING_DAMPING] * sqrt(I_r * inv_I);
      break;
    }
    case ADEM_ROLLING_DTK: {
      /* k_r = 4 F_C (a/a0)^(3/2) (H20) at the collision's peak, at least a = a0, with F_C real
       * under reduced stiffness (H section 3.2): the mode that stays fast when E is reduced */
      bool keep_real = pp->dtk_rolling_modification;
      double f_c = adem_jkr_critical_force(keep_real ? pp->gamma_real : pp->gamma, R);
      double a0 = adem_jkr_a0(pp->gamma, R, pp->E);
      double a_jkr = pp->gamma > 0.0 ? adem_jkr_contact_radius(pp->gamma, R, pp->E, a * a / R) : a;
      double ratio = a0 > 0.0 ? fmax(1.0, a_jkr / a0) : 1.0;
      k_theta = 4.0 * f_c * ratio * sqrt(ratio) * R; /* torque k_r xi, xi = R theta */
      break;
    }
    default:
      break;
  }
  double w_r2 = k_theta * inv_I;
  /* the normal dashpot on the predicted velocity (explicit), damping ratio sqrt(5/6) |beta| (H11;
   * the clamped law's refitted beta) */
  double beta = it->damping == ADEM_DAMPING_CLAMPED ? pp->beta_clamped : pp->beta;
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
