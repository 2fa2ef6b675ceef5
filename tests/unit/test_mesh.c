/* STL meshes: ASCII and binary give the same mesh, transforms are exact where they should be,
 * degenerate triangles are dropped and counted, every kind of bad file is an error that says
 * which file and where, group names are unique, topology (adjacency, edge kinds, flat regions) and
 * the VTU writer. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include "adem/adem.h"
#include "case_text.h"
#include "log_capture.h"
#include "mesh.h"
#include "output.h"
#include "stl.h"
#include "tmpdir.h"

#define DATA ADEM_SOURCE_DIR "/tests/data/"

static int group_setup(void **state) {
  (void)state;
  return tmpdir_make("adem_mesh");
}

static void tmp_path(char *out, size_t cap, const char *name) {
  snprintf(out, cap, "%s/%s", tmpdir, name);
}

static unsigned char *read_file(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  unsigned char *buf = malloc(1 << 20);
  assert_non_null(buf);
  *n = fread(buf, 1, 1 << 20, f);
  fclose(f);
  return buf;
}

static void write_file(const char *path, const void *data, size_t n) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(data, 1, n, f), n);
  fclose(f);
}

static void write_text(const char *path, const char *text) { write_file(path, text, strlen(text)); }

/* Claim: the ASCII and binary files of one cube (coordinates exact in float32) load to identical
 * meshes, bit for bit: 8 shared vertices, 12 triangles, a closed surface of 18 edges (12 convex
 * box edges and 6 flat face diagonals), 6 flat regions rooted at the first triangle of each face. */
static void test_ascii_binary_identical(void **state) {
  (void)state;
  adem_mesh a = {0}, b = {0};
  adem_error err;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", NULL, NULL, &a, &err), ADEM_OK);
  assert_int_equal(adem_mesh_load_stl(DATA "cube_binary.stl", NULL, NULL, &b, &err), ADEM_OK);
  assert_int_equal(a.nverts, 8);
  assert_int_equal(a.ntris, 12);
  assert_int_equal(b.nverts, a.nverts);
  assert_int_equal(b.ntris, a.ntris);
  assert_memory_equal(a.vert, b.vert, a.nverts * sizeof *a.vert);
  assert_memory_equal(a.tri, b.tri, a.ntris * sizeof *a.tri);
  assert_memory_equal(a.normal, b.normal, a.ntris * sizeof *a.normal);
  assert_memory_equal(a.adj, b.adj, a.ntris * sizeof *a.adj);
  assert_memory_equal(a.edge_kind, b.edge_kind, a.ntris * sizeof *a.edge_kind);
  assert_memory_equal(a.edge_id, b.edge_id, a.ntris * sizeof *a.edge_id);
  assert_memory_equal(a.region, b.region, a.ntris * sizeof *a.region);
  /* names: the solid's for ASCII, the stem for binary (its header is not a name) */
  assert_int_equal(a.ngroups, 1);
  assert_string_equal(a.groups[0].name, "cube");
  assert_string_equal(b.groups[0].name, "cube_binary");
  assert_int_equal(a.nedges, 18);
  int convex = 0, flat = 0;
  for (size_t t = 0; t < a.ntris; ++t)
    for (int k = 0; k < 3; ++k) {
      assert_true(a.adj[t][k] >= 0); /* closed */
      int u = a.adj[t][k];
      /* adjacency is symmetric and shares the edge id */
      int back = 0;
      for (int j = 0; j < 3; ++j) back += a.adj[u][j] == (int32_t)t && a.edge_id[u][j] == a.edge_id[t][k];
      assert_int_equal(back, 1);
      convex += a.edge_kind[t][k] == ADEM_MESH_EDGE_CONVEX;
      flat += a.edge_kind[t][k] == ADEM_MESH_EDGE_FLAT;
    }
  assert_int_equal(convex, 24);
  assert_int_equal(flat, 12);
  for (size_t t = 0; t < a.ntris; ++t) assert_int_equal(a.region[t], t - t % 2);
  for (size_t v = 0; v < a.nverts; ++v) assert_int_equal(a.vert_flat[v], 0);
  /* every normal is an exact unit axis vector pointing out of the cube */
  for (size_t t = 0; t < a.ntris; ++t) {
    adem_vec3 n = a.normal[t];
    assert_true(fabs(n.x) + fabs(n.y) + fabs(n.z) == 1.0);
    adem_vec3 c = a.vert[a.tri[t][0]];
    assert_true((c.x - 0.5) * n.x + (c.y - 0.5) * n.y + (c.z - 0.5) * n.z == 0.5);
  }
  assert_int_equal(a.normals_disagreed, 0);
  assert_int_equal(a.degenerate_dropped, 0);
  /* area 6 and the unit box: exact sums of halves */
  assert_true(adem_mesh_area(&a, -1) == 6.0);
  assert_true(adem_mesh_area(&a, 0) == 6.0);
  adem_vec3 lo, hi;
  adem_mesh_bounds(&a, &lo, &hi);
  assert_true(lo.x == 0.0 && lo.y == 0.0 && lo.z == 0.0 && hi.x == 1.0 && hi.y == 1.0 && hi.z == 1.0);
  assert_string_equal(logged, "");
  adem_mesh_free(&a);
  adem_mesh_free(&b);
}

