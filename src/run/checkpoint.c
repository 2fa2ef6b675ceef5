/* Checkpoints: the case text (to rebuild materials, walls and settings) and the whole dynamic
 * state of the world, so that a resumed run continues bit for bit. Each part saves and loads
 * itself (adem_world_save: world scalars, particles, pair lists, mesh contacts and face loads;
 * the pours their streams; this file the case section); this file frames them.
 *
 * Layout, all in the writing machine's byte order (checked by a marker):
 *   header  "ADEMCKPT", u32 version, u32 0x01020304, u64 payload bytes, u64 FNV-1a of the
 *           payload, u32 sizeof(adem_vec3), u32 sizeof(adem_contact_history)
 *   payload case: source text, --set strings, path, base folder, end time, output settings,
 *           what the run has written, the stage in force, the pours' state (streams, counts),
 *           the stages' start steps and the run-until conditions' state; then the world
 *           (adem_world_save), "ADEMEND\0"
 * Strings are u64 length + bytes; arrays are u64 count + raw elements. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/case.h"
#include "adem/run.h"
#include "adem/world.h"
#include "adem/files.h"
#include "insert.h"
#include "log.h"
#include "outlets.h"
#include "stages.h"
#include "stream.h"
#include "world_internal.h"

#define CKPT_MAGIC ADEM_CKPT_MAGIC
#define CKPT_WORLD_MAGIC "ADEMWRLD" /* a world made through the API, set-up included */
#define CKPT_END "ADEMEND"
#define CKPT_VERSION ADEM_CKPT_VERSION
#define CKPT_ENDIAN ADEM_CKPT_ENDIAN
#define CKPT_HEADER_BYTES ADEM_CKPT_HEADER_BYTES

/* ---------------------------------------------------------------- writing */

static int file_sink(void *ctx, const void *data, size_t n) {
  return fwrite(data, 1, n, (FILE *)ctx) == n;
}

static void header_bytes(unsigned char h[CKPT_HEADER_BYTES], const char *magic,
                         uint64_t payload_bytes, uint64_t hash) {
  uint32_t version = CKPT_VERSION, endian = CKPT_ENDIAN;
  uint32_t vec_size = sizeof(adem_vec3), hist_size = sizeof(adem_contact_history);
  memcpy(h, magic, 8);
  memcpy(h + 8, &version, 4);
  memcpy(h + 12, &endian, 4);
  memcpy(h + 16, &payload_bytes, 8);
  memcpy(h + 24, &hash, 8);
  memcpy(h + 32, &vec_size, 4);
  memcpy(h + 36, &hist_size, 4);
}

/* The case section: what loads the case again and the settings a caller may have changed after
 * loading (--out, a shorter end time). */
static void save_case(adem_writer *wr, const adem_case *c, int *nomem) {
  adem_put_str(wr, c->source);
  adem_put_u32(wr, (uint32_t)c->nsets);
  for (int k = 0; k < c->nsets; ++k) adem_put_str(wr, c->sets[k]);
  adem_put_str(wr, c->path);
  adem_put_str(wr, c->base_dir); /* mesh files are found from it, whatever the working folder */
  adem_put_f64(wr, c->end_time);
  adem_put_i32(wr, c->dt_auto);
  adem_put_str(wr, c->output.dir);
  adem_put_f64(wr, c->output.frame_interval);
  adem_put_f64(wr, c->output.csv_interval);
  adem_put_f64(wr, c->output.checkpoint_interval);
  adem_put_i32(wr, c->output.plot);
  adem_put_u64(wr, c->frames_written);
  adem_put_i32(wr, c->csv_last_extra);
  /* Staged runs and pours: the stage in force (its configuration is replayed from the case) and
   * the pours' random streams and counts. */
  adem_put_u32(wr, (uint32_t)adem_stages_current(c));
  size_t nruns = 0;
  unsigned char *runs = adem_pours_pack(c->pours, &nruns);
  if (!runs) *nomem = 1;
  adem_put_array(wr, runs, runs ? nruns : 0, 1);
  free(runs);
  /* when each stage began and the run-until conditions' streaks */
  adem_stages_save(wr, c);
  adem_outlets_save(wr, c->outlets); /* removed counts and masses, the flows' state */
}

typedef void save_fn(adem_writer *wr, const void *what, int *nomem);

