/* Claim: what the split runs beyond plane walls gives the serial run's results bit for bit
 * under `mpirun -np N adem run` for N = 1, 2, 3 and 4: servo walls (plane forces every step),
 * stages (one cut short by its `until`), time.until, output.regions (tests/mpi/feature_cases.h,
 * press), pours (pour, also into an empty box), mesh walls (hopper: the flagship's meshes, a gate moved and switched
 * off by a stage) and a mesh servo (face loads every step; with a gain far too high, its
 * stability warnings are the serial run's). Compared: the final checkpoint's
 * particles by id (every field), contacts with their histories, diagnostics and plane forces
 * (split_compare.h), the face loads, the walls' state (servos), the stages' and pours' state,
 * and the CSV time series as text. A checkpoint written by 3 processes resumes on 2 to the
 * serial run's end (press, pour, hopper).
 *
 * Controls (each must differ): ADEM_SPLIT_BREAK (src/mpi/split.h) leaves one exchange out:
 * "plane_forces" (a servo measures its own process's contacts only), "face_loads" (likewise a
 * mesh servo), "mesh_history" (mesh contacts lose their history when their particle changes
 * process), "resplit" (the parts do not take in a pour batch or a stage's change),
 * "periodic_axis" (below).
 *
 * output.pieces (pieces): every frame of a split run as a .pvtu of one .vtu per process; the
 * pieces together hold every particle once, with the serial frame's bits (press on 2, 3, 4
 * processes, hopper on 3); control: pieces with the ghosts too ("pieces") are caught.
 *
 * Periodic axes (periodic): bitwise/periodic_case.h's bed, periodic along x and y (the slabs
 * are cut along z, which does not wrap), with a plate that a stage lowers and drags; control
 * "periodic_axis" (slabs along x, a periodic axis, without images across its faces) must
 * differ (the plain bed: the run fails).
 *
 * Run as `test_split_features GROUP`, GROUP one of press, pour, hopper, mesh_servo, restart,
 * controls, pieces, periodic (one ctest test each). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "adem/adem.h"
#include "adem/frames.h"
#include "cli_run.h"
#include "feature_cases.h"
#include "periodic_case.h"
#include "insert.h"
#include "outlets.h"
#include "plate_stl.h"
#include "split_compare.h"
#include "stages.h"
#include "world_internal.h"

/* What the last adem_np printed. */
static char np_out[1 << 16];

/* Runs `adem ARGS` under `mpirun -np np` (np 0: plain `adem ARGS`), with ADEM_SPLIT_BREAK=brk
 * when brk is not NULL; the exit status, the output in np_out. */
static int adem_np(int np, const char *brk, const char *fmt, ...) {
  char args[4096];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(args, sizeof args, fmt, ap);
  va_end(ap);
  char *log = path_in_tmp("mpi_output.txt");
  char cmd[8192];
  if (np == 0)
    snprintf(cmd, sizeof cmd, "'%s' %s > '%s' 2>&1 < /dev/null", ADEM_BINARY, args, log);
  else
    snprintf(cmd, sizeof cmd,
             "%s%s '%s' -np %d --oversubscribe %s '%s' %s > '%s' 2>&1 < /dev/null",
             brk ? "ADEM_SPLIT_BREAK=" : "", brk ? brk : "", ADEM_MPIEXEC, np,
             brk ? "-x ADEM_SPLIT_BREAK" : "", ADEM_BINARY, args, log);
  int status = system(cmd);
  assert_true(status != -1 && WIFEXITED(status));
  FILE *lf = fopen(log, "r");
  size_t got = lf ? fread(np_out, 1, sizeof np_out - 1, lf) : 0;
  np_out[got] = '\0';
  if (lf) fclose(lf);
  char how[128] = "";
  if (np) snprintf(how, sizeof how, "%s%s%smpirun -np %d ", brk ? "ADEM_SPLIT_BREAK=" : "",
                   brk ? brk : "", brk ? " " : "", np);
  printf("# %sadem %s -> %d\n", how, args, WEXITSTATUS(status));
  if (WEXITSTATUS(status) != 0) {
    FILE *f = fopen(log, "r");
    char buf[4096];
    size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
    buf[n] = '\0';
    if (f) fclose(f);
    printf("# output:\n%s\n", buf);
  }
  free(log);
  return WEXITSTATUS(status);
}

