/* Paper studies built on the library (src/studies): single collisions in bulk (`adem collide`)
 * and the reproductions of the papers' figures (`adem validate`). They use only the public API,
 * as a program of your own would. */
#ifndef ADEM_STUDIES_H
#define ADEM_STUDIES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/base.h"
#include "adem/laws.h"
#include "adem/world.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------- collisions */

/* Single collisions in bulk: head-on particle-particle and oblique particle-wall impacts, each in
 * its own two-body world, run in parallel over collisions (notes section 7, H section 5). */
typedef enum adem_collide_kind {
  ADEM_COLLIDE_PAIR = 0, /* two spheres of one material, head-on */
  ADEM_COLLIDE_WALL = 1  /* a sphere on a rigid plane wall at angle psi */
} adem_collide_kind;

/* What became of a collision (H Fig. 9). */
typedef enum adem_collide_outcome {
  ADEM_OUTCOME_REBOUND = 0,  /* the sphere separates (e1) */
  ADEM_OUTCOME_CAPTURED = 1, /* it stays in contact; no rolling phase (pair, no DTK, ...) */
  ADEM_OUTCOME_ROLLING = 2,  /* it stays in contact and keeps rolling (e2) */
  ADEM_OUTCOME_STUCK = 3     /* it stays in contact and comes to rest (e3) */
} adem_collide_outcome;
const char *adem_collide_outcome_name(adem_collide_outcome o); /* "rebound", ... */

/* Called after every time step: time since the start, overlap (m, < 0 while apart), normal
 * approach speed (m/s, > 0 approaching) and the normal contact force (N, > 0 repulsive). */
typedef void adem_collide_sample_fn(double t, double overlap, double v_n, double force_n,
                                    void *user);
/* Wall impacts: called after every time step with the time since the start, the centre's travel
 * along the wall since the first touch (m), its speed along the wall (m/s) and |xi| of the DTK
 * contact (m, 0 without contact). */
typedef void adem_collide_track_fn(double t, double travel, double v_along, double xi,
                                   void *user);

typedef struct adem_collide_spec {
  adem_collide_kind kind;
  double radius;                  /* r_i, m */
  double size_ratio;              /* beta = r_j / r_i (pair only) */
  double density;                 /* rho of both spheres, kg/m^3 */
  double young;                   /* effective modulus E of the real materials (H2), Pa */
  double poisson;                 /* nu of the spheres (enters G, H15) */
  double restitution;             /* e of the pair, (0, 1] */
  double friction;                /* mu_s */
  double surface_energy;          /* gamma of the pair, J/m^2; > 0 selects simplified JKR, 0 Hertz */
  double stiffness_factor;        /* f = E_mod/E in (0, 1] */
  bool keep_gamma;                /* true: E reduced but gamma left as is (not H24), for comparison */
  double speed;                   /* relative impact speed, m/s */
  double angle;                   /* psi, between the velocity and the wall, rad (pi/2: normal impact) */
  double steps_per_tc;            /* time steps per collision time t_c (default 200) */
  double max_periods;             /* in contact this many t_c without a decision: stuck, undecided */
  adem_collide_sample_fn *sample; /* may be NULL */
  void *sample_user;
  /* Deposition on the wall (H section 5.3, Fig. 9): DTK rolling resistance and a constant force
   * through the centre, parallel to the wall, along the tangential impact velocity (+x; +x also
   * for a normal impact). F_ext = force_ext + force_hat F_yield: give one of the two. */
  bool dtk;                     /* DTK rolling resistance on the sphere-wall pair (H18-H22) */
  double hysteresis;            /* adhesion hysteresis delta_gamma/gamma (H18) */
  bool dtk_modification;        /* true (default): real F_C, a0, xi_crit, only a/a0 modified (H section
                                 * 3.2); false: all from the modified material */
  double force_ext;             /* N */
  double force_hat;             /* F_ext / F_yield, F_yield = adem_collide_yield_force() */
  bool at_rest;                 /* no impact: start at rest at the JKR equilibrium (a = a0) */
  double rest_periods;          /* decision window, in rolling periods T_r (default 3) */
  double max_roll_periods;      /* longest rolling phase, in T_r (default 400); then undecided */
  bool capture_only;            /* stop at the capture (outcome captured): no rolling phase */
  adem_collide_track_fn *track; /* may be NULL */
  void *track_user;
  adem_tangential_model tangential; /* tangential law (default: incremental; H14 is `total`) */
  adem_contact_scheme scheme;       /* contact forces in the step (default: second order) */
  double approach_steps;            /* steps of travel to the first touch (default 1.5: the
                                     * crossing falls half a step before a force pass) */
  double dt;                        /* > 0: this time step instead of t_ref / steps_per_tc */
  int normal_law;                   /* >= 0: this normal law (a row of laws.h) instead of jkr for
                                     * a surface energy > 0 and hertz for 0 (-1, the default) */
  int rolling_law;                  /* >= 0: this rolling law instead of DTK when dtk is set */
} adem_collide_spec;
adem_collide_spec adem_default_collide_spec(void);

