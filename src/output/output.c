#include "output.h"
#include "adem/internal/plot.h"
#include "vtu.h"

#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "adem/files.h"
#include "log.h"
#include "world_internal.h"
#include "cylinder.h"

_Static_assert(sizeof(adem_vec3) == 3 * sizeof(double), "adem_vec3 must be three packed doubles");

/* ---------------------------------------------------------------- VTU */

static int put_raw(FILE *f, const void *data, size_t nbytes) {
  return nbytes == 0 || fwrite(data, 1, nbytes, f) == nbytes;
}

/* Arrays that must be converted or generated are written through a small buffer. */
enum { CHUNK = 4096 };

static int put_material(FILE *f, const uint16_t *m, size_t n) {
  int32_t buf[CHUNK];
  for (size_t i = 0; i < n; i += CHUNK) {
    size_t k = n - i < CHUNK ? n - i : CHUNK;
    for (size_t j = 0; j < k; ++j) buf[j] = m[i + j];
    if (fwrite(buf, sizeof buf[0], k, f) != k) return 0;
  }
  return 1;
}

/* connectivity (first = 0) or offsets (first = 1): 0..n-1 or 1..n. */
static int put_counting(FILE *f, size_t n, int64_t first) {
  int64_t buf[CHUNK];
  for (size_t i = 0; i < n; i += CHUNK) {
    size_t k = n - i < CHUNK ? n - i : CHUNK;
    for (size_t j = 0; j < k; ++j) buf[j] = (int64_t)(i + j) + first;
    if (fwrite(buf, sizeof buf[0], k, f) != k) return 0;
  }
  return 1;
}

static int put_types(FILE *f, size_t n) {
  uint8_t buf[CHUNK];
  memset(buf, 1, sizeof buf); /* VTK_VERTEX */
  for (size_t i = 0; i < n; i += CHUNK) {
    size_t k = n - i < CHUNK ? n - i : CHUNK;
    if (fwrite(buf, 1, k, f) != k) return 0;
  }
  return 1;
}

/* The particles a frame writes: all of them in storage order (idx NULL), or those at idx. */
typedef struct frame_set {
  const adem_particles *p;
  const uint32_t *idx;
  size_t n;
} frame_set;

/* Elements idx[0..n) of an array of elem-byte elements, through a small buffer. */
static int put_picked(FILE *f, const void *base, size_t elem, const uint32_t *idx, size_t n) {
  unsigned char buf[CHUNK * 8];
  size_t per = sizeof buf / elem;
  for (size_t i = 0; i < n; i += per) {
    size_t k = n - i < per ? n - i : per;
    for (size_t j = 0; j < k; ++j)
      memcpy(buf + j * elem, (const unsigned char *)base + (size_t)idx[i + j] * elem, elem);
    if (fwrite(buf, elem, k, f) != k) return 0;
  }
  return 1;
}

static int put_material_picked(FILE *f, const uint16_t *m, const uint32_t *idx, size_t n) {
  int32_t buf[CHUNK];
  for (size_t i = 0; i < n; i += CHUNK) {
    size_t k = n - i < CHUNK ? n - i : CHUNK;
    for (size_t j = 0; j < k; ++j) buf[j] = m[idx[i + j]];
    if (fwrite(buf, sizeof buf[0], k, f) != k) return 0;
  }
  return 1;
}

/* The masses (1 / inverse mass) of the particles at idx (idx NULL: the first n): what the
 * coarse-grained fields weigh them by (adem analyze fields). */
static int put_mass(FILE *f, const double *inv_mass, const uint32_t *idx, size_t n) {
  double buf[CHUNK];
  for (size_t i = 0; i < n; i += CHUNK) {
    size_t k = n - i < CHUNK ? n - i : CHUNK;
    for (size_t j = 0; j < k; ++j) buf[j] = 1.0 / inv_mass[idx ? idx[i + j] : i + j];
    if (fwrite(buf, sizeof buf[0], k, f) != k) return 0;
  }
  return 1;
}

