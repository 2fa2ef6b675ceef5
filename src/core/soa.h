/* Structure-of-arrays storage described once. A module lists its per-item arrays in an X-macro;
 * the same list declares the struct's pointers and builds a table of adem_soa_field that these
 * functions walk to grow, free, reorder, save and load every array, so that no array can be
 * forgotten in one of those places. */
#ifndef ADEM_SOA_H
#define ADEM_SOA_H

#include <stdbool.h>
#include <stddef.h>

#include "adem/base.h"
#include "stream.h"

typedef struct adem_soa_field {
  const char *name;
  size_t offset; /* of the array's pointer in the owning struct */
  size_t elem;   /* bytes per item */
  int kind;      /* 0: always allocated; else optional: its array may be NULL (absent), which
                  * reads as all zeros; the owning module allocates it (particles.h's kinds) */
} adem_soa_field;

typedef struct adem_soa_layout {
  const adem_soa_field *fields;
  size_t count;
} adem_soa_layout;

/* Reallocates every array of obj to cap items (contents kept up to the old size); an absent
 * optional array stays absent. */
adem_status adem_soa_grow(void *obj, adem_soa_layout L, size_t cap);
/* Frees every array and sets the pointers to NULL. */
void adem_soa_free(void *obj, adem_soa_layout L);
/* Reorders items 0..n-1 of every present array: new item k is old item perm[k]. */
adem_status adem_soa_permute(void *obj, adem_soa_layout L, size_t n, const size_t *perm);
/* Items 0..n-1 of every array, each as a u64 count and raw bytes (zeros for an absent one: the
 * format does not depend on which arrays a run keeps). */
void adem_soa_save(adem_writer *wr, const void *obj, adem_soa_layout L, size_t n);
/* The arrays saved by adem_soa_save, into arrays that hold at least n items (every one present). */
void adem_soa_load(adem_reader *rd, void *obj, adem_soa_layout L, size_t n);
/* Bytes per item over every array, present or not (the saved record). */
size_t adem_soa_item_bytes(adem_soa_layout L);
/* Whether items 0..n-1 of array k are all zero bytes (true for an absent one). */
bool adem_soa_all_zero(const void *obj, const adem_soa_field *f, size_t n);

#endif
