/* The contact laws, one row per law and slot. A contact between two materials is composed of one
 * law per slot (normal, damping, tangential, rolling; twisting and cohesion have room but no law
 * yet), chosen per material pair. The rows below are the single source of: the case file's
 * choices (interactions[].normal, .damping, .tangential, .rolling), their validation (the
 * parameters each law reads, what it requires of the normal law), the names `adem check` prints,
 * the reference docs and the dispatch in the force pass (src/core/contact_force.h).
 *
 * Adding a law: write its kernel in src/laws/ (the signature of its slot, see
 * src/laws/laws_kernels.h), its cold-path hooks if the defaults do not fit it (its own file in
 * src/laws/, src/laws/law_hooks.h), add one row to its slot's list here, and unit-test the
 * kernel (docs/architecture.md, "Contact laws as rows"). A build may add rows without editing
 * this file: define ADEM_EXTRA_LAWS_HEADER to a header that defines ADEM_EXTRA_ROLLING_LAWS(X)
 * (or ADEM_EXTRA_NORMAL_LAWS, and ADEM_EXTRA_LAW_PARAMS(P) for new parameters), and
 * ADEM_EXTRA_KERNELS_HEADER to one with the kernels (tests/laws/ does this for test-only rolling
 * and normal laws). */
#ifndef ADEM_LAWS_H
#define ADEM_LAWS_H

#include <stdbool.h>
#include <stddef.h>

#ifdef ADEM_EXTRA_LAWS_HEADER
#include ADEM_EXTRA_LAWS_HEADER
#endif
#ifndef ADEM_EXTRA_NORMAL_LAWS
#define ADEM_EXTRA_NORMAL_LAWS(X)
#endif
#ifndef ADEM_EXTRA_ROLLING_LAWS
#define ADEM_EXTRA_ROLLING_LAWS(X)
#endif
#ifndef ADEM_EXTRA_LAW_PARAMS
#define ADEM_EXTRA_LAW_PARAMS(P)
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Parameters the laws read, given per material (and mixed for a pair by the rule of the row) or
 * per material pair in an interaction entry (then used as they are for both sides).
 * P(ID, key in the case file, unit, default, lower bound, mixing rule, what it is) */
// clang-format off
#define ADEM_LAW_PARAMS(P)                                                                        \
  P(ADEM_PARAM_SURFACE_ENERGY, "surface_energy", "J/m^2", 0.0, 0.0, ADEM_MIX_GEOMETRIC,             \
    "Surface energy gamma per surface (work of adhesion 2 gamma); a pair takes the geometric "     \
    "mean, scaled by (E_mod/E)^(2/5) under reduced stiffness (H24).")                              \
  P(ADEM_PARAM_ADHESION_HYSTERESIS, "adhesion_hysteresis", "", 0.0, 0.0, ADEM_MIX_MEAN,           \
    "Adhesion hysteresis delta_gamma/gamma, sets xi_crit = (a0/12) delta_gamma/gamma (H22).")      \
  P(ADEM_PARAM_ROLLING_FRICTION, "rolling_friction", "", 0.0, 0.0, ADEM_MIX_SIDES,                 \
    "Rolling friction coefficient eta_r. Particle pair: models A and C take the mean of the two "  \
    "materials' values with R_r = r_i r_j/(r_i + r_j); BROF takes min(eta_i r_i, eta_j r_j). "     \
    "Particle on a wall: the particle's material's value (the wall's is not used) with R_r = r_i. " \
    "An interaction entry's value replaces both sides'. At the same eta_r, BROF's lever arm "      \
    "between two spheres of radius r is eta_r r, twice model C's eta_r r/2.")                      \
  P(ADEM_PARAM_ROLLING_DAMPING, "rolling_damping", "", 0.0, 0.0, ADEM_MIX_MEAN,                    \
    "Rolling damping ratio delta_r of model C: C_r = delta_r 2 sqrt(I_r k_r).")                     \
  ADEM_EXTRA_LAW_PARAMS(P)
// clang-format on

/* How a pair's value comes from its two materials' values. */
typedef enum adem_law_mixing {
  ADEM_MIX_MEAN = 0,      /* (a + b) / 2 */
  ADEM_MIX_GEOMETRIC = 1, /* sqrt(a b) */
  ADEM_MIX_SIDES = 2      /* both kept; the law combines them (the pair value is the mean) */
} adem_law_mixing;

typedef enum adem_law_param_id {
#define ADEM_X(ID, key, unit, def, lo, mix, doc) ID,
  ADEM_LAW_PARAMS(ADEM_X)
#undef ADEM_X
      ADEM_PARAM_COUNT
} adem_law_param_id;

