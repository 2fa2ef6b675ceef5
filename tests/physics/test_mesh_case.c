/* Mesh walls through case files: a box of STL faces is the box of planes, a settled bed's load on
 * the named floor group is its weight, the torques are about the documented point, a moving
 * plate carries a sphere to the closed-form speed, and rolling resistance carries over triangle
 * edges (DTK and model C). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <unistd.h>

#include "case_file.h"
#include "adem/files.h"
#include "helpers.h"
#include "plate_stl.h"
#include "tmpdir.h"
#include "world_internal.h"

static int group_setup(void **state) {
  (void)state;
  return tmpdir_make("adem_meshcase");
}

/* The set "key=DIR/file" with DIR the test's temporary folder (a static buffer per slot). */
static const char *in_tmpdir(int slot, const char *key, const char *file) {
  static char sets[4][600];
  snprintf(sets[slot], sizeof sets[slot], "%s=%s/%s", key, tmpdir, file);
  return sets[slot];
}


/* Claim: two spheres bouncing for 0.4 s in a 0.1 m box made of 12 STL triangles (cube_ascii.stl
 * scaled by 0.1) follow the trajectories they follow in the box of six planes, to round-off:
 * the faces give plane contacts with the planes' normal and overlap; corners and edges of the
 * box are concave, where each face touched is one contact as each plane is. Only the order in
 * which two simultaneous wall forces are added may differ (planes by index, faces by region key),
 * so the states agree to a few ulps times the growth of round-off over some 30 wall impacts:
 * 1e-9 of the box size (measured: identical bits). */
static void test_box_of_faces(void **state) {
  (void)state;
  adem_case *a = case_file_load("mesh-box-bounce", NULL, 0);
  const char *mesh[] = {
      "walls=[{type: mesh, name: box, material: steel, file: ../data/cube_ascii.stl, scale: 0.1}]"};
  adem_case *b = case_file_load("mesh-box-bounce", mesh, 1);
  assert_int_equal(b->world->walls.mesh.ntris, 12);
  adem_error err;
  assert_int_equal(adem_world_prepare(a->world, &err), ADEM_OK);
  assert_int_equal(adem_world_prepare(b->world, &err), ADEM_OK);
  double worst = 0.0;
  size_t impacts = 0, was = 0;
  for (int s = 0; s < 2000; ++s) {
    assert_int_equal(adem_world_step(a->world, 100, &err), ADEM_OK);
    assert_int_equal(adem_world_step(b->world, 100, &err), ADEM_OK);
    for (size_t i = 0; i < 2; ++i) {
      size_t j = b->world->p.id[i] == a->world->p.id[i] ? i : 1 - i;
      worst = fmax(worst, v3_norm(v3_sub(a->world->p.pos[i], b->world->p.pos[j])));
    }
    size_t now = adem_world_diagnostics(b->world).contacts_pw;
    if (now > was) impacts += now - was;
    was = now;
  }
  printf("# %zu wall impacts sampled; largest position difference %.3g m\n", impacts, worst);
  assert_true(impacts >= 20);
  assert_true(worst < 1e-10);
  adem_case_free(a);
  adem_case_free(b);
}


/* An ASCII STL of an open box [0, L] x [0, L] x [0, H]: solids floor, xmin, xmax, ymin, ymax,
 * two triangles each (coordinates exact in binary). */
static void write_open_box(const char *path, double L, double H) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  const char *names[5] = {"floor", "xmin", "xmax", "ymin", "ymax"};
  /* corners of each face, counter-clockwise seen from inside */
  double q[5][4][3] = {
      {{0, 0, 0}, {L, 0, 0}, {L, L, 0}, {0, L, 0}},
      {{0, 0, 0}, {0, L, 0}, {0, L, H}, {0, 0, H}},
      {{L, 0, 0}, {L, 0, H}, {L, L, H}, {L, L, 0}},
      {{0, 0, 0}, {0, 0, H}, {L, 0, H}, {L, 0, 0}},
      {{0, L, 0}, {L, L, 0}, {L, L, H}, {0, L, H}},
  };
  for (int s = 0; s < 5; ++s) {
    fprintf(f, "solid %s\n", names[s]);
    int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int t = 0; t < 2; ++t) {
      fprintf(f, "facet normal 0 0 0\nouter loop\n");
      for (int k = 0; k < 3; ++k) {
        const double *x = q[s][tri[t][k]];
        fprintf(f, "vertex %.17g %.17g %.17g\n", x[0], x[1], x[2]);
      }
      fprintf(f, "endloop\nendfacet\n");
    }
    fprintf(f, "endsolid %s\n", names[s]);
  }
  fclose(f);
}

