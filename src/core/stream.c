#include "stream.h"

#include <stdio.h>
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
uint8_t adem_get_u8(adem_reader *rd) {
  uint8_t v;
  adem_get(rd, &v, 1);
  return v;
}
uint32_t adem_get_u32(adem_reader *rd) {
  uint32_t v;
  adem_get(rd, &v, 4);
  return v;
}
int32_t adem_get_i32(adem_reader *rd) {
  int32_t v;
  adem_get(rd, &v, 4);
  return v;
}
uint64_t adem_get_u64(adem_reader *rd) {
  uint64_t v;
  adem_get(rd, &v, 8);
  return v;
}
double adem_get_f64(adem_reader *rd) {
  double v;
  adem_get(rd, &v, 8);
  return v;
}
adem_vec3 adem_get_vec(adem_reader *rd) {
  adem_vec3 v;
  adem_get(rd, &v, sizeof v);
  return v;
}

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

static adem_status bad_file(adem_error *err, const char *path, const char *why) {
  return adem_error_set(err, ADEM_ERR_INPUT, "%s is not a usable adem checkpoint: %s", path, why);
}

/* Checks the header of a checkpoint of kind magic; the payload's reader on success. */
adem_status adem_checkpoint_header_check(const char *data, size_t len, const char *path,
                                         const char *magic, uint32_t hist, adem_reader *rd,
                                         adem_error *err) {
  const unsigned char *b = (const unsigned char *)data;
  if (len < 8 || memcmp(b, magic, 8) != 0) {
    char why[96];
    snprintf(why, sizeof why, "it does not start with %s (not a %s)", magic,
             strcmp(magic, ADEM_CKPT_MAGIC) ? "world checkpoint" : "checkpoint");
    return bad_file(err, path, why);
  }
  if (len < ADEM_CKPT_HEADER_BYTES) return bad_file(err, path, "it is truncated (header)");
  uint32_t version, endian, vec_size, hist_size;
  uint64_t payload, hash;
  memcpy(&version, b + 8, 4);
  memcpy(&endian, b + 12, 4);
  memcpy(&payload, b + 16, 8);
  memcpy(&hash, b + 24, 8);
  memcpy(&vec_size, b + 32, 4);
  memcpy(&hist_size, b + 36, 4);
  char why[160];
  if (endian != ADEM_CKPT_ENDIAN)
    return bad_file(err, path, "it was written on a machine with another byte order");
  if (version != ADEM_CKPT_VERSION) {
    snprintf(why, sizeof why, "it has format version %u, this adem reads version %u", version,
             ADEM_CKPT_VERSION);
    return bad_file(err, path, why);
  }
  if (vec_size != sizeof(adem_vec3) || hist_size != hist)
    return bad_file(err, path, "it was written by a build with another contact-history layout");
  if (payload != (uint64_t)(len - ADEM_CKPT_HEADER_BYTES)) {
    snprintf(why, sizeof why, "it is %s: %zu bytes instead of %llu",
             payload > (uint64_t)(len - ADEM_CKPT_HEADER_BYTES) ? "truncated" : "too long", len,
             (unsigned long long)(payload + ADEM_CKPT_HEADER_BYTES));
    return bad_file(err, path, why);
  }
  if (adem_fnv1a(ADEM_FNV_START, b + ADEM_CKPT_HEADER_BYTES, (size_t)payload) != hash)
    return bad_file(err, path, "its checksum does not match (the file is damaged)");
  rd->at = b + ADEM_CKPT_HEADER_BYTES;
  rd->end = b + len;
  rd->failed = 0;
  return ADEM_OK;
}
