/* Checkpoints: the case text (to rebuild materials, walls and settings) and the whole dynamic
 * state of the world, so that a resumed run continues bit for bit.
 *
 * Layout, all in the writing machine's byte order (checked by a marker):
 *   header  "ADEMCKPT", u32 version, u32 0x01020304, u64 payload bytes, u64 FNV-1a of the
 *           payload, u32 sizeof(adem_vec3), u32 sizeof(adem_contact_history)
 *   payload case: source text, --set strings, path, base folder, end time, dt, output settings,
 *           the stage in force and the pours' state (streams, counts)
 *           world scalars: time, step, dt, next_id, energy_initial, gravity, limits, skin
 *           groups and planes (planes may move), particles (every array, current order),
 *           the pp and pw pair lists (pairs, history, touching flags and per-pair results),
 *           the particle-mesh pairs (the same, plus region keys, owning triangles and each
 *           particle's slot range) and the force and torque on every mesh face,
 *           "ADEMEND\0"
 * Strings are u64 length + bytes; arrays are u64 count + raw elements. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "fileio.h"
#include "insert.h"
#include "log.h"
#include "stages.h"
#include "world.h"

#define CKPT_MAGIC "ADEMCKPT"
#define CKPT_END "ADEMEND"
#define CKPT_VERSION 3u
#define CKPT_ENDIAN 0x01020304u
#define CKPT_HEADER_BYTES 40u

static uint64_t fnv1a(uint64_t h, const void *data, size_t n) {
  const unsigned char *b = data;
  for (size_t i = 0; i < n; ++i) {
    h ^= b[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}
#define FNV_START 0xcbf29ce484222325ULL

/* ---------------------------------------------------------------- writing */

typedef struct ck_writer {
  FILE *f;
  uint64_t bytes, hash;
  int failed;
} ck_writer;

static void put(ck_writer *wr, const void *data, size_t n) {
  if (wr->failed || n == 0) return;
  if (fwrite(data, 1, n, wr->f) != n) {
    wr->failed = 1;
    return;
  }
  wr->bytes += n;
  wr->hash = fnv1a(wr->hash, data, n);
}
static void put_u8(ck_writer *wr, uint8_t v) { put(wr, &v, 1); }
static void put_u32(ck_writer *wr, uint32_t v) { put(wr, &v, 4); }
static void put_i32(ck_writer *wr, int32_t v) { put(wr, &v, 4); }
static void put_u64(ck_writer *wr, uint64_t v) { put(wr, &v, 8); }
static void put_f64(ck_writer *wr, double v) { put(wr, &v, 8); }
static void put_vec(ck_writer *wr, adem_vec3 v) { put(wr, &v, sizeof v); }
static void put_str(ck_writer *wr, const char *s) {
  size_t n = s ? strlen(s) : 0;
  put_u64(wr, n);
  put(wr, s, n);
}
static void put_array(ck_writer *wr, const void *data, size_t count, size_t elem) {
  put_u64(wr, count);
  put(wr, data, count * elem);
}
static void put_bools(ck_writer *wr, const bool *b, size_t n) {
  put_u64(wr, n);
  uint8_t buf[4096];
  for (size_t i = 0; i < n; i += sizeof buf) {
    size_t k = n - i < sizeof buf ? n - i : sizeof buf;
    for (size_t j = 0; j < k; ++j) buf[j] = b[i + j] ? 1 : 0;
    put(wr, buf, k);
  }
}

static void put_pairs(ck_writer *wr, const adem_pair_list *l) {
  size_t n = l->n;
  put_u64(wr, n);
  put_array(wr, l->a, n, sizeof *l->a);
  put_array(wr, l->b, n, sizeof *l->b);
  put_array(wr, l->hist, n, sizeof *l->hist);
  put_bools(wr, l->touching, n);
  put_array(wr, l->force_a, n, sizeof *l->force_a);
  put_array(wr, l->torque_a, n, sizeof *l->torque_a);
  put_array(wr, l->torque_b, n, sizeof *l->torque_b);
  put_array(wr, l->rolling_a, n, sizeof *l->rolling_a);
  put_array(wr, l->rolling_capacity, n, sizeof *l->rolling_capacity);
  put_array(wr, l->elastic, n, sizeof *l->elastic);
  put_array(wr, l->overlap_ratio, n, sizeof *l->overlap_ratio);
}

