/* A system split over MPI processes in slabs (split.h). Why the results are the serial run's:
 * every pair with one of a process's own particles is on that process, between the same
 * inputs bit for bit (ghosts are copies of their owners' state), with the same history; a
 * particle sums its contacts by partner id; so its force is the serial one. */
#include "split_parts.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

bool adem_split_break(const char *what) {
  const char *b = getenv("ADEM_SPLIT_BREAK");
  return b && strcmp(b, what) == 0;
}

static bool split_broken(const char *what) { return adem_split_break(what); }

/* What a ghost takes from its owner every step. */
typedef struct ghost_state {
  adem_vec3 pos, vel, omega, force, torque;
  uint8_t held;
} ghost_state;

/* A touching pair's history at a rebuild: ids (a lower), or id and plane (wall = 1), or id
 * and mesh contact key (wall = 2). */
typedef struct history_rec {
  uint64_t ka, kb, wall;
  adem_contact_history h;
} history_rec;

static int compare_history(const void *x, const void *y) {
  const history_rec *a = x, *b = y;
  if (a->wall != b->wall) return a->wall < b->wall ? -1 : 1;
  if (a->ka != b->ka) return a->ka < b->ka ? -1 : 1;
  if (a->kb != b->kb) return a->kb < b->kb ? -1 : 1;
  return 0;
}

/* ---------------------------------------------------------------- slabs */

/* Reach of a pair: the cut-off of the largest two spheres and the skin the build takes (as
 * adem_neighbors_build: skin_fraction of the largest diameter), widened a little: a copy too
 * many costs some work, one too few a wrong force. */
static double halo(const adem_split *s, const adem_world *w) {
  double skin = w->nb.skin_fraction * 2.0 * s->rmax;
  return 1.01 * (2.0 * s->rmax + skin);
}

/* Within the halo of slab q (a copy of the particle is needed there). Along a periodic axis the
 * first and the last slab end at the box's faces, and a coordinate is near a slab through its
 * images one box length away too (its copy keeps its own position: the pairs take minimum
 * images). */
static bool near_in(const adem_split *s, const double *cut, int q, double x, double h) {
  int size = s->size;
  if (!s->wraps) {
    double lo = q > 0 ? cut[q - 1] - h : -INFINITY;
    double hi = q < size - 1 ? cut[q] + h : INFINITY;
    return x > lo && x < hi;
  }
  double lo = (q > 0 ? cut[q - 1] : s->plo) - h;
  double hi = (q < size - 1 ? cut[q] : s->plo + s->plen) + h;
  for (int k = -1; k <= 1; ++k) {
    double y = x + k * s->plen;
    if (y > lo && y < hi) return true;
  }
  return false;
}

static bool near_slab(const adem_split *s, int q, double x, double h) {
  return near_in(s, s->cut, q, x, h);
}

static int compare_double(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return a < b ? -1 : a > b;
}

/* Cuts at the quantiles of n coordinates (sorted here): slabs of equal counts. */
static void quantile_cuts(double *x, size_t n, int size, double *cut) {
  qsort(x, n, sizeof *x, compare_double);
  for (int r = 1; r < size; ++r) {
    size_t k = (size_t)r * n / (size_t)size;
    cut[r - 1] = n == 0 ? 0.0 : k == 0 ? x[0]
                            : k >= n   ? x[n - 1]
                                       : 0.5 * (x[k - 1] + x[k]);
  }
}

/* ---------------------------------------------------------------- exchanges */

adem_status adem_split_too_big(adem_error *err) {
  return adem_error_set(err, ADEM_ERR_NOMEM, "an MPI message would exceed 2 GiB");
}

/* Sends out[q] to every rank q and receives what each sends here, in rank order, into *in
 * (free it). Collective. */