/* A checkpoint file: header, the payload save() writes, the end marker; atomic. */
static adem_status write_file(const char *path, const char *magic, save_fn *save,
                              const void *what, adem_error *err) {
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  unsigned char h[CKPT_HEADER_BYTES];
  header_bytes(h, magic, 0, 0); /* rewritten once the payload's size and hash are known */
  int failed = fwrite(h, 1, sizeof h, af.f) != sizeof h;
  adem_writer wr = adem_writer_make(file_sink, af.f);
  int nomem = 0;
  save(&wr, what, &nomem);
  adem_put(&wr, CKPT_END, 8);
  failed |= wr.failed | nomem;
  if (!failed) {
    header_bytes(h, magic, wr.bytes, wr.hash);
    failed = fseek(af.f, 0, SEEK_SET) != 0 || fwrite(h, 1, sizeof h, af.f) != sizeof h;
  }
  if (failed) {
    int e = nomem ? ENOMEM : errno ? errno
                                   : EIO;
    adem_file_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write checkpoint %s: %s", path, strerror(e));
  }
  return adem_file_commit(&af, err);
}

static int count_sink(void *ctx, const void *data, size_t n) {
  (void)ctx;
  (void)data;
  (void)n;
  return 1;
}

static void save_case_and_world(adem_writer *wr, const void *what, int *nomem) {
  const adem_case *c = what;
  /* the case section's length first, so that a reader of the world alone (a case's `type:
   * state`) can skip it */
  adem_writer counter = adem_writer_make(count_sink, NULL);
  save_case(&counter, c, nomem);
  adem_put_u64(wr, counter.bytes);
  save_case(wr, c, nomem);
  adem_world_save(wr, c->world);
}

static void save_world(adem_writer *wr, const void *what, int *nomem) {
  (void)nomem;
  adem_world_save_setup(wr, what);
  adem_world_save(wr, what);
}

adem_status adem_checkpoint_write(const adem_case *c, const char *path, adem_error *err) {
  return write_file(path, CKPT_MAGIC, save_case_and_world, c, err);
}

adem_status adem_world_checkpoint_write(const adem_world *w, const char *path, adem_error *err) {
  return write_file(path, CKPT_WORLD_MAGIC, save_world, w, err);
}

/* ---------------------------------------------------------------- reading */

static adem_status bad_file(adem_error *err, const char *path, const char *why) {
  return adem_error_set(err, ADEM_ERR_INPUT, "%s is not a usable adem checkpoint: %s", path, why);
}

/* What a resumed run may change (adem_checkpoint_read_with): the end and the output intervals. */
static const char *const resume_keys[] = {"time.end", "output.frame_interval",
                                          "output.csv_interval", "output.checkpoint_interval"};
enum { RESUME_END = 0,
       RESUME_FRAME = 1,
       RESUME_CSV = 2,
       RESUME_CKPT = 3,
       RESUME_KEYS = 4 };

/* Which of resume_keys the sets change (given[k]); ADEM_ERR_INPUT for any other key. */
static adem_status resume_sets_check(const char *const *sets, int nsets, bool given[RESUME_KEYS],
                                     adem_error *err) {
  for (int k = 0; k < RESUME_KEYS; ++k) given[k] = false;
  for (int j = 0; j < nsets; ++j) {
    size_t n = strcspn(sets[j], "=");
    int found = -1;
    for (int k = 0; k < RESUME_KEYS; ++k)
      if (strlen(resume_keys[k]) == n && !strncmp(sets[j], resume_keys[k], n)) found = k;
    if (found < 0 || sets[j][n] != '=')
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "--set %s: a resumed run may change only time.end (a later end "
                            "continues the run as if it had had that end from the start) and "
                            "output.frame_interval, output.csv_interval, "
                            "output.checkpoint_interval; the rest of the case is the one stored "
                            "in the checkpoint (start a new run, or use stages, to change it)",
                            sets[j]);
    given[found] = true;
  }
  return ADEM_OK;
}

/* Loads the stored case text, with the extra sets on top of its own; *out is the freshly loaded
 * case. */