/* Rows of each slot: X(ID, kernel, history doubles, descriptive columns...), the descriptive
 * columns a designated initializer of adem_law (below): .name (in the case file), .requires (a
 * normal law's name, or ""), .per_particle, .params (keys read, space separated), .equations,
 * .doc, .absolute_spin, .history_kind, and .hooks, the law's cold-path hooks
 * (src/laws/law_hooks.h: its pair's constants, collision time, checks, report lines...),
 * NULL for none. A column left out is "" or 0, so a new column touches only the rows that set
 * it. */
// clang-format off
#define ADEM_NORMAL_LAWS(X)                                                                       \
  X(ADEM_NORMAL_HERTZ, adem_normal_hertz_law, 0, .name = "hertz", .equations = "H8-H9",           \
    .doc = "Hertz elastic force (4/3) E sqrt(R) delta^(3/2), no adhesion.",                       \
    .hooks = &adem_hertz_hooks)                                                                   \
  X(ADEM_NORMAL_JKR, adem_normal_jkr_law, 0, .name = "jkr", .params = "surface_energy",           \
    .equations = "H7-H10",                                                                        \
    .doc = "Simplified JKR adhesion: forms at delta = 0 with -(8/9) F_C, breaks at delta < 0; "   \
           "contact radius in closed form.",                                                      \
    .hooks = &adem_jkr_hooks)                                                                     \
  ADEM_EXTRA_NORMAL_LAWS(X)
// clang-format on

// clang-format off
#define ADEM_DAMPING_LAWS(X)                                                                      \
  X(ADEM_DAMPING_VISCOELASTIC, adem_damping_viscoelastic_law, 0, .name = "viscoelastic",          \
    .equations = "H11-H13, H16",                                                                  \
    .doc = "-2 sqrt(5/6) beta sqrt(S m*) v, beta = ln e / sqrt(ln^2 e + pi^2): normal and "       \
           "tangential dashpots that make a Hertz collision's restitution e; the normal force "   \
           "may pull at the end of a collision.")                                                 \
  X(ADEM_DAMPING_CLAMPED, adem_damping_clamped_law, 0, .name = "clamped",                         \
    .equations = "H11-H13, H16",                                                                  \
    .doc = "The same dashpots, but without adhesion the normal force never pulls (max(0, F)); "   \
           "the normal beta is refitted so that a Hertz collision's restitution is still e.",     \
    .hooks = &adem_damping_clamped_hooks)
// clang-format on

// clang-format off
#define ADEM_TANGENTIAL_LAWS(X)                                                                   \
  X(ADEM_TANGENTIAL_INCREMENTAL, adem_tangential_incremental_law, 4, .name = "incremental",       \
    .equations = "H14-H17, Mindlin-Deresiewicz", .history_kind = "spring_force",                  \
    .doc = "Spring force kept as history and changed by -S_t ds each step (S_t = 8 G sqrt(R "     \
           "delta)), scaled down with S_t when the contact shrinks; dashpot; Coulomb limit mu "   \
           "|F_N + 2 F_C|. Cannot create energy on a closed load path.")                          \
  X(ADEM_TANGENTIAL_TOTAL, adem_tangential_total_law, 3, .name = "total", .equations = "H14-H17",  \
    .history_kind = "displacement",                                                               \
    .doc = "Spring S_t = 8 G sqrt(R delta) on the accumulated tangential displacement (kept in "  \
           "the tangent plane), dashpot, Coulomb limit mu |F_N + 2 F_C| with the spring "         \
           "rescaled on sliding; as H writes it (a load that rises at fixed displacement raises " \
           "the force for free).")
// clang-format on

