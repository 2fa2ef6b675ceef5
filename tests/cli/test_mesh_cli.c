/* Mesh walls in case files, bad input through the adem command: every mistake exits 2 and the
 * message names the case file's line and column and, for a bad STL, the STL file and the line
 * (ASCII) or byte offset (binary) where it goes wrong. A valid mesh case runs, writes mesh frames
 * and resumes from another working folder. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>

#include "case_file.h"
#include "cli_run.h"
#include "adem/adem.h"
#include "adem/vec3.h"
#include "world_internal.h"

/* A valid case: one sphere in the unit cube of tests/data scaled to 0.1 m, a lid that moves. */
#define base_case case_file_text("mesh-cli") /* tests/cases/mesh-cli.yaml */

static void copy_data(const char *from, const char *to) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cp '%s/tests/data/%s' '%s/meshes/%s'", ADEM_SOURCE_DIR, from, tmpdir, to);
  assert_int_equal(system(cmd), 0);
}

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_meshcli")) return -1;
  char *d = path_in_tmp("meshes");
  int r = mkdir(d, 0777);
  free(d);
  if (r) return -1;
  copy_data("cube_ascii.stl", "cube.stl");
  copy_data("bad_endloop.stl", "bad_endloop.stl");
  copy_data("nan_vertex.stl", "nan_vertex.stl");
  copy_data("two_solids.stl", "two_solids.stl");
  return 0;
}

/* `adem check` and `adem run` on the case text must exit 2 and mention every word given. */
static void expect_bad(const char *text, const char *const *words) {
  char *path = write_case("bad.yaml", text);
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 2);
  for (const char *const *w = words; *w; ++w) assert_mentions(out, *w);
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_bad'", path, tmpdir), 2);
  for (const char *const *w = words; *w; ++w) assert_mentions(out, *w);
  free(path);
}

/* Claim: the valid mesh case checks, runs (mesh frames and mesh.pvd beside the particle ones,
 * box and lid columns in the CSV) and resumes from its checkpoint when run from another working
 * folder: the checkpoint finds meshes/cube.stl through the case's absolute folder. */
static void test_valid_mesh_case(void **state) {
  (void)state;
  char *path = write_case("ok.yaml", base_case);
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  assert_mentions(out, "24 triangles in 2 groups: box, lid");
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_ok'", path, tmpdir), 0);
  const char *files[] = {"out_ok/frames/mesh_000004.vtu", "out_ok/mesh.pvd",
                         "out_ok/frames/particles_000004.vtu"};
  for (int k = 0; k < 3; ++k) {
    char *f = path_in_tmp(files[k]);
    if (!file_exists(f)) fail_msg("%s is missing", f);
    free(f);
  }
  char *csv = path_in_tmp("out_ok/timeseries.csv");
  FILE *f = fopen(csv, "r");
  assert_non_null(f);
  char header[4096];
  assert_non_null(fgets(header, sizeof header, f));
  fclose(f);
  free(csv);
  assert_mentions(header, "box_fz_N,box_tx_Nm");
  assert_mentions(header, "lid_fx_N");
  /* resuming loads the case again with its meshes, here from the working folder / */
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cd / && '%s' run --quiet --resume '%s/out_ok/checkpoint' > /dev/null 2>&1",
           ADEM_BINARY, tmpdir);
  int status = system(cmd);
  assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  free(path);
}

/* Claim: a malformed ASCII STL (a facet without `endloop`) is refused naming the case file's
 * line:column of `file`, the key, the STL file and its line. */
static void test_bad_ascii_stl(void **state) {
  (void)state;
  char *text = replaced(base_case, "file: meshes/cube.stl", "file: meshes/bad_endloop.stl");
  const char *words[] = {"bad.yaml:14:11", "walls[0].file", "bad_endloop.stl:14", "endloop", NULL};
  expect_bad(text, words);
  free(text);
  text = replaced(base_case, "file: meshes/cube.stl", "file: meshes/nan_vertex.stl");
  const char *nan_words[] = {"bad.yaml:14:11", "nan_vertex.stl:", "non-finite", NULL};
  expect_bad(text, nan_words);
  free(text);
}