static adem_status load_case(adem_reader *rd, const char *path, const char *const *extra,
                             int nextra, adem_case **out, adem_error *err) {
  int nomem = 0;
  char *source = adem_get_str(rd, &nomem);
  uint32_t nsets = adem_get_u32(rd);
  if (rd->failed || nsets > adem_reader_left(rd) / 8) {
    free(source);
    return bad_file(err, path, "it is truncated (case section)");
  }
  char **sets = calloc(nsets + (uint32_t)nextra + 1, sizeof *sets);
  if (!sets) nomem = 1;
  for (uint32_t k = 0; k < nsets && sets; ++k) sets[k] = adem_get_str(rd, &nomem);
  char *case_path = adem_get_str(rd, &nomem);
  char *base_dir = adem_get_str(rd, &nomem);
  adem_status st = ADEM_OK;
  adem_case *c = NULL;
  if (nomem) {
    st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory reading %s", path);
  } else if (rd->failed || !source || !case_path || !base_dir) {
    st = bad_file(err, path, "it is truncated (case section)");
  } else {
    for (int k = 0; k < nextra; ++k) sets[nsets + (uint32_t)k] = (char *)extra[k];
    st = adem_case_load_string_at(source, case_path, base_dir, (const char *const *)sets,
                                  (int)nsets + nextra, &c, err);
    if (st) {
      /* Say where the case came from: the checkpoint, not the file named in the message. */
      char msg[ADEM_MSG_MAX];
      snprintf(msg, sizeof msg, "%s", err ? err->message : "");
      adem_error_set(err, st, "the case stored in %s does not load: %s", path, msg);
    }
  }
  for (uint32_t k = 0; k < nsets && sets; ++k) free(sets[k]);
  free(sets);
  free(source);
  free(case_path);
  free(base_dir);
  *out = c;
  return st;
}

/* Parses the payload into a freshly loaded case; the extra sets (resume_keys only) change the
 * end and the output intervals for the rest of the run. */
static adem_status restore(adem_reader *rd, const char *path, const char *const *extra,
                           int nextra, adem_case **out, adem_error *err) {
  bool given[RESUME_KEYS];
  adem_case *c = NULL;
  adem_status st = resume_sets_check(extra, nextra, given, err);
  (void)adem_get_u64(rd); /* the case section's length */
  if (!st) st = load_case(rd, path, extra, nextra, &c, err);
  if (st) return st;
  adem_world *w = c->world;
  double stored[RESUME_KEYS];
  stored[RESUME_END] = adem_get_f64(rd);
  c->dt_auto = adem_get_i32(rd);
  adem_get_str_into(rd, c->output.dir, sizeof c->output.dir);
  stored[RESUME_FRAME] = adem_get_f64(rd);
  stored[RESUME_CSV] = adem_get_f64(rd);
  stored[RESUME_CKPT] = adem_get_f64(rd);
  /* the stored values, unless given now (the fresh load has those) */
  if (!given[RESUME_END]) c->end_time = stored[RESUME_END];
  if (!given[RESUME_FRAME]) c->output.frame_interval = stored[RESUME_FRAME];
  if (!given[RESUME_CSV]) c->output.csv_interval = stored[RESUME_CSV];
  if (!given[RESUME_CKPT]) c->output.checkpoint_interval = stored[RESUME_CKPT];
  c->output.plot = adem_get_i32(rd);
  c->frames_written = adem_get_u64(rd);
  c->csv_last_extra = adem_get_i32(rd);
  uint32_t stage = adem_get_u32(rd);
  uint64_t nruns = adem_get_count(rd, 1);
  char why[ADEM_MSG_MAX];
  if (rd->failed) goto truncated;
  const unsigned char *runs = rd->at;
  rd->at += nruns;
  if ((st = adem_pours_unpack(c->pours, runs, (size_t)nruns, err))) goto mismatch;
  if ((st = adem_stages_load(rd, c, err))) goto mismatch;
  if ((st = adem_outlets_load(rd, c->outlets, err))) goto mismatch;

  bool prepared;
  if ((st = adem_world_load_prepared(rd, &prepared, err))) goto damaged;
  if (!prepared) {
    /* Written before the first step: the loaded case is the whole state. */
    if ((st = adem_stages_resume(c, (int)stage, err))) goto mismatch;
    *out = c;
    return ADEM_OK;
  }
  /* Prepare the freshly loaded world first (derived tables, buffers), then overwrite every
   * piece of dynamic state with the stored one. */
  st = adem_world_prepare(w, err);
  if (st) {
    adem_case_free(c);
    return st;
  }
  /* A new end widens the default escape domain as a run with that end would have it. */
  bool has_domain = w->has_domain;
  adem_vec3 domain_lo = w->domain_lo, domain_hi = w->domain_hi;
  /* The stage in force: its materials, walls and settings, replayed stage start by stage start
   * as the run made them; then the stored state, which has where the walls started their
   * motions from (a servo's travel is not a function of time, the replay cannot know it). */
  if ((st = adem_stages_resume(c, (int)stage, err))) goto mismatch;
  if ((st = adem_world_load(rd, w, err))) goto damaged;
  if (given[RESUME_END]) {
    w->has_domain = has_domain;
    w->domain_lo = domain_lo;
    w->domain_hi = domain_hi;
  }
  char end[8];
  adem_get(rd, end, 8);
  if (rd->failed || memcmp(end, CKPT_END, 8) != 0) goto truncated;
  if (rd->at != rd->end) {
    adem_case_free(c);
    return bad_file(err, path, "it has data after its end marker");
  }
  /* The per-particle sums run over these lists: rebuilt in the order the neighbour build
   * makes them, so the forces of the next step are summed exactly as without the restart. */
  adem_world_place_walls(w, w->time); /* moving walls are a function of time */
  if (adem_world_gather(w) != ADEM_OK) {
    adem_case_free(c);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the contact lists");
  }
  *out = c;
  return ADEM_OK;

truncated:
  adem_case_free(c);
  return bad_file(err, path, "its contents are cut short or damaged");
damaged:
  if (st == ADEM_ERR_NOMEM) {
    adem_case_free(c);
    return st;
  }
  /* fall through: the message says why */
mismatch:
  snprintf(why, sizeof why, "%s", err ? err->message : "its stage or pour state is damaged");
  adem_case_free(c);
  return bad_file(err, path, why);
}

