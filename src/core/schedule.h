/* How a run turns times into step counts. Shared by the runner and `adem check`, so that what
 * check announces is what run does. */
#ifndef ADEM_SCHEDULE_H
#define ADEM_SCHEDULE_H

#include <math.h>
#include <stdint.h>

/* Steps needed to reach t_end: the last step may end slightly past it, never short of it
 * (beyond rounding noise). */
static inline uint64_t adem_schedule_total_steps(double t_end, double dt) {
  if (!(t_end > 0.0) || !(dt > 0.0)) return 0;
  double n = ceil(t_end / dt - 1e-9);
  return n < 1.0 ? 1 : (uint64_t)n;
}

/* Steps between two events of an output with this interval: round(interval/dt), at least 1;
 * 0 when the output is off. */
static inline uint64_t adem_schedule_period(double interval, double dt) {
  if (!(interval > 0.0) || !(dt > 0.0)) return 0;
  double k = round(interval / dt);
  return k < 1.0 ? 1 : (uint64_t)k;
}

/* Number of events of a period over a run of total steps: steps 0, k, 2k, ... and the last. */
static inline uint64_t adem_schedule_count(uint64_t period, uint64_t total) {
  if (period == 0) return 0;
  return total / period + 1 + (total % period != 0);
}

#endif
