/* The kernels behind the rows of include/adem/laws.h: one function per law with its slot's
 * signature, pure (inputs in, force out, history updated in place). The force pass
 * (src/core/contact_force.h) calls them through a switch generated from the rows, so a law costs no
 * function pointer per contact. Conventions (physics notes 2-3): n points from i to j (or from the
 * particle into the wall), the overlap is positive in contact, positive normal force is
 * repulsive, w = v_i,c - v_j,c is the velocity of i's contact point relative to j's. */
#ifndef ADEM_LAWS_KERNELS_H
#define ADEM_LAWS_KERNELS_H

#include <math.h>
#include <stdbool.h>

#include "adem/laws.h"
#include "adem/vec3.h"
#include "hertz.h"
#include "jkr.h"
#include "law_inline.h"
#include "rolling.h"
#include "tangential.h"

/* What the laws know about a pair of materials: derived once per pair (core/materials.c). */
typedef struct adem_pair_params {
  double E;      /* effective Young's modulus 1/E = sum (1-nu^2)/E_k, modified stiffness (H2) */
  double G;      /* effective shear modulus, 1/G = sum (2-nu_k)/G_k (H15) */
  double E_real; /* the same for the real material (f = 1) */
  double G_real;
  double restitution;
  double beta;         /* ln e / sqrt(ln^2 e + pi^2) <= 0 (H12) */
  double beta_clamped; /* beta that gives e_eff = e when the normal force cannot pull (damping
                        * `clamped`; derived only for pairs that use it) */
  double friction;
  double gamma;                     /* effective surface energy, modified (H24) */
  double gamma_real;                /* of the real material */
  double param[ADEM_PARAM_COUNT];   /* the pair's value of each law parameter (its mixing rule) */
  double param_a[ADEM_PARAM_COUNT]; /* side a's (the first material's) value */
  double param_b[ADEM_PARAM_COUNT]; /* side b's value */
  /* DTK under reduced stiffness: keep F_C, a0 and xi_crit of the real material (H section 3.2) */
  bool dtk_rolling_modification;
} adem_pair_params;

/* One contact as the laws see it. */
typedef struct adem_contact_geometry {
  adem_vec3 n;          /* unit normal from i to j */
  double delta;         /* overlap, > 0 */
  double R;             /* effective radius (H2; wall: r_i) */
  double mstar;         /* effective mass (wall: m_i) */
  adem_vec3 w;          /* relative velocity of the contact points, i minus j, at the half step
                         * (the drift's: displacements of the step are w dt) */
  adem_vec3 omega_rel;  /* (omega_i - omega_j) without its twist about n, at the half step */
  adem_vec3 w_pred;     /* w predicted at the full step, v + F_old dt/(2m): the dashpots' */
  double mob_t;         /* the change of w's tangential part per unit tangential force on i over
                         * the closing half kick: for spheres (r^2/I = 2.5/m) 3.5 (1/m_i + 1/m_j)
                         * dt/2; 0 in the first-order scheme */
  adem_vec3 omega_pred; /* omega_rel likewise: model C's dashpot */
  double ri, rj;        /* radii; rj = 0 for a wall */
  double inertia_r;     /* rolling inertia I_r (Ai et al. 2011) */
  bool energy;          /* the normal law's stored energy is wanted (else it may be left 0) */
  bool packed;          /* in a loop the compiler packs (the force pass's block kernels): where a
                         * law would call the library it gives NaN instead, and the pass does
                         * that contact again one at a time */
} adem_contact_geometry;

/* ---------------------------------------------------------------- normal slot */

typedef struct adem_normal_result {
  double f_elastic;  /* elastic normal force, > 0 repulsive */
  double e_elastic;  /* energy stored, J */
  double f_critical; /* F_C of an adhesive law (the Coulomb load is |F + 2 F_C|), else 0 */
  double a;          /* contact radius the rolling laws see */
} adem_normal_result;

