/* Staged runs and pours: what a stage changes takes effect at its start (the pair friction of a
 * sliding sphere, a wall switched off, a wall set moving from where it is), and a staged run with
 * a pour is deterministic: the same for 1 and 2 threads and any chunking, resumed bit for bit
 * from checkpoints written in stage 1, in stage 2 and in the middle of the pour. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bitwise/settle_case.h"
#include "case_file.h"
#include "insert.h"
#include "restart_run.h"
#include "staged_run.h"

static void quiet(adem_log_level level, const char *message, void *user) {
  (void)level, (void)message, (void)user;
}

static int setup(void **state) {
  (void)state;
  adem_log_set_hook(quiet, NULL);
  return tmpdir_make("adem_stages");
}

/* The sliding sphere (tests/cases/stages-slide.yaml) with the overrides SETS. */
static adem_case *load_slide(const char *const *sets, int nsets) {
  return case_file_load("stages-slide", sets, nsets);
}

static double vx_at(adem_case *c, double t) {
  adem_error err;
  uint64_t s = (uint64_t)llround(t / c->world->dt);
  if (staged_advance(c, s, 100, &err)) fail_msg("%s", err.message);
  return c->world->p.vel[0].x;
}

/* Claim: setting friction to 0 in a stage re-derives the pair table: the sphere slides without
 * losing speed (deceleration 0, to round-off), and restoring it in the next stage brings back
 * Coulomb sliding, deceleration mu g = 0.5 x 9.81 = 4.905 m/s^2. The normal force oscillates
 * about m g (the sphere settles into the Hertz contact, damped by e = 0.5), so over 10 ms the
 * mean is m g within 1 %; 2 % is the tolerance. */
static void test_friction_stages(void **state) {
  (void)state;
  adem_error err;
  adem_case *c = load_slide(NULL, 0);
  adem_world *w = c->world;
  const adem_interaction *it = adem_world_interaction(w, 0, 1);
  assert_true(it->pp.friction == 0.0); /* stage 0 is in force from the start */
  assert_int_equal(staged_start(c, &err), ADEM_OK);
  double v1 = vx_at(c, 0.005), v2 = vx_at(c, 0.015);
  double a_pack = (v1 - v2) / 0.01;
  assert_int_equal(adem_stages_current(c), 0);
  double v3 = vx_at(c, 0.025), v4 = vx_at(c, 0.035);
  double a_test = (v3 - v4) / 0.01;
  assert_int_equal(adem_stages_current(c), 1);
  it = adem_world_interaction(w, 0, 1);
  printf("# deceleration %.3g m/s^2 with friction 0, %.5g m/s^2 with 0.5 (mu g = 4.905); pair "
         "friction now %g\n",
         a_pack, a_test, it->pp.friction);
  assert_true(it->pp.friction == 0.5);
  assert_float_equal(a_pack, 0.0, 1e-9);
  assert_float_equal(a_test, 0.5 * 9.81, 0.02 * 0.5 * 9.81);
  assert_true(v4 > 5.0 / 7.0); /* still sliding: rolling without slip starts at 5/7 v0 */
  adem_case_free(c);
}

/* Claim: a stage that switches the floor off lets the sphere fall freely (acceleration -g within
 * 1e-9 relative: nothing else acts on it), and a plane set moving in a stage starts from where it
 * is, its motion's clock starting at the stage's start (no jump: the plane is at its old place
 * plus v (t - t_stage)). */
