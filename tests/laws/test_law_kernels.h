/* The kernel of the test-only rolling law (test_law_rows.h): a couple proportional to the relative
 * spin, -eta_r R_r |F_n| omega_rel / (1 rad/s), equal and opposite on the two bodies. */
#ifndef ADEM_TEST_LAW_KERNELS_H
#define ADEM_TEST_LAW_KERNELS_H

static inline void adem_rolling_test_viscous_law(const adem_rolling_input *in, adem_vec3 *hist, double *aux,
                                                 adem_rolling_output *out) {
  (void)hist;
  (void)aux;
  double c = adem_rolling_eta(in) * adem_rolling_radius(in->g) * in->f_load;
  out->torque = v3_scale(in->g->omega_rel, -c);
}

/* Model C with k_r 1.1 times Ai et al.'s (a wrong law): the rocking period drops by 1/sqrt(1.1). */
static inline void adem_rolling_test_model_c_stiff_law(const adem_rolling_input *in,
                                                       adem_vec3 *hist, double *aux,
                                                       adem_rolling_output *out) {
  const adem_contact_geometry *g = in->g;
  double R_r = adem_rolling_radius(g);
  double eta = adem_rolling_eta(in);
  double k_r = 1.1 * 2.25 * in->Sn * eta * eta * R_r * R_r;
  double c_r = in->pp->param[ADEM_PARAM_ROLLING_DAMPING] * 2.0 * sqrt(g->inertia_r * k_r);
  out->torque = adem_rolling_model_c(hist, aux, g->n, g->omega_rel, g->omega_pred, in->dt, k_r,
                                     eta * R_r * in->f_load, c_r, &out->dissipated);
  out->dashpot = v3_sub(out->torque, *hist);
  if (k_r > 0.0) out->elastic = 0.5 * v3_norm2(*hist) / k_r;
}

/* Model C limited to half its bound: holds a sphere only up to half of eta_r's slope. */
static inline void adem_rolling_test_model_c_half_limit_law(const adem_rolling_input *in,
                                                            adem_vec3 *hist, double *aux,
                                                            adem_rolling_output *out) {
  const adem_contact_geometry *g = in->g;
  double R_r = adem_rolling_radius(g);
  double eta = adem_rolling_eta(in);
  double k_r = 2.25 * in->Sn * eta * eta * R_r * R_r;
  double c_r = in->pp->param[ADEM_PARAM_ROLLING_DAMPING] * 2.0 * sqrt(g->inertia_r * k_r);
  out->torque = adem_rolling_model_c(hist, aux, g->n, g->omega_rel, g->omega_pred, in->dt, k_r,
                                     0.5 * eta * R_r * in->f_load, c_r, &out->dissipated);
  out->dashpot = v3_sub(out->torque, *hist);
  if (k_r > 0.0) out->elastic = 0.5 * v3_norm2(*hist) / k_r;
}

/* DTK (H18-H22) with k_r 0.2 times H20's: the yield torque drops to 0.2 k_r xi_crit. */
static inline void adem_rolling_test_dtk_soft_law(const adem_rolling_input *in, adem_vec3 *hist, double *aux,
                                                  adem_rolling_output *out) {
  const adem_contact_geometry *g = in->g;
  const adem_pair_params *pp = in->pp;
  bool keep_real = pp->dtk_rolling_modification;
  double f_c = adem_jkr_critical_force(keep_real ? pp->gamma_real : pp->gamma, g->R);
  double a0_mod = adem_jkr_a0(pp->gamma, g->R, pp->E);
  double a0_real = keep_real ? adem_jkr_a0(pp->gamma_real, g->R, pp->E_real) : a0_mod;
  double ratio = in->a / a0_mod;
  double k_r = 0.2 * 4.0 * f_c * ratio * sqrt(ratio);
  double xi_crit = a0_real / 12.0 * pp->param[ADEM_PARAM_ADHESION_HYSTERESIS];
  adem_vec3 v_l = adem_rolling_dtk_velocity(g->omega_rel, g->n, g->R);
  out->torque = adem_rolling_dtk(hist, aux, g->n, v_l, in->dt, k_r, xi_crit, g->R, &out->dissipated);
  out->elastic = 0.5 * k_r * v3_norm2(*hist) / g->R;
}

/* Simplified JKR with the surface energy (so F_C = 3 pi gamma R) 1.05 times the pair's. */
static inline adem_normal_result adem_normal_test_jkr_fc105_law(const adem_pair_params *pp,
                                                                const adem_contact_geometry *g,
                                                                double a_hertz) {
  adem_pair_params q = *pp;
  q.gamma *= 1.05;
  return adem_normal_jkr_law(&q, g, a_hertz);
}

/* Simplified JKR with gamma x (E/E_real)^0.05: right at f = 1, a pull-off that drifts with f. */
static inline adem_normal_result adem_normal_test_jkr_epull_law(const adem_pair_params *pp,
                                                                const adem_contact_geometry *g,
                                                                double a_hertz) {
  adem_pair_params q = *pp;
  q.gamma *= pow(pp->E / pp->E_real, 0.05);
  return adem_normal_jkr_law(&q, g, a_hertz);
}

/* Simplified JKR under another name (test_law_rows.h: its cold path is JKR's hooks). */
static inline adem_normal_result adem_normal_test_jkr_like_law(const adem_pair_params *pp,
                                                               const adem_contact_geometry *g,
                                                               double a_hertz) {
  return adem_normal_jkr_law(pp, g, a_hertz);
}

#endif
