/* The contact laws, one row per law and slot. A contact between two materials is composed of one
 * law per slot (normal, damping, tangential, rolling; twisting and cohesion have room but no law
 * yet), chosen per material pair. The rows below are the single source of: the case file's
 * choices (interactions[].normal, .damping, .tangential, .rolling), their validation (the
 * parameters each law reads, what it requires of the normal law), the names `adem check` prints,
 * the reference docs and the dispatch in the force pass (src/core/contacts.c).
 *
 * Adding a law: write its kernel in src/contact/ (the signature of its slot, see
 * src/contact/laws_kernels.h), add one row to its slot's list here, and unit-test the kernel.
 * A build may add rows without editing this file: define ADEM_EXTRA_LAWS_HEADER to a header that
 * defines ADEM_EXTRA_ROLLING_LAWS(X) (or ADEM_EXTRA_NORMAL_LAWS, and ADEM_EXTRA_LAW_PARAMS(P) for
 * new parameters), and ADEM_EXTRA_KERNELS_HEADER to one with the kernels (tests/laws/ does this
 * for a test-only rolling law). */
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

/* Rows of each slot: X(ID, name in the case file, kernel, history doubles, requires (a normal law
 * name, or ""), per particle (1) or per contact (0), parameters read (keys, space separated),
 * equations, what it is). */
// clang-format off
#define ADEM_NORMAL_LAWS(X)                                                                       \
  X(ADEM_NORMAL_HERTZ, "hertz", adem_normal_hertz_law, 0, "", 0, "", "H8-H9",                      \
    "Hertz elastic force (4/3) E sqrt(R) delta^(3/2), no adhesion.")                              \
  X(ADEM_NORMAL_JKR, "jkr", adem_normal_jkr_law, 0, "", 0, "surface_energy", "H7-H10",             \
    "Simplified JKR adhesion: forms at delta = 0 with -(8/9) F_C, breaks at delta < 0; contact "   \
    "radius in closed form.")                                                                      \
  ADEM_EXTRA_NORMAL_LAWS(X)
// clang-format on

// clang-format off
#define ADEM_DAMPING_LAWS(X)                                                                      \
  X(ADEM_DAMPING_VISCOELASTIC, "viscoelastic", adem_damping_viscoelastic_law, 0, "", 0, "",        \
    "H11-H13, H16",                                                                                \
    "-2 sqrt(5/6) beta sqrt(S m*) v, beta = ln e / sqrt(ln^2 e + pi^2): normal and tangential "    \
    "dashpots that make a Hertz collision's restitution e; the normal force may pull at the end "  \
    "of a collision.")                                                                             \
  X(ADEM_DAMPING_CLAMPED, "clamped", adem_damping_clamped_law, 0, "", 0, "", "H11-H13, H16",       \
    "The same dashpots, but without adhesion the normal force never pulls (max(0, F)); the "      \
    "normal beta is refitted so that a Hertz collision's restitution is still e.")
// clang-format on

// clang-format off
#define ADEM_TANGENTIAL_LAWS(X)                                                                   \
  X(ADEM_TANGENTIAL_INCREMENTAL, "incremental", adem_tangential_incremental_law, 4, "", 0, "",     \
    "H14-H17, Mindlin-Deresiewicz",                                                                \
    "Spring force kept as history and changed by -S_t ds each step (S_t = 8 G sqrt(R delta)), "   \
    "scaled down with S_t when the contact shrinks; dashpot; Coulomb limit mu |F_N + 2 F_C|. "     \
    "Cannot create energy on a closed load path.")                                                 \
  X(ADEM_TANGENTIAL_TOTAL, "total", adem_tangential_total_law, 3, "", 0, "", "H14-H17",            \
    "Spring S_t = 8 G sqrt(R delta) on the accumulated tangential displacement (kept in the "     \
    "tangent plane), dashpot, Coulomb limit mu |F_N + 2 F_C| with the spring rescaled on sliding; " \
    "as H writes it (a load that rises at fixed displacement raises the force for free).")
// clang-format on

