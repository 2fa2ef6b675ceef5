/* The MPI split's byte buffers, the records they carry (particles: every field of the particle
 * table; pairs: their keys as ids, every field, the balance record) and the collectives that
 * gather them (split_parts.h). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "split_parts.h"

/* ---------------------------------------------------------------- byte buffers */
bool adem_split_bytes_put(bytes *b, const void *x, size_t n) {
  if (b->n + n > b->cap) {
    size_t c = 2 * (b->n + n) + 256;
    unsigned char *q = realloc(b->d, c);
    if (!q) return false;
    b->d = q;
    b->cap = c;
  }
  memcpy(b->d + b->n, x, n);
  b->n += n;
  return true;
}

void adem_split_bytes_free_all(bytes *b, int n) {
  for (int k = 0; b && k < n; ++k) free(b[k].d);
  free(b);
}

int adem_split_mem_sink(void *ctx, const void *data, size_t n) {
  return adem_split_bytes_put(ctx, data, n);
}

/* ---------------------------------------------------------------- records */

/* A particle: every field of ADEM_PARTICLE_FIELDS, zeros for one its process does not keep. */
size_t adem_split_particle_bytes(void) { return adem_soa_item_bytes(adem_particles_layout()); }

bool adem_split_put_particle(bytes *b, const adem_particles *p, size_t i) {
  static const char zeros[64]; /* the largest field is an adem_vec3 */
  adem_soa_layout L = adem_particles_layout();
  bool ok = true;
  for (size_t k = 0; k < L.count; ++k) {
    size_t e = L.fields[k].elem;
    const char *a = *(char *const *)((const char *)p + L.fields[k].offset);
    ok = ok && e <= sizeof zeros && adem_split_bytes_put(b, a ? a + i * e : zeros, e);
  }
  return ok;
}

bool adem_split_get_particle(adem_particles *p, size_t i, const unsigned char *src) {
  adem_soa_layout L = adem_particles_layout();
  for (size_t k = 0; k < L.count; ++k) {
    size_t e = L.fields[k].elem;
    char **a = (char **)((char *)p + L.fields[k].offset);
    if (!*a) { /* absent here: zeros stay so, anything else makes its kind present */
      bool zero = true;
      for (size_t b = 0; b < e && zero; ++b) zero = src[b] == 0;
      if (!zero && adem_particles_keep(p, (adem_particle_kind)L.fields[k].kind)) return false;
    }
    if (*a) memcpy(*a + i * e, src, e);
    src += e;
  }
  return true;
}

/* A pair for the assembly: its keys as ids (or id and plane), then every field of
 * ADEM_PAIR_FIELDS but the keys and every field of ADEM_PAIR_SLOT_FIELDS, then (bal: while the
 * balance is on) its balance record. */
size_t adem_split_pair_bytes(bool bal) {
  size_t n = 2 * sizeof(uint64_t);
#define ADEM_X(type, name, role, doc) \
  if (role != ADEM_PAIR_KEY) n += sizeof(type);
  ADEM_PAIR_FIELDS(ADEM_X)
  ADEM_PAIR_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
  return n + (bal ? sizeof(adem_pair_balance) : 0);
}

bool adem_split_put_pair(bytes *b, const adem_pair_list *l, size_t k, uint64_t ka, uint64_t kb,
                         bool bal) {
  bool ok = adem_split_bytes_put(b, &ka, sizeof ka) && adem_split_bytes_put(b, &kb, sizeof kb);
  size_t s = adem_pairs_slot(l, k);
#define ADEM_X(type, name, role, doc) \
  if (role != ADEM_PAIR_KEY) ok = ok && adem_split_bytes_put(b, &l->name[k], sizeof(type));
  ADEM_PAIR_FIELDS(ADEM_X)
#undef ADEM_X
#define ADEM_X(type, name, role, doc) ok = ok && adem_split_bytes_put(b, &l->name[s], sizeof(type));
  ADEM_PAIR_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
  if (bal) { /* records not made yet (no force pass since the balance came on) are zero */
    adem_pair_balance zero;
    memset(&zero, 0, sizeof zero);
    ok = ok && adem_split_bytes_put(b, l->bal ? &l->bal[s] : &zero, sizeof zero);
  }
  return ok;
}