/* Particle-mesh contacts: the pair list, the slots' region keys and triangles, each particle's
 * slot range, and the loads on the faces. */
static void put_mesh_state(ck_writer *wr, const adem_world *w) {
  const adem_mesh_pairs *pm = &w->pm;
  size_t n = pm->l.n;
  put_pairs(wr, &pm->l);
  put_array(wr, pm->key, n, sizeof *pm->key);
  put_array(wr, pm->owner, n, sizeof *pm->owner);
  size_t ns = pm->start ? w->p.n + 1 : 0;
  put_u64(wr, ns);
  for (size_t i = 0; i < ns; ++i) put_u64(wr, pm->start[i]);
  size_t nf = 3 * w->mesh.ntris;
  put_array(wr, w->face_force, nf, sizeof *w->face_force);
  put_array(wr, w->face_torque, nf, sizeof *w->face_torque);
}

static void put_header(ck_writer *wr, uint64_t payload_bytes, uint64_t hash) {
  unsigned char h[CKPT_HEADER_BYTES];
  uint32_t version = CKPT_VERSION, endian = CKPT_ENDIAN;
  uint32_t vec_size = sizeof(adem_vec3), hist_size = sizeof(adem_contact_history);
  memcpy(h, CKPT_MAGIC, 8);
  memcpy(h + 8, &version, 4);
  memcpy(h + 12, &endian, 4);
  memcpy(h + 16, &payload_bytes, 8);
  memcpy(h + 24, &hash, 8);
  memcpy(h + 32, &vec_size, 4);
  memcpy(h + 36, &hist_size, 4);
  if (fwrite(h, 1, sizeof h, wr->f) != sizeof h) wr->failed = 1;
}