/* Array k of a frame of the particles at idx. */
static int put_picked_array(FILE *f, int k, const frame_set *fs) {
  const adem_particles *p = fs->p;
  const uint32_t *x = fs->idx;
  size_t n = fs->n;
  switch (k) {
    case 0: return put_picked(f, p->radius, sizeof *p->radius, x, n);
    case 1: return put_picked(f, p->id, sizeof *p->id, x, n);
    case 2: return put_material_picked(f, p->material, x, n);
    case 3: return put_picked(f, p->vel, sizeof *p->vel, x, n);
    case 4: return put_picked(f, p->omega, sizeof *p->omega, x, n);
    case 5: return put_picked(f, p->force, sizeof *p->force, x, n);
    case 6: return put_picked(f, p->rolling_torque, sizeof *p->rolling_torque, x, n);
    case 7: return put_mass(f, p->inv_mass, x, n);
    case 8: return put_picked(f, p->pos, sizeof *p->pos, x, n);
    case 9: return put_counting(f, n, 0);
    case 10: return put_counting(f, n, 1);
    default: return put_types(f, n);
  }
}

/* Array k of a particle frame (the order of the table in adem_output_write_vtu). */
static int put_particle_array(FILE *f, int k, void *user) {
  const frame_set *fs = user;
  if (fs->idx) return put_picked_array(f, k, fs);
  const adem_particles *p = fs->p;
  size_t n = p->n;
  switch (k) {
    case 0: return put_raw(f, p->radius, n * sizeof *p->radius);
    case 1: return put_raw(f, p->id, n * sizeof *p->id); /* ids < 2^63: same bits as Int64 */
    case 2: return put_material(f, p->material, n);
    case 3: return put_raw(f, p->vel, n * sizeof *p->vel);
    case 4: return put_raw(f, p->omega, n * sizeof *p->omega);
    case 5: return put_raw(f, p->force, n * sizeof *p->force);
    case 6: return put_raw(f, p->rolling_torque, n * sizeof *p->rolling_torque); /* every model */
    case 7: return put_mass(f, p->inv_mass, NULL, n);
    case 8: return put_raw(f, p->pos, n * sizeof *p->pos);
    case 9: return put_counting(f, n, 0);
    case 10: return put_counting(f, n, 1);
    default: return put_types(f, n);
  }
}

/* The point arrays of a particle frame, as the .vtu and the .pvtu list them. */
static const struct {
  const char *name, *type;
  int ncomp;
} frame_arrays[] = {{"radius", "Float64", 1}, {"id", "Int64", 1}, {"material", "Int32", 1}, {"velocity", "Float64", 3}, {"angular_velocity", "Float64", 3}, {"force", "Float64", 3}, {"rolling_torque", "Float64", 3}, {"mass", "Float64", 1}};

adem_status adem_output_write_vtu(const adem_world *w, const char *path, adem_error *err) {
  return adem_output_write_vtu_of(w, NULL, w->p.n, path, err);
}

adem_status adem_output_write_vtu_of(const adem_world *w, const uint32_t *idx, size_t count,
                                     const char *path, adem_error *err) {
  const adem_particles *p = &w->p;
  const size_t n = idx ? count : p->n;
  frame_set fs = {p, idx, n};
  /* Arrays in the order they are appended. */
  const adem_vtu_array arr[] = {
      {"radius", "Float64", 1, 8 * n},
      {"id", "Int64", 1, 8 * n},
      {"material", "Int32", 1, 4 * n},
      {"velocity", "Float64", 3, 24 * n},
      {"angular_velocity", "Float64", 3, 24 * n},
      {"force", "Float64", 3, 24 * n},
      {"rolling_torque", "Float64", 3, 24 * n},
      {"mass", "Float64", 1, 8 * n},
      {"position", "Float64", 3, 24 * n},
      {"connectivity", "Int64", 1, 8 * n},
      {"offsets", "Int64", 1, 8 * n},
      {"types", "UInt8", 1, n},
  };
  char field[512];
  snprintf(field, sizeof field,
           "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
           "format=\"ascii\">%.17g</DataArray>\n"
           "      <DataArray type=\"Int64\" Name=\"Step\" NumberOfTuples=\"1\" "
           "format=\"ascii\">%" PRIu64 "</DataArray>\n",
           w->time, w->step);
  adem_vtu_layout lay = {n, n, field, "PointData", "Scalars=\"radius\" Vectors=\"velocity\"", 8, 9};
  return adem_vtu_write(path, &lay, arr, (int)(sizeof arr / sizeof arr[0]), put_particle_array,
                        &fs, err);
}

