/* Walls that are the same all along a periodic axis need no images: a drum of 90 STL facets
 * extruded along the periodic axis past both faces, and an analytic infinite cylinder along it,
 * carry a sphere across the periodic faces as the same wall without the periodic box does; other
 * meshes and curved walls near a periodic face are refused with a message. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "helpers.h"
#include "world_internal.h"

static const double PI = 3.14159265358979323846;
static const double R = 0.05, BOX = 0.03, SR = 0.005;

/* A shell of n facets about x from x0 to x1 (normals inwards), one flat strip per facet, each
 * strip cut into `pieces` along x. */
static void add_shell(adem_world *w, int mat, int n, double x0, double x1, int pieces,
                      const char *name) {
  size_t nt = 2 * (size_t)n * (size_t)pieces;
  adem_vec3 *c = malloc(3 * nt * sizeof *c);
  assert_non_null(c);
  size_t q = 0;
  for (int k = 0; k < n; ++k)
    for (int s = 0; s < pieces; ++s) {
      double p0 = (k + 0.5) * 2.0 * PI / n, p1 = (k + 1.5) * 2.0 * PI / n;
      double xa = x0 + (x1 - x0) * s / pieces, xb = s + 1 == pieces ? x1 : x0 + (x1 - x0) * (s + 1) / pieces;
      adem_vec3 a0 = v3(xa, R * sin(p0), -R * cos(p0)), a1 = v3(xa, R * sin(p1), -R * cos(p1));
      adem_vec3 b0 = v3(xb, a0.y, a0.z), b1 = v3(xb, a1.y, a1.z);
      /* (a0, b1, a1): the normal (b1 - a0) x (a1 - a0) points to the axis */
      adem_vec3 t[6] = {a0, b1, a1, a0, b0, b1};
      for (int j = 0; j < 6; ++j) c[q++] = t[j];
    }
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.material = mat;
  tf.own_vertices = 1;
  adem_error err;
  if (adem_world_add_mesh(w, c, nt, name, &tf, &err)) fail_msg("%s", err.message);
  free(c);
}

/* A sphere rolling round a turning drum (2 rad/s) and sliding along its axis at 0.2 m/s, in a box
 * periodic along x (BOX long) or not. */
static adem_world *shell_world(bool periodic, bool mesh, double x0, double x1) {
  adem_world *w = adem_world_create();
  int glass = test_material(w, "glass", 1e7, 0.3, 0.3, 0.3);
  adem_material_def steel = adem_default_material_def();
  snprintf(steel.name, sizeof steel.name, "steel");
  steel.rigid = 1;
  steel.friction = 0.3;
  steel.restitution = 0.3;
  adem_error err;
  int st = -1;
  assert_int_equal(adem_world_add_material(w, &steel, &st, &err), ADEM_OK);
  adem_motion_def md = {0};
  md.axis = v3(1, 0, 0);
  md.angular_speed = 2.0;
  if (mesh) {
    add_shell(w, st, 90, x0, x1, 3, "shell");
    assert_int_equal(adem_world_set_mesh_motion(w, 0, &md, &err), ADEM_OK);
  } else {
    adem_plane_def d = adem_default_plane_def();
    snprintf(d.name, sizeof d.name, "drum");
    d.material = st;
    d.shape = ADEM_WALL_CYLINDER;
    d.normal = v3(1, 0, 0);
    d.radius = R;
    int idx = -1;
    assert_int_equal(adem_world_add_plane(w, &d, &idx, &err), ADEM_OK);
    assert_int_equal(adem_world_set_plane_motion(w, idx, &md, &err), ADEM_OK);
  }
  if (periodic)
    assert_int_equal(adem_world_set_periodic(w, v3(0, -0.1, -0.1), v3(BOX, 0.1, 0.1),
                                             ADEM_PERIODIC_X, &err),
                     ADEM_OK);
  adem_particle_def p = adem_default_particle_def();
  p.material = glass;
  p.radius = SR;
  p.position = v3(0.015, 0.0, -(R * cos(PI / 90) - SR) + 1e-4);
  p.velocity = v3(0.2, 0.05, 0.0);
  assert_int_equal(adem_world_add_particle(w, &p, NULL, &err), ADEM_OK);
  adem_world_set_gravity(w, v3(0, 0, -9.81));
  adem_world_set_dt(w, 4e-6);
  return w;
}

