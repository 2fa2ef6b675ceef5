/* Bulk access in id order (adem_world_get_ids, adem_world_set_particles), the id -> index map
 * behind adem_world_set_particle, and the per-particle external force. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "adem/adem.h"
#include "adem/vec3.h"
#include "helpers.h"
#include "world_internal.h"

/* A loose cloud of n spheres of radius 1 mm on a 3 mm lattice, falling onto a floor. */
static adem_world *cloud(int n) {
  adem_world *w = adem_world_create();
  int m = test_material(w, "glass", 1e7, 0.3, 0.5, 0.5);
  assert_true(m >= 0);
  int side = 1;
  while (side * side * side < n) ++side;
  for (int k = 0; k < n; ++k) {
    adem_vec3 x = v3(3e-3 * (k % side), 3e-3 * ((k / side) % side), 2e-3 + 3e-3 * (k / (side * side)));
    assert_true(test_particle(w, m, x, v3(0.01 * (k % 7), -0.01 * (k % 5), 0.0), 1e-3) == k);
  }
  adem_plane_def floor = adem_default_plane_def();
  floor.normal = v3(0, 0, 1);
  adem_error err;
  assert_int_equal(adem_world_add_plane(w, &floor, NULL, &err), ADEM_OK);
  adem_world_set_dt(w, 1e-5);
  return w;
}

static double *field(const adem_world *w, adem_particle_field f) {
  size_t n = adem_world_particle_count(w) * 3;
  double *a = malloc(n * sizeof *a);
  adem_error err;
  assert_int_equal(adem_world_get_particles(w, f, a, n, &err), ADEM_OK);
  return a;
}

/* Rows set in id order come back in id order, whatever order the particles are stored in. */
static void test_set_particles_in_id_order(void **state) {
  (void)state;
  adem_world *w = cloud(200);
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  assert_int_equal(adem_world_shuffle_storage(w, 7, &err), ADEM_OK);
  assert_true(w->p.id[0] != 0 || w->p.id[1] != 1); /* stored out of id order */
  size_t n = adem_world_particle_count(w);
  uint64_t *ids = malloc(n * sizeof *ids);
  assert_int_equal(adem_world_get_ids(w, ids, n, &err), ADEM_OK);
  for (size_t k = 0; k < n; ++k) assert_int_equal(ids[k], k);
  double *v = malloc(3 * n * sizeof *v);
  for (size_t k = 0; k < 3 * n; ++k) v[k] = 0.001 * (double)k;
  assert_int_equal(adem_world_set_particles(w, ADEM_FIELD_VELOCITY, v, n, &err), ADEM_OK);
  double *back = field(w, ADEM_FIELD_VELOCITY);
  assert_memory_equal(back, v, 3 * n * sizeof *v);
  /* and through the storage: particle id k holds row k */
  for (size_t i = 0; i < n; ++i) assert_true(w->p.vel[i].y == v[3 * w->p.id[i] + 1]);
  free(back);
  /* the external force is a field like the others */
  assert_int_equal(adem_world_set_particles(w, ADEM_FIELD_EXTERNAL_FORCE, v, n, &err), ADEM_OK);
  back = field(w, ADEM_FIELD_EXTERNAL_FORCE);
  assert_memory_equal(back, v, 3 * n * sizeof *v);
  assert_int_equal(adem_particle_field_components(ADEM_FIELD_EXTERNAL_FORCE), 3);
  free(back);
  free(v);
  free(ids);
  adem_world_free(w);
}

/* adem_world_set_particle finds the particle through the id map, which a reordering (here a
 * shuffle of the storage, then neighbour builds that sort by cell) makes stale, never wrong. */
static void test_set_particle_after_reordering(void **state) {
  (void)state;
  adem_world *w = cloud(300);
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  size_t n = adem_world_particle_count(w);
  for (int round = 0; round < 3; ++round) {
    assert_int_equal(adem_world_shuffle_storage(w, 11 + (uint64_t)round, &err), ADEM_OK);
    for (size_t id = 0; id < n; ++id) {
      adem_vec3 spin = v3((double)id, (double)round, -(double)id);
      assert_int_equal(adem_world_set_particle(w, id, NULL, NULL, &spin, &err), ADEM_OK);
    }
    double *om = field(w, ADEM_FIELD_ANGULAR_VELOCITY);
    for (size_t id = 0; id < n; ++id) {
      assert_true(om[3 * id] == (double)id);
      assert_true(om[3 * id + 1] == (double)round);
    }
    free(om);
    assert_int_equal(adem_world_step(w, 20, &err), ADEM_OK);
  }
  /* one stale look-up rebuilds the map: the rest of a pass over every id are hits */
  assert_true(w->id_map_n == n);
  assert_int_equal(adem_world_set_particle(w, n, NULL, NULL, NULL, &err), ADEM_ERR_INPUT);
  assert_non_null(strstr(err.message, "no particle has id"));
  adem_world_free(w);
}