static int has_vertex(const adem_mesh *m, adem_vec3 x) {
  for (size_t v = 0; v < m->nverts; ++v)
    if (m->vert[v].x == x.x && m->vert[v].y == x.y && m->vert[v].z == x.z) return 1;
  return 0;
}

/* Claim: x' = R (s x) + t maps every cube corner exactly for s = 2, 90 degrees about z and
 * t = (1, 2, 3) (all exact in binary), e.g. (1, 0, 0) -> (1, 4, 3); normals turn with R exactly.
 * A general rotation maps to 1e-15 (a few ulps of coordinates of size 2). */
static void test_transform(void **state) {
  (void)state;
  adem_error err;
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.scale = 2.0;
  tf.translation = (adem_vec3){1.0, 2.0, 3.0};
  tf.material = 3;
  assert_int_equal(adem_mesh_transform_rotate(&tf, (adem_vec3){0, 0, 5}, 90.0, &err), ADEM_OK);
  adem_mesh m = {0};
  assert_int_equal(adem_mesh_load_stl(DATA "cube_binary.stl", &tf, "box", &m, &err), ADEM_OK);
  assert_int_equal(m.groups[0].material, 3);
  assert_true(has_vertex(&m, (adem_vec3){1.0, 4.0, 3.0}));  /* (1,0,0) */
  assert_true(has_vertex(&m, (adem_vec3){1.0, 2.0, 3.0}));  /* (0,0,0) */
  assert_true(has_vertex(&m, (adem_vec3){-1.0, 4.0, 5.0})); /* (1,1,1) */
  for (int c = 0; c < 8; ++c) {
    double x = c & 1, y = (c >> 1) & 1, z = (c >> 2) & 1;
    assert_true(has_vertex(&m, (adem_vec3){1.0 - 2.0 * y, 2.0 + 2.0 * x, 3.0 + 2.0 * z}));
  }
  /* the +x face (triangles 10, 11 of the file) now faces +y */
  assert_true(m.normal[10].x == 0.0 && m.normal[10].y == 1.0 && m.normal[10].z == 0.0);
  assert_true(adem_mesh_area(&m, -1) == 24.0);
  adem_mesh_free(&m);

  /* A rotation matrix given directly: the cyclic permutation x -> y -> z -> x. */
  tf = adem_default_mesh_transform();
  double perm[3][3] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
  memcpy(tf.rotation, perm, sizeof perm);
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", &tf, NULL, &m, &err), ADEM_OK);
  assert_true(m.vert[m.tri[10][0]].x == 0.0 && m.vert[m.tri[10][0]].y == 1.0);
  adem_mesh_free(&m);

  /* 120 degrees about (1,1,1) is the same permutation, up to rounding of sin and cos. */
  tf = adem_default_mesh_transform();
  assert_int_equal(adem_mesh_transform_rotate(&tf, (adem_vec3){1, 1, 1}, 120.0, &err), ADEM_OK);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) assert_true(fabs(tf.rotation[i][j] - perm[i][j]) < 1e-15);

  /* Not rotations, not scales: errors naming the file. */
  tf = adem_default_mesh_transform();
  tf.rotation[2][2] = -1.0;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", &tf, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "cube_ascii.stl");
  assert_contains(err.message, "mirror");
  tf = adem_default_mesh_transform();
  tf.rotation[0][1] = 0.1;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", &tf, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "orthonormal");
  tf = adem_default_mesh_transform();
  tf.scale = 0.0;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", &tf, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "scale");
  tf = adem_default_mesh_transform();
  tf.scale = 1e308; /* finite, but x = 1e308 + 1e308 overflows */
  tf.translation.x = 1e308;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", &tf, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "cube_ascii.stl:");
  assert_contains(err.message, "not finite");
  assert_int_equal(m.ntris, 0);
  adem_mesh_free(&m);
}

