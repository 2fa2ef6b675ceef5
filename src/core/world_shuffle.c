/* The test-only shuffle of a world's storage: the same run in another particle order. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fpenv.h"
#include "hertz.h"
#include "history_switch.h"
#include "jkr.h"
#include "log.h"
#include "parallel.h"
#include "rng.h"
#include "step_limit.h"
#include "world_internal.h"
#include "world_parts.h"
#include "cylinder.h"
#include "mesh_periodic.h"

/* A random permutation of 0 .. n-1 (Fisher-Yates; the modulo's bias does not matter here). */
static void random_permutation(size_t *perm, size_t n, adem_rng *r) {
  for (size_t k = 0; k < n; ++k) perm[k] = k;
  for (size_t k = n; k > 1; --k) {
    size_t j = (size_t)(adem_rng_next(r) % k), t = perm[k - 1];
    perm[k - 1] = perm[j];
    perm[j] = t;
  }
}

adem_status adem_world_shuffle_storage(adem_world *w, uint64_t seed, adem_error *err) {
  if (w->admit_pending)
    return adem_error_set(err, ADEM_ERR_INPUT, "particles wait to be admitted: step first");
  adem_particles *p = &w->p;
  adem_mesh_pairs *pm = &w->pm;
  size_t n = p->n, m = w->pp.n;
  if (w->pw.n > m) m = w->pw.n;
  if (pm->l.n > m) m = pm->l.n;
  size_t *perm = malloc((n + 1) * sizeof *perm), *inv = malloc((n + 1) * sizeof *inv);
  size_t *pairs = malloc((m + 1) * sizeof *pairs), *start = malloc((n + 1) * sizeof *start);
  adem_status st = perm && inv && pairs && start ? ADEM_OK : ADEM_ERR_NOMEM;
  adem_rng r = adem_rng_seed(seed);
  if (!st) {
    random_permutation(perm, n, &r);
    for (size_t k = 0; k < n; ++k) inv[perm[k]] = k;
    st = adem_particles_permute(p, perm);
  }
  adem_pair_list *lists[2] = {&w->pp, &w->pw};
  for (int s = 0; s < 2 && !st; ++s) {
    adem_pair_list *l = lists[s];
    random_permutation(pairs, l->n, &r);
    st = adem_pairs_permute(l, pairs);
    for (size_t k = 0; k < l->n && !st; ++k) {
      l->a[k] = (uint32_t)inv[l->a[k]];
      if (s == 0) l->b[k] = (uint32_t)inv[l->b[k]]; /* a keeps the lower id */
    }
  }
  /* mesh slots: each particle's range moves with it, its slots in their order */
  if (!st && pm->start && pm->l.n > 0) {
    size_t q = 0;
    start[0] = 0;
    for (size_t k = 0; k < n; ++k) {
      for (size_t e = pm->start[perm[k]]; e < pm->start[perm[k] + 1]; ++e) pairs[q++] = e;
      start[k + 1] = q;
    }
    st = adem_mesh_pairs_permute(pm, pairs);
    if (!st) {
      memcpy(pm->start, start, (n + 1) * sizeof *start);
      for (size_t k = 0; k < pm->l.n; ++k) pm->l.a[k] = (uint32_t)inv[pm->l.a[k]];
    }
  }
  free(perm);
  free(inv);
  free(pairs);
  free(start);
  if (!st) st = adem_world_gather(w);
  if (st) return adem_error_set(err, st, "out of memory shuffling the particles");
  return ADEM_OK;
}