/* The last row of a CSV as numbers, and the column index of a name in its header (-1: none). */
typedef struct csv_last {
  char header[8192];
  double value[512];
  int n;
} csv_last;

static void read_last_row(const char *path, csv_last *out) {
  char *text;
  size_t len;
  adem_error err;
  if (adem_file_read_all(path, &text, &len, &err)) fail_msg("%s", err.message);
  char *nl = strchr(text, '\n');
  assert_non_null(nl);
  snprintf(out->header, sizeof out->header, "%.*s", (int)(nl - text), text);
  char *last = text + len - 1; /* final newline */
  while (last > text && last[-1] != '\n') --last;
  out->n = 0;
  for (char *s = last; *s && *s != '\n' && out->n < 512;) {
    out->value[out->n++] = strtod(s, &s);
    if (*s == ',') ++s;
  }
  free(text);
}

static int column(const csv_last *c, const char *name) {
  size_t n = strlen(name);
  int k = 0;
  for (const char *s = c->header; *s; ++k) {
    size_t len = strcspn(s, ",");
    if (len == n && strncmp(s, name, n) == 0) return k;
    s += len + (s[len] == ',');
  }
  return -1;
}


/* Claim: a bed of 150 spheres settled for 0.5 s in a box of five named groups, with
 * frictionless walls, loads the `box.floor` group with its weight within 0.1 %: the side walls
 * can only push horizontally, so in equilibrium the floor carries all of it; what is left is
 * the bed's residual motion, measured below 1e-4 of the weight. The five groups' forces add up
 * to the file's total (box_fx_N ...) and to the total contact force on the mesh summed over the
 * contacts, to round-off (1e-12 of the weight: the sums run in different orders). */
static void test_bed_weight_on_floor(void **state) {
  (void)state;
  char stl[512], out[512];
  snprintf(stl, sizeof stl, "%s/box.stl", tmpdir);
  write_open_box(stl, 0.032, 0.1);
  snprintf(out, sizeof out, "%s/bed", tmpdir);
  const char *sets[] = {in_tmpdir(0, "walls.box.file", "box.stl"), in_tmpdir(1, "output.dir", "bed")};
  adem_case *c = case_file_load("mesh-bed", sets, 2);
  adem_error err;
  adem_run_options opt = adem_default_run_options();
  if (adem_run(c, &opt, &err)) fail_msg("%s", err.message);
  const adem_world *w = c->world;
  double weight = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) weight += 9.81 / w->p.inv_mass[i];
  char csv[600];
  snprintf(csv, sizeof csv, "%s/timeseries.csv", out);
  static csv_last row;
  read_last_row(csv, &row);
  int floor = column(&row, "box__floor_fz_N"), total = column(&row, "box_fx_N");
  assert_true(floor > 0 && total > 0);
  double load = -row.value[floor];
  printf("# floor load %.6f N, weight %.6f N, ratio %.6f; kinetic energy %.3g J\n", load, weight,
         load / weight, row.value[1]);
  assert_true(fabs(load / weight - 1.0) < 1e-3);
  /* groups add up to the file's total, component by component */
  const char *groups[5] = {"box__floor", "box__xmin", "box__xmax", "box__ymin", "box__ymax"};
  for (int d = 0; d < 3; ++d) {
    double sum = 0.0;
    for (int g = 0; g < 5; ++g) {
      char name[64];
      snprintf(name, sizeof name, "%s_f%c_N", groups[g], "xyz"[d]);
      int k = column(&row, name);
      assert_true(k > 0);
      sum += row.value[k];
    }
    assert_true(fabs(sum - row.value[total + d]) <= 1e-12 * weight);
  }
  /* and to the force of all mesh contacts on the mesh, summed over the contacts */
  adem_vec3 contacts = v3_zero(), groups_now[5], file_now;
  for (size_t k = 0; k < w->pm.l.n; ++k)
    if (w->pm.l.touching[k]) contacts = v3_sub(contacts, w->pm.l.res[k].force_a);
  adem_world_mesh_loads(w, groups_now, NULL, &file_now, NULL);
  printf("# contact sum (%.9g, %.9g, %.9g) N, file total (%.9g, %.9g, %.9g) N\n", contacts.x,
         contacts.y, contacts.z, file_now.x, file_now.y, file_now.z);
  assert_true(v3_norm(v3_sub(contacts, file_now)) <= 1e-12 * weight);
  assert_true(fabs(file_now.z + weight) < 1e-3 * weight);
  adem_case_free(c);
}