static adem_status exchange(adem_split *s, const bytes *out, bytes *in, adem_error *err) {
  int n = s->size;
  int *sc = s->bytes_a, *sd = s->bytes_b, *rc = s->bytes_c, *rd = s->bytes_d;
  size_t total = 0;
  for (int q = 0; q < n; ++q) {
    if (out[q].n > INT_MAX || total > (size_t)INT_MAX) return adem_split_too_big(err);
    sc[q] = (int)out[q].n;
    total += out[q].n;
  }
  if (total > INT_MAX) return adem_split_too_big(err);
  bytes all = {0};
  for (int q = 0; q < n; ++q) {
    sd[q] = (int)all.n;
    if (out[q].n && !adem_split_bytes_put(&all, out[q].d, out[q].n)) {
      free(all.d);
      return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    }
  }
  MPI_Alltoall(sc, 1, MPI_INT, rc, 1, MPI_INT, s->comm);
  size_t rtotal = 0;
  for (int q = 0; q < n; ++q) {
    rd[q] = (int)rtotal;
    rtotal += (size_t)rc[q];
  }
  in->d = malloc(rtotal + 1);
  in->n = in->cap = rtotal;
  if (!in->d || rtotal > INT_MAX) {
    free(all.d);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  MPI_Alltoallv(all.d ? all.d : in->d, sc, sd, MPI_BYTE, in->d, rc, rd, MPI_BYTE, s->comm);
  tally(s, (double)total - (double)sc[s->rank]);
  free(all.d);
  return ADEM_OK;
}

/* ---------------------------------------------------------------- ghost lists */

typedef struct rank_item {
  int rank;
  uint64_t id;
  uint32_t i;
} rank_item;

static int compare_rank_item(const void *x, const void *y) {
  const rank_item *a = x, *b = y;
  if (a->rank != b->rank) return a->rank < b->rank ? -1 : 1;
  return a->id < b->id ? -1 : a->id > b->id;
}

/* Fills counts, offsets and indices from items sorted by rank and id. */
static void lay_out(const adem_split *s, const rank_item *it, size_t n, int *count, int *displ,
                    uint32_t *idx) {
  for (int q = 0; q < s->size; ++q) count[q] = 0;
  for (size_t k = 0; k < n; ++k) {
    count[it[k].rank]++;
    idx[k] = it[k].i;
  }
  int at = 0;
  for (int q = 0; q < s->size; ++q) {
    displ[q] = at;
    at += count[q];
  }
}

/* After a build: which own particles each rank holds copies of, and which copies here are
 * whose, both by id; every rank checks that its senders agree. Collective. */
static adem_status make_lists(adem_split *s, const adem_world *w, adem_error *err) {
  const adem_particles *p = &w->p;
  double h = halo(s, w);
  size_t ns = 0, nr = 0;
  rank_item *snd = NULL, *rcv = NULL;
  size_t cap = p->n + 1;
  snd = malloc(cap * sizeof *snd);
  rcv = malloc(cap * sizeof *rcv);
  adem_status st = snd && rcv ? ADEM_OK : ADEM_ERR_NOMEM;
  for (size_t i = 0; i < p->n && !st; ++i) {
    int o = owner(s, p, i);
    if (o != s->rank) {
      rcv[nr++] = (rank_item){o, p->id[i], (uint32_t)i};
      continue;
    }
    double x = coord(s, p->pos_at_build[i]);
    for (int q = 0; q < s->size && !st; ++q) {
      if (q == s->rank || !near_slab(s, q, x, h)) continue;
      if (ns == cap) {
        cap *= 2;
        rank_item *m = realloc(snd, cap * sizeof *m);
        if (!m) st = ADEM_ERR_NOMEM;
        else snd = m;
      }
      if (!st) snd[ns++] = (rank_item){q, p->id[i], (uint32_t)i};
    }
  }
  if (!st) {
    qsort(snd, ns, sizeof *snd, compare_rank_item);
    qsort(rcv, nr, sizeof *rcv, compare_rank_item);
    free(s->send_idx);
    free(s->recv_idx);
    s->send_idx = malloc((ns + 1) * sizeof *s->send_idx);
    s->recv_idx = malloc((nr + 1) * sizeof *s->recv_idx);
    if (!s->send_idx || !s->recv_idx) st = ADEM_ERR_NOMEM;
  }
  if (!st) {
    lay_out(s, snd, ns, s->scount, s->sdispl, s->send_idx);
    lay_out(s, rcv, nr, s->rcount, s->rdispl, s->recv_idx);
  }
  free(snd);
  free(rcv);
  if (st) return adem_error_set(err, st, "out of memory listing the ghosts");
  /* what each rank will send here must be what is expected */
  MPI_Alltoall(s->scount, 1, MPI_INT, s->bytes_a, 1, MPI_INT, s->comm);
  int bad = 0;
  for (int q = 0; q < s->size; ++q) bad |= s->bytes_a[q] != s->rcount[q];
  int any = 0;
  MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_LOR, s->comm);
  if (any)
    return adem_error_set(err, ADEM_ERR_RUNTIME,
                          "the processes disagree on which particles are copied where (a bug)");
  return ADEM_OK;
}

