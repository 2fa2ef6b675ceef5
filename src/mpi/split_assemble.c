/* The whole system of a split run gathered on rank 0 (or every process) for output and
 * checkpoints, every particle and pair as the serial run has them (split_parts.h). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "split_parts.h"

/* A mesh slot for the assembly: its particle's id, its place in the particle's range, its
 * triangle and key; then the pair record (adem_split_put_pair). */
typedef struct mesh_head {
  uint64_t id;
  uint32_t seq, owner;
  uint64_t key;
} mesh_head;

typedef struct mesh_slot_ref {
  uint64_t id;
  uint32_t seq;
  const unsigned char *at;
} mesh_slot_ref;

static int compare_mesh_slot(const void *x, const void *y) {
  const mesh_slot_ref *a = x, *b = y;
  if (a->id != b->id) return a->id < b->id ? -1 : 1;
  return a->seq < b->seq ? -1 : a->seq > b->seq;
}

/* The gathered mesh slots into pm of the whole (its n particles stored by id: map), each
 * particle's range in its order. */
static adem_status put_mesh_slots(adem_mesh_pairs *pm, const bytes *in, const id_index *map,
                                  size_t n, bool bal) {
  size_t rec = sizeof(mesh_head) + adem_split_pair_bytes(bal), m = in->n / rec;
  mesh_slot_ref *r = malloc((m + 1) * sizeof *r);
  if (!r) return ADEM_ERR_NOMEM;
  for (size_t k = 0; k < m; ++k) {
    mesh_head h;
    memcpy(&h, in->d + k * rec, sizeof h);
    r[k] = (mesh_slot_ref){h.id, h.seq, in->d + k * rec};
  }
  qsort(r, m, sizeof *r, compare_mesh_slot);
  adem_status st = adem_pairs_keep_balance(&pm->l, bal);
  if (!st) st = adem_pairs_reserve(&pm->l, m);
  if (!st) st = adem_mesh_pairs_reserve(pm);
  if (!st) {
    pm->l.n = m;
    memset(pm->start, 0, (n + 1) * sizeof *pm->start);
    for (size_t k = 0; k < m; ++k) {
      mesh_head h;
      memcpy(&h, r[k].at, sizeof h);
      uint64_t ka, kb;
      adem_split_get_pair(&pm->l, k, r[k].at + sizeof h, &ka, &kb, bal);
      size_t i = adem_split_find_id(map, n, ka);
      if (i == SIZE_MAX) {
        st = ADEM_ERR_RUNTIME;
        break;
      }
      pm->l.a[k] = (uint32_t)i;
      pm->l.b[k] = (uint32_t)kb;
      pm->key[k] = h.key;
      pm->owner[k] = h.owner;
      pm->start[i + 1]++;
    }
    for (size_t i = 0; i < n; ++i) pm->start[i + 1] += pm->start[i];
  }
  free(r);
  return st;
}

/* The walls' state (servo positions and speeds, the meshes' reference points) from one world
 * into another of the same set-up, as a checkpoint carries it. */
static adem_status copy_wall_state(const adem_world *from, adem_world *to) {
  bytes b = {0};
  adem_writer wr = adem_writer_make(adem_split_mem_sink, &b);
  adem_walls_save_state(&wr, &from->walls);
  adem_reader rd = {b.d, b.d + b.n, 0};
  if (!wr.failed) adem_walls_load_state(&rd, &to->walls);
  adem_status st = wr.failed || rd.failed ? ADEM_ERR_NOMEM : ADEM_OK;
  free(b.d);
  return st;
}

