/* Claim: a run with analytic curved walls (a drum periodic along its axis, turning, whose
 * spheres press on it and on a holed plate inside it) restarted from a checkpoint after every
 * chunk continues bit for bit like the uninterrupted run (particles, wall contacts and their
 * history, the CSV with the drum's force and torque columns), and 1 thread gives the bits of 2:
 * the drum's placement is a function of time and its shape is in the checkpoint. */
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
#include "restart_run.h"

#define DRUM_STEPS 3000

static char case_path[512];

#define drum_case case_file_text("bitwise-drum") /* tests/cases/bitwise-drum.yaml */

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_drumrestart")) return -1;
  snprintf(case_path, sizeof case_path, "%s/drum.yaml", tmpdir);
  FILE *f = fopen(case_path, "w");
  if (!f) return -1;
  fputs(drum_case, f);
  fclose(f);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  return tmpdir_remove();
}

static adem_case *load_drum_case(const char *subdir) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_file(case_path, NULL, 0, &c, &err)) fail_msg("case does not load: %s", err.message);
  snprintf(c->output.dir, sizeof c->output.dir, "%s/%s", tmpdir, subdir);
  return c;
}

/* Touching contacts on the drum and on the plate, and the drum's loaded tangential springs. */
static void drum_activity(const adem_world *w, size_t *drum, size_t *plate, size_t *loaded) {
  *drum = *plate = *loaded = 0;
  for (size_t k = 0; k < w->pw.n; ++k) {
    if (!w->pw.touching[k]) continue;
    if (w->pw.b[k] == 0) ++*drum;
    else ++*plate;
    if (w->pw.b[k] == 0 && w->pw.hist[k].tangential.x != 0.0) ++*loaded;
  }
}

static void test_run_interrupted_everywhere(void **state) {
  (void)state;
  adem_error err;
  adem_case *a = load_drum_case("run_a");
  adem_run_options opt = adem_default_run_options();
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  adem_case *b = load_drum_case("run_b");
  int stops = 0;
  b = run_stopped_everywhere(b, opt, &stops);
  size_t drum, plate, loaded;
  drum_activity(a->world, &drum, &plate, &loaded);
  printf("# stopped and resumed %d times; at the end %zu contacts on the drum (%zu with a "
         "loaded spring), %zu on the plate\n",
         stops, drum, loaded, plate);
  assert_true(stops >= 20);
  assert_true(drum >= 20 && loaded >= 10 && plate >= 1);
  const char *what = "";
  if (!settle_same_state(a->world, b->world, &what)) fail_msg("the runs differ in %s", what);
  const char *files[] = {"timeseries.csv", "particles.pvd", "frames/particles_000004.vtu", NULL};
  assert_same_files("run_a", "run_b", files, "the restart");
  adem_case_free(a);
  adem_case_free(b);
}

static void test_threads(void **state) {
  (void)state;
  adem_error err;
  adem_case *c[2];
  for (int k = 0; k < 2; ++k) {
    c[k] = load_drum_case(k ? "t2" : "t1");
    adem_world_set_threads(c[k]->world, k + 1);
    c[k]->world->parallel_min = 0;
    assert_int_equal(adem_world_prepare(c[k]->world, &err), ADEM_OK);
    if (adem_world_step(c[k]->world, DRUM_STEPS, &err)) fail_msg("%s", err.message);
  }
  const char *what = "";
  if (!settle_same_state(c[0]->world, c[1]->world, &what)) fail_msg("the runs differ in %s", what);
  adem_case_free(c[0]);
  adem_case_free(c[1]);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_run_interrupted_everywhere),
      cmocka_unit_test(test_threads),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