static void test_bad_input(void **state) {
  (void)state;
  adem_world *w = cloud(10);
  adem_error err;
  double a[33] = {0};
  assert_int_equal(adem_world_set_particles(w, ADEM_FIELD_POSITION, a, 11, &err), ADEM_ERR_INPUT);
  assert_non_null(strstr(err.message, "11 rows given for 10 particles"));
  assert_int_equal(adem_world_set_particles(w, ADEM_FIELD_RADIUS, a, 10, &err), ADEM_ERR_INPUT);
  assert_non_null(strstr(err.message, "cannot be set"));
  double *before = field(w, ADEM_FIELD_POSITION);
  a[17] = NAN;
  assert_int_equal(adem_world_set_particles(w, ADEM_FIELD_POSITION, a, 10, &err), ADEM_ERR_INPUT);
  double *after = field(w, ADEM_FIELD_POSITION);
  assert_memory_equal(before, after, 30 * sizeof *before); /* nothing was set */
  free(before);
  free(after);
  uint64_t ids[9];
  assert_int_equal(adem_world_get_ids(w, ids, 9, &err), ADEM_ERR_INPUT);
  assert_int_equal(adem_world_set_external_force(w, 99, v3(1, 0, 0), &err), ADEM_ERR_INPUT);
  adem_world_free(w);
}

/* A lone sphere without gravity under a constant external force F: velocity Verlet is exact
 * for a constant force, v = F t / m and x = x0 + F t^2 / (2 m), to rounding (1e-12). Without the
 * force in the force pass v stays 0. The balance counts F as the potential -F . x. */
static void test_external_force_accelerates(void **state) {
  (void)state;
  adem_world *w = adem_world_create();
  int m = test_material(w, "glass", 1e7, 0.3, 0.5, 0.5);
  test_particle(w, m, v3(0, 0, 0), v3_zero(), 1e-3);
  adem_world_set_gravity(w, v3_zero());
  adem_world_set_dt(w, 1e-5);
  adem_error err;
  double mass = test_sphere_mass(1e-3, 2500.0);
  adem_vec3 F = v3(2e-6, -1e-6, 0.5e-6);
  assert_int_equal(adem_world_set_external_force(w, 0, F, &err), ADEM_OK);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  assert_int_equal(adem_world_step(w, 1000, &err), ADEM_OK);
  double t = adem_world_time(w);
  double *v = field(w, ADEM_FIELD_VELOCITY), *x = field(w, ADEM_FIELD_POSITION);
  assert_float_equal(v[0], F.x / mass * t, 1e-12 * fabs(F.x / mass * t));
  assert_float_equal(v[1], F.y / mass * t, 1e-12 * fabs(F.y / mass * t));
  assert_float_equal(x[0], 0.5 * F.x / mass * t * t, 1e-12 * fabs(0.5 * F.x / mass * t * t));
  free(v);
  free(x);
  adem_diagnostics d = adem_world_diagnostics(w);
  double ke = d.kinetic;
  assert_true(ke > 0.0);
  assert_true(fabs(d.balance_error) < 1e-9 * ke);
  /* a change of the force is work from outside: the balance still closes */
  assert_int_equal(adem_world_set_external_force(w, 0, v3(-F.x, 0, 0), &err), ADEM_OK);
  assert_int_equal(adem_world_step(w, 1000, &err), ADEM_OK);
  d = adem_world_diagnostics(w);
  assert_true(fabs(d.balance_error) < 1e-9 * ke);
  adem_world_free(w);
}

static void hash_state(const adem_world *w, double **pos, double **vel) {
  *pos = field(w, ADEM_FIELD_POSITION);
  *vel = field(w, ADEM_FIELD_VELOCITY);
}

