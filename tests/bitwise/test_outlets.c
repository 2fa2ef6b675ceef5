/* Outlets and mass flows (issue 29 items 1 and 2): a small silo of 300 spheres empties through a
 * square orifice (cases/silo/plate-24mm.stl) into an outlet region under it and out of the
 * domain's bottom face. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "bitwise/settle_case.h"
#include "case_file.h"
#include "outlets.h"
#include "restart_run.h"
#include "world_internal.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_outlets");
}

#define SILO_N 300

/* The silo: tests/cases/outlets-silo.yaml. */

static adem_case *load_silo(const char *subdir, const char *const *sets, int nsets) {
  adem_case *c = case_file_load("outlets-silo", sets, nsets);
  snprintf(c->output.dir, sizeof c->output.dir, "%s/%s", tmpdir, subdir);
  return c;
}

/* The CSV of tmpdir/DIR: rows x columns of numbers, the header's names. */
typedef struct table {
  char names[64][64];
  int ncol;
  double v[400][64];
  int nrow;
} table;

static void read_table(const char *dir, table *t) {
  char path[600], line[8192];
  snprintf(path, sizeof path, "%s/%s/timeseries.csv", tmpdir, dir);
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  memset(t, 0, sizeof *t);
  assert_non_null(fgets(line, sizeof line, f));
  for (char *s = strtok(line, ",\n"); s && t->ncol < 64; s = strtok(NULL, ",\n"))
    snprintf(t->names[t->ncol++], sizeof t->names[0], "%s", s);
  while (t->nrow < 400 && fgets(line, sizeof line, f)) {
    int k = 0;
    for (char *s = strtok(line, ",\n"); s && k < t->ncol; s = strtok(NULL, ",\n"))
      t->v[t->nrow][k++] = strtod(s, NULL);
    t->nrow++;
  }
  fclose(f);
}

static int column(const table *t, const char *name) {
  for (int k = 0; k < t->ncol; ++k)
    if (!strcmp(t->names[k], name)) return k;
  fail_msg("no column %s", name);
  return -1;
}

static double total_mass(const adem_world *w) {
  double m = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) m += 1.0 / w->p.inv_mass[i];
  return m;
}

/* Claim: the mass through the orifice's plane is the silo's loss of mass at every CSV row to
 * round-off (|through + M_silo - M_0| <= 1e-13 M_0: the same masses added in another order),
 * its rate is the silo region's rate with the sign changed (to 1e-9 of the largest), and every
 * particle is in the silo, in flight or removed: the outlets' counts and masses plus what is
 * left are the 300 spheres and their mass (1e-13). Both outlets remove: the region (z -0.025 .. -0.003 m) is
 * checked every 0.005 s, and the domain's bottom face (z = -0.006 m, every 0.0024 s) takes
 * those that fell past it in between. The CSV rows are 0.02 s apart, so that many spheres cross
 * the plane and are removed between two rows: their crossing must be counted before they go. */