/* ---------------------------------------------------------------- hooks */

static bool any_hook(void *ctx, bool yes) {
  adem_split *s = ctx;
  int v = yes ? 1 : 0, r = 0;
  MPI_Allreduce(&v, &r, 1, MPI_INT, MPI_LOR, s->comm);
  return r != 0;
}

static adem_status refresh_hook_work(adem_split *s, adem_world *w, adem_error *err);

/* The ghost refresh, timed and counted (adem_split_stats). */
static adem_status refresh_hook(void *ctx, adem_world *w, adem_error *err) {
  adem_split *s = ctx;
  double t0 = MPI_Wtime(), sent0 = s->sent;
  adem_status st = refresh_hook_work(s, w, err);
  s->stats.refreshes += 1.0;
  s->stats.refresh_seconds += MPI_Wtime() - t0;
  s->stats.refresh_bytes += s->sent - sent0;
  s->stats.ghosts += (double)(s->rdispl[s->size - 1] + s->rcount[s->size - 1]);
  s->stats.owned += (double)(w->p.n) - (double)(s->rdispl[s->size - 1] + s->rcount[s->size - 1]);
  return st;
}

static adem_status refresh_hook_work(adem_split *s, adem_world *w, adem_error *err) {
  adem_particles *p = &w->p;
  size_t rec = sizeof(ghost_state);
  size_t ns = (size_t)(s->sdispl[s->size - 1] + s->scount[s->size - 1]);
  size_t nr = (size_t)(s->rdispl[s->size - 1] + s->rcount[s->size - 1]);
  if (ns * rec > INT_MAX || nr * rec > INT_MAX) return adem_split_too_big(err);
  if (ns * rec + 1 > s->sbuf_cap) {
    free(s->sbuf);
    s->sbuf_cap = ns * rec + 1;
    s->sbuf = malloc(s->sbuf_cap);
  }
  if (nr * rec + 1 > s->rbuf_cap) {
    free(s->rbuf);
    s->rbuf_cap = nr * rec + 1;
    s->rbuf = malloc(s->rbuf_cap);
  }
  if (!s->sbuf || !s->rbuf) {
    s->sbuf_cap = s->rbuf_cap = 0;
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  for (size_t k = 0; k < ns; ++k) {
    size_t i = s->send_idx[k];
    ghost_state g;
    memset(&g, 0, sizeof g);
    g = (ghost_state){p->pos[i], p->vel[i], p->omega[i], p->force[i], p->torque[i], p->held[i]};
    memcpy(s->sbuf + k * rec, &g, rec);
  }
  for (int q = 0; q < s->size; ++q) {
    s->bytes_a[q] = s->scount[q] * (int)rec;
    s->bytes_b[q] = s->sdispl[q] * (int)rec;
    s->bytes_c[q] = s->rcount[q] * (int)rec;
    s->bytes_d[q] = s->rdispl[q] * (int)rec;
  }
  MPI_Alltoallv(s->sbuf, s->bytes_a, s->bytes_b, MPI_BYTE, s->rbuf, s->bytes_c, s->bytes_d,
                MPI_BYTE, s->comm);
  tally(s, (double)(ns - (size_t)s->scount[s->rank]) * (double)rec);
  for (size_t k = 0; k < nr; ++k) {
    size_t i = s->recv_idx[k];
    ghost_state g;
    memcpy(&g, s->rbuf + k * rec, rec);
    p->pos[i] = g.pos;
    p->vel[i] = g.vel;
    p->omega[i] = g.omega;
    p->force[i] = g.force;
    p->torque[i] = g.torque;
    p->held[i] = g.held;
  }
  return ADEM_OK;
}

/* Keeps the mesh slots of this process's own particles (a ghost's mesh contacts are its
 * owner's to compute), for particles now at i that were at from[i] when the slots were laid
 * out (from NULL: where they are), n of them. */
static adem_status keep_own_mesh_slots(adem_split *s, adem_world *w, const size_t *from, size_t n) {
  adem_mesh_pairs *pm = &w->pm;
  const adem_particles *p = &w->p;
  if (!pm->start || w->walls.mesh.ntris == 0) {
    pm->l.n = 0;
    if (pm->start) memset(pm->start, 0, (n + 1) * sizeof *pm->start);
    return ADEM_OK;
  }
  size_t *keep = calloc(pm->l.n + 1, sizeof *keep), *start = malloc((n + 1) * sizeof *start);
  if (!keep || !start || pm->start_cap < n + 1) {
    free(keep);
    free(start);
    return ADEM_ERR_NOMEM;
  }
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    start[i] = m;
    if (owner(s, p, i) != s->rank) continue;
    size_t o = from ? from[i] : i;
    for (size_t k = pm->start[o]; k < pm->start[o + 1]; ++k) keep[m++] = k;
  }
  start[n] = m;
  pm->l.n = m;
  adem_status st = adem_mesh_pairs_permute(pm, keep);
  if (!st) {
    memcpy(pm->start, start, (n + 1) * sizeof *start);
    for (size_t i = 0; i < n; ++i)
      for (size_t k = start[i]; k < start[i + 1]; ++k) pm->l.a[k] = (uint32_t)i;
  }
  free(keep);
  free(start);
  return st;
}

