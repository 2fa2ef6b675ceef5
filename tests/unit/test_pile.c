/* Pile measurement (src/studies/pile.c) on synthetic cones of spheres of known slope: both
 * methods must give the cone's angle within 0.5 degrees, and a cone of another angle must not be
 * reported as 30 or 40 degrees. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>
#include <math.h>

#include "adem/pile.h"

static const double PI = 3.14159265358979323846;

/* Tolerances of the laboratory angle and the ring-top line on synthetic cones, from the survey
 * of test_lab_survey (ADEM_PILE_SURVEY=20: bias, sd, worst over seeds 1..20, 30/40/48 deg):
 *   base 1.2 m (24 d): lab -0.72/-0.67/-0.43, sd 0.22-0.36, worst 1.25; ring-top -0.14..-0.22,
 *                      sd 0.09-0.12, worst 0.39; surface +0.05..+0.10, slices +0.03..+0.04
 *   base 0.55 m (11 d, the case's full pile): lab -0.83..-0.92, sd 0.82-0.99, worst 2.61;
 *                      ring-top -0.65..-0.85, sd 0.54-0.70, worst 2.54
 * The laboratory angle reads low because spheres cannot fill a sharp apex: the highest top is
 * about half a diameter under the cone's apex (a real pile's cap is rounded, and a laboratory
 * reads its real top). Hence a window around the measured bias at 24 d: [-1.5, +0.5]. Perturbed
 * once, atan(H / R_base) in place of atan((H - h_e) / R_base) (the skirt level left in the
 * height), gave 31.28, 31.39, 32.01 at 30 deg and 40.79, 40.59 at 40 deg: FAIL. */
#define LAB_LO_BIG (-1.5)
#define LAB_HI_BIG 0.5
#define RING_TOL_BIG 0.6
#define LAB_TOL_SMALL 3.0
#define RING_TOL_SMALL 3.0

/* splitmix64: a small seeded generator, the same numbers on every platform. */
static uint64_t rng_next(uint64_t *s) {
  uint64_t z = (*s += UINT64_C(0x9E3779B97F4A7C15));
  z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
  z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
  return z ^ (z >> 31);
}
static double rng_uniform(uint64_t *s) { return (double)(rng_next(s) >> 11) * 0x1.0p-53; }

/* A cone of spheres on the floor z = 0 with its axis through (cx, cy): base radius base_r, slope
 * angle_deg. Spheres sit on a face-centred cubic lattice (nearest neighbours 1.1 d apart) turned
 * by a random rotation and shifted at random, so that no lattice plane lies along the floor or
 * the slope; each is moved by up to 0.06 d along each axis and given a radius in [0.4 d, 0.44 d]:
 * dense (solid fraction about 0.5), irregular, and never overlapping (0.88 d + 2 sqrt(3) 0.06 d
 * < 1.1 d). A sphere is kept when its centre is above r and below the cone surface
 * z = (base_r - rho) tan(angle). */
typedef struct cone {
  adem_vec3 *pos;
  double *radius;
  size_t n;
} cone;