/* Claim: a zero-area triangle (collinear corners) and one with a repeated vertex are dropped,
 * counted (2) and reported in one warning; the vertex used only by a dropped triangle is not
 * kept; the remaining square has one flat diagonal and four border edges. */
static void test_degenerate(void **state) {
  (void)state;
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_load_stl(DATA "degenerate.stl", NULL, NULL, &m, &err), ADEM_OK);
  assert_int_equal(m.ntris, 2);
  assert_int_equal(m.nverts, 4);
  assert_int_equal(m.degenerate_dropped, 2);
  assert_contains(logged, "W ");
  assert_contains(logged, "degenerate.stl: dropped 2 degenerate triangles");
  assert_null(strchr(strchr(logged, '\n') + 1, '\n')); /* one line */
  int flat = 0, border = 0;
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) {
      flat += m.edge_kind[t][k] == ADEM_MESH_EDGE_FLAT;
      border += m.edge_kind[t][k] == ADEM_MESH_EDGE_BORDER;
    }
  assert_int_equal(flat, 2);
  assert_int_equal(border, 4);
  assert_int_equal(m.region[0], 0);
  assert_int_equal(m.region[1], 0);
  for (size_t v = 0; v < m.nverts; ++v) assert_int_equal(m.vert_flat[v], 0); /* all on the border */
  assert_true(adem_mesh_area(&m, -1) == 1.0);
  adem_mesh_free(&m);
}

/* Claim: each malformed ASCII file is ADEM_ERR_INPUT with "file:line" of the offending token,
 * and a mesh that already held a cube is left exactly as it was. */