static void test_walls_in_stages(void **state) {
  (void)state;
  adem_error err;
  const char *sets[] = {"stages.1.set={walls.floor.active: false}",
                        "walls=[{type: plane, name: floor, material: steel, point: [0, 0, 0], "
                        "normal: [0, 0, 1]}, {type: plane, name: wall, material: steel, point: "
                        "[0.2, 0, 0], normal: [-1, 0, 0], velocity: [0.1, 0, 0]}]",
                        "stages.0.set={walls.wall.velocity: [-0.5, 0, 0]}"};
  adem_case *c = load_slide(sets, 3);
  adem_world *w = c->world;
  assert_int_equal(staged_start(c, &err), ADEM_OK);
  /* stage 0 sets the wall moving at -0.5 m/s from t = 0 */
  vx_at(c, 0.02);
  double dt = w->dt, t_s = (double)adem_stages_start_step(c, 1) * dt;
  assert_float_equal(w->walls.planes[1].def.point.x, 0.2 - 0.5 * t_s, 1e-12);
  double z1 = w->p.pos[0].z;
  (void)vx_at(c, 0.03);
  double vz1 = w->p.vel[0].z, t1 = w->time;
  (void)vx_at(c, 0.04);
  double vz2 = w->p.vel[0].z, z2 = w->p.pos[0].z;
  double g = (vz2 - vz1) / (w->time - t1);
  printf("# floor off: dv_z/dt = %.12g m/s^2, fell %g m; the wall at x = %g\n", g, z1 - z2,
         w->walls.planes[1].def.point.x);
  assert_float_equal(g, -9.81, 9.81 * 1e-9);
  assert_true(z2 - 0.005 < -0.0015); /* a third of the way through where the floor was */
  assert_true(w->walls.planes[0].inactive);
  adem_case_free(c);

  /* a motion set in stage 1 only: the wall rests until then, then moves from its place */
  const char *sets3[] = {"walls=[{type: plane, name: floor, material: steel, point: [0, 0, 0], "
                         "normal: [0, 0, 1]}, {type: plane, name: wall, material: steel, point: "
                         "[0.2, 0, 0], normal: [-1, 0, 0]}]",
                         "stages.1.set={walls.wall.motion: {velocity: [-0.5, 0, 0]}}"};
  adem_case *d = NULL;
  d = load_slide(sets3, 2);
  w = d->world;
  assert_int_equal(staged_start(d, &err), ADEM_OK);
  vx_at(d, 0.02);
  t_s = (double)adem_stages_start_step(d, 1) * w->dt;
  assert_true(w->walls.planes[1].def.point.x == 0.2); /* at rest through stage 0, moved at its start */
  vx_at(d, 0.04);
  double t = w->time;
  printf("# wall set moving at t = %g s: at t = %g s it is at x = %.12g (expected %.12g)\n", t_s,
         t, w->walls.planes[1].def.point.x, 0.2 - 0.5 * (t - t_s));
  assert_float_equal(w->walls.planes[1].def.point.x, 0.2 - 0.5 * (t - t_s), 1e-12);
  adem_case_free(d);

  /* a mesh floor (the top face of an STL block) switched off by stage 1 */
  char mesh[600];
  snprintf(mesh, sizeof mesh,
           "walls=[{type: mesh, name: block, material: steel, file: %s/tests/data/cube_ascii.stl, "
           "scale: 0.1, translate: [-0.05, -0.05, -0.1]}]",
           ADEM_SOURCE_DIR);
  const char *sets4[] = {mesh, "particles.0.spheres.0.velocity=[0, 0, 0]",
                         "stages.1.set={walls.block.active: false}"};
  adem_case *e = load_slide(sets4, 3);
  w = e->world;
  assert_int_equal(staged_start(e, &err), ADEM_OK);
  vx_at(e, 0.019);
  double z_rest = w->p.pos[0].z, t_off = (double)adem_stages_start_step(e, 1) * w->dt;
  vx_at(e, 0.04);
  double fall = z_rest - w->p.pos[0].z, free_fall = 0.5 * 9.81 * (w->time - t_off) * (w->time - t_off);
  printf("# mesh floor off at t = %g s: fell %g m (free fall %g m)\n", t_off, fall, free_fall);
  assert_true(fabs(z_rest - 0.005) < 1e-4); /* resting on the block until then */
  assert_float_equal(fall, free_fall, 0.05 * free_fall);
  adem_case_free(e);
}

/* The settle case with a pour and stages, as --set overrides: friction off and stronger gravity
 * while packing, then friction back, a lid switched on and moving down, and a denser CSV; the
 * fifth override (another seed) only when asked for. */