/* External forces on a falling cloud: the same bits with 1 and 2 threads, and a world written
 * to a checkpoint and read back steps on to the same bits (the force is saved). */
static void test_external_force_bits(void **state) {
  (void)state;
  char dir[] = "/tmp/adem_bulk_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char path[256];
  snprintf(path, sizeof path, "%s/world", dir);
  double *pos[3], *vel[3];
  for (int run = 0; run < 3; ++run) {
    adem_world *w = cloud(400);
    adem_world_set_threads(w, run == 1 ? 2 : 1);
    w->parallel_min = 1; /* 400 particles would run on one thread */
    adem_error err;
    size_t n = adem_world_particle_count(w);
    double *f = malloc(3 * n * sizeof *f);
    for (size_t k = 0; k < n; ++k) {
      f[3 * k] = 1e-5 * sin((double)k);
      f[3 * k + 1] = 1e-5 * cos((double)k);
      f[3 * k + 2] = 0.0;
    }
    assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
    assert_int_equal(adem_world_set_particles(w, ADEM_FIELD_EXTERNAL_FORCE, f, n, &err), ADEM_OK);
    free(f);
    assert_int_equal(adem_world_step(w, 300, &err), ADEM_OK);
    if (run == 2) { /* through a checkpoint */
      assert_int_equal(adem_world_checkpoint_write(w, path, &err), ADEM_OK);
      adem_world_free(w);
      assert_int_equal(adem_world_checkpoint_read(path, &w, &err), ADEM_OK);
    }
    assert_int_equal(adem_world_step(w, 300, &err), ADEM_OK);
    hash_state(w, &pos[run], &vel[run]);
    if (run == 0) { /* the forces moved the cloud sideways */
      adem_world *still = cloud(400);
      assert_int_equal(adem_world_step(still, 600, &err), ADEM_OK);
      double *p0 = field(still, ADEM_FIELD_POSITION);
      int moved = 0;
      for (size_t k = 0; k < 3 * n; ++k) moved += p0[k] != pos[0][k];
      assert_true(moved > (int)n);
      free(p0);
      adem_world_free(still);
    }
    adem_world_free(w);
  }
  size_t bytes = 3 * 400 * sizeof(double);
  assert_memory_equal(pos[0], pos[1], bytes);
  assert_memory_equal(vel[0], vel[1], bytes);
  assert_memory_equal(pos[0], pos[2], bytes);
  assert_memory_equal(vel[0], vel[2], bytes);
  for (int k = 0; k < 3; ++k) {
    free(pos[k]);
    free(vel[k]);
  }
  unlink(path);
  rmdir(dir);
}

/* Particles from arrays: the ids come back in order, and a bad row adds none. */
static void test_add_particles(void **state) {
  (void)state;
  adem_world *w = adem_world_create();
  int m = test_material(w, "glass", 1e7, 0.3, 0.5, 0.5);
  double pos[9] = {0, 0, 0, 0.01, 0, 0, 0.02, 0, 0}, r[3] = {1e-3, 1e-3, -1.0};
  int mat[3] = {m, m, m};
  uint64_t ids[3] = {9, 9, 9};
  adem_error err;
  assert_int_equal(adem_world_add_particles(w, 3, pos, NULL, NULL, r, mat, NULL, ids, &err),
                   ADEM_ERR_INPUT);
  assert_non_null(strstr(err.message, "row 2"));
  assert_int_equal(adem_world_particle_count(w), 0);
  r[2] = 2e-3;
  assert_int_equal(adem_world_add_particles(w, 3, pos, pos, NULL, r, mat, NULL, ids, &err), ADEM_OK);
  assert_int_equal(adem_world_particle_count(w), 3);
  for (int k = 0; k < 3; ++k) assert_int_equal(ids[k], k);
  double *v = field(w, ADEM_FIELD_VELOCITY), *rad = field(w, ADEM_FIELD_RADIUS);
  assert_memory_equal(v, pos, sizeof pos);
  assert_true(rad[2] == 2e-3);
  free(v);
  free(rad);
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_set_particles_in_id_order),
      cmocka_unit_test(test_set_particle_after_reordering),
      cmocka_unit_test(test_bad_input),
      cmocka_unit_test(test_external_force_accelerates),
      cmocka_unit_test(test_external_force_bits),
      cmocka_unit_test(test_add_particles),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