/* Keeps the pairs with one of this process's particles (a for a wall pair): a pair of two
 * ghosts is another process's to compute. Then the gather lists. */
static adem_status keep_own_pairs(adem_split *s, adem_world *w) {
  const adem_particles *p = &w->p;
  adem_pair_list *lists[2] = {&w->pp, &w->pw};
  size_t m = w->pp.n > w->pw.n ? w->pp.n : w->pw.n;
  size_t *keep = malloc((m + 1) * sizeof *keep);
  if (!keep) return ADEM_ERR_NOMEM;
  adem_status st = ADEM_OK;
  for (int l = 0; l < 2 && !st; ++l) {
    adem_pair_list *L = lists[l];
    size_t n = 0;
    for (size_t k = 0; k < L->n; ++k)
      if (owner(s, p, L->a[k]) == s->rank || (l == 0 && owner(s, p, L->b[k]) == s->rank))
        keep[n++] = k;
    L->n = n;
    st = adem_pairs_permute(L, keep);
  }
  free(keep);
  if (!st) st = keep_own_mesh_slots(s, w, NULL, p->n);
  if (!st) st = adem_world_gather(w);
  return st;
}

/* The cuts for the next build (into cut): the quantiles of every process's own centres now,
 * gathered, so that the slabs follow the particles (a bed settling into the bottom slab would
 * leave the others idle). Every process gets the same. Collective. */
static adem_status recut(adem_split *s, const adem_world *w, double *cut) {
  const adem_particles *p = &w->p;
  double *mine = malloc((p->n + 1) * sizeof *mine);
  int *count = s->bytes_a, *displ = s->bytes_b;
  int n = 0;
  for (size_t i = 0; mine && i < p->n; ++i)
    if (owner(s, p, i) == s->rank) mine[n++] = coord(s, p->pos[i]);
  MPI_Allgather(&n, 1, MPI_INT, count, 1, MPI_INT, s->comm);
  size_t total = 0;
  for (int q = 0; q < s->size; ++q) {
    displ[q] = (int)total;
    total += (size_t)count[q];
  }
  double *all = malloc((total + 1) * sizeof *all);
  int ok = mine && all && total <= INT_MAX, every = 0;
  MPI_Allreduce(&ok, &every, 1, MPI_INT, MPI_LAND, s->comm);
  if (every) {
    MPI_Allgatherv(mine, n, MPI_DOUBLE, all, count, displ, MPI_DOUBLE, s->comm);
    tally(s, (double)n * sizeof *mine * (s->size - 1));
    quantile_cuts(all, total, s->size, cut);
  }
  free(mine);
  free(all);
  return every ? ADEM_OK : ADEM_ERR_NOMEM;
}

/* The neighbour build of a split system, at the same steps as the serial run's (the decision
 * is the largest displacement of all): each process sends its own particles to their new
 * owners and copies to the slabs within reach, and the history of each touching pair of one
 * of its own to the new owners of its particles of the pair (the old owner of a particle holds
 * every pair of it: so the new owner of a particle gets every history it needs). */
static adem_status build_hook_work(void *ctx, adem_world *w, adem_error *err);

/* The build, timed and counted (adem_split_stats). */
static adem_status build_hook(void *ctx, adem_world *w, adem_error *err) {
  adem_split *s = ctx;
  double t0 = MPI_Wtime(), sent0 = s->sent;
  adem_status st = build_hook_work(ctx, w, err);
  s->stats.builds += 1.0;
  s->stats.build_seconds += MPI_Wtime() - t0;
  s->stats.build_bytes += s->sent - sent0;
  return st;
}

