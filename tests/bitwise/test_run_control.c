/* How a run ends and goes on: the plots of a run however it stops, a later end on resume. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bitwise/settle_case.h"
#include "log_capture.h"
#include "restart_run.h"
#include "stages.h"
#include "until.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_runctl");
}

static adem_case *load_settle(const char *subdir, const char *const *sets, int nsets) {
  adem_case *c = settle_load(sets, nsets);
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

/* The settle case with BROF, so that the bed comes to rest exactly. */
#define BROF_SETS                                                                              \
  "materials.glass.rolling_friction=0.1",                                                      \
      "interactions=[{materials: [glass, glass], rolling: brof}, {materials: [glass, steel], " \
      "rolling: brof}]"

/* The run of A again in DIR: ended on the step halfway between `since` and `met` (the streak of
 * a condition; an end given by time.end, whose checkpoint holds the streak), resumed with A's
 * end and from there stopped after every chunk and resumed. */
static adem_case *resumed_mid_streak(const adem_case *a, const char *dir, const char *const *sets,
                                     int nsets, uint64_t since, uint64_t met,
                                     adem_run_options opt) {
  uint64_t mid = since + (met - since) / 2;
  char end[64], ckpt[600];
  snprintf(end, sizeof end, "time.end=%.17g", ((double)mid - 0.5) * a->world->dt);
  const char *more[8];
  for (int k = 0; k < nsets; ++k) more[k] = sets[k];
  more[nsets] = end;
  adem_case *b = load_settle(dir, more, nsets + 1);
  adem_error err;
  if (adem_run(b, &opt, &err)) fail_msg("%s", err.message);
  assert_true(b->world->step == mid);
  adem_case_free(b);
  snprintf(ckpt, sizeof ckpt, "%s/%s/checkpoint", tmpdir, dir);
  snprintf(end, sizeof end, "time.end=%.17g", a->end_time);
  const char *later[] = {end};
  if (adem_checkpoint_read_with(ckpt, later, 1, &b, &err)) fail_msg("%s", err.message);
  int stops = 0;
  b = run_stopped_everywhere(b, opt, &stops);
  printf("# stopped at step %llu (the streak began at %llu), then %d times more\n",
         (unsigned long long)mid, (unsigned long long)since, stops);
  assert_true(stops >= 5);
  return b;
}

/* Claim: time.until ends the run at the first check where the kinetic energy per particle has
 * stayed below the threshold for `for`: on the same step, in the same state and with the same
 * files for 2 threads and for 1 thread stopped inside the streak and resumed (the streak is in
 * the checkpoint), then stopped after every chunk; the CSV's last row is that step, below the threshold, and a resume of the ended
 * run does nothing. */
static void test_until_at_rest(void **state) {
  (void)state;
  adem_error err;
  const char *sets[] = {BROF_SETS, "time.end=1",
                        "time.until={kinetic_energy_per_particle: 1.0e-12, for: 0.01}"};
  adem_run_options opt = adem_default_run_options();
  adem_case *a = load_settle("until_a", sets, 4);
  opt.nthreads = 2;
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  uint64_t end = a->world->step, period = adem_until_period(a->until, a->world->dt);
  printf("# ended at step %llu (t = %.6g s) of %llu; checks every %llu steps\n",
         (unsigned long long)end, a->world->time,
         (unsigned long long)adem_case_total_steps(a), (unsigned long long)period);
  assert_true(end < adem_case_total_steps(a) / 4);
  assert_int_equal(end % period, 0);
  assert_true(a->until->met_step == end);
  assert_true(end - a->until->kinetic_since >= (uint64_t)llround(0.01 / a->world->dt));
  char csv[600];
  snprintf(csv, sizeof csv, "%s/until_a/timeseries.csv", tmpdir);
  FILE *f = fopen(csv, "r");
  assert_non_null(f);
  char line[1 << 12], last[1 << 12] = "";
  while (fgets(line, sizeof line, f)) memcpy(last, line, sizeof last);
  fclose(f);
  double t_last = strtod(last, NULL);
  assert_true(t_last == a->world->time);

  opt.nthreads = 1;
  adem_case *b = resumed_mid_streak(a, "until_b", sets, 4, a->until->kinetic_since, end, opt);
  assert_same(a->world, b->world, "a run stopped in the streak");
  const char *files[] = {"timeseries.csv", "particles.pvd", NULL};
  assert_same_files("until_a", "until_b", files, "the restarts");
  adem_case_free(b);

  char ckpt[600];
  snprintf(ckpt, sizeof ckpt, "%s/until_a/checkpoint", tmpdir);
  const char *later[] = {"time.end=2"};
  if (adem_checkpoint_read_with(ckpt, later, 1, &b, &err)) fail_msg("%s", err.message);
  char why[ADEM_MSG_MAX];
  assert_true(adem_stages_ended(b, why, sizeof why));
  printf("# %s\n", why);
  assert_int_equal(adem_run(b, &opt, &err), ADEM_OK);
  assert_true(b->world->step == end);
  adem_case_free(b);
  adem_case_free(a);
}