// clang-format off
#define ADEM_ROLLING_LAWS(X)                                                                      \
  X(ADEM_ROLLING_NONE, "none", adem_rolling_none_law, 0, "", 0, "", "", "No rolling resistance.") \
  X(ADEM_ROLLING_DTK, "dtk", adem_rolling_dtk_law, 4, "jkr", 0, "adhesion_hysteresis",             \
    "H18-H22",                                                                                     \
    "Adhesive rolling resistance (Dominik-Tielens-Krijt): torque k_r xi, k_r = 4 F_C (a/a0)^(3/2), " \
    "|xi| <= xi_crit; under reduced stiffness F_C, a0, xi_crit stay real (H section 3.2).")       \
  X(ADEM_ROLLING_A, "model_a", adem_rolling_model_a_law, 0, "", 0, "rolling_friction", "I7-I8",   \
    "Constant directional torque eta_r R_r |F_n| against the relative spin (oscillates at rest).") \
  X(ADEM_ROLLING_C, "model_c", adem_rolling_model_c_law, 4, "", 0,                                 \
    "rolling_friction rolling_damping", "Ai et al. 2011",                                          \
    "Elastic-plastic spring k_r = 2.25 S_n eta_r^2 R_r^2 limited to eta_r R_r |F_n|, with a "      \
    "dashpot while below the limit.")                                                             \
  X(ADEM_ROLLING_C_CAPPED, "model_c_capped", adem_rolling_model_c_capped_law, 4, "", 0,         \
    "rolling_friction rolling_damping", "Ai et al. 2011, capped",                                  \
    "Model C with spring + dashpot limited to eta_r R_r |F_n| (model C's dashpot alone is not "   \
    "bounded).")                                                                                   \
  X(ADEM_ROLLING_BROF, "brof", adem_rolling_brof_law, 0, "", 1, "rolling_friction", "I9-I10",      \
    "Bounded rolling friction: per particle, the torque that stops its spin within the step, "    \
    "bounded by the sum of e_c |F_n| over its contacts; never reverses the rotation.")             \
  X(ADEM_ROLLING_BROF_OBJECTIVE, "brof_objective", adem_rolling_brof_objective_law, 0, "", 1,      \
    "rolling_friction", "I9-I10, objective",                                                       \
    "BROF whose target spin is the capacity-weighted mean of all its partners' spins (walls' and " \
    "particles'), not 0 for particle partners: I9-I10 when the partners are at rest; a cluster "  \
    "turning rigidly with a drum or turntable is not braked.")                                     \
  ADEM_EXTRA_ROLLING_LAWS(X)
// clang-format on

typedef enum adem_normal_model {
#define ADEM_X(ID, name, kernel, hist, req, pp, params, eq, doc) ID,
  ADEM_NORMAL_LAWS(ADEM_X)
#undef ADEM_X
  ADEM_NORMAL_COUNT
} adem_normal_model;

typedef enum adem_damping_model {
#define ADEM_X(ID, name, kernel, hist, req, pp, params, eq, doc) ID,
  ADEM_DAMPING_LAWS(ADEM_X)
#undef ADEM_X
  ADEM_DAMPING_COUNT
} adem_damping_model;

typedef enum adem_tangential_model {
#define ADEM_X(ID, name, kernel, hist, req, pp, params, eq, doc) ID,
  ADEM_TANGENTIAL_LAWS(ADEM_X)
#undef ADEM_X
  ADEM_TANGENTIAL_COUNT
} adem_tangential_model;

typedef enum adem_rolling_model {
#define ADEM_X(ID, name, kernel, hist, req, pp, params, eq, doc) ID,
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
} adem_law;

typedef struct adem_law_param {
  adem_law_param_id id;
  const char *key;
  const char *unit;
  double def, lo;       /* default and lower bound (value >= lo) */
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
double adem_law_jkr_critical_force(double gamma, double R);          /* F_C = 3 pi gamma R */
double adem_law_jkr_a0(double gamma, double R, double E);            /* (9 pi gamma R^2/E)^(1/3) */
double adem_law_jkr_contact_radius(double gamma, double R, double E, double delta); /* H10 */
double adem_law_jkr_force(double gamma, double R, double E, double a);  /* H8-H9, > 0 repulsive */
double adem_law_jkr_energy(double gamma, double R, double E, double a); /* relative to delta = 0 */
double adem_law_hertz_force(double E, double R, double delta);       /* (4/3) E sqrt(R) delta^1.5 */

#ifdef __cplusplus
}
#endif
#endif