/* Claim: the torque on a group is taken about its area centroid (default) or `torque_about`,
 * the force acting at the contact point: a sphere resting at x on the floor of the open box
 * (floor centroid c, weight W) gives T = (x - c) x (0, 0, -W) on the floor group. The file's
 * total is about the file's own area centroid. Static load: 1e-6 of W |x - c|. */
static void test_torque_reference(void **state) {
  (void)state;
  for (int about = 0; about < 2; ++about) {
    const char *sets[] = {in_tmpdir(0, "walls.plate.file", "box.stl"),
                          "walls.plate.torque_about=[0, 0, 0]"};
    adem_case *c = case_file_load("mesh-torque", sets, about ? 2 : 1);
    adem_world *w = c->world;
    adem_error err;
    if (adem_world_step(w, 20000, &err)) fail_msg("%s", err.message);
    double W = 9.81 / w->p.inv_mass[0];
    adem_vec3 f[5], t[5], ff, tf;
    adem_world_mesh_loads(w, f, t, &ff, &tf);
    int floor = adem_mesh_find_group(&w->walls.mesh, "plate.floor");
    assert_true(floor >= 0);
    /* floor centroid: the middle of [0, 0.032]^2 translated */
    adem_vec3 cen = about ? v3_zero() : v3(0.026, -0.004, 0.0);
    adem_vec3 x = v3(w->p.pos[0].x, w->p.pos[0].y, 0.0);
    adem_vec3 expect = v3_cross(v3_sub(x, cen), v3(0, 0, -W));
    printf("# about %s: torque (%.9g, %.9g, %.9g), expected (%.9g, %.9g, %.9g) N m\n",
           about ? "origin" : "centroid", t[floor].x, t[floor].y, t[floor].z, expect.x, expect.y,
           expect.z);
    double scale = W * v3_norm(v3_sub(x, cen));
    assert_true(v3_norm(v3_sub(t[floor], expect)) < 1e-6 * scale);
    /* the file's total: about the area centroid of all five faces (or the given point) */
    double area = 0.0;
    adem_vec3 fc = v3_zero();
    for (size_t k = 0; k < w->walls.mesh.ntris; ++k) {
      const uint32_t *v = w->walls.mesh.tri[k];
      adem_vec3 g = v3_scale(v3_add(w->walls.mesh.vert[v[0]], v3_add(w->walls.mesh.vert[v[1]], w->walls.mesh.vert[v[2]])), 1.0 / 3.0);
      fc = v3_axpy(fc, w->walls.mesh.area[k], g);
      area += w->walls.mesh.area[k];
    }
    fc = about ? v3_zero() : v3_scale(fc, 1.0 / area);
    adem_vec3 expect_file = v3_cross(v3_sub(x, fc), v3(0, 0, -W));
    assert_true(v3_norm(v3_sub(tf, expect_file)) < 1e-6 * W * v3_norm(v3_sub(x, fc)));
    adem_case_free(c);
  }
}