/* The file's bytes (at most 4 MiB; *len their count if len) with a NUL after, or NULL. */
static char *slurp_n(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  char *b = malloc(1 << 22);
  assert_non_null(b);
  size_t n = fread(b, 1, (1 << 22) - 1, f);
  b[n] = '\0';
  fclose(f);
  if (len) *len = n;
  return b;
}

static char *slurp(const char *path) { return slurp_n(path, NULL); }

typedef struct membuf {
  unsigned char *d;
  size_t n, cap;
} membuf;

static int mem_put(void *ctx, const void *data, size_t n) {
  membuf *b = ctx;
  if (b->n + n > b->cap) {
    size_t c = 2 * (b->n + n) + 256;
    unsigned char *q = realloc(b->d, c);
    if (!q) return 0;
    b->d = q;
    b->cap = c;
  }
  memcpy(b->d + b->n, data, n);
  b->n += n;
  return 1;
}

/* Whether two savers write the same bytes. */
static int same_bytes(const membuf *a, const membuf *b) {
  return a->n == b->n && (a->n == 0 || memcmp(a->d, b->d, a->n) == 0);
}

/* What differs between the runs written into tmpdir/A and tmpdir/B, or NULL. */
static const char *differs(const char *da, const char *db) {
  static char why[ADEM_MSG_MAX + 128];
  char path[600];
  adem_case *c[2] = {NULL, NULL};
  const char *dirs[2] = {da, db};
  for (int k = 0; k < 2; ++k) {
    adem_error err;
    snprintf(path, sizeof path, "%s/%s/checkpoint", tmpdir, dirs[k]);
    if (adem_checkpoint_read(path, &c[k], &err)) {
      snprintf(why, sizeof why, "%s: no checkpoint (%s)", dirs[k], err.message);
      adem_case_free(c[0]);
      return why;
    }
  }
  const adem_world *a = c[0]->world, *b = c[1]->world;
  const char *w = split_compare(a, b);
  if (w) snprintf(why, sizeof why, "%s", w);
  size_t nf = 3 * a->walls.mesh.ntris;
  if (!w && (a->walls.mesh.ntris != b->walls.mesh.ntris ||
             (nf && (memcmp(a->walls.face_force, b->walls.face_force, nf * sizeof(double)) ||
                     memcmp(a->walls.face_torque, b->walls.face_torque, nf * sizeof(double))))))
    snprintf(why, sizeof why, "%s", w = "face loads");
  membuf m[2][3];
  memset(m, 0, sizeof m);
  for (int k = 0; k < 2; ++k) {
    adem_writer wr = adem_writer_make(mem_put, &m[k][0]);
    adem_walls_save_state(&wr, &c[k]->world->walls);
    adem_writer ws = adem_writer_make(mem_put, &m[k][1]);
    adem_stages_save(&ws, c[k]);
    adem_outlets_save(&ws, c[k]->outlets);
    size_t len = 0;
    unsigned char *pk = adem_pours_pack(c[k]->pours, &len);
    if (pk) mem_put(&m[k][2], pk, len);
    free(pk);
  }
  if (!w && !same_bytes(&m[0][0], &m[1][0])) snprintf(why, sizeof why, "%s", w = "wall state (servos)");
  if (!w && !same_bytes(&m[0][1], &m[1][1])) snprintf(why, sizeof why, "%s", w = "stage state");
  if (!w && !same_bytes(&m[0][2], &m[1][2])) snprintf(why, sizeof why, "%s", w = "pour state");
  if (!w && adem_stages_current(c[0]) != adem_stages_current(c[1]))
    snprintf(why, sizeof why, "%s", w = "stage");
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j) free(m[k][j].d);
  adem_case_free(c[0]);
  adem_case_free(c[1]);
  if (w) return why;
  char *t[2];
  for (int k = 0; k < 2; ++k) {
    snprintf(path, sizeof path, "%s/%s/timeseries.csv", tmpdir, dirs[k]);
    t[k] = slurp(path);
  }
  if (!t[0] || !t[1] || strcmp(t[0], t[1]) != 0) w = "the CSV text";
  free(t[0]);
  free(t[1]);
  return w;
}

