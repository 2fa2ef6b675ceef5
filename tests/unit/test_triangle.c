/* Sphere-triangle geometry: the closest-point feature in each of the 7 Voronoi regions, the
 * closest point against brute-force sampling, and the one-contact-per-region rule on a flat plate
 * (face, shared edge, shared vertex: exactly the infinite plane's contact), a convex box edge and
 * vertex, a face next to a convex edge, a concave corner, and the border of a flat strip. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "adem/adem.h"
#include "mesh_contact.h"
#include "mesh.h"
#include "stl.h"
#include "rng.h"

#define DATA ADEM_SOURCE_DIR "/tests/data/"

static void silent(adem_log_level level, const char *message, void *user) {
  (void)level;
  (void)message;
  (void)user;
}

static int setup(void **state) {
  (void)state;
  adem_log_set_hook(silent, NULL);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  adem_log_set_hook(NULL, NULL);
  return 0;
}

static double dist(adem_vec3 a, adem_vec3 b) { return v3_norm(v3_sub(a, b)); }

/* Claim: a point in each of the 7 Voronoi regions of the triangle (0,0,0), (1,0,0), (0,1,0), on
 * either side of its plane, gets that feature and its closest point: exact for the vertices, to
 * 1e-15 (rounding of a few operations on numbers of order 1) for edges and face. */
static void test_voronoi_regions(void **state) {
  (void)state;
  adem_vec3 a = {0, 0, 0}, b = {1, 0, 0}, c = {0, 1, 0};
  struct {
    adem_vec3 p, q;
    adem_triangle_feature f;
  } cases[] = {
      {{0.25, 0.25, 0.5}, {0.25, 0.25, 0}, ADEM_TRIANGLE_FACE},
      {{0.2, 0.3, -0.7}, {0.2, 0.3, 0}, ADEM_TRIANGLE_FACE},
      {{-1, -1, 0.3}, {0, 0, 0}, ADEM_TRIANGLE_VERTEX0},
      {{2, -0.5, 1}, {1, 0, 0}, ADEM_TRIANGLE_VERTEX1},
      {{-0.5, 2, -1}, {0, 1, 0}, ADEM_TRIANGLE_VERTEX2},
      {{0.5, -1, 0.2}, {0.5, 0, 0}, ADEM_TRIANGLE_EDGE0},
      {{1, 1, 0.3}, {0.5, 0.5, 0}, ADEM_TRIANGLE_EDGE1},
      {{-1, 0.5, -0.2}, {0, 0.5, 0}, ADEM_TRIANGLE_EDGE2},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    adem_triangle_feature f;
    adem_vec3 q = adem_triangle_closest_point(cases[i].p, a, b, c, &f);
    assert_int_equal(f, cases[i].f);
    assert_true(dist(q, cases[i].q) <= 1e-15);
    /* the vertex order does not change the point: cyclic shift moves the feature number */
    adem_triangle_feature g;
    adem_vec3 q2 = adem_triangle_closest_point(cases[i].p, b, c, a, &g);
    assert_true(dist(q2, cases[i].q) <= 1e-15);
    if (f == ADEM_TRIANGLE_FACE) assert_int_equal(g, f);
    else if (adem_triangle_feature_is_edge(f)) assert_int_equal(g, ADEM_TRIANGLE_EDGE0 + (f - ADEM_TRIANGLE_EDGE0 + 2) % 3);
    else assert_int_equal(g, ADEM_TRIANGLE_VERTEX0 + (f - ADEM_TRIANGLE_VERTEX0 + 2) % 3);
  }
}

/* Claim: on random triangles (some slivers) and points, the closest point lies on the triangle
 * (barycentric coordinates >= -1e-12), on the feature it names, and is no farther than the best of
 * 200x200 sampled points on the triangle (to 1e-12 of the triangle size): a brute-force check. */
