/* The run's time estimate from its recent rate (adem/run.h). */
#include <string.h>

#include "adem/run.h"

void adem_eta_init(adem_eta *e) { memset(e, 0, sizeof *e); }

static int at(const adem_eta *e, int k) { return (e->head + k) % ADEM_ETA_SAMPLES; }

void adem_eta_add(adem_eta *e, double wall_seconds, uint64_t step, size_t contacts,
                  size_t particles) {
  if (e->n == ADEM_ETA_SAMPLES) { /* full: the oldest goes */
    e->head = at(e, 1);
    e->n--;
  }
  int k = at(e, e->n++);
  e->wall[k] = wall_seconds;
  e->step[k] = step;
  e->contacts[k] = (double)contacts;
  e->particles[k] = (double)particles;
  /* Keep one sample at or before the window's start, so that the rate spans the whole window. */
  while (e->n > 2 && e->wall[at(e, 1)] <= wall_seconds - ADEM_ETA_WINDOW) {
    e->head = at(e, 1);
    e->n--;
  }
}

double adem_eta_rate(const adem_eta *e) {
  if (e->n < 2) return 0.0;
  int a = at(e, 0), b = at(e, e->n - 1);
  double dt = e->wall[b] - e->wall[a];
  if (!(dt > 0.0) || e->step[b] <= e->step[a]) return 0.0;
  return (double)(e->step[b] - e->step[a]) / dt;
}

double adem_eta_seconds(const adem_eta *e, uint64_t total_steps, int *rough) {
  if (rough) *rough = ADEM_ETA_STARTING;
  double rate = adem_eta_rate(e);
  if (!(rate > 0.0)) return -1.0;
  int a = at(e, 0), b = at(e, e->n - 1);
  if (rough) {
    if (e->wall[b] - e->wall[a] < ADEM_ETA_SETTLING) *rough = ADEM_ETA_STARTING;
    else if (e->particles[b] > e->particles[a] * (1.0 + ADEM_ETA_GROWTH))
      *rough = ADEM_ETA_PARTICLES;
    else if (e->contacts[b] > e->contacts[a] * (1.0 + ADEM_ETA_GROWTH) + 10.0)
      *rough = ADEM_ETA_CONTACTS;
    else *rough = ADEM_ETA_STEADY;
  }
  uint64_t left = total_steps > e->step[b] ? total_steps - e->step[b] : 0;
  return (double)left / rate;
}