typedef struct adem_collide_result {
  adem_status status; /* ADEM_OK, or why this collision could not be run (message) */
  bool stuck;         /* captured: the spheres never separate (the contact's energy says so);
                       * whether the sphere then rolls or rests is in `outcome` */
  bool undecided;     /* stopped after max_periods without separating or a sure capture */
  double e_eff;       /* separation / approach normal speed; 0 when stuck */
  double v_n_in;      /* normal approach speed, m/s */
  double v_n_out;     /* normal separation speed, m/s (0 when stuck) */
  double v_t_out;     /* tangential speed of the centre after the impact (wall), m/s */
  double omega_out;   /* angular speed after the impact (wall), rad/s */
  double t_touch;     /* time of the first touch since the start, s */
  double duration;    /* first touch to separation (to the stop when stuck), s */
  double max_overlap; /* m */
  double t_c;         /* collision time the step was taken from (modified stiffness), s */
  double dt;          /* time step, s */
  uint64_t steps;
  double ke_in, ke_out; /* kinetic energy (translation + rotation) before and at the end, J */
  double work;          /* work of all forces and torques over the run (Verlet trapezoid), J */
  /* Deposition (wall with DTK; see adem_collide for the rule) */
  adem_collide_outcome outcome;
  double force_ext;     /* F_ext applied, N */
  double xi_crit;       /* critical rolling distance of the contact (H18), m */
  double t_roll;        /* period T_r of rolling oscillations on k_r = 4 F_C at a = a0, s */
  double roll_distance; /* centre's travel along the wall from the first touch to rest (stuck),
                         * to the end (rolling) or to the separation (rebound), m */
  double t_rest;        /* first touch (start when at rest) to rest, s; NaN unless stuck */
  double v_end;         /* speed of the centre along the wall at the end, m/s */
  double rolling_work;  /* work of the rolling couple on the sphere over the run, J */
  char message[256];
} adem_collide_result;

/* Dimensionless groups of H section 5.1 with the text's Ad (notes section 7): lambda =
 * E/(rho v^2 sin^2 psi), Ad = 3 gamma/(rho v^2 sin^2 psi r_i) (1+b^3)/((1+b^2) b) for pairs
 * (b the size ratio), 3 gamma/(rho v^2 sin^2 psi r_i) for a wall. E and gamma are the real ones. */
double adem_collide_lambda(const adem_collide_spec *s);
double adem_collide_ad(const adem_collide_spec *s);
/* Set E (resp. gamma) so that lambda (resp. Ad) takes the given value at the spec's speed. */
void adem_collide_set_lambda(adem_collide_spec *s, double lambda);
void adem_collide_set_ad(adem_collide_spec *s, double ad);

/* Effective radius R, mass m* and the contact law's modulus and surface energy (modified). */
typedef struct adem_collide_params {
  double R, mstar, E_mod, gamma_mod;
  double v_n;   /* normal impact speed */
  double u_min; /* JKR energy at equilibrium relative to contact formation (<= 0), J */
  double t_c;   /* Hertz collision time at the speed reached in contact, s */
  double t_osc; /* period of small oscillations about the JKR equilibrium (0 for Hertz), s */
} adem_collide_params;
adem_collide_params adem_collide_derive(const adem_collide_spec *s);

/* F_yield = k_r xi_crit / r at a = a0 = 4 F_C (a0/12)(delta_gamma/gamma) / r with the real E and
 * gamma of the spec (notes section 4; H writes it without the 1/R). 0 unless a wall with DTK. */