static void test_malformed_ascii(void **state) {
  (void)state;
  struct {
    const char *file, *where, *what;
  } cases[] = {
      {"bad_endloop.stl", "bad_endloop.stl:14:", "found 'endfacet'"},
      {"bad_number.stl", "bad_number.stl:6:", "bad number '1.0.5'"},
      {"two_vertices.stl", "two_vertices.stl:6:", "has 2 vertices, expected 3"},
      {"nan_vertex.stl", "nan_vertex.stl:12:", "non-finite coordinate 'nan'"},
  };
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", NULL, NULL, &m, &err), ADEM_OK);
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    char path[512];
    snprintf(path, sizeof path, DATA "%s", cases[c].file);
    memset(&err, 0, sizeof err);
    assert_int_equal(adem_mesh_load_stl(path, NULL, NULL, &m, &err), ADEM_ERR_INPUT);
    assert_int_equal(err.status, ADEM_ERR_INPUT);
    printf("# %s\n", err.message);
    assert_contains(err.message, cases[c].where);
    assert_contains(err.message, cases[c].what);
    assert_int_equal(m.ntris, 12);
    assert_int_equal(m.nverts, 8);
    assert_int_equal(m.ngroups, 1);
  }
  /* a file cut after a vertex: the end of the file is named */
  char path[512];
  tmp_path(path, sizeof path, "cut.stl");
  write_text(path, "solid cut\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n");
  assert_int_equal(adem_mesh_load_stl(path, NULL, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "cut.stl:4:");
  assert_contains(err.message, "end of the file");
  /* missing file */
  assert_int_equal(adem_mesh_load_stl(DATA "no_such_file.stl", NULL, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "no_such_file.stl");
  assert_int_equal(m.ntris, 12);
  adem_mesh_free(&m);
}

/* Claim: a truncated binary file, one with extra bytes and one with a NaN coordinate are
 * ADEM_ERR_INPUT naming the file, the triangle and its byte offset (84 + 50 i, + 12 + 4 j for
 * coordinate j). The cube's header starts with "solid": still read as binary. */
static void test_binary_errors(void **state) {
  (void)state;
  size_t n;
  unsigned char *cube = read_file(DATA "cube_binary.stl", &n);
  assert_int_equal(n, 84 + 50 * 12);
  assert_memory_equal(cube, "solid", 5);
  adem_mesh m = {0};
  adem_error err;
  char path[512];

  tmp_path(path, sizeof path, "truncated.stl");
  write_file(path, cube, 84 + 50 * 5 + 20);
  assert_int_equal(adem_mesh_load_stl(path, NULL, NULL, &m, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_contains(err.message, "truncated.stl");
  assert_contains(err.message, "truncated");
  assert_contains(err.message, "triangle 5 (byte offset 334)");

  tmp_path(path, sizeof path, "extra.stl");
  unsigned char *big = calloc(n + 7, 1);
  memcpy(big, cube, n);
  write_file(path, big, n + 7);
  free(big);
  assert_int_equal(adem_mesh_load_stl(path, NULL, NULL, &m, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_contains(err.message, "extra.stl");
  assert_contains(err.message, "byte offset 684");

  tmp_path(path, sizeof path, "nan.stl");
  float nan = NAN;
  memcpy(cube + 84 + 50 * 3 + 12 + 4 * 4, &nan, 4); /* triangle 3, second vertex, y */
  write_file(path, cube, n);
  assert_int_equal(adem_mesh_load_stl(path, NULL, NULL, &m, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_contains(err.message, "nan.stl: triangle 3 (byte offset 262)");
  assert_contains(err.message, "non-finite");

  tmp_path(path, sizeof path, "short.stl");
  write_file(path, "abc", 3);
  assert_int_equal(adem_mesh_load_stl(path, NULL, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "short.stl");
  assert_int_equal(m.ntris, 0);
  free(cube);
  adem_mesh_free(&m);
}

/* Claim: group names are unique within a mesh (explicit or derived), and the solids of one
 * ASCII file become groups PREFIX.SOLID with their own triangles. */
static void test_groups(void **state) {
  (void)state;
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", NULL, "walls", &m, &err), ADEM_OK);
  assert_int_equal(adem_mesh_load_stl(DATA "cube_binary.stl", NULL, "walls", &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "cube_binary.stl");
  assert_contains(err.message, "'walls' is already used");
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", NULL, NULL, &m, &err), ADEM_OK);
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", NULL, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "cube_ascii.stl:1:");
  assert_contains(err.message, "'cube' is already used");
  assert_int_equal(m.ngroups, 2);
  /* the second cube shares all 8 vertices with the first: exact duplicates are one vertex */
  assert_int_equal(m.nverts, 8);
  assert_int_equal(m.ntris, 24);

  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.material = 1;
  assert_int_equal(adem_mesh_load_stl(DATA "two_solids.stl", &tf, "hopper", &m, &err), ADEM_OK);
  assert_int_equal(m.ngroups, 4);
  int floor = adem_mesh_find_group(&m, "hopper.floor"), wall = adem_mesh_find_group(&m, "hopper.wall");
  assert_int_equal(floor, 2);
  assert_int_equal(wall, 3);
  assert_int_equal(m.groups[floor].first, 24);
  assert_int_equal(m.groups[floor].count, 1);
  assert_int_equal(m.groups[wall].first, 25);
  assert_int_equal(m.group[25], 3);
  assert_int_equal(m.groups[wall].material, 1);
  assert_true(adem_mesh_area(&m, wall) == 0.5);
  adem_mesh_free(&m);

  assert_int_equal(adem_mesh_load_stl(DATA "two_solids.stl", NULL, NULL, &m, &err), ADEM_OK);
  assert_true(adem_mesh_find_group(&m, "two_solids.floor") == 0);
  assert_true(adem_mesh_find_group(&m, "two_solids.wall") == 1);
  adem_mesh_free(&m);

  /* the same solid name twice in one file */
  char path[512];
  tmp_path(path, sizeof path, "twice.stl");
  write_text(path, "solid a\nendsolid a\nsolid a\nendsolid a\n");
  assert_int_equal(adem_mesh_load_stl(path, NULL, NULL, &m, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "twice.stl:3:");
  assert_contains(err.message, "'twice.a' is already used");
  adem_mesh_free(&m);
}

/* Claim: a stored normal against the vertex order is counted and the vertex order wins; a zero
 * stored normal is not a disagreement. */
static void test_stored_normals(void **state) {
  (void)state;
  char path[512];
  tmp_path(path, sizeof path, "flipped.stl");
  write_text(path,
             "solid s\n"
             "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
             "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\n"
             "endsolid s\n");
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_load_stl(path, NULL, NULL, &m, &err), ADEM_OK);
  assert_int_equal(m.normals_disagreed, 1);
  assert_true(m.normal[0].z == 1.0 && m.normal[1].z == 1.0);
  assert_contains(logged, "1 of 2 stored normals point against the vertex order");
  adem_mesh_free(&m);
}

/* Claim: adjacency across an L-shaped fold sees the edge as concave from both faces (normals
 * into the corner) and a tent-shaped fold as convex; coplanar triangles from separate groups
 * share a flat region rooted at the smallest index. */
static void test_edge_kinds(void **state) {
  (void)state;
  adem_vec3 l[6] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, /* floor, normal +z */
                    {0, 0, 0},
                    {0, 1, 0},
                    {0, 0, 1}}; /* wall x = 0, normal +x */
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_add_triangles(&m, l, NULL, 2, "corner", 0, 0, &err), ADEM_OK);
  assert_true(m.normal[0].z == 1.0 && m.normal[1].x == 1.0);
  int shared = -1;
  for (int k = 0; k < 3; ++k)
    if (m.adj[0][k] == 1) shared = k;
  assert_true(shared >= 0);
  assert_int_equal(m.edge_kind[0][shared], ADEM_MESH_EDGE_CONCAVE);
  for (int k = 0; k < 3; ++k)
    if (m.adj[1][k] == 0) assert_int_equal(m.edge_kind[1][k], ADEM_MESH_EDGE_CONCAVE);
  assert_int_equal(m.region[1], 1);
  /* the same fold with the wall's winding reversed seen from the wall is convex */
  adem_vec3 w2[3] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}; /* normal -x */
  adem_mesh m2 = {0};
  assert_int_equal(adem_mesh_add_triangles(&m2, l, NULL, 1, "floor", 0, 0, &err), ADEM_OK);
  assert_int_equal(adem_mesh_add_triangles(&m2, w2, NULL, 1, "wall", 0, 0, &err), ADEM_OK);
  for (int k = 0; k < 3; ++k)
    if (m2.adj[1][k] == 0) assert_int_equal(m2.edge_kind[1][k], ADEM_MESH_EDGE_CONVEX);
  /* a coplanar triangle in another group: flat, one region */
  adem_vec3 f3[3] = {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  assert_int_equal(adem_mesh_add_triangles(&m2, f3, NULL, 1, "floor2", 0, 0, &err), ADEM_OK);
  assert_int_equal(m2.region[2], 0);
  assert_int_equal(adem_mesh_add_triangles(&m2, f3, NULL, 1, "floor2", 0, 0, &err), ADEM_ERR_INPUT);
  adem_mesh_free(&m);
  adem_mesh_free(&m2);
}

/* Claim: a group loaded with own_vertices shares no vertex (16, not 8, for two equal cubes) and
 * no edge with the others, can be moved exactly by a translation, and a shared group cannot. */
static void test_own_vertices(void **state) {
  (void)state;
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", NULL, "floor", &m, &err), ADEM_OK);
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.own_vertices = 1;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_binary.stl", &tf, "sleeper", &m, &err), ADEM_OK);
  assert_int_equal(m.nverts, 16);
  assert_int_equal(m.groups[1].vert_first, 8);
  assert_int_equal(m.groups[1].vert_count, 8);
  for (size_t t = 0; t < m.ntris; ++t)
    for (int k = 0; k < 3; ++k) {
      assert_true(m.adj[t][k] >= 0);
      assert_int_equal(m.group[m.adj[t][k]], m.group[t]);
    }
  /* a third, shared group does not join the sleeper's vertices but does join the floor's */
  assert_int_equal(adem_mesh_load_stl(DATA "two_solids.stl", NULL, NULL, &m, &err), ADEM_OK);
  assert_int_equal(m.nverts, 16);
  for (size_t t = 24; t < m.ntris; ++t)
    for (int k = 0; k < 3; ++k) assert_true(m.tri[t][k] < 8);
  assert_int_equal(adem_mesh_translate_group(&m, 1, (adem_vec3){2.0, 0.0, -0.5}, &err), ADEM_OK);
  for (uint32_t v = 8; v < 16; ++v) {
    assert_true(m.vert[v].x == 2.0 || m.vert[v].x == 3.0);
    assert_true(m.vert[v].z == -0.5 || m.vert[v].z == 0.5);
  }
  for (uint32_t v = 0; v < 8; ++v) assert_true(m.vert[v].x == 0.0 || m.vert[v].x == 1.0);
  assert_int_equal(adem_mesh_translate_group(&m, 0, (adem_vec3){1, 0, 0}, &err), ADEM_ERR_INPUT);
  assert_contains(err.message, "'floor' shares vertices");
  adem_mesh_free(&m);
}

static uint64_t get_u64(const unsigned char *p) {
  uint64_t x;
  memcpy(&x, p, 8);
  return x;
}

/* Claim: the VTU holds 12 triangle cells whose appended pressure block is |force|/area per face
 * (bit for bit: the same double operations), and the group and connectivity blocks hold the mesh. */
static void test_vtu(void **state) {
  (void)state;
  adem_mesh m = {0};
  adem_error err;
  assert_int_equal(adem_mesh_load_stl(DATA "cube_ascii.stl", NULL, NULL, &m, &err), ADEM_OK);
  double force[36];
  for (int i = 0; i < 36; ++i) force[i] = 0.25 * (i - 17);
  char path[512];
  tmp_path(path, sizeof path, "cube.vtu");
  assert_int_equal(adem_mesh_write_vtu(&m, force, path, &err), ADEM_OK);
  size_t n;
  unsigned char *buf = read_file(path, &n);
  buf[n - 1] = '\0';
  const char *text = (const char *)buf;
  assert_contains(text, "NumberOfPoints=\"8\" NumberOfCells=\"12\"");
  assert_contains(text, "Name=\"pressure\"");
  const char *pr = strstr(text, "Name=\"pressure\" format=\"appended\" offset=\"");
  const char *cn = strstr(text, "Name=\"connectivity\" format=\"appended\" offset=\"");
  assert_non_null(pr);
  assert_non_null(cn);
  unsigned long long off_p = strtoull(strstr(pr, "offset=\"") + 8, NULL, 10);
  unsigned long long off_c = strtoull(strstr(cn, "offset=\"") + 8, NULL, 10);
  const unsigned char *base = (const unsigned char *)strstr(text, "   _") + 4;
  assert_int_equal(get_u64(base + off_p), 12 * 8);
  for (int t = 0; t < 12; ++t) {
    double p;
    memcpy(&p, base + off_p + 8 + 8 * (size_t)t, 8);
    double f = sqrt(force[3 * t] * force[3 * t] + force[3 * t + 1] * force[3 * t + 1] +
                    force[3 * t + 2] * force[3 * t + 2]);
    assert_true(p == f / 0.5);
  }
  assert_int_equal(get_u64(base + off_c), 36 * 8);
  for (int t = 0; t < 12; ++t)
    for (int k = 0; k < 3; ++k) {
      int64_t v;
      memcpy(&v, base + off_c + 8 + 8 * (size_t)(3 * t + k), 8);
      assert_int_equal(v, m.tri[t][k]);
    }
  free(buf);
  /* no forces: zeros, still valid */
  assert_int_equal(adem_mesh_write_vtu(&m, NULL, path, &err), ADEM_OK);
  /* a folder that does not exist: an I/O error naming the file */
  assert_int_equal(adem_mesh_write_vtu(&m, NULL, "/nonexistent_dir_adem/x.vtu", &err), ADEM_ERR_IO);
  assert_contains(err.message, "x.vtu");
  adem_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_ascii_binary_identical, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_transform, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_degenerate, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_malformed_ascii, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_binary_errors, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_groups, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_stored_normals, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_edge_kinds, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_own_vertices, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_vtu, capture_setup, capture_teardown),
  };
  return cmocka_run_group_tests(tests, group_setup, tmpdir_teardown);
}