static cone make_cone(double angle_deg, double base_r, double d, double cx, double cy,
                      uint64_t seed) {
  uint64_t s = seed;
  double t = tan(angle_deg * PI / 180.0), height = base_r * t;
  double a = 1.1 * d * sqrt(2.0); /* cubic cell of an FCC lattice with neighbours 1.1 d apart */
  /* a uniformly random rotation (unit quaternion, Shoemake 1992) */
  double u1 = rng_uniform(&s), u2 = 2.0 * PI * rng_uniform(&s), u3 = 2.0 * PI * rng_uniform(&s);
  double qw = sqrt(1.0 - u1) * sin(u2), qx = sqrt(1.0 - u1) * cos(u2), qy = sqrt(u1) * sin(u3),
         qz = sqrt(u1) * cos(u3);
  double R[3][3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)},
                    {2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)},
                    {2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)}};
  double o[3] = {a * rng_uniform(&s), a * rng_uniform(&s), a * rng_uniform(&s)};
  static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  double half = (base_r > height ? base_r : height) + 2.0 * a; /* a cube that holds the cone */
  int m = (int)ceil(half / a);
  size_t cap = (size_t)(2 * m + 1) * (size_t)(2 * m + 1) * (size_t)(2 * m + 1) * 4;
  cone c = {malloc(cap * sizeof(adem_vec3)), malloc(cap * sizeof(double)), 0};
  assert_non_null(c.pos);
  assert_non_null(c.radius);
  for (int k = -m; k <= m; ++k)
    for (int j = -m; j <= m; ++j)
      for (int i = -m; i <= m; ++i)
        for (int b = 0; b < 4; ++b) {
          double l[3] = {(i + basis[b][0]) * a + o[0], (j + basis[b][1]) * a + o[1],
                         (k + basis[b][2]) * a + o[2]};
          double x = R[0][0] * l[0] + R[0][1] * l[1] + R[0][2] * l[2];
          double y = R[1][0] * l[0] + R[1][1] * l[1] + R[1][2] * l[2];
          double z = R[2][0] * l[0] + R[2][1] * l[1] + R[2][2] * l[2] + 0.5 * height;
          x += 0.06 * d * (2.0 * rng_uniform(&s) - 1.0);
          y += 0.06 * d * (2.0 * rng_uniform(&s) - 1.0);
          z += 0.06 * d * (2.0 * rng_uniform(&s) - 1.0);
          double r = d * (0.4 + 0.04 * rng_uniform(&s));
          double rho = sqrt(x * x + y * y);
          if (z < r || z > (base_r - rho) * t) continue;
          c.pos[c.n] = (adem_vec3){x + cx, y + cy, z};
          c.radius[c.n] = r;
          c.n++;
        }
  return c;
}

static void free_cone(cone *c) {
  free(c->pos);
  free(c->radius);
}

static adem_pile_result measure(const cone *c, const adem_pile_options *o) {
  adem_pile_result r;
  adem_error err = {0};
  adem_status st = adem_pile_measure(c->pos, c->radius, c->n, o, &r, &err);
  if (st) fail_msg("adem_pile_measure: %s", err.message);
  printf("# %zu spheres: H %.3f m, base %.3f m, surface %.2f deg (R2 %.4f, %zu), slices %.2f deg "
         "(R2 %.4f, %zu)\n",
         c->n, r.height, r.base_radius, r.angle_surface_deg, r.surface.r2,
         r.surface.n, r.angle_slices_deg, r.slices.r2, r.slices.n);
  return r;
}

/* Claim: on cones of 30 and 40 degrees (spheres of 0.05 m, base 24 diameters wide) both methods
 * are within 0.5 degrees of the cone's angle, for three seeds each, and fit well. Over seeds
 * 1..40 the largest deviation is 0.44 degrees (surface fit, 30 degrees); on a cone 15 diameters
 * wide, the size of the repose case's pile, the standard deviation per pile is 0.3 to 0.4
 * degrees for either method (cases/irazabal/REPOSE-NOTES.md). */
static void test_known_cones(void **state) {
  (void)state;
  const double angles[2] = {30.0, 40.0};
  for (int a = 0; a < 2; ++a)
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      cone c = make_cone(angles[a], 1.2, 0.05, 0.0, 0.0, seed);
      adem_pile_options o = adem_pile_default_options();
      adem_pile_result r = measure(&c, &o);
      assert_true(fabs(r.angle_surface_deg - angles[a]) < 0.5);
      assert_true(fabs(r.angle_slices_deg - angles[a]) < 0.5);
      assert_true(r.surface.r2 > 0.95 && r.slices.r2 > 0.99);
      adem_pile_result_free(&r);
      /* sqrt(A / pi) instead of the mean radius: 0.2 degrees steeper on average at this size (up
       * to 0.54 over seeds 1..40), hence the wider tolerance; see slice_req in pile.c */
      o.slice_radius = ADEM_PILE_AREA_RADIUS;
      r = measure(&c, &o);
      assert_true(fabs(r.angle_slices_deg - angles[a]) < 0.75);
      adem_pile_result_free(&r);
      free_cone(&c);
    }
}

/* Claim: a 35-degree cone is measured as 35 (within 0.5) by both methods, so it is reported
 * neither as 30 nor as 40: the measurement follows the input instead of returning a constant. */
static void test_other_angle_is_not_30_or_40(void **state) {
  (void)state;
  cone c = make_cone(35.0, 1.2, 0.05, 0.0, 0.0, 7);
  adem_pile_options o = adem_pile_default_options();
  adem_pile_result r = measure(&c, &o);
  assert_true(fabs(r.angle_surface_deg - 35.0) < 0.5 && fabs(r.angle_slices_deg - 35.0) < 0.5);
  assert_true(fabs(r.angle_surface_deg - 30.0) > 4.0 && fabs(r.angle_surface_deg - 40.0) > 4.0);
  assert_true(fabs(r.angle_slices_deg - 30.0) > 4.0 && fabs(r.angle_slices_deg - 40.0) > 4.0);
  adem_pile_result_free(&r);
  free_cone(&c);
}