// clang-format off
#define ADEM_ROLLING_LAWS(X)                                                                      \
  X(ADEM_ROLLING_NONE, adem_rolling_none_law, 0, .name = "none", .doc = "No rolling resistance.") \
  X(ADEM_ROLLING_DTK, adem_rolling_dtk_law, 4, .name = "dtk", .requires = "jkr",                  \
    .params = "adhesion_hysteresis", .equations = "H18-H22",                                      \
    .doc = "Adhesive rolling resistance (Dominik-Tielens-Krijt): torque k_r xi, k_r = 4 F_C "     \
           "(a/a0)^(3/2), |xi| <= xi_crit; under reduced stiffness F_C, a0, xi_crit stay real "   \
           "(H section 3.2).",                                                                    \
    .hooks = &adem_rolling_dtk_hooks)                                                             \
  X(ADEM_ROLLING_A, adem_rolling_model_a_law, 0, .name = "model_a", .params = "rolling_friction", \
    .equations = "I7-I8",                                                                         \
    .doc = "Constant directional torque eta_r R_r |F_n| against the relative spin (oscillates "   \
           "at rest).")                                                                           \
  X(ADEM_ROLLING_C, adem_rolling_model_c_law, 4, .name = "model_c",                               \
    .params = "rolling_friction rolling_damping", .equations = "Ai et al. 2011",                  \
    .history_kind = "model_c",                                                                    \
    .doc = "Elastic-plastic spring k_r = 2.25 S_n eta_r^2 R_r^2 limited to eta_r R_r |F_n|, with " \
           "a dashpot while below the limit.",                                                    \
    .hooks = &adem_rolling_model_c_hooks)                                                         \
  X(ADEM_ROLLING_C_CAPPED, adem_rolling_model_c_capped_law, 4, .name = "model_c_capped",          \
    .params = "rolling_friction rolling_damping", .equations = "Ai et al. 2011, capped",          \
    .history_kind = "model_c",                                                                    \
    .doc = "Model C with spring + dashpot limited to eta_r R_r |F_n| (model C's dashpot alone is " \
           "not bounded).",                                                                       \
    .hooks = &adem_rolling_model_c_hooks)                                                         \
  X(ADEM_ROLLING_BROF, adem_rolling_brof_law, 0, .name = "brof", .per_particle = true,            \
    .params = "rolling_friction", .equations = "I9-I10", .absolute_spin = true,                   \
    .doc = "Bounded rolling friction: per particle, the torque that stops its spin within the "   \
           "step, bounded by the sum of e_c |F_n| over its contacts; never reverses the "         \
           "rotation.",                                                                           \
    .hooks = &adem_rolling_brof_hooks)                                                            \
  X(ADEM_ROLLING_BROF_OBJECTIVE, adem_rolling_brof_objective_law, 0, .name = "brof_objective",    \
    .per_particle = true, .params = "rolling_friction", .equations = "I9-I10, objective",         \
    .doc = "BROF whose target spin is the capacity-weighted mean of all its partners' spins "     \
           "(walls' and particles'), not 0 for particle partners: I9-I10 when the partners are "  \
           "at rest; a cluster turning rigidly with a drum or turntable is not braked.",          \
    .hooks = &adem_rolling_brof_hooks)                                                            \
  ADEM_EXTRA_ROLLING_LAWS(X)
// clang-format on

typedef enum adem_normal_model {
#define ADEM_X(ID, kernel, hist, ...) ID,
  ADEM_NORMAL_LAWS(ADEM_X)
#undef ADEM_X
      ADEM_NORMAL_COUNT
} adem_normal_model;

typedef enum adem_damping_model {
#define ADEM_X(ID, kernel, hist, ...) ID,
  ADEM_DAMPING_LAWS(ADEM_X)
#undef ADEM_X
      ADEM_DAMPING_COUNT
} adem_damping_model;

typedef enum adem_tangential_model {
#define ADEM_X(ID, kernel, hist, ...) ID,
  ADEM_TANGENTIAL_LAWS(ADEM_X)
#undef ADEM_X
      ADEM_TANGENTIAL_COUNT
} adem_tangential_model;

typedef enum adem_rolling_model {
#define ADEM_X(ID, kernel, hist, ...) ID,
  ADEM_ROLLING_LAWS(ADEM_X)
#undef ADEM_X
      ADEM_ROLLING_COUNT
} adem_rolling_model;

typedef enum adem_law_slot {
  ADEM_SLOT_NORMAL = 0,
  ADEM_SLOT_DAMPING = 1,
  ADEM_SLOT_TANGENTIAL = 2,
  ADEM_SLOT_ROLLING = 3,
  ADEM_SLOT_TWISTING = 4, /* no law yet */
  ADEM_SLOT_COHESION = 5, /* no law yet */
  ADEM_SLOT_COUNT
} adem_law_slot;

/* A law's cold-path hooks (src/laws/law_hooks.h); opaque here. */
struct adem_law_hooks;

