/* The bitwise tests' case, tests/cases/settle.yaml: 300 frictional spheres of mixed sizes falling
 * into a box and settling, 2000 steps (the file says why so), and the comparison of two runs'
 * states bit for bit. Include after cmocka.h. */
#ifndef ADEM_TEST_SETTLE_CASE_H
#define ADEM_TEST_SETTLE_CASE_H

#include <string.h>

#include "adem/adem.h"
#include "case_file.h"
#include "world_internal.h"

#define SETTLE_STEPS 2000

/* The case's text (tests/cases/settle.yaml); settle_load loads it with overrides. */
#define settle_case case_file_text("settle")
#define settle_load(sets, nsets) case_file_load("settle", sets, nsets)

/* Bit-for-bit equality of everything that carries the motion forward. */
static inline int settle_same_state(const adem_world *a, const adem_world *b, const char **what) {
  const adem_particles *p = &a->p, *q = &b->p;
  size_t n = p->n;
#define SAME(cond, name) \
  if (!(cond)) {         \
    *what = name;        \
    return 0;            \
  }
  SAME(n == q->n, "particle count");
  SAME(a->step == b->step, "step");
  SAME(memcmp(&a->time, &b->time, sizeof a->time) == 0, "time");
  SAME(memcmp(p->id, q->id, n * sizeof *p->id) == 0, "particle order (ids)");
  SAME(memcmp(p->pos, q->pos, n * sizeof *p->pos) == 0, "positions");
  SAME(memcmp(p->vel, q->vel, n * sizeof *p->vel) == 0, "velocities");
  SAME(memcmp(p->omega, q->omega, n * sizeof *p->omega) == 0, "angular velocities");
  SAME(memcmp(p->force, q->force, n * sizeof *p->force) == 0, "forces");
  SAME(memcmp(p->torque, q->torque, n * sizeof *p->torque) == 0, "torques");
  const adem_pair_list *la[2] = {&a->pp, &a->pw}, *lb[2] = {&b->pp, &b->pw};
  for (int s = 0; s < 2; ++s) {
    SAME(la[s]->n == lb[s]->n, s ? "wall pair count" : "particle pair count");
    size_t m = la[s]->n;
    if (m == 0) continue; /* no list yet: its arrays may be NULL, which memcmp must not get */
    SAME(memcmp(la[s]->a, lb[s]->a, m * sizeof *la[s]->a) == 0 &&
             memcmp(la[s]->b, lb[s]->b, m * sizeof *la[s]->b) == 0,
         s ? "wall pairs" : "particle pairs");
    bool same_hist = true; /* by pair: a slot's number is the threads' order of taking it */
    for (size_t k = 0; k < m && same_hist; ++k)
      same_hist = memcmp(&la[s]->hist[adem_pairs_slot(la[s], k)], &lb[s]->hist[adem_pairs_slot(lb[s], k)],
                         sizeof *la[s]->hist) == 0;
    SAME(same_hist, s ? "wall contact history" : "particle contact history");
    SAME(memcmp(la[s]->touching, lb[s]->touching, m * sizeof *la[s]->touching) == 0,
         "touching flags");
  }
#undef SAME
  return 1;
}

/* Contacts whose tangential spring is loaded: the test is void without them. */
static inline size_t settle_loaded_contacts(const adem_world *w) {
  size_t k, count = 0;
  for (k = 0; k < w->pp.n; ++k)
    if (w->pp.touching[k] && w->pp.hist[adem_pairs_slot(&w->pp, k)].tangential.x != 0.0) ++count;
  for (k = 0; k < w->pw.n; ++k)
    if (w->pw.touching[k] && w->pw.hist[k].tangential.x != 0.0) ++count;
  return count;
}

#endif
