/* Pours: particles inserted into a region at a rate during a window, while the run goes on. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "adem/adem.h"
#include "case_file.h"
#include "insert.h"
#include "log_capture.h"
#include "staged_run.h"
#include "world_internal.h"

/* Spheres poured from a cylinder into a bin: 4000/s from 5 ms to 35 ms, a batch every 3 ms
 * (tests/cases/pour-bin.yaml). */
static adem_case *load(const char *const *sets, int nsets) {
  return case_file_load("pour-bin", sets, nsets);
}

/* Particles [first, n) overlap nothing, and every particle clears the bin's planes. */
static void assert_clear(const adem_world *w, size_t first_id) {
  const adem_particles *p = &w->p;
  for (size_t i = 0; i < p->n; ++i) {
    if (p->id[i] < first_id) continue;
    for (size_t j = 0; j < p->n; ++j) {
      if (j == i) continue;
      double s = p->radius[i] + p->radius[j], d = v3_norm(v3_sub(p->pos[i], p->pos[j]));
      if (d < s) fail_msg("new particle id %llu overlaps id %llu by %g m",
                          (unsigned long long)p->id[i], (unsigned long long)p->id[j], s - d);
    }
    for (int k = 0; k < w->walls.nplanes; ++k) {
      const adem_plane_def *pl = &w->walls.planes[k].def;
      double d = v3_dot(v3_sub(p->pos[i], pl->point), pl->normal);
      if (d < p->radius[i] * (1 - 1e-9)) fail_msg("new particle overlaps wall %s", pl->name);
    }
  }
}

/* Claim: the pour inserts round(rate x window) = 4000 x 0.03 = 120 particles exactly, batch by
 * batch as scheduled (batch j brings the total to round(120 min(1, (j+1) k / span)), k and span
 * in steps), each batch overlapping neither the particles already there nor the walls. */
static void test_pour_count(void **state) {
  (void)state;
  adem_error err;
  adem_case *c = load(NULL, 0);
  adem_world *w = c->world;
  assert_int_equal(w->p.n, 0);
  assert_int_equal(staged_start(c, &err), ADEM_OK);
  const adem_pour *p = &c->pours->p[0];
  uint64_t s_a = (uint64_t)llround(0.005 / w->dt), s_b = (uint64_t)llround(0.035 / w->dt);
  uint64_t k = (uint64_t)llround(0.003 / w->dt), span = s_b - s_a;
  uint64_t total = adem_schedule_total_steps(c->end_time, w->dt);
  int batches = 0;
  while (w->step < total) {
    uint64_t next = adem_stages_next_step(c, w->step);
    if (next > total) next = total;
    uint64_t before = w->next_id;
    if (adem_world_step(w, next - w->step, &err)) fail_msg("%s", err.message);
    assert_int_equal(adem_stages_events(c, &err), ADEM_OK);
    if (w->next_id == before) continue;
    assert_clear(w, before);
    uint64_t j = (w->step - s_a) / k;
    double frac = fmin(1.0, (double)((j + 1) * k) / (double)span);
    assert_int_equal(w->p.n, llround(120.0 * frac));
    ++batches;
  }
  printf("# %d batches, %zu particles, dt %g s\n", batches, w->p.n, w->dt);
  assert_int_equal(batches, 10);
  assert_int_equal(w->p.n, 120);
  assert_int_equal(p->inserted, 120);
  adem_case_free(c);
}

/* Claim: with a mass rate, the pour's mass is mass_rate x window = 0.08 x 0.03 = 2.4 g within
 * half the largest particle's mass (radii are drawn while the mass plus half the next stays
 * within the target). */
static void test_pour_mass_rate(void **state) {
  (void)state;
  adem_error err;
  /* the pour as written, its rate a mass rate */
  const char *sets[] = {"pours=[{name: feed, material: glass, radius: {distribution: uniform, min: 0.001,"
                        " max: 0.0015}, region: {shape: cylinder, start: [0.02, 0.02, 0.03],"
                        " end: [0.02, 0.02, 0.05], radius: 0.015}, mass_rate: 0.08, start: 0.005,"
                        " end: 0.035, interval: 0.003, velocity: [0, 0, -0.5]}]"};
  adem_case *c = load(sets, 1);
  assert_int_equal(staged_start(c, &err), ADEM_OK);
  assert_int_equal(staged_advance(c, adem_schedule_total_steps(c->end_time, c->world->dt), 1000,
                                  &err),
                   ADEM_OK);
  double mass = 0.0;
  for (size_t i = 0; i < c->world->p.n; ++i) mass += 1.0 / c->world->p.inv_mass[i];
  double m_max = 2500 * 4.0 / 3.0 * ADEM_PI * pow(0.0015, 3);
  printf("# %zu particles, %.6g kg for 0.0024 kg (tolerance %.3g kg)\n", c->world->p.n, mass,
         0.5 * m_max);
  assert_float_equal(mass, 0.0024, 0.5 * m_max);
  assert_float_equal(c->pours->p[0].mass, mass, 1e-12);
  adem_case_free(c);
}

