/* Insertion (src/input/insert_*.c) through case files: random fills of a box, a cylinder and a closed STL
 * volume (an L-shaped prism, not convex) give exactly the count asked, never overlap, keep every
 * sphere inside its region and clear of the walls, reach a solid fraction within half a sphere,
 * repeat bit for bit for a seed and differ for another; the five size distributions have the
 * stated mean and spread; bad regions and distributions are refused with their key path. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>
#include <unistd.h>

#include "adem/adem.h"
#include "insert.h"
#include "log_capture.h"
#include "tmpdir.h"
#include "world_internal.h"

/* An L-shaped prism, 2 x 2 x 1 units: the polygon (0,0) (2,0) (2,1) (1,1) (1,2) (0,2) (0,1)
 * extruded over z in [0, 1], closed, outward normals. */
static void write_l_prism(const char *path) {
  static const double poly[7][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 1}};
  static const int cap[5][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 6}, {6, 3, 4}, {6, 4, 5}};
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fprintf(f, "solid l\n");
#define TRI(ax, ay, az, bx, by, bz, cx, cy, cz)                                                    \
  fprintf(f, "facet normal 0 0 0\nouter loop\nvertex %g %g %g\nvertex %g %g %g\nvertex %g %g %g\n" \
             "endloop\nendfacet\n",                                                                \
          ax, ay, az, bx, by, bz, cx, cy, cz)
  for (int k = 0; k < 5; ++k) {
    const double *a = poly[cap[k][0]], *b = poly[cap[k][1]], *c = poly[cap[k][2]];
    TRI(a[0], a[1], 1.0, b[0], b[1], 1.0, c[0], c[1], 1.0); /* top, counter-clockwise */
    TRI(a[0], a[1], 0.0, c[0], c[1], 0.0, b[0], b[1], 0.0); /* bottom, reversed */
  }
  for (int k = 0; k < 7; ++k) {
    const double *a = poly[k], *b = poly[(k + 1) % 7];
    TRI(a[0], a[1], 0.0, b[0], b[1], 0.0, b[0], b[1], 1.0);
    TRI(a[0], a[1], 0.0, b[0], b[1], 1.0, a[0], a[1], 1.0);
  }
#undef TRI
  fprintf(f, "endsolid l\n");
  fclose(f);
}

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_insert")) return -1;
  char path[512];
  snprintf(path, sizeof path, "%s/l.stl", tmpdir);
  write_l_prism(path);
  snprintf(path, sizeof path, "%s/plate.stl", tmpdir);
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fprintf(f, "solid plate\nfacet normal 0 0 1\nouter loop\nvertex -0.01 -0.01 0.01\nvertex 0.03 -0.01 "
             "0.01\nvertex 0.03 0.03 0.01\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex "
             "-0.01 -0.01 0.01\nvertex 0.03 0.03 0.01\nvertex -0.01 0.03 0.01\nendloop\nendfacet\n"
             "endsolid plate\n");
  fclose(f);
  snprintf(path, sizeof path, "%s/open.stl", tmpdir);
  f = fopen(path, "w");
  if (!f) return -1;
  fprintf(f, "solid open\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
             "endloop\nendfacet\nendsolid open\n");
  fclose(f);
  adem_log_set_hook(capture, NULL);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  adem_log_set_hook(NULL, NULL);
  return tmpdir_remove();
}

/* A case with one random set: the given region keys, radius, count line and seed. */
static adem_case *load_fill(const char *region, const char *radius, const char *amount,
                            unsigned seed, const char *extra_walls, adem_error *err) {
  char text[4096];
  snprintf(text, sizeof text,
           "seed: %u\n"
           "materials:\n"
           "  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}\n"
           "  - {name: steel, rigid: true}\n"
           "particles:\n"
           "  - type: random\n"
           "    material: glass\n"
           "    radius: %s\n"
           "    %s\n"
           "    %s\n"
           "%s"
           "time: {end: 0.1}\n",
           seed, radius, region, amount, extra_walls ? extra_walls : "");
  adem_case *c = NULL;
  char name[300];
  snprintf(name, sizeof name, "%s/fill.yaml", tmpdir);
  adem_case_load_string(text, name, NULL, 0, &c, err);
  return c;
}

