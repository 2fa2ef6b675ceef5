#include "soa.h"

#include <stdlib.h>
#include <string.h>

static void **slot(void *obj, const adem_soa_field *f) { return (void **)((char *)obj + f->offset); }
static void *const *cslot(const void *obj, const adem_soa_field *f) {
  return (void *const *)((const char *)obj + f->offset);
}

adem_status adem_soa_grow(void *obj, adem_soa_layout L, size_t cap) {
  for (size_t k = 0; k < L.count; ++k) {
    void **p = slot(obj, &L.fields[k]);
    if (L.fields[k].kind && !*p) continue; /* absent: allocated when its kind is needed */
    void *q = realloc(*p, (cap ? cap : 1) * L.fields[k].elem);
    if (!q) return ADEM_ERR_NOMEM;
    *p = q;
  }
  return ADEM_OK;
}

void adem_soa_free(void *obj, adem_soa_layout L) {
  for (size_t k = 0; k < L.count; ++k) {
    void **p = slot(obj, &L.fields[k]);
    free(*p);
    *p = NULL;
  }
}

adem_status adem_soa_permute(void *obj, adem_soa_layout L, size_t n, const size_t *perm) {
  if (n == 0) return ADEM_OK; /* arrays never grown are NULL */
  size_t largest = 1;
  for (size_t k = 0; k < L.count; ++k)
    if (L.fields[k].elem > largest) largest = L.fields[k].elem;
  char *scratch = malloc(n * largest + 1);
  if (!scratch) return ADEM_ERR_NOMEM;
  for (size_t k = 0; k < L.count; ++k) {
    size_t e = L.fields[k].elem;
    char *a = *slot(obj, &L.fields[k]);
    if (!a) continue; /* absent: all zeros in any order */
    for (size_t i = 0; i < n; ++i) memcpy(scratch + i * e, a + perm[i] * e, e);
    memcpy(a, scratch, n * e);
  }
  free(scratch);
  return ADEM_OK;
}

void adem_soa_save(adem_writer *wr, const void *obj, adem_soa_layout L, size_t n) {
  static const char zeros[4096];
  for (size_t k = 0; k < L.count; ++k) {
    const void *a = *cslot(obj, &L.fields[k]);
    if (a) {
      adem_put_array(wr, a, n, L.fields[k].elem);
      continue;
    }
    adem_put_u64(wr, n); /* absent: the bytes it reads as */
    for (size_t left = n * L.fields[k].elem; left > 0;) {
      size_t c = left < sizeof zeros ? left : sizeof zeros;
      adem_put(wr, zeros, c);
      left -= c;
    }
  }
}

void adem_soa_load(adem_reader *rd, void *obj, adem_soa_layout L, size_t n) {
  for (size_t k = 0; k < L.count; ++k)
    adem_get_array(rd, *slot(obj, &L.fields[k]), n, L.fields[k].elem);
}

size_t adem_soa_item_bytes(adem_soa_layout L) {
  size_t b = 0;
  for (size_t k = 0; k < L.count; ++k) b += L.fields[k].elem;
  return b;
}

bool adem_soa_all_zero(const void *obj, const adem_soa_field *f, size_t n) {
  const unsigned char *a = *cslot(obj, f);
  for (size_t i = 0; a && i < n * f->elem; ++i)
    if (a[i]) return false;
  return true;
}
