/* The registry of contact laws and their parameters, built from the rows of include/adem/laws.h. */
#include "adem/laws.h"

#include <math.h>
#include <string.h>

#include "dmath.h"
#include "hertz.h"
#include "jkr.h"
#include "law_hooks.h"

/* A row's descriptive columns are a designated initializer (adem/laws.h); those it leaves out
 * take the defaults written first here, which the row's own override. */
#define ROW(SLOT, ID, hist, ...) \
  {.slot = SLOT, .id = ID, .history = hist, .requires = "", .params = "", .equations = "", .doc = "", .history_kind = "", __VA_ARGS__},
#if defined(__clang__)
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Winitializer-overrides"
#elif defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Woverride-init"
#endif
static const adem_law normal_laws[] = {
#define ADEM_X(ID, kernel, hist, ...) ROW(ADEM_SLOT_NORMAL, ID, hist, __VA_ARGS__)
    ADEM_NORMAL_LAWS(ADEM_X)
#undef ADEM_X
};
static const adem_law damping_laws[] = {
#define ADEM_X(ID, kernel, hist, ...) ROW(ADEM_SLOT_DAMPING, ID, hist, __VA_ARGS__)
    ADEM_DAMPING_LAWS(ADEM_X)
#undef ADEM_X
};
static const adem_law tangential_laws[] = {
#define ADEM_X(ID, kernel, hist, ...) ROW(ADEM_SLOT_TANGENTIAL, ID, hist, __VA_ARGS__)
    ADEM_TANGENTIAL_LAWS(ADEM_X)
#undef ADEM_X
};
static const adem_law rolling_laws[] = {
#define ADEM_X(ID, kernel, hist, ...) ROW(ADEM_SLOT_ROLLING, ID, hist, __VA_ARGS__)
    ADEM_ROLLING_LAWS(ADEM_X)
#undef ADEM_X
};
#if defined(__clang__)
#pragma clang diagnostic pop
#elif defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
#undef ROW

static const adem_law_param params[] = {
#define ADEM_X(ID, key, unit, def, lo, mix, doc) {ID, key, unit, def, lo, mix, doc},
    ADEM_LAW_PARAMS(ADEM_X)
#undef ADEM_X
};

/* History is kept in four doubles for the tangential and rolling slots (pairs.h), none for the
 * normal slot: a row cannot ask for more. */
#define ADEM_X(ID, kernel, hist, ...) \
  _Static_assert((hist) == 0, "a normal law keeps no history");
ADEM_NORMAL_LAWS(ADEM_X)
#undef ADEM_X
#define ADEM_X(ID, kernel, hist, ...) \
  _Static_assert((hist) >= 0 && (hist) <= 4, "a law keeps at most 4 doubles of history");
ADEM_ROLLING_LAWS(ADEM_X)
ADEM_TANGENTIAL_LAWS(ADEM_X)
#undef ADEM_X

typedef struct slot_table {
  const char *name;
  const adem_law *rows;
  size_t n;
} slot_table;

static const slot_table slots[ADEM_SLOT_COUNT] = {
    {"normal", normal_laws, sizeof normal_laws / sizeof normal_laws[0]},
    {"damping", damping_laws, sizeof damping_laws / sizeof damping_laws[0]},
    {"tangential", tangential_laws, sizeof tangential_laws / sizeof tangential_laws[0]},
    {"rolling", rolling_laws, sizeof rolling_laws / sizeof rolling_laws[0]},
    {"twisting", NULL, 0},
    {"cohesion", NULL, 0},
};

const char *adem_law_slot_name(adem_law_slot slot) {
  return (unsigned)slot < ADEM_SLOT_COUNT ? slots[slot].name : "?";
}

size_t adem_law_count(adem_law_slot slot) {
  return (unsigned)slot < ADEM_SLOT_COUNT ? slots[slot].n : 0;
}

const adem_law *adem_law_get(adem_law_slot slot, int id) {
  if ((unsigned)slot >= ADEM_SLOT_COUNT || id < 0 || (size_t)id >= slots[slot].n) return NULL;
  return &slots[slot].rows[id];
}

const adem_law *adem_law_find(adem_law_slot slot, const char *name) {
  for (size_t k = 0; k < adem_law_count(slot); ++k)
    if (!strcmp(slots[slot].rows[k].name, name)) return &slots[slot].rows[k];
  return NULL;
}

const char *adem_law_choices(adem_law_slot slot) {
  static char buf[ADEM_SLOT_COUNT][512];
  if ((unsigned)slot >= ADEM_SLOT_COUNT) return "";
  char *b = buf[slot];
  if (!b[0]) {
    size_t at = 0;
    for (size_t k = 0; k < slots[slot].n && at + 1 < sizeof buf[slot]; ++k) {
      const char *nm = slots[slot].rows[k].name;
      size_t len = strlen(nm);
      if (at + len + 2 >= sizeof buf[slot]) break;
      if (k) b[at++] = '|';
      memcpy(b + at, nm, len);
      at += len;
    }
    b[at] = '\0';
  }
  return b;
}

