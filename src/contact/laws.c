/* The registry of contact laws and their parameters, built from the rows of include/adem/laws.h. */
#include "adem/laws.h"

#include <string.h>

#include "hertz.h"
#include "jkr.h"

static const adem_law normal_laws[] = {
#define ADEM_X(ID, nm, kernel, hist, req, pp, prm, eq, dc) {ADEM_SLOT_NORMAL, ID, nm, hist, req, pp, prm, eq, dc},
    ADEM_NORMAL_LAWS(ADEM_X)
#undef ADEM_X
};
static const adem_law damping_laws[] = {
#define ADEM_X(ID, nm, kernel, hist, req, pp, prm, eq, dc) {ADEM_SLOT_DAMPING, ID, nm, hist, req, pp, prm, eq, dc},
    ADEM_DAMPING_LAWS(ADEM_X)
#undef ADEM_X
};
static const adem_law tangential_laws[] = {
#define ADEM_X(ID, nm, kernel, hist, req, pp, prm, eq, dc) {ADEM_SLOT_TANGENTIAL, ID, nm, hist, req, pp, prm, eq, dc},
    ADEM_TANGENTIAL_LAWS(ADEM_X)
#undef ADEM_X
};
static const adem_law rolling_laws[] = {
#define ADEM_X(ID, nm, kernel, hist, req, pp, prm, eq, dc) {ADEM_SLOT_ROLLING, ID, nm, hist, req, pp, prm, eq, dc},
    ADEM_ROLLING_LAWS(ADEM_X)
#undef ADEM_X
};

static const adem_law_param params[] = {
#define ADEM_X(ID, key, unit, def, lo, mix, doc) {ID, key, unit, def, lo, mix, doc},
    ADEM_LAW_PARAMS(ADEM_X)
#undef ADEM_X
};

/* History is kept in three doubles per slot, four for the tangential slot (pairs.h): a row
 * cannot ask for more. */
#define ADEM_X(ID, nm, kernel, hist, req, pp, prm, eq, dc) \
  _Static_assert((hist) >= 0 && (hist) <= 3, "a law keeps at most 3 doubles of history");
ADEM_NORMAL_LAWS(ADEM_X)
ADEM_ROLLING_LAWS(ADEM_X)
#undef ADEM_X
#define ADEM_X(ID, nm, kernel, hist, req, pp, prm, eq, dc) \
  _Static_assert((hist) >= 0 && (hist) <= 4, "a tangential law keeps at most 4 doubles of history");
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
