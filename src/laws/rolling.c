/* The rolling laws' cold path (law_hooks.h): their modes in the step's stability limit, model
 * C's rolling inertia, DTK's check and BROF's rolling-friction line. */
#include "rolling.h"

#include <math.h>
#include <stdio.h>

#include "jkr.h"
#include "law_hooks.h"

/* Model C (Ai et al. 2011): the spring k_r = 2.25 S_n eta_r^2 R^2 and its dashpot
 * delta_r 2 sqrt(I_r k_r), I_r about the contact points, on the predicted spin. */
static void model_c_mode(const adem_law_mode_input *in, double *k_theta, double *zeta_r) {
  double R = in->R, eta = in->eta;
  *k_theta = 2.25 * in->Sn * eta * eta * R * R;
  bool wall = !(in->m_j > 0.0);
  double Ic_i = 1.4 * in->m_i * in->r_i * in->r_i;
  double Ic_j = wall ? INFINITY : 1.4 * in->m_j * in->r_j * in->r_j;
  double I_r = 1.0 / (1.0 / Ic_i + 1.0 / Ic_j);
  *zeta_r = in->pp->param[ADEM_PARAM_ROLLING_DAMPING] * sqrt(I_r * in->inv_I);
}

/* The dashpot of model C needs I_r (contact_force.h computes it per contact). */
static bool model_c_inertia(const adem_pair_params *pp) {
  return pp->param[ADEM_PARAM_ROLLING_DAMPING] != 0.0;
}

const adem_law_hooks adem_rolling_model_c_hooks = {.rolling_mode = model_c_mode,
                                                   .needs_rolling_inertia = model_c_inertia};

/* DTK: k_r = 4 F_C (a/a0)^(3/2) (H20) at the collision's peak, at least a = a0, with F_C real
 * under reduced stiffness (H section 3.2): the mode that stays fast when E is reduced. */
static void dtk_mode(const adem_law_mode_input *in, double *k_theta, double *zeta_r) {
  const adem_pair_params *pp = in->pp;
  double R = in->R, a = in->a;
  bool keep_real = pp->dtk_rolling_modification;
  double f_c = adem_jkr_critical_force(keep_real ? pp->gamma_real : pp->gamma, R);
  double a0 = adem_jkr_a0(pp->gamma, R, pp->E);
  double a_jkr = pp->gamma > 0.0 ? adem_jkr_contact_radius(pp->gamma, R, pp->E, a * a / R) : a;
  double ratio = a0 > 0.0 ? fmax(1.0, a_jkr / a0) : 1.0;
  *k_theta = 4.0 * f_c * ratio * sqrt(ratio) * R; /* torque k_r xi, xi = R theta */
  *zeta_r = 0.0;
}

/* DTK's stiffness and limit come from F_C and a0 (H18-H22): it needs a surface energy > 0. */
static const char *dtk_check(const adem_law_check *c, int *side, char *buf, size_t n) {
  const int k = ADEM_PARAM_SURFACE_ENERGY;
  double gamma = !isnan(c->param_entry[k]) ? c->param_entry[k]
                                           : adem_law_param_mix(k, c->param_a[k], c->param_b[k]);
  if (gamma > 0.0) return NULL;
  *side = -1;
  snprintf(buf, n, "`%s` rolling needs a surface energy > 0 (its stiffness and limit come from "
                   "F_C and a0), but the pair's is 0",
           c->law);
  return buf;
}

const adem_law_hooks adem_rolling_dtk_hooks = {.rolling_mode = dtk_mode, .check = dtk_check};

/* BROF (I9): e_c = min(eta_i r_i, eta_j r_j). */
static void brof_friction_line(const adem_law_report *r) {
  char text[512];
  snprintf(text, sizeof text, "rolling friction e_c = min(%g r_i, %g r_j) (BROF, I9: %s)",
           r->eta_a, r->eta_b, r->from);
  r->line(r->ctx, text);
}

const adem_law_hooks adem_rolling_brof_hooks = {.friction_line = brof_friction_line};
