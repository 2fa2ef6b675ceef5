/* How a run ends and goes on: the plots of a run however it stops, a later end on resume. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "golden/settle_case.h"
#include "restart_run.h"
#include "stages.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_runctl");
}

static adem_case *load_settle(const char *subdir, const char *const *sets, int nsets) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_string(settle_case, "settle.yaml", sets, nsets, &c, &err))
    fail_msg("case does not load: %s", err.message);
  snprintf(c->output.dir, sizeof c->output.dir, "%s/%s", tmpdir, subdir);
  return c;
}

static bool have_gnuplot(void) { return system("command -v gnuplot > /dev/null 2>&1") == 0; }

/* Whether tmpdir/DIR/NAME exists; removes it (so that the next look sees a fresh one). */
static bool take_file(const char *dir, const char *name) {
  char p[512];
  snprintf(p, sizeof p, "%s/%s/%s", tmpdir, dir, name);
  bool there = file_exists(p);
  unlink(p);
  return there;
}

/* Claim: the energy and load plots are written however a run ends: stopped by a signal (the
 * stop flag SIGINT/SIGTERM set), ended after a resume, and resumed when already at its end. */
static void test_plots_on_every_stop(void **state) {
  (void)state;
  if (!have_gnuplot()) {
    printf("# no gnuplot: nothing to check\n");
    return;
  }
  const char *sets[] = {"output.plot=true", "output.plot_loads=true", "time.end=0.002"};
  adem_case *c = load_settle("plots", sets, 3);
  adem_run_options opt = adem_default_run_options();
  volatile sig_atomic_t stop = 1;
  opt.stop_flag = &stop;
  adem_error err;
  assert_int_equal(adem_run(c, &opt, &err), ADEM_INTERRUPTED);
  assert_true(c->world->step < 286);
  assert_true(take_file("plots", "energy.png"));
  assert_true(take_file("plots", "loads.png"));
  adem_case_free(c);

  char ckpt[600];
  snprintf(ckpt, sizeof ckpt, "%s/plots/checkpoint", tmpdir);
  if (adem_checkpoint_read(ckpt, &c, &err)) fail_msg("%s", err.message);
  opt.stop_flag = NULL;
  assert_int_equal(adem_run(c, &opt, &err), ADEM_OK);
  assert_true(take_file("plots", "energy.png"));
  assert_true(take_file("plots", "loads.png"));
  adem_case_free(c);

  if (adem_checkpoint_read(ckpt, &c, &err)) fail_msg("%s", err.message);
  assert_int_equal(adem_run(c, &opt, &err), ADEM_OK); /* at its end already */
  assert_true(take_file("plots", "energy.png"));
  assert_true(take_file("plots", "loads.png"));
  adem_case_free(c);
}

static void assert_same(const adem_world *a, const adem_world *b, const char *after) {
  const char *what = "";
  if (!settle_same_state(a, b, &what)) fail_msg("%s differs after %s", what, after);
}

/* The settle case with counting regions and two stages, the second (friction 0.2) starting at
 * step 872: the last step of a run that ends at 0.0061 s. */
static const char *const extend_sets[] = {
    "output.regions=[{name: low, shape: box, min: [0, 0, 0], max: [0.015, 0.015, 0.005]}]",
    "stages=[{name: fall, duration: 0.006104}, {name: rough, set: {materials.glass.friction: 0.2}}]",
};

/* Claim: a run that ended (at 0.0061 s, between two frames and two CSV rows, on the step where
 * its second stage begins) and is resumed with a later end goes on bit for bit as the run that
 * had that end from the start: the same state, and the same CSV, PVD and frames (the frame and
 * row written only because the short run ended are replaced, the earlier ones kept); also when
 * the extension is itself stopped after every chunk and resumed. */
static void test_extend_on_resume(void **state) {
  (void)state;
  adem_error err;
  adem_run_options opt = adem_default_run_options();
  adem_case *a = load_settle("ext_a", extend_sets, 2);
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  assert_int_equal(a->world->step, SETTLE_STEPS);

  const char *sets[3] = {extend_sets[0], extend_sets[1], "time.end=0.0061"};
  for (int stopped = 0; stopped < 2; ++stopped) {
    const char *dir = stopped ? "ext_c" : "ext_b";
    adem_case *b = load_settle(dir, sets, 3);
    if (adem_run(b, &opt, &err)) fail_msg("%s", err.message);
    assert_int_equal(b->world->step, 872);
    assert_int_equal(adem_stages_current(b), 1); /* the stage began at the last step */
    assert_true(b->csv_last_extra);
    char ckpt[600];
    snprintf(ckpt, sizeof ckpt, "%s/%s/checkpoint", tmpdir, dir);
    adem_case_free(b);
    const char *later[] = {"time.end=0.014"};
    if (adem_checkpoint_read_with(ckpt, later, 1, &b, &err)) fail_msg("%s", err.message);
    assert_true(b->end_time == 0.014);
    if (stopped) {
      int stops = 0;
      b = run_stopped_everywhere(b, opt, &stops);
      printf("# the extension stopped and resumed %d times\n", stops);
      assert_true(stops >= 5);
    } else if (adem_run(b, &opt, &err)) {
      fail_msg("%s", err.message);
    }
    assert_same(a->world, b->world, stopped ? "an extension stopped everywhere" : "an extension");
    const char *files[] = {"timeseries.csv", "particles.pvd", "frames/particles_000001.vtu",
                           "frames/particles_000002.vtu", "frames/particles_000004.vtu", NULL};
    assert_same_files("ext_a", dir, files, "an extension");
    adem_case_free(b);
  }
  adem_case_free(a);
}

/* Claim: on resume only the end and the output intervals may change: another key is refused
 * naming the keys that may, and so is an end before the checkpoint's time. */
static void test_resume_sets_refused(void **state) {
  (void)state;
  adem_error err;
  const char *sets[] = {"time.end=0.001"};
  adem_case *c = load_settle("refuse", sets, 1);
  adem_run_options opt = adem_default_run_options();
  if (adem_run(c, &opt, &err)) fail_msg("%s", err.message);
  adem_case_free(c);
  char ckpt[600];
  snprintf(ckpt, sizeof ckpt, "%s/refuse/checkpoint", tmpdir);
  const char *other[] = {"materials.glass.friction=0.1"};
  assert_int_equal(adem_checkpoint_read_with(ckpt, other, 1, &c, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "materials.glass.friction"));
  assert_non_null(strstr(err.message, "only time.end"));
  assert_non_null(strstr(err.message, "output.csv_interval"));
  const char *early[] = {"time.end=0.0005"};
  assert_int_equal(adem_checkpoint_read_with(ckpt, early, 1, &c, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "later end"));
  const char *bad[] = {"time.end=-1"};
  assert_int_equal(adem_checkpoint_read_with(ckpt, bad, 1, &c, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "time.end"));
  /* a new interval is taken from the resume on */
  const char *interval[] = {"time.end=0.002", "output.csv_interval=0.0007"};
  if (adem_checkpoint_read_with(ckpt, interval, 2, &c, &err)) fail_msg("%s", err.message);
  assert_true(c->output.csv_interval == 0.0007 && c->end_time == 0.002);
  adem_case_free(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plots_on_every_stop),
      cmocka_unit_test(test_extend_on_resume),
      cmocka_unit_test(test_resume_sets_refused),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