static const char *const staged_sets[] = {
    "walls=[{type: box, name: box, material: steel, min: [0, 0, 0], max: [0.015, 0.015, 0.05]},"
    " {type: plane, name: lid, material: steel, point: [0, 0, 0.049], normal: [0, 0, -1],"
    " active: false}]",
    "pours=[{name: feed, material: glass, radius: {distribution: normal, mean: 0.001, std: 0.0001},"
    " region: {shape: box, min: [0.001, 0.001, 0.03], max: [0.014, 0.014, 0.045]}, rate: 10000,"
    " start: 0.002, end: 0.009, interval: 0.001, velocity: [0, 0, -0.5]}]",
    "stages=[{name: pack, duration: 0.006,"
    " set: {materials.glass.friction: 0, materials.steel.friction: 0, gravity: [0, 0, -15]}},"
    " {name: press, set: {materials.glass.friction: 0.5, materials.steel.friction: 0.4,"
    " gravity: [0, 0, -9.81], walls.lid.active: true, walls.lid.motion: {velocity: [0, 0, -0.5]},"
    " output.csv_interval: 0.0007, output.frame_interval: 0.002}}]",
    "seed=8"};
#define staged_settle(other_seed) settle_load(staged_sets, (other_seed) ? 4 : 3)

static void assert_same(const adem_world *a, const adem_world *b, const char *what_run) {
  const char *what = "";
  if (!settle_same_state(a, b, &what)) fail_msg("%s differs in %s", what_run, what);
}

/* Claim: the staged, poured run ends bit for bit the same when run in chunks of 100 steps with 2
 * threads, in chunks of 7 with 1 thread, and when resumed from checkpoints written in stage 1
 * (during the pour), right at the start of stage 2, and in stage 2 after the pour. */
static void test_staged_restart(void **state) {
  (void)state;
  adem_error err;
  adem_case *a = staged_settle(false);
  adem_world_set_threads(a->world, 2);
  a->world->parallel_min = 0; /* small systems would otherwise stay on one thread */
  uint64_t total = adem_schedule_total_steps(a->end_time, a->world->dt);
  assert_int_equal(staged_start(a, &err), ADEM_OK);
  if (staged_advance(a, total, 100, &err)) fail_msg("%s", err.message);
  uint64_t s2 = adem_stages_start_step(a, 1);
  printf("# %zu particles (%zu poured), stage 2 from step %llu of %llu, %zu loaded contacts\n",
         a->world->p.n, a->world->p.n - 300, (unsigned long long)s2, (unsigned long long)total,
         settle_loaded_contacts(a->world));
  assert_int_equal(a->world->p.n, 300 + 70);
  assert_int_equal(adem_stages_current(a), 1);
  assert_true(settle_loaded_contacts(a->world) > 100);

  adem_case *b = staged_settle(false);
  adem_world_set_threads(b->world, 1);
  assert_int_equal(staged_start(b, &err), ADEM_OK);
  if (staged_advance(b, total, 7, &err)) fail_msg("%s", err.message);
  assert_same(a->world, b->world, "1 thread, chunks of 7");
  adem_case_free(b);

  uint64_t stops[3] = {s2 / 2, s2, s2 + (total - s2) / 2};
  for (int k = 0; k < 3; ++k) {
    adem_case *c = staged_settle(false);
    assert_int_equal(staged_start(c, &err), ADEM_OK);
    if (staged_advance(c, stops[k], 100, &err)) fail_msg("%s", err.message);
    int stage = adem_stages_current(c);
    uint64_t poured = c->pours->p[0].inserted;
    char path[512];
    snprintf(path, sizeof path, "%s/stop%d.ckpt", tmpdir, k);
    if (adem_checkpoint_write(c, path, &err)) fail_msg("%s", err.message);
    adem_case_free(c);
    adem_case *r = NULL;
    if (adem_checkpoint_read(path, &r, &err)) fail_msg("%s", err.message);
    assert_int_equal(adem_stages_current(r), stage);
    assert_true(adem_world_interaction(r->world, 0, 1)->pp.friction == (stage ? 0.45 : 0.0));
    if (staged_advance(r, total, 100, &err)) fail_msg("%s", err.message);
    printf("# resumed from step %llu (stage %d, %llu poured)\n", (unsigned long long)stops[k],
           stage + 1, (unsigned long long)poured);
    char what[64];
    snprintf(what, sizeof what, "the run resumed at step %llu", (unsigned long long)stops[k]);
    assert_same(a->world, r->world, what);
    adem_case_free(r);
  }
  adem_case *d = staged_settle(true);
  assert_int_equal(staged_start(d, &err), ADEM_OK);
  if (staged_advance(d, total, 100, &err)) fail_msg("%s", err.message);
  assert_int_equal(d->world->p.n, a->world->p.n);
  const char *what = "";
  assert_false(settle_same_state(a->world, d->world, &what)); /* another seed, other particles */
  adem_case_free(d);
  adem_case_free(a);
}