double adem_collide_yield_force(const adem_collide_spec *s);
/* F_ext of the spec, N. */
double adem_collide_force(const adem_collide_spec *s);
/* The DTK torque the engine applies (N m, magnitude) to the spec's sphere resting on the wall at
 * a = a0 after rolling a distance xi >= 0 without slip: k_r min(xi, xi_crit) (H20-H22). One force
 * pass of the spec's world, so the material derivation and dtk_modification are the engine's. */
adem_status adem_collide_dtk_torque(const adem_collide_spec *s, double xi, double *torque,
                                    adem_error *err);

/* The elastic normal force (N, > 0 repulsive) the engine applies to the spec's sphere resting on
 * the wall with overlap delta >= 0, at rest (no dashpot): one force pass of the spec's world, so
 * its normal law (normal_law) and the material derivation (f, H24) are the engine's. */
adem_status adem_collide_normal_force(const adem_collide_spec *s, double delta, double *force,
                                      adem_error *err);

/* Hertz collision time t_c = 2.86827 (m*^2/(R E^2 v))^(1/5) (notes section 6). */

/* One collision in its own world (one thread). Never prints.
 *
 * Normal phase: the sphere rebounds when the contact breaks (delta <= 0) and is captured when
 * the contact's normal energy says it can never break (see `stuck`).
 *
 * Rolling phase (wall with DTK, after a capture or from rest): the run goes on with the rolling
 * displacement xi of the contact watched at every step.
 *  - stuck: for a window of rest_periods T_r without a break, |xi| stays below xi_crit and the
 *    centre's speed along the wall below v_rest = 2 omega_r xi_crit, omega_r = 2 pi / T_r. Below
 *    xi_crit the rolling spring is elastic, so the sphere cannot move more than 2 xi_crit from
 *    where it is, and an elastic rolling oscillation moves the centre at most at omega_r xi_crit
 *    (the factor 2 is a margin). The time to rest is the start of that window.
 *  - rolling: for a window of rest_periods T_r without a break, |xi| = xi_crit (the rolling
 *    torque saturated at k_r xi_crit), the normal motion has settled (its energy within 1% of
 *    the JKR well depth of the equilibrium) and the speed along the wall at the end of the window
 *    is not below the speed at its start. A saturated, decelerating sphere is watched on.
 *  - after max_roll_periods T_r without a decision: undecided, classified by the last step
 *    (saturated: rolling, else stuck). */
adem_collide_result adem_collide(const adem_collide_spec *spec);
/* n collisions over nthreads OpenMP threads; out[k] belongs to specs[k] whatever the threads. */
void adem_collide_many(const adem_collide_spec *specs, adem_collide_result *out, size_t n,
                       int nthreads);

/* Sets the parameter x (speed, lambda, ...) of a spec. */
typedef void adem_collide_param_fn(adem_collide_spec *s, double x, void *user);
/* The value of x in [lo, hi] where the outcome changes between stuck and rebound, to a relative
 * width rel_tol, by multisection in log x (3 collisions per round, run on nthreads). Returns
 * ADEM_ERR_INPUT when lo and hi give the same outcome. */
adem_status adem_collide_threshold(const adem_collide_spec *base, adem_collide_param_fn *set,
                                   void *user, double lo, double hi, double rel_tol, int nthreads,
                                   double *x_crit, adem_error *err);

/* Which two outcomes a threshold separates. */
typedef enum adem_collide_split {
  ADEM_SPLIT_CAPTURE = 0, /* captured (stuck, rolling or captured) against rebound */
  ADEM_SPLIT_REST = 1     /* comes to rest (stuck) against anything else (rolling, rebound) */
} adem_collide_split;
/* adem_collide_threshold for either split. The capture split skips the rolling phase
 * (capture_only): whether the sphere rolls or stops does not change a capture. */
adem_status adem_collide_threshold_split(const adem_collide_spec *base,
                                         adem_collide_param_fn *set, void *user,
                                         adem_collide_split split, double lo, double hi,
                                         double rel_tol, int nthreads, double *x_crit,
                                         adem_error *err);

/* Least squares of log y = log c + k log x over the n points with finite, positive x and y;
 * returns how many were used (c and k are NaN below 2). */
size_t adem_collide_fit_power(const double *x, const double *y, size_t n, double *c, double *k);


