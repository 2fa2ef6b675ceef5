/* Removing particles from a running world (outlets): the particles go, with every candidate pair
 * and mesh slot they are in, and the neighbour lists are built again, so that the survivors keep
 * their contacts' history (carried by id, as at any build). The energy the removed particles
 * carried leaves the balance with them. */
#include <stdlib.h>
#include <string.h>

#include "world_internal.h"

enum { GONE = SIZE_MAX };

/* Keeps the pairs of l whose particles stay, in their order, with indices renumbered by inv;
 * b is a particle (particle pairs) or a wall index. */
static adem_status keep_pairs(adem_pair_list *l, const size_t *inv, bool b_is_particle,
                              size_t *scratch) {
  size_t m = 0;
  for (size_t k = 0; k < l->n; ++k)
    if (inv[l->a[k]] != GONE && (!b_is_particle || inv[l->b[k]] != GONE)) scratch[m++] = k;
  l->n = m;
  adem_status st = adem_pairs_permute(l, scratch);
  for (size_t k = 0; k < m && !st; ++k) {
    l->a[k] = (uint32_t)inv[l->a[k]];
    if (b_is_particle) l->b[k] = (uint32_t)inv[l->b[k]];
  }
  return st;
}

adem_status adem_world_remove_particles(adem_world *w, const uint8_t *gone, size_t *removed,
                                        adem_error *err) {
  adem_particles *p = &w->p;
  size_t n = p->n, kept = 0;
  if (removed) *removed = 0;
  for (size_t i = 0; i < n; ++i) kept += gone[i] ? 0 : 1;
  if (kept == n) return ADEM_OK; /* nothing to do: no build either */
  if (w->admit_pending)
    return adem_error_set(err, ADEM_ERR_INPUT, "particles wait to be admitted: step first");
  adem_pair_list *lists[3] = {&w->pp, &w->pw, &w->pm.l};
  size_t m = 1;
  for (int s = 0; s < 3; ++s) m = lists[s]->n > m ? lists[s]->n : m;
  size_t *perm = malloc((n + 1) * sizeof *perm), *inv = malloc((n + 1) * sizeof *inv);
  size_t *scratch = malloc((m + 1) * sizeof *scratch), *start = malloc((n + 1) * sizeof *start);
  adem_status st = perm && inv && scratch && start ? ADEM_OK : ADEM_ERR_NOMEM;
  /* the balance before: what the removed particles (and their contacts) held leaves with them */
  adem_diagnostics before = adem_world_diagnostics(w);
  if (!st) {
    size_t q = 0;
    for (size_t i = 0; i < n; ++i) {
      inv[i] = gone[i] ? GONE : q;
      if (!gone[i]) perm[q++] = i;
    }
    st = keep_pairs(&w->pp, inv, true, scratch);
    if (!st) st = keep_pairs(&w->pw, inv, false, scratch);
  }
  /* mesh slots: a kept particle's range moves with it, in its order */
  adem_mesh_pairs *pm = &w->pm;
  if (!st && pm->start && pm->l.n > 0) {
    size_t q = 0;
    start[0] = 0;
    for (size_t k = 0; k < kept; ++k) {
      for (size_t e = pm->start[perm[k]]; e < pm->start[perm[k] + 1]; ++e) scratch[q++] = e;
      start[k + 1] = q;
    }
    pm->l.n = q;
    st = adem_mesh_pairs_permute(pm, scratch);
    if (!st) {
      memcpy(pm->start, start, (kept + 1) * sizeof *start);
      for (size_t k = 0; k < q; ++k) pm->l.a[k] = (uint32_t)inv[pm->l.a[k]];
    }
  } else if (!st && pm->start) {
    memset(pm->start, 0, (kept + 1) * sizeof *pm->start);
  }
  if (!st) {
    p->n = kept;
    st = adem_soa_permute(p, adem_particles_layout(), kept, perm);
  }
  free(perm);
  free(inv);
  free(scratch);
  free(start);
  if (st) return adem_error_set(err, st, "out of memory removing particles");
  st = adem_world_build_neighbors(w, err);
  if (st) return st;
  /* balance_error = E + D - E0 - W stays what it was: E0 loses what left */
  adem_diagnostics after = adem_world_diagnostics(w);
  double e_before = before.kinetic + before.rotational + before.potential + before.elastic;
  double e_after = after.kinetic + after.rotational + after.potential + after.elastic;
  if (w->energy_balance)
    w->energy_initial += (e_after - e_before) + (after.dissipated - before.dissipated) -
                         (after.wall_work - before.wall_work);
  else
    w->energy_initial += e_after - e_before;
  if (removed) *removed = n - kept;
  return ADEM_OK;
}