/* One row, as the registry gives it. */
typedef struct adem_law {
  adem_law_slot slot;
  int id;               /* the enum value in its slot */
  const char *name;     /* as written in a case file */
  int history;          /* doubles of contact history it keeps (0..4) */
  const char *requires; /* name of the normal law it needs, or "" */
  bool per_particle;    /* acts per particle (BROF), not as a couple per contact */
  const char *params;   /* keys of the parameters it reads, space separated */
  const char *equations;
  const char *doc;
  bool absolute_spin;                 /* rolling: resists a particle's absolute spin against particle partners
                                       * (BROF, I9-I10): brakes a bed turning with a wall and adds angular
                                       * impulse no partner takes back */
  const char *history_kind;           /* what its history holds; laws of a slot with the same kind keep
                                       * it when a stage switches between them (core/history_switch.c):
                                       * tangential "spring_force" or "displacement", rolling "model_c";
                                       * "": cleared on a switch */
  const struct adem_law_hooks *hooks; /* or NULL: every hook's default */
} adem_law;

typedef struct adem_law_param {
  adem_law_param_id id;
  const char *key;
  const char *unit;
  double def, lo; /* default and lower bound (value >= lo) */
  adem_law_mixing mixing;
  const char *doc;
} adem_law_param;

/* "normal", "damping", ... */
const char *adem_law_slot_name(adem_law_slot slot);
/* Rows of a slot, in order of their ids. */
size_t adem_law_count(adem_law_slot slot);
const adem_law *adem_law_get(adem_law_slot slot, int id);
/* The row named name in slot, or NULL. */
const adem_law *adem_law_find(adem_law_slot slot, const char *name);
/* "hertz|jkr": the slot's names, for choices and messages. */
const char *adem_law_choices(adem_law_slot slot);
/* Whether the row reads parameter key. */
bool adem_law_reads(const adem_law *law, const char *key);

const adem_law_param *adem_law_param_get(adem_law_param_id id);
/* The parameter with that key, or NULL. */
const adem_law_param *adem_law_param_find(const char *key);

/* Closed forms of the laws, for studies and checks (the same kernels the force pass calls):
 * simplified JKR (H7-H10) with effective E and gamma, and Hertz. SI units. */
double adem_law_jkr_critical_force(double gamma, double R);                         /* F_C = 3 pi gamma R */
double adem_law_jkr_a0(double gamma, double R, double E);                           /* (9 pi gamma R^2/E)^(1/3) */
double adem_law_jkr_contact_radius(double gamma, double R, double E, double delta); /* H10 */
double adem_law_jkr_force(double gamma, double R, double E, double a);              /* H8-H9, > 0 repulsive */
double adem_law_jkr_energy(double gamma, double R, double E, double a);             /* relative to delta = 0 */
double adem_law_hertz_force(double E, double R, double delta);                      /* (4/3) E sqrt(R) delta^1.5 */

/* ---- what a law pair implies (src/laws/hertz.c, jkr.c) ---- */

/* Hertz collision time (notes section 6): t_c = 2.86827 (m*^2 / (R E^2 v))^(1/5), s. */
double adem_hertz_collision_time(double mstar, double R, double E, double v);

/* What a JKR material pair implies (notes sections 1, 5, 6): `adem check` prints it and the case
 * loader warns from it. */

/* External forces that pull spheres apart should stay below this fraction of the modified
 * pull-off force (H section 6.2: "significantly higher"; a 10% margin). */
#define ADEM_PULLOFF_SAFETY 0.1
/* Minimum atomic separation of the Tabor parameter, m (H1). */
#define ADEM_TABOR_DMIN 1.65e-10

typedef struct adem_jkr_pair_summary {
  double R, mstar;               /* effective radius and mass used */
  double E, E_mod;               /* effective modulus, real and modified (H2, H24) */
  double gamma, gamma_mod;       /* surface energy, real and modified (H24) */
  double a0, a0_mod;             /* equilibrium contact radius (H7) */
  double delta_eq, delta_eq_mod; /* equilibrium overlap a0^2/(3R) */
  double f_c, f_c_mod;           /* critical force 3 pi gamma R */
  double pull_off, pull_off_mod; /* force that breaks the contact, (8/9) F_C */
  double tabor;                  /* Tabor parameter of the real material (H1); JKR valid above 3 */
  double t_c, t_c_mod;           /* Hertz collision time at v_ref (notes section 6) */
  double dt, dt_mod;             /* t_c / 50 */
  double speedup;                /* t_c_mod / t_c = (E/E_mod)^(2/5) */
  double f_ext_max;              /* ADEM_PULLOFF_SAFETY * pull_off_mod */
} adem_jkr_pair_summary;
adem_jkr_pair_summary adem_jkr_pair_summarize(double E, double E_mod, double gamma,
                                              double gamma_mod, double R, double mstar,
                                              double v_ref);

#ifdef __cplusplus
}
#endif
#endif