adem_status adem_checkpoint_write(const adem_case *c, const char *path, adem_error *err) {
  const adem_world *w = c->world;
  const adem_particles *p = &w->p;
  adem_afile af;
  adem_status st = adem_fileio_open(&af, path, err);
  if (st) return st;
  ck_writer wr = {af.f, 0, FNV_START, 0};
  put_header(&wr, 0, 0); /* rewritten once the payload's size and hash are known */

  /* The case, to be loaded again. */
  put_str(&wr, c->source);
  put_u32(&wr, (uint32_t)c->nsets);
  for (int k = 0; k < c->nsets; ++k) put_str(&wr, c->sets[k]);
  put_str(&wr, c->path);
  put_str(&wr, c->base_dir); /* mesh files are found from it, whatever the working folder */
  /* Settings a caller may have changed after loading (--out, a shorter end time). */
  put_f64(&wr, c->end_time);
  put_f64(&wr, c->dt);
  put_i32(&wr, c->dt_auto);
  put_str(&wr, c->output.dir);
  put_f64(&wr, c->output.frame_interval);
  put_f64(&wr, c->output.csv_interval);
  put_f64(&wr, c->output.checkpoint_interval);
  put_i32(&wr, c->output.plot);
  /* Staged runs and pours: the stage in force (its configuration is replayed from the case) and
   * the pours' random streams and counts. */
  put_u32(&wr, (uint32_t)adem_stages_current(c));
  size_t nruns = 0;
  unsigned char *runs = adem_pours_pack(c->pours, &nruns);
  if (!runs) wr.failed = 1;
  put_array(&wr, runs, nruns, 1);
  free(runs);

  /* World scalars. */
  put_u8(&wr, w->prepared ? 1 : 0);
  put_f64(&wr, w->time);
  put_u64(&wr, w->step);
  put_f64(&wr, w->dt);
  put_u64(&wr, w->next_id);
  put_f64(&wr, w->energy_initial);
  put_vec(&wr, w->gravity);
  put_f64(&wr, w->max_overlap_ratio);
  put_u8(&wr, w->has_domain ? 1 : 0);
  put_vec(&wr, w->domain_lo);
  put_vec(&wr, w->domain_hi);
  put_f64(&wr, w->nb.skin);
  put_f64(&wr, w->nb.skin_fraction);
  put_u8(&wr, w->nb.brute_force ? 1 : 0);
  put_u64(&wr, w->nb.rebuilds);
  put_f64(&wr, w->nb.time_at_build);
  put_u32(&wr, (uint32_t)w->nmaterials);
  put_u32(&wr, (uint32_t)w->ngroups);
  for (int k = 0; k < w->ngroups; ++k) put_vec(&wr, w->groups[k].external_force);
  put_u32(&wr, (uint32_t)w->nplanes);
  for (int k = 0; k < w->nplanes; ++k) {
    const adem_plane_def *d = &w->planes[k].def;
    put_str(&wr, d->name);
    put_vec(&wr, d->point);
    put_vec(&wr, d->normal);
    put_vec(&wr, d->velocity);
    put_i32(&wr, d->material);
  }

  /* Particles, in their current (cell-sorted) order. */
  size_t n = p->n;
  put_u64(&wr, n);
  put_array(&wr, p->pos, n, sizeof *p->pos);
  put_array(&wr, p->vel, n, sizeof *p->vel);
  put_array(&wr, p->omega, n, sizeof *p->omega);
  put_array(&wr, p->force, n, sizeof *p->force);
  put_array(&wr, p->torque, n, sizeof *p->torque);
  put_array(&wr, p->radius, n, sizeof *p->radius);
  put_array(&wr, p->inv_mass, n, sizeof *p->inv_mass);
  put_array(&wr, p->inv_inertia, n, sizeof *p->inv_inertia);
  put_array(&wr, p->id, n, sizeof *p->id);
  put_array(&wr, p->material, n, sizeof *p->material);
  put_array(&wr, p->group, n, sizeof *p->group);
  put_array(&wr, p->pos_at_build, n, sizeof *p->pos_at_build);
  put_array(&wr, p->rolling_torque, n, sizeof *p->rolling_torque);
  put_array(&wr, p->path_length, n, sizeof *p->path_length);

  put_pairs(&wr, &w->pp);
  put_pairs(&wr, &w->pw);
  put_mesh_state(&wr, w);
  put(&wr, CKPT_END, 8);

  if (!wr.failed) {
    uint64_t bytes = wr.bytes, hash = wr.hash;
    if (fseek(af.f, 0, SEEK_SET) != 0) wr.failed = 1;
    else put_header(&wr, bytes, hash);
  }
  if (wr.failed) {
    int e = errno ? errno : EIO;
    adem_fileio_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write checkpoint %s: %s", path, strerror(e));
  }
  return adem_fileio_commit(&af, err);
}

/* ---------------------------------------------------------------- reading */

typedef struct ck_reader {
  const unsigned char *at, *end;
  int short_read;
} ck_reader;

static int get(ck_reader *rd, void *out, size_t n) {
  if (rd->short_read || (size_t)(rd->end - rd->at) < n) {
    rd->short_read = 1;
    if (out && n) memset(out, 0, n);
    return 0;
  }
  if (n) memcpy(out, rd->at, n);
  rd->at += n;
  return 1;
}
static uint8_t get_u8(ck_reader *rd) { uint8_t v; get(rd, &v, 1); return v; }
static uint32_t get_u32(ck_reader *rd) { uint32_t v; get(rd, &v, 4); return v; }
static int32_t get_i32(ck_reader *rd) { int32_t v; get(rd, &v, 4); return v; }
static uint64_t get_u64(ck_reader *rd) { uint64_t v; get(rd, &v, 8); return v; }
static double get_f64(ck_reader *rd) { double v; get(rd, &v, 8); return v; }
static adem_vec3 get_vec(ck_reader *rd) { adem_vec3 v; get(rd, &v, sizeof v); return v; }

