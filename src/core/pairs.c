/* Flat arrays of candidate contacts and their history (the tables in pairs.h). */
#include "pairs.h"

#include <stdlib.h>

#include "log.h"

/* Per candidate; a sparse list's slot numbers; per slot (per pair in a dense list). */
static const adem_soa_field pair_fields[] = {
#define ADEM_X(type, name, role, doc) {#name, offsetof(adem_pair_list, name), sizeof(type), 0},
    ADEM_PAIR_FIELDS(ADEM_X)
#undef ADEM_X
};
static const adem_soa_layout pair_layout = {pair_fields, sizeof pair_fields / sizeof pair_fields[0]};
static const adem_soa_field slot_index_fields[] = {{"slot", offsetof(adem_pair_list, slot), sizeof(uint32_t), 0}};
static const adem_soa_layout slot_index_layout = {slot_index_fields, 1};
static const adem_soa_field state_fields[] = {
#define ADEM_X(type, name, role, doc) {#name, offsetof(adem_pair_list, name), sizeof(type), 0},
    ADEM_PAIR_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
};
static const adem_soa_layout state_layout = {state_fields, sizeof state_fields / sizeof state_fields[0]};

static const adem_soa_field slot_fields[] = {
#define ADEM_X(type, name, saved, doc) {#name, offsetof(adem_mesh_pairs, name), sizeof(type), 0},
    ADEM_MESH_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
};
static const adem_soa_layout slot_layout = {slot_fields, sizeof slot_fields / sizeof slot_fields[0]};