/* Claim: over 0.5 s, in which the sphere crosses the periodic faces twice, its unwrapped
 * position in the periodic box (drum and shell 0.03 m long) is the one it has in the same drum
 * without a periodic box (a 0.3 m long shell): with the analytic infinite cylinder its velocity,
 * spin and position across the axis bit for bit (its surface does not depend on the position
 * along the axis) and along it to 1e-14 m (the unwrapping's rounding), and to 1e-9 m with the STL
 * shell (the same planes, its distances computed from other triangles' corners). */
static void test_shell_across_faces(void **state) {
  (void)state;
  for (int mesh = 0; mesh < 2; ++mesh) {
    adem_world *a = shell_world(true, mesh, -0.012, BOX + 0.012);
    adem_world *b = shell_world(false, mesh, -0.012, 0.3);
    adem_error err;
    assert_int_equal(adem_world_prepare(a, &err), ADEM_OK);
    assert_int_equal(adem_world_prepare(b, &err), ADEM_OK);
    double worst = 0.0;
    size_t touching = 0;
    bool same_bits = true; /* across the axis, and the velocities and spins */
    for (int s = 0; s < 125; ++s) {
      assert_int_equal(adem_world_step(a, 1000, &err), ADEM_OK);
      assert_int_equal(adem_world_step(b, 1000, &err), ADEM_OK);
      adem_vec3 xa = adem_periodic_unwrap(&a->periodic, a->p.pos[0], a->p.image[0]);
      worst = fmax(worst, v3_norm(v3_sub(xa, b->p.pos[0])));
      same_bits = same_bits && a->p.pos[0].y == b->p.pos[0].y && a->p.pos[0].z == b->p.pos[0].z &&
                  !memcmp(&a->p.vel[0], &b->p.vel[0], sizeof(adem_vec3)) &&
                  !memcmp(&a->p.omega[0], &b->p.omega[0], sizeof(adem_vec3));
      touching += adem_world_diagnostics(a).contacts_pw > 0 || a->pm.l.n > 0;
    }
    printf("# %s: crossed the faces %d times, x = %.4f m, largest difference %.3g m\n",
           mesh ? "STL shell" : "cylinder", a->p.image[0].n[0], b->p.pos[0].x, worst);
    assert_true(a->p.image[0].n[0] >= 2);
    assert_true(touching >= 100);
    if (mesh) assert_true(worst <= 1e-9);
    else assert_true(same_bits && worst <= 1e-14);
    adem_world_free(a);
    adem_world_free(b);
  }
}

/* Claim: a shell that stops at the periodic faces, one with a gap along the axis, a mesh not the
 * same along the axis near a face, and a finite cylinder across a face are refused, each with a
 * message that says what to do. */
static void test_refusals(void **state) {
  (void)state;
  adem_error err;
  /* the shell stops 1 mm past the faces: not the reach */
  adem_world *w = shell_world(true, true, -0.001, BOX + 0.001);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "does not reach past both faces"));
  adem_world_free(w);
  /* a gap: a second shell piece leaves 2 mm out */
  w = shell_world(true, true, -0.012, 0.01);
  add_shell(w, 1, 90, 0.012, BOX + 0.012, 1, "shell2");
  assert_int_equal(adem_world_prepare(w, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "gap along the axis"));
  adem_world_free(w);
  /* a sloping plate across the faces, not the same along x */
  w = shell_world(true, false, 0, 0);
  const adem_vec3 tri[3] = {v3(-0.5, -0.04, -0.03), v3(1.5, -0.04, -0.02), v3(0.5, 0.04, -0.03)};
  assert_int_equal(adem_world_add_mesh(w, tri, 1, "floor", NULL, &err), ADEM_OK);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "not the same along that axis"));
  adem_world_free(w);
  /* a finite cylinder along the periodic axis */
  w = shell_world(true, false, 0, 0);
  w->walls.planes[0].def.length = 0.02;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "only an infinite cylinder"));
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_shell_across_faces),
      cmocka_unit_test(test_refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