static void test_closest_brute_force(void **state) {
  (void)state;
  adem_rng rng = adem_rng_seed(12345);
  for (int trial = 0; trial < 300; ++trial) {
    adem_vec3 v[3];
    for (int k = 0; k < 3; ++k)
      v[k] = v3(adem_rng_uniform(&rng) - 0.5, adem_rng_uniform(&rng) - 0.5, adem_rng_uniform(&rng) - 0.5);
    if (trial % 10 == 0) v[2] = v3_axpy(v3_scale(v3_add(v[0], v[1]), 0.5), 1e-3, v[2]); /* sliver */
    adem_vec3 p = v3(3 * adem_rng_uniform(&rng) - 1.5, 3 * adem_rng_uniform(&rng) - 1.5,
                     3 * adem_rng_uniform(&rng) - 1.5);
    adem_triangle_feature f;
    adem_vec3 q = adem_triangle_closest_point(p, v[0], v[1], v[2], &f);
    adem_vec3 e0 = v3_sub(v[1], v[0]), e1 = v3_sub(v[2], v[0]), d = v3_sub(q, v[0]);
    double d00 = v3_dot(e0, e0), d01 = v3_dot(e0, e1), d11 = v3_dot(e1, e1);
    double d20 = v3_dot(d, e0), d21 = v3_dot(d, e1), den = d00 * d11 - d01 * d01;
    double bv = (d11 * d20 - d01 * d21) / den, bw = (d00 * d21 - d01 * d20) / den, bu = 1 - bv - bw;
    double tol = 1e-12 * (1.0 + 1.0 / sqrt(den)); /* slivers amplify rounding in the coordinates */
    assert_true(bu >= -tol && bv >= -tol && bw >= -tol);
    double bary[3] = {bu, bv, bw};
    if (adem_triangle_feature_is_vertex(f)) {
      assert_true(dist(q, v[f - ADEM_TRIANGLE_VERTEX0]) == 0.0);
    } else if (adem_triangle_feature_is_edge(f)) {
      int k = f - ADEM_TRIANGLE_EDGE0; /* the opposite vertex has weight 0 */
      assert_true(fabs(bary[(k + 2) % 3]) <= tol);
    }
    double best = INFINITY;
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; j <= 200 - i; ++j) {
        adem_vec3 s = v3_add(v[0], v3_add(v3_scale(e0, i / 200.0), v3_scale(e1, j / 200.0)));
        best = fmin(best, dist(s, p));
      }
    assert_true(dist(q, p) <= best + 1e-12);
  }
}

/* A flat square plate of n x n squares of side h in the plane z = 0, each split in two along its
 * diagonal (CCW from +z), then rotated by R and moved by t. Interior vertices have 6 triangles. */
static void make_plate(adem_mesh *m, int n, double h, const double R[3][3], adem_vec3 t) {
  adem_vec3 *c = malloc((size_t)(6 * n * n) * sizeof *c);
  assert_non_null(c);
  size_t k = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      adem_vec3 v00 = {i * h, j * h, 0}, v10 = {(i + 1) * h, j * h, 0};
      adem_vec3 v11 = {(i + 1) * h, (j + 1) * h, 0}, v01 = {i * h, (j + 1) * h, 0};
      adem_vec3 q[6] = {v00, v10, v11, v00, v11, v01};
      for (int s = 0; s < 6; ++s) {
        adem_vec3 x = q[s];
        c[k++] = v3(R[0][0] * x.x + R[0][1] * x.y + R[0][2] * x.z + t.x,
                    R[1][0] * x.x + R[1][1] * x.y + R[1][2] * x.z + t.y,
                    R[2][0] * x.x + R[2][1] * x.y + R[2][2] * x.z + t.z);
      }
    }
  adem_error err;
  assert_int_equal(adem_mesh_add_triangles(m, c, NULL, (size_t)(2 * n * n), "plate", 0, 0, &err), ADEM_OK);
  free(c);
}

static adem_vec3 apply(const double R[3][3], adem_vec3 x, adem_vec3 t) {
  return v3(R[0][0] * x.x + R[0][1] * x.y + R[0][2] * x.z + t.x,
            R[1][0] * x.x + R[1][1] * x.y + R[1][2] * x.z + t.y,
            R[2][0] * x.x + R[2][1] * x.y + R[2][2] * x.z + t.z);
}