/* a_hertz = sqrt(R delta), computed once per contact. */
ADEM_LAW adem_normal_result adem_normal_hertz_law(const adem_pair_params *pp,
                                                  const adem_contact_geometry *g,
                                                  double a_hertz) {
  adem_normal_result r;
  r.f_elastic = adem_hertz_force(pp->E, a_hertz, g->delta); /* H9 without adhesion */
  r.e_elastic = g->energy ? adem_hertz_energy(pp->E, a_hertz, g->delta) : 0.0;
  r.f_critical = 0.0;
  r.a = a_hertz;
  return r;
}

ADEM_LAW adem_normal_result adem_normal_jkr_law(const adem_pair_params *pp,
                                                const adem_contact_geometry *g,
                                                double a_hertz) {
  (void)a_hertz;
  adem_normal_result r;
  r.a = adem_jkr_contact_radius_as(pp->gamma, g->R, pp->E, g->delta, g->packed); /* H10 */
  r.f_elastic = adem_jkr_force(pp->gamma, g->R, pp->E, r.a);                     /* H8-H9 */
  r.e_elastic = g->energy ? adem_jkr_energy(pp->gamma, g->R, pp->E, r.a) : 0.0;
  r.f_critical = adem_jkr_critical_force(pp->gamma, g->R);
  return r;
}

/* ---------------------------------------------------------------- damping slot */

/* The dashpots beside the normal and tangential springs, and the total normal force. */
typedef struct adem_damping_input {
  double Sn, St; /* normal and tangential stiffness, 2 E a and 8 G a (H13, H14) */
  double mstar;
  double vn;         /* normal approach speed (> 0 approaching) */
  double f_elastic;  /* elastic normal force of the normal law, > 0 repulsive */
  double f_critical; /* F_C of an adhesive normal law, else 0 */
} adem_damping_input;

typedef struct adem_damping_output {
  double f_normal; /* total normal force, > 0 repulsive: f_elastic and the dashpot */
  double ct;       /* tangential dashpot coefficient (force -ct v_t), N s/m */
} adem_damping_output;

/* H11-H13 with H16's square root: F_N = F_el + c_n v_n, c = -2 sqrt(5/6) beta sqrt(S m*). The
 * total is not clipped: near separation the dashpot pulls, which is what makes e_eff = e. */
ADEM_LAW void adem_damping_viscoelastic_law(const adem_pair_params *pp,
                                            const adem_damping_input *in,
                                            adem_damping_output *out) {
  double cn = adem_damping_coefficient(pp->beta, in->Sn, in->mstar);
  out->f_normal = in->f_elastic + cn * in->vn;
  out->ct = adem_damping_coefficient(pp->beta, in->St, in->mstar);
}

/* The same dashpots, but the dashpot never pulls the contact below the least force of its
 * elastic law: F_N = max(F_min, F_el + c_n v_n), F_min = 0 without adhesion and the simplified
 * JKR's force where the contact forms and breaks, -(8/9) F_C (H8-H10 at delta = 0), with it: the
 * JKR force pulls by design, the dashpot does not add to the pull beyond it, and as gamma -> 0
 * the law becomes Hertz's clamped one (docs/models.md). The normal dashpot takes the beta that
 * gives e_eff = e with the clamp (adem_damping_beta_clamped, derived per pair); the tangential
 * one keeps H12's beta. */
ADEM_LAW void adem_damping_clamped_law(const adem_pair_params *pp,
                                       const adem_damping_input *in,
                                       adem_damping_output *out) {
  double cn = adem_damping_coefficient(pp->beta_clamped, in->Sn, in->mstar);
  double f = in->f_elastic + cn * in->vn;
  double f_min = 0.0 - (8.0 / 9.0) * in->f_critical; /* +0 without adhesion */
  out->f_normal = f < f_min ? f_min : f;
  out->ct = adem_damping_coefficient(pp->beta, in->St, in->mstar);
}

/* ---------------------------------------------------------------- tangential slot */

/* Advances the history (three doubles and one more, aux) by one step and fills the tangential
 * force on i, its dashpot part, the stored and the dissipated energy (tangential.h). */
ADEM_LAW void adem_tangential_total_law(const adem_tangential_input *in, adem_vec3 *hist,
                                        double *aux, adem_tangential_output *out) {
  adem_tangential_total(in, hist, aux, out); /* H14-H17 */
}