/* A fresh NUL-terminated string, or NULL (short_read set, or out of memory: *nomem). */
static char *get_str(ck_reader *rd, int *nomem) {
  uint64_t n = get_u64(rd);
  if (rd->short_read || n > (uint64_t)(rd->end - rd->at)) {
    rd->short_read = 1;
    return NULL;
  }
  char *s = malloc((size_t)n + 1);
  if (!s) {
    *nomem = 1;
    return NULL;
  }
  get(rd, s, (size_t)n);
  s[n] = '\0';
  return s;
}
static void get_str_into(ck_reader *rd, char *dst, size_t cap) {
  uint64_t n = get_u64(rd);
  if (rd->short_read || n >= cap || n > (uint64_t)(rd->end - rd->at)) {
    rd->short_read = 1;
    dst[0] = '\0';
    return;
  }
  get(rd, dst, (size_t)n);
  dst[n] = '\0';
}
/* An array of exactly count elements. */
static void get_array(ck_reader *rd, void *dst, size_t count, size_t elem) {
  uint64_t n = get_u64(rd);
  if (n != count) {
    rd->short_read = 1;
    return;
  }
  get(rd, dst, count * elem);
}

static adem_status get_pairs(ck_reader *rd, adem_pair_list *l, adem_error *err) {
  uint64_t n = get_u64(rd);
  /* Each pair takes well over 8 bytes: a larger count means a damaged file, not a huge list. */
  if (rd->short_read || n > (uint64_t)(rd->end - rd->at) / 8) {
    rd->short_read = 1;
    return ADEM_OK;
  }
  if (n > l->cap && adem_pair_list_reserve(l, (size_t)n) != ADEM_OK)
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %llu pairs", (unsigned long long)n);
  l->n = (size_t)n;
  get_array(rd, l->a, l->n, sizeof *l->a);
  get_array(rd, l->b, l->n, sizeof *l->b);
  get_array(rd, l->hist, l->n, sizeof *l->hist);
  if (get_u64(rd) != n) rd->short_read = 1;
  for (size_t k = 0; k < l->n && !rd->short_read; ++k) l->touching[k] = get_u8(rd) != 0;
  get_array(rd, l->force_a, l->n, sizeof *l->force_a);
  get_array(rd, l->torque_a, l->n, sizeof *l->torque_a);
  get_array(rd, l->torque_b, l->n, sizeof *l->torque_b);
  get_array(rd, l->rolling_a, l->n, sizeof *l->rolling_a);
  get_array(rd, l->rolling_capacity, l->n, sizeof *l->rolling_capacity);
  get_array(rd, l->elastic, l->n, sizeof *l->elastic);
  get_array(rd, l->overlap_ratio, l->n, sizeof *l->overlap_ratio);
  return ADEM_OK;
}

static adem_status get_mesh_state(ck_reader *rd, adem_world *w, adem_error *err) {
  adem_mesh_pairs *pm = &w->pm;
  adem_status st = get_pairs(rd, &pm->l, err);
  if (st || rd->short_read) return st;
  if (adem_mesh_pairs_reserve(pm))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the mesh contacts");
  size_t n = pm->l.n;
  get_array(rd, pm->key, n, sizeof *pm->key);
  get_array(rd, pm->owner, n, sizeof *pm->owner);
  uint64_t ns = get_u64(rd);
  if (rd->short_read || (ns != 0 && ns != (uint64_t)w->p.n + 1)) {
    rd->short_read = 1;
    return ADEM_OK;
  }
  if (ns > pm->start_cap) {
    size_t *q = realloc(pm->start, (size_t)ns * sizeof *q);
    if (!q) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the mesh contacts");
    pm->start = q;
    pm->start_cap = (size_t)ns;
  }
  for (size_t i = 0; i < ns; ++i) pm->start[i] = (size_t)get_u64(rd);
  size_t nf = 3 * w->mesh.ntris;
  get_array(rd, w->face_force, nf, sizeof *w->face_force);
  get_array(rd, w->face_torque, nf, sizeof *w->face_torque);
  return ADEM_OK;
}

