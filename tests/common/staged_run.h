/* Drives a case step by step as adem_run does (chunks end where a stage begins or a pour batch is
 * due; the events of a step follow it), for tests that look at the world between events. */
#ifndef ADEM_TEST_STAGED_RUN_H
#define ADEM_TEST_STAGED_RUN_H

#include "adem/adem.h"
#include "schedule.h"
#include "stages.h"
#include "world_internal.h"

/* Prepares the world and runs the events of step 0 (pour batches due then). */
static inline adem_status staged_start(adem_case *c, adem_error *err) {
  adem_status st = adem_world_prepare(c->world, err);
  return st ? st : adem_stages_events(c, err);
}

/* Steps to `until` in chunks of at most `chunk` steps, handling each step's events. */
static inline adem_status staged_advance(adem_case *c, uint64_t until, uint64_t chunk,
                                         adem_error *err) {
  adem_world *w = c->world;
  while (w->step < until) {
    uint64_t next = adem_stages_next_step(c, w->step);
    if (next > until) next = until;
    if (next > w->step + chunk) next = w->step + chunk;
    adem_status st = adem_world_step(w, next - w->step, err);
    if (!st) st = adem_stages_events(c, err);
    if (st) return st;
  }
  return ADEM_OK;
}

#endif
