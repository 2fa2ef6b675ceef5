/* The walls' loads of a split system on every process (or rank 0), bit for bit the serial sums:
 * plane forces, mesh groups' forces and torques, and the servos' sums of terms by id
 * (split_parts.h). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "split_parts.h"

/* A wall contact's share of a plane force: the particle's id and the contact's place in its
 * gather list (the order the serial sum takes them in). */
typedef struct wall_term {
  uint64_t id;
  uint32_t seq, wall;
  adem_vec3 f;
} wall_term;

static int compare_wall_term(const void *x, const void *y) {
  const wall_term *a = x, *b = y;
  if (a->id != b->id) return a->id < b->id ? -1 : 1;
  return a->seq < b->seq ? -1 : a->seq > b->seq;
}

/* The plane forces of the whole system on every process, the serial sum's bits: every process
 * sends every process its own particles' wall contact forces, and each sums all of them in the
 * serial order (particles by id, each one's contacts as its gather list has them). An
 * MPI_Allreduce would add in another order. Collective. */
adem_status adem_split_plane_forces_hook(void *ctx, const adem_world *w, adem_vec3 *out,
                                         adem_error *err) {
  adem_split *s = ctx;
  const adem_particles *p = &w->p;
  const adem_neighbors *nb = &w->nb;
  const adem_pair_list *l = &w->pw;
  bytes mine = {0}, all = {0};
  adem_status st = ADEM_OK;
  bool alone = adem_split_break("plane_forces"); /* the test's control: this part's only */
  for (size_t i = 0; i < nb->gathered && !st; ++i) {
    if (owner(s, p, i) != s->rank) continue;
    for (size_t e = nb->pw_start[i]; e < nb->pw_start[i + 1] && !st; ++e) {
      size_t k = nb->pw_entries[e];
      wall_term t;
      memset(&t, 0, sizeof t);
      t.id = p->id[i];
      t.seq = (uint32_t)(e - nb->pw_start[i]);
      t.wall = l->b[k];
      t.f = l->res[k].force_a;
      if (!adem_split_bytes_put(&mine, &t, sizeof t)) st = ADEM_ERR_NOMEM;
    }
  }
  if (st) adem_error_set(err, st, "out of memory summing the plane forces");
  st = adem_split_agree(s, st, err);
  if (!st && alone) {
    all = mine;
    mine = (bytes){0};
  } else if (!st) {
    st = adem_split_allgather(s, &mine, &all, err);
  }
  for (int k = 0; k < w->walls.nplanes; ++k) out[k] = v3_zero();
  if (!st) {
    size_t m = all.n / sizeof(wall_term);
    wall_term *t = (wall_term *)(void *)all.d;
    qsort(t, m, sizeof *t, compare_wall_term);
    for (size_t k = 0; k < m; ++k)
      if (t[k].wall < (uint32_t)w->walls.nplanes) out[t[k].wall] = v3_sub(out[t[k].wall], t[k].f);
  }
  free(mine.d);
  free(all.d);
  return st;
}

/* A touching mesh contact's load on its face (the opposite of the particle's force, and its
 * moment about the face's group's reference point less the rolling couple), by the particle's
 * id and the contact's slot: the order of the serial sum (force_pass.c, mesh_pairs). */
typedef struct face_term {
  uint64_t id;
  uint32_t seq, tri;
  adem_vec3 f, t;
} face_term;

static int compare_face_term(const void *x, const void *y) {
  const face_term *a = x, *b = y;
  if (a->id != b->id) return a->id < b->id ? -1 : 1;
  return a->seq < b->seq ? -1 : a->seq > b->seq;
}

/* The face loads of the whole system, the serial sum's bits, into `into` (on rank 0, or on
 * every process): each process computes its own particles' terms as the serial pass does, and
 * the receivers add them all in the serial order. Collective. */
adem_status adem_split_face_loads(adem_split *s, const adem_world *w, adem_walls *into,
                                  bool everywhere, adem_error *err) {
  const adem_particles *p = &w->p;
  const adem_mesh_pairs *pm = &w->pm;
  const adem_pair_list *l = &pm->l;
  const adem_walls *wl = &w->walls;
  bytes mine = {0}, all = {0};
  adem_status st = ADEM_OK;
  for (size_t i = 0; i < p->n && pm->start && !st; ++i) {
    if (owner(s, p, i) != s->rank) continue;
    for (size_t k = pm->start[i]; k < pm->start[i + 1] && l->touching[k] && !st; ++k) {
      face_term t;
      memset(&t, 0, sizeof t);
      size_t tri = pm->owner[k];
      t.id = p->id[i];
      t.seq = (uint32_t)(k - pm->start[i]);
      t.tri = (uint32_t)tri;
      t.f = v3_neg(l->res[k].force_a);
      adem_vec3 arm = v3_sub(pm->found[k].point, wl->mesh_ref[wl->mesh.group[tri]]);
      t.t = v3_sub(v3_cross(arm, t.f), l->res[k].rolling_a);
      if (!adem_split_bytes_put(&mine, &t, sizeof t)) st = ADEM_ERR_NOMEM;
    }
  }
  if (st) adem_error_set(err, st, "out of memory summing the face loads");
  st = adem_split_agree(s, st, err);
  if (!st)
    st = everywhere ? adem_split_allgather(s, &mine, &all, err)
                    : adem_split_gather(s, &mine, &all, err);
  if (!st && into) {
    size_t m = all.n / sizeof(face_term);
    face_term *t = (face_term *)(void *)all.d;
    qsort(t, m, sizeof *t, compare_face_term);
    adem_walls_clear_face_loads(into);
    for (size_t k = 0; k < m; ++k) adem_walls_add_face_load(into, t[k].tri, t[k].f, t[k].t);
  }
  free(mine.d);
  free(all.d);
  return st;
}

/* After a force pass: the face loads the mesh servos move by, the whole system's. */
adem_status adem_split_mesh_loads_hook(void *ctx, adem_world *w, adem_error *err) {
  adem_split *s = ctx;
  if (adem_split_break("face_loads")) return ADEM_OK; /* the control of the test: this part's only */
  return adem_split_face_loads(s, w, &w->walls, true, err);
}

static int compare_id_term(const void *x, const void *y) {
  const adem_id_term *a = x, *b = y;
  if (a->id != b->id) return a->id < b->id ? -1 : 1;
  return a->seq < b->seq ? -1 : a->seq > b->seq;
}

/* Sums of terms over every process's own particles, in the serial order (id, then seq), on
 * every process. Collective. */
adem_status adem_split_sum_terms_hook(void *ctx, const adem_world *w, const adem_id_term *t,
                                      size_t n, double *out, int nout, adem_error *err) {
  adem_split *s = ctx;
  bytes mine = {0}, all = {0};
  adem_status st = ADEM_OK;
  for (size_t k = 0; k < n && !st; ++k)
    if (owner(s, &w->p, t[k].i) == s->rank && !adem_split_bytes_put(&mine, &t[k], sizeof t[k]))
      st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  st = adem_split_agree(s, st, err);
  if (!st) st = adem_split_allgather(s, &mine, &all, err);
  for (int k = 0; k < nout; ++k) out[k] = 0.0;
  if (!st) {
    size_t m = all.n / sizeof(adem_id_term);
    adem_id_term *a = (adem_id_term *)(void *)all.d;
    qsort(a, m, sizeof *a, compare_id_term);
    for (size_t k = 0; k < m; ++k)
      if (a[k].slot < (uint32_t)nout) out[a[k].slot] += a[k].v;
  }
  free(mine.d);
  free(all.d);
  return st;
}
