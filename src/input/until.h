/* Run-until conditions (time.until, stages[].until): a run, or a stage, ends at the first check
 * where every condition it gives has held for `for` seconds:
 *   - kinetic energy per particle: (translational + rotational kinetic energy) / particles below
 *     a threshold;
 *   - wall load: a named wall's force along a direction steady within a relative tolerance (its
 *     largest and smallest value since the streak began differ by at most tolerance x the
 *     larger magnitude; a wall that carries nothing is not steady).
 * Checks fall on fixed steps (multiples of round(interval / dt)) and the state between them (the
 * step each streak began, the load's range) is kept in checkpoints, so that where a run ends
 * is the same for any thread count and across restarts. No condition counts while a pour still
 * has particles to insert. */
#ifndef ADEM_UNTIL_H
#define ADEM_UNTIL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/case.h"
#include "adem/world.h"
#include "stream.h"

typedef enum adem_until_wall_kind {
  ADEM_UNTIL_PLANE = 0,
  ADEM_UNTIL_MESH_GROUP = 1,
  ADEM_UNTIL_MESH_WALL = 2 /* a file of several groups: their total */
} adem_until_wall_kind;

typedef struct adem_until_def {
  double kinetic;       /* J per particle; <= 0: no such condition */
  double kinetic_ratio; /* kinetic energy over sum m |g| d; <= 0: no such condition */
  bool load;            /* a wall-load condition is given */
  char wall[ADEM_NAME_MAX];
  adem_until_wall_kind wall_kind;
  int wall_index;
  adem_vec3 direction; /* unit */
  double tolerance;    /* relative */
  double hold;         /* s every condition must hold (`for`) */
  double interval;     /* s between checks */
} adem_until_def;

typedef struct adem_until {
  adem_until_def def;
  /* state */
  uint64_t kinetic_since;       /* first check of the current streak below the threshold */
  uint64_t load_since;          /* first check of the current steady streak */
  double load_lo, load_hi;      /* the load's range over that streak */
  double kinetic_now, load_now; /* at the last check (for messages) */
  double ratio_now;             /* kinetic energy over sum m |g| d at the last check */
  bool checked;                 /* a check has run since the condition (or its stage) began */
  uint64_t met_step;            /* step it was met at; UINT64_MAX: not (yet) */
} adem_until;

#define ADEM_UNTIL_NEVER UINT64_MAX

/* A fresh condition of def (state reset). */
void adem_until_init(adem_until *u, const adem_until_def *def);
/* Forgets the streaks (a stage begins). */
void adem_until_reset(adem_until *u);
/* Steps between checks: round(interval / dt), at least 1. */
uint64_t adem_until_period(const adem_until *u, double dt);
/* Smallest check step > step. */
uint64_t adem_until_next_check(const adem_until *u, double dt, uint64_t step);
/* At a check step (a multiple of the period), evaluates the conditions on the world and updates
 * the streaks; true (and met_step set) when every condition has held for `for`. waiting: a pour
 * still has particles to insert (nothing counts yet). */
bool adem_until_check(adem_until *u, const adem_world *w, bool waiting);
/* "kinetic energy per particle 8.1e-08 J < 1e-07 J and the load on `floor` steady within 1 %
 * (2.48 N), for 0.2 s" */
void adem_until_describe(const adem_until *u, char *buf, size_t n);
/* The conditions against their thresholds at the last check, short, for the progress line:
 * "until: E_k 4.1e-10 > 1e-10 J/particle" or "... held 0.05/0.2 s". */
void adem_until_status(const adem_until *u, double dt, uint64_t step, char *buf, size_t n);
/* The conditions in words for `adem check`. */
void adem_until_summary(const adem_until *u, char *buf, size_t n);

void adem_until_save(adem_writer *wr, const adem_until *u);
void adem_until_load(adem_reader *rd, adem_until *u);

#endif
