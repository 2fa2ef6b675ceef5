/* Claim: a system split over MPI processes (src/mpi/split.c) ends bit for bit where the serial
 * run ends, whatever the number of processes: every particle field by id, every contact with
 * its history, the diagnostics and the plane forces. Run by ctest under mpirun with 2, 3 and 4
 * processes. The settle case (300 spheres falling into a box, 2000 steps) rebuilds its lists
 * often, so particles cross the cuts and take their histories along; a second run adds a lid
 * moving down onto the bed.
 *
 * Control: with the ghosts' refresh left out (a ghost keeps stepping with the partial force
 * its own process gave it) the states differ, or the run fails on a runaway overlap: the
 * comparison can see a broken exchange. */
#include <mpi.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "adem/adem.h"
#include "settle_case.h"
#include "split.h"
#include "split_compare.h"
#include "world_internal.h"

static int rank, nproc;

/* The settle case with a lid coming down at 0.8 m/s from z = 30 mm onto the bed (a moving
 * plane uses up the skin: builds at other steps), 18 ms. */
static char *lid_case(void) {
  const char *lid = "  - {type: plane, name: lid, material: steel, point: [0, 0, 0.03], normal: "
                    "[0, 0, -1], motion: {velocity: [0, 0, -0.8]}}\n";
  const char *at = strstr(settle_case, "time:\n");
  size_t n = strlen(settle_case) + strlen(lid) + 1;
  char *t = malloc(n);
  assert_non_null(t);
  snprintf(t, n, "%.*s%s%s", (int)(at - settle_case), settle_case, lid, at);
  return t;
}

static adem_case *load(const char *text) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_string(text, "settle.yaml", NULL, 0, &c, &err))
    fail_msg("case does not load: %s", err.message);
  adem_world_set_threads(c->world, 1);
  return c;
}

/* The serial run, in chunks of 100 steps as `adem run` under MPI steps. */
static adem_case *run_serial(const char *text, uint64_t steps) {
  adem_case *c = load(text);
  adem_error err;
  for (uint64_t s = 0; s < steps; s += 100)
    if (adem_world_step(c->world, steps - s < 100 ? steps - s : 100, &err))
      fail_msg("serial: %s", err.message);
  return c;
}

static adem_status skip_refresh(void *ctx, adem_world *w, adem_error *err) {
  (void)ctx;
  (void)w;
  (void)err;
  return ADEM_OK;
}

/* The split run, assembled on rank 0 into the case's world; broken: no ghost refresh (the run
 * may then fail: *failed gets why, NULL for a run that ended). */
static adem_case *run_split(const char *text, uint64_t steps, bool broken, const char **failed) {
  adem_case *c = load(text);
  adem_error err;
  if (adem_world_prepare(c->world, &err)) fail_msg("prepare: %s", err.message);
  adem_split *s = NULL;
  adem_world *part = NULL;
  if (adem_split_create(c->world, MPI_COMM_WORLD, &s, &part, &err)) fail_msg("%s", err.message);
  adem_world_split hooks = *part->split;
  if (broken) {
    hooks.refresh = skip_refresh;
    part->split = &hooks;
  }
  /* each process owns some, none owns all, and every particle has one owner */
  unsigned long long own = adem_split_owned(s, part), total = 0;
  MPI_Allreduce(&own, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  assert_int_equal(total, c->world->p.n);
  assert_true(own > 0 && own < total);
  adem_status st = ADEM_OK;
  for (uint64_t k = 0; k < steps && !st; k += 100)
    st = adem_world_step(part, steps - k < 100 ? steps - k : 100, &err);
  /* the cuts follow the particles at every build: equal shares (to one) after the last */
  unsigned long long mine = adem_split_owned(s, part), most = 0, least = 0;
  MPI_Allreduce(&mine, &most, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
  MPI_Allreduce(&mine, &least, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, MPI_COMM_WORLD);
  if (!broken && rank == 0)
    printf("# %d processes own %llu to %llu particles each at the end\n", nproc, least, most);
  if (!broken) assert_true(most - least <= 1);
  if (!st) st = adem_split_assemble(s, part, c->world, false, &err);
  static char why[ADEM_MSG_MAX];
  snprintf(why, sizeof why, "%s", err.message);
  if (failed) *failed = st ? why : NULL;
  else if (st) fail_msg("split run: %s", err.message);
  adem_world_free(part);
  adem_split_free(s);
  return c;
}

static void test_split_equals_serial(void **state) {
  (void)state;
  adem_case *b = run_split(settle_case, SETTLE_STEPS, false, NULL);
  if (rank == 0) {
    adem_case *a = run_serial(settle_case, SETTLE_STEPS);
    const char *why = split_compare(a->world, b->world);
    if (why) fail_msg("%d processes: %s differs from the serial run", nproc, why);
    printf("# %d processes: %zu particles, %llu neighbour builds, %zu touching contacts with "
           "loaded springs: the same bits as the serial run\n",
           nproc, a->world->p.n, (unsigned long long)a->world->nb.rebuilds,
           settle_loaded_contacts(a->world));
    assert_true(settle_loaded_contacts(a->world) > 100);
    assert_true(a->world->nb.rebuilds > 10);
    adem_case_free(a);
  }
  adem_case_free(b);
}

static void test_lid_equals_serial(void **state) {
  (void)state;
  char *t = lid_case();
  const uint64_t steps = 2572; /* 18 ms */
  adem_case *b = run_split(t, steps, false, NULL);
  if (rank == 0) {
    adem_case *a = run_serial(t, steps);
    const char *why = split_compare(a->world, b->world);
    if (why) fail_msg("%d processes, moving lid: %s differs from the serial run", nproc, why);
    printf("# %d processes, moving lid: the lid at z = %.6g m, %llu builds: the same bits\n", nproc,
           a->world->walls.planes[a->world->walls.nplanes - 1].def.point.z,
           (unsigned long long)a->world->nb.rebuilds);
    adem_case_free(a);
  }
  adem_case_free(b);
  free(t);
}

static void test_broken_refresh_differs(void **state) {
  (void)state;
  const char *failed = NULL;
  adem_case *b = run_split(settle_case, SETTLE_STEPS, true, &failed);
  if (rank == 0) {
    adem_case *a = run_serial(settle_case, SETTLE_STEPS);
    const char *why = failed ? failed : split_compare(a->world, b->world);
    printf("# without the ghost refresh: %s\n", why ? why : "no difference");
    assert_non_null(why);
    adem_case_free(a);
  }
  adem_case_free(b);
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &nproc);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_split_equals_serial),
      cmocka_unit_test(test_lid_equals_serial),
      cmocka_unit_test(test_broken_refresh_differs),
  };
  int failed = cmocka_run_group_tests(tests, NULL, NULL);
  int any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return any ? 1 : 0;
}
