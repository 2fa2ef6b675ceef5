/* Claim: the results do not depend on the order in which the particles and the pair lists are
 * stored, bit for bit: a run whose storage is shuffled at random at the start and twice while it
 * runs ends with the same state, particle by particle (by id), contact by contact, the same wall
 * and face loads and the same diagnostics as the run stored in the order the neighbour builds
 * give. Each pair is evaluated with the lower id first, each particle's sum runs over its
 * partners by id, and global sums run over the particles by id (docs/architecture.md, "Order
 * independence"): what an MPI run, whose ranks each store their own subset in their own order,
 * needs to give the serial run's bits (issue 15). Cases: the settle case (planes, friction), the
 * periodic bed (contacts through the periodic faces), and a mesh box with a moving, spinning
 * plate, JKR adhesion and rolling resistance (BROF between spheres, model C on the walls). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "bitwise/periodic_case.h"
#include "bitwise/settle_case.h"
#include "case_file.h"
#include "plate_stl.h"
#include "tmpdir.h"
#include "world_internal.h"

/* The cases: tests/cases/settle.yaml, periodic.yaml and bitwise-mesh-order.yaml. */

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_storage_order")) return -1;
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s/plate.stl", tmpdir);
  write_plate(cmd, 3, 0.004); /* a 0.012 m plate of 3 x 3 squares */
  return 0;
}

/* tests/cases/NAME.yaml; the mesh case's plate is the one setup wrote. */
static adem_case *load(const char *name) {
  char plate[600];
  snprintf(plate, sizeof plate, "walls.plate.file=%s/plate.stl", tmpdir);
  const char *sets[] = {plate};
  return case_file_load(name, sets, strcmp(name, "bitwise-mesh-order") ? 0 : 1);
}

/* Steps in three chunks (the same in both runs: the last pass of a call computes the stored
 * energies the diagnostics read); shuffled before each chunk when seed != 0. */
static void run(adem_case *c, const uint64_t chunks[3], uint64_t seed) {
  adem_error err;
  adem_world *w = c->world;
  adem_world_set_threads(w, 1); /* the thread count is bitwise/test_threads.c's claim */
  if (adem_world_prepare(w, &err)) fail_msg("%s", err.message);
  for (int k = 0; k < 3; ++k) {
    if (seed && adem_world_shuffle_storage(w, seed + (uint64_t)k, &err)) fail_msg("%s", err.message);
    if (adem_world_step(w, chunks[k], &err)) fail_msg("%s", err.message);
  }
}

/* Index of each id (ids are 0 .. n-1 here). */
static size_t *index_of_ids(const adem_particles *p) {
  size_t *at = malloc((p->n + 1) * sizeof *at);
  assert_non_null(at);
  for (size_t i = 0; i < p->n; ++i) {
    assert_true(p->id[i] < p->n);
    at[p->id[i]] = i;
  }
  return at;
}

/* Every per-particle array (ADEM_PARTICLE_FIELDS), particle by particle by id; an absent optional
 * one as the zeros it reads as. */
static void assert_same_particles(const adem_particles *p, const adem_particles *q) {
  static const char zeros[64];
  assert_int_equal(p->n, q->n);
  size_t *ip = index_of_ids(p), *iq = index_of_ids(q);
  adem_soa_layout L = adem_particles_layout();
  for (size_t f = 0; f < L.count; ++f) {
    const char *a = *(char *const *)((const char *)p + L.fields[f].offset);
    const char *b = *(char *const *)((const char *)q + L.fields[f].offset);
    size_t e = L.fields[f].elem;
    assert_true(e <= sizeof zeros);
    for (uint64_t id = 0; id < p->n; ++id)
      if (memcmp(a ? a + ip[id] * e : zeros, b ? b + iq[id] * e : zeros, e) != 0)
        fail_msg("particle id %llu: %s differs", (unsigned long long)id, L.fields[f].name);
  }
  free(ip);
  free(iq);
}

static int compare_contacts(const void *x, const void *y) {
  const adem_contact_info *a = x, *b = y;
  if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
  if (a->a != b->a) return a->a < b->a ? -1 : 1;
  if (a->b != b->b) return a->b < b->b ? -1 : 1;
  return memcmp(a, b, sizeof *a); /* two contacts of one particle with one mesh group */
}

static adem_contact_info *sorted_contacts(const adem_world *w, size_t *n) {
  *n = adem_world_contacts(w, NULL, 0);
  adem_contact_info *c = calloc(*n + 1, sizeof *c); /* zero padding: compared with memcmp */
  assert_non_null(c);
  assert_int_equal(adem_world_contacts(w, c, *n), *n);
  qsort(c, *n, sizeof *c, compare_contacts);
  return c;
}

static void assert_same_bits(const void *a, const void *b, size_t bytes, const char *what) {
  if (bytes > 0 && memcmp(a, b, bytes) != 0) fail_msg("%s differ", what); /* no mesh: NULL */
}

