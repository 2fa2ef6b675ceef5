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
} frame_arrays[] = {{"radius", "Float64", 1},           {"id", "Int64", 1},
                    {"material", "Int32", 1},           {"velocity", "Float64", 3},
                    {"angular_velocity", "Float64", 3}, {"force", "Float64", 3},
                    {"rolling_torque", "Float64", 3},   {"mass", "Float64", 1}};

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
      {"radius", "Float64", 1, 8 * n},           {"id", "Int64", 1, 8 * n},
      {"material", "Int32", 1, 4 * n},           {"velocity", "Float64", 3, 24 * n},
      {"angular_velocity", "Float64", 3, 24 * n}, {"force", "Float64", 3, 24 * n},
      {"rolling_torque", "Float64", 3, 24 * n},   {"mass", "Float64", 1, 8 * n},
      {"position", "Float64", 3, 24 * n},
      {"connectivity", "Int64", 1, 8 * n},       {"offsets", "Int64", 1, 8 * n},
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
  char (*names)[64] = calloc(frames_done ? frames_done : 1, sizeof *names);
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

/* ---------------------------------------------------------------- CSV */

/* Growing string for rows and headers. */
typedef struct strbuf {
  char *s;
  size_t n, cap;
  int failed;
} strbuf;

static void sb_printf(strbuf *b, const char *fmt, ...) ADEM_PRINTF(2, 3);
static void sb_printf(strbuf *b, const char *fmt, ...) {
  if (b->failed) return;
  for (;;) {
    va_list ap;
    va_start(ap, fmt);
    int m = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? b->cap - b->n : 0, fmt, ap);
    va_end(ap);
    if (m < 0) {
      b->failed = 1;
      return;
    }
    if (b->s && b->n + (size_t)m < b->cap) {
      b->n += (size_t)m;
      return;
    }
    size_t cap = b->cap ? b->cap : 256;
    while (cap <= b->n + (size_t)m) cap *= 2;
    char *s = realloc(b->s, cap);
    if (!s) {
      b->failed = 1;
      return;
    }
    b->s = s;
    b->cap = cap;
  }
}

static char *sb_finish(strbuf *b) {
  if (b->failed) {
    free(b->s);
    return NULL;
  }
  return b->s;
}

/* A wall's name as the start of CSV column names: one CSV field per column, and names that
 * numpy's genfromtxt(names=True) keeps (it drops every character but letters, digits and `_`):
 * the dot of a mesh group or a box's plane (`hopper.funnel`, `box.xmin`) becomes `__`. */
static void csv_field_name(char *buf, size_t n, const char *name) {
  size_t k = 0;
  for (const char *c = name; *c && k + 2 < n; ++c) {
    if (*c == '.') {
      buf[k++] = '_';
      buf[k++] = '_';
    } else {
      buf[k++] = (*c == ',' || *c == '"' || *c == '\n' || *c == '\r' || *c == ' ') ? '_' : *c;
    }
  }
  if (n) buf[k < n ? k : n - 1] = '\0';
}

/* Mesh loads: force and torque on every group, then on every file with several groups (a file
 * of one group would repeat its columns). */

static void mesh_csv_header(strbuf *b, const adem_world *w) {
  char name[2 * ADEM_NAME_MAX];
  for (int g = 0; g < w->walls.mesh.ngroups + w->walls.nmesh_walls; ++g) {
    bool group = g < w->walls.mesh.ngroups;
    const adem_mesh_wall *mw = group ? NULL : &w->walls.mesh_walls[g - w->walls.mesh.ngroups];
    if (mw && mw->count < 2) continue;
    csv_field_name(name, sizeof name, group ? w->walls.mesh.groups[g].name : mw->name);
    sb_printf(b, ",%s_fx_N,%s_fy_N,%s_fz_N,%s_tx_Nm,%s_ty_Nm,%s_tz_Nm", name, name, name, name,
              name, name);
  }
}

