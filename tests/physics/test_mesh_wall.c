/* Triangle-mesh walls in the engine: a plate of many triangles acts exactly like the infinite
 * plane it lies in (bit for bit, tangential history carried across triangles by the region key),
 * results do not depend on the thread count, and a moving mesh drags a sphere to the closed-form
 * rolling speed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <unistd.h>

#include "helpers.h"
#include "plate_stl.h"
#include "tmpdir.h"
#include "world_internal.h"
#include "stl.h"

static int group_setup(void **state) {
  (void)state;
  return tmpdir_make("adem_meshwall");
}

static adem_world *bouncing_world(int use_mesh, const char *plate) {
  adem_world *w = adem_world_create();
  int glass = test_material(w, "glass", 1e7, 0.25, 0.5, 0.4);
  adem_material_def steel = adem_default_material_def();
  snprintf(steel.name, sizeof steel.name, "steel");
  steel.rigid = 1;
  steel.friction = 0.4;
  steel.restitution = 0.5;
  adem_error err;
  int st = -1;
  assert_int_equal(adem_world_add_material(w, &steel, &st, &err), ADEM_OK);
  assert_true(st >= 0);
  if (use_mesh) {
    adem_mesh_transform tf = adem_default_mesh_transform();
    tf.material = st;
    assert_int_equal(adem_world_add_stl(w, plate, &tf, "floor", v3_zero(), &err), ADEM_OK);
  } else {
    adem_plane_def pl = adem_default_plane_def();
    snprintf(pl.name, sizeof pl.name, "floor");
    pl.material = st;
    assert_int_equal(adem_world_add_plane(w, &pl, NULL, &err), ADEM_OK);
  }
  /* three spheres thrown at the floor with spin: they bounce, slide and roll over triangles */
  adem_particle_def d = adem_default_particle_def();
  d.material = glass;
  d.radius = 0.004;
  d.position = v3(-0.03, 0.01, 0.006);
  d.velocity = v3(0.4, 0.1, -0.3);
  d.angular_velocity = v3(20, -30, 5);
  assert_int_equal(adem_world_add_particle(w, &d, NULL, &err), ADEM_OK);
  d.position = v3(0.02, -0.02, 0.0045);
  d.velocity = v3(-0.2, 0.35, 0.0);
  d.angular_velocity = v3(0, 0, 0);
  assert_int_equal(adem_world_add_particle(w, &d, NULL, &err), ADEM_OK);
  d.position = v3(0.0, 0.04, 0.0100);
  d.velocity = v3(0.05, -0.3, -0.1);
  d.radius = 0.003;
  assert_int_equal(adem_world_add_particle(w, &d, NULL, &err), ADEM_OK);
  adem_world_set_dt(w, 2e-6);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  return w;
}

/* Claim: three spheres bouncing and rolling on a plate of 2 x 32 x 32 triangles follow exactly
 * (bit for bit) the trajectories they follow on the infinite plane z = 0, over 0.1 s in which
 * they cross tens of triangle edges and vertices: one contact per sphere with the plane's normal
 * and overlap, and the tangential history kept across triangles by the region key. */
static void test_plate_is_plane(void **state) {
  (void)state;
  char plate[512];
  snprintf(plate, sizeof plate, "%s/plate.stl", tmpdir);
  write_plate(plate, 32, 0.00390625); /* 1/256 m squares: a 0.125 m plate */
  adem_world *a = bouncing_world(0, plate), *b = bouncing_world(1, plate);
  adem_error err;
  adem_vec3 start[3];
  for (int i = 0; i < 3; ++i) start[i] = b->p.pos[i];
  size_t touching = 0;
  for (int s = 0; s < 100; ++s) {
    assert_int_equal(adem_world_step(a, 500, &err), ADEM_OK);
    assert_int_equal(adem_world_step(b, 500, &err), ADEM_OK);
    for (size_t i = 0; i < 3; ++i) {
      assert_memory_equal(&a->p.pos[i], &b->p.pos[i], sizeof(adem_vec3));
      assert_memory_equal(&a->p.vel[i], &b->p.vel[i], sizeof(adem_vec3));
      assert_memory_equal(&a->p.omega[i], &b->p.omega[i], sizeof(adem_vec3));
    }
    adem_diagnostics da = adem_world_diagnostics(a), db = adem_world_diagnostics(b);
    assert_true(da.elastic == db.elastic);
    assert_int_equal(da.contacts_pw, db.contacts_pw);
    touching += db.contacts_pw;
  }
  double travel = 0.0;
  for (int i = 0; i < 3; ++i) travel += v3_norm(v3_sub(b->p.pos[i], start[i]));
  printf("# total travel %.3f m (%.0f triangle widths), %zu contact samples\n", travel,
         travel / 0.00390625, touching);
  assert_true(travel > 20 * 0.00390625);
  assert_true(touching > 50);
  adem_world_free(a);
  adem_world_free(b);
}