static size_t all_candidates(const adem_mesh *m, uint32_t **cand) {
  *cand = malloc(m->ntris * sizeof **cand);
  assert_non_null(*cand);
  for (size_t t = 0; t < m->ntris; ++t) (*cand)[t] = (uint32_t)t;
  return m->ntris;
}

/* Claim: on a 20 x 20 plate (800 triangles) a sphere (r = 0.04, overlap 0.004) with its centre
 * over (a) a face interior, (b) a shared grid edge and a shared diagonal, (c) a vertex where 6
 * triangles meet gets exactly one contact, keyed by the plate's flat region (0), equal to the
 * infinite plane's contact (n = -plane normal, overlap = r - (x - p).n_plane as force_pass.c
 * computes it) to 1e-12 relative. Checked for the plate at z = 0 and turned by 37 degrees about
 * (1, 2, 3) and moved: there the plane's own rounding (coordinates of order 1, 1e-16) against an
 * overlap of 4e-3 allows 1e-13, so 1e-12 is a real bound. */
static void test_plate_one_contact(void **state) {
  (void)state;
  const double h = 0.05, r = 0.04, delta = 0.004;
  adem_mesh_transform tilt = adem_default_mesh_transform();
  adem_error err;
  assert_int_equal(adem_mesh_transform_rotate(&tilt, (adem_vec3){1, 2, 3}, 37.0, &err), ADEM_OK);
  adem_mesh_transform flat = adem_default_mesh_transform();
  const adem_mesh_transform *tfs[2] = {&flat, &tilt};
  adem_vec3 moves[2] = {{0, 0, 0}, {0.3, -0.2, 0.1}};
  /* positions in plate coordinates (units of h); the last three on features */
  double spots[5][2] = {{10.3, 10.6}, {10.0, 10.5}, {10.5, 10.5}, {10.0, 10.0}, {3.0, 17.0}};
  for (int w = 0; w < 2; ++w) {
    adem_mesh m = {0};
    make_plate(&m, 20, h, tfs[w]->rotation, moves[w]);
    assert_int_equal(m.ntris, 800);
    assert_int_equal(m.nverts, 441);
    for (size_t t = 0; t < m.ntris; ++t) assert_int_equal(m.region[t], 0);
    if (w == 0) { /* the vertex of case (c) has 6 triangles around it, all flat */
      size_t v = 0;
      while (v < m.nverts && !(m.vert[v].x == 10 * h && m.vert[v].y == 10 * h)) ++v;
      assert_true(v < m.nverts);
      assert_int_equal(m.vt_start[v + 1] - m.vt_start[v], 6);
      assert_int_equal(m.vert_flat[v], 1);
    }
    uint32_t *cand;
    size_t nc = all_candidates(&m, &cand);
    adem_mesh_contact *out = malloc(nc * sizeof *out);
    adem_vec3 pn = apply(tfs[w]->rotation, v3(0, 0, 1), v3_zero()); /* the plane: point, normal */
    adem_vec3 pp = moves[w];
    for (int s = 0; s < 5; ++s) {
      for (int side = -1; side <= 1; side += 2) {
        adem_vec3 local = {spots[s][0] * h, spots[s][1] * h, side * (r - delta)};
        adem_vec3 x = apply(tfs[w]->rotation, local, moves[w]);
        size_t n = adem_triangle_sphere_contacts(&m, x, r, cand, nc, out);
        assert_int_equal(n, 1);
        double d = v3_dot(v3_sub(x, pp), pn); /* force_pass.c: dist = (x - point).normal */
        adem_vec3 n_plane = d >= 0 ? v3_neg(pn) : pn;
        double overlap_plane = r - fabs(d);
        assert_true(fabs(out[0].overlap - overlap_plane) <= 1e-12 * overlap_plane);
        assert_true(dist(out[0].normal, n_plane) <= 1e-12);
        assert_true(out[0].key == adem_mesh_contact_key(ADEM_MESH_CONTACT_PLANE, 0));
        assert_true(dist(out[0].point, v3_axpy(x, fabs(d), n_plane)) <= 1e-12);
        if (w == 0) { /* exactly the plane: z = 0 plate, normals (0, 0, +-1) */
          assert_true(out[0].overlap == overlap_plane);
          assert_true(out[0].normal.x == 0.0 && out[0].normal.y == 0.0 && out[0].normal.z == -side);
        }
      }
    }
    free(out);
    free(cand);
    adem_mesh_free(&m);
  }
}

