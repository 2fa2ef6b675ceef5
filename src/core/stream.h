/* Serialization for checkpoints: a writer that hashes everything it passes to a sink, and a reader
 * over bytes in memory that never reads past their end. Every module saves and loads its own
 * state through these; the output layer decides where the bytes go. Values are written in the
 * machine's byte order (the checkpoint header records it). */
#ifndef ADEM_STREAM_H
#define ADEM_STREAM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/base.h"

#define ADEM_FNV_START 0xcbf29ce484222325ULL
/* FNV-1a of n bytes, continuing from h (start with ADEM_FNV_START). */
uint64_t adem_fnv1a(uint64_t h, const void *data, size_t n);

/* Returns 0 when the bytes could not be taken (the writer then fails and stops writing). */
typedef int adem_sink_fn(void *ctx, const void *data, size_t n);

typedef struct adem_writer {
  adem_sink_fn *sink;
  void *ctx;
  uint64_t bytes, hash; /* what was written, and its FNV-1a */
  int failed;
} adem_writer;

adem_writer adem_writer_make(adem_sink_fn *sink, void *ctx);
void adem_put(adem_writer *wr, const void *data, size_t n);
void adem_put_u8(adem_writer *wr, uint8_t v);
void adem_put_u32(adem_writer *wr, uint32_t v);
void adem_put_i32(adem_writer *wr, int32_t v);
void adem_put_u64(adem_writer *wr, uint64_t v);
void adem_put_f64(adem_writer *wr, double v);
void adem_put_vec(adem_writer *wr, adem_vec3 v);
/* u64 length, then the bytes (NULL writes an empty string). */
void adem_put_str(adem_writer *wr, const char *s);
/* u64 count, then count * elem raw bytes. */
void adem_put_array(adem_writer *wr, const void *data, size_t count, size_t elem);

/* A reader over [at, end). Any read past the end, or a count that does not match, sets failed and
 * yields zeros from then on: callers check failed once after a section. */
typedef struct adem_reader {
  const unsigned char *at, *end;
  int failed;
} adem_reader;

int adem_get(adem_reader *rd, void *out, size_t n);
uint8_t adem_get_u8(adem_reader *rd);
uint32_t adem_get_u32(adem_reader *rd);
int32_t adem_get_i32(adem_reader *rd);
uint64_t adem_get_u64(adem_reader *rd);
double adem_get_f64(adem_reader *rd);
adem_vec3 adem_get_vec(adem_reader *rd);
/* A fresh NUL-terminated string, or NULL (failed set, or out of memory: *nomem set). */
char *adem_get_str(adem_reader *rd, int *nomem);
/* Into a buffer of cap bytes; a longer string fails the reader. */
void adem_get_str_into(adem_reader *rd, char *dst, size_t cap);
/* An array of exactly count elements (the stored count must match). */
void adem_get_array(adem_reader *rd, void *dst, size_t count, size_t elem);
/* A stored count, refused (failed) when the rest of the data could not hold count elements of at
 * least min_elem bytes: a damaged count must not make the caller allocate gigabytes. */
uint64_t adem_get_count(adem_reader *rd, size_t min_elem);
/* Bytes left. */
size_t adem_reader_left(const adem_reader *rd);

/* Checkpoint files (written by the run layer, read by it and by the case loader's `type: state`):
 * header "ADEMCKPT" (or "ADEMWRLD"), u32 version, u32 0x01020304, u64 payload bytes, u64 FNV-1a
 * of the payload, u32 sizeof(adem_vec3), u32 history bytes; then the payload. */
#define ADEM_CKPT_MAGIC "ADEMCKPT"
#define ADEM_CKPT_VERSION 11u /* 6: pair results as one record per pair; 7: where the walls are \
                                placed from, servo state, material names, the case section's    \
                                length, the energy-balance switch, the periodic box and the     \
                                per-particle image counters; 8: a pair's energy bookkeeping in  \
                                a record of its own; 9: a pair's stored energy alone, the       \
                                balance's records only while the balance is on; 10: a pair's    \
                                opened flag; 11: the domain's open (outlet) faces, the          \
                                outlets' and mass flows' state, the per-particle external       \
                                force, the rolling stiffness a contact's rolling spring was     \
                                stored with, the tangential force a contact applied at the      \
                                last pass, a plane's shape (cylinder, disc) */
#define ADEM_CKPT_ENDIAN 0x01020304u
#define ADEM_CKPT_HEADER_BYTES 40u
/* Checks the header of checkpoint bytes of kind magic (hist_size: the build's contact-history
 * size); the payload's reader on success, else ADEM_ERR_INPUT "PATH is not a usable adem
 * checkpoint: why". */
adem_status adem_checkpoint_header_check(const char *data, size_t len, const char *path,
                                         const char *magic, uint32_t hist_size, adem_reader *rd,
                                         adem_error *err);

#endif