/* Claim: a sphere at rest on a plate whose case-file `motion` carries it along x at V ends up
 * rolling at v = (2/7) V: friction acts at the contact point, so the angular momentum about it
 * is conserved (zero), m v r = I omega with v - omega r = V... whatever the plate's velocity
 * history, so the same for a constant `velocity` and a `table` ramping to V in 20 ms. Within
 * 1 %: the tangential spring holds a little of the motion. */
static void test_moving_plate_case(void **state) {
  (void)state;
  char stl[512];
  snprintf(stl, sizeof stl, "%s/belt.stl", tmpdir);
  write_plate(stl, 16, 0.0625);
  const char *motions[2] = {"{velocity: [0.2, 0, 0]}",
                            "{table: [[0, 0, 0, 0], [0.02, 0.2, 0, 0]]}"};
  for (int k = 0; k < 2; ++k) {
    char motion[128];
    snprintf(motion, sizeof motion, "walls.belt.motion=%s", motions[k]);
    const char *sets[] = {in_tmpdir(0, "walls.belt.file", "belt.stl"), motion};
    adem_case *c = case_file_load("mesh-belt", sets, 2);
    adem_error err;
    if (adem_world_step(c->world, 40000, &err)) fail_msg("%s", err.message);
    double v = c->world->p.vel[0].x;
    printf("# %s: v/V = %.5f (2/7 = %.5f)\n", motions[k], v / 0.2, 2.0 / 7.0);
    assert_true(fabs(v / 0.2 - 2.0 / 7.0) < 0.01 * 2.0 / 7.0);
    adem_case_free(c);
  }
}


/* Claim: rolling resistance with history (model C's spring torque, DTK's rolling displacement)
 * carries over when the contact passes from one triangle to the next on a flat plate: the
 * history is keyed by the flat region, so at every triangle change the rolling torque changes
 * from one step to the next exactly as on the infinite plane (compared bit for bit), and it is
 * not reset: at each crossing it is at least half its value on the plane (a reset would drop it
 * to the first step's increment of the spring). */
static void test_rolling_across_edges(void **state) {
  (void)state;
  char stl[512];
  snprintf(stl, sizeof stl, "%s/rollplate.stl", tmpdir);
  write_plate(stl, 32, 0.00390625);
  const char *laws[2] = {"interactions.0={materials: [glass, steel], rolling: model_c}",
                         "interactions.0={materials: [glass, steel], normal: jkr, rolling: dtk}"};
  for (int law = 0; law < 2; ++law) {
    char mesh[700];
    snprintf(mesh, sizeof mesh, "walls=[{type: mesh, name: floor, material: steel, file: %s/rollplate.stl}]",
             tmpdir);
    const char *sets[] = {laws[law], mesh};
    adem_case *a = case_file_load("mesh-rolling", sets, 1);
    adem_case *b = case_file_load("mesh-rolling", sets, 2);
    adem_error err;
    assert_int_equal(adem_world_prepare(a->world, &err), ADEM_OK);
    assert_int_equal(adem_world_prepare(b->world, &err), ADEM_OK);
    adem_vec3 prev_a = v3_zero(), prev_b = v3_zero();
    uint32_t owner = UINT32_MAX;
    int crossings = 0;
    double smallest = INFINITY;
    for (int s = 0; s < 30000; ++s) {
      if (adem_world_step(a->world, 1, &err)) fail_msg("%s", err.message);
      if (adem_world_step(b->world, 1, &err)) fail_msg("%s", err.message);
      adem_vec3 ma = a->world->p.rolling_torque[0], mb = b->world->p.rolling_torque[0];
      const adem_mesh_pairs *pm = &b->world->pm;
      bool touching = pm->l.n > 0 && pm->l.touching[0];
      if (touching && owner != UINT32_MAX && pm->owner[0] != owner) {
        ++crossings;
        /* the step-to-step change at the crossing is the plane's */
        assert_memory_equal(&mb, &ma, sizeof ma);
        assert_memory_equal(&prev_b, &prev_a, sizeof ma);
        double m = v3_norm(ma);
        if (m > 0.0) smallest = fmin(smallest, v3_norm(mb) / m);
      }
      if (touching) owner = pm->owner[0];
      prev_a = ma;
      prev_b = mb;
    }
    printf("# %s: %d triangle changes, rolling torque there %.3g of the plane's at least; "
           "last |M| = %.3g N m\n",
           laws[law], crossings, smallest, v3_norm(prev_a));
    assert_true(crossings >= 10);
    assert_true(smallest >= 0.5);
    assert_true(v3_norm(prev_a) > 0.0);
    adem_case_free(a);
    adem_case_free(b);
  }
}


