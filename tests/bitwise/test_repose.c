/* The angle-of-repose case (cases/irazabal/repose.yaml) in its quick form (E / 100, the pour cut
 * short): the quick irazabal-fig11 reproduction runs and finds the angle rising with eta_r, and
 * the pile's run is bitwise the same for 1 and 2 threads and after a restart from a checkpoint.
 * Claims: I Fig. 11's trend (quick: the rise only); determinism of a case with a mesh hopper,
 * a pour and BROF. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <string.h>

#include "adem/adem.h"
#include "tmpdir.h"
#include "world_internal.h"

#define CASE ADEM_SOURCE_DIR "/cases/irazabal/repose.yaml"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_repose");
}

static void test_quick_fig11_rises(void **state) {
  (void)state;
  adem_validation_context ctx = {tmpdir, 2, true, NULL, NULL};
  const char *names[] = {"irazabal-fig11"};
  int failed = -1;
  adem_error err;
  if (adem_validation_run(names, 1, &ctx, &failed, &err)) fail_msg("%s", err.message);
  char path[512];
  snprintf(path, sizeof path, "%s/summary.md", tmpdir);
  char *text = NULL;
  size_t n = 0;
  assert_int_equal(adem_file_read_all(path, &text, &n, &err), ADEM_OK);
  const char *m = strstr(text, "Primary (laboratory) measure");
  printf("# %.200s\n", m ? m : "(no figures)");
  assert_int_equal(failed, 0);
  free(text);
}

/* A quick pile to t_end (particles' state read back), with 1 or 2 threads; when restart_at > 0,
 * run to restart_at, read the checkpoint back, extend the end time and go on. */
static double *pile_state(int threads, double t_end, double restart_at, const char *dir,
                          size_t *count) {
  char out[512], end[64];
  snprintf(out, sizeof out, "output.dir=%s/%s", tmpdir, dir);
  snprintf(end, sizeof end, "time.end=%g", restart_at > 0 ? restart_at : t_end);
  const char *sets[] = {"materials.ballast.stiffness_factor=0.01", "time.step=auto",
                        "pours.feed.end=4", "output.frame_interval=0", "output.csv_interval=0",
                        "output.plot=false", "output.plot_loads=false", end, out};
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_file(CASE, sets, 9, &c, &err)) fail_msg("%s", err.message);
  adem_run_options o = adem_default_run_options();
  o.nthreads = threads;
  c->world->parallel_min = 0; /* a small system would otherwise stay on one thread */
  if (adem_run(c, &o, &err)) fail_msg("%s", err.message);
  if (restart_at > 0) {
    char ck[600];
    snprintf(ck, sizeof ck, "%s/%s/checkpoint", tmpdir, dir);
    adem_case_free(c);
    if (adem_checkpoint_read(ck, &c, &err)) fail_msg("%s", err.message);
    c->end_time = t_end;
    c->world->parallel_min = 0;
    if (adem_run(c, &o, &err)) fail_msg("%s", err.message);
  }
  size_t n = adem_world_particle_count(c->world);
  double *s = calloc(9 * n + 1, sizeof *s);
  *count = n;
  adem_world_get_particles(c->world, ADEM_FIELD_POSITION, s, 3 * n, NULL);
  adem_world_get_particles(c->world, ADEM_FIELD_VELOCITY, s + 3 * n, 3 * n, NULL);
  adem_world_get_particles(c->world, ADEM_FIELD_ANGULAR_VELOCITY, s + 6 * n, 3 * n, NULL);
  printf("# %d thread%s%s: %zu particles at t = %g s\n", threads, threads > 1 ? "s" : "",
         restart_at > 0 ? ", restarted" : "", n, adem_world_time(c->world));
  adem_case_free(c);
  return s;
}

static void test_threads_and_restart(void **state) {
  (void)state;
  size_t np = 0, n2 = 0, n3 = 0;
  double *one = pile_state(1, 2.0, 0.0, "one", &np);
  double *two = pile_state(2, 2.0, 0.0, "two", &n2);
  double *re = pile_state(2, 2.0, 1.0, "restart", &n3);
  /* 4 s of pour at 100/s, 0.05 s batches: by t = 2 s about 200 spheres */
  assert_true(np > 100);
  assert_int_equal(np, n2);
  assert_int_equal(np, n3);
  assert_memory_equal(one, two, 9 * np * sizeof *one);
  assert_memory_equal(one, re, 9 * np * sizeof *one);
  free(one);
  free(two);
  free(re);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_quick_fig11_rises),
      cmocka_unit_test(test_threads_and_restart),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
