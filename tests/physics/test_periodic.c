/* Periodic boundaries (docs/architecture.md, "Periodic boundaries"). Claims checked:
 *  - a pair touching through a periodic face feels the same force as the same pair in the middle
 *    of the box, along each axis and through an edge (minimum image; without it the pair across
 *    the face is 0.88 m apart and feels nothing, so the test fails);
 *  - a sphere leaving through a face comes in through the opposite one with its velocity bit for
 *    bit unchanged, and its image counter counts each crossing with its sign;
 *  - a sliding pair carried through a face keeps its tangential history: its force follows, to
 *    round-off, the force of the same pair carried through the middle of the box (checked to
 *    fail: without the minimum image in force_pass.c both the first and this test fail; with the
 *    history dropped for a pair whose centres sit on two sides of the face, this one does). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "adem/adem.h"
#include "adem/vec3.h"
#include "helpers.h"

static adem_world *periodic_world(double E, double mu, unsigned axes, adem_vec3 lo, adem_vec3 hi) {
  adem_world *w = adem_world_create();
  adem_error err;
  assert_true(test_material(w, "glass", E, 0.3, 0.5, mu) == 0);
  adem_world_set_gravity(w, v3_zero());
  adem_world_set_threads(w, 1);
  if (adem_world_set_periodic(w, lo, hi, axes, &err)) fail_msg("%s", err.message);
  return w;
}

static adem_vec3 force_of(const adem_world *w, uint64_t id) {
  size_t n = adem_world_particle_count(w);
  double *f = malloc(3 * n * sizeof *f);
  adem_error err;
  assert_int_equal(adem_world_get_particles(w, ADEM_FIELD_FORCE, f, 3 * n, &err), ADEM_OK);
  adem_vec3 r = v3(f[3 * id], f[3 * id + 1], f[3 * id + 2]);
  free(f);
  return r;
}

static double rel_diff(adem_vec3 a, adem_vec3 b) {
  return v3_norm(v3_sub(a, b)) / fmax(v3_norm(b), 1e-300);
}

/* Two spheres of radius 1/16 m at centre distance 30/256 m (overlap 1/128 m) with a sliding and
 * an approaching velocity, at `a` and `a + sep`; 40 steps. Returns the force history on id 0. */
static void run_pair(adem_vec3 a, adem_vec3 sep, adem_vec3 *force, int steps) {
  adem_world *w = periodic_world(1e6, 0.5, 7u, v3(0, 0, 0), v3(1, 1, 1));
  adem_world_set_initial_overlap(w, 0.2);
  adem_vec3 u = v3_scale(sep, 1.0 / v3_norm(sep));
  adem_vec3 t = v3(u.y - u.z, u.z - u.x, u.x - u.y); /* perpendicular to u */
  test_particle(w, 0, a, v3_add(v3_scale(u, 0.01), v3_scale(t, 0.02)), 0.0625);
  test_particle(w, 0, v3_add(a, sep), v3_scale(u, -0.01), 0.0625);
  adem_world_set_dt(w, 1e-5);
  adem_error err;
  if (adem_world_prepare(w, &err)) fail_msg("%s", err.message);
  for (int s = 0; s < steps; ++s) {
    force[s] = force_of(w, 0);
    if (adem_world_step(w, 1, &err)) fail_msg("%s", err.message);
  }
  adem_world_free(w);
}

/* Across the x, y and z faces and through the x-y edge, against the pair in the middle. The
 * positions are dyadic, so the first force is bit for bit equal; afterwards the centres move by
 * non-dyadic amounts near 1 m instead of near 0.5 m, which changes round-off in the overlap
 * (1e-3 m) by about 2e-16 m / 1e-3 = 2e-13 relative: 1e-12 bounds it. */
