/* Bit-for-bit comparison of two worlds by particle id (storage orders differ): every particle
 * field, every contact, the diagnostics and the plane forces. Returns NULL when they are the
 * same, else what differs first (in a static buffer). */
#ifndef ADEM_TEST_SPLIT_COMPARE_H
#define ADEM_TEST_SPLIT_COMPARE_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "world_internal.h"

static char split_compare_why[256];

static const char *split_differs(const char *what, unsigned long long id) {
  snprintf(split_compare_why, sizeof split_compare_why, "%s (id %llu)", what, id);
  return split_compare_why;
}

static int split_compare_contact(const void *x, const void *y) {
  const adem_contact_info *a = x, *b = y;
  if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
  if (a->a != b->a) return a->a < b->a ? -1 : 1;
  return a->b < b->b ? -1 : a->b > b->b;
}

static adem_contact_info *split_contacts(const adem_world *w, size_t *n) {
  *n = adem_world_contacts(w, NULL, 0);
  adem_contact_info *c = calloc(*n + 1, sizeof *c); /* zeroed padding: compared with memcmp */
  if (!c) return NULL;
  adem_world_contacts(w, c, *n);
  qsort(c, *n, sizeof *c, split_compare_contact);
  return c;
}

/* the same ids in both (0 .. n-1, or fewer once an outlet has removed some) */
static const char *split_compare(const adem_world *a, const adem_world *b) {
  const adem_particles *p = &a->p, *q = &b->p;
  if (a->step != b->step) return split_differs("step", 0);
  if (p->n != q->n) return split_differs("particle count", p->n);
  size_t n = p->n;
  uint32_t *ia = malloc((n + 1) * sizeof *ia), *ib = malloc((n + 1) * sizeof *ib);
  const char *why = ia && ib ? NULL : "out of memory";
  if (!why && (adem_particles_id_order(p, ia) || adem_particles_id_order(q, ib))) why = "out of memory";
  for (size_t r = 0; r < n && !why; ++r)
    if (p->id[ia[r]] != q->id[ib[r]]) why = split_differs("particle ids", p->id[ia[r]]);
  adem_soa_layout L = adem_particles_layout();
  static const char zeros[64]; /* an absent optional field reads as zeros (particles.h) */
  for (size_t f = 0; f < L.count && !why; ++f) {
    const char *x = *(char *const *)((const char *)p + L.fields[f].offset);
    const char *y = *(char *const *)((const char *)q + L.fields[f].offset);
    size_t e = L.fields[f].elem;
    for (size_t id = 0; id < n && !why; ++id)
      if (memcmp(x ? x + ia[id] * e : zeros, y ? y + ib[id] * e : zeros, e) != 0)
        why = split_differs(L.fields[f].name, id);
  }
  free(ia);
  free(ib);
  if (why) return why;
  size_t na = 0, nb = 0;
  adem_contact_info *ca = split_contacts(a, &na), *cb = split_contacts(b, &nb);
  if (!ca || !cb) why = "out of memory";
  else if (na != nb) why = split_differs("contact count", na);
  for (size_t k = 0; k < na && !why; ++k)
    if (memcmp(&ca[k], &cb[k], sizeof ca[k]) != 0) why = split_differs("contact of", ca[k].a);
  free(ca);
  free(cb);
  if (why) return why;
  adem_diagnostics da = adem_world_diagnostics(a), db = adem_world_diagnostics(b);
  da.time = db.time; /* compared as step above */
  if (memcmp(&da, &db, sizeof da) != 0) return split_differs("diagnostics", 0);
  adem_vec3 fa[32], fb[32];
  int np = a->walls.nplanes < 32 ? a->walls.nplanes : 32;
  if (np > 0) {
    adem_world_plane_forces(a, fa);
    adem_world_plane_forces(b, fb);
    if (memcmp(fa, fb, (size_t)np * sizeof *fa) != 0) return split_differs("plane forces", 0);
  }
  return NULL;
}

#endif