static void test_flow_is_mass_change(void **state) {
  (void)state;
  adem_case *c = load_silo("flow", NULL, 0);
  double m0 = total_mass(c->world);
  adem_run_options opt = adem_default_run_options();
  adem_error err;
  if (adem_run(c, &opt, &err)) fail_msg("%s", err.message);
  table *t = malloc(sizeof *t);
  assert_non_null(t);
  read_table("flow", t);
  int through = column(t, "orifice_through_kg"), silo = column(t, "silo_mass_kg");
  int rate = column(t, "orifice_flow_kg_s"), brate = column(t, "bin_flow_kg_s");
  double worst = 0.0, worst_rate = 0.0, top_rate = 0.0;
  for (int r = 0; r < t->nrow; ++r) {
    worst = fmax(worst, fabs(t->v[r][through] + t->v[r][silo] - m0));
    if (r == 0) continue;
    top_rate = fmax(top_rate, fabs(t->v[r][rate]));
    worst_rate = fmax(worst_rate, fabs(t->v[r][rate] + t->v[r][brate]));
  }
  double through_end = t->v[t->nrow - 1][through];
  printf("# M_0 = %.17g kg; through the orifice %.6g kg by the end; |through + M_silo - M_0| "
         "at most %.3g kg (%.3g of M_0); rates up to %.4g kg/s, |plane + region| at most %.3g\n",
         m0, through_end, worst, worst / m0, top_rate, worst_rate);
  assert_true(through_end > 0.2 * m0); /* a real discharge */
  assert_true(worst <= 1e-13 * m0);
  assert_true(top_rate > 0.0 && worst_rate <= 1e-9 * top_rate);

  /* the outlets' tally against what is left, from the world itself */
  int last = t->nrow - 1;
  double removed_n = t->v[last][column(t, "catch_deleted_count")] +
                     t->v[last][column(t, "bottom_deleted_count")];
  printf("# removed by the last row: %.0f (region), %.0f (face); left at the end %zu\n",
         t->v[last][column(t, "catch_deleted_count")], t->v[last][column(t, "bottom_deleted_count")],
         c->world->p.n);
  assert_true(removed_n > 30);
  assert_true(t->v[last][column(t, "catch_deleted_count")] > 0);
  assert_true(t->v[last][column(t, "bottom_deleted_count")] > 0);
  free(t);
  /* the outlets' own counters after the last check (the last row precedes it) */
  char ckpt[600];
  snprintf(ckpt, sizeof ckpt, "%s/flow/checkpoint", tmpdir);
  adem_case_free(c);
  if (adem_checkpoint_read(ckpt, &c, &err)) fail_msg("%s", err.message);
  double vals[16];
  /* a CSV row now: the counters as saved, without a step */
  if (adem_outlets_sample(c, vals, &err)) fail_msg("%s", err.message);
  double n_left = (double)c->world->p.n, m_left = total_mass(c->world);
  printf("# at the end: %.0f + %.0f removed (%.9g + %.9g kg), %.0f left (%.9g kg)\n", vals[0],
         vals[2], vals[1], vals[3], n_left, m_left);
  assert_true(vals[0] + vals[2] + n_left == SILO_N);
  assert_true(fabs(vals[1] + vals[3] + m_left - m0) <= 1e-13 * m0);
  adem_case_free(c);
}

/* Claim: removal is deterministic: two threads give the one-thread run's state and CSV bit for
 * bit, and so does the run stopped after every chunk and resumed from its checkpoint each time
 * (the outlets' counts, the flows' sides and windows are in the checkpoint). */
static void test_threads_and_restart(void **state) {
  (void)state;
  adem_error err;
  const char *sets[] = {"time.end=0.12", "output.mass_flow.orifice.window=0.03"};
  adem_case *a = load_silo("one", sets, 2);
  adem_run_options opt = adem_default_run_options();
  opt.nthreads = 1;
  if (adem_run(a, &opt, &err)) fail_msg("%s", err.message);
  assert_true(a->world->p.n < SILO_N);
  printf("# %zu of %d spheres left at t = %g s\n", a->world->p.n, SILO_N, a->world->time);

  adem_case *b = load_silo("two", sets, 2);
  opt.nthreads = 2;
  adem_world_set_threads(b->world, 2);
  b->world->parallel_min = 1; /* two threads even for a few hundred particles */
  if (adem_run(b, &opt, &err)) fail_msg("%s", err.message);
  const char *what = "";
  if (!settle_same_state(a->world, b->world, &what)) fail_msg("%s differs with 2 threads", what);
  const char *files[] = {"timeseries.csv", NULL};
  assert_same_files("one", "two", files, "two threads");
  adem_case_free(b);

  adem_case *s = load_silo("stopped", sets, 2);
  opt.nthreads = 1;
  int stops = 0;
  s = run_stopped_everywhere(s, opt, &stops);
  printf("# stopped and resumed %d times\n", stops);
  assert_true(stops > 20);
  if (!settle_same_state(a->world, s->world, &what)) fail_msg("%s differs after restarts", what);
  assert_same_files("one", "stopped", files, "restarts");
  adem_case_free(s);
  adem_case_free(a);
}

