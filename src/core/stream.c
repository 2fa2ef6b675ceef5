#include "stream.h"

#include <stdlib.h>
#include <string.h>

uint64_t adem_fnv1a(uint64_t h, const void *data, size_t n) {
  const unsigned char *b = data;
  for (size_t i = 0; i < n; ++i) {
    h ^= b[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

/* ---------------------------------------------------------------- writing */

adem_writer adem_writer_make(adem_sink_fn *sink, void *ctx) {
  adem_writer wr = {sink, ctx, 0, ADEM_FNV_START, 0};
  return wr;
}

void adem_put(adem_writer *wr, const void *data, size_t n) {
  if (wr->failed || n == 0) return;
  if (!wr->sink(wr->ctx, data, n)) {
    wr->failed = 1;
    return;
  }
  wr->bytes += n;
  wr->hash = adem_fnv1a(wr->hash, data, n);
}
void adem_put_u8(adem_writer *wr, uint8_t v) { adem_put(wr, &v, 1); }
void adem_put_u32(adem_writer *wr, uint32_t v) { adem_put(wr, &v, 4); }
void adem_put_i32(adem_writer *wr, int32_t v) { adem_put(wr, &v, 4); }
void adem_put_u64(adem_writer *wr, uint64_t v) { adem_put(wr, &v, 8); }
void adem_put_f64(adem_writer *wr, double v) { adem_put(wr, &v, 8); }
void adem_put_vec(adem_writer *wr, adem_vec3 v) { adem_put(wr, &v, sizeof v); }
void adem_put_str(adem_writer *wr, const char *s) {
  size_t n = s ? strlen(s) : 0;
  adem_put_u64(wr, n);
  adem_put(wr, s, n);
}
void adem_put_array(adem_writer *wr, const void *data, size_t count, size_t elem) {
  adem_put_u64(wr, count);
  adem_put(wr, data, count * elem);
}

/* ---------------------------------------------------------------- reading */

size_t adem_reader_left(const adem_reader *rd) { return (size_t)(rd->end - rd->at); }

int adem_get(adem_reader *rd, void *out, size_t n) {
  if (rd->failed || adem_reader_left(rd) < n) {
    rd->failed = 1;
    if (out && n) memset(out, 0, n);
    return 0;
  }
  if (n) memcpy(out, rd->at, n);
  rd->at += n;
  return 1;
}
uint8_t adem_get_u8(adem_reader *rd) { uint8_t v; adem_get(rd, &v, 1); return v; }
uint32_t adem_get_u32(adem_reader *rd) { uint32_t v; adem_get(rd, &v, 4); return v; }
int32_t adem_get_i32(adem_reader *rd) { int32_t v; adem_get(rd, &v, 4); return v; }
uint64_t adem_get_u64(adem_reader *rd) { uint64_t v; adem_get(rd, &v, 8); return v; }
double adem_get_f64(adem_reader *rd) { double v; adem_get(rd, &v, 8); return v; }
adem_vec3 adem_get_vec(adem_reader *rd) { adem_vec3 v; adem_get(rd, &v, sizeof v); return v; }

char *adem_get_str(adem_reader *rd, int *nomem) {
  uint64_t n = adem_get_u64(rd);
  if (rd->failed || n > (uint64_t)adem_reader_left(rd)) {
    rd->failed = 1;
    return NULL;
  }
  char *s = malloc((size_t)n + 1);
  if (!s) {
    *nomem = 1;
    return NULL;
  }
  adem_get(rd, s, (size_t)n);
  s[n] = '\0';
  return s;
}

void adem_get_str_into(adem_reader *rd, char *dst, size_t cap) {
  uint64_t n = adem_get_u64(rd);
  if (rd->failed || n >= cap || n > (uint64_t)adem_reader_left(rd)) {
    rd->failed = 1;
    dst[0] = '\0';
    return;
  }
  adem_get(rd, dst, (size_t)n);
  dst[n] = '\0';
}

void adem_get_array(adem_reader *rd, void *dst, size_t count, size_t elem) {
  uint64_t n = adem_get_u64(rd);
  if (n != count) {
    rd->failed = 1;
    return;
  }
  adem_get(rd, dst, count * elem);
}

uint64_t adem_get_count(adem_reader *rd, size_t min_elem) {
  uint64_t n = adem_get_u64(rd);
  if (rd->failed || (min_elem > 0 && n > (uint64_t)adem_reader_left(rd) / min_elem)) {
    rd->failed = 1;
    return 0;
  }
  return n;
}