static adem_case *must_fill(const char *region, const char *radius, const char *amount,
                            unsigned seed, const char *walls) {
  adem_error err;
  adem_case *c = load_fill(region, radius, amount, seed, walls, &err);
  if (!c) fail_msg("fill does not load: %s", err.message);
  return c;
}

/* Every pair, O(N^2): touching is allowed, overlapping by more than round-off is not. */
static void assert_no_overlap(const adem_particles *p) {
  for (size_t i = 0; i < p->n; ++i)
    for (size_t j = i + 1; j < p->n; ++j) {
      double s = p->radius[i] + p->radius[j];
      double d = v3_norm(v3_sub(p->pos[i], p->pos[j]));
      if (d < s * (1.0 - 1e-12))
        fail_msg("spheres %zu and %zu overlap by %g m", i, j, s - d);
    }
}

/* Claim: a box fill places exactly `count` spheres, none overlapping, all inside the box and
 * clear of a plane that cuts the box; the same seed repeats it bit for bit, another differs. */
static void test_box_fill(void **state) {
  (void)state;
  const char *box = "min: [0, 0, 0]\n    max: [0.02, 0.02, 0.02]";
  const char *radius = "{distribution: uniform, min: 0.0005, max: 0.001}";
  const char *wall = "walls:\n  - {type: plane, name: cut, material: steel, point: [0, 0, 0.005], "
                     "normal: [0, 0, 1]}\n";
  adem_case *a = must_fill(box, radius, "count: 800", 5, wall);
  adem_case *b = must_fill(box, radius, "count: 800", 5, wall);
  adem_case *d = must_fill(box, radius, "count: 800", 6, wall);
  const adem_particles *p = &a->world->p;
  assert_int_equal(p->n, 800);
  assert_int_equal(d->world->p.n, 800);
  assert_memory_equal(p->pos, b->world->p.pos, p->n * sizeof *p->pos);
  assert_memory_equal(p->radius, b->world->p.radius, p->n * sizeof *p->radius);
  assert_true(memcmp(p->pos, d->world->p.pos, p->n * sizeof *p->pos) != 0);
  assert_no_overlap(p);
  double lowest = 1.0;
  for (size_t i = 0; i < p->n; ++i) {
    adem_vec3 x = p->pos[i];
    double r = p->radius[i];
    assert_true(x.x - r >= 0 && x.y - r >= 0 && x.x + r <= 0.02 && x.y + r <= 0.02 &&
                x.z + r <= 0.02);
    lowest = fmin(lowest, x.z - r - 0.005);
  }
  printf("# box fill: 800 spheres, lowest gap to the plane %g m\n", lowest);
  assert_true(lowest >= -1e-9 * 0.001); /* the plane at z = 0.005: round-off only */
  adem_case_free(a);
  adem_case_free(b);
  adem_case_free(d);
}

/* Claim: a fill keeps clear of a mesh wall across its box: every sphere is at least its radius
 * from a plate of two STL triangles at z = 10 mm (a mesh is a surface: only touching counts). */
static void test_fill_clears_mesh(void **state) {
  (void)state;
  char walls[700];
  snprintf(walls, sizeof walls,
           "walls:\n  - {type: mesh, name: plate, material: steel, file: %s/plate.stl}\n", tmpdir);
  adem_case *c = must_fill("min: [0, 0, 0]\n    max: [0.02, 0.02, 0.02]",
                           "{distribution: constant, value: 0.001}", "count: 300", 7, walls);
  const adem_particles *p = &c->world->p;
  assert_int_equal(p->n, 300);
  double worst = INFINITY;
  for (size_t i = 0; i < p->n; ++i) worst = fmin(worst, fabs(p->pos[i].z - 0.01) - p->radius[i]);
  printf("# fill across a mesh plate: smallest clearance %g m\n", worst);
  assert_true(worst >= -1e-9 * 0.001);
  adem_case_free(c);
}