/* Everything the two runs report, compared bit for bit. Returns the touching contacts. */
static size_t assert_same_results(const adem_world *a, const adem_world *b) {
  assert_int_equal(a->step, b->step);
  assert_same_particles(&a->p, &b->p);
  size_t na, nb;
  adem_contact_info *ca = sorted_contacts(a, &na), *cb = sorted_contacts(b, &nb);
  assert_int_equal(na, nb);
  for (size_t k = 0; k < na; ++k)
    if (memcmp(&ca[k], &cb[k], sizeof ca[k]) != 0)
      fail_msg("contact %llu-%llu (kind %d) differs", (unsigned long long)ca[k].a,
               (unsigned long long)ca[k].b, (int)ca[k].kind);
  free(ca);
  free(cb);
  adem_diagnostics da = adem_world_diagnostics(a), db = adem_world_diagnostics(b);
  printf("# kinetic %.17g J, elastic %.17g J, dissipated %.17g J, %zu + %zu contacts\n", da.kinetic,
         da.elastic, da.dissipated, da.contacts_pp, da.contacts_pw);
  const double *x[] = {&da.kinetic, &da.rotational, &da.potential, &da.elastic, &da.dissipated,
                       &da.wall_work, &da.initial, &da.balance_error, &da.max_overlap_ratio};
  const double *y[] = {&db.kinetic, &db.rotational, &db.potential, &db.elastic, &db.dissipated,
                       &db.wall_work, &db.initial, &db.balance_error, &db.max_overlap_ratio};
  const char *names[] = {"kinetic energies", "rotational energies", "potential energies",
                         "elastic energies", "dissipated energies", "wall works",
                         "initial energies", "balance errors", "largest overlaps"};
  for (size_t k = 0; k < sizeof x / sizeof x[0]; ++k) assert_same_bits(x[k], y[k], sizeof *x[k], names[k]);
  assert_same_bits(&da.angular_momentum, &db.angular_momentum, sizeof da.angular_momentum,
                   "angular momenta");
  assert_same_bits(&da.brof_impulse, &db.brof_impulse, sizeof da.brof_impulse, "BROF impulses");
  assert_int_equal(da.contacts_pp, db.contacts_pp);
  assert_int_equal(da.contacts_pw, db.contacts_pw);
  int np = a->walls.nplanes;
  adem_vec3 fa[16], fb[16];
  assert_true(np <= 16);
  adem_world_plane_forces(a, fa);
  adem_world_plane_forces(b, fb);
  assert_same_bits(fa, fb, (size_t)np * sizeof *fa, "plane forces");
  size_t nf = 3 * a->walls.mesh.ntris;
  assert_same_bits(a->walls.face_force, b->walls.face_force, nf * sizeof(double), "face forces");
  assert_same_bits(a->walls.face_torque, b->walls.face_torque, nf * sizeof(double), "face torques");
  /* the servo and motion state of the walls (moving plate) */
  assert_same_bits(a->walls.mesh.vert, b->walls.mesh.vert, a->walls.mesh.nverts * sizeof(adem_vec3),
                   "mesh vertices");
  return na;
}

static void test_settle_shuffled(void **state) {
  (void)state;
  const uint64_t chunks[3] = {600, 700, SETTLE_STEPS - 1300};
  adem_case *a = load("settle"), *b = load("settle");
  run(a, chunks, 0);
  run(b, chunks, 42);
  size_t n = assert_same_results(a->world, b->world);
  printf("# settle: %zu touching contacts, %zu with a loaded spring\n", n,
         settle_loaded_contacts(a->world));
  assert_true(settle_loaded_contacts(a->world) > 100);
  adem_case_free(a);
  adem_case_free(b);
}

static void test_periodic_shuffled(void **state) {
  (void)state;
  const uint64_t chunks[3] = {500, 700, PERIODIC_STEPS - 1200};
  adem_case *a = load("periodic"), *b = load("periodic");
  run(a, chunks, 0);
  run(b, chunks, 99);
  size_t n = assert_same_results(a->world, b->world);
  size_t crossed = 0;
  for (size_t i = 0; i < a->world->p.n; ++i)
    crossed += a->world->p.image[i].n[0] != 0 || a->world->p.image[i].n[1] != 0;
  printf("# periodic: %zu touching contacts, %zu spheres crossed a periodic face\n", n, crossed);
  assert_true(n > 100 && crossed > 50);
  adem_case_free(a);
  adem_case_free(b);
}

static void test_mesh_jkr_shuffled(void **state) {
  (void)state;
  const uint64_t chunks[3] = {1200, 1400, 1600};
  adem_case *a = load("bitwise-mesh-order"), *b = load("bitwise-mesh-order");
  run(a, chunks, 0);
  run(b, chunks, 1234);
  size_t n = assert_same_results(a->world, b->world);
  size_t mesh = 0;
  for (size_t k = 0; k < a->world->pm.l.n; ++k) mesh += a->world->pm.l.touching[k];
  printf("# mesh: %zu touching contacts, %zu on the mesh\n", n, mesh);
  assert_true(mesh > 100 && n > 200);
  adem_case_free(a);
  adem_case_free(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_settle_shuffled),
      cmocka_unit_test(test_periodic_shuffled),
      cmocka_unit_test(test_mesh_jkr_shuffled),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
