/* Claim: a run stopped, checkpointed and resumed continues bit for bit like the uninterrupted
 * run (positions, velocities, spins, forces, the pair lists and their tangential history), and
 * its output files (CSV, PVD, frames) are identical too. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "bitwise/settle_case.h"
#include "restart_run.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_restart");
}

static adem_case *load_settle_as(const char *subdir, bool balance) {
  const char *const sets[] = {"output.energy_balance=false"};
  adem_case *c = settle_load(sets, balance ? 0 : 1);
  snprintf(c->output.dir, sizeof c->output.dir, "%s/%s", tmpdir, subdir);
  return c;
}
static adem_case *load_settle(const char *subdir) { return load_settle_as(subdir, true); }

static void assert_same(const adem_world *a, const adem_world *b) {
  const char *what = "";
  if (!settle_same_state(a, b, &what)) fail_msg("restarted run differs in %s", what);
}

/* Stop halfway through world stepping, write a checkpoint, read it into a new case, go on; with
 * the energy balance on (the pairs carry their balance records) or off (they carry none). */
static void restart_halfway(bool balance) {
  adem_error err;
  adem_case *a = load_settle_as("a", balance);
  assert_int_equal(adem_world_prepare(a->world, &err), ADEM_OK);
  assert_int_equal(adem_world_step(a->world, SETTLE_STEPS, &err), ADEM_OK);

  adem_case *b = load_settle_as("b", balance);
  assert_int_equal(adem_world_prepare(b->world, &err), ADEM_OK);
  assert_int_equal(adem_world_step(b->world, SETTLE_STEPS / 2, &err), ADEM_OK);
  uint64_t rebuilds_half = b->world->nb.rebuilds;
  char path[512];
  snprintf(path, sizeof path, "%s/halfway.ckpt", tmpdir);
  if (adem_checkpoint_write(b, path, &err)) fail_msg("%s", err.message);
  adem_case_free(b);
  adem_case *r = NULL;
  if (adem_checkpoint_read(path, &r, &err)) fail_msg("%s", err.message);
  assert_int_equal(r->world->step, SETTLE_STEPS / 2);
  assert_int_equal(adem_world_step(r->world, SETTLE_STEPS / 2, &err), ADEM_OK);

  printf("# %zu particle pairs, %zu wall pairs, %zu loaded contacts, %llu rebuilds (%llu after "
         "the restart)\n",
         a->world->pp.n, a->world->pw.n, settle_loaded_contacts(a->world),
         (unsigned long long)a->world->nb.rebuilds,
         (unsigned long long)(a->world->nb.rebuilds - rebuilds_half));
  /* The comparison means something only with loaded contacts and rebuilds after the restart. */
  assert_true(settle_loaded_contacts(a->world) > 100);
  assert_true(a->world->nb.rebuilds > rebuilds_half);
  assert_true(adem_world_energy_balance(r->world) == balance);
  assert_true((r->world->pp.bal != NULL) == balance);
  assert_same(a->world, r->world);
  adem_case_free(a);
  adem_case_free(r);
}

static void test_restart_halfway(void **state) {
  (void)state;
  restart_halfway(true);
}

static void test_restart_halfway_without_balance(void **state) {
  (void)state;
  restart_halfway(false);
}

/* The same through adem_run: a run stopped after every chunk (stop flag always set) and resumed
 * from its checkpoint each time ends like the run that was never stopped, files included. */
static void test_run_interrupted_everywhere(void **state) {
  (void)state;
  adem_error err;
  adem_case *a = load_settle("run_a");
  adem_run_options opt = adem_default_run_options();
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  assert_int_equal(a->world->step, SETTLE_STEPS);

  adem_case *b = load_settle("run_b");
  int stops = 0;
  b = run_stopped_everywhere(b, opt, &stops);
  printf("# stopped and resumed %d times\n", stops);
  assert_true(stops >= 20);
  assert_same(a->world, b->world);
  const char *files[] = {"timeseries.csv", "particles.pvd", "frames/particles_000004.vtu", NULL};
  assert_same_files("run_a", "run_b", files, "the restart");
  adem_case_free(a);
  adem_case_free(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_restart_halfway),
      cmocka_unit_test(test_restart_halfway_without_balance),
      cmocka_unit_test(test_run_interrupted_everywhere),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