/* The PSL sphere of 1.27 um on quartz of H Fig. 5 (a wall impact), from the case file
 * cases/haervig/psl-quartz.yaml (embedded at build time): kind, radius, density, E*, nu,
 * restitution and surface energy; the rest of *s is left as it is. */
adem_status adem_collide_psl_quartz(adem_collide_spec *s, adem_error *err);

/* ---------------------------------------------------------------- a sleeper push */

/* The lateral resistance of one sleeper push of cases/irazabal/ballast (push.yaml: the push
 * begins at t = 0.19 s) and its shares by face group, read from PUSH_DIR/timeseries.csv as
 * irazabal-fig17 reads its own push: rows binned by the sleeper's displacement in 0.1 mm bins,
 * each group's mean -F_x over the bin's mean resistance. Writes PUSH_DIR/shares.csv (every bin)
 * and PUSH_DIR/shares.png (gnuplot; png[0] == 0 when it could not be drawn). */
typedef struct adem_push_shares {
  double u_end;       /* the sleeper's displacement at the last row, m */
  double share[4][4]; /* at 0-0.3 mm, 1, 3 and 6 mm (the bins within 0.2 mm of each): base,
                       * cribs (both faces), shoulder end, far end */
  double R[4];        /* the lateral resistance there, N */
  double crossing;    /* the displacement from which the shoulder carries the most of base, cribs
                       * and shoulder in every later bin, m (NaN: not at the end) */
  char csv[4200], png[4200];
} adem_push_shares;

adem_status adem_push_shares_analyze(const char *push_dir, adem_push_shares *out, adem_error *err);

/* ---------------------------------------------------------------- validations */

/* Paper reproductions (`adem validate`): each writes DIR/NAME.csv and DIR/NAME.png and reports
 * the paper's claim, the figure measured here and pass/fail; adem_validation_run collects them in
 * DIR/summary.json and DIR/summary.md. */
typedef struct adem_validation_context {
  const char *out_dir;
  int nthreads; /* threads the validation may use (collisions in bulk run in parallel) */
  bool quick;   /* a smaller version, for the test suite */
  /* Law overrides, for the tests that show a validation can fail with a wrong law: the name of a
   * row of laws.h used instead of the paper's law (NULL: the paper's). normal_law replaces the
   * simplified JKR law of the Haervig validations (their collisions and the curves of Fig. 3);
   * rolling_law replaces model C in irazabal-fig6 and fig9 (Ai et al.'s variant) and DTK in
   * haervig-fig10. */
  const char *normal_law;
  const char *rolling_law;
} adem_validation_context;

typedef struct adem_validation_report {
  char claim[2048];    /* what the paper says, with its figure or section */
  char measured[2048]; /* the figure measured here, with numbers */
  char notes[2048];    /* parameters the paper omits and the choice made, missing data, ... */
  bool pass;
} adem_validation_report;

typedef adem_status adem_validation_fn(const adem_validation_context *ctx, const char *name,
                                       adem_validation_report *report, adem_error *err);

typedef struct adem_validation {
  const char *name;   /* "haervig-fig5" */
  const char *source; /* "Haervig et al. 2017, Fig. 5" */
  const char *title;  /* one line: what is plotted */
  adem_validation_fn *run;
} adem_validation;

size_t adem_validation_count(void);
const adem_validation *adem_validation_at(size_t i);
const adem_validation *adem_validation_find(const char *name);

/* Runs the named validations (all when n == 0) and writes the summaries. *failed counts the
 * validations whose claim did not hold. */
adem_status adem_validation_run(const char *const *names, int n, const adem_validation_context *ctx,
                                int *failed, adem_error *err);

/* Validations of each paper (validate_haervig.c, validate_irazabal.c). */
extern const adem_validation adem_validations_haervig[];
extern const size_t adem_validations_haervig_count;
extern const adem_validation adem_validations_irazabal[];
extern const size_t adem_validations_irazabal_count;
/* Paper-scale runs of whole cases, resumable (validate_repose.c). */
extern const adem_validation adem_validations_repose[];
extern const size_t adem_validations_repose_count;
/* The ballast lateral-resistance test, Figs 16-17 (validate_ballast.c), resumable. */
extern const adem_validation adem_validations_ballast[];
extern const size_t adem_validations_ballast_count;

#ifdef __cplusplus
}
#endif
#endif