static void mesh_csv_row(strbuf *b, const adem_world *w) {
  size_t ng = (size_t)w->walls.mesh.ngroups, nw = (size_t)w->walls.nmesh_walls;
  if (ng == 0) return;
  adem_vec3 *f = malloc(2 * (ng + nw) * sizeof *f);
  if (!f) {
    b->failed = 1;
    return;
  }
  adem_vec3 *t = f + ng + nw;
  adem_world_mesh_loads(w, f, t, f + ng, t + ng);
  for (size_t k = 0; k < ng + nw; ++k) {
    if (k >= ng && w->walls.mesh_walls[k - ng].count < 2) continue;
    sb_printf(b, ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", f[k].x, f[k].y, f[k].z, t[k].x, t[k].y,
              t[k].z);
  }
  free(f);
}

/* Walls that move or have a servo in some configuration of the run (ADEM_WALL_CSV_*): the
 * displacement of their reference point since their motion began, and the servo's displacement
 * and measured force. After the loads, so that the loads' columns keep their places. */
static void motion_csv_header(strbuf *b, const adem_world *w) {
  char name[2 * ADEM_NAME_MAX];
  int np = w->walls.nplanes;
  for (int k = 0; k < np + w->walls.nmesh_walls; ++k) {
    uint8_t csv = k < np ? w->walls.planes[k].csv : w->walls.mesh_walls[k - np].csv;
    if (!csv) continue;
    csv_field_name(name, sizeof name,
                   k < np ? w->walls.planes[k].def.name : w->walls.mesh_walls[k - np].name);
    if (!name[0]) snprintf(name, sizeof name, "plane%d", k);
    sb_printf(b, ",%s_ux_m,%s_uy_m,%s_uz_m", name, name, name);
    if (csv & ADEM_WALL_CSV_SERVO) sb_printf(b, ",%s_servo_u_m,%s_servo_F_N", name, name);
    sb_printf(b, ",%s_drive_power_W", name);
    if (k >= np) sb_printf(b, ",%s_axis_torque_Nm", name);
  }
}

/* What driving a moving wall costs: the power its motion puts into the particles,
 * -(F . v_ref + T_ref . omega), F and T_ref the particles' force and torque on it (a mesh wall:
 * summed over its groups, each about its reference point), and the particles' torque about its
 * rotation axis through the axis's point now (0 while it does not turn); a drive holds the wall
 * on its path against them. A plane's torque is not summed: its power is that of its
 * translation, and NaN while it turns. */
static void drive_load(const adem_world *w, int k, const adem_vec3 *gf, const adem_vec3 *gt,
                       const adem_vec3 *pf, double *power, double *axis_torque) {
  const adem_walls *wl = &w->walls;
  int np = wl->nplanes;
  *power = *axis_torque = 0.0;
  if (k < np) {
    const adem_motion *m = &wl->planes[k].motion;
    *power = m->omega != 0.0 ? NAN : -v3_dot(pf[k], adem_motion_velocity(m, wl->time));
    return;
  }
  const adem_mesh_wall *mw = &wl->mesh_walls[k - np];
  for (int g = mw->first; g < mw->first + mw->count; ++g) {
    const adem_motion *m = &wl->mesh_motion[g];
    adem_vec3 spin = v3_scale(m->axis, m->omega);
    *power -= v3_dot(gf[g], adem_motion_point_velocity(m, wl->time, wl->mesh_ref[g])) +
              v3_dot(gt[g], spin);
    if (m->omega == 0.0) continue;
    adem_vec3 c = v3_add(m->center, adem_motion_displacement(m, wl->time));
    *axis_torque += v3_dot(v3_add(gt[g], v3_cross(v3_sub(wl->mesh_ref[g], c), gf[g])), m->axis);
  }
}