/* Claim: a cylinder fill (axis along x+y, not a coordinate axis) keeps every sphere whole inside:
 * axial position in [r, L - r] and distance from the axis <= R - r. */
static void test_cylinder_fill(void **state) {
  (void)state;
  const char *cyl = "region: {shape: cylinder, start: [0, 0, 0], end: [0.03, 0.03, 0], radius: 0.01}";
  adem_case *c = must_fill(cyl, "{distribution: constant, value: 0.001}", "count: 600", 1, NULL);
  const adem_particles *p = &c->world->p;
  assert_int_equal(p->n, 600);
  assert_no_overlap(p);
  adem_vec3 axis = v3_scale(v3(1, 1, 0), 1.0 / sqrt(2.0));
  double L = 0.03 * sqrt(2.0), worst = INFINITY;
  for (size_t i = 0; i < p->n; ++i) {
    double s = v3_dot(p->pos[i], axis);
    adem_vec3 radial = v3_axpy(p->pos[i], -s, axis);
    double r = p->radius[i];
    worst = fmin(worst, fmin(fmin(s - r, L - r - s), 0.01 - r - v3_norm(radial)));
  }
  printf("# cylinder: smallest clearance to the surface %g m\n", worst);
  assert_true(worst >= -1e-12);
  adem_case_free(c);
}

/* Distance from x to the boundary of the L prism (scaled by 0.01) when inside, else -1. */
static double l_clearance(adem_vec3 x) {
  double u = x.x / 0.01, v = x.y / 0.01, w = x.z / 0.01;
  bool in_a = u > 0 && u < 2 && v > 0 && v<1, in_b = u> 0 && u < 1 && v > 0 && v < 2;
  if (!(in_a || in_b) || w <= 0 || w >= 1) return -1.0;
  static const double poly[7][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 1}};
  double d = fmin(w, 1 - w);
  for (int k = 0; k < 7; ++k) {
    double ax = poly[k][0], ay = poly[k][1], bx = poly[(k + 1) % 7][0], by = poly[(k + 1) % 7][1];
    double ex = bx - ax, ey = by - ay;
    double t = ((u - ax) * ex + (v - ay) * ey) / (ex * ex + ey * ey);
    t = t < 0 ? 0 : t > 1 ? 1
                          : t;
    d = fmin(d, hypot(u - ax - t * ex, v - ay - t * ey));
  }
  return 0.01 * d;
}

/* Claim: a fill of a closed, non-convex STL volume (the L prism) keeps every sphere inside it at
 * least its radius from the surface (checked against the exact L geometry), including none in
 * the missing quarter of the bounding box; the region's volume is the prism's, 3e-6 m^3. */
static void test_mesh_fill(void **state) {
  (void)state;
  char region[600];
  snprintf(region, sizeof region, "region: {shape: mesh, file: %s/l.stl, scale: 0.01}", tmpdir);
  adem_case *c = must_fill(region, "{distribution: uniform, min: 0.0006, max: 0.0009}",
                           "count: 500", 2, NULL);
  const adem_particles *p = &c->world->p;
  assert_int_equal(p->n, 500);
  assert_no_overlap(p);
  double worst = INFINITY;
  size_t in_corner = 0;
  for (size_t i = 0; i < p->n; ++i) {
    worst = fmin(worst, l_clearance(p->pos[i]) - p->radius[i]);
    in_corner += p->pos[i].x > 0.01 && p->pos[i].y > 0.01;
  }
  printf("# L prism: smallest clearance %g m, %zu centres in the missing quarter\n", worst, in_corner);
  assert_true(worst >= -1e-12);
  assert_int_equal(in_corner, 0);
  adem_region r;
  adem_error err;
  char path[512];
  snprintf(path, sizeof path, "%s/l.stl", tmpdir);
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.scale = 0.01;
  assert_int_equal(adem_insert_region_mesh(&r, path, &tf, &err), ADEM_OK);
  assert_float_equal(r.volume, 3e-6, 1e-15);
  /* points: inside each arm, in the missing corner, above, below */
  assert_true(adem_insert_region_holds(&r, v3(0.015, 0.005, 0.005), 0.001));
  assert_true(adem_insert_region_holds(&r, v3(0.005, 0.015, 0.005), 0.001));
  assert_false(adem_insert_region_holds(&r, v3(0.015, 0.015, 0.005), 0.001));
  assert_false(adem_insert_region_holds(&r, v3(0.005, 0.005, 0.0095), 0.001));
  assert_false(adem_insert_region_holds(&r, v3(0.0105, 0.0105, 0.005), 0.0001)); /* re-entrant corner */
  adem_insert_region_free(&r);
  adem_case_free(c);
}