/* Slot ranges that tile the list in particle order, particles and triangles that exist. */
static bool mesh_state_consistent(const adem_world *w) {
  const adem_mesh_pairs *pm = &w->pm;
  size_t n = w->p.n;
  if (!pm->start) return pm->l.n == 0;
  /* The stepper walks every particle's range, contacts or not: all n + 1 bounds must be there. */
  if (pm->start_cap < n + 1 || pm->start[0] != 0 || pm->start[n] != pm->l.n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (pm->start[i + 1] < pm->start[i] || pm->start[i + 1] > pm->l.n) return false;
    for (size_t k = pm->start[i]; k < pm->start[i + 1]; ++k)
      if (pm->l.a[k] != i || pm->l.b[k] >= w->mesh.ntris ||
          (pm->l.touching[k] && pm->owner[k] >= w->mesh.ntris))
        return false;
  }
  return true;
}

static adem_status bad_file(adem_error *err, const char *path, const char *why) {
  return adem_error_set(err, ADEM_ERR_INPUT, "%s is not a usable adem checkpoint: %s", path, why);
}

/* Parses the payload into a freshly loaded case. */
static adem_status restore(ck_reader *rd, const char *path, adem_case **out, adem_error *err) {
  int nomem = 0;
  char *source = get_str(rd, &nomem);
  uint32_t nsets = get_u32(rd);
  if (rd->short_read || nsets > (uint64_t)(rd->end - rd->at) / 8) {
    free(source);
    return bad_file(err, path, "it is truncated (case section)");
  }
  char **sets = calloc(nsets ? nsets : 1, sizeof *sets);
  if (!sets) nomem = 1;
  for (uint32_t k = 0; k < nsets && sets; ++k) sets[k] = get_str(rd, &nomem);
  char *case_path = get_str(rd, &nomem);
  char *base_dir = get_str(rd, &nomem);
  adem_status st = ADEM_OK;
  adem_case *c = NULL;
  if (nomem) {
    st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory reading %s", path);
  } else if (rd->short_read || !source || !case_path || !base_dir) {
    st = bad_file(err, path, "it is truncated (case section)");
  } else {
    st = adem_case_load_string_at(source, case_path, base_dir, (const char *const *)sets, (int)nsets,
                                  &c, err);
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
  if (st) return st;

  adem_world *w = c->world;
  c->end_time = get_f64(rd);
  c->dt = get_f64(rd);
  c->dt_auto = get_i32(rd);
  get_str_into(rd, c->output.dir, sizeof c->output.dir);
  c->output.frame_interval = get_f64(rd);
  c->output.csv_interval = get_f64(rd);
  c->output.checkpoint_interval = get_f64(rd);
  c->output.plot = get_i32(rd);
  uint32_t stage = get_u32(rd);
  uint64_t nruns = get_u64(rd);
  if (rd->short_read || nruns > (uint64_t)(rd->end - rd->at)) goto truncated;
  const unsigned char *runs = rd->at;
  rd->at += nruns;
  if ((st = adem_pours_unpack(c->pours, runs, (size_t)nruns, err))) goto mismatch;

  bool prepared = get_u8(rd) != 0;
  if (rd->short_read) goto truncated;
  if (!prepared) {
    /* Written before the first step: the loaded case is the whole state. */
    adem_world_set_dt(w, c->dt);
    if ((st = adem_stages_resume(c, (int)stage, err))) goto mismatch;
    *out = c;
    return ADEM_OK;
  }
  /* Prepare the freshly loaded world first (derived tables, buffers), then overwrite every
   * piece of dynamic state with the stored one. */
  adem_world_set_dt(w, c->dt);
  st = adem_world_prepare(w, err);
  if (st) {
    adem_case_free(c);
    return st;
  }
  w->time = get_f64(rd);
  w->step = get_u64(rd);
  w->dt = get_f64(rd);
  w->next_id = get_u64(rd);
  w->energy_initial = get_f64(rd);
  w->gravity = get_vec(rd);
  w->max_overlap_ratio = get_f64(rd);
  w->has_domain = get_u8(rd) != 0;
  w->domain_lo = get_vec(rd);
  w->domain_hi = get_vec(rd);
  w->nb.skin = get_f64(rd);
  w->nb.skin_fraction = get_f64(rd);
  w->nb.brute_force = get_u8(rd) != 0;
  w->nb.rebuilds = get_u64(rd);
  w->nb.time_at_build = get_f64(rd);
  uint32_t nmat = get_u32(rd);
  uint32_t ngroups = get_u32(rd);
  if (rd->short_read) goto truncated;
  if (nmat != (uint32_t)w->nmaterials || ngroups != (uint32_t)w->ngroups) {
    adem_case_free(c);
    return bad_file(err, path, "its materials or groups do not match its own case text");
  }
  for (int k = 0; k < w->ngroups; ++k) w->groups[k].external_force = get_vec(rd);
  uint32_t nplanes = get_u32(rd);
  if (rd->short_read) goto truncated;
  if (nplanes != (uint32_t)w->nplanes) {
    adem_case_free(c);
    return bad_file(err, path, "its walls do not match its own case text");
  }
  for (int k = 0; k < w->nplanes; ++k) {
    adem_plane_def *d = &w->planes[k].def;
    get_str_into(rd, d->name, sizeof d->name);
    d->point = get_vec(rd);
    d->normal = get_vec(rd);
    d->velocity = get_vec(rd);
    d->material = get_i32(rd);
  }

  adem_particles *p = &w->p;
  uint64_t n = get_u64(rd);
  /* A particle takes about 200 bytes: a larger count is a damaged file. */
  if (rd->short_read || n > (uint64_t)(rd->end - rd->at) / 64) goto truncated;
  if (n > p->cap && adem_particles_reserve(p, (size_t)n) != ADEM_OK) {
    adem_case_free(c);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %llu particles",
                          (unsigned long long)n);
  }
  p->n = (size_t)n;
  get_array(rd, p->pos, p->n, sizeof *p->pos);
  get_array(rd, p->vel, p->n, sizeof *p->vel);
  get_array(rd, p->omega, p->n, sizeof *p->omega);
  get_array(rd, p->force, p->n, sizeof *p->force);
  get_array(rd, p->torque, p->n, sizeof *p->torque);
  get_array(rd, p->radius, p->n, sizeof *p->radius);
  get_array(rd, p->inv_mass, p->n, sizeof *p->inv_mass);
  get_array(rd, p->inv_inertia, p->n, sizeof *p->inv_inertia);
  get_array(rd, p->id, p->n, sizeof *p->id);
  get_array(rd, p->material, p->n, sizeof *p->material);
  get_array(rd, p->group, p->n, sizeof *p->group);
  get_array(rd, p->pos_at_build, p->n, sizeof *p->pos_at_build);
  get_array(rd, p->rolling_torque, p->n, sizeof *p->rolling_torque);
  get_array(rd, p->path_length, p->n, sizeof *p->path_length);
  if (rd->short_read) goto truncated;

  if ((st = get_pairs(rd, &w->pp, err)) || (st = get_pairs(rd, &w->pw, err)) ||
      (st = get_mesh_state(rd, w, err))) {
    adem_case_free(c);
    return st;
  }
  char end[8];
  get(rd, end, 8);
  if (rd->short_read || memcmp(end, CKPT_END, 8) != 0) goto truncated;
  if (rd->at != rd->end) {
    adem_case_free(c);
    return bad_file(err, path, "it has data after its end marker");
  }
  /* Indices must be in range before the gather lists and the stepper use them. */
  for (size_t k = 0; k < w->pp.n; ++k)
    if (w->pp.a[k] >= p->n || w->pp.b[k] >= p->n) goto inconsistent;
  for (size_t k = 0; k < w->pw.n; ++k)
    if (w->pw.a[k] >= p->n || w->pw.b[k] >= (uint32_t)w->nplanes) goto inconsistent;
  if (!mesh_state_consistent(w)) goto inconsistent;
  for (size_t i = 0; i < p->n; ++i)
    if (p->material[i] >= w->nmaterials || (w->ngroups > 0 && p->group[i] >= w->ngroups))
      goto inconsistent;
  for (int k = 0; k < w->nplanes; ++k)
    if (w->planes[k].def.material < 0 || w->planes[k].def.material >= w->nmaterials)
      goto inconsistent;
  /* What sizes the cell grid and the step must be finite and positive (a zero cell size would
   * never fit the grid), as the case loader requires of them. */
  if (!(w->dt > 0.0) || !isfinite(w->dt) || !(w->nb.skin_fraction > 0.0) ||
      !isfinite(w->nb.skin_fraction) || !(w->nb.skin >= 0.0) || !isfinite(w->nb.skin))
    goto not_finite;
  for (size_t i = 0; i < p->n; ++i)
    if (!(p->radius[i] > 0.0) || !isfinite(p->radius[i]) || !v3_isfinite(p->pos[i]))
      goto not_finite;
  c->dt = w->dt;
  /* The stage in force: its materials, walls and settings, replayed stage start by stage start
   * as the run made them (walls that started a new motion start it from where they were). */
  if ((st = adem_stages_resume(c, (int)stage, err))) goto mismatch;
  /* The per-particle sums run over these lists: rebuilt in the order the neighbour build
   * makes them, so the forces of the next step are summed exactly as without the restart. */
  adem_world_place_walls(w, w->time); /* moving walls are a function of time */
  if (adem_neighbors_gather(w) != ADEM_OK) {
    adem_case_free(c);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the contact lists");
  }
  *out = c;
  return ADEM_OK;

truncated:
  adem_case_free(c);
  return bad_file(err, path, "its contents are cut short or damaged");
not_finite:
  adem_case_free(c);
  return bad_file(err, path, "its time step, skin, radii or positions are not finite and positive");
inconsistent:
  adem_case_free(c);
  return bad_file(err, path, "its particle, pair or wall indices are out of range");
mismatch: {
  char why[ADEM_MSG_MAX];
  snprintf(why, sizeof why, "%s", err ? err->message : "its stage or pour state is damaged");
  adem_case_free(c);
  return bad_file(err, path, why);
}
}