static adem_status check_header(const char *data, size_t len, const char *path, const char *magic,
                                adem_reader *rd, adem_error *err) {
  return adem_checkpoint_header_check(data, len, path, magic, sizeof(adem_contact_history), rd, err);
}

adem_status adem_checkpoint_read_bytes(const char *data, size_t len, const char *path,
                                       adem_case **out, adem_error *err) {
  *out = NULL;
  adem_reader rd;
  adem_status st = check_header(data, len, path, CKPT_MAGIC, &rd, err);
  if (st) return st;
  return restore(&rd, path, NULL, 0, out, err);
}

adem_status adem_world_checkpoint_read(const char *path, adem_world **out, adem_error *err) {
  *out = NULL;
  char *data = NULL;
  size_t len = 0;
  adem_status st = adem_file_read_all(path, &data, &len, err);
  if (st) return st;
  adem_reader rd;
  adem_world *w = NULL;
  st = check_header(data, len, path, CKPT_WORLD_MAGIC, &rd, err);
  if (!st && !(w = adem_world_create())) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  if (!st) st = adem_world_load_setup(&rd, w, err);
  bool prepared = false;
  if (!st) st = adem_world_load_prepared(&rd, &prepared, err);
  /* a prepared world: its tables and buffers first (no particles yet), then the state */
  if (!st && prepared) st = adem_world_prepare(w, err);
  if (!st) st = adem_world_load(&rd, w, err);
  char end[8] = "";
  if (!st) {
    adem_get(&rd, end, 8);
    if (rd.failed || memcmp(end, CKPT_END, 8) != 0 || rd.at != rd.end)
      st = bad_file(err, path, "its contents are cut short or damaged");
  }
  if (!st && prepared) {
    adem_world_place_walls(w, w->time);
    if (adem_world_gather(w) != ADEM_OK) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  if (st && st != ADEM_ERR_NOMEM && strstr(err ? err->message : "", "adem checkpoint") == NULL) {
    char why[ADEM_MSG_MAX];
    snprintf(why, sizeof why, "%s", err ? err->message : "damaged");
    st = bad_file(err, path, why);
  }
  free(data);
  if (st) {
    adem_world_free(w);
    return st;
  }
  *out = w;
  return ADEM_OK;
}

adem_status adem_checkpoint_read_with(const char *path, const char *const *sets, int nsets,
                                      adem_case **out, adem_error *err) {
  *out = NULL;
  if (nsets < 0 || (nsets > 0 && !sets))
    return adem_error_set(err, ADEM_ERR_INPUT, "adem_checkpoint_read_with: no sets");
  bool given[RESUME_KEYS];
  adem_status st = resume_sets_check(sets, nsets, given, err);
  if (st) return st;
  char *data = NULL;
  size_t len = 0;
  st = adem_file_read_all(path, &data, &len, err);
  if (st) return st;
  adem_reader rd;
  st = check_header(data, len, path, CKPT_MAGIC, &rd, err);
  if (!st) st = restore(&rd, path, sets, nsets, out, err);
  free(data);
  if (!st && given[RESUME_END] && (*out)->end_time < adem_world_time((*out)->world)) {
    st = adem_error_set(err, ADEM_ERR_INPUT,
                        "--set time.end=%g: the checkpoint %s is at t = %.9g s already; give a "
                        "later end",
                        (*out)->end_time, path, adem_world_time((*out)->world));
    adem_case_free(*out);
    *out = NULL;
  }
  return st;
}

adem_status adem_checkpoint_read(const char *path, adem_case **out, adem_error *err) {
  return adem_checkpoint_read_with(path, NULL, 0, out, err);
}