/* Claim: the candidate list's order and repeats do not change the contacts (bitwise), and a
 * sphere sliding across the plate keeps one key while its owning triangle changes: the history
 * key of a flat region. */
static void test_order_and_key(void **state) {
  (void)state;
  adem_mesh m = {0};
  double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  make_plate(&m, 8, 0.1, I, v3_zero());
  uint32_t *cand;
  size_t nc = all_candidates(&m, &cand);
  uint32_t *rev = malloc(2 * nc * sizeof *rev);
  for (size_t i = 0; i < nc; ++i) rev[i] = rev[nc + i] = cand[nc - 1 - i];
  adem_mesh_contact *a = malloc(2 * nc * sizeof *a), *b = malloc(2 * nc * sizeof *b);
  uint32_t owners[64];
  size_t nowners = 0;
  for (int s = 0; s <= 40; ++s) {
    adem_vec3 x = {0.2 + 0.4 * s / 40.0, 0.33, 0.07};
    size_t na = adem_triangle_sphere_contacts(&m, x, 0.08, cand, nc, a);
    size_t nb = adem_triangle_sphere_contacts(&m, x, 0.08, rev, 2 * nc, b);
    assert_int_equal(na, 1);
    assert_int_equal(nb, 1);
    assert_memory_equal(&a[0], &b[0], sizeof a[0]);
    assert_true(a[0].key == 0);
    if (nowners == 0 || owners[nowners - 1] != a[0].tri) owners[nowners++] = a[0].tri;
  }
  assert_true(nowners >= 4); /* it crossed several triangles */
  free(a);
  free(b);
  free(rev);
  free(cand);
  adem_mesh_free(&m);
}

static void load_cube(adem_mesh *m) {
  adem_error err;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", NULL, NULL, m, &err), ADEM_OK);
}

/* Claim: a sphere off a convex edge of the unit box, its centre on the bisector at distance
 * r - delta, gets one contact on the edge: point (1, 0.4, 1), normal -(1, 0, 1)/sqrt 2 (along the
 * line from the centre to the edge) and overlap delta, to 1e-12 relative; off a corner, one vertex
 * contact along -(1, 1, 1)/sqrt 3. */
static void test_convex_edge_and_vertex(void **state) {
  (void)state;
  adem_mesh m = {0};
  load_cube(&m);
  uint32_t *cand;
  size_t nc = all_candidates(&m, &cand);
  adem_mesh_contact out[12];
  const double r = 0.1, delta = 0.01;
  double a = (r - delta) / sqrt(2.0);
  adem_vec3 x = {1 + a, 0.4, 1 + a};
  size_t n = adem_triangle_sphere_contacts(&m, x, r, cand, nc, out);
  assert_int_equal(n, 1);
  assert_int_equal(adem_mesh_contact_key_kind(out[0].key), ADEM_MESH_CONTACT_EDGE);
  assert_true(fabs(out[0].overlap - delta) <= 1e-12 * delta);
  adem_vec3 ne = v3_scale(v3(-1, 0, -1), 1 / sqrt(2.0));
  assert_true(dist(out[0].normal, ne) <= 1e-12);
  assert_true(dist(out[0].point, v3(1, 0.4, 1)) <= 1e-15);

  double b = (r - delta) / sqrt(3.0);
  x = v3(1 + b, 1 + b, 1 + b);
  n = adem_triangle_sphere_contacts(&m, x, r, cand, nc, out);
  assert_int_equal(n, 1);
  assert_int_equal(adem_mesh_contact_key_kind(out[0].key), ADEM_MESH_CONTACT_VERTEX);
  assert_true(fabs(out[0].overlap - delta) <= 1e-12 * delta);
  assert_true(dist(out[0].normal, v3_scale(v3(-1, -1, -1), 1 / sqrt(3.0))) <= 1e-12);
  assert_true(dist(out[0].point, v3(1, 1, 1)) == 0.0);
  free(cand);
  adem_mesh_free(&m);
}

