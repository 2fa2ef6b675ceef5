/* Per-particle arrays: growth and reordering. */
#include <stdlib.h>
#include <string.h>

#include "world.h"

#define GROW(field)                                                    \
  do {                                                                 \
    void *q = realloc(p->field, cap * sizeof *p->field);               \
    if (!q) return ADEM_ERR_NOMEM;                                     \
    p->field = q;                                                      \
  } while (0)

adem_status adem_particles_reserve(adem_particles *p, size_t cap) {
  if (cap <= p->cap) return ADEM_OK;
  GROW(pos);
  GROW(vel);
  GROW(omega);
  GROW(force);
  GROW(torque);
  GROW(radius);
  GROW(inv_mass);
  GROW(inv_inertia);
  GROW(id);
  GROW(material);
  GROW(group);
  GROW(pos_at_build);
  GROW(rolling_torque);
  GROW(held);
  GROW(path_length);
  p->cap = cap;
  return ADEM_OK;
}

void adem_particles_free(adem_particles *p) {
  free(p->pos);
  free(p->vel);
  free(p->omega);
  free(p->force);
  free(p->torque);
  free(p->radius);
  free(p->inv_mass);
  free(p->inv_inertia);
  free(p->id);
  free(p->material);
  free(p->group);
  free(p->pos_at_build);
  free(p->rolling_torque);
  free(p->held);
  free(p->path_length);
  memset(p, 0, sizeof *p);
}

/* Gathers one array through perm using scratch of at least n elements of the same size. */
static void permute_array(void *array, size_t elem, size_t n, const size_t *perm, void *scratch) {
  char *src = array, *dst = scratch;
  for (size_t k = 0; k < n; ++k) memcpy(dst + k * elem, src + perm[k] * elem, elem);
  memcpy(array, scratch, n * elem);
}

adem_status adem_particles_permute(adem_particles *p, const size_t *perm) {
  size_t n = p->n;
  void *scratch = malloc(n * sizeof(adem_vec3) + 1);
  if (!scratch) return ADEM_ERR_NOMEM;
  permute_array(p->pos, sizeof *p->pos, n, perm, scratch);
  permute_array(p->vel, sizeof *p->vel, n, perm, scratch);
  permute_array(p->omega, sizeof *p->omega, n, perm, scratch);
  permute_array(p->force, sizeof *p->force, n, perm, scratch);
  permute_array(p->torque, sizeof *p->torque, n, perm, scratch);
  permute_array(p->radius, sizeof *p->radius, n, perm, scratch);
  permute_array(p->inv_mass, sizeof *p->inv_mass, n, perm, scratch);
  permute_array(p->inv_inertia, sizeof *p->inv_inertia, n, perm, scratch);
  permute_array(p->id, sizeof *p->id, n, perm, scratch);
  permute_array(p->material, sizeof *p->material, n, perm, scratch);
  permute_array(p->group, sizeof *p->group, n, perm, scratch);
  permute_array(p->pos_at_build, sizeof *p->pos_at_build, n, perm, scratch);
  permute_array(p->rolling_torque, sizeof *p->rolling_torque, n, perm, scratch);
  permute_array(p->path_length, sizeof *p->path_length, n, perm, scratch);
  free(scratch);
  return ADEM_OK;
}