static void test_force_across_faces(void **state) {
  (void)state;
  enum { STEPS = 40 };
  const double s = 30.0 / 256.0, h = s / 2.0;
  const adem_vec3 seps[4] = {v3(s, 0, 0), v3(0, s, 0), v3(0, 0, s),
                             v3(s / sqrt(2.0), s / sqrt(2.0), 0)};
  const char *names[4] = {"x face", "y face", "z face", "x-y edge"};
  for (int k = 0; k < 4; ++k) {
    adem_vec3 f_mid[STEPS], f_face[STEPS];
    adem_vec3 mid = v3_sub(v3(0.5, 0.5, 0.5), v3_scale(seps[k], 0.5));
    run_pair(mid, seps[k], f_mid, STEPS);
    /* the same pair with its first sphere just inside the upper faces, the second across them */
    adem_vec3 a = v3(seps[k].x > 0 ? 1.0 - h : 0.5, seps[k].y > 0 ? 1.0 - h : 0.5,
                     seps[k].z > 0 ? 1.0 - h : 0.5);
    if (k == 3) a = v3(1.0 - seps[k].x / 2.0, 1.0 - seps[k].y / 2.0, 0.5);
    run_pair(a, seps[k], f_face, STEPS);
    double worst = 0.0;
    for (int i = 0; i < STEPS; ++i) worst = fmax(worst, rel_diff(f_face[i], f_mid[i]));
    printf("# %-8s |F| %.6g N at the start, %.6g N at the end; largest relative difference %.3g\n",
           names[k], v3_norm(f_mid[0]), v3_norm(f_mid[STEPS - 1]), worst);
    assert_true(v3_norm(f_mid[0]) > 1.0); /* a real contact */
    assert_true(rel_diff(f_face[0], f_mid[0]) < 1e-12);
    assert_true(worst < 1e-12);
  }
}

/* One sphere of radius 0.05 m in a box periodic in x and y, 0.3 m long: at 3 m/s along +x and
 * -1 m/s along y for 0.3 s it travels 0.9 m = 3 box lengths along x and 1 along -y. */
static void test_sphere_through_faces(void **state) {
  (void)state;
  adem_world *w = periodic_world(1e7, 0.5, ADEM_PERIODIC_X | ADEM_PERIODIC_Y, v3(0, 0, 0),
                                 v3(0.3, 0.3, 0.3));
  adem_vec3 v0 = v3(3.0, -1.0, 0.0), x0 = v3(0.25, 0.1, 0.15);
  test_particle(w, 0, x0, v0, 0.05);
  adem_world_set_dt(w, 1e-4);
  adem_error err;
  if (adem_world_prepare(w, &err)) fail_msg("%s", err.message);
  int32_t im[3];
  double x[3], v[3];
  /* first crossing of x = 0.3: after (0.3 - 0.25) / 3 s, 167 steps; the wrap comes at the next
   * neighbour build, within skin / 2 = 0.01 m of travel */
  if (adem_world_step(w, 200, &err)) fail_msg("%s", err.message);
  assert_int_equal(adem_world_get_particles(w, ADEM_FIELD_POSITION, x, 3, &err), ADEM_OK);
  assert_int_equal(adem_world_particle_image(w, 0, im, &err), ADEM_OK);
  printf("# after 200 steps: x = %.6g m, image (%d, %d, %d)\n", x[0], im[0], im[1], im[2]);
  assert_int_equal(im[0], 1);
  assert_true(x[0] < 0.1); /* came in through the lower face */
  if (adem_world_step(w, 2800, &err)) fail_msg("%s", err.message);
  assert_int_equal(adem_world_get_particles(w, ADEM_FIELD_POSITION, x, 3, &err), ADEM_OK);
  assert_int_equal(adem_world_get_particles(w, ADEM_FIELD_VELOCITY, v, 3, &err), ADEM_OK);
  assert_int_equal(adem_world_particle_image(w, 0, im, &err), ADEM_OK);
  /* the unwrapped centre: x0 + v t, to the round-off of 3000 drifts near 1 m (1e-12 m) */
  double ux = x[0] + im[0] * 0.3, uy = x[1] + im[1] * 0.3;
  printf("# after 3000 steps: (%.9g, %.9g) m, image (%d, %d, %d), unwrapped (%.12g, %.12g), "
         "velocity (%.17g, %.17g)\n",
         x[0], x[1], im[0], im[1], im[2], ux, uy, v[0], v[1]);
  assert_int_equal(im[0], 3);
  assert_int_equal(im[1], -1);
  assert_int_equal(im[2], 0);
  assert_true(fabs(ux - (0.25 + 0.9)) < 1e-9);
  assert_true(fabs(uy - (0.1 - 0.3)) < 1e-9);
  assert_true(v[0] == v0.x && v[1] == v0.y && v[2] == v0.z); /* nothing touched it */
  adem_world_free(w);
}