static void motion_csv_row(strbuf *b, const adem_world *w) {
  int np = w->walls.nplanes;
  size_t ng = (size_t)w->walls.mesh.ngroups;
  adem_vec3 *gf = malloc((2 * ng + (size_t)np + 1) * sizeof *gf);
  if (!gf) {
    b->failed = 1;
    return;
  }
  adem_vec3 *gt = gf + ng, *pf = gf + 2 * ng;
  if (ng) adem_world_mesh_loads(w, gf, gt, NULL, NULL);
  if (np) adem_world_plane_forces(w, pf);
  for (int k = 0; k < np + w->walls.nmesh_walls; ++k) {
    uint8_t csv = k < np ? w->walls.planes[k].csv : w->walls.mesh_walls[k - np].csv;
    if (!csv) continue;
    adem_vec3 u = k < np ? adem_walls_plane_displacement(&w->walls, k)
                         : adem_walls_mesh_wall_displacement(&w->walls, k - np);
    sb_printf(b, ",%.17g,%.17g,%.17g", u.x, u.y, u.z);
    if (csv & ADEM_WALL_CSV_SERVO) {
      const adem_motion *m = k < np ? adem_walls_plane_servo(&w->walls, k)
                                    : adem_walls_mesh_wall_servo(&w->walls, k - np);
      /* a stage without the servo: no servo displacement, no measurement */
      if (m)
        sb_printf(b, ",%.17g,%.17g", m->servo_u, m->servo_force);
      else
        sb_printf(b, ",0,nan");
    }
    double power, torque;
    drive_load(w, k, gf, gt, pf, &power, &torque);
    sb_printf(b, ",%.17g", power);
    if (k >= np) sb_printf(b, ",%.17g", torque);
  }
  free(gf);
}

/* Cylinders and plates (core/cylinder.h): the torque of the particles on each about its point (a
 * cylinder: its axis point) and, for a cylinder, its component along the axis. After the motion
 * columns, so that the columns before keep their places. */
static void shape_csv_header(strbuf *b, const adem_world *w) {
  char name[2 * ADEM_NAME_MAX];
  for (int k = 0; k < w->walls.nplanes; ++k) {
    const adem_plane_def *d = &w->walls.planes[k].def;
    if (d->shape == ADEM_WALL_PLANE) continue;
    csv_field_name(name, sizeof name, d->name);
    if (!name[0]) snprintf(name, sizeof name, "plane%d", k);
    sb_printf(b, ",%s_tx_Nm,%s_ty_Nm,%s_tz_Nm", name, name, name);
    if (d->shape == ADEM_WALL_CYLINDER) sb_printf(b, ",%s_t_axis_Nm", name);
  }
}

static void shape_csv_row(strbuf *b, const adem_world *w, const adem_vec3 *t) {
  for (int k = 0; k < w->walls.nplanes; ++k) {
    const adem_plane_def *d = &w->walls.planes[k].def;
    if (d->shape == ADEM_WALL_PLANE) continue;
    sb_printf(b, ",%.17g,%.17g,%.17g", t[k].x, t[k].y, t[k].z);
    if (d->shape == ADEM_WALL_CYLINDER) sb_printf(b, ",%.17g", v3_dot(t[k], d->normal));
  }
}

char *adem_output_csv_header(const adem_world *w, const adem_output_track *track,
                             const adem_output_extra *extra) {
  strbuf b = {0};
  sb_printf(&b, "time_s,kinetic_J,rotational_J,potential_J,elastic_J,dissipated_J,wall_work_J,"
                "contacts_pp,contacts_pw,max_overlap_ratio");
  for (int k = 0; k < w->walls.nplanes; ++k) {
    /* Plane names come from the case file: keep the header one CSV field per column. */
    char name[2 * ADEM_NAME_MAX];
    csv_field_name(name, sizeof name, w->walls.planes[k].def.name);
    if (!name[0]) snprintf(name, sizeof name, "plane%d", k);
    sb_printf(&b, ",%s_fx_N,%s_fy_N,%s_fz_N", name, name, name);
  }
  mesh_csv_header(&b, w);
  motion_csv_header(&b, w);
  shape_csv_header(&b, w);
  for (int k = 0; track && k < track->n; ++k) {
    unsigned long long id = (unsigned long long)track->id[k];
    sb_printf(&b, ",p%llu_rolling_torque_x_Nm,p%llu_rolling_torque_y_Nm,p%llu_rolling_torque_z_Nm", id,
              id, id);
    sb_printf(&b, ",p%llu_omega_x_rad_s,p%llu_omega_y_rad_s,p%llu_omega_z_rad_s,p%llu_distance_m", id,
              id, id, id);
  }
  for (int k = 0; extra && k < extra->n; ++k) {
    char name[2 * ADEM_NAME_MAX + 16];
    csv_field_name(name, sizeof name, extra->name[k]);
    sb_printf(&b, ",%s", name);
  }
  sb_printf(&b, "\n");
  return sb_finish(&b);
}