static const adem_soa_field saved_slot_fields[] = {
#define ADEM_X(type, name, saved, doc) \
  {saved ? #name : NULL, offsetof(adem_mesh_pairs, name), sizeof(type), 0},
    ADEM_MESH_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
};

/* The balance records as a layout of their own, grown, reordered and saved only while kept. */
static const adem_soa_field balance_fields[] = {{"bal", offsetof(adem_pair_list, bal), sizeof(adem_pair_balance), 0}};
static const adem_soa_layout balance_layout = {balance_fields, 1};

size_t adem_pairs_item_bytes(bool with_balance) {
  return adem_soa_item_bytes(pair_layout) + adem_soa_item_bytes(state_layout) +
         (with_balance ? sizeof(adem_pair_balance) : 0);
}

adem_status adem_pairs_reserve(adem_pair_list *l, size_t cap) {
  if (cap <= l->cap && (l->slot_cap > 0 || !l->sparse)) return ADEM_OK; /* sparse: slot 0 too */
  cap = cap + cap / 4 + 16;                                             /* headroom: the list is rebuilt often with similar sizes */
  /* a sparse list: a slot for every candidate and the zeros' slot; only the slots taken are
   * ever written, so the rest costs address space, not memory */
  size_t scap = l->sparse ? cap + 1 : cap;
  adem_status st = adem_soa_grow(l, pair_layout, cap);
  if (!st && l->sparse) st = adem_soa_grow(l, slot_index_layout, cap);
  if (!st) st = adem_soa_grow(l, state_layout, scap);
  if (!st && l->keeps_balance) st = adem_soa_grow(l, balance_layout, scap);
  if (st) return st;
  if (l->sparse && l->slot_cap == 0) {
    l->nslots = 1;
    adem_pairs_clear_slot(l, 0);
  }
  l->cap = cap;
  l->slot_cap = scap;
  return ADEM_OK;
}

adem_status adem_pairs_keep_balance(adem_pair_list *l, bool on) {
  if (on == l->keeps_balance) return ADEM_OK;
  l->keeps_balance = on;
  if (!on) {
    adem_soa_free(l, balance_layout);
    return ADEM_OK;
  }
  if (l->slot_cap == 0) return ADEM_OK; /* grown with the list */
  l->bal = calloc(l->slot_cap, sizeof *l->bal);
  if (l->bal) return ADEM_OK;
  l->keeps_balance = false;
  return ADEM_ERR_NOMEM;
}

void adem_pairs_free(adem_pair_list *l) {
  bool sparse = l->sparse;
  adem_soa_free(l, pair_layout);
  adem_soa_free(l, slot_index_layout);
  adem_soa_free(l, state_layout);
  adem_soa_free(l, balance_layout);
  memset(l, 0, sizeof *l);
  l->sparse = sparse;
}

/* A sparse list's slots renumbered 1, 2, ... in the order of its pairs, every record kept (after
 * a permutation, which may drop pairs): the slots in use are then at most one per pair, so the
 * pairs still without one can each take one within the capacity (a slot per candidate). */
static adem_status repack_slots(adem_pair_list *l) {
  size_t m = 0;
  for (size_t k = 0; k < l->n; ++k) m += l->slot[k] != 0;
  if (m == 0) { /* (the arrays may not exist yet) */
    if (l->slot_cap > 0) l->nslots = 1;
    return ADEM_OK;
  }
  adem_contact_history *h = malloc((m + 1) * sizeof *h);
  adem_pair_result *r = malloc((m + 1) * sizeof *r);
  double *e = malloc((m + 1) * sizeof *e);
  adem_pair_balance *b = l->bal ? malloc((m + 1) * sizeof *b) : NULL;
  adem_status st = h && r && e && (b || !l->bal) ? ADEM_OK : ADEM_ERR_NOMEM;
  for (size_t k = 0, d = 1; k < l->n && !st; ++k) {
    size_t s = l->slot[k];
    if (s == 0) continue;
    h[d] = l->hist[s];
    r[d] = l->res[s];
    e[d] = l->elastic[s];
    if (b) b[d] = l->bal[s];
    l->slot[k] = (uint32_t)d++;
  }
  if (!st) {
    memcpy(l->hist + 1, h + 1, m * sizeof *h);
    memcpy(l->res + 1, r + 1, m * sizeof *r);
    memcpy(l->elastic + 1, e + 1, m * sizeof *e);
    if (b) memcpy(l->bal + 1, b + 1, m * sizeof *b);
    l->nslots = m + 1;
  }
  free(h);
  free(r);
  free(e);
  free(b);
  return st;
}

adem_status adem_pairs_permute(adem_pair_list *l, const size_t *perm) {
  adem_status st = adem_soa_permute(l, pair_layout, l->n, perm);
  if (l->sparse) {
    if (!st) st = adem_soa_permute(l, slot_index_layout, l->n, perm);
    return st ? st : repack_slots(l);
  }
  if (!st) st = adem_soa_permute(l, state_layout, l->n, perm);
  if (!st && l->bal) st = adem_soa_permute(l, balance_layout, l->n, perm);
  return st;
}

adem_status adem_pairs_pack_slots(adem_pair_list *l, const uint32_t *src) {
  size_t n = l->n, m = 0;
  for (size_t k = 0; k < n; ++k) m += src[k] != 0;
  size_t span = l->nslots > m + 1 ? l->nslots : m + 1;
  uint32_t *from = malloc((m + 2) * sizeof *from);
  unsigned char *state = calloc(span + 1, 1); /* 1: an old slot some new one takes; 2: filled */
  if (!from || !state) {
    free(from);
    free(state);
    return ADEM_ERR_NOMEM;
  }
  /* new slot d (1 .. m) takes old slot from[d]; from is one-to-one, so the moves are chains that
   * start at a slot nobody takes from, and cycles, which go through one temporary */
  from[0] = 0;
  for (size_t k = 0, d = 1; k < n; ++k) /* a fresh slot takes slot 0's zeros */
    if (src[k] != 0) from[d++] = src[k] == ADEM_PAIR_FRESH_SLOT ? 0u : src[k];
  for (size_t d = 1; d <= m; ++d) state[from[d]] |= 1;
  adem_contact_history *h = l->hist;
  for (size_t p0 = 1; p0 <= m; ++p0) {
    if (state[p0] & 1) continue;
    for (size_t p = p0; p >= 1 && p <= m && !(state[p] & 2); p = from[p]) {
      h[p] = h[from[p]];
      state[p] |= 2;
    }
  }
  for (size_t p0 = 1; p0 <= m; ++p0) {
    if (state[p0] & 2) continue;
    adem_contact_history first = h[p0];
    size_t p = p0;
    for (; from[p] != p0; p = from[p]) {
      h[p] = h[from[p]];
      state[p] |= 2;
    }
    h[p] = first;
    state[p] |= 2;
  }
  for (size_t k = 0, d = 1; k < n; ++k) {
    bool kept = src[k] != 0;
    l->slot[k] = kept ? (uint32_t)d : 0u;
    l->touching[k] = kept && src[k] != ADEM_PAIR_FRESH_SLOT;
    l->opened[k] = false;
    if (!kept) continue;
    adem_contact_history hk = h[d];
    adem_pairs_clear_slot(l, d);
    h[d] = hk;
    ++d;
  }
  adem_pairs_clear_slot(l, 0);
  l->nslots = m + 1;
  free(from);
  free(state);
  return ADEM_OK;
}

/* One per-slot array written per pair (a sparse list's untaken slot as zeros): the file is the
 * same whatever the list keeps in slots. */
static void put_by_pair(adem_writer *wr, const adem_pair_list *l, const void *arr, size_t elem) {
  adem_put_u64(wr, l->n);
  for (size_t k = 0; k < l->n; ++k)
    adem_put(wr, (const char *)arr + adem_pairs_slot(l, k) * elem, elem);
}

void adem_pairs_save(adem_writer *wr, const adem_pair_list *l) {
  adem_put_u64(wr, l->n);
  /* the order of the format: a, b, hist, touching, opened, res, elastic */
  adem_put_array(wr, l->a, l->n, sizeof *l->a);
  adem_put_array(wr, l->b, l->n, sizeof *l->b);
  put_by_pair(wr, l, l->hist, sizeof *l->hist);
  adem_put_array(wr, l->touching, l->n, sizeof *l->touching);
  adem_put_array(wr, l->opened, l->n, sizeof *l->opened);
  put_by_pair(wr, l, l->res, sizeof *l->res);
  put_by_pair(wr, l, l->elastic, sizeof *l->elastic);
  adem_put_u8(wr, l->bal ? 1 : 0);
  if (l->bal) put_by_pair(wr, l, l->bal, sizeof *l->bal);
}

static bool all_zero(const void *x, size_t n) {
  const unsigned char *c = x;
  for (size_t i = 0; i < n; ++i)
    if (c[i]) return false;
  return true;
}

adem_status adem_pairs_load(adem_reader *rd, adem_pair_list *l, adem_error *err) {
  uint64_t n = adem_get_count(rd, adem_pairs_item_bytes(false));
  if (rd->failed) return ADEM_OK;
  if (adem_pairs_reserve(l, (size_t)n) != ADEM_OK)
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %llu pairs", (unsigned long long)n);
  l->n = (size_t)n;
  /* read by pair, as a dense list holds them (a sparse list's slots hold a slot per pair) */
  if (l->sparse) {
    for (size_t k = 0; k < l->n; ++k) l->slot[k] = (uint32_t)(k + 1);
    l->nslots = l->n + 1; /* consistent even if the file turns out bad below */
  }
  adem_get_array(rd, l->a, l->n, sizeof *l->a);
  adem_get_array(rd, l->b, l->n, sizeof *l->b);
  /* a sparse list's pair k in slot k + 1 (reserved: the arrays exist); a dense list's arrays
   * as they are (NULL while it never grew, which takes no offset) */
  bool o = l->sparse;
  adem_get_array(rd, o ? l->hist + 1 : l->hist, l->n, sizeof *l->hist);
  adem_get_array(rd, l->touching, l->n, sizeof *l->touching);
  adem_get_array(rd, l->opened, l->n, sizeof *l->opened);
  adem_get_array(rd, o ? l->res + 1 : l->res, l->n, sizeof *l->res);
  adem_get_array(rd, o ? l->elastic + 1 : l->elastic, l->n, sizeof *l->elastic);
  uint8_t with_balance = adem_get_u8(rd);
  if (rd->failed || with_balance > 1) {
    rd->failed = 1;
    return ADEM_OK;
  }
  if (with_balance) {
    if (adem_pairs_keep_balance(l, true) != ADEM_OK)
      return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %llu pairs", (unsigned long long)n);
    adem_get_array(rd, o ? l->bal + 1 : l->bal, l->n, sizeof *l->bal);
  } else if (l->bal) {
    memset(l->bal, 0, l->slot_cap * sizeof *l->bal);
  }
  /* a bool must hold 0 or 1 */
  for (size_t k = 0; k < l->n && !rd->failed; ++k) {
    unsigned char b, c;
    memcpy(&b, &l->touching[k], 1);
    memcpy(&c, &l->opened[k], 1);
    if (b > 1 || c > 1) rd->failed = 1;
  }
  if (rd->failed || !l->sparse) return ADEM_OK;
  /* a sparse list: every pair in slot k + 1; those whose records are all zero go to slot 0, and
   * the rest are packed in order (a move down, never onto a slot still to be read) */
  adem_pairs_clear_slot(l, 0);
  size_t d = 1;
  for (size_t k = 0; k < l->n; ++k) {
    size_t s = k + 1;
    bool zero = !l->touching[k] && !l->opened[k] && all_zero(&l->hist[s], sizeof l->hist[s]) &&
                all_zero(&l->res[s], sizeof l->res[s]) && all_zero(&l->elastic[s], sizeof l->elastic[s]) &&
                (!l->bal || all_zero(&l->bal[s], sizeof l->bal[s]));
    if (zero) {
      l->slot[k] = 0;
      continue;
    }
    if (d != s) {
      l->hist[d] = l->hist[s];
      l->res[d] = l->res[s];
      l->elastic[d] = l->elastic[s];
      if (l->bal) l->bal[d] = l->bal[s];
    }
    l->slot[k] = (uint32_t)d++;
  }
  l->nslots = d;
  return ADEM_OK;
}

size_t adem_mesh_pairs_slot_bytes(void) { return adem_soa_item_bytes(slot_layout); }

adem_status adem_mesh_pairs_reserve(adem_mesh_pairs *pm) {
  size_t cap = pm->l.cap;
  if (cap <= pm->cap) return ADEM_OK;
  adem_status st = adem_soa_grow(pm, slot_layout, cap);
  if (!st) pm->cap = cap;
  return st;
}

void adem_mesh_pairs_free(adem_mesh_pairs *pm) {
  adem_pairs_free(&pm->l);
  free(pm->start);
  adem_soa_free(pm, slot_layout);
  memset(pm, 0, sizeof *pm);
}

adem_status adem_mesh_pairs_permute(adem_mesh_pairs *pm, const size_t *perm) {
  adem_status st = adem_pairs_permute(&pm->l, perm);
  return st ? st : adem_soa_permute(pm, slot_layout, pm->l.n, perm);
}

void adem_mesh_pairs_save(adem_writer *wr, const adem_mesh_pairs *pm, size_t nparticles) {
  adem_pairs_save(wr, &pm->l);
  for (size_t k = 0; k < slot_layout.count; ++k)
    if (saved_slot_fields[k].name)
      adem_put_array(wr, *(void *const *)((const char *)pm + slot_fields[k].offset), pm->l.n,
                     slot_fields[k].elem);
  size_t ns = pm->start ? nparticles + 1 : 0;
  adem_put_u64(wr, ns);
  for (size_t i = 0; i < ns; ++i) adem_put_u64(wr, pm->start[i]);
}

adem_status adem_mesh_pairs_load(adem_reader *rd, adem_mesh_pairs *pm, size_t nparticles,
                                 adem_error *err) {
  adem_status st = adem_pairs_load(rd, &pm->l, err);
  if (st || rd->failed) return st;
  if (adem_mesh_pairs_reserve(pm))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the mesh contacts");
  for (size_t k = 0; k < slot_layout.count; ++k)
    if (saved_slot_fields[k].name)
      adem_get_array(rd, *(void **)((char *)pm + slot_fields[k].offset), pm->l.n,
                     slot_fields[k].elem);
  uint64_t ns = adem_get_u64(rd);
  if (rd->failed || (ns != 0 && ns != (uint64_t)nparticles + 1)) {
    rd->failed = 1;
    return ADEM_OK;
  }
  if (ns > pm->start_cap) {
    size_t *q = realloc(pm->start, (size_t)ns * sizeof *q);
    if (!q) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the mesh contacts");
    pm->start = q;
    pm->start_cap = (size_t)ns;
  }
  for (size_t i = 0; i < ns; ++i) pm->start[i] = (size_t)adem_get_u64(rd);
  return ADEM_OK;
}

bool adem_mesh_pairs_consistent(const adem_mesh_pairs *pm, size_t n, size_t ntris) {
  if (!pm->start) return pm->l.n == 0;
  /* The stepper walks every particle's range, contacts or not: all n + 1 bounds must be there. */
  if (pm->start_cap < n + 1 || pm->start[0] != 0 || pm->start[n] != pm->l.n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (pm->start[i + 1] < pm->start[i] || pm->start[i + 1] > pm->l.n) return false;
    for (size_t k = pm->start[i]; k < pm->start[i + 1]; ++k)
      if (pm->l.a[k] != i || pm->l.b[k] >= ntris || (pm->l.touching[k] && pm->owner[k] >= ntris))
        return false;
  }
  return true;
}