/* Claim: a stage's `until` ends it where its condition is met, the next stage begins at that
 * step (its duration was a maximum), and a run stopped inside the streak and then after every
 * chunk ends the same, files included; the wall-load condition ends a run once the floor's load is steady. */
static void test_until_stage(void **state) {
  (void)state;
  adem_error err;
  const char *sets[] = {BROF_SETS, "time.end=0.16",
                        "stages=[{name: settle, duration: 0.5, until: "
                        "{kinetic_energy_per_particle: 1.0e-12, for: 0.01}}, "
                        "{name: heavy, set: {gravity: [0, 0, -30]}}]"};
  adem_run_options opt = adem_default_run_options();
  adem_case *a = load_settle("stage_a", sets, 4);
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  uint64_t s1 = adem_stages_start_step(a, 1);
  printf("# stage 2 began at step %llu (t = %.6g s) instead of %.0f\n", (unsigned long long)s1,
         (double)s1 * a->world->dt, 0.5 / a->world->dt);
  assert_int_equal(adem_stages_current(a), 1);
  assert_true(s1 == a->stages->s[0].until->met_step);
  assert_true(s1 < (uint64_t)(0.16 / a->world->dt));
  assert_true(a->world->gravity.z == -30.0);

  adem_case *b = resumed_mid_streak(a, "stage_b", sets, 4, a->stages->s[0].until->kinetic_since,
                                    s1, opt);
  assert_same(a->world, b->world, "a staged run stopped in the streak");
  assert_true(adem_stages_start_step(b, 1) == s1);
  const char *files[] = {"timeseries.csv", "particles.pvd", NULL};
  assert_same_files("stage_a", "stage_b", files, "the restarts");
  adem_case_free(b);
  adem_case_free(a);

  const char *load[] = {BROF_SETS, "time.end=1",
                        "time.until={wall_load: {wall: box.zmin, tolerance: 0.001}, for: 0.02}"};
  adem_case *c = load_settle("load", load, 4);
  if (adem_run(c, &opt, &err)) fail_msg("%s", err.message);
  printf("# the floor's load steady at %.6g N (range %.6g..%.6g) from step %llu, ended at %llu\n",
         c->until->load_now, c->until->load_lo, c->until->load_hi,
         (unsigned long long)c->until->load_since, (unsigned long long)c->world->step);
  assert_true(c->world->step < adem_case_total_steps(c) / 4);
  assert_true(c->until->load_hi - c->until->load_lo <= 0.001 * c->until->load_hi);
  assert_true(c->until->load_now > 0.0);
  adem_case_free(c);
}

/* Claim: time.until's relative form ends the run at rest where the total kinetic energy,
 * recomputed here from the particles (sum 1/2 m v^2 + 1/2 I w^2 over sum m |g| 2r), is below the
 * ratio: the library's ratio equals it to round-off (a diameter taken as the radius gives twice
 * it, a ratio without the spins less), and the progress status names it against the threshold. */
static void test_until_ratio(void **state) {
  (void)state;
  adem_error err;
  const char *sets[] = {BROF_SETS, "time.end=1",
                        "time.until={kinetic_energy_ratio: 1.0e-9, for: 0.01}"};
  adem_run_options opt = adem_default_run_options();
  adem_case *a = load_settle("until_ratio", sets, 4);
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  const adem_world *w = a->world;
  double e = 0.0, lift = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) {
    e += 0.5 * v3_norm2(w->p.vel[i]) / w->p.inv_mass[i] +
         0.5 * v3_norm2(w->p.omega[i]) / w->p.inv_inertia[i];
    lift += v3_norm(w->gravity) * 2.0 * w->p.radius[i] / w->p.inv_mass[i];
  }
  printf("# ended at step %llu of %llu: ratio %.6g (recomputed %.6g) < 1e-9\n",
         (unsigned long long)w->step, (unsigned long long)adem_case_total_steps(a),
         a->until->ratio_now, e / lift);
  assert_true(w->step < adem_case_total_steps(a) / 4);
  assert_true(a->until->met_step == w->step);
  assert_true(fabs(a->until->ratio_now - e / lift) <= 1e-12 * (e / lift));
  assert_true(a->until->ratio_now < 1.0e-9);
  char status[200];
  adem_stages_until_status(a, status, sizeof status);
  printf("# %s\n", status);
  assert_non_null(strstr(status, "E_k/mgd"));
  assert_non_null(strstr(status, "< 1e-09"));
  assert_non_null(strstr(status, "held"));
  adem_case_free(a);
}