/* Claim: the case-file transform is x' = R (scale x) + translate with the `rotate` entries
 * applied in order (a mapping or a list; quarter turns exact): the 0.1 m cube turned a quarter
 * about z and moved by 0.1 m in x is [0, 0.1]^3 again, exactly; turned about z then -90 deg
 * about x it lies in z in [-0.1, 0] before the shift. A plane's `motion` table and rotation
 * place it as the closed forms do: v = (0, 0, 2t) gives z = 1 + t^2, the normal turns by 0.5 t. */
static void test_transform_and_plane_motion(void **state) {
  (void)state;
  adem_case *c = case_file_load("mesh-transform", NULL, 0);
  adem_world *w = c->world;
  const adem_mesh *m = &w->walls.mesh;
  adem_vec3 lo[2] = {{1e9, 1e9, 1e9}, {1e9, 1e9, 1e9}};
  adem_vec3 hi[2] = {{-1e9, -1e9, -1e9}, {-1e9, -1e9, -1e9}};
  for (size_t t = 0; t < m->ntris; ++t)
    for (int k = 0; k < 3; ++k) {
      int g = (int)m->group[t];
      adem_vec3 x = m->vert[m->tri[t][k]];
      lo[g] = v3(fmin(lo[g].x, x.x), fmin(lo[g].y, x.y), fmin(lo[g].z, x.z));
      hi[g] = v3(fmax(hi[g].x, x.x), fmax(hi[g].y, x.y), fmax(hi[g].z, x.z));
    }
  assert_true(lo[0].x == 0.0 && lo[0].y == 0.0 && lo[0].z == 0.0);
  assert_true(hi[0].x == 0.1 && hi[0].y == 0.1 && hi[0].z == 0.1);
  /* (x, y, z) -> about z: (-y, x, z) -> -90 about x: (-y, z, -x) */
  assert_true(lo[1].x == 1.9 && hi[1].x == 2.0);
  assert_true(lo[1].y == 0.0 && hi[1].y == 0.1);
  assert_true(fabs(lo[1].z - 0.0) < 1e-17 && fabs(hi[1].z - 0.1) < 1e-17);
  adem_error err;
  if (adem_world_step(w, 500, &err)) fail_msg("%s", err.message); /* t = 0.01 s */
  const adem_plane_def *lid = &w->walls.planes[0].def;
  double t = w->time;
  printf("# lid at z = %.15g (1 + t^2 = %.15g), normal (%.15g, %.15g, %.15g)\n", lid->point.z,
         1.0 + t * t, lid->normal.x, lid->normal.y, lid->normal.z);
  assert_true(fabs(lid->point.z - (1.0 + t * t)) < 1e-15);
  assert_true(fabs(lid->normal.y - sin(0.5 * t)) < 1e-15 && fabs(lid->normal.z + cos(0.5 * t)) < 1e-15);
  adem_case_free(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_box_of_faces),
      cmocka_unit_test(test_bed_weight_on_floor),
      cmocka_unit_test(test_torque_reference),
      cmocka_unit_test(test_moving_plate_case),
      cmocka_unit_test(test_rolling_across_edges),
      cmocka_unit_test(test_transform_and_plane_motion),
  };
  return cmocka_run_group_tests(tests, group_setup, tmpdir_teardown);
}
