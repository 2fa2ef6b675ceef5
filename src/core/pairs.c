/* Flat arrays of candidate contacts and their history. */
#include <stdlib.h>
#include <string.h>

#include "world.h"

#define GROW(field)                                                    \
  do {                                                                 \
    void *q = realloc(l->field, cap * sizeof *l->field);               \
    if (!q) return ADEM_ERR_NOMEM;                                     \
    l->field = q;                                                      \
  } while (0)

adem_status adem_pair_list_reserve(adem_pair_list *l, size_t cap) {
  if (cap <= l->cap) return ADEM_OK;
  cap = cap + cap / 4 + 16; /* headroom: the list is rebuilt often with similar sizes */
  GROW(a);
  GROW(b);
  GROW(hist);
  GROW(touching);
  GROW(force_a);
  GROW(torque_a);
  GROW(torque_b);
  GROW(rolling_a);
  GROW(rolling_capacity);
  GROW(elastic);
  GROW(overlap_ratio);
  l->cap = cap;
  return ADEM_OK;
}

void adem_pair_list_free(adem_pair_list *l) {
  free(l->a);
  free(l->b);
  free(l->hist);
  free(l->touching);
  free(l->force_a);
  free(l->torque_a);
  free(l->torque_b);
  free(l->rolling_a);
  free(l->rolling_capacity);
  free(l->elastic);
  free(l->overlap_ratio);
  memset(l, 0, sizeof *l);
}

#define GROW_PM(field)                                                 \
  do {                                                                 \
    void *q = realloc(pm->field, cap * sizeof *pm->field);             \
    if (!q) return ADEM_ERR_NOMEM;                                     \
    pm->field = q;                                                     \
  } while (0)

adem_status adem_mesh_pairs_reserve(adem_mesh_pairs *pm) {
  size_t cap = pm->l.cap;
  if (cap <= pm->cap) return ADEM_OK;
  GROW_PM(key);
  GROW_PM(key_prev);
  GROW_PM(owner);
  GROW_PM(hist_prev);
  GROW_PM(touching_prev);
  GROW_PM(found);
  pm->cap = cap;
  return ADEM_OK;
}

void adem_mesh_pairs_free(adem_mesh_pairs *pm) {
  adem_pair_list_free(&pm->l);
  free(pm->start);
  free(pm->key);
  free(pm->key_prev);
  free(pm->owner);
  free(pm->hist_prev);
  free(pm->touching_prev);
  free(pm->found);
  memset(pm, 0, sizeof *pm);
}
