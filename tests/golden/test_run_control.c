/* How a run ends and goes on: the plots of a run however it stops. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <unistd.h>

#include "golden/settle_case.h"
#include "restart_run.h"

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

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plots_on_every_stop),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