/* Into pair k of a list being filled anew (a sparse one's slots freed: adem_pairs_free_slots). */
void adem_split_get_pair(adem_pair_list *l, size_t k, const unsigned char *src, uint64_t *ka,
                         uint64_t *kb, bool bal) {
  memcpy(ka, src, sizeof *ka);
  memcpy(kb, src + sizeof *ka, sizeof *kb);
  src += 2 * sizeof(uint64_t);
#define ADEM_X(type, name, role, doc)       \
  if (role != ADEM_PAIR_KEY) {              \
    memcpy(&l->name[k], src, sizeof(type)); \
    src += sizeof(type);                    \
  }
  ADEM_PAIR_FIELDS(ADEM_X)
#undef ADEM_X
  if (l->slot) l->slot[k] = 0;
  size_t s = adem_pairs_own_slot(l, k); /* zeros or not, the assembled list is not timed */
#define ADEM_X(type, name, role, doc)     \
  memcpy(&l->name[s], src, sizeof(type)); \
  src += sizeof(type);
  ADEM_PAIR_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
  if (bal && l->bal) memcpy(&l->bal[s], src, sizeof l->bal[s]);
}

int adem_split_compare_id_index(const void *x, const void *y) {
  const id_index *a = x, *b = y;
  return a->id < b->id ? -1 : a->id > b->id;
}

size_t adem_split_find_id(const id_index *m, size_t n, uint64_t id) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (m[mid].id < id) lo = mid + 1;
    else hi = mid;
  }
  return lo < n && m[lo].id == id ? m[lo].i : SIZE_MAX;
}

/* ---------------------------------------------------------------- collectives */

/* Gathers the bytes of every rank to every rank, in rank order (into *in). Collective. */
adem_status adem_split_allgather(adem_split *s, const bytes *mine, bytes *in, adem_error *err) {
  int n = mine->n > INT_MAX ? -1 : (int)mine->n;
  MPI_Allgather(&n, 1, MPI_INT, s->bytes_a, 1, MPI_INT, s->comm);
  size_t total = 0;
  int ok = 1;
  for (int q = 0; q < s->size; ++q) {
    if (s->bytes_a[q] < 0) ok = 0;
    s->bytes_b[q] = (int)(total <= INT_MAX ? total : 0);
    total += s->bytes_a[q] > 0 ? (size_t)s->bytes_a[q] : 0;
  }
  if (total > INT_MAX) ok = 0;
  in->d = ok ? malloc(total + 1) : NULL;
  in->n = in->cap = total;
  int mine_ok = in->d != NULL, all_ok = 0;
  MPI_Allreduce(&mine_ok, &all_ok, 1, MPI_INT, MPI_LAND, s->comm);
  if (!all_ok) {
    free(in->d);
    in->d = NULL;
    in->n = in->cap = 0;
    return ok ? adem_error_set(err, ADEM_ERR_NOMEM, "out of memory gathering the particles")
              : adem_split_too_big(err);
  }
  MPI_Allgatherv(mine->d ? mine->d : in->d, n, MPI_BYTE, in->d, s->bytes_a, s->bytes_b, MPI_BYTE,
                 s->comm);
  tally(s, (double)n * (s->size - 1));
  return ADEM_OK;
}

/* Gathers the bytes of every rank to rank 0 (into *in there). Collective. */
adem_status adem_split_gather(adem_split *s, const bytes *mine, bytes *in, adem_error *err) {
  if (mine->n > INT_MAX) return adem_split_too_big(err);
  int n = (int)mine->n;
  MPI_Gather(&n, 1, MPI_INT, s->bytes_a, 1, MPI_INT, 0, s->comm);
  size_t total = 0;
  if (s->rank == 0)
    for (int q = 0; q < s->size; ++q) {
      s->bytes_b[q] = (int)total;
      total += (size_t)s->bytes_a[q];
    }
  int ok = total <= INT_MAX && (in->d = malloc(total + 1)) != NULL;
  in->n = in->cap = total;
  MPI_Bcast(&ok, 1, MPI_INT, 0, s->comm);
  if (!ok) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory gathering the particles");
  MPI_Gatherv(mine->d ? mine->d : in->d, n, MPI_BYTE, in->d, s->bytes_a, s->bytes_b, MPI_BYTE, 0,
              s->comm);
  if (s->rank != 0) tally(s, (double)n);
  return ADEM_OK;
}