/* A soft pair (E = 1e5 Pa, mu = 0.5) in a slow collision (t_c about 0.1 s) with a sliding
 * velocity, both carried along x at 1 m/s: through the face x = 1 (run at x0 = 0.9) and through
 * the middle (x0 = 0.4). The crossing comes 0.1 s into the contact. Returns the contact force
 * and the tangential history of every step. */
static int carried_pair(double x0, adem_vec3 *force, adem_vec3 *hist, int32_t *image, int steps) {
  adem_world *w = periodic_world(1e5, 0.5, ADEM_PERIODIC_X, v3(0, 0, 0), v3(1, 1, 1));
  const double r = 0.05;
  /* touching, the centre line tilted in x: for 0.03 / 1 m/s = 0.03 s one centre is across the
   * face and the other not, so the pair needs the minimum image as well as its history */
  double dx = 0.03, dz = sqrt(4.0 * r * r - dx * dx);
  test_particle(w, 0, v3(x0, 0.5, 0.5 - dz / 2), v3(1.0, 0.01, 0.005), r);
  test_particle(w, 0, v3(x0 + dx, 0.5, 0.5 + dz / 2), v3(1.0, -0.01, -0.005), r);
  adem_world_set_dt(w, 2e-4);
  adem_error err;
  if (adem_world_prepare(w, &err)) fail_msg("%s", err.message);
  int touching = 0;
  for (int s = 0; s < steps; ++s) {
    if (adem_world_step(w, 1, &err)) fail_msg("%s", err.message);
    adem_contact_info c;
    force[s] = hist[s] = v3_zero();
    if (adem_world_contacts(w, &c, 1) == 1) {
      force[s] = c.force;
      hist[s] = c.tangential_history;
      touching++;
    }
  }
  assert_int_equal(adem_world_particle_image(w, 0, image, &err), ADEM_OK);
  adem_world_free(w);
  return touching;
}

static void test_history_through_face(void **state) {
  (void)state;
  enum { STEPS = 1000 };
  static adem_vec3 f_face[STEPS], h_face[STEPS], f_mid[STEPS], h_mid[STEPS];
  int32_t im_face[3], im_mid[3];
  int n_face = carried_pair(0.9, f_face, h_face, im_face, STEPS);
  int n_mid = carried_pair(0.4, f_mid, h_mid, im_mid, STEPS);
  /* the step at which the pair's centre line passes x = 1 */
  int cross = (int)ceil(0.1 / 2e-4);
  double worst = 0.0, fmax_mid = 0.0;
  for (int s = 0; s < STEPS; ++s) {
    fmax_mid = fmax(fmax_mid, v3_norm(f_mid[s]));
    worst = fmax(worst, v3_norm(v3_sub(f_face[s], f_mid[s])));
  }
  printf("# contact %d / %d steps (face / middle), image x %d / %d; at the crossing (step %d): "
         "|F| %.6g N, |tangential history| %.6g N; largest |F_face - F_mid| %.3g N of max |F| "
         "%.6g N\n",
         n_face, n_mid, im_face[0], im_mid[0], cross, v3_norm(f_face[cross]),
         v3_norm(h_face[cross]), worst, fmax_mid);
  assert_int_equal(n_face, n_mid);
  assert_true(n_face > cross + 50); /* the pair still touches well after the crossing */
  assert_int_equal(im_face[0], 1);  /* and did cross */
  assert_int_equal(im_mid[0], 0);
  assert_true(v3_norm(h_face[cross]) > 0.05 * fmax_mid); /* a loaded tangential spring */
  /* round-off of centres near 1 m instead of 0.5 m on an overlap of about 1e-3 m: 1e-12 of
   * the peak force, accumulated over 1000 steps, stays below 1e-9 of it; dropping the history
   * at the wrap would make an error of the size of the spring force, 0.05 of the peak at least */
  assert_true(worst < 1e-9 * fmax_mid);
  for (int s = cross - 3; s <= cross + 3; ++s)
    assert_true(v3_norm(v3_sub(h_face[s], h_mid[s])) < 1e-9 * fmax_mid);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_force_across_faces),
      cmocka_unit_test(test_sphere_through_faces),
      cmocka_unit_test(test_history_through_face),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
