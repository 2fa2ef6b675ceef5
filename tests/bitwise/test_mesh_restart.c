/* Claim: a run with mesh walls (a box of STL faces and a plate that slides to and fro and spins
 * under the falling spheres) restarted from a checkpoint continues bit for bit like the uninterrupted run
 * (particles, the particle-mesh pair list with its region keys, owners and history, the face
 * loads, and the output files, mesh frames included), the checkpoint read from another working
 * folder; and 1 thread gives the same bits as 2. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bitwise/settle_case.h"
#include "case_file.h"
#include "plate_stl.h"
#include "restart_run.h"

#define MESH_STEPS 3000

static char case_path[512], cwd[4096];

#define mesh_case case_file_text("bitwise-mesh") /* tests/cases/bitwise-mesh.yaml */

static int setup(void **state) {
  (void)state;
  if (!getcwd(cwd, sizeof cwd)) return -1;
  if (tmpdir_make("adem_meshrestart")) return -1;
  char dir[300], cmd[1400];
  snprintf(dir, sizeof dir, "%s/case/meshes", tmpdir);
  snprintf(cmd, sizeof cmd, "mkdir -p '%s' && cp '%s/tests/data/cube_ascii.stl' '%s/cube.stl'", dir,
           ADEM_SOURCE_DIR, dir);
  if (system(cmd) != 0) return -1;
  snprintf(cmd, sizeof cmd, "%s/plate.stl", dir);
  write_plate(cmd, 3, 0.004); /* a 0.012 m plate of 3 x 3 squares */
  snprintf(case_path, sizeof case_path, "%s/case/mesh.yaml", tmpdir);
  FILE *f = fopen(case_path, "w");
  if (!f) return -1;
  fputs(mesh_case, f);
  fclose(f);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  if (chdir(cwd) != 0) return -1;
  return tmpdir_remove();
}

/* The case loaded from its file (relative mesh paths), output into tmpdir/subdir. */
static adem_case *load_mesh_case(const char *subdir) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_file(case_path, NULL, 0, &c, &err)) fail_msg("case does not load: %s", err.message);
  snprintf(c->output.dir, sizeof c->output.dir, "%s/%s", tmpdir, subdir);
  return c;
}

/* settle_same_state, plus the mesh contacts and the face loads. */
static void assert_same(const adem_world *a, const adem_world *b) {
  const char *what = "";
  if (!settle_same_state(a, b, &what)) fail_msg("the runs differ in %s", what);
  const adem_mesh_pairs *p = &a->pm, *q = &b->pm;
  size_t n = p->l.n;
  if (n != q->l.n) fail_msg("mesh pair counts differ: %zu, %zu", n, q->l.n);
  if (memcmp(p->start, q->start, (a->p.n + 1) * sizeof *p->start) != 0)
    fail_msg("mesh slot ranges differ");
  if (memcmp(p->l.b, q->l.b, n * sizeof *p->l.b) != 0) fail_msg("mesh candidate triangles differ");
  if (memcmp(p->l.touching, q->l.touching, n * sizeof *p->l.touching) != 0)
    fail_msg("mesh touching flags differ");
  for (size_t k = 0; k < n; ++k) {
    if (!p->l.touching[k]) continue;
    if (p->key[k] != q->key[k] || p->owner[k] != q->owner[k]) fail_msg("mesh contact %zu differs", k);
    if (memcmp(&p->l.hist[k], &q->l.hist[k], sizeof p->l.hist[k]) != 0)
      fail_msg("mesh contact history %zu differs", k);
    if (memcmp(&p->l.res[k].force_a, &q->l.res[k].force_a, sizeof(adem_vec3)) != 0)
      fail_msg("mesh contact force %zu differs", k);
  }
  size_t nf = 3 * a->walls.mesh.ntris;
  if (memcmp(a->walls.face_force, b->walls.face_force, nf * sizeof(double)) != 0) fail_msg("face forces differ");
  if (memcmp(a->walls.face_torque, b->walls.face_torque, nf * sizeof(double)) != 0) fail_msg("face torques differ");
  if (memcmp(a->walls.mesh.vert, b->walls.mesh.vert, a->walls.mesh.nverts * sizeof(adem_vec3)) != 0)
    fail_msg("mesh vertices differ");
}