/* The case (a file in tmpdir) run serially and on 1 .. 4 processes: the same. */
static void runs_equal(const char *yaml, const char *name) {
  char dir[64];
  snprintf(dir, sizeof dir, "%s_serial", name);
  assert_int_equal(adem_np(0, NULL, "run '%s' --out '%s/%s' --threads 1 --quiet", yaml, tmpdir, dir), 0);
  char *csv = NULL;
  {
    char path[600];
    snprintf(path, sizeof path, "%s/%s/timeseries.csv", tmpdir, dir);
    csv = slurp(path);
    assert_non_null(csv);
  }
  for (int np = 1; np <= 4; ++np) {
    char d[64];
    snprintf(d, sizeof d, "%s_np%d", name, np);
    assert_int_equal(adem_np(np, NULL, "run '%s' --out '%s/%s' --threads 1 --quiet", yaml, tmpdir, d), 0);
    const char *why = differs(dir, d);
    if (why) fail_msg("%s, %d processes: %s differs from the serial run's", name, np, why);
    printf("# %s, %d process%s: checkpoint, walls, stages, pours and the CSV (%zu bytes) are the "
           "serial run's\n",
           name, np, np > 1 ? "es" : "", strlen(csv));
  }
  free(csv);
}

static char *case_file(const char *name, const char *text) { return write_case(name, text); }

/* tests/cases/NAME.yaml with the overrides SETS written into it (adem_case_text_with_sets; a
 * fresh string). */
static char *feature_case_with_sets(const char *name, const char *const *sets, int nsets) {
  char *text = NULL;
  adem_error err;
  if (adem_case_text_with_sets(case_file_text(name), name, sets, nsets, &text, &err))
    fail_msg("%s: %s", name, err.message);
  return text;
}

static char *hopper_file(void) { return strdup(case_file_path("mpi-hopper")); }

/* The mesh servo case with frames. */
static char *mesh_servo_text(void) {
  const char *sets[] = {"output.frame_interval=0.007"};
  return feature_case_with_sets("bitwise-servo", sets, 1);
}

static char *mesh_servo_file(void) {
  char dir[400], cmd[1400];
  snprintf(dir, sizeof dir, "%s/servo_case/meshes", tmpdir);
  snprintf(cmd, sizeof cmd, "mkdir -p '%s' && cp '%s/tests/data/cube_ascii.stl' '%s/cube.stl'", dir,
           ADEM_SOURCE_DIR, dir);
  assert_int_equal(system(cmd), 0);
  snprintf(cmd, sizeof cmd, "%s/plate.stl", dir);
  write_plate(cmd, 3, 0.0078125);
  char *text = mesh_servo_text();
  char *y = case_file("servo_case/servo.yaml", text);
  free(text);
  return y;
}

static void test_press(void **state) {
  (void)state;
  char *y = case_file("press.yaml", press_case);
  runs_equal(y, "press");
  free(y);
}