/* Claim: the height and the base radius of the fitted cone come out of the construction within
 * a diameter, and an off-centre pile is found by its centroid as well as with its axis given. */
static void test_height_base_axis(void **state) {
  (void)state;
  const double base = 1.2, d = 0.05, t = tan(40.0 * PI / 180.0);
  cone c = make_cone(40.0, base, d, 0.3, -0.2, 11);
  adem_pile_options o = adem_pile_default_options();
  adem_pile_result r = measure(&c, &o);
  assert_true(fabs(r.axis_x - 0.3) < 0.02 && fabs(r.axis_y + 0.2) < 0.02);
  assert_true(fabs(r.height - base * t) < d);
  assert_true(fabs(r.base_radius - base) < d);
  assert_true(fabs(r.angle_surface_deg - 40.0) < 0.5 && fabs(r.angle_slices_deg - 40.0) < 0.5);
  adem_pile_result_free(&r);
  o.axis_given = 1;
  o.axis_x = 0.3;
  o.axis_y = -0.2;
  r = measure(&c, &o);
  assert_true(fabs(r.angle_surface_deg - 40.0) < 0.5 && fabs(r.angle_slices_deg - 40.0) < 0.5);
  adem_pile_result_free(&r);
  free_cone(&c);
}

/* Claim: spheres that are not the pile do not change the angle: a few that rolled away on the
 * floor are below the fit band, and spheres left in a hopper above are cut off by zmax. */
static void test_strays(void **state) {
  (void)state;
  cone c = make_cone(40.0, 1.2, 0.05, 0.0, 0.0, 5);
  adem_vec3 *pos = realloc(c.pos, (c.n + 40) * sizeof *pos);
  double *rad = realloc(c.radius, (c.n + 40) * sizeof *rad);
  assert_non_null(pos);
  assert_non_null(rad);
  c.pos = pos;
  c.radius = rad;
  for (int k = 0; k < 20; ++k) { /* rolled away: one layer on the floor out to 1.9 m */
    double phi = 0.9 * k;
    c.pos[c.n] = (adem_vec3){(1.4 + 0.025 * k) * cos(phi), (1.4 + 0.025 * k) * sin(phi), 0.021};
    c.radius[c.n++] = 0.021;
  }
  for (int k = 0; k < 20; ++k) { /* in a hopper whose outlet is at 1.2 m */
    c.pos[c.n] = (adem_vec3){0.05 * (k % 5) - 0.1, 0.05 * (k / 5) - 0.1, 1.25 + 0.01 * k};
    c.radius[c.n++] = 0.021;
  }
  adem_pile_options o = adem_pile_default_options();
  o.zmax = 1.2;
  o.axis_given = 1;
  adem_pile_result r = measure(&c, &o);
  assert_true(fabs(r.angle_surface_deg - 40.0) < 0.5 && fabs(r.angle_slices_deg - 40.0) < 0.5);
  adem_pile_result_free(&r);
  free_cone(&c);
}

/* Claim: unusable input is refused with ADEM_ERR_INPUT and a message, never measured: no
 * particles, a NaN centre, a zero radius, a flat layer (no pile), a bad band. */
static void test_bad_input(void **state) {
  (void)state;
  adem_pile_result r;
  adem_error err = {0};
  adem_pile_options o = adem_pile_default_options();
  assert_int_equal(adem_pile_measure(NULL, NULL, 0, &o, &r, &err), ADEM_ERR_INPUT);
  adem_vec3 p[64];
  double rad[64];
  for (int i = 0; i < 64; ++i) { /* one flat layer: 8 x 8 spheres on the floor */
    p[i] = (adem_vec3){0.05 * (i % 8), 0.05 * (i / 8), 0.025};
    rad[i] = 0.025;
  }
  assert_int_equal(adem_pile_measure(p, rad, 64, &o, &r, &err), ADEM_ERR_INPUT);
  printf("# flat layer: %s\n", err.message);
  p[3].x = NAN;
  assert_int_equal(adem_pile_measure(p, rad, 64, &o, &r, &err), ADEM_ERR_INPUT);
  p[3].x = 0.15;
  rad[5] = 0.0;
  assert_int_equal(adem_pile_measure(p, rad, 64, &o, &r, &err), ADEM_ERR_INPUT);
  rad[5] = 0.025;
  o.band_lo = 0.8;
  o.band_hi = 0.2;
  assert_int_equal(adem_pile_measure(p, rad, 64, &o, &r, &err), ADEM_ERR_INPUT);
  printf("# bad band: %s\n", err.message);
  assert_null(r.surface_pts);
}