/* Claim: a pour whose region cannot take its particles inserts what fits and says how many. */
static void test_pour_falls_short(void **state) {
  (void)state;
  adem_error err;
  logged[0] = '\0';
  adem_log_set_hook(capture, NULL);
  const char *sets[] = {"pours.feed.region={shape: box, min: [0.01, 0.01, 0.03], max: [0.016, 0.016, 0.036]}",
                        "pours.feed.max_attempts=200"};
  adem_case *c = load(sets, 2);
  assert_int_equal(staged_start(c, &err), ADEM_OK);
  assert_int_equal(staged_advance(c, adem_schedule_total_steps(c->end_time, c->world->dt), 1000,
                                  &err),
                   ADEM_OK);
  adem_log_set_hook(NULL, NULL);
  char expect[128];
  snprintf(expect, sizeof expect, "inserted %zu of 120 particles", c->world->p.n);
  printf("# %s", logged);
  assert_true(c->world->p.n < 120);
  if (!strstr(logged, expect)) fail_msg("'%s' not in: %s", expect, logged);
  adem_case_free(c);
}

static void expect_error(const char *const *sets, int nsets, const char *w1, const char *w2) {
  adem_case *c = NULL;
  adem_error err;
  if (!adem_case_load_file(case_file_path("pour-bin"), sets, nsets, &c, &err)) {
    adem_case_free(c);
    fail_msg("expected an error with '%s'", w1);
  }
  printf("# %s\n", err.message);
  if (!strstr(err.message, w1) || (w2 && !strstr(err.message, w2)))
    fail_msg("'%s' / '%s' not in: %s", w1, w2 ? w2 : "", err.message);
}

/* Claim: bad pours are refused naming the key: a negative rate, a window that ends before it
 * starts, both rates, no rate, a rigid material. */
static void test_pour_bad_input(void **state) {
  (void)state;
  const char *neg[] = {"pours.feed.rate=-10"};
  expect_error(neg, 1, "pours[0].rate", "out of range");
  const char *window[] = {"pours.feed.start=0.03", "pours.feed.end=0.02"};
  expect_error(window, 2, "pours[0].end", "before it starts");
  const char *both[] = {"pours.feed.mass_rate=1"};
  expect_error(both, 1, "pours[0].mass_rate", "not both");
  const char *none[] = {"pours.feed.rate=~"};
  expect_error(none, 1, "pours[0].rate", "got no value");
  const char *rigid[] = {"pours.feed.material=steel"};
  expect_error(rigid, 1, "pours[0].material", "rigid");
  const char *interval[] = {"pours.feed.interval=0"};
  expect_error(interval, 1, "pours[0].interval", "> 0");
}

/* Claim: a poured case gets an automatic step from the poured radii although it starts empty
 * (the step of 1 mm spheres of this material), and its domain holds the pour region. */
static void test_pour_step(void **state) {
  (void)state;
  adem_case *c = load(NULL, 0);
  const char *sets[] = {"pours.feed.radius={distribution: constant, value: 0.001}"};
  adem_case *d = load(sets, 1);
  printf("# dt %g s (uniform 1-1.5 mm), %g s (constant 1 mm)\n", adem_world_dt(c->world), adem_world_dt(d->world));
  assert_true(adem_world_dt(c->world) > 0 && isfinite(adem_world_dt(c->world)));
  assert_float_equal(adem_world_dt(c->world), adem_world_dt(d->world), 1e-12 * adem_world_dt(d->world));
  assert_true(c->world->has_domain && c->world->domain_hi.z >= 0.1);
  adem_case_free(c);
  adem_case_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pour_count),
      cmocka_unit_test(test_pour_mass_rate),
      cmocka_unit_test(test_pour_falls_short),
      cmocka_unit_test(test_pour_bad_input),
      cmocka_unit_test(test_pour_step),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