/* Claim: `solid_fraction` is met within half the largest sphere's volume (the rule keeps a sphere
 * while the volume plus half of it stays within the target), and the placed volume is the drawn
 * one (every sphere found room). */
static void test_solid_fraction(void **state) {
  (void)state;
  const char *box = "min: [0, 0, 0]\n    max: [0.03, 0.03, 0.03]";
  adem_case *c = must_fill(box, "{distribution: uniform, min: 0.0008, max: 0.0012}",
                           "solid_fraction: 0.25", 4, NULL);
  const adem_particles *p = &c->world->p;
  double v = 0.0;
  for (size_t i = 0; i < p->n; ++i) v += 4.0 / 3.0 * ADEM_PI * pow(p->radius[i], 3);
  double V = 0.03 * 0.03 * 0.03, phi = v / V;
  double tol = 0.5 * 4.0 / 3.0 * ADEM_PI * pow(0.0012, 3) / V;
  printf("# solid fraction %.6f for 0.25 (tolerance %.2e), %zu spheres\n", phi, tol, p->n);
  assert_float_equal(phi, 0.25, tol);
  assert_no_overlap(p);
  adem_case_free(c);
}

/* Claim: each distribution's sample of 10,000 radii has the stated mean and standard deviation
 * within 2 %. Standard errors at N = 1e4: mean sigma/sqrt(N) <= 0.2 % of it for the spreads used
 * (cv <= 0.2); std about sqrt((kurtosis - 1)/(4N)) <= 0.9 % (lognormal, cv 0.2); so 2 % is over 2
 * standard errors for the std and 10 for the mean. Constant: exactly the value. */
static void test_distributions(void **state) {
  (void)state;
  struct {
    const char *text;
    double mean, std;
  } cases[] = {
      {"{distribution: constant, value: 0.0005}", 0.0005, 0.0},
      {"{distribution: uniform, min: 0.0004, max: 0.0006}", 0.0005, 0.0002 / sqrt(12.0)},
      {"{distribution: normal, mean: 0.0005, std: 0.0001}", 0.0005, 0.0001},
      {"{distribution: lognormal, mean: 0.0005, std: 0.0001}", 0.0005, 0.0001},
      /* 0.2 x 0.4 + 0.5 x 0.5 + 0.3 x 0.6 = 0.51 mm; E[r^2] = 0.2 x 0.16 + 0.5 x 0.25 + 0.3 x 0.36
       * = 0.265 mm^2; var = 0.265 - 0.2601 = 0.0049 mm^2, std 0.07 mm */
      {"{distribution: discrete, values: [0.0004, 0.0005, 0.0006], weights: [2, 5, 3]}", 0.00051,
       0.00007},
  };
  const char *box = "min: [0, 0, 0]\n    max: [0.2, 0.2, 0.2]";
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    adem_case *c = must_fill(box, cases[k].text, "count: 10000", 9, NULL);
    const adem_particles *p = &c->world->p;
    assert_int_equal(p->n, 10000);
    double s = 0, s2 = 0;
    for (size_t i = 0; i < p->n; ++i) s += p->radius[i];
    double mean = s / (double)p->n;
    for (size_t i = 0; i < p->n; ++i) s2 += (p->radius[i] - mean) * (p->radius[i] - mean);
    double std = sqrt(s2 / (double)(p->n - 1));
    printf("# %s: mean %.6g (%.6g), std %.6g (%.6g)\n", cases[k].text, mean, cases[k].mean, std,
           cases[k].std);
    assert_float_equal(mean, cases[k].mean, 0.02 * cases[k].mean);
    assert_float_equal(std, cases[k].std, cases[k].std > 0 ? 0.02 * cases[k].std : 1e-15);
    adem_case_free(c);
  }
}