/* A skirt of spheres that rolled away: n spheres of radius 0.4..0.44 d lying on the floor
 * between rho_in and rho_out, no two overlapping (dense near rho_in when n is large). */
static void add_skirt(cone *c, size_t n, double rho_in, double rho_out, double d, uint64_t seed) {
  uint64_t s = seed;
  adem_vec3 *pos = realloc(c->pos, (c->n + n) * sizeof *pos);
  double *rad = realloc(c->radius, (c->n + n) * sizeof *rad);
  assert_non_null(pos);
  assert_non_null(rad);
  c->pos = pos;
  c->radius = rad;
  size_t first = c->n, tries = 0;
  while (c->n < first + n && tries++ < 200000 * n) {
    double r = d * (0.4 + 0.04 * rng_uniform(&s));
    double rho = rho_in + (rho_out - rho_in) * rng_uniform(&s), phi = 2.0 * PI * rng_uniform(&s);
    adem_vec3 p = {rho * cos(phi), rho * sin(phi), r};
    int ok = 1;
    for (size_t j = 0; j < c->n && ok; ++j) { /* clear of the cone and of the skirt so far */
      double dx = p.x - c->pos[j].x, dy = p.y - c->pos[j].y, dz = p.z - c->pos[j].z;
      ok = dx * dx + dy * dy + dz * dz >= (r + c->radius[j]) * (r + c->radius[j]);
    }
    if (!ok) continue;
    c->pos[c->n] = p;
    c->radius[c->n++] = r;
  }
  assert_int_equal(c->n, first + n);
}

/* Claim: on cones of 30, 40 and 48 degrees the laboratory angle and the ring-top line give the
 * cone's angle: base 1.2 m (24 diameters), three seeds each, lab within -1.5..+0.5 degrees
 * (its apex bias, above), ring-top within 0.6; base 0.55 m (the case's full pile, 11
 * diameters), both within 3.0 (one pile's resolution there: sd 0.5-1.0). */
static void test_lab_and_ringtop_cones(void **state) {
  (void)state;
  const double angles[3] = {30.0, 40.0, 48.0};
  for (int a = 0; a < 3; ++a)
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      cone c = make_cone(angles[a], 1.2, 0.05, 0.0, 0.0, seed);
      adem_pile_options o = adem_pile_default_options();
      adem_pile_result r = measure(&c, &o);
      printf("#   lab %.2f (plain %.2f, h_e %.4f, R_base %.4f sd %.4f, %zu rings), ring-top %.2f "
             "(R2 %.3f, %zu), footprint %.2f\n",
             r.angle_lab_deg, r.angle_lab_plain_deg,
             r.skirt_level, r.lab_base_radius, r.lab_base_sd, r.base_rings, r.angle_ringtop_deg,
             r.ringtop.r2, r.ringtop.n, r.angle_footprint_deg);
      assert_true(r.angle_lab_deg - angles[a] > LAB_LO_BIG && r.angle_lab_deg - angles[a] < LAB_HI_BIG);
      assert_true(fabs(r.angle_ringtop_deg - angles[a]) < RING_TOL_BIG);
      adem_pile_result_free(&r);
      free_cone(&c);
      c = make_cone(angles[a], 0.55, 0.05, 0.0, 0.0, seed);
      r = measure(&c, &o);
      printf("#   lab %.2f, ring-top %.2f (%zu rings)\n", r.angle_lab_deg, r.angle_ringtop_deg,
             r.ringtop.n);
      assert_true(fabs(r.angle_lab_deg - angles[a]) < LAB_TOL_SMALL);
      assert_true(fabs(r.angle_ringtop_deg - angles[a]) < RING_TOL_SMALL);
      adem_pile_result_free(&r);
      free_cone(&c);
    }
}

