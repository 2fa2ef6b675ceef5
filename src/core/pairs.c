/* Flat arrays of candidate contacts and their history (the tables in pairs.h). */
#include "pairs.h"

#include <stdlib.h>

#include "log.h"

static const adem_soa_field pair_fields[] = {
#define ADEM_X(type, name, role, doc) {#name, offsetof(adem_pair_list, name), sizeof(type), 0},
    ADEM_PAIR_FIELDS(ADEM_X)
#undef ADEM_X
};
static const adem_soa_layout pair_layout = {pair_fields, sizeof pair_fields / sizeof pair_fields[0]};

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
  return adem_soa_item_bytes(pair_layout) + (with_balance ? sizeof(adem_pair_balance) : 0);
}

adem_status adem_pairs_reserve(adem_pair_list *l, size_t cap) {
  if (cap <= l->cap) return ADEM_OK;
  cap = cap + cap / 4 + 16; /* headroom: the list is rebuilt often with similar sizes */
  adem_status st = adem_soa_grow(l, pair_layout, cap);
  if (!st && l->keeps_balance) st = adem_soa_grow(l, balance_layout, cap);
  if (!st) l->cap = cap;
  return st;
}

adem_status adem_pairs_keep_balance(adem_pair_list *l, bool on) {
  if (on == l->keeps_balance) return ADEM_OK;
  l->keeps_balance = on;
  if (!on) {
    adem_soa_free(l, balance_layout);
    return ADEM_OK;
  }
  if (l->cap == 0) return ADEM_OK; /* grown with the list */
  l->bal = calloc(l->cap, sizeof *l->bal);
  if (l->bal) return ADEM_OK;
  l->keeps_balance = false;
  return ADEM_ERR_NOMEM;
}

void adem_pairs_free(adem_pair_list *l) {
  adem_soa_free(l, pair_layout);
  adem_soa_free(l, balance_layout);
  memset(l, 0, sizeof *l);
}

adem_status adem_pairs_permute(adem_pair_list *l, const size_t *perm) {
  adem_status st = adem_soa_permute(l, pair_layout, l->n, perm);
  if (!st && l->bal) st = adem_soa_permute(l, balance_layout, l->n, perm);
  return st;
}

void adem_pairs_save(adem_writer *wr, const adem_pair_list *l) {
  adem_put_u64(wr, l->n);
  adem_soa_save(wr, l, pair_layout, l->n);
  adem_put_u8(wr, l->bal ? 1 : 0);
  if (l->bal) adem_soa_save(wr, l, balance_layout, l->n);
}

adem_status adem_pairs_load(adem_reader *rd, adem_pair_list *l, adem_error *err) {
  uint64_t n = adem_get_count(rd, adem_pairs_item_bytes(false));
  if (rd->failed) return ADEM_OK;
  if (n > l->cap && adem_pairs_reserve(l, (size_t)n) != ADEM_OK)
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %llu pairs", (unsigned long long)n);
  l->n = (size_t)n;
  adem_soa_load(rd, l, pair_layout, l->n);
  uint8_t with_balance = adem_get_u8(rd);
  if (rd->failed || with_balance > 1) {
    rd->failed = 1;
    return ADEM_OK;
  }
  if (with_balance) {
    if (adem_pairs_keep_balance(l, true) != ADEM_OK)
      return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %llu pairs", (unsigned long long)n);
    adem_soa_load(rd, l, balance_layout, l->n);
  } else if (l->bal) {
    memset(l->bal, 0, l->n * sizeof *l->bal);
  }
  /* a bool must hold 0 or 1 */
  for (size_t k = 0; k < l->n && !rd->failed; ++k) {
    unsigned char b;
    memcpy(&b, &l->touching[k], 1);
    if (b > 1) rd->failed = 1;
  }
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