/* Claim: a sphere on the top face 0.03 from a convex edge also reaches the edge (0.0949 < r),
 * but the side triangle's edge point is not where it touches (the top face is closer): one plane
 * contact, overlap r - 0.09 = 0.01 and normal (0, 0, -1), to 1e-12. */
static void test_face_next_to_convex_edge(void **state) {
  (void)state;
  adem_mesh m = {0};
  load_cube(&m);
  uint32_t *cand;
  size_t nc = all_candidates(&m, &cand);
  adem_mesh_contact out[12];
  adem_vec3 x = {0.97, 0.4, 1.09};
  size_t n = adem_triangle_sphere_contacts(&m, x, 0.1, cand, nc, out);
  assert_int_equal(n, 1);
  assert_int_equal(adem_mesh_contact_key_kind(out[0].key), ADEM_MESH_CONTACT_PLANE);
  assert_true(fabs(out[0].overlap - 0.01) <= 1e-12 * 0.01);
  assert_true(out[0].normal.x == 0.0 && out[0].normal.y == 0.0 && out[0].normal.z == -1.0);
  assert_true(m.region[out[0].tri] == 2); /* the top face's region: triangles 2 and 3 */
  free(cand);
  adem_mesh_free(&m);
}

/* Claim: a sphere in a concave 90-degree corner (floor z = 0 and wall x = 0, two triangles each)
 * touching both faces gets two contacts, one per face, with each face's normal and overlap
 * (0.02 and 0.01) to 1e-12. */
static void test_concave_corner(void **state) {
  (void)state;
  adem_vec3 c[12] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 0}, {0, 1, 1}, {0, 0, 1}};
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_add_triangles(&m, c, NULL, 4, "corner", 0, 0, &err), ADEM_OK);
  for (int t = 0; t < 4; ++t)
    for (int k = 0; k < 3; ++k)
      if (m.adj[t][k] >= 0 && m.region[m.adj[t][k]] != m.region[t])
        assert_int_equal(m.edge_kind[t][k], ADEM_MESH_EDGE_CONCAVE);
  uint32_t cand[4] = {0, 1, 2, 3};
  adem_mesh_contact out[4];
  const double r = 0.1;
  for (int s = 0; s < 3; ++s) {
    double y = s == 0 ? 0.5 : s == 1 ? 0.25
                                     : 0.0001; /* face interior, diagonal's end, near the border */
    adem_vec3 x = {0.09, y + 0.3 * (s == 1), 0.08};
    size_t n = adem_triangle_sphere_contacts(&m, x, r, cand, 4, out);
    assert_int_equal(n, 2);
    /* sorted by key: floor region 0 first, then the wall's region 2 */
    assert_true(out[0].key == 0 && out[1].key == 2);
    assert_true(fabs(out[0].overlap - 0.02) <= 1e-12 * 0.02);
    assert_true(fabs(out[1].overlap - 0.01) <= 1e-12 * 0.01);
    assert_true(out[0].normal.x == 0.0 && out[0].normal.y == 0.0 && out[0].normal.z == -1.0);
    assert_true(out[1].normal.x == -1.0 && out[1].normal.y == 0.0 && out[1].normal.z == 0.0);
  }
  adem_mesh_free(&m);
}