/* Claim: a skirt of spheres that rolled away does not move the laboratory angle: 300 spheres
 * lying on the floor around a 40-degree cone, packed against its toe and out to twice its base
 * radius, change the laboratory angle by less than 0.05 degrees (axis given, so that only the
 * base's definition is tested), while height over footprint, which counts them, falls by more
 * than 5 degrees. */
static void test_lab_ignores_skirt(void **state) {
  (void)state;
  cone c = make_cone(40.0, 0.8, 0.05, 0.0, 0.0, 3);
  adem_pile_options o = adem_pile_default_options();
  o.axis_given = 1;
  o.bin_width = 0.05; /* the ring width of the clean cone, which the skirt would change a little */
  adem_pile_result r0 = measure(&c, &o);
  add_skirt(&c, 300, 0.8, 1.6, 0.05, 99);
  adem_pile_result r1 = measure(&c, &o);
  printf("# skirt: lab %.3f -> %.3f deg, ring-top %.3f -> %.3f, footprint %.2f -> %.2f\n",
         r0.angle_lab_deg, r1.angle_lab_deg, r0.angle_ringtop_deg, r1.angle_ringtop_deg,
         r0.angle_footprint_deg, r1.angle_footprint_deg);
  assert_true(fabs(r1.angle_lab_deg - r0.angle_lab_deg) < 0.05);
  assert_true(fabs(r1.angle_ringtop_deg - r0.angle_ringtop_deg) < 0.05);
  assert_true(r1.angle_lab_deg - 40.0 > LAB_LO_BIG && r1.angle_lab_deg - 40.0 < LAB_HI_BIG);
  assert_true(r0.angle_footprint_deg - r1.angle_footprint_deg > 5.0);
  adem_pile_result_free(&r0);
  adem_pile_result_free(&r1);
  free_cone(&c);
}

/* Not a test: with ADEM_PILE_SURVEY=N set, the bias, sd and worst deviation of every measure over
 * seeds 1..N, for the tolerances above. */
static void test_lab_survey(void **state) {
  (void)state;
  const char *e = getenv("ADEM_PILE_SURVEY");
  if (!e) return;
  int ns = atoi(e);
  const double angles[3] = {30.0, 40.0, 48.0}, bases[2] = {1.2, 0.55};
  for (int b = 0; b < 2; ++b)
    for (int a = 0; a < 3; ++a) {
      double s[4] = {0}, s2[4] = {0}, worst[4] = {0};
      for (int seed = 1; seed <= ns; ++seed) {
        cone c = make_cone(angles[a], bases[b], 0.05, 0.0, 0.0, (uint64_t)seed);
        adem_pile_options o = adem_pile_default_options();
        adem_pile_result r;
        adem_error err = {0};
        assert_int_equal(adem_pile_measure(c.pos, c.radius, c.n, &o, &r, &err), ADEM_OK);
        double v[4] = {r.angle_lab_deg, r.angle_ringtop_deg, r.angle_surface_deg,
                       r.angle_slices_deg};
        for (int k = 0; k < 4; ++k) {
          double dv = v[k] - angles[a];
          s[k] += dv;
          s2[k] += dv * dv;
          if (fabs(dv) > worst[k]) worst[k] = fabs(dv);
        }
        adem_pile_result_free(&r);
        free_cone(&c);
      }
      printf("# survey %g deg base %.2f m, %d seeds: bias/sd/worst lab %+.2f %.2f %.2f, ring-top "
             "%+.2f %.2f %.2f, surface %+.2f %.2f %.2f, slices %+.2f %.2f %.2f\n",
             angles[a],
             bases[b], ns, s[0] / ns, sqrt(s2[0] / ns - (s[0] / ns) * (s[0] / ns)), worst[0],
             s[1] / ns, sqrt(s2[1] / ns - (s[1] / ns) * (s[1] / ns)), worst[1], s[2] / ns,
             sqrt(s2[2] / ns - (s[2] / ns) * (s[2] / ns)), worst[2], s[3] / ns,
             sqrt(s2[3] / ns - (s[3] / ns) * (s[3] / ns)), worst[3]);
    }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_known_cones),
      cmocka_unit_test(test_other_angle_is_not_30_or_40),
      cmocka_unit_test(test_height_base_axis),
      cmocka_unit_test(test_strays),
      cmocka_unit_test(test_bad_input),
      cmocka_unit_test(test_lab_and_ringtop_cones),
      cmocka_unit_test(test_lab_ignores_skirt),
      cmocka_unit_test(test_lab_survey),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