adem_status adem_output_write_pvtu(const char *path, const char *const *pieces, int npieces,
                                   adem_error *err) {
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  FILE *f = af.f;
  fprintf(f,
          "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" "
          "header_type=\"UInt64\">\n"
          "  <PUnstructuredGrid GhostLevel=\"0\">\n"
          "    <PPointData Scalars=\"radius\" Vectors=\"velocity\">\n",
          adem_vtu_byte_order());
  for (size_t k = 0; k < sizeof frame_arrays / sizeof frame_arrays[0]; ++k) {
    fprintf(f, "      <PDataArray type=\"%s\" Name=\"%s\"", frame_arrays[k].type,
            frame_arrays[k].name);
    if (frame_arrays[k].ncomp > 1) fprintf(f, " NumberOfComponents=\"%d\"", frame_arrays[k].ncomp);
    fprintf(f, "/>\n");
  }
  fprintf(f,
          "    </PPointData>\n"
          "    <PPoints>\n"
          "      <PDataArray type=\"Float64\" Name=\"position\" NumberOfComponents=\"3\"/>\n"
          "    </PPoints>\n");
  for (int k = 0; k < npieces; ++k) fprintf(f, "    <Piece Source=\"%s\"/>\n", pieces[k]);
  fprintf(f, "  </PUnstructuredGrid>\n</VTKFile>\n");
  if (ferror(f)) {
    adem_file_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s", path);
  }
  return adem_file_commit(&af, err);
}

/* ---------------------------------------------------------------- PVD */

adem_status adem_output_pvd_add(adem_pvd *pvd, double time, const char *file, adem_error *err) {
  if (pvd->n == pvd->cap) {
    size_t cap = pvd->cap ? 2 * pvd->cap : 64;
    double *t = realloc(pvd->time, cap * sizeof *t);
    if (t) pvd->time = t;
    char **fl = realloc(pvd->file, cap * sizeof *fl);
    if (fl) pvd->file = fl;
    if (!t || !fl) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the PVD list");
    pvd->cap = cap;
  }
  size_t len = strlen(file) + 1;
  char *copy = malloc(len);
  if (!copy) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the PVD list");
  memcpy(copy, file, len);
  pvd->time[pvd->n] = time;
  pvd->file[pvd->n] = copy;
  pvd->n++;
  return ADEM_OK;
}

adem_status adem_output_pvd_write(const adem_pvd *pvd, const char *path, adem_error *err) {
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  fprintf(af.f,
          "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"%s\">\n"
          "  <Collection>\n",
          adem_vtu_byte_order());
  for (size_t k = 0; k < pvd->n; ++k)
    fprintf(af.f, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"%s\"/>\n",
            pvd->time[k], pvd->file[k]);
  fprintf(af.f, "  </Collection>\n</VTKFile>\n");
  return adem_file_commit(&af, err);
}

void adem_output_pvd_free(adem_pvd *pvd) {
  for (size_t k = 0; k < pvd->n; ++k) free(pvd->file[k]);
  free(pvd->file);
  free(pvd->time);
  memset(pvd, 0, sizeof *pvd);
}

/* Frame file name relative to the output folder. */
static void frame_name(char *buf, size_t cap, size_t index) {
  snprintf(buf, cap, "frames/particles_%06zu.vtu", index);
}

/* frames/particles_NNNNNN_pK.vtu, relative to the output folder (piece < 0: the .pvtu). */
static void piece_name(char *buf, size_t cap, size_t index, int piece) {
  if (piece < 0) snprintf(buf, cap, "frames/particles_%06zu.pvtu", index);
  else snprintf(buf, cap, "frames/particles_%06zu_p%d.vtu", index, piece);
}

/* Reads the times of frames 0..frames_done-1 back from a PVD we wrote earlier. Entries that
 * cannot be found get k * frame_period. */
