/* The cold-path hooks of a contact law: what the code around the force pass needs to know of a
 * law (its pair's constants, the collision time of the step proposal, the stability limit's
 * modes, the checks of a pair's values, the lines of `adem check`), so that a law lives in its
 * own file and its row (include/adem/laws.h, column .hooks) and no code outside src/laws/
 * names a law (tests/tools/check_law_ids.sh). As LAMMPS's granular sub-models carry
 * coeffs_to_local and pulloff_distance, and MercuryDPM's species getCollisionTime. Every hook is
 * optional: a row without it gets the default written beside it. The hot path does not come
 * here: the force pass keeps its switch generated from the rows and the inline kernels. */
#ifndef ADEM_LAW_HOOKS_H
#define ADEM_LAW_HOOKS_H

#include <stdbool.h>
#include <stddef.h>

#include "adem/laws.h"
#include "laws_kernels.h"

/* The laws of a pair, one per slot (ids of the rows). */
typedef struct adem_law_set {
  int normal, damping, tangential, rolling;
} adem_law_set;

/* A pair's values before derivation, for the checks: each material's value of every law
 * parameter, and the interaction entry's (NaN where it gives none). */
typedef struct adem_law_check {
  const double *param_a, *param_b, *param_entry;
  const char *name[2];  /* the two materials' names */
  const char *where[2]; /* where each is defined ("line 11:5"), or NULL */
  const char *law;      /* the name of the row whose hook runs (the dispatch sets it) */
} adem_law_check;

/* The stability limit's rolling mode (core/step_limit.c) at a collision's peak: the spring
 * k_theta (couple per unit relative rotation) and its damping ratio zeta_r. */
typedef struct adem_law_mode_input {
  const adem_pair_params *pp;
  double Sn;                 /* normal stiffness at the peak */
  double a;                  /* Hertz contact radius there */
  double R;                  /* effective radius */
  double eta;                /* rolling friction: the mean of the sides, the particle's on a wall */
  double m_i, r_i, m_j, r_j; /* m_j = 0: a wall */
  double inv_I;              /* 1/I_i + 1/I_j of the spins */
} adem_law_mode_input;

/* `adem check`'s view of a pair at its smallest spheres. */
typedef struct adem_law_report {
  const adem_pair_params *pp;
  double R, mstar, v_ref;
  bool wall;
  const char *pair;                          /* "a-b", "a-b (wall)": for warnings */
  const char *law;                           /* the name of the row whose hook runs (the dispatch sets it) */
  double eta_a, eta_b;                       /* rolling friction of each side */
  const char *from;                          /* where the rolling friction comes from, said after it */
  void (*line)(void *ctx, const char *text); /* one line of the report (the caller indents) */
  void (*warn)(void *ctx, const char *text); /* a warning */
  void *ctx;
} adem_law_report;

typedef struct adem_law_hooks {
  /* The pair's constants this law reads, after the common ones (core/materials.c).
   * Default: none. */
  void (*derive)(adem_pair_params *pp);
  /* Normal slot: the collision time of effective mass m* and radius R at speed v_ref, for the
   * step proposal. Default: Hertz's (notes section 6). */
  double (*collision_time)(const adem_pair_params *pp, double mstar, double R, double v_ref);
  /* Normal slot: the force that breaks a contact of effective radius R under the modified
   * stiffness, for the load-time warning on pulling forces. Default: 0 (nothing holds). */
  double (*pull_off)(const adem_pair_params *pp, double R);
  /* Damping slot: the beta of the normal dashpot the stability limit sees. Default: pp->beta. */
  double (*normal_beta)(const adem_pair_params *pp);
  /* Rolling slot: the rolling mode of the stability limit. Default: none (k_theta = 0). */
  void (*rolling_mode)(const adem_law_mode_input *in, double *k_theta, double *zeta_r);
  /* Rolling slot: whether a contact needs the rolling inertia I_r. Default: false. */
  bool (*needs_rolling_inertia)(const adem_pair_params *pp);
  /* NULL when the law can run with a pair's values, else why not (one sentence in buf);
   * *side: the material to blame (0 or 1), or -1 the pair. Default: always fine. */
  const char *(*check)(const adem_law_check *c, int *side, char *buf, size_t n);
  /* `adem check`'s lines about a pair under this law. Default: none. */
  void (*report)(const adem_law_report *r);
  /* Rolling slot, for a law that reads rolling_friction: how it combines the two sides' eta_r
   * (one line). Default: their mean with R_r = r_i r_j/(r_i + r_j). */
  void (*friction_line)(const adem_law_report *r);
} adem_law_hooks;

/* ---- what the code around the force pass calls: each slot's row's hook, or its default ---- */

/* The pair's constants of its laws, after the common ones. */
void adem_laws_derive(adem_law_set laws, adem_pair_params *pp);
double adem_laws_collision_time(adem_law_set laws, const adem_pair_params *pp, double mstar,
                                double R, double v_ref);
double adem_laws_pull_off(adem_law_set laws, const adem_pair_params *pp, double R);
double adem_laws_normal_beta(adem_law_set laws, const adem_pair_params *pp);
void adem_laws_rolling_mode(adem_law_set laws, const adem_law_mode_input *in, double *k_theta,
                            double *zeta_r);
bool adem_laws_need_rolling_inertia(adem_law_set laws, const adem_pair_params *pp);
/* The first slot's complaint (slots in order), or NULL; *slot the slot that complains. */
const char *adem_laws_check(adem_law_set laws, const adem_law_check *c, adem_law_slot *slot,
                            int *side, char *buf, size_t n);
void adem_laws_report(adem_law_set laws, const adem_law_report *r);
/* The rolling friction line of a pair whose rolling law reads rolling_friction. */
void adem_laws_friction_line(adem_law_set laws, const adem_law_report *r);
/* Whether the rolling law resists absolute spin (the row's .absolute_spin). */
bool adem_laws_absolute_spin(int rolling);

/* A parameter's pair value from its two sides, by the rule of its row (ADEM_LAW_PARAMS). */
double adem_law_param_mix(adem_law_param_id id, double a, double b);

/* Hertz collision time (notes section 6), hertz.c: t_c = 2.86827 (m*^2 / (R E^2 v))^(1/5). The
 * public adem_hertz_collision_time. */
double adem_hertz_collision_time(double mstar, double R, double E, double v);

#endif