/* Claim: a big sphere (r = 1) just beyond the border of a one-square-wide strip, 0.02 above its
 * plane and 0.05 outside, touches only the border edge: the flat diagonal's point on the other
 * triangle (0.67 away) and the vertices of the next squares are not local minima of the distance.
 * One edge contact, overlap 1 - sqrt(0.05^2 + 0.02^2), normal towards (x, 0, 0), to 1e-12. */
static void test_strip_border(void **state) {
  (void)state;
  adem_mesh m = {0};
  adem_vec3 c[6 * 6];
  for (int i = 0; i < 6; ++i) {
    adem_vec3 q[6] = {{i, 0, 0}, {i + 1, 0, 0}, {i + 1, 1, 0}, {i, 0, 0}, {i + 1, 1, 0}, {i, 1, 0}};
    memcpy(&c[6 * i], q, sizeof q);
  }
  adem_error err;
  assert_int_equal(adem_mesh_add_triangles(&m, c, NULL, 12, "strip", 0, 0, &err), ADEM_OK);
  uint32_t *cand;
  size_t nc = all_candidates(&m, &cand);
  adem_mesh_contact out[12];
  adem_vec3 x = {2.9, -0.05, 0.02};
  size_t n = adem_triangle_sphere_contacts(&m, x, 1.0, cand, nc, out);
  assert_int_equal(n, 1);
  assert_int_equal(adem_mesh_contact_key_kind(out[0].key), ADEM_MESH_CONTACT_EDGE);
  double d = sqrt(0.05 * 0.05 + 0.02 * 0.02);
  assert_true(fabs(out[0].overlap - (1.0 - d)) <= 1e-12 * (1.0 - d));
  assert_true(dist(out[0].normal, v3_scale(v3(0, 0.05, -0.02), 1 / d)) <= 1e-12);
  assert_true(dist(out[0].point, v3(2.9, 0, 0)) <= 1e-15);
  /* past the end of the strip: the corner vertex (6, 0, 0) */
  x = v3(6.03, -0.04, 0.0);
  n = adem_triangle_sphere_contacts(&m, x, 0.1, cand, nc, out);
  assert_int_equal(n, 1);
  assert_int_equal(adem_mesh_contact_key_kind(out[0].key), ADEM_MESH_CONTACT_VERTEX);
  assert_true(fabs(out[0].overlap - 0.05) <= 1e-12 * 0.05);
  free(cand);
  adem_mesh_free(&m);
}

/* Claim: on a turned box (random rotations), a sphere whose centre lies exactly on the boundary
 * between a face's prism and a convex edge's wedge, or between an edge's wedge and a corner's
 * cone, gets one contact with overlap r - (distance to the box) to 1e-12 relative: the triangles
 * that see the point as different features (a rounding tie) give the same contact once. */
static void test_boundary_ties(void **state) {
  (void)state;
  adem_rng rng = adem_rng_seed(777);
  adem_error err;
  int mixed = 0;
  for (int trial = 0; trial < 200; ++trial) {
    adem_mesh_transform tf = adem_default_mesh_transform();
    adem_vec3 axis = v3(adem_rng_uniform(&rng) - 0.5, adem_rng_uniform(&rng) - 0.5, adem_rng_uniform(&rng) - 0.5);
    assert_int_equal(adem_mesh_transform_rotate(&tf, axis, 360.0 * adem_rng_uniform(&rng), &err), ADEM_OK);
    tf.translation = v3(adem_rng_uniform(&rng), adem_rng_uniform(&rng), adem_rng_uniform(&rng));
    adem_mesh m = {0};
    assert_int_equal(adem_mesh_load_stl(DATA "cube_binary.stl", &tf, NULL, &m, &err), ADEM_OK);
    uint32_t cand[12];
    for (uint32_t t = 0; t < 12; ++t) cand[t] = t;
    adem_mesh_contact out[12];
    const double r = 0.1, gap = 0.09;
    double y = adem_rng_uniform(&rng);
    /* above the top face's edge x = 1 (face/edge boundary), and off the corner along the
     * edge/vertex boundary x = 1 + a, z = 1 + a, y = 1 */
    adem_vec3 local[2] = {{1.0, y, 1.0 + gap}, {1.0 + gap / sqrt(2.0), 1.0, 1.0 + gap / sqrt(2.0)}};
    for (int s = 0; s < 2; ++s) {
      adem_vec3 x = apply(tf.rotation, local[s], tf.translation);
      size_t n = adem_triangle_sphere_contacts(&m, x, r, cand, 12, out);
      assert_int_equal(n, 1);
      assert_true(fabs(out[0].overlap - (r - gap)) <= 1e-12 * (r - gap));
      /* how often did two triangles disagree on the feature? */
      int kinds = 0;
      for (uint32_t t = 0; t < 12; ++t) {
        adem_vec3 q;
        adem_triangle_feature f;
        if (adem_triangle_distance2(&m, t, x, &q, &f) < r * r) kinds |= 1 << (f == ADEM_TRIANGLE_FACE ? 0 : adem_triangle_feature_is_edge(f) ? 1
                                                                                                                                             : 2);
      }
      mixed += kinds != 1 << (s + 1);
    }
    adem_mesh_free(&m);
  }
  printf("# %d of 400 boundary spheres saw mixed features\n", mixed);
  assert_true(mixed > 0); /* the test exercises ties, not only clean cases */
}