static adem_status build_hook_work(void *ctx, adem_world *w, adem_error *err) {
  adem_split *s = ctx;
  adem_particles *p = &w->p;
  int me = s->rank, size = s->size;
  double h = halo(s, w);
  bytes *pout = calloc((size_t)size, sizeof *pout), *hout = calloc((size_t)size, sizeof *hout);
  bytes pin = {0}, hin = {0};
  id_index *map = NULL;
  history_rec *hr = NULL;
  double *next = malloc((size_t)size * sizeof *next); /* the cuts from this build on */
  adem_status st = pout && hout && next ? ADEM_OK : ADEM_ERR_NOMEM;
  st = adem_split_agree(s, st, err);
  if (!st) st = recut(s, w, next);
  for (size_t k = 0; k < w->pp.n && !st; ++k) {
    if (!w->pp.touching[k]) continue;
    size_t a = w->pp.a[k], b = w->pp.b[k];
    int da = owner(s, p, a) == me ? slab_in(next, size, coord(s, p->pos[a])) : -1;
    int db = owner(s, p, b) == me ? slab_in(next, size, coord(s, p->pos[b])) : -1;
    history_rec r;
    memset(&r, 0, sizeof r);
    r.ka = p->id[a];
    r.kb = p->id[b];
    r.h = w->pp.hist[adem_pairs_slot(&w->pp, k)];
    if (da >= 0 && !adem_split_bytes_put(&hout[da], &r, sizeof r)) st = ADEM_ERR_NOMEM;
    if (db >= 0 && db != da && !adem_split_bytes_put(&hout[db], &r, sizeof r)) st = ADEM_ERR_NOMEM;
  }
  for (size_t k = 0; k < w->pw.n && !st; ++k) {
    size_t a = w->pw.a[k];
    if (!w->pw.touching[k] || owner(s, p, a) != me) continue;
    history_rec r;
    memset(&r, 0, sizeof r);
    r = (history_rec){p->id[a], w->pw.b[k], 1, w->pw.hist[k]};
    if (!adem_split_bytes_put(&hout[slab_in(next, size, coord(s, p->pos[a]))], &r, sizeof r))
      st = ADEM_ERR_NOMEM;
  }
  const adem_mesh_pairs *pm = &w->pm;
  bool no_mesh_history = split_broken("mesh_history"); /* the test's control */
  for (size_t k = 0; k < pm->l.n && pm->start && !no_mesh_history && !st; ++k) {
    /* mesh contacts: by id and key */
    size_t a = pm->l.a[k];
    if (!pm->l.touching[k] || owner(s, p, a) != me) continue;
    history_rec r;
    memset(&r, 0, sizeof r);
    r = (history_rec){p->id[a], pm->key[k], 2, pm->l.hist[k]};
    if (!adem_split_bytes_put(&hout[slab_in(next, size, coord(s, p->pos[a]))], &r, sizeof r))
      st = ADEM_ERR_NOMEM;
  }
  for (size_t i = 0; i < p->n && !st; ++i) {
    if (owner(s, p, i) != me) continue;
    double x = coord(s, p->pos[i]);
    int r = slab_in(next, size, x);
    for (int q = 0; q < size && !st; ++q)
      if ((q == r || near_in(s, next, q, x, h)) && !adem_split_put_particle(&pout[q], p, i))
        st = ADEM_ERR_NOMEM;
  }
  if (st == ADEM_ERR_NOMEM) adem_error_set(err, st, "out of memory moving the particles");
  st = adem_split_agree(s, st, err); /* no process may leave the exchange alone */
  if (st) goto out;
  st = exchange(s, pout, &pin, err);
  if (!st) st = exchange(s, hout, &hin, err);
  if (st) goto done;
  memcpy(s->cut, next, (size_t)(size - 1) * sizeof *next); /* owners by the new cuts from here */

  /* the particles here now: own and ghosts, in the order they came */
  size_t rec = adem_split_particle_bytes(), n = pin.n / rec;
  if (adem_particles_reserve(p, n) || !(map = malloc((n + 1) * sizeof *map))) {
    st = ADEM_ERR_NOMEM;
    goto done;
  }
  p->n = n;
  for (size_t i = 0; i < n; ++i) {
    if (!adem_split_get_particle(p, i, pin.d + i * rec)) {
      p->n = i; /* those taken so far: the exchange failed */
      st = ADEM_ERR_NOMEM;
      goto done;
    }
    map[i] = (id_index){p->id[i], (uint32_t)i};
  }
  qsort(map, n, sizeof *map, adem_split_compare_id_index);

  /* the histories as touching pairs, for the build to carry over */
  size_t nh = hin.n / sizeof(history_rec), m[3] = {0, 0, 0};
  hr = malloc((nh + 1) * sizeof *hr);
  if (!hr) {
    st = ADEM_ERR_NOMEM;
    goto done;
  }
  if (nh) memcpy(hr, hin.d, nh * sizeof *hr);
  qsort(hr, nh, sizeof *hr, compare_history);
  /* particle pairs, plane contacts (wall 1: b the plane), mesh contacts (wall 2: b the key,
   * which the build puts in the particle's first slots) */
  adem_pair_list *lists[3] = {&w->pp, &w->pw, &w->pm.l};
  for (int pass = 0; pass < 2 && !st; ++pass) {
    m[0] = m[1] = m[2] = 0;
    if (pass == 1) adem_pairs_free_slots(&w->pp); /* the old slots are the old lists' */
    for (size_t k = 0; k < nh; ++k) {
      if (k > 0 && compare_history(&hr[k - 1], &hr[k]) == 0) continue; /* held on both sides */
      size_t a = adem_split_find_id(map, n, hr[k].ka);
      size_t b = hr[k].wall ? (size_t)hr[k].kb : adem_split_find_id(map, n, hr[k].kb);
      if (a == SIZE_MAX || b == SIZE_MAX) continue; /* a partner beyond reach: no candidate */
      int l = (int)hr[k].wall;
      adem_pair_list *L = lists[l];
      if (pass == 1) {
        L->a[m[l]] = (uint32_t)a;
        L->b[m[l]] = l == 2 ? 0u : (uint32_t)b;
        if (L->slot) L->slot[m[l]] = 0; /* before the clear: none of its own yet */
        adem_pairs_clear(L, m[l]);
        if (l == 2) w->pm.key[m[l]] = hr[k].kb;
        L->hist[adem_pairs_own_slot(L, m[l])] = hr[k].h;
        L->touching[m[l]] = true;
      }
      m[l]++;
    }
    if (pass == 0 && (adem_pairs_reserve(&w->pp, m[0]) || adem_pairs_reserve(&w->pw, m[1]) ||
                      adem_pairs_reserve(&w->pm.l, m[2]) || adem_mesh_pairs_reserve(&w->pm)))
      st = ADEM_ERR_NOMEM;
  }
  if (st) goto done;
  w->pp.n = m[0];
  w->pw.n = m[1];
  w->pm.l.n = m[2];
  w->nb.rmax_floor = s->rmax;
  st = adem_world_build_neighbors(w, err);
  if (st) goto out;
  st = keep_own_pairs(s, w);
  if (!st) st = make_lists(s, w, err);
  goto out;
done:
  if (st == ADEM_ERR_NOMEM) adem_error_set(err, st, "out of memory moving the particles");
out:
  adem_split_bytes_free_all(pout, size);
  adem_split_bytes_free_all(hout, size);
  free(pin.d);
  free(hin.d);
  free(map);
  free(hr);
  free(next);
  return st;
}