static void test_pour(void **state) {
  (void)state;
  char *y = case_file("pour.yaml", pour_case);
  runs_equal(y, "pour");
  free(y);
  /* every particle poured: the processes split at the first batch */
  const char *a = strstr(pour_case, "particles:\n"), *b = strstr(pour_case, "walls:\n");
  char text[4096];
  snprintf(text, sizeof text, "%.*s%s", (int)(a - pour_case), pour_case, b);
  y = case_file("pour_only.yaml", text);
  runs_equal(y, "pour_only");
  free(y);
}

/* Claim: outlets remove the same particles at the same steps split as serial, and the CSV's
 * counts, masses and flows are the serial run's, on 1 .. 4 processes. */
static void test_silo(void **state) {
  (void)state;
  const char *sets[] = {"time.end=0.12", "output.checkpoint_interval=0.06",
                        "output.mass_flow.orifice.window=0.03",
                        "walls.plate.file=" ADEM_SOURCE_DIR "/cases/silo/plate-24mm.stl"};
  char *text = feature_case_with_sets("outlets-silo", sets, 4);
  char *y = case_file("silo.yaml", text);
  free(text);
  runs_equal(y, "silo");
  free(y);
}

static void test_hopper(void **state) {
  (void)state;
  char *y = hopper_file();
  runs_equal(y, "hopper");
  free(y);
}

/* The lines of text that hold `what`, in order (a static buffer). */
static const char *lines_with(const char *text, const char *what) {
  static char buf[8192];
  size_t n = 0;
  buf[0] = '\0';
  for (const char *l = text; *l;) {
    size_t len = strcspn(l, "\n");
    const char *hit = strstr(l, what);
    if (hit && hit < l + len && n + len + 2 < sizeof buf) {
      memcpy(buf + n, l, len);
      n += len;
      buf[n++] = '\n';
      buf[n] = '\0';
    }
    l += len + (l[len] == '\n');
  }
  return buf;
}

static void test_mesh_servo(void **state) {
  (void)state;
  char *y = mesh_servo_file();
  runs_equal(y, "mesh_servo");
  /* a gain a thousand times too high: the stability warnings (stiffness summed over every
   * process's contacts in the serial order) are the serial run's, word for word */
  char text[8192] = "";
  char *servo = mesh_servo_text();
  for (const char *at = servo, *g; *at; at = g + 9) {
    g = strstr(at, "gain: 5.0");
    if (!g) {
      strncat(text, at, sizeof text - strlen(text) - 1);
      break;
    }
    strncat(text, at, (size_t)(g - at));
    strncat(text, "gain: 5000.0", sizeof text - strlen(text) - 1);
  }
  free(servo);
  free(y);
  y = case_file("servo_case/servo_warn.yaml", text);
  const char *sets = "--set time.end=0.016";
  assert_int_equal(adem_np(0, NULL, "run '%s' --out '%s/warn_serial' %s --threads 1", y, tmpdir, sets), 0);
  char serial[8192];
  snprintf(serial, sizeof serial, "%s", lines_with(np_out, "may be unstable"));
  assert_non_null(strstr(serial, "may be unstable"));
  assert_int_equal(adem_np(3, NULL, "run '%s' --out '%s/warn_np3' %s --threads 1", y, tmpdir, sets), 0);
  assert_string_equal(serial, lines_with(np_out, "may be unstable"));
  printf("# gain 5000, 3 processes: the servo warnings are the serial run's:\n%s", serial);
  free(y);
}

/* Part of the run on 3 processes, the rest resumed from its checkpoint on 2: the serial end. */
static void resumed(const char *yaml, const char *name, const char *half, const char *end) {
  char whole[64], part[64];
  snprintf(whole, sizeof whole, "%s_whole", name);
  snprintf(part, sizeof part, "%s_half", name);
  assert_int_equal(adem_np(0, NULL, "run '%s' --out '%s/%s' --threads 1 --quiet", yaml, tmpdir, whole), 0);
  assert_int_equal(adem_np(3, NULL, "run '%s' --out '%s/%s' --set time.end=%s --threads 1 --quiet",
                           yaml, tmpdir, part, half),
                   0);
  assert_int_equal(adem_np(2, NULL, "run --resume '%s/%s' --set time.end=%s --threads 1 --quiet",
                           tmpdir, part, end),
                   0);
  const char *why = differs(whole, part);
  if (why) fail_msg("%s: resumed on 2 processes from 3's checkpoint at t = %s s: %s differs", name,
                    half, why);
  printf("# %s: 3 processes to t = %s s, resumed on 2 to %s s: the serial run's\n", name, half, end);
}