/* Claim: a plate folded by 5e-6 rad (below ADEM_MESH_FLAT_ANGLE) is one flat region, and a
 * sphere over the crease, inside both faces' prisms, gets one contact (the deeper face), not two:
 * two would double the force of what is a flat wall within STL's float precision. */
static void test_nearly_flat_fold(void **state) {
  (void)state;
  const double eps = 5e-6;
  adem_vec3 c[12] = {{-1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {0, 0, 0}, {1, 0, eps}, {1, 1, eps}, {0, 0, 0}, {1, 1, eps}, {0, 1, 0}};
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_add_triangles(&m, c, NULL, 4, "fold", 0, 0, &err), ADEM_OK);
  for (int t = 0; t < 4; ++t) assert_int_equal(m.region[t], 0);
  uint32_t cand[4] = {0, 1, 2, 3};
  adem_mesh_contact out[4];
  /* both prisms overlap over the concave crease for -eps z < x < 0; the two faces' points are
   * 0.09 eps = 4.5e-7 apart, more than the 1e-6 r = 1e-7 under which points are merged anyway */
  adem_vec3 x = {-0.5 * eps * 0.09, 0.5, 0.09};
  adem_vec3 q;
  adem_triangle_feature f0, f2;
  adem_triangle_distance2(&m, 0, x, &q, &f0);
  adem_triangle_distance2(&m, 3, x, &q, &f2);
  assert_int_equal(f0, ADEM_TRIANGLE_FACE);
  assert_int_equal(f2, ADEM_TRIANGLE_FACE);
  size_t n = adem_triangle_sphere_contacts(&m, x, 0.1, cand, 4, out);
  assert_int_equal(n, 1);
  assert_true(fabs(out[0].overlap - 0.01) <= 1e-6); /* 0.01 up to the fold's tilt, 0.09 * eps^2 */
  adem_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_voronoi_regions, setup, teardown),
      cmocka_unit_test_setup_teardown(test_closest_brute_force, setup, teardown),
      cmocka_unit_test_setup_teardown(test_plate_one_contact, setup, teardown),
      cmocka_unit_test_setup_teardown(test_order_and_key, setup, teardown),
      cmocka_unit_test_setup_teardown(test_convex_edge_and_vertex, setup, teardown),
      cmocka_unit_test_setup_teardown(test_face_next_to_convex_edge, setup, teardown),
      cmocka_unit_test_setup_teardown(test_concave_corner, setup, teardown),
      cmocka_unit_test_setup_teardown(test_strip_border, setup, teardown),
      cmocka_unit_test_setup_teardown(test_boundary_ties, setup, teardown),
      cmocka_unit_test_setup_teardown(test_nearly_flat_fold, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