adem_status adem_checkpoint_read(const char *path, adem_case **out, adem_error *err) {
  *out = NULL;
  char *data = NULL;
  size_t len = 0;
  adem_status st = adem_fileio_read_all(path, &data, &len, err);
  if (st) return st;
  const unsigned char *b = (const unsigned char *)data;
  if (len < 8 || memcmp(b, CKPT_MAGIC, 8) != 0) {
    free(data);
    return bad_file(err, path, "it does not start with ADEMCKPT (not a checkpoint)");
  }
  if (len < CKPT_HEADER_BYTES) {
    free(data);
    return bad_file(err, path, "it is truncated (header)");
  }
  uint32_t version, endian, vec_size, hist_size;
  uint64_t payload, hash;
  memcpy(&version, b + 8, 4);
  memcpy(&endian, b + 12, 4);
  memcpy(&payload, b + 16, 8);
  memcpy(&hash, b + 24, 8);
  memcpy(&vec_size, b + 32, 4);
  memcpy(&hist_size, b + 36, 4);
  char why[160];
  if (endian != CKPT_ENDIAN) {
    st = bad_file(err, path, "it was written on a machine with another byte order");
  } else if (version != CKPT_VERSION) {
    snprintf(why, sizeof why, "it has format version %u, this adem reads version %u", version,
             CKPT_VERSION);
    st = bad_file(err, path, why);
  } else if (vec_size != sizeof(adem_vec3) || hist_size != sizeof(adem_contact_history)) {
    st = bad_file(err, path, "it was written by a build with another contact-history layout");
  } else if (payload != (uint64_t)(len - CKPT_HEADER_BYTES)) {
    snprintf(why, sizeof why, "it is %s: %zu bytes instead of %llu",
             payload > (uint64_t)(len - CKPT_HEADER_BYTES) ? "truncated" : "too long", len,
             (unsigned long long)(payload + CKPT_HEADER_BYTES));
    st = bad_file(err, path, why);
  } else if (fnv1a(FNV_START, b + CKPT_HEADER_BYTES, (size_t)payload) != hash) {
    st = bad_file(err, path, "its checksum does not match (the file is damaged)");
  }
  if (!st) {
    ck_reader rd = {b + CKPT_HEADER_BYTES, b + len, 0};
    st = restore(&rd, path, out, err);
  }
  free(data);
  return st;
}