ADEM_LAW void adem_tangential_incremental_law(const adem_tangential_input *in,
                                              adem_vec3 *hist, double *aux,
                                              adem_tangential_output *out) {
  adem_tangential_incremental(in, hist, aux, out); /* H14, H16-H17, Mindlin-Deresiewicz */
}

/* ---------------------------------------------------------------- rolling slot */

typedef struct adem_rolling_input {
  const adem_contact_geometry *g;
  const adem_pair_params *pp;
  double dt;
  double f_load; /* normal load |F_el + 2 F_C| */
  double a;      /* contact radius of the normal law */
  double Sn;     /* normal stiffness 2 E sqrt(R delta) */
} adem_rolling_input;

typedef struct adem_rolling_output {
  adem_vec3 torque;  /* couple on i (j takes the opposite) */
  adem_vec3 dashpot; /* the part of torque that is not a spring's (model A's whole couple, model
                      * C's dashpot): its work is dissipation */
  double capacity;   /* per-particle laws: resistance this contact offers (BROF's e_c |F_n|) */
  double elastic;    /* energy stored in a rolling spring, J */
  double dissipated; /* energy a spring's limit took in the step (models C, DTK), J */
} adem_rolling_output;

/* Rolling radius R_r (wall: r_i) and the eta_r of models A and C: the mean of a particle pair's,
 * the particle's on a wall (notes section 4). */
ADEM_LAW double adem_rolling_radius(const adem_contact_geometry *g) {
  return g->R; /* r_i r_j/(r_i + r_j), a wall's r_i: the effective radius, computed once */
}
/* (Both values are read whatever the branch: a load under a branch keeps the force pass's block
 * loops from packing, pair_blocks.c.) */
ADEM_LAW double adem_rolling_eta(const adem_rolling_input *in) {
  int k = ADEM_PARAM_ROLLING_FRICTION;
  double eta_a = in->pp->param_a[k], eta_b = in->pp->param_b[k];
  return in->g->rj == 0.0 ? eta_a : 0.5 * (eta_a + eta_b);
}

/* Model C's dashpot C_r = delta_r 2 sqrt(I_r k_r); without one (delta_r = 0) the square root is
 * skipped: the same 0. */
ADEM_LAW double adem_rolling_damping(const adem_pair_params *pp, const adem_contact_geometry *g,
                                     double k_r) {
  double d = pp->param[ADEM_PARAM_ROLLING_DAMPING];
  return d == 0.0 ? 0.0 : d * 2.0 * sqrt(g->inertia_r * k_r);
}

ADEM_LAW void adem_rolling_none_law(const adem_rolling_input *in, adem_vec3 *hist, double *aux,
                                    adem_rolling_output *out) {
  (void)in;
  (void)hist;
  (void)aux;
  (void)out;
}

ADEM_LAW void adem_rolling_model_a_law(const adem_rolling_input *in, adem_vec3 *hist, double *aux,
                                       adem_rolling_output *out) {
  (void)hist; /* I7-I8 */
  (void)aux;
  out->torque = adem_rolling_model_a(in->g->omega_rel, adem_rolling_eta(in) * adem_rolling_radius(in->g),
                                     in->f_load);
  out->dashpot = out->torque; /* no spring: all its work is dissipation */
}

ADEM_LAW void adem_rolling_model_c_law(const adem_rolling_input *in, adem_vec3 *hist, double *aux,
                                       adem_rolling_output *out) {
  const adem_contact_geometry *g = in->g;
  double R_r = adem_rolling_radius(g);
  double eta = adem_rolling_eta(in);
  double k_r = 2.25 * in->Sn * eta * eta * R_r * R_r;
  double c_r = adem_rolling_damping(in->pp, g, k_r);
  out->torque = adem_rolling_model_c(hist, aux, g->n, g->omega_rel, g->omega_pred, in->dt, k_r,
                                     eta * R_r * in->f_load, c_r, &out->dissipated);
  out->dashpot = v3_sub(out->torque, *hist);
  if (k_r > 0.0) out->elastic = 0.5 * v3_norm2(*hist) / k_r; /* spring: M^2/(2 k_r) */
}