static void test_restart(void **state) {
  (void)state;
  char *y = case_file("press.yaml", press_case);
  resumed(y, "press", "0.012", "0.024");
  free(y);
  y = case_file("pour.yaml", pour_case);
  resumed(y, "pour", "0.0042", "0.014");
  free(y);
  y = hopper_file();
  resumed(y, "hopper", "0.045", "0.09");
  free(y);
}

/* Each exchange left out in turn: the run differs from the serial one (or fails). */
static void broken(const char *yaml, const char *name, int np, const char *brk) {
  char serial[64], d[64];
  snprintf(serial, sizeof serial, "%s_cserial", name);
  snprintf(d, sizeof d, "%s_%s", name, brk);
  assert_int_equal(adem_np(0, NULL, "run '%s' --out '%s/%s' --threads 1 --quiet", yaml, tmpdir, serial), 0);
  int st = adem_np(np, brk, "run '%s' --out '%s/%s' --threads 1 --quiet", yaml, tmpdir, d);
  const char *why = st ? "the run failed" : differs(serial, d);
  printf("# %s on %d processes without `%s`: %s\n", name, np, brk, why ? why : "no difference");
  if (!why) fail_msg("%s: leaving out %s changes nothing: the test cannot see it", name, brk);
}

static void test_controls(void **state) {
  (void)state;
  char *y = case_file("press.yaml", press_case);
  broken(y, "press", 2, "plane_forces");
  free(y);
  y = mesh_servo_file();
  broken(y, "mesh_servo", 2, "face_loads");
  free(y);
  y = hopper_file();
  broken(y, "hopper", 3, "mesh_history");
  free(y);
  y = case_file("pour.yaml", pour_case);
  broken(y, "pour", 2, "resplit");
  free(y);
  y = case_file("press.yaml", press_case);
  broken(y, "press", 3, "resplit");
  free(y);
  y = case_file("periodic.yaml", periodic_case);
  broken(y, "periodic", 2, "periodic_axis");
  free(y);
}

/* Frame k of tmpdir/dir: the .vtu, or the .pvtu's np pieces together (checked: the .pvtu names
 * them); the particles by id in *ids order. */
static adem_vtu_frame read_frame(const char *dir, int k, int np) {
  char path[700];
  adem_vtu_frame all;
  memset(&all, 0, sizeof all);
  adem_error err;
  if (np == 0) {
    snprintf(path, sizeof path, "%s/%s/frames/particles_%06d.vtu", tmpdir, dir, k);
    if (adem_vtu_read_file(path, &all, &err)) fail_msg("%s", err.message);
    return all;
  }
  snprintf(path, sizeof path, "%s/%s/frames/particles_%06d.pvtu", tmpdir, dir, k);
  char *pv = slurp(path);
  if (!pv) fail_msg("no %s", path);
  size_t cap = 0;
  for (int q = 0; q < np; ++q) {
    char src[128];
    snprintf(src, sizeof src, "<Piece Source=\"particles_%06d_p%d.vtu\"/>", k, q);
    if (!strstr(pv, src)) fail_msg("%s does not name piece %d", path, q);
    snprintf(path, sizeof path, "%s/%s/frames/particles_%06d_p%d.vtu", tmpdir, dir, k, q);
    adem_vtu_frame f;
    if (adem_vtu_read_file(path, &f, &err)) fail_msg("%s", err.message);
    if (all.n + f.n > cap) {
      cap = 2 * (all.n + f.n) + 16;
      all.pos = realloc(all.pos, cap * sizeof *all.pos);
      all.radius = realloc(all.radius, cap * sizeof *all.radius);
      all.id = realloc(all.id, cap * sizeof *all.id);
      assert_true(all.pos && all.radius && all.id);
    }
    memcpy(all.pos + all.n, f.pos, f.n * sizeof *f.pos);
    memcpy(all.radius + all.n, f.radius, f.n * sizeof *f.radius);
    memcpy(all.id + all.n, f.id, f.n * sizeof *f.id);
    all.n += f.n;
    all.time = f.time;
    all.step = f.step;
    adem_vtu_frame_free(&f);
  }
  free(pv);
  return all;
}