/* ---------------------------------------------------------------- set-up */

const char *adem_split_refusal(const adem_world *w) {
  if (w->admit_pending) return "particles waiting to be admitted (a bug: admit them first)";
  if (w->p.n == 0) return "having no particles";
  return NULL;
}

/* A copy of a prepared world, through its checkpoint bytes. */
static adem_status world_copy(const adem_world *w, adem_world **out, adem_error *err) {
  bytes b = {0};
  adem_writer wr = adem_writer_make(adem_split_mem_sink, &b);
  adem_world_save_setup(&wr, w);
  adem_world_save(&wr, w);
  adem_world *c = adem_world_create();
  adem_status st = !wr.failed && c ? ADEM_OK : adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_reader rd = {b.d, b.d + b.n, 0};
  bool prepared = false;
  if (!st) st = adem_world_load_setup(&rd, c, err);
  if (!st) st = adem_world_load_prepared(&rd, &prepared, err);
  if (!st && prepared) st = adem_world_prepare(c, err);
  if (!st) st = adem_world_load(&rd, c, err);
  if (!st) {
    c->nthreads = w->nthreads;
    adem_world_place_walls(c, w->time);
    if (adem_world_gather(c)) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  free(b.d);
  if (st) {
    adem_world_free(c);
    return st;
  }
  *out = c;
  return ADEM_OK;
}

/* Cuts along the longest axis of the domain box that is not periodic (slabs along an axis that
 * does not wrap hold the whole box along the periodic ones, so that the build's minimum images
 * along those are within each process's part), or, when all three wrap, along the longest,
 * whose slabs meet across its faces; at the quantiles of the centres (at the last build): equal
 * particle counts. */
static adem_status place_cuts(adem_split *s, const adem_world *w) {
  const adem_particles *p = &w->p;
  adem_vec3 e = v3_sub(w->domain_hi, w->domain_lo);
  double len[3] = {e.x, e.y, e.z};
  s->axis = -1;
  unsigned wraps = w->periodic.axes;
  for (int d = 0; d < 3; ++d) /* the longest that does not wrap */
    if (!(wraps & (1u << d)) && (s->axis < 0 || len[d] > len[s->axis])) s->axis = d;
  for (int d = 0; d < 3 && wraps == 7u; ++d) /* all wrap: the longest */
    if (s->axis < 0 || len[d] > len[s->axis]) s->axis = d;
  s->wraps = (wraps >> s->axis) & 1u;
  s->plo = w->periodic.lo[s->axis];
  s->plen = w->periodic.len[s->axis];
  if (wraps && split_broken("periodic_axis")) { /* the test's control: along one that wraps, */
    s->axis = wraps & 1u ? 0 : wraps & 2u ? 1
                                          : 2; /* as if it did not (no images across) */
    s->wraps = false;
  }
  size_t n = p->n;
  double *x = malloc((n + 1) * sizeof *x);
  s->cut = malloc((size_t)s->size * sizeof *s->cut);
  if (!x || !s->cut) {
    free(x);
    return ADEM_ERR_NOMEM;
  }
  for (size_t i = 0; i < n; ++i) x[i] = coord(s, p->pos_at_build[i]);
  quantile_cuts(x, n, s->size, s->cut);
  free(x);
  return ADEM_OK;
}

/* Keeps of a whole world this process's particles and its ghosts, and the pairs with one of
 * its own: the state the serial run has, cut to this slab. */
static adem_status trim(adem_split *s, adem_world *w) {
  adem_particles *p = &w->p;
  double h = halo(s, w);
  size_t n = p->n;
  size_t *keep = malloc((n + 1) * sizeof *keep), *to = malloc((n + 1) * sizeof *to);
  if (!keep || !to) {
    free(keep);
    free(to);
    return ADEM_ERR_NOMEM;
  }
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    to[i] = SIZE_MAX;
    if (owner(s, p, i) == s->rank || near_slab(s, s->rank, coord(s, p->pos_at_build[i]), h)) {
      to[i] = m;
      keep[m++] = i;
    }
  }
  p->n = m;
  adem_status st = adem_particles_permute(p, keep);
  adem_pair_list *lists[2] = {&w->pp, &w->pw};
  for (int l = 0; l < 2 && !st; ++l) {
    adem_pair_list *L = lists[l];
    size_t *kp = malloc((L->n + 1) * sizeof *kp), np = 0;
    if (!kp) {
      st = ADEM_ERR_NOMEM;
      break;
    }
    for (size_t k = 0; k < L->n; ++k) {
      size_t a = to[L->a[k]], b = l == 0 ? to[L->b[k]] : 0;
      if (a == SIZE_MAX || b == SIZE_MAX) continue;
      if (owner(s, p, a) == s->rank || (l == 0 && owner(s, p, b) == s->rank)) kp[np++] = k;
    }
    L->n = np;
    st = adem_pairs_permute(L, kp);
    for (size_t k = 0; k < np && !st; ++k) {
      L->a[k] = (uint32_t)to[L->a[k]];
      if (l == 0) L->b[k] = (uint32_t)to[L->b[k]];
    }
    free(kp);
  }
  if (!st) st = keep_own_mesh_slots(s, w, keep, m);
  free(keep);
  free(to);
  if (!st) st = adem_world_gather(w);
  return st;
}