static adem_status pvd_reload(adem_pvd *pvd, const char *path, size_t frames_done,
                              double frame_period, adem_error *err) {
  double *time = malloc((frames_done ? frames_done : 1) * sizeof *time);
  unsigned char *found = calloc(frames_done ? frames_done : 1, 1);
  char(*names)[64] = calloc(frames_done ? frames_done : 1, sizeof *names);
  if (!time || !found || !names) {
    free(time);
    free(found);
    free(names);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the PVD list");
  }
  char *text = NULL;
  size_t len = 0;
  adem_error ignored;
  size_t missing = frames_done;
  if (adem_file_read_all(path, &text, &len, &ignored) == ADEM_OK) {
    for (char *line = text; line && *line;) {
      char *next = strchr(line, '\n');
      if (next) *next++ = '\0';
      const char *ts = strstr(line, "timestep=\"");
      const char *fl = strstr(line, "file=\"frames/particles_");
      if (ts && fl) {
        double t = strtod(ts + 10, NULL);
        unsigned long long k = strtoull(fl + 23, NULL, 10);
        size_t nl = strcspn(fl + 6, "\"");
        if (k < frames_done && !found[k] && nl < sizeof names[0]) {
          /* only the names adem gives frame k: its .vtu, or the .pvtu of a run split in
           * pieces (a name is written back into the PVD as it is) */
          char vtu[64], pvtu[64];
          frame_name(vtu, sizeof vtu, (size_t)k);
          piece_name(pvtu, sizeof pvtu, (size_t)k, -1);
          const char *nm = fl + 6;
          bool ok = (nl == strlen(vtu) && !strncmp(nm, vtu, nl)) ||
                    (nl == strlen(pvtu) && !strncmp(nm, pvtu, nl));
          if (ok) {
            time[k] = t;
            found[k] = 1;
            memcpy(names[k], nm, nl);
            names[k][nl] = '\0';
            missing--;
          }
        }
      }
      line = next;
    }
    free(text);
  }
  if (missing > 0)
    adem_log(ADEM_LOG_WARN, "%s lacks %zu of the %zu earlier frames; their times are estimated",
             path, missing, frames_done);
  adem_status st = ADEM_OK;
  char name[64];
  for (size_t k = 0; k < frames_done && !st; ++k) {
    frame_name(name, sizeof name, k);
    st = adem_output_pvd_add(pvd, found[k] ? time[k] : (double)k * frame_period,
                             found[k] ? names[k] : name, err);
  }
  free(time);
  free(found);
  free(names);
  return st;
}

/* ---------------------------------------------------------------- CSV file (rows: output_csv.c) */