/* What differs between two frames, compared by id (each id once), or NULL. */
static const char *frames_differ(const adem_vtu_frame *a, const adem_vtu_frame *b) {
  if (a->n != b->n) return "the particle count";
  if (memcmp(&a->time, &b->time, sizeof a->time) || a->step != b->step) return "the time";
  size_t n = a->n;
  long long *where = malloc((n + 1) * sizeof *where);
  assert_non_null(where);
  for (size_t i = 0; i < n; ++i) where[i] = -1;
  const char *why = NULL;
  for (size_t i = 0; i < n && !why; ++i) {
    if (b->id[i] < 0 || (size_t)b->id[i] >= n || where[b->id[i]] >= 0) why = "the ids";
    else where[b->id[i]] = (long long)i;
  }
  for (size_t i = 0; i < n && !why; ++i) {
    if (a->id[i] < 0 || (size_t)a->id[i] >= n || where[a->id[i]] < 0) why = "the ids";
    else {
      size_t j = (size_t)where[a->id[i]];
      if (memcmp(&a->pos[i], &b->pos[j], sizeof a->pos[i]) ||
          memcmp(&a->radius[i], &b->radius[j], sizeof a->radius[i]))
        why = "a position or radius";
    }
  }
  free(where);
  return why;
}

/* The frames of `adem run` and of `mpirun -np np` with output.pieces (brk: a control): the
 * same particles (every id once), the same bits; the PVD lists the .pvtu files. */
static const char *pieces_differ(const char *yaml, const char *name, int np, const char *brk,
                                 int nframes) {
  char serial[64], d[64], path[700];
  snprintf(serial, sizeof serial, "%s_pserial", name);
  snprintf(d, sizeof d, "%s_pieces%d%s", name, np, brk ? brk : "");
  snprintf(path, sizeof path, "%s/%s/checkpoint", tmpdir, serial);
  FILE *done = fopen(path, "rb"); /* the serial run once per case */
  if (done) fclose(done);
  else
    assert_int_equal(adem_np(0, NULL, "run '%s' --out '%s/%s' --threads 1 --quiet", yaml, tmpdir, serial), 0);
  assert_int_equal(adem_np(np, brk, "run '%s' --out '%s/%s' --set output.pieces=true --threads 1 --quiet",
                           yaml, tmpdir, d),
                   0);
  snprintf(path, sizeof path, "%s/%s/particles.pvd", tmpdir, d);
  char *pvd = slurp(path);
  assert_non_null(pvd);
  char entry[64];
  snprintf(entry, sizeof entry, "frames/particles_%06d.pvtu", nframes - 1);
  assert_non_null(strstr(pvd, entry));
  free(pvd);
  const char *why = differs(serial, d);
  for (int k = 0; k < nframes && !why; ++k) {
    adem_vtu_frame a = read_frame(serial, k, 0), b = read_frame(d, k, np);
    why = frames_differ(&a, &b);
    adem_vtu_frame_free(&a);
    adem_vtu_frame_free(&b);
    char pa[700], pb[700];
    snprintf(pa, sizeof pa, "%s/%s/frames/mesh_%06d.vtu", tmpdir, serial, k);
    snprintf(pb, sizeof pb, "%s/%s/frames/mesh_%06d.vtu", tmpdir, d, k);
    size_t na = 0, nb = 0;
    char *ma = slurp_n(pa, &na), *mb = slurp_n(pb, &nb); /* the mesh frames: the same bytes */
    if (!why && (!ma) != (!mb)) why = "the mesh frames";
    if (!why && ma && (na != nb || memcmp(ma, mb, na) != 0)) why = "a mesh frame";
    free(ma);
    free(mb);
  }
  return why;
}