/* Claim: through adem_run, the staged, poured run stopped after every chunk and resumed from its
 * checkpoint each time ends like the run never stopped, its CSV and PVD (whose intervals the
 * second stage changes) included. */
static void test_run_interrupted(void **state) {
  (void)state;
  adem_error err;
  adem_case *a = staged_settle(false);
  snprintf(a->output.dir, sizeof a->output.dir, "%s/run_a", tmpdir);
  adem_run_options opt = adem_default_run_options();
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);

  adem_case *b = staged_settle(false);
  snprintf(b->output.dir, sizeof b->output.dir, "%s/run_b", tmpdir);
  int stops = 0;
  b = run_stopped_everywhere(b, opt, &stops);
  printf("# stopped and resumed %d times\n", stops);
  assert_true(stops >= 20);
  assert_same(a->world, b->world, "the run stopped everywhere");
  const char *files[] = {"timeseries.csv", "particles.pvd", "frames/particles_000005.vtu", NULL};
  assert_same_files("run_a", "run_b", files, "the restarts");
  adem_case_free(a);
  adem_case_free(b);
}

static void expect_error(const char *const *sets, int nsets, const char *w1, const char *w2) {
  adem_case *c = NULL;
  adem_error err;
  if (!adem_case_load_file(case_file_path("stages-slide"), sets, nsets, &c, &err)) {
    adem_case_free(c);
    fail_msg("expected an error with '%s'", w1);
  }
  printf("# %s\n", err.message);
  if (!strstr(err.message, w1) || (w2 && !strstr(err.message, w2)))
    fail_msg("'%s' / '%s' not in: %s", w1, w2 ? w2 : "", err.message);
}

/* Claim: bad stages are refused, naming the stage and the key: an unknown stage key (with a
 * suggestion), a path that does not exist, a key a stage may not change, a value out of range, a
 * motion table not ordered in time, a middle stage without a duration, and a stage that would
 * add a wall. */
static void test_bad_stages(void **state) {
  (void)state;
  const char *unknown_key[] = {"stages.0.durration=1"};
  expect_error(unknown_key, 1, "stages[0].durration", "did you mean `duration`");
  const char *bad_path[] = {"stages.1.set={materials.glass.frction: 0.3}"};
  expect_error(bad_path, 1, "stages[1] (`test`).set", "did you mean `friction`");
  const char *bad_item[] = {"stages.1.set={materials.sand.friction: 0.3}"};
  expect_error(bad_item, 1, "stages[1] (`test`).set", "no item of `materials` has that name");
  const char *fixed[] = {"stages.1.set={time.end: 3}"};
  expect_error(fixed, 1, "stages[1].set.time.end", "cannot change in a stage");
  const char *range[] = {"stages.0.set={materials.glass.friction: -1}"};
  expect_error(range, 1, "stages[0] (`pack`).set", "out of range");
  const char *table[] = {"stages.1.set={walls.floor.motion: {table: [[0.01, 0, 0, 0], [0.005, 0, 0, 1]]}}"};
  expect_error(table, 1, "stages[1] (`test`).set", "not ordered in time");
  const char *duration[] = {"stages=[{name: a, set: {gravity: [0, 0, -1]}}, {name: b}]"};
  expect_error(duration, 1, "stages[0] (`a`): duration", "every stage but the last");
  const char *add[] = {"stages.1.set={walls: [{type: plane, material: steel, point: [0, 0, 0], "
                       "normal: [0, 0, 1]}, {type: plane, material: steel, point: [0, 0, 1], normal: "
                       "[0, 0, -1]}]}"};
  expect_error(add, 1, "stage `test` changes which walls there are", "active: false");
  const char *dup[] = {"stages.1.name=pack"};
  expect_error(dup, 1, "stages[1].name", "duplicate stage name");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_friction_stages),
      cmocka_unit_test(test_walls_in_stages),
      cmocka_unit_test(test_staged_restart),
      cmocka_unit_test(test_run_interrupted),
      cmocka_unit_test(test_bad_stages),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