char *adem_output_csv_row(const adem_world *w, const adem_output_track *track,
                          const adem_output_extra *extra) {
  adem_diagnostics d = adem_world_diagnostics(w);
  strbuf b = {0};
  /* %.17g: the times read back on resume compare exactly with the checkpoint's. */
  sb_printf(&b, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%zu,%zu,%.17g", w->time, d.kinetic,
            d.rotational, d.potential, d.elastic, d.dissipated, d.wall_work, d.contacts_pp,
            d.contacts_pw, d.max_overlap_ratio);
  adem_vec3 *f = malloc((size_t)(w->walls.nplanes > 0 ? w->walls.nplanes : 1) * sizeof *f);
  if (!f) {
    free(b.s);
    return NULL;
  }
  adem_world_plane_forces(w, f);
  for (int k = 0; k < w->walls.nplanes; ++k) sb_printf(&b, ",%.17g,%.17g,%.17g", f[k].x, f[k].y, f[k].z);
  mesh_csv_row(&b, w);
  motion_csv_row(&b, w);
  adem_world_plane_torques(w, f); /* cylinders' and plates' torques */
  shape_csv_row(&b, w, f);
  free(f);
  const adem_particles *p = &w->p;
  for (int k = 0; track && k < track->n; ++k) {
    size_t i = 0; /* particles are reordered by cell: find the id (a few per row) */
    while (i < p->n && p->id[i] != track->id[k]) ++i;
    if (i == p->n) {
      sb_printf(&b, ",nan,nan,nan,nan,nan,nan,nan");
      continue;
    }
    adem_vec3 t = p->rolling_torque[i], o = p->omega[i];
    sb_printf(&b, ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", t.x, t.y, t.z, o.x, o.y, o.z,
              p->path_length[i]);
  }
  for (int k = 0; extra && k < extra->n; ++k) sb_printf(&b, ",%.17g", extra->value[k]);
  sb_printf(&b, "\n");
  return sb_finish(&b);
}

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

/* ---------------------------------------------------------------- plot */