bool adem_law_reads(const adem_law *law, const char *key) {
  size_t n = strlen(key);
  for (const char *p = law->params; *p;) {
    while (*p == ' ') ++p;
    size_t len = strcspn(p, " ");
    if (len == n && !strncmp(p, key, n)) return true;
    p += len;
  }
  return false;
}

const adem_law_param *adem_law_param_get(adem_law_param_id id) {
  return (unsigned)id < ADEM_PARAM_COUNT ? &params[id] : NULL;
}

const adem_law_param *adem_law_param_find(const char *key) {
  for (size_t k = 0; k < ADEM_PARAM_COUNT; ++k)
    if (!strcmp(params[k].key, key)) return &params[k];
  return NULL;
}

double adem_law_jkr_critical_force(double gamma, double R) { return adem_jkr_critical_force(gamma, R); }
double adem_law_jkr_a0(double gamma, double R, double E) { return adem_jkr_a0(gamma, R, E); }
double adem_law_jkr_contact_radius(double gamma, double R, double E, double delta) {
  return adem_jkr_contact_radius(gamma, R, E, delta);
}
double adem_law_jkr_force(double gamma, double R, double E, double a) {
  return adem_jkr_force(gamma, R, E, a);
}
double adem_law_jkr_energy(double gamma, double R, double E, double a) {
  return adem_jkr_energy(gamma, R, E, a);
}
double adem_law_hertz_force(double E, double R, double delta) {
  return adem_hertz_force(E, adem_hertz_radius(R, delta), delta);
}

/* ---------------------------------------------------------------- Hertz restitution */

typedef struct hz_state {
  double x, v;
} hz_state;

static double hz_force(double x, double v, double g) {
  if (x <= 0.0) return 0.0;
  return x * sqrt(x) + g * sqrt(sqrt(x)) * v;
}

static hz_state hz_rk4(hz_state s, double h, double g, int clamp) {
#define HZ_ACC(x, v) (clamp ? -fmax(0.0, hz_force(x, v, g)) : -hz_force(x, v, g))
  double k1x = s.v, k1v = HZ_ACC(s.x, s.v);
  double k2x = s.v + 0.5 * h * k1v, k2v = HZ_ACC(s.x + 0.5 * h * k1x, s.v + 0.5 * h * k1v);
  double k3x = s.v + 0.5 * h * k2v, k3v = HZ_ACC(s.x + 0.5 * h * k2x, s.v + 0.5 * h * k2v);
  double k4x = s.v + h * k3v, k4v = HZ_ACC(s.x + h * k3x, s.v + h * k3v);
#undef HZ_ACC
  hz_state r = {s.x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
                s.v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)};
  return r;
}

double adem_hertz_restitution(double beta, int clamp) {
  const double g = -sqrt(5.0) * beta, h = 2e-4, t0 = 1e-3;
  /* series start: x' = 1 - 0.4 t^2.5 - 0.8 g t^1.25 (x^(1/4) is singular in its derivative) */
  hz_state s = {t0 - 0.4 / 3.5 * adem_dmath_pow(t0, 3.5) -
                    0.8 / 2.25 * g * adem_dmath_pow(t0, 2.25),
                1.0 - 0.4 * adem_dmath_pow(t0, 2.5) - 0.8 * g * adem_dmath_pow(t0, 1.25)};
  for (int k = 0; k < 200000; ++k) {
    hz_state n = hz_rk4(s, h, g, clamp);
    if (clamp && n.v < 0.0) {
      double f0 = hz_force(s.x, s.v, g), f1 = hz_force(n.x, n.v, g);
      if (f1 <= 0.0 && f0 > 0.0) { /* the force reaches zero in this step: they part there */
        double w = f0 / (f0 - f1);
        return -(s.v + w * (n.v - s.v));
      }
    }
    if (n.x <= 0.0) { /* back at x = 0: interpolate the speed there (Hermite in time) */
      double w = s.x / (s.x - n.x);
      return -(s.v + w * (n.v - s.v));
    }
    s = n;
  }
  return 0.0; /* overdamped: never comes back */
}

double adem_damping_beta_clamped(double e) {
  if (!(e < 1.0)) return 0.0;
  /* start from H12's beta (which gives e with the pulling force) and one more damped */
  double b0 = adem_damping_beta(e), b1 = 1.2 * b0 - 0.01;
  double r0 = adem_hertz_restitution(b0, 1) - e, r1 = adem_hertz_restitution(b1, 1) - e;
  for (int k = 0; k < 40 && fabs(r1) > 1e-10 && r1 != r0; ++k) {
    double b2 = b1 - r1 * (b1 - b0) / (r1 - r0);
    if (!(b2 < 0.0)) b2 = 0.5 * b1;
    b0 = b1;
    r0 = r1;
    b1 = b2;
    r1 = adem_hertz_restitution(b1, 1) - e;
  }
  return b1;
}