/* Claim: adem_world_remove_particles drops the particles and every pair they are in, and the
 * others keep their contacts as they were: after the settle case's bed has formed, removing
 * every third particle leaves each touching contact between two survivors with the same force
 * and history bits, and no contact of a removed particle. */
static void test_remove_keeps_history(void **state) {
  (void)state;
  adem_case *c = settle_load(NULL, 0);
  adem_error err;
  adem_world *w = c->world;
  if (adem_world_step(w, 1500, &err)) fail_msg("%s", err.message);
  size_t cap = 8 * w->p.n + 64;
  adem_contact_info *before = malloc(cap * sizeof *before), *after = malloc(cap * sizeof *after);
  assert_non_null(before);
  assert_non_null(after);
  size_t nb = adem_world_contacts(w, before, cap), n0 = w->p.n;
  uint8_t *gone = calloc(n0, 1);
  for (size_t i = 0; i < n0; ++i) gone[i] = w->p.id[i] % 3 == 0;
  size_t removed = 0;
  if (adem_world_remove_particles(w, gone, &removed, &err)) fail_msg("%s", err.message);
  size_t na = adem_world_contacts(w, after, cap);
  size_t kept = 0, found = 0, wrong = 0;
  for (size_t k = 0; k < nb; ++k) {
    const adem_contact_info *x = &before[k];
    bool dead = x->a % 3 == 0 || (x->kind == ADEM_CONTACT_PARTICLE && x->b % 3 == 0);
    if (dead) continue;
    kept++;
    for (size_t j = 0; j < na; ++j) {
      const adem_contact_info *y = &after[j];
      if (y->kind != x->kind || y->a != x->a || y->b != x->b) continue;
      found++;
      if (memcmp(&x->tangential_history, &y->tangential_history, sizeof x->tangential_history))
        wrong++;
      break;
    }
  }
  size_t dead_after = 0;
  for (size_t j = 0; j < na; ++j)
    dead_after += after[j].a % 3 == 0 || (after[j].kind == ADEM_CONTACT_PARTICLE && after[j].b % 3 == 0);
  printf("# removed %zu of %zu; contacts %zu -> %zu; of %zu between survivors %zu found, %zu with "
         "another history; %zu of removed particles\n",
         removed, n0, nb, na, kept, found, wrong, dead_after);
  assert_int_equal(w->p.n, n0 - removed);
  assert_int_equal(removed, (n0 + 2) / 3);
  assert_true(kept > 100);
  assert_int_equal(found, kept);
  assert_int_equal(wrong, 0);
  assert_int_equal(dead_after, 0);
  /* and it steps on */
  if (adem_world_step(w, 200, &err)) fail_msg("%s", err.message);
  free(gone);
  free(before);
  free(after);
  adem_case_free(c);
}

static void expect_refused(const char *set, const char *needle) {
  adem_case *c = NULL;
  adem_error err;
  const char *sets[] = {set};
  adem_status st = adem_case_load_file(case_file_path("outlets-silo"), sets, 1, &c, &err);
  if (st == ADEM_OK) adem_case_free(c);
  printf("# %s -> %s\n", set, err.message);
  assert_int_equal(st, ADEM_ERR_INPUT);
  assert_non_null(strstr(err.message, needle));
}

/* Claim: a wrong outlet or flow is refused naming the key and what is allowed. */
static void test_refusals(void **state) {
  (void)state;
  expect_refused("outlets.catch.region=nowhere", "no region named `nowhere`");
  expect_refused("outlets.bottom.region=below", "give either `region` or `face`");
  expect_refused("outlets.bottom.face=top", "x_min");
  expect_refused("output.mass_flow.orifice.normal=[0, 0, 0]", "the normal is zero");
  expect_refused("output.mass_flow.bin.point=[0, 0, 0]", "give either `region`");
  expect_refused("output.mass_flow.bin.name=silo", "duplicate name `silo`");
  expect_refused("outlets.catch.interval=0", "outlets.catch.interval");
  expect_refused("domain.periodic=[false, false, true]", "periodic axis");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_flow_is_mass_change),
      cmocka_unit_test(test_threads_and_restart),
      cmocka_unit_test(test_remove_keeps_history),
      cmocka_unit_test(test_refusals),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