adem_status adem_split_create(const adem_world *whole, MPI_Comm comm, adem_split **out,
                              adem_world **local, adem_error *err) {
  *out = NULL;
  *local = NULL;
  const char *why = adem_split_refusal(whole);
  if (why)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "this case cannot run on more than one MPI process yet because of %s; "
                          "run it with one process",
                          why);
  adem_split *s = calloc(1, sizeof *s);
  if (!s) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  s->comm = comm;
  MPI_Comm_rank(comm, &s->rank);
  MPI_Comm_size(comm, &s->size);
  size_t q = (size_t)s->size;
  int **arrays[8] = {&s->scount, &s->sdispl, &s->rcount, &s->rdispl,
                     &s->bytes_a, &s->bytes_b, &s->bytes_c, &s->bytes_d};
  adem_status st = ADEM_OK;
  for (int k = 0; k < 8; ++k)
    if (!(*arrays[k] = calloc(q, sizeof(int)))) st = ADEM_ERR_NOMEM;
  for (size_t i = 0; i < whole->p.n; ++i) s->rmax = fmax(s->rmax, whole->p.radius[i]);
  if (!st) st = place_cuts(s, whole);
  if (st) {
    adem_split_free(s);
    return adem_error_set(err, st, "out of memory");
  }
  adem_world *w = NULL;
  st = world_copy(whole, &w, err);
  if (!st && trim(s, w)) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  if (!st) {
    w->nb.rmax_floor = s->rmax;
    s->hooks = (adem_world_split){s, refresh_hook, any_hook, build_hook,
                                  adem_split_plane_forces_hook, adem_split_mesh_loads_hook,
                                  adem_split_sum_terms_hook};
    w->split = &s->hooks;
    st = make_lists(s, w, err);
  }
  if (st) {
    adem_world_free(w);
    adem_split_free(s);
    return st;
  }
  *out = s;
  *local = w;
  return ADEM_OK;
}