adem_status adem_output_plot_energy(const char *csv_path, const char *png_path, const char *title,
                                    adem_error *err) {
  size_t qn = 2 * (strlen(csv_path) + strlen(title)) + 8;
  char *qcsv = malloc(qn), *qtitle = malloc(qn);
  if (!qcsv || !qtitle) {
    free(qcsv);
    free(qtitle);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  strbuf b = {0};
  sb_printf(&b, "set title %s\nset xlabel 'time (s)'\nset ylabel 'energy (J)'\n"
                "set key outside right\nset grid\nf = %s\n",
            adem_plot_quote(title, qtitle, qn), adem_plot_quote(csv_path, qcsv, qn));
  /* The total goes down by what is dissipated and up by what moving walls give: the total plus
   * the dissipated energy less the wall work is the balance, flat but for the integration
   * error (and the work of a stage's change of gravity or group forces). */
  sb_printf(&b, "plot f skip 1 using 1:2 with lines title 'kinetic', \\\n"
                "     f skip 1 using 1:3 with lines title 'rotational', \\\n"
                "     f skip 1 using 1:4 with lines title 'potential', \\\n"
                "     f skip 1 using 1:5 with lines title 'elastic', \\\n"
                "     f skip 1 using 1:6 with lines title 'dissipated', \\\n"
                "     f skip 1 using 1:7 with lines title 'wall work', \\\n"
                "     f skip 1 using 1:($2+$3+$4+$5) with lines lw 2 title 'total', \\\n"
                "     f skip 1 using 1:($2+$3+$4+$5+$6-$7) with lines lw 2 dt 2 "
                "title 'total + dissipated - wall work'\n");
  free(qcsv);
  free(qtitle);
  char *body = sb_finish(&b);
  if (!body) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_status st = adem_plot_png(png_path, 1000, 600, body, err);
  free(body);
  return st;
}

/* Wall loads from the CSV: for every mesh group and plane, its force along gravity (what a load
 * cell under it would read), and the particles' weight for reference. Columns as the header
 * writes them: 9, then 3 per plane, then 6 per mesh group. */
adem_status adem_output_plot_loads(const adem_world *w, const char *csv_path, const char *png_path,
                                   const char *title, adem_error *err) {
  double gn = v3_norm(w->gravity);
  adem_vec3 down = gn > 0.0 ? v3_scale(w->gravity, 1.0 / gn) : v3(0.0, 0.0, -1.0);
  double weight = 0.0;
  uint32_t *order = adem_world_id_order(w); /* summed by id, as every sum over particles */
  if (!order) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  for (size_t k = 0; k < w->p.n; ++k) weight += gn / w->p.inv_mass[order[k]];
  free(order);
  size_t qn = 2 * (strlen(csv_path) + strlen(title) + ADEM_NAME_MAX) + 8;
  char *qcsv = malloc(qn), *qname = malloc(qn);
  strbuf b = {0};
  bool ok = qcsv && qname;
  if (ok) {
    sb_printf(&b, "set title %s\nset xlabel 'time (s)'\nset ylabel 'load along gravity (N)'\n"
                  "set key outside right\nset grid\nset autoscale xfix\nset datafile separator ','\n"
                  "f = %s\n",
              adem_plot_quote(title, qname, qn), adem_plot_quote(csv_path, qcsv, qn));
    sb_printf(&b, "plot %.17g with lines dt 2 lc rgb 'black' title 'weight of the particles'", weight);
    for (int k = 0; k < w->walls.mesh.ngroups + w->walls.nplanes; ++k) {
      bool mesh = k < w->walls.mesh.ngroups;
      int col = mesh ? 11 + 3 * w->walls.nplanes + 6 * k : 11 + 3 * (k - w->walls.mesh.ngroups);
      const char *name = mesh ? w->walls.mesh.groups[k].name : w->walls.planes[k - w->walls.mesh.ngroups].def.name;
      sb_printf(&b, ", \\\n     f skip 1 using 1:(%.17g*column(%d)+%.17g*column(%d)+%.17g*column(%d)) "
                    "with lines lw 2 title %s",
                down.x, col, down.y, col + 1, down.z, col + 2, adem_plot_quote(name, qname, qn));
    }
    sb_printf(&b, "\n");
    /* Moving walls: a second panel with the power their drives put into the particles. */
    char *head = adem_output_csv_header(w, NULL, NULL);
    int nmoving = 0;
    for (char *tok = head ? strstr(head, "_drive_power_W") : NULL; tok; tok = strstr(tok + 1, "_drive_power_W"))
      ++nmoving;
    if (nmoving > 0) {
      char *body0 = sb_finish(&b);
      memset(&b, 0, sizeof b);
      sb_printf(&b, "set multiplot layout 2,1\n%s", body0 ? body0 : "");
      free(body0);
      sb_printf(&b, "set ylabel 'drive power (W)'\nset title 'power the moving walls put into the "
                    "particles (integral: wall work)'\nplot 0 with lines lc rgb 'black' notitle");
      int col = 0;
      for (char *tok = strtok(head, ",\n"); tok; tok = strtok(NULL, ",\n")) {
        ++col;
        size_t n = strlen(tok), sfx = strlen("_drive_power_W");
        if (n <= sfx || strcmp(tok + n - sfx, "_drive_power_W")) continue;
        tok[n - sfx] = '\0';
        sb_printf(&b, ", \\\n     f skip 1 using 1:%d with lines lw 2 title %s", col,
                  adem_plot_quote(tok, qname, qn));
      }
      sb_printf(&b, "\nunset multiplot\n");
    }
    free(head);
  }
  free(qcsv);
  free(qname);
  char *body = ok ? sb_finish(&b) : NULL;
  if (!body) {
    free(b.s);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  adem_status st = adem_plot_png(png_path, 1000, 600, body, err);
  free(body);
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
  char (*pieces)[64] = calloc((size_t)(npieces > 0 ? npieces : 1), sizeof *pieces);
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