/* One write(2) per row: a reader or a crash sees whole rows only. */
static int write_whole(int fd, const char *s, size_t n) {
  while (n > 0) {
    ssize_t m = write(fd, s, n);
    if (m < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    s += m;
    n -= (size_t)m;
  }
  return 0;
}

/* Keeps the header and the complete rows with time <= t_resume (< t_resume with drop_at),
 * rewritten atomically. */
static adem_status csv_truncate(const char *path, const char *header, double t_resume,
                                bool drop_at, adem_error *err) {
  char *text = NULL;
  size_t len = 0;
  adem_error rd;
  if (adem_file_read_all(path, &text, &len, &rd) != ADEM_OK) {
    adem_log(ADEM_LOG_WARN, "%s is missing; the time series restarts at t = %.9g s", path, t_resume);
    return adem_file_write_all(path, header, strlen(header), err);
  }
  size_t keep = 0;
  char *nl = strchr(text, '\n');
  if (!nl || strncmp(text, header, (size_t)(nl - text) + 1) != 0) {
    adem_log(ADEM_LOG_WARN, "%s has another header than this case; it is started again", path);
    free(text);
    return adem_file_write_all(path, header, strlen(header), err);
  }
  keep = (size_t)(nl - text) + 1;
  while (keep < len) {
    char *end = strchr(text + keep, '\n');
    if (!end) break; /* a partial last row is dropped */
    char *num_end;
    double t = strtod(text + keep, &num_end);
    /* strtod skips blank lines: a time read past this row's end is not this row's. */
    if (num_end == text + keep || num_end > end || !(drop_at ? t < t_resume : t <= t_resume)) break;
    keep = (size_t)(end - text) + 1;
  }
  adem_status st = ADEM_OK;
  if (keep != len) st = adem_file_write_all(path, text, keep, err);
  free(text);
  return st;
}

/* ---------------------------------------------------------------- run output */

/* Mesh frames: frames/mesh_NNNNNN.vtu beside each particle frame, listed in their own collection
 * mesh.pvd with the particle frames' times. A second file rather than a second part of
 * particles.pvd: ParaView would merge the parts into one multiblock, and a Glyph filter on the
 * particles would then draw spheres at the mesh's vertices too. */
static adem_status mesh_pvd_write(const adem_output *o, adem_error *err) {
  char *path = adem_file_join(o->dir, "mesh.pvd");
  if (!path) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  free(path);
  if (st) return st;
  fprintf(af.f,
          "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"%s\">\n"
          "  <Collection>\n",
          adem_vtu_byte_order());
  for (size_t k = 0; k < o->pvd.n; ++k)
    fprintf(af.f,
            "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"frames/mesh_%06zu.vtu\"/>\n",
            o->pvd.time[k], k);
  fprintf(af.f, "  </Collection>\n</VTKFile>\n");
  return adem_file_commit(&af, err);
}

static adem_status mesh_frame(const adem_output *o, const adem_world *w, adem_error *err) {
  if (w->walls.mesh.ntris == 0) return ADEM_OK;
  char name[64];
  snprintf(name, sizeof name, "frames/mesh_%06zu.vtu", o->next_frame);
  char *path = adem_file_join(o->dir, name);
  if (!path) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_status st = adem_mesh_write_vtu(&w->walls.mesh, w->walls.face_force, path, err);
  free(path);
  return st;
}

adem_status adem_output_open(adem_output *o, const char *dir, const adem_world *w, bool frames,
                             bool csv, bool resume, size_t frames_done, double frame_period,
                             double t_resume, bool drop_resume_row,
                             const adem_output_track *track, const adem_output_extra *extra,
                             adem_error *err) {
  memset(o, 0, sizeof *o);
  o->csv_fd = -1;
  if (track) o->track = *track;
  if (extra) o->extra = *extra;
  o->frames = frames;
  o->csv = csv;
  adem_status st = adem_file_mkdir_p(dir, err);
  if (!st) st = adem_file_check_writable(dir, err);
  if (st) return st;
  o->dir = adem_file_join(dir, "");
  o->pvd_path = adem_file_join(dir, "particles.pvd");
  o->csv_path = adem_file_join(dir, "timeseries.csv");
  o->png_path = adem_file_join(dir, "energy.png");
  char *frames_dir = adem_file_join(dir, "frames");
  if (!o->dir || !o->pvd_path || !o->csv_path || !o->png_path || !frames_dir) {
    free(frames_dir);
    adem_output_close(o);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  if (frames) {
    st = adem_file_mkdir_p(frames_dir, err);
    if (!st) st = adem_file_check_writable(frames_dir, err);
    if (!st && resume) {
      st = pvd_reload(&o->pvd, o->pvd_path, frames_done, frame_period, err);
      o->next_frame = frames_done;
      /* The PVD must not list frames the resumed run is about to rewrite. */
      if (!st) st = adem_output_pvd_write(&o->pvd, o->pvd_path, err);
      if (!st && w->walls.mesh.ntris > 0) st = mesh_pvd_write(o, err);
    }
  }
  free(frames_dir);
  if (!st && csv) {
    char *header = adem_output_csv_header(w, &o->track, &o->extra);
    if (!header) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    else if (resume) st = csv_truncate(o->csv_path, header, t_resume, drop_resume_row, err);
    else st = adem_file_write_all(o->csv_path, header, strlen(header), err);
    free(header);
    if (!st) {
      o->csv_fd = open(o->csv_path, O_WRONLY | O_APPEND | O_CLOEXEC);
      if (o->csv_fd < 0)
        st = adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", o->csv_path, strerror(errno));
    }
  }
  if (st) adem_output_close(o);
  return st;
}

/* After a frame's particle file: the particles' .pvd lists it (name, relative to the output
 * folder), the mesh frame and its .pvd are written, and the frame counter moves on. */
static adem_status finish_frame(adem_output *o, const adem_world *w, const char *name,
                                adem_error *err) {
  adem_status st = adem_output_pvd_add(&o->pvd, w->time, name, err);
  if (!st) st = adem_output_pvd_write(&o->pvd, o->pvd_path, err);
  if (!st) st = mesh_frame(o, w, err);
  if (!st && w->walls.mesh.ntris > 0) st = mesh_pvd_write(o, err);
  if (!st) st = adem_output_contacts_frame(o, w, err);
  if (!st) o->next_frame++;
  return st;
}

adem_status adem_output_frame(adem_output *o, const adem_world *w, adem_error *err) {
  if (!o->frames) return ADEM_OK;
  char name[64];
  frame_name(name, sizeof name, o->next_frame);
  char *path = adem_file_join(o->dir, name);
  if (!path) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_status st = adem_output_write_vtu(w, path, err);
  free(path);
  if (!st) st = finish_frame(o, w, name, err);
  return st;
}

adem_status adem_output_frame_piece(const char *dir, size_t index, int piece, const adem_world *w,
                                    const uint32_t *idx, size_t n, adem_error *err) {
  char name[64];
  piece_name(name, sizeof name, index, piece);
  char *path = adem_file_join(dir, name);
  if (!path) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_status st = adem_output_write_vtu_of(w, idx, n, path, err);
  free(path);
  return st;
}

adem_status adem_output_frame_pvtu(adem_output *o, const adem_world *w, int npieces,
                                   adem_error *err) {
  if (!o->frames) return ADEM_OK;
  char name[64];
  piece_name(name, sizeof name, o->next_frame, -1);
  char *path = adem_file_join(o->dir, name);
  char(*pieces)[64] = calloc((size_t)(npieces > 0 ? npieces : 1), sizeof *pieces);
  const char **src = calloc((size_t)(npieces > 0 ? npieces : 1), sizeof *src);
  adem_status st = path && pieces && src ? ADEM_OK : adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  for (int k = 0; k < npieces && !st; ++k) { /* beside the .pvtu, in frames/ */
    snprintf(pieces[k], sizeof pieces[k], "particles_%06zu_p%d.vtu", o->next_frame, k);
    src[k] = pieces[k];
  }
  if (!st) st = adem_output_write_pvtu(path, src, npieces, err);
  /* pieces of this frame left by a run on more processes that ended here: named by nothing */
  for (int k = npieces; !st; ++k) {
    char stale[64];
    piece_name(stale, sizeof stale, o->next_frame, k);
    char *sp = adem_file_join(o->dir, stale);
    int gone = !sp || unlink(sp) != 0;
    free(sp);
    if (gone) break;
  }
  free(path);
  free(pieces);
  free(src);
  if (!st) st = finish_frame(o, w, name, err);
  return st;
}

adem_status adem_output_csv_append(adem_output *o, const adem_world *w, adem_error *err) {
  if (!o->csv || o->csv_fd < 0) return ADEM_OK;
  char *row = adem_output_csv_row(w, &o->track, &o->extra);
  if (!row) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  off_t before = lseek(o->csv_fd, 0, SEEK_END);
  int e = write_whole(o->csv_fd, row, strlen(row));
  free(row);
  if (!e) return ADEM_OK;
  /* A full disk may have taken part of the row: cut it off, so that the file keeps whole rows. */
  if (before >= 0 && ftruncate(o->csv_fd, before) != 0)
    adem_log(ADEM_LOG_WARN, "%s ends in a partial row that could not be removed: %s", o->csv_path,
             strerror(errno));
  return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", o->csv_path, strerror(e));
}

void adem_output_close(adem_output *o) {
  if (o->csv_fd >= 0) {
    fsync(o->csv_fd);
    close(o->csv_fd);
  }
  adem_output_pvd_free(&o->pvd);
  adem_output_pvd_free(&o->contacts_pvd);
  free(o->dir);
  free(o->pvd_path);
  free(o->csv_path);
  free(o->png_path);
  memset(o, 0, sizeof *o);
  o->csv_fd = -1;
}