adem_status adem_split_agree(adem_split *s, adem_status st, adem_error *err) {
  int v = (int)st, r = 0;
  MPI_Allreduce(&v, &r, 1, MPI_INT, MPI_MAX, s->comm);
  if (r && !st) return adem_error_set(err, (adem_status)r, "another MPI process failed");
  return st;
}

int adem_split_rank(const adem_split *s) { return s->rank; }

adem_status adem_split_own_by_id(const adem_split *s, const adem_world *local, uint32_t **idx,
                                 size_t *n) {
  const adem_particles *p = &local->p;
  id_index *m = malloc((p->n + 1) * sizeof *m);
  uint32_t *x = malloc((p->n + 1) * sizeof *x);
  *idx = NULL;
  *n = 0;
  if (!m || !x) {
    free(m);
    free(x);
    return ADEM_ERR_NOMEM;
  }
  size_t k = 0;
  for (size_t i = 0; i < p->n; ++i)
    if (owner(s, p, i) == s->rank) m[k++] = (id_index){p->id[i], (uint32_t)i};
  qsort(m, k, sizeof *m, adem_split_compare_id_index);
  for (size_t j = 0; j < k; ++j) x[j] = m[j].i;
  free(m);
  *idx = x;
  *n = k;
  return ADEM_OK;
}

size_t adem_split_owned(const adem_split *s, const adem_world *local) {
  size_t n = 0;
  for (size_t i = 0; i < local->p.n; ++i) n += owner(s, &local->p, i) == s->rank;
  return n;
}

void adem_split_stats_add(const adem_split *s, adem_split_stats *into) {
  into->refreshes += s->stats.refreshes;
  into->ghosts += s->stats.ghosts;
  into->owned += s->stats.owned;
  into->refresh_bytes += s->stats.refresh_bytes;
  into->refresh_seconds += s->stats.refresh_seconds;
  into->builds += s->stats.builds;
  into->build_bytes += s->stats.build_bytes;
  into->build_seconds += s->stats.build_seconds;
  into->other_bytes += s->sent - s->stats.refresh_bytes - s->stats.build_bytes;
}

void adem_split_free(adem_split *s) {
  if (!s) return;
  free(s->cut);
  free(s->scount);
  free(s->sdispl);
  free(s->rcount);
  free(s->rdispl);
  free(s->bytes_a);
  free(s->bytes_b);
  free(s->bytes_c);
  free(s->bytes_d);
  free(s->send_idx);
  free(s->recv_idx);
  free(s->sbuf);
  free(s->rbuf);
  free(s);
}