ADEM_LAW void adem_rolling_model_c_capped_law(const adem_rolling_input *in, adem_vec3 *hist, double *aux,
                                              adem_rolling_output *out) {
  const adem_contact_geometry *g = in->g;
  double R_r = adem_rolling_radius(g);
  double eta = adem_rolling_eta(in);
  double k_r = 2.25 * in->Sn * eta * eta * R_r * R_r;
  double c_r = adem_rolling_damping(in->pp, g, k_r);
  out->torque = adem_rolling_model_c_capped(hist, aux, g->n, g->omega_rel, g->omega_pred, in->dt, k_r,
                                            eta * R_r * in->f_load, c_r, &out->dissipated);
  out->dashpot = v3_sub(out->torque, *hist);
  if (k_r > 0.0) out->elastic = 0.5 * v3_norm2(*hist) / k_r;
}

ADEM_LAW void adem_rolling_brof_law(const adem_rolling_input *in, adem_vec3 *hist, double *aux,
                                    adem_rolling_output *out) {
  (void)aux;
  (void)hist; /* I9: e_c = min(eta_i r_i, eta_j r_j); wall: eta_i r_i */
  const adem_contact_geometry *g = in->g;
  int k = ADEM_PARAM_ROLLING_FRICTION;
  double e_c = in->pp->param_a[k] * g->ri;
  double e_b = in->pp->param_b[k] * g->rj; /* read whatever the branch, as in adem_rolling_eta */
  /* fmin without a library call: both are finite and >= 0 */
  if (g->rj != 0.0 && e_b < e_c) e_c = e_b;
  out->capacity = e_c * in->f_load;
}

/* The same capacity; the force pass's per-particle sum takes the partners' spins into the target
 * (force_sums.c). */
ADEM_LAW void adem_rolling_brof_objective_law(const adem_rolling_input *in, adem_vec3 *hist,
                                              double *aux, adem_rolling_output *out) {
  adem_rolling_brof_law(in, hist, aux, out); /* I9 */
}

ADEM_LAW void adem_rolling_dtk_law(const adem_rolling_input *in, adem_vec3 *hist, double *aux,
                                   adem_rolling_output *out) {
  const adem_contact_geometry *g = in->g;
  const adem_pair_params *pp = in->pp;
  /* Real F_C, a0 and xi_crit; only a/a0 from the modified material (H section 3.2). Without that
   * modification every quantity is the modified material's. */
  bool keep_real = pp->dtk_rolling_modification;
  double f_c = adem_jkr_critical_force(keep_real ? pp->gamma_real : pp->gamma, g->R);
  double a0_mod = adem_jkr_a0(pp->gamma, g->R, pp->E);
  double a0_real = keep_real ? adem_jkr_a0(pp->gamma_real, g->R, pp->E_real) : a0_mod;
  double ratio = in->a / a0_mod;
  double k_r = 4.0 * f_c * ratio * sqrt(ratio);                                /* H20 */
  double xi_crit = a0_real / 12.0 * pp->param[ADEM_PARAM_ADHESION_HYSTERESIS]; /* H22 */
  /* Rolling velocity without Marshall's slip term (as Wang et al. 2015, eq. 31, and LAMMPS):
   * with it xi follows the translation while the couple acts on the spin alone, a circulatory
   * law that feeds energy in when the tangential spring is soft (reduced stiffness). Pure rolling
   * still gives |v_L| = the centre's speed. */
  adem_vec3 v_l = adem_rolling_dtk_velocity(g->omega_rel, g->n, g->R);
  out->torque = adem_rolling_dtk(hist, aux, g->n, v_l, in->dt, k_r, xi_crit, g->R, &out->dissipated);
  /* M = k_r xi over a turn of xi/R: energy k_r xi^2/(2R) */
  out->elastic = 0.5 * k_r * v3_norm2(*hist) / g->R;
}

/* Kernels of rows a build adds (see include/adem/laws.h). */
#ifdef ADEM_EXTRA_KERNELS_HEADER
#include ADEM_EXTRA_KERNELS_HEADER
#endif

#endif