static void test_pieces(void **state) {
  (void)state;
  char *y = case_file("press.yaml", press_case);
  for (int np = 2; np <= 4; ++np) {
    const char *why = pieces_differ(y, "press", np, NULL, 6);
    if (why) fail_msg("frames in pieces on %d processes: %s differs", np, why);
    printf("# press, %d processes: the 6 frames' pieces together are the serial frames\n", np);
  }
  const char *why = pieces_differ(y, "press", 3, "pieces", 6);
  printf("# control: pieces with the ghosts: %s\n", why ? why : "no difference");
  if (!why) fail_msg("a piece with ghosts is not seen");
  free(y);
  y = hopper_file(); /* meshes: the mesh frames too */
  why = pieces_differ(y, "hopper", 3, NULL, 4);
  if (why) fail_msg("hopper in pieces on 3 processes: %s differs", why);
  free(y);
}

/* The periodic bed (x and y wrap: slabs along z) with a top plate that a second stage lowers
 * and drags along x (a shear box in small). */
static char *periodic_shear(void) {
  const char *at = strstr(periodic_case, "domain:\n"), *t = strstr(periodic_case, "time:\n");
  char text[8192];
  snprintf(text, sizeof text,
           "%.*s  - {type: plane, name: top, material: steel, point: [0, 0, 0.035], normal: [0, 0, -1]}\n"
           "%.*sstages:\n"
           "  - {name: fall, duration: 0.006}\n"
           "  - name: shear\n"
           "    set:\n"
           "      walls.top.motion: {velocity: [0.3, 0, -1.5]}\n"
           "%s",
           (int)(at - periodic_case), periodic_case, (int)(t - at), at, t);
  return case_file("periodic_shear.yaml", text);
}

static void test_periodic(void **state) {
  (void)state;
  char *y = periodic_shear();
  runs_equal(y, "periodic_shear");
  free(y);
}

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_split_features") ? -1 : 0;
}

int main(int argc, char **argv) {
  const struct CMUnitTest all[] = {
      cmocka_unit_test(test_press),
      cmocka_unit_test(test_pour),
      cmocka_unit_test(test_hopper),
      cmocka_unit_test(test_silo),
      cmocka_unit_test(test_mesh_servo),
      cmocka_unit_test(test_restart),
      cmocka_unit_test(test_controls),
      cmocka_unit_test(test_pieces),
      cmocka_unit_test(test_periodic),
  };
  /* one name per entry of all[], in its order (ctest runs each group by its name) */
  const char *names[] = {"press", "pour", "hopper", "silo", "mesh_servo",
                         "restart", "controls", "pieces", "periodic"};
  int n = (int)(sizeof all / sizeof all[0]);
  _Static_assert(sizeof names / sizeof names[0] == sizeof all / sizeof all[0],
                 "a name for every test group");
  if (argc > 1) {
    for (int k = 0; k < n; ++k)
      if (strcmp(argv[1], names[k]) == 0) {
        struct CMUnitTest one[1] = {all[k]};
        return _cmocka_run_group_tests(names[k], one, 1, setup, tmpdir_teardown);
      }
    fprintf(stderr, "no test group `%s`\n", argv[1]);
    return 2;
  }
  return cmocka_run_group_tests(all, setup, tmpdir_teardown);
}