/* Claim: the messages of a staged run agree with each other and are not repeated: the step
 * warning comes once for two stages with the same stricter proposal (gravity 30 m/s^2 twice),
 * none for a stage that changes only friction; a stage that starts on the run's last step (572:
 * t = 0.004004 s for time.end 0.004 s and dt 7e-6 s) is announced as
 * not running and then set up at the end time, never as beginning; frames whose interval is not
 * a whole number of steps say where they land. */
static void test_stage_messages(void **state) {
  (void)state;
  adem_error err;
  const char *sets[] = {"time.end=0.004", "output.frame_interval=0.0011",
                        "stages=[{name: a, duration: 0.001, set: {materials.glass.friction: 0.2}}, "
                        "{name: heavy, duration: 0.001, set: {gravity: [0, 0, -30]}}, "
                        "{name: heavier, duration: 0.002004, set: {materials.glass.friction: 0.3}}, "
                        "{name: late, set: {materials.glass.friction: 0.4}}]"};
  capture_setup(NULL);
  adem_case *c = load_settle("messages", sets, 3);
  adem_run_options opt = adem_default_run_options();
  if (adem_run(c, &opt, &err)) fail_msg("%s", err.message);
  capture_teardown(NULL);
  printf("%s", logged);
  const char *w = strstr(logged, "the step its materials propose");
  assert_non_null(w);
  assert_non_null(strstr(logged, "stage `heavy`: the time step"));
  assert_null(strstr(w + 1, "the step its materials propose")); /* once */
  assert_non_null(strstr(logged, "stage `late` begins at t = 0.004004 s, at or after time.end"));
  assert_non_null(strstr(logged, "stage `late` is set up at the end time"));
  assert_null(strstr(logged, "stage `late` begins\n"));
  assert_non_null(strstr(logged, "stage `heavier` begins"));
  assert_non_null(strstr(logged, "frames every 157 steps = 0.001099 s"));
  adem_case_free(c);
}

/* Claim: bad conditions are refused naming the key: none given, an unknown wall (with the
 * nearest name), a zero direction. */
static void test_until_errors(void **state) {
  (void)state;
  const struct {
    const char *set, *word, *also;
  } bad[] = {
      {"time.until={for: 1}", "give a condition", NULL},
      {"time.until={wall_load: {wall: box.zmn}}", "did you mean `box.zmin`", NULL},
      {"time.until={wall_load: {wall: box.zmin, direction: [0, 0, 0]}}", "non-zero", NULL},
      {"time.until={kinetic_energy_per_particle: 0}", "out of range", NULL},
      {"time.until={kinetic_energy: 1}", "did you mean `kinetic_energy_", NULL},
      {"time.until={kinetic_energy_ratio: -1}", "out of range", NULL},
      {"time.until={kinetic_energy_ratio: 1e-4}", "gravity is zero", "gravity=[0, 0, 0]"},
  };
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
    adem_case *c = NULL;
    adem_error err;
    const char *sets[] = {bad[k].also ? bad[k].also : bad[k].set, bad[k].set};
    assert_int_equal(adem_case_load_file(case_file_path("settle"), sets, 2, &c, &err),
                     ADEM_ERR_INPUT);
    printf("# %s\n", err.message);
    assert_non_null(strstr(err.message, "time.until"));
    assert_non_null(strstr(err.message, bad[k].word));
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plots_on_every_stop),
      cmocka_unit_test(test_extend_on_resume),
      cmocka_unit_test(test_resume_sets_refused),
      cmocka_unit_test(test_until_at_rest),
      cmocka_unit_test(test_until_stage),
      cmocka_unit_test(test_until_ratio),
      cmocka_unit_test(test_stage_messages),
      cmocka_unit_test(test_until_errors),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