/* Claim: a binary STL cut short, or with a NaN coordinate, is refused naming the case file's
 * line:column, the STL file and the byte offset. */
static void test_bad_binary_stl(void **state) {
  (void)state;
  unsigned char data[84 + 2 * 50];
  memset(data, 0, sizeof data);
  uint32_t n = 2;
  memcpy(data + 80, &n, 4);
  float tri[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  for (int t = 0; t < 2; ++t) memcpy(data + 84 + 50 * t, tri, sizeof tri);
  /* 1.5 triangles of the 2 announced */
  char *p = write_file("meshes/cut.stl", data, 84 + 75);
  free(p);
  char *text = replaced(base_case, "file: meshes/cube.stl", "file: meshes/cut.stl");
  const char *words[] = {"bad.yaml:14:11", "cut.stl", "byte", "134", NULL};
  expect_bad(text, words);
  free(text);
  float nan = NAN;
  memcpy(data + 84 + 50 + 12 + 4, &nan, 4); /* triangle 1, vertex 0, y at byte 150 */
  p = write_file("meshes/nan.stl", data, sizeof data);
  free(p);
  text = replaced(base_case, "file: meshes/cube.stl", "file: meshes/nan.stl");
  const char *nan_words[] = {"bad.yaml:14:11", "nan.stl", "byte offset 150", "non-finite", NULL};
  expect_bad(text, nan_words);
  free(text);
}

/* Claim: a group name used twice is refused: two walls given the same name (at the second
 * name's line), and a file whose solids make group names another file already has (at the
 * second `file`, naming the solid's line). */
static void test_group_name_twice(void **state) {
  (void)state;
  char *text = replaced(base_case, "name: lid", "name: box");
  const char *words[] = {"bad.yaml:17:11", "duplicate wall name `box`", NULL};
  expect_bad(text, words);
  free(text);
  char *t1 = replaced(base_case, "    name: box\n    material: steel\n    file: meshes/cube.stl\n",
                      "    material: steel\n    file: meshes/two_solids.stl\n");
  char *t2 = replaced(t1, "    name: lid\n    material: steel\n    file: meshes/cube.stl\n",
                      "    material: steel\n    file: meshes/two_solids.stl\n");
  const char *solid_words[] = {"bad.yaml:17:11", "two_solids.stl:1", "two_solids.floor",
                               "already used", NULL};
  expect_bad(t2, solid_words);
  free(t1);
  free(t2);
}

/* Claim: a motion table whose times do not increase is refused at the offending row; a moving
 * mesh without its own vertices and a plane with both `velocity` and `motion` are refused too. */
static void test_bad_motion(void **state) {
  (void)state;
  char *text = replaced(base_case, "[[0, 0, 0, 0], [0.002, 0, 0, -1]]",
                        "[[0, 0, 0, 0], [0.002, 0, 0, -1], [0.001, 0, 0, 0]]");
  const char *words[] = {"bad.yaml:22:", "walls[1].motion.table[2]", "not ordered in time",
                         "0.001", NULL};
  expect_bad(text, words);
  free(text);
  text = replaced(base_case, "    motion:", "    own_vertices: false\n    motion:");
  const char *own_words[] = {"bad.yaml:22:", "own_vertices: true", NULL};
  expect_bad(text, own_words);
  free(text);
  text = replaced(base_case, "time:\n",
                  "  - {type: plane, name: floor, material: steel, point: [0, 0, -1],\n"
                  "     normal: [0, 0, 1], velocity: [0, 0, 1], motion: {velocity: [1, 0, 0]}}\n"
                  "time:\n");
  const char *plane_words[] = {"bad.yaml:24:54", "either `velocity` or `motion`", NULL};
  expect_bad(text, plane_words);
  free(text);
  /* velocities and positions together; a positions row that is not [t, x, y, z] */
  text = replaced(base_case, "motion: {table: [[0, 0, 0, 0], [0.002, 0, 0, -1]]}",
                  "motion: {table: [[0, 0, 0, 0]], positions: [[0, 0, 0, 0], [0.002, 0, 0, -1]]}");
  const char *both_words[] = {"walls[1].motion.positions", "not two of them", "`positions`", NULL};
  expect_bad(text, both_words);
  free(text);
  text = replaced(base_case, "motion: {table: [[0, 0, 0, 0], [0.002, 0, 0, -1]]}",
                  "motion: {positions: [[0, 0, 0, 0], [0.002, 0, -1]]}");
  const char *row_words[] = {"walls[1].motion.positions[1]", "[t, x, y, z]", "(s, m)", NULL};
  expect_bad(text, row_words);
  free(text);
}

/* Claim: `adem check` counts the mesh pairs in reach (a sphere 0.2 mm above the box's floor: 2,
 * the floor's two triangles), prints the domain particles must stay in, and gives a rotating
 * wall's rate in each stage that changes it, not only the last one's. */
static void test_check_mesh_pairs_rates_domain(void **state) {
  (void)state;
  char *t1 = replaced(base_case, "[0.05, 0.05, 0.05], radius: 0.005", "[0.05, 0.05, 0.0052], radius: 0.005");
  char *t2 = replaced(t1, "motion: {table: [[0, 0, 0, 0], [0.002, 0, 0, -1]]}",
                      "motion: {rotation: {axis: [0, 0, 1], center: [0.05, 0.05, 0.09], speed: 1}}");
  char *t3 = replaced(t2, "time:\n", "stages:\n  - {name: slow, duration: 0.002}\n"
                                     "  - {name: fast, set: {walls.lid.motion: {rotation: {axis: [0, 0, 1], "
                                     "center: [0.05, 0.05, 0.09], speed: 2}}}}\ntime:\n");
  char *path = write_case("pairs.yaml", t3);
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  assert_mentions(out, "0 particle pairs, 0 plane pairs and 2 mesh pairs within reach");
  assert_mentions(out, "it turns at 1 rad/s, then 2 rad/s from t = 0.002008 s (stage `fast`)");
  assert_mentions(out, "domain      (");
  free(path);
  free(t1);
  free(t2);
  free(t3);
}

/* Claim: `adem check` shows the geometry: each mesh group's box, where the moving lid is at the
 * start, at its table's knot and at the end (the integral of its velocity table: -1 mm at
 * 2 ms), and warns about fill regions that cross a mesh or a plane or lie outside
 * the closed mesh that could hold them; a region inside the box is clear. */
static void test_check_geometry(void **state) {
  (void)state;
  char *path = write_case("geom.yaml", base_case);
  char *out;
  assert_int_equal(adem(&out, "check '%s'", path), 0);
  assert_mentions(out, "box                      12 triangles, (0, 0, 0) .. (0.1, 0.1, 0.1) m");
  /* the end is the last step's time, at or just after time.end */
  assert_mentions(out, "lid (mesh group, centre of its box): (0.05, 0.05, 0.09) at 0 s, "
                       "(0.05, 0.05, 0.089) at 0.002 s, (0.05, 0.05, 0.08");
  assert_mentions(out, "s (end)");
  free(path);
  const char *fill =
      "  - type: random\n"
      "    material: glass\n"
      "    count: 1\n"
      "    radius: {distribution: constant, value: 0.002}\n";
  const struct {
    const char *region, *word1, *word2;
  } cases[] = {
      {"    region: {shape: box, min: [0.01, 0.01, 0.01], max: [0.03, 0.03, 0.03]}\n",
       "particles[1].region (a box): clear of every wall", NULL},
      {"    region: {shape: box, min: [0.05, 0.05, 0.05], max: [0.2, 0.2, 0.08]}\n",
       "particles[1].region (a box) crosses mesh group `box` (", "spheres may be placed on both sides"},
      {"    region: {shape: cylinder, start: [0.5, 0.5, 0.5], end: [0.5, 0.5, 0.55], radius: 0.02}\n",
       "particles[1].region (a cylinder) lies outside every closed mesh wall that could hold it (`box`)",
       NULL},
      {"    region: {shape: cylinder, start: [0.03, 0.03, 0.01], end: [0.03, 0.03, 0.05], radius: 0.01}\n",
       "particles[1].region (a cylinder) crosses plane `shelf`", NULL},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    char add[1024];
    snprintf(add, sizeof add, "%s%swalls:\n", fill, cases[k].region);
    char *t1 = replaced(base_case, "walls:\n", add);
    char *t2 = replaced(t1, "time:\n", "  - {type: plane, name: shelf, material: steel, point: [0, 0, 0.03],\n"
                                       "     normal: [0, 0, 1], active: true}\n"
                                       "time:\n");
    /* the shelf is in the way of the first sphere only for the plane case */
    char *t3 = k == 3 ? t2 : replaced(t2, "point: [0, 0, 0.03]", "point: [0, 0, -1]");
    path = write_case("geom.yaml", t3);
    adem(&out, "check '%s'", path);
    assert_mentions(out, cases[k].word1);
    if (cases[k].word2) assert_mentions(out, cases[k].word2);
    if (k == 0) assert_false(mentions(out, "warning: particles[1]"));
    free(path);
    free(t1);
    if (t3 != t2) free(t3);
    free(t2);
  }
}

/* Claim: a lid moved by a table of positions is exactly at the last row's displacement once the
 * table is over (bit for bit: its vertices are the loaded ones plus that displacement), and at
 * rest. */
static void test_positions_motion(void **state) {
  (void)state;
  char *text = replaced(base_case, "motion: {table: [[0, 0, 0, 0], [0.002, 0, 0, -1]]}",
                        "motion: {positions: [[0.001, 0, 0, 0], [0.002, 0.001, 0, -0.003]]}");
  char *path = write_case("positions.yaml", text);
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_file(path, NULL, 0, &c, &err)) fail_msg("%s", err.message);
  adem_world *w = c->world;
  int lid = adem_mesh_find_group(&w->walls.mesh, "lid");
  assert_true(lid >= 0);
  const adem_mesh_group *g = &w->walls.mesh.groups[lid];
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  uint64_t n = (uint64_t)llround(0.003 / adem_world_dt(w));
  assert_int_equal(adem_world_step(w, n, &err), ADEM_OK);
  for (uint32_t v = g->vert_first; v < g->vert_first + g->vert_count; ++v) {
    adem_vec3 want = v3_add(w->walls.mesh_vert0[v], v3(0.001, 0.0, -0.003));
    assert_memory_equal(&w->walls.mesh.vert[v], &want, sizeof want);
  }
  adem_vec3 vel = adem_motion_velocity(&w->walls.mesh_motion[lid], w->time);
  assert_true(v3_norm(vel) == 0.0);
  adem_case_free(c);
  free(path);
  free(text);
}

/* Claim: a sphere that starts cutting into a mesh face is refused when the run starts, naming
 * the particle and the group. */
static void test_particle_in_mesh(void **state) {
  (void)state;
  char *text = replaced(base_case, "position: [0.05, 0.05, 0.05]", "position: [0.05, 0.05, 0.003]");
  char *path = write_case("bad.yaml", text);
  char *out;
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/out_bad'", path, tmpdir), 2);
  assert_mentions(out, "particle id 0");
  assert_mentions(out, "mesh group 'box'");
  assert_mentions(out, "allowed 0 by limits.initial_overlap"); /* the key that allows it */
  assert_mentions(out, "back at its file placement");          /* why a state import may overlap */
  free(path);
  free(text);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_valid_mesh_case),
      cmocka_unit_test(test_bad_ascii_stl),
      cmocka_unit_test(test_bad_binary_stl),
      cmocka_unit_test(test_group_name_twice),
      cmocka_unit_test(test_bad_motion),
      cmocka_unit_test(test_positions_motion),
      cmocka_unit_test(test_check_geometry),
      cmocka_unit_test(test_check_mesh_pairs_rates_domain),
      cmocka_unit_test(test_particle_in_mesh),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
