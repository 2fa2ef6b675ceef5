/* Claim: a run with a servo-controlled mesh plate (switched on by a stage, then given a new
 * motion by a later stage while the servo goes on) is the same bit for bit on 1 and 2 threads,
 * and a run stopped after every chunk and resumed from its checkpoints, in every stage, ends
 * like the run never stopped: particles, contacts, face loads, the plate's vertices and the
 * servo's state, and the CSV (servo and displacement columns included). The servo's displacement
 * is integrated, not a function of time, so this fails if the checkpoint loses it or if a stage
 * replayed on resume places the plate from the wrong point. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bitwise/settle_case.h"
#include "case_file.h"
#include "plate_stl.h"
#include "restart_run.h"

static char case_path[512];

/* 180 soft spheres fall into a 3 cm box; the plate above them is switched on at 4 ms with a
 * servo (target 0.02 N, about the weight of the bed) and comes down; at 14 ms a
 * new motion slides it along x while the servo keeps holding the force. */
#define servo_case case_file_text("bitwise-servo") /* tests/cases/bitwise-servo.yaml */

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_servo")) return -1;
  char dir[300], cmd[1400];
  snprintf(dir, sizeof dir, "%s/case/meshes", tmpdir);
  snprintf(cmd, sizeof cmd, "mkdir -p '%s' && cp '%s/tests/data/cube_ascii.stl' '%s/cube.stl'", dir,
           ADEM_SOURCE_DIR, dir);
  if (system(cmd) != 0) return -1;
  snprintf(cmd, sizeof cmd, "%s/plate.stl", dir);
  write_plate(cmd, 3, 0.0078125); /* a 2.3 cm plate of 3 x 3 squares */
  snprintf(case_path, sizeof case_path, "%s/case/servo.yaml", tmpdir);
  FILE *f = fopen(case_path, "w");
  if (!f) return -1;
  fputs(servo_case, f);
  fclose(f);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  return tmpdir_remove();
}

static adem_case *load_servo_case(const char *subdir) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_file(case_path, NULL, 0, &c, &err)) fail_msg("case does not load: %s", err.message);
  snprintf(c->output.dir, sizeof c->output.dir, "%s/%s", tmpdir, subdir);
  return c;
}

static const adem_motion *plate_servo(const adem_world *w) {
  int g = adem_mesh_find_group(&w->walls.mesh, "plate");
  assert_true(g >= 0);
  return &w->walls.mesh_motion[g];
}

static void assert_same(const adem_world *a, const adem_world *b) {
  const char *what = "";
  if (!settle_same_state(a, b, &what)) fail_msg("the runs differ in %s", what);
  size_t nf = 3 * a->walls.mesh.ntris;
  if (memcmp(a->walls.face_force, b->walls.face_force, nf * sizeof(double)) != 0) fail_msg("face forces differ");
  if (memcmp(a->walls.mesh.vert, b->walls.mesh.vert, a->walls.mesh.nverts * sizeof(adem_vec3)) != 0)
    fail_msg("mesh vertices differ");
  const adem_motion *p = plate_servo(a), *q = plate_servo(b);
  if (memcmp(&p->servo_u, &q->servo_u, sizeof p->servo_u) || memcmp(&p->servo_v, &q->servo_v, sizeof p->servo_v) ||
      memcmp(&p->servo_force, &q->servo_force, sizeof p->servo_force))
    fail_msg("servo states differ: u %.17g / %.17g, F %.17g / %.17g", p->servo_u, q->servo_u,
             p->servo_force, q->servo_force);
}

/* The runs mean something only if the servo carried its target and moved in both of its stages. */
static void assert_servo_worked(const adem_world *w) {
  const adem_motion *m = plate_servo(w);
  int g = adem_mesh_find_group(&w->walls.mesh, "plate");
  adem_vec3 f[64];
  assert_true(w->walls.mesh.ngroups <= 64);
  adem_world_mesh_loads(w, f, NULL, NULL, NULL);
  printf("# plate: servo u = %.6g m in the last stage, F_z = %.6g N (filtered %.6g), x = %.6g m\n",
         m->servo_u, f[g].z, m->servo_force, w->walls.mesh_ref[g].x);
  assert_true(m->servo.on && m->servo_started);
  assert_true(fabs(m->servo_u) > 1e-5); /* it moved in the slide stage too */
  /* it holds the load to within a factor 2: sliding at 0.2 m/s dilates the bed faster than the
   * servo (time constant 1/(gain K) of a few collision times) follows; this is a bitwise test */
  assert_true(f[g].z > 0.01 && f[g].z < 0.04);
}

/* 1 and 2 threads (every loop parallel: parallel_min = 0) give the same bits. */
static void test_threads(void **state) {
  (void)state;
  adem_error err;
  adem_case *c[2];
  adem_run_options opt = adem_default_run_options();
  for (int k = 0; k < 2; ++k) {
    c[k] = load_servo_case(k ? "t2" : "t1");
    c[k]->world->parallel_min = 0;
    opt.nthreads = k + 1;
    if (adem_run(c[k], &opt, &err)) fail_msg("%s", err.message);
  }
  assert_servo_worked(c[0]->world);
  assert_same(c[0]->world, c[1]->world);
  const char *files[] = {"timeseries.csv", NULL};
  assert_same_files("t1", "t2", files, "1 and 2 threads");
  adem_case_free(c[0]);
  adem_case_free(c[1]);
}

/* Stopped after every chunk (in every stage) and resumed each time, files included. */
static void test_run_interrupted_everywhere(void **state) {
  (void)state;
  adem_error err;
  adem_case *a = load_servo_case("run_a");
  adem_run_options opt = adem_default_run_options();
  opt.nthreads = 1;
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  adem_case *b = load_servo_case("run_b");
  int stops = 0;
  b = run_stopped_everywhere(b, opt, &stops);
  printf("# stopped and resumed %d times\n", stops);
  assert_true(stops >= 20);
  assert_servo_worked(a->world);
  assert_same(a->world, b->world);
  const char *files[] = {"timeseries.csv", NULL};
  assert_same_files("run_a", "run_b", files, "the restarts");
  adem_case_free(a);
  adem_case_free(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_threads),
      cmocka_unit_test(test_run_interrupted_everywhere),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