static void expect_fill_error(const char *region, const char *radius, const char *amount,
                              const char *w1, const char *w2) {
  adem_error err;
  adem_case *c = load_fill(region, radius, amount, 1, NULL, &err);
  if (c) fail_msg("expected an error with '%s'", w1);
  printf("# %s\n", err.message);
  if (!strstr(err.message, w1)) fail_msg("'%s' not in: %s", w1, err.message);
  if (w2 && !strstr(err.message, w2)) fail_msg("'%s' not in: %s", w2, err.message);
}

/* Claim: bad regions, amounts and distributions are refused with the key path and the reason. */
static void test_bad_input(void **state) {
  (void)state;
  const char *box = "min: [0, 0, 0]\n    max: [0.02, 0.02, 0.02]";
  const char *r = "{distribution: constant, value: 0.001}";
  char open_region[600];
  snprintf(open_region, sizeof open_region, "region: {shape: mesh, file: %s/open.stl}", tmpdir);
  expect_fill_error(open_region, r, "count: 10", "particles[0].region.file", "does not enclose a volume");
  expect_fill_error("region: {shape: cylinder, start: [0, 0, 0], end: [0, 0, 0], radius: 0.01}", r,
                    "count: 10", "particles[0].region.end", "same point");
  expect_fill_error("region: {shape: cone}", r, "count: 10", "particles[0].region.shape", "cylinder");
  expect_fill_error("region: {shape: box, min: [0, 0, 0], max: [0.02, 0.02, 0.02]}\n    min: [0, 0, 0]",
                    r, "count: 10", "particles[0].min", "not both");
  expect_fill_error(box, r, "count: 10\n    solid_fraction: 0.2", "particles[0].solid_fraction", "not both");
  expect_fill_error(box, r, "solid_fraction: 1.5", "particles[0].solid_fraction", "in (0, 1)");
  expect_fill_error(box, r, "max_attempts: 5", "particles[0].count", "required");
  expect_fill_error(box, "{distribution: discrete, values: [0.001, 0.002], weights: [1]}", "count: 10",
                    "particles[0].radius.weights", "one weight per value");
  expect_fill_error(box, "{distribution: discrete, values: [0.001, -0.002]}", "count: 10",
                    "particles[0].radius.values[1]", "> 0");
  expect_fill_error(box, "{distribution: discrete, values: [0.001, 0.02]}", "count: 10",
                    "particles[0].radius.values", "does not fit the box");
  expect_fill_error("region: {shape: cylinder, start: [0, 0, 0], end: [0, 0, 0.1], radius: 0.002}",
                    "{distribution: constant, value: 0.003}", "count: 10",
                    "particles[0].radius.value", "does not fit the cylinder");
}

/* Claim: a fill that cannot reach its target keeps what it placed and says how many. */
static void test_fill_falls_short(void **state) {
  (void)state;
  logged[0] = '\0';
  const char *box = "min: [0, 0, 0]\n    max: [0.01, 0.01, 0.01]";
  adem_case *c = must_fill(box, "{distribution: constant, value: 0.001}",
                           "count: 1000\n    max_attempts: 20000", 3, NULL);
  size_t n = c->world->p.n;
  char expect[160];
  snprintf(expect, sizeof expect, "placed %zu of 1000 spheres", n);
  printf("# %s", logged);
  assert_true(n > 50 && n < 1000);
  if (!strstr(logged, expect)) fail_msg("'%s' not in: %s", expect, logged);
  adem_case_free(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_box_fill),
      cmocka_unit_test(test_fill_clears_mesh),
      cmocka_unit_test(test_cylinder_fill),
      cmocka_unit_test(test_mesh_fill),
      cmocka_unit_test(test_solid_fraction),
      cmocka_unit_test(test_distributions),
      cmocka_unit_test(test_bad_input),
      cmocka_unit_test(test_fill_falls_short),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