/* Mesh contacts with a loaded tangential spring, and contacts on the moving plate. */
static void mesh_activity(const adem_world *w, size_t *loaded, size_t *on_plate) {
  *loaded = *on_plate = 0;
  int plate = adem_mesh_find_group(&w->walls.mesh, "plate");
  for (size_t k = 0; k < w->pm.l.n; ++k) {
    if (!w->pm.l.touching[k]) continue;
    if (w->pm.l.hist[k].tangential.x != 0.0) ++*loaded;
    if ((int)w->walls.mesh.group[w->pm.owner[k]] == plate) ++*on_plate;
  }
}

/* Stop halfway, checkpoint, read it back from another working folder, go on. */
static void test_restart_halfway(void **state) {
  (void)state;
  adem_error err;
  adem_case *a = load_mesh_case("a");
  assert_int_equal(adem_world_prepare(a->world, &err), ADEM_OK);
  if (adem_world_step(a->world, MESH_STEPS, &err)) fail_msg("%s", err.message);

  adem_case *b = load_mesh_case("b");
  assert_int_equal(adem_world_prepare(b->world, &err), ADEM_OK);
  if (adem_world_step(b->world, MESH_STEPS / 2, &err)) fail_msg("%s", err.message);
  uint64_t rebuilds_half = b->world->nb.rebuilds;
  size_t loaded_half, plate_half;
  mesh_activity(b->world, &loaded_half, &plate_half);
  char path[512];
  snprintf(path, sizeof path, "%s/halfway.ckpt", tmpdir);
  if (adem_checkpoint_write(b, path, &err)) fail_msg("%s", err.message);
  adem_case_free(b);
  assert_int_equal(chdir("/"), 0); /* the case's meshes/ is relative to its own folder */
  adem_case *r = NULL;
  adem_status st = adem_checkpoint_read(path, &r, &err);
  assert_int_equal(chdir(cwd), 0);
  if (st) fail_msg("%s", err.message);
  if (adem_world_step(r->world, MESH_STEPS / 2, &err)) fail_msg("%s", err.message);

  size_t loaded, on_plate;
  mesh_activity(a->world, &loaded, &on_plate);
  printf("# halfway: %zu loaded mesh contacts, %zu on the plate; end: %zu and %zu; %llu rebuilds "
         "(%llu after the restart)\n",
         loaded_half, plate_half, loaded, on_plate, (unsigned long long)a->world->nb.rebuilds,
         (unsigned long long)(a->world->nb.rebuilds - rebuilds_half));
  /* the comparison means something only with mesh history at the restart and after it */
  assert_true(loaded_half >= 5 && plate_half >= 3 && loaded > 20 && on_plate >= 3);
  assert_true(a->world->nb.rebuilds > rebuilds_half);
  assert_same(a->world, r->world);
  adem_case_free(a);
  adem_case_free(r);
}

/* Through adem_run: stopped after every chunk and resumed each time, files included. */
static void test_run_interrupted_everywhere(void **state) {
  (void)state;
  adem_error err;
  adem_case *a = load_mesh_case("run_a");
  adem_run_options opt = adem_default_run_options();
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  adem_case *b = load_mesh_case("run_b");
  int stops = 0;
  b = run_stopped_everywhere(b, opt, &stops);
  printf("# stopped and resumed %d times\n", stops);
  assert_true(stops >= 20);
  assert_same(a->world, b->world);
  const char *files[] = {"timeseries.csv", "particles.pvd", "mesh.pvd", "frames/mesh_000002.vtu",
                         "frames/mesh_000004.vtu", "frames/particles_000004.vtu", NULL};
  assert_same_files("run_a", "run_b", files, "the restart");
  adem_case_free(a);
  adem_case_free(b);
}

/* 1 and 2 threads (every loop parallel: parallel_min = 0) give the same bits. */
static void test_threads(void **state) {
  (void)state;
  adem_error err;
  adem_case *c[2];
  for (int k = 0; k < 2; ++k) {
    c[k] = load_mesh_case(k ? "t2" : "t1");
    adem_world_set_threads(c[k]->world, k + 1);
    c[k]->world->parallel_min = 0;
    assert_int_equal(adem_world_prepare(c[k]->world, &err), ADEM_OK);
    if (adem_world_step(c[k]->world, MESH_STEPS, &err)) fail_msg("%s", err.message);
  }
  assert_same(c[0]->world, c[1]->world);
  adem_case_free(c[0]);
  adem_case_free(c[1]);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_restart_halfway),
      cmocka_unit_test(test_run_interrupted_everywhere),
      cmocka_unit_test(test_threads),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