/* Claim: 400 spheres poured into a box made of a 12-triangle mesh (walls and floor) give the same
 * state bit for bit with 1 and 2 threads. */
static void test_mesh_threads(void **state) {
  (void)state;
  adem_vec3 pos[2][400];
  for (int run = 0; run < 2; ++run) {
    adem_world *w = adem_world_create();
    adem_world_set_threads(w, run + 1);
    w->parallel_min = 0;
    int glass = test_material(w, "glass", 1e7, 0.25, 0.5, 0.4);
    adem_mesh_transform tf = adem_default_mesh_transform();
    tf.scale = 0.05;
    tf.material = glass;
    adem_error err;
    assert_int_equal(adem_world_add_stl(w, ADEM_SOURCE_DIR "/tests/data/cube_ascii.stl", &tf, "box",
                                        v3_zero(), &err),
                     ADEM_OK);
    for (int k = 0; k < 400; ++k) {
      adem_vec3 x = v3(0.005 + 0.005 * (k % 8), 0.005 + 0.005 * ((k / 8) % 8), 0.0025 + 0.0045 * (k / 64));
      test_particle(w, glass, x, v3(0.01 * (k % 3), -0.01 * (k % 5), 0), 0.002);
    }
    adem_world_set_dt(w, 5e-6);
    assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
    assert_int_equal(adem_world_step(w, 10000, &err), ADEM_OK);
    for (size_t i = 0; i < w->p.n; ++i) pos[run][w->p.id[i]] = w->p.pos[i];
    adem_diagnostics d = adem_world_diagnostics(w);
    printf("# %d thread(s): %zu wall contacts\n", run + 1, d.contacts_pw);
    assert_true(d.contacts_pw > 40);
    adem_world_free(w);
  }
  assert_memory_equal(pos[0], pos[1], sizeof pos[0]);
}

/* Claim: a sphere at rest on a plate moving at V along x is dragged by friction until it rolls;
 * the angular momentum about the contact point gives v = (2/7) V (I = 2/5 m r^2). Within 1 %:
 * the tangential spring stores a little of the motion. */
static void test_moving_mesh_drags(void **state) {
  (void)state;
  char plate[512];
  snprintf(plate, sizeof plate, "%s/belt.stl", tmpdir);
  write_plate(plate, 16, 0.0625);
  adem_world *w = adem_world_create();
  int glass = test_material(w, "glass", 1e7, 0.25, 0.9, 0.3);
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.material = glass;
  tf.own_vertices = 1;
  adem_error err;
  const double V = 0.2;
  assert_int_equal(adem_world_add_stl(w, plate, &tf, "belt", v3(V, 0, 0), &err), ADEM_OK);
  double r = 0.005;
  /* just touching: a particle may not start inside a mesh face; it sinks by the resting overlap
   * (about 2 um) with a bounce far too small to matter */
  test_particle(w, glass, v3(0, 0, r), v3_zero(), r);
  adem_world_set_dt(w, 5e-6);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  assert_int_equal(adem_world_step(w, 40000, &err), ADEM_OK); /* 0.2 s; slip ends after ~0.02 s */
  double v = w->p.vel[0].x;
  printf("# v/V = %.5f (2/7 = %.5f)\n", v / V, 2.0 / 7.0);
  assert_true(fabs(v / V - 2.0 / 7.0) < 0.01 * 2.0 / 7.0);
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plate_is_plane),
      cmocka_unit_test(test_mesh_threads),
      cmocka_unit_test(test_moving_mesh_drags),
  };
  return cmocka_run_group_tests(tests, group_setup, tmpdir_teardown);
}
