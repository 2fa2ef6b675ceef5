/* Claims, on a bed in a box periodic in x and y (periodic_case.h):
 *  - the state is bit for bit the same for 1, 2 and 3 threads;
 *  - a run checkpointed halfway and resumed ends bit for bit like the uninterrupted one (image
 *    counters included);
 *  - with a frictionless floor nothing acts along x and y but pair forces, equal and opposite:
 *    the total momentum along the periodic axes keeps its initial value to round-off. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "bitwise/periodic_case.h"
#include "restart_run.h"
#include "world_internal.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_periodic");
}

static adem_case *load_periodic(int nthreads) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_string(periodic_case, "periodic.yaml", NULL, 0, &c, &err))
    fail_msg("case does not load: %s", err.message);
  adem_world_set_threads(c->world, nthreads);
  c->world->parallel_min = 0; /* 300 particles would otherwise stay on one thread */
  if (adem_world_prepare(c->world, &err)) fail_msg("%s", err.message);
  return c;
}

/* Bit-for-bit equality of what carries the motion forward, image counters included. */
static int same_state(const adem_world *a, const adem_world *b, const char **what) {
  const adem_particles *p = &a->p, *q = &b->p;
  size_t n = p->n;
#define SAME(cond, name) \
  if (!(cond)) {         \
    *what = name;        \
    return 0;            \
  }
  SAME(n == q->n && a->step == b->step, "particle or step count");
  SAME(memcmp(p->id, q->id, n * sizeof *p->id) == 0, "particle order (ids)");
  SAME(memcmp(p->pos, q->pos, n * sizeof *p->pos) == 0, "positions");
  SAME(memcmp(p->image, q->image, n * sizeof *p->image) == 0, "image counters");
  SAME(memcmp(p->vel, q->vel, n * sizeof *p->vel) == 0, "velocities");
  SAME(memcmp(p->omega, q->omega, n * sizeof *p->omega) == 0, "angular velocities");
  SAME(memcmp(p->force, q->force, n * sizeof *p->force) == 0, "forces");
  SAME(a->pp.n == b->pp.n && a->pw.n == b->pw.n, "pair counts");
  SAME(memcmp(a->pp.a, b->pp.a, a->pp.n * sizeof *a->pp.a) == 0 &&
           memcmp(a->pp.b, b->pp.b, a->pp.n * sizeof *a->pp.b) == 0,
       "particle pairs");
  bool same_hist = true; /* by pair: a slot's number is the threads' order of taking it */
  for (size_t k = 0; k < a->pp.n && same_hist; ++k)
    same_hist = memcmp(&a->pp.hist[adem_pairs_slot(&a->pp, k)], &b->pp.hist[adem_pairs_slot(&b->pp, k)],
                       sizeof *a->pp.hist) == 0;
  SAME(same_hist, "contact history");
#undef SAME
  return 1;
}

/* Pairs touching through a periodic face (centres more than half a box apart along x or y),
 * with a loaded tangential spring: without them the test says nothing about periodicity. */
static size_t loaded_across(const adem_world *w) {
  size_t count = 0;
  for (size_t k = 0; k < w->pp.n; ++k) {
    if (!w->pp.touching[k] || w->pp.hist[adem_pairs_slot(&w->pp, k)].tangential.x == 0.0) continue;
    adem_vec3 d = v3_sub(w->p.pos[w->pp.b[k]], w->p.pos[w->pp.a[k]]);
    if (fabs(d.x) > 0.0075 || fabs(d.y) > 0.0075) ++count;
  }
  return count;
}

static void momentum(const adem_world *w, double *px, double *py, double *scale) {
  *px = *py = *scale = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) {
    double m = 1.0 / w->p.inv_mass[i];
    *px += m * w->p.vel[i].x;
    *py += m * w->p.vel[i].y;
    *scale += m * v3_norm(w->p.vel[i]);
  }
}

static void test_threads_and_momentum(void **state) {
  (void)state;
  adem_error err;
  adem_case *c[3];
  for (int t = 0; t < 3; ++t) c[t] = load_periodic(t + 1);
  double px0, py0, s0, px, py, s, worst = 0.0, across = 0.0;
  momentum(c[0]->world, &px0, &py0, &s0);
  for (int chunk = 0; chunk < 20; ++chunk) {
    for (int t = 0; t < 3; ++t)
      if (adem_world_step(c[t]->world, PERIODIC_STEPS / 20, &err)) fail_msg("%s", err.message);
    momentum(c[0]->world, &px, &py, &s);
    worst = fmax(worst, fmax(fabs(px - px0), fabs(py - py0)) / s0);
    across = fmax(across, (double)loaded_across(c[0]->world));
  }
  const adem_world *w = c[0]->world;
  long crossings = 0;
  for (size_t i = 0; i < w->p.n; ++i)
    crossings += labs((long)w->p.image[i].n[0]) + labs((long)w->p.image[i].n[1]);
  printf("# momentum x %.6g -> %.6g, y %.6g -> %.6g kg m/s; largest change %.3g of sum m|v| "
         "(%.6g at the start); %ld face crossings, up to %.0f loaded contacts through a face, %zu "
         "floor contacts at the end\n",
         px0, px, py0, py, worst, s0, crossings, across, (size_t)adem_world_diagnostics(w).contacts_pw);
  assert_true(crossings > 100);
  assert_true(across >= 5);
  /* each step changes each velocity by F dt / m with round-off 1e-16 relative: 2000 steps of
   * 300 particles leave a random walk far below 1e-12 of sum m|v| (measured 4e-16); a floor
   * friction of 0.4 would take most of the sideways momentum (1.7e-3 kg m/s) in these 14 ms */
  assert_true(worst < 1e-12);
  const char *what = "";
  for (int t = 1; t < 3; ++t)
    if (!same_state(c[0]->world, c[t]->world, &what)) fail_msg("%d threads differ in %s", t + 1, what);
  for (int t = 0; t < 3; ++t) adem_case_free(c[t]);
}

static void test_restart_halfway(void **state) {
  (void)state;
  adem_error err;
  adem_case *a = load_periodic(2);
  if (adem_world_step(a->world, PERIODIC_STEPS, &err)) fail_msg("%s", err.message);
  adem_case *b = load_periodic(2);
  if (adem_world_step(b->world, PERIODIC_STEPS / 2, &err)) fail_msg("%s", err.message);
  uint64_t rebuilds_half = b->world->nb.rebuilds;
  char path[512];
  snprintf(path, sizeof path, "%s/halfway.ckpt", tmpdir);
  if (adem_checkpoint_write(b, path, &err)) fail_msg("%s", err.message);
  adem_case_free(b);
  adem_case *r = NULL;
  if (adem_checkpoint_read(path, &r, &err)) fail_msg("%s", err.message);
  adem_world_set_threads(r->world, 2);
  r->world->parallel_min = 0;
  if (adem_world_step(r->world, PERIODIC_STEPS / 2, &err)) fail_msg("%s", err.message);
  printf("# %llu rebuilds (%llu after the restart), %zu contacts loaded through a face\n",
         (unsigned long long)a->world->nb.rebuilds,
         (unsigned long long)(a->world->nb.rebuilds - rebuilds_half), loaded_across(a->world));
  assert_true(a->world->nb.rebuilds > rebuilds_half);
  const char *what = "";
  if (!same_state(a->world, r->world, &what)) fail_msg("restarted run differs in %s", what);
  adem_case_free(a);
  adem_case_free(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_threads_and_momentum),
      cmocka_unit_test(test_restart_halfway),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