adem_status adem_split_assemble(adem_split *s, const adem_world *local, adem_world *whole,
                                bool everywhere, adem_error *err) {
  const adem_particles *p = &local->p;
  bool bal = local->energy_balance; /* the pairs carry their balance records (pairs.h) */
  bytes mine[4] = {{0}, {0}, {0}, {0}}, in[4] = {{0}, {0}, {0}, {0}};
  adem_status st = ADEM_OK;
  const adem_mesh_pairs *lpm = &local->pm;
  for (size_t i = 0; i < p->n && lpm->start && !st; ++i) { /* every mesh slot of its own */
    if (owner(s, p, i) != s->rank) continue;
    for (size_t k = lpm->start[i]; k < lpm->start[i + 1] && !st; ++k) {
      mesh_head h;
      memset(&h, 0, sizeof h);
      h = (mesh_head){p->id[i], (uint32_t)(k - lpm->start[i]), lpm->owner[k], lpm->key[k]};
      if (!adem_split_bytes_put(&mine[3], &h, sizeof h) ||
          !adem_split_put_pair(&mine[3], &lpm->l, k, p->id[i], lpm->l.b[k], bal))
        st = ADEM_ERR_NOMEM;
    }
  }
  for (size_t i = 0; i < p->n && !st; ++i)
    if (owner(s, p, i) == s->rank && !adem_split_put_particle(&mine[0], p, i)) st = ADEM_ERR_NOMEM;
  for (size_t k = 0; k < local->pp.n && !st; ++k)
    if (owner(s, p, local->pp.a[k]) == s->rank &&
        !adem_split_put_pair(&mine[1], &local->pp, k, p->id[local->pp.a[k]],
                             p->id[local->pp.b[k]], bal))
      st = ADEM_ERR_NOMEM;
  for (size_t k = 0; k < local->pw.n && !st; ++k)
    if (owner(s, p, local->pw.a[k]) == s->rank &&
        !adem_split_put_pair(&mine[2], &local->pw, k, p->id[local->pw.a[k]], local->pw.b[k], bal))
      st = ADEM_ERR_NOMEM;
  if (st) st = adem_error_set(err, st, "out of memory gathering the particles");
  st = adem_split_agree(s, st, err);
  for (int k = 0; k < 4 && !st; ++k)
    st = everywhere ? adem_split_allgather(s, &mine[k], &in[k], err)
                    : adem_split_gather(s, &mine[k], &in[k], err);
  if (!st && (everywhere || s->rank == 0)) {
    adem_particles *q = &whole->p;
    size_t rec = adem_split_particle_bytes(), n = in[0].n / rec;
    uint32_t *order = malloc((n + 1) * sizeof *order);
    size_t *perm = malloc((n + 1) * sizeof *perm);
    if (!order || !perm || adem_particles_reserve(q, n)) st = ADEM_ERR_NOMEM;
    if (!st) {
      q->n = n;
      for (size_t i = 0; i < n && !st; ++i)
        if (!adem_split_get_particle(q, i, in[0].d + i * rec)) st = ADEM_ERR_NOMEM;
      if (!st) st = adem_particles_id_order(q, order); /* stored by id, as a serial world starts */
    }
    for (size_t i = 0; i < n && !st; ++i) perm[i] = order[i];
    if (!st) st = adem_particles_permute(q, perm);
    free(order);
    free(perm);
    id_index *map = st ? NULL : malloc((n + 1) * sizeof *map);
    if (!st && !map) st = ADEM_ERR_NOMEM;
    for (size_t i = 0; i < n && !st; ++i) map[i] = (id_index){q->id[i], (uint32_t)i};
    adem_pair_list *lists[2] = {&whole->pp, &whole->pw};
    size_t prec = adem_split_pair_bytes(bal);
    for (int l = 0; l < 2 && !st; ++l) {
      adem_pair_list *L = lists[l];
      size_t m = in[l + 1].n / prec;
      if (adem_pairs_keep_balance(L, bal) || adem_pairs_reserve(L, m)) {
        st = ADEM_ERR_NOMEM;
        break;
      }
      L->n = m;
      adem_pairs_free_slots(L);
      for (size_t k = 0; k < m; ++k) {
        uint64_t ka, kb;
        adem_split_get_pair(L, k, in[l + 1].d + k * prec, &ka, &kb, bal);
        L->a[k] = (uint32_t)adem_split_find_id(map, n, ka);
        L->b[k] = l == 0 ? (uint32_t)adem_split_find_id(map, n, kb) : (uint32_t)kb;
      }
    }
    adem_mesh_pairs *pm = &whole->pm;
    if (!st && pm->start_cap < n + 1) {
      size_t *z = realloc(pm->start, (n + 1) * sizeof *z);
      if (!z) st = ADEM_ERR_NOMEM;
      else {
        pm->start = z;
        pm->start_cap = n + 1;
      }
    }
    if (!st) st = put_mesh_slots(pm, &in[3], map, n, bal);
    free(map);
    if (!st) {
      whole->time = local->time;
      whole->step = local->step;
      whole->nb.skin = local->nb.skin;
      whole->nb.rebuilds = local->nb.rebuilds;
      whole->nb.time_at_build = local->nb.time_at_build;
      st = copy_wall_state(local, whole); /* servos: every process moves them alike */
      adem_world_place_walls(whole, local->time);
      if (!st) st = adem_world_gather(whole);
    }
    if (st) st = adem_error_set(err, st, "out of memory gathering the particles");
  }
  for (int k = 0; k < 4; ++k) {
    free(mine[k].d);
    free(in[k].d);
  }
  st = adem_split_agree(s, st, err);
  if (!st && local->walls.mesh.ntris > 0)
    st = adem_split_face_loads(s, local, everywhere || s->rank == 0 ? &whole->walls : NULL,
                               everywhere, err);
  return adem_split_agree(s, st, err);
}
