/* The case-file loader: what a good case builds, how each kind of bad input is reported
 * (file:line:column, key path, what is allowed), --set overrides, seeded random fills and the
 * reference page generated from the schema table. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>
#include <time.h>

#include "adem/adem.h"
#include "case_file.h"
#include "case_text.h"
#include "log_capture.h"
#include "world_internal.h"

/* Two glass spheres above a steel floor (tests/cases/loader-two-spheres.yaml); the messages
 * below name its lines and columns. */
#define BASE case_file_text("loader-two-spheres") /* 22 */

static adem_case *load_ok(const char *text, const char *const *sets, int nsets) {
  adem_case *c = NULL;
  adem_error err = {ADEM_OK, ""};
  adem_status st = adem_case_load_string(text, "test.yaml", sets, nsets, &c, &err);
  if (st != ADEM_OK) fail_msg("load failed (%d): %s", (int)st, err.message);
  assert_non_null(c);
  return c;
}

/* Loads text (with sets), expects ADEM_ERR_INPUT and a message holding each word. */
static void expect_error_sets(const char *text, const char *const *sets, int nsets,
                              const char *const *words) {
  adem_case *c = (adem_case *)1;
  adem_error err = {ADEM_OK, ""};
  adem_status st = adem_case_load_string(text, "test.yaml", sets, nsets, &c, &err);
  printf("# %s\n", err.message);
  assert_int_equal(st, ADEM_ERR_INPUT);
  assert_int_equal(err.status, ADEM_ERR_INPUT);
  assert_null(c);
  for (; *words; ++words) assert_contains(err.message, *words);
}

#define WORDS(...) ((const char *const[]){__VA_ARGS__, NULL})

/* The two spheres' text with one replacement must fail naming all the words. */
static void expect_bad(const char *from, const char *to, const char *const *words) {
  char *text = replaced(BASE, from, to);
  expect_error_sets(text, NULL, 0, words);
  free(text);
}

/* Claim: a good case builds what it says: particle count, materials, normalised wall normal,
 * derived defaults (name from the file, out/<name>, intervals from time.end), and the automatic
 * step equals the world's proposal at v_ref = sqrt(2 g H) (H = 0.101 m: floor to sphere top). */
static void test_good_case(void **state) {
  (void)state;
  adem_case *c = load_ok(BASE, NULL, 0);
  adem_world *w = c->world;
  assert_int_equal(adem_world_particle_count(w), 2);
  assert_int_equal(w->mat.n, 2);
  assert_true(w->mat.m[1].def.rigid);
  assert_int_equal(w->walls.nplanes, 1);
  assert_string_equal(w->walls.planes[0].def.name, "floor");
  assert_float_equal(w->walls.planes[0].def.normal.z, 1.0, 1e-15);
  assert_string_equal(c->name, "test");
  assert_string_equal(c->output.dir, "out/test");
  assert_float_equal(c->end_time, 0.5, 0);
  assert_float_equal(c->output.frame_interval, 0.005, 1e-15);
  assert_float_equal(c->output.csv_interval, 0.0005, 1e-15);
  assert_float_equal(c->output.checkpoint_interval, 0.05, 1e-15);
  assert_int_equal(c->output.plot, 0);
  assert_int_equal(c->seed, 1);
  assert_float_equal(w->gravity.z, -9.81, 0);
  assert_float_equal(w->nb.skin_fraction, 0.2, 0);
  assert_float_equal(w->max_overlap_ratio, 0.2, 0);
  assert_true(c->dt_auto);
  double v_ref = sqrt(2.0 * 9.81 * 0.101);
  assert_float_equal(c->estimate.v_ref, v_ref, 1e-12 * v_ref);
  adem_step_estimate e = adem_world_estimate_step(w, v_ref);
  assert_float_equal(adem_world_dt(c->world), e.dt, 0);
  assert_float_equal(adem_world_dt(w), e.dt, 0);
  assert_float_equal(c->dt_user_ratio, 1.0, 0);
  assert_string_equal(c->source, BASE);
  assert_int_equal(c->nsets, 0);
  /* The derived escape box holds the free fall over time.end: 0.5 g t^2 = 1.23 m. */
  assert_true(w->has_domain);
  assert_true(w->domain_lo.z < -1.2 && w->domain_hi.z > 1.3);
  /* and the world accepts it */
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  adem_case_free(c);
  assert_string_equal(logged, "");
}

/* Claim: every key of the format is read into the world: interactions, groups, lattice with a
 * count cap, boxes, domain, limits, neighbour skin, output settings, a user step. */
static void test_full_case(void **state) {
  (void)state;
  adem_case *c = case_file_load("loader-full", NULL, 0);
  adem_world *w = c->world;
  /* 4 sites per axis: (0.01 - 0.002) / 0.0025 = 3.2 -> 4; first set capped at 20 */
  assert_int_equal(adem_world_particle_count(w), 20 + 64);
  assert_string_equal(c->name, "full");
  assert_int_equal(c->seed, 42);
  const adem_material_def *g = &w->mat.m[0].def;
  assert_float_equal(g->restitution, 0.9, 0);
  assert_float_equal(g->friction, 0.3, 0);
  assert_float_equal(g->param[ADEM_PARAM_SURFACE_ENERGY], 0.1, 0);
  assert_float_equal(g->param[ADEM_PARAM_ADHESION_HYSTERESIS], 0.2, 0);
  assert_float_equal(g->stiffness_factor, 0.5, 0);
  assert_float_equal(g->param[ADEM_PARAM_ROLLING_FRICTION], 0.01, 0);
  assert_float_equal(g->param[ADEM_PARAM_ROLLING_DAMPING], 0.3, 0);
  assert_float_equal(w->mat.m[1].def.young, 2e11, 0);
  assert_int_equal(w->mat.ndefs, 2);
  const adem_interaction_def *i0 = &w->mat.defs[0], *i1 = &w->mat.defs[1];
  assert_int_equal(i0->material_a, 0);
  assert_int_equal(i0->material_b, 1);
  assert_float_equal(i0->restitution, 0.4, 0);
  assert_float_equal(i0->friction, 0.2, 0);
  assert_int_equal(i0->normal, ADEM_NORMAL_JKR);
  assert_int_equal(i0->rolling, ADEM_ROLLING_C);
  assert_true(i1->restitution < 0 && i1->friction < 0); /* derived from the materials */
  assert_int_equal(i1->normal, ADEM_NORMAL_HERTZ);
  assert_int_equal(i1->rolling, ADEM_ROLLING_BROF);
  assert_int_equal(w->ngroups, 2);
  assert_float_equal(w->groups[1].external_force.z, 1e-6, 0);
  assert_int_equal(w->p.group[0], 1);
  assert_int_equal(w->p.group[20], 0);
  /* lattice order: x fastest, first centre at min + r */
  assert_float_equal(w->p.pos[0].x, 0.001, 1e-15);
  assert_float_equal(w->p.pos[1].x, 0.0035, 1e-15);
  assert_float_equal(w->p.pos[4].y, 0.0035, 1e-15);
  assert_float_equal(w->p.pos[16].z, 0.0035, 1e-15);
  assert_float_equal(w->p.vel[0].z, -1.0, 0);
  assert_int_equal(w->walls.nplanes, 6);
  assert_float_equal(w->gravity.z, -1.0, 0);
  assert_true(w->has_domain);
  assert_float_equal(w->domain_hi.z, 2.0, 0);
  assert_float_equal(w->nb.skin_fraction, 0.3, 0);
  assert_float_equal(w->max_overlap_ratio, 0.05, 0);
  assert_string_equal(c->output.dir, "/tmp/adem_full");
  assert_float_equal(c->output.frame_interval, 0.001, 0);
  assert_float_equal(c->output.csv_interval, 0.0, 0);
  assert_float_equal(c->output.checkpoint_interval, 0.002, 0);
  assert_int_equal(c->output.plot, 1);
  assert_false(c->dt_auto);
  assert_float_equal(adem_world_dt(c->world), 1e-6, 0);
  assert_float_equal(c->estimate.v_ref, 2.0, 0);
  assert_float_equal(c->dt_user_ratio, 1e-6 / c->estimate.dt, 1e-12);
  adem_error err;
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  adem_case_free(c);
}

/* Claim: a step above the proposal is kept but warned about, saying by how much and why. */
static void test_step_too_large_warns(void **state) {
  (void)state;
  /* above the proposal (3.4e-6 s), below the stability limit t_c/5 (3.4e-5 s): a warning */
  char *text = replaced(BASE, "  end: 0.5\n", "  end: 0.5\n  step: 2e-5\n");
  adem_case *c = load_ok(text, NULL, 0);
  assert_float_equal(adem_world_dt(c->world), 2e-5, 0);
  assert_true(c->dt_user_ratio > 1.0);
  assert_float_equal(c->dt_user_ratio, 2e-5 / c->estimate.dt, 1e-12);
  assert_contains(logged, "W ");
  assert_contains(logged, "time.step 2e-05 s is ");
  assert_contains(logged, "x the proposed");
  assert_contains(logged, "t_collision/50");
  assert_contains(logged, "the limit t_collision/5");
  assert_contains(logged, "test.yaml:23:9");
  adem_case_free(c);
  free(text);
  /* above the limit: refused, unless limits.allow_large_step */
  expect_bad("  end: 0.5\n", "  end: 0.5\n  step: 1e-3\n",
             WORDS("test.yaml:23:9: ", "time.step", "29.80x the limit t_collision/5",
                   "limits.allow_large_step: true"));
  text = replaced(BASE, "  end: 0.5\n", "  end: 0.5\n  step: 1e-3\nlimits: {allow_large_step: true}\n");
  c = load_ok(text, NULL, 0);
  assert_float_equal(adem_world_dt(c->world), 1e-3, 0);
  assert_contains(logged, "and the step is above it (limits.allow_large_step)");
  adem_case_free(c);
  free(text);
}

/* Claim: each kind of bad input is refused with ADEM_ERR_INPUT, and the message names the place
 * (line:column), the key path and what is allowed. */
static void test_unknown_key(void **state) {
  (void)state;
  expect_bad("    poisson_ratio: 0.25\n", "    poison_ratio: 0.25\n",
             WORDS("test.yaml:5:5: ", "materials[0].poison_ratio", "unknown key",
                   "did you mean `poisson_ratio`?", "youngs_modulus"));
  expect_bad("time:\n", "tme:\n", WORDS("test.yaml:21:1: ", "tme", "did you mean `time`?"));
  /* a key of another type of set */
  expect_bad("    spheres:\n", "    spacing: 1\n    spheres:\n",
             WORDS("test.yaml:12:5: ", "particles[0].spacing", "does not apply to type `list`",
                   "lattice"));
  expect_bad("      - {position: [0, 0, 0.1], radius: 0.001}",
             "      - {position: [0, 0, 0.1], radius: 0.001, vel: [0, 0, 1]}",
             WORDS("test.yaml:13:48: ", "particles[0].spheres[0].vel", "velocity"));
  expect_bad("  end: 0.5\n", "  end: 0.5\n  end: 0.6\n",
             WORDS("test.yaml:23:3: ", "time.end", "duplicate key", "line 22:3"));
}

static void test_wrong_type(void **state) {
  (void)state;
  expect_bad("density: 2500", "density: heavy",
             WORDS("test.yaml:3:14: ", "materials[0].density", "expected a number > 0 (kg/m^3)",
                   "`heavy`"));
  expect_bad("density: 2500", "density: \"2500\"",
             WORDS("test.yaml:3:14: ", "materials[0].density", "quoted string"));
  expect_bad("point: [0, 0, 0]", "point: [0, 0]",
             WORDS("test.yaml:19:12: ", "walls[0].point", "[x, y, z] of 3 numbers (m), got a list of 2 items"));
  expect_bad("point: [0, 0, 0]", "point: [0, zero, 0]",
             WORDS("test.yaml:19:16: ", "walls[0].point[1]", "expected a number"));
  expect_bad("rigid: true", "rigid: maybe", WORDS("test.yaml:8:12: ", "materials[1].rigid", "true or false"));
  expect_bad("type: plane", "type: sphere",
             WORDS("test.yaml:16:11: ", "walls[0].type", "one of: plane, box"));
  expect_bad("materials:\n", "seed: -3\nmaterials:\n", WORDS("test.yaml:1:7: ", "seed", "integer >= 0"));
  expect_bad("walls:\n  - type: plane\n    name: floor\n    material: steel\n    point: [0, 0, 0]\n"
             "    normal: [0, 0, 2]\n",
             "walls: floor\n",
             WORDS("test.yaml:15:8: ", "walls: expected a list of mappings, got `floor`"));
  expect_bad("name: glass", "name: 9glass", WORDS("test.yaml:2:11: ", "materials[0].name", "a name"));
}

static void test_missing_required(void **state) {
  (void)state;
  expect_bad("    youngs_modulus: 1.0e7\n", "",
             WORDS("test.yaml:2:5: ", "materials[0].youngs_modulus", "required value is missing",
                   "unless `rigid: true`"));
  expect_bad("time:\n  end: 0.5\n", "", WORDS("test.yaml:1:1: ", "time", "required value is missing"));
  expect_bad("  end: 0.5\n", "  step: auto\n", WORDS("test.yaml:22:3: ", "time.end", "required"));
  expect_bad("  - type: list\n    material: glass\n", "  - material: glass\n",
             WORDS("particles[0].type", "required", "list, lattice, random"));
  expect_bad("radius: 0.001}\n      - {position: [0.01", "}\n      - {position: [0.01",
             WORDS("particles[0].spheres[0].radius", "required", "test.yaml:13:9: "));
}

static void test_out_of_range(void **state) {
  (void)state;
  expect_bad("radius: 0.001}", "radius: 0}",
             WORDS("test.yaml:13:41: ", "particles[0].spheres[0].radius", "must be > 0 (m)"));
  expect_bad("radius: 0.001}", "radius: -1e-3}", WORDS("particles[0].spheres[0].radius", "-1e-3"));
  expect_bad("density: 2500", "density: 0", WORDS("test.yaml:3:14: ", "materials[0].density", "> 0"));
  expect_bad("poisson_ratio: 0.25", "poisson_ratio: 0.5",
             WORDS("test.yaml:5:20: ", "materials[0].poisson_ratio", "in (-1, 0.5)"));
  expect_bad("poisson_ratio: 0.25", "poisson_ratio: -1", WORDS("materials[0].poisson_ratio", "(-1, 0.5)"));
  expect_bad("restitution: 0.5", "restitution: 0",
             WORDS("test.yaml:6:18: ", "materials[0].restitution", "in (0, 1]"));
  expect_bad("restitution: 0.5", "restitution: 1.5", WORDS("materials[0].restitution", "1.5", "(0, 1]"));
  expect_bad("  end: 0.5", "  end: 0", WORDS("time.end", "> 0 (s)"));
  expect_bad("normal: [0, 0, 2]", "normal: [0, 0, 0]",
             WORDS("test.yaml:20:13: ", "walls[0].normal", "non-zero"));
}

static void test_bad_names(void **state) {
  (void)state;
  expect_bad("    material: glass\n    spheres:", "    material: glas\n    spheres:",
             WORDS("test.yaml:11:15: ", "particles[0].material", "unknown material `glas`",
                   "did you mean `glass`?", "glass, steel"));
  expect_bad("    material: steel\n", "    material: copper\n",
             WORDS("test.yaml:18:15: ", "walls[0].material", "unknown material `copper`"));
  expect_bad("    material: glass\n    spheres:", "    material: glass\n    group: tracer\n    spheres:",
             WORDS("test.yaml:12:12: ", "particles[0].group", "unknown group `tracer`", "default"));
  expect_bad("name: steel", "name: glass",
             WORDS("test.yaml:7:11: ", "materials[1].name", "duplicate material name `glass`",
                   "line 2:5"));
  expect_bad("walls:\n", "groups:\n  - name: a\n  - name: a\nwalls:\n",
             WORDS("test.yaml:17:11: ", "groups[1].name", "duplicate group name `a`"));
  expect_bad("time:\n", "  - {type: plane, name: floor, material: steel, point: [0, 0, 1], normal: [0, 0, -1]}\ntime:\n",
             WORDS("test.yaml:21:", "walls[1].name", "duplicate wall name `floor`"));
  expect_bad("time:\n", "interactions:\n  - {materials: [glass, steel]}\n  - {materials: [steel, glass]}\ntime:\n",
             WORDS("test.yaml:23:5: ", "interactions[1]", "second interaction", "line 22:5"));
  expect_bad("time:\n", "interactions:\n  - {materials: [glass, stel]}\ntime:\n",
             WORDS("test.yaml:22:25: ", "interactions[0].materials[1]", "did you mean `steel`?"));
  expect_bad("time:\n", "interactions:\n  - {materials: [glass, steel], normal: hertzz}\ntime:\n",
             WORDS("interactions[0].normal", "`hertzz` is not one of: hertz, jkr",
                   "did you mean `hertz`?"));
  /* particles need a density and a non-rigid material */
  expect_bad("    material: glass\n    spheres:", "    material: steel\n    spheres:",
             WORDS("test.yaml:11:15: ", "particles[0].material", "rigid"));
  expect_bad("    density: 2500\n", "", WORDS("particles[0].material", "no `density`", "line 2:5"));
}

static void test_bad_geometry(void **state) {
  (void)state;
  /* overlapping spheres of one list: both are named */
  expect_bad("[0.01, 0, 0.1], radius: 0.001}", "[0.0015, 0, 0.1], radius: 0.001}",
             WORDS("test.yaml:14:9: ", "particles[0].spheres[1]", "overlaps particles[0].spheres[0]",
                   "line 13:9"));
  const char *lattice = case_file_text("loader-lattice");
  adem_case *c = load_ok(lattice, NULL, 0);
  assert_int_equal(c->world->p.n, 64);
  adem_case_free(c);
  char *t = replaced(lattice, "spacing: 0.0025", "spacing: 0.0015");
  expect_error_sets(t, NULL, 0,
                    WORDS("test.yaml:3:62: ", "particles[0].spacing", "less than the diameter"));
  free(t);
  t = replaced(lattice, "max: [0.01, 0.01, 0.01]", "max: [0.01, 0, 0.01]");
  expect_error_sets(t, NULL, 0, WORDS("test.yaml:4:27: ", "particles[0].max", "greater than `min`", "y:"));
  free(t);
  t = replaced(lattice, "spacing: 0.0025", "spacing: 0.003");
  char *t2 = replaced(t, "max: [0.01, 0.01, 0.01]", "max: [0.01, 0.0015, 0.01]");
  expect_error_sets(t2, NULL, 0, WORDS("particles[0].max", "narrower than one sphere", "along y"));
  free(t);
  free(t2);
  expect_bad("time:\n", "  - {type: box, material: steel, min: [0, 0, 0], max: [1, 1, 0]}\ntime:\n",
             WORDS("test.yaml:21:", "walls[1].max", "greater than `min`", "z:"));
}

/* Claim: unreadable input is refused: a missing file (path and the system's reason), a YAML
 * syntax error (libyaml's problem at its line:column), an empty case, two documents. */
static void test_bad_files(void **state) {
  (void)state;
  adem_case *c = (adem_case *)1;
  adem_error err = {ADEM_OK, ""};
  assert_int_equal(adem_case_load_file("/nonexistent/dir/case.yaml", NULL, 0, &c, &err),
                   ADEM_ERR_INPUT);
  assert_null(c);
  assert_contains(err.message, "/nonexistent/dir/case.yaml");
  assert_contains(err.message, "No such file or directory");
  expect_error_sets("materials:\n  - name: glass\n    density: [2500\n", NULL, 0,
                    WORDS("test.yaml:4:1: ", "YAML syntax error"));
  expect_error_sets("a: b\n  c: d\n", NULL, 0, WORDS("test.yaml:2:4: ", "YAML syntax error"));
  expect_error_sets("", NULL, 0, WORDS("test.yaml:1:1: ", "time", "required value is missing"));
  expect_error_sets("- 1\n- 2\n", NULL, 0, WORDS("test.yaml:1:1: ", "expected a mapping"));
  char *two = replaced(BASE, "time:\n", "---\ntime:\n");
  expect_error_sets(two, NULL, 0, WORDS("test.yaml:22:1: ", "second YAML document"));
  free(two);
}

/* Claim: a case file on disk loads like its text; the name defaults to the file's stem. */
static void test_load_file(void **state) {
  (void)state;
  char path[] = "/tmp/adem_case_XXXXXX";
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  FILE *f = fdopen(fd, "w");
  assert_non_null(f);
  fputs(BASE, f);
  fclose(f);
  adem_case *c = NULL;
  adem_error err = {ADEM_OK, ""};
  assert_int_equal(adem_case_load_file(path, NULL, 0, &c, &err), ADEM_OK);
  assert_string_equal(c->path, path);
  assert_string_equal(c->name, path + 5); /* stem of /tmp/adem_case_XXXXXX */
  assert_string_equal(c->source, BASE);
  assert_int_equal(adem_world_particle_count(c->world), 2);
  adem_case_free(c);
  remove(path);
  /* text without a file name: messages say <case>, the name is `case` */
  assert_int_equal(adem_case_load_string(BASE, NULL, NULL, 0, &c, &err), ADEM_OK);
  assert_string_equal(c->path, "<case>");
  assert_string_equal(c->name, "case");
  assert_string_equal(c->output.dir, "out/case");
  adem_case_free(c);
}

/* Claim: --set overrides change the document before validation: scalars, list items by name and
 * by index, flow sequences, keys the file lacks (with their parent mapping); the strings are kept. */
static void test_set_overrides(void **state) {
  (void)state;
  const char *sets[] = {"time.end=2",
                        "materials.glass.friction=0.3",
                        "materials.0.restitution=0.7",
                        "output.dir=/tmp/x",
                        "gravity=[0,0,-1]",
                        "neighbor.skin=0.35",
                        "particles.0.spheres.1.velocity=[1, 2, 3]",
                        "walls.floor.point=[0, 0, -0.5]",
                        "name=renamed"};
  int n = (int)(sizeof sets / sizeof sets[0]);
  adem_case *c = load_ok(BASE, sets, n);
  adem_world *w = c->world;
  assert_float_equal(c->end_time, 2.0, 0);
  assert_float_equal(w->mat.m[0].def.friction, 0.3, 0);
  assert_float_equal(w->mat.m[0].def.restitution, 0.7, 0);
  assert_string_equal(c->output.dir, "/tmp/x");
  assert_float_equal(w->gravity.z, -1.0, 0);
  assert_float_equal(w->nb.skin_fraction, 0.35, 0);
  assert_float_equal(w->p.vel[1].y, 2.0, 0);
  assert_float_equal(w->walls.planes[0].def.point.z, -0.5, 0);
  assert_string_equal(c->name, "renamed");
  assert_int_equal(c->nsets, n);
  for (int k = 0; k < n; ++k) assert_string_equal(c->sets[k], sets[k]);
  assert_string_equal(c->source, BASE); /* the text itself is unchanged */
  /* loading again from what the case kept gives the same case (checkpoints rely on it) */
  adem_case *d = load_ok(c->source, (const char *const *)c->sets, c->nsets);
  assert_float_equal(d->end_time, 2.0, 0);
  assert_float_equal(d->world->p.vel[1].y, 2.0, 0);
  adem_case_free(d);
  adem_case_free(c);
}

/* Claim: an interaction found by its name takes a --set however the list is ordered, and a
 * second interaction of the same name is refused naming the first. */
static void test_interaction_names(void **state) {
  (void)state;
  char text[2048];
  snprintf(text, sizeof text, "%.*sinteractions:\n  - {name: glass-glass, materials: [glass, glass]}\n"
                              "  - {name: glass-floor, materials: [glass, steel], friction: 0.2}\ntime:\n  end: 0.5\n",
           (int)(strstr(BASE, "time:") - BASE), BASE);
  const char *sets[] = {"interactions.glass-floor.friction=0.35"};
  adem_case *c = load_ok(text, sets, 1);
  const adem_interaction_def *d = &c->world->mat.defs[1];
  assert_true(d->material_a + d->material_b == 1); /* glass (0) and steel (1) */
  assert_float_equal(d->friction, 0.35, 0);
  assert_true(c->world->mat.defs[0].friction < 0); /* glass-glass untouched: derived */
  adem_case_free(c);
  expect_error_sets(text, WORDS("interactions.glass-flor.friction=0.35"), 1,
                    WORDS("`glass-flor`", "glass-glass, glass-floor"));
  snprintf(text, sizeof text, "%.*sinteractions:\n  - {name: a, materials: [glass, glass]}\n"
                              "  - {name: a, materials: [glass, steel]}\ntime:\n  end: 0.5\n",
           (int)(strstr(BASE, "time:") - BASE), BASE);
  expect_error_sets(text, NULL, 0, WORDS("interactions[1].name", "duplicate interaction name `a`", "first at line 22:12"));
}

/* Claim: a material's rolling friction that no pair can read (every pair keeps rolling: none)
 * is warned about, naming the key; an interaction or a later stage that chooses a rolling law
 * silences it, and so does a pair that chose another law of the slot (BROF leaves model C's
 * rolling_damping unread on purpose). */
static void test_unused_law_params_warned(void **state) {
  (void)state;
  char text[2048];
  const char *mat = strstr(BASE, "    restitution: 0.5\n");
  size_t head = (size_t)(mat - BASE) + strlen("    restitution: 0.5\n");
  const char *tail_at = strstr(BASE, "time:");
  const struct {
    const char *extra, *more;
    bool warned;
  } cases[] = {
      {"", "", true},
      {"interactions:\n  - {materials: [glass, steel], rolling: brof}\n", "", false},
      {"interactions:\n  - {materials: [glass, glass], rolling: model_a}\n", "", false},
      {"interactions:\n  - {name: gs, materials: [glass, steel]}\n",
       "stages:\n  - {name: a, duration: 0.1}\n  - {name: b, set: {interactions.gs.rolling: brof}}\n",
       false},
      {"interactions:\n  - {name: gs, materials: [glass, steel]}\n",
       "stages:\n  - {name: a, duration: 0.1}\n  - {name: b, set: {interactions.gs.friction: 0.1}}\n",
       true},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    snprintf(text, sizeof text, "%.*s    rolling_friction: 0.2\n%.*s%s%s%s", (int)head, BASE,
             (int)(tail_at - (BASE + head)), BASE + head, cases[k].extra, tail_at, cases[k].more);
    logged[0] = '\0';
    adem_case *c = load_ok(text, NULL, 0);
    printf("# case %zu: %s", k, logged[0] ? logged : "(nothing logged)\n");
    const char *w = strstr(logged, "materials.glass.rolling_friction = 0.2 has no effect");
    assert_true((w != NULL) == cases[k].warned);
    if (w && !strstr(cases[k].more, "stages")) assert_non_null(strstr(logged, "test.yaml:7:23"));
    adem_case_free(c);
  }
}

/* Claim: BROF meeting a turning wall is warned about (in the case, or from a stage that starts
 * the turning), and a wall that does not turn, or a turning wall without BROF, is not. */
static void test_brof_turning_wall_warned(void **state) {
  (void)state;
  char text[2048];
  const char *walls_at = strstr(BASE, "time:");
  const struct {
    const char *rolling, *motion, *more;
    bool warned;
  } cases[] = {
      {"brof", "    motion: {rotation: {axis: [0, 0, 1], center: [0, 0, 0], speed: 1}}\n", "", true},
      {"brof", "", "", false},
      {"model_a", "    motion: {rotation: {axis: [0, 0, 1], center: [0, 0, 0], speed: 1}}\n", "", false},
      {"brof", "", "stages:\n  - {name: a, duration: 0.1}\n  - {name: b, set: {walls.floor.motion: "
                   "{rotation: {axis: [0, 0, 1], center: [0, 0, 0], speed: 1}}}}\n",
       true},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    snprintf(text, sizeof text, "%.*s%sinteractions:\n  - {materials: [glass, steel], rolling: %s}\n%s%s",
             (int)(walls_at - BASE), BASE, cases[k].motion, cases[k].rolling, walls_at, cases[k].more);
    logged[0] = '\0';
    adem_case *c = load_ok(text, NULL, 0);
    printf("# case %zu: %s", k, logged[0] ? logged : "(nothing logged)\n");
    assert_true((strstr(logged, "BROF meets a turning wall") != NULL) == cases[k].warned);
    adem_case_free(c);
  }
}

/* Claim: an override is validated like the file (messages name the --set), and a path that does
 * not resolve is refused naming the failing segment. */
static void test_set_errors(void **state) {
  (void)state;
  expect_error_sets(BASE, WORDS("materials.copper.friction=0.3"), 1,
                    WORDS("--set materials.copper.friction=0.3", "`copper`", "glass, steel"));
  expect_error_sets(BASE, WORDS("materials.5.friction=0.3"), 1,
                    WORDS("`5`", "index out of range", "2 items"));
  expect_error_sets(BASE, WORDS("time.end.x=1"), 1, WORDS("`x`", "`time.end` is a single value"));
  expect_error_sets(BASE, WORDS("time.end=soon"), 1,
                    WORDS("--set time.end=soon: time.end: expected a number > 0 (s), got `soon`"));
  expect_error_sets(BASE, WORDS("materials.glass.poisson_ratio=0.7"), 1,
                    WORDS("--set materials.glass.poisson_ratio=0.7", "materials[0].poisson_ratio",
                          "(-1, 0.5)"));
  expect_error_sets(BASE, WORDS("time.ende=1"), 1,
                    WORDS("--set time.ende=1", "time.ende", "did you mean `end`?"));
  expect_error_sets(BASE, WORDS("time.end"), 1, WORDS("--set time.end", "key.path=value"));
  expect_error_sets(BASE, WORDS("time..end=1"), 1, WORDS("empty segment"));
  expect_error_sets(BASE, WORDS("time.end="), 1, WORDS("--set time.end=: time.end", "got no value"));
  expect_error_sets(BASE, WORDS("gravity=[0, 0"), 1, WORDS("--set gravity=[0, 0", "not valid YAML"));
  expect_error_sets(BASE, WORDS("gravity=[0, 0]"), 1, WORDS("--set gravity=[0, 0]", "gravity", "3 numbers"));
}

/* A sphere and a random fill of 1000 around it (tests/cases/loader-random-fill.yaml). */
#define RANDOM_FILL "loader-random-fill"

/* Claim: a random fill is deterministic in the seed, different for another seed, puts whole
 * spheres inside its box, and overlaps neither itself nor the spheres of earlier sets. */
static void test_random_fill(void **state) {
  (void)state;
  adem_case *a = case_file_load(RANDOM_FILL, NULL, 0);
  adem_case *b = case_file_load(RANDOM_FILL, NULL, 0);
  adem_case *d = case_file_load(RANDOM_FILL, WORDS("seed=8"), 1);
  const adem_particles *p = &a->world->p;
  assert_int_equal(p->n, 1001);
  assert_int_equal(b->world->p.n, 1001);
  assert_memory_equal(p->pos, b->world->p.pos, p->n * sizeof *p->pos);
  assert_memory_equal(p->radius, b->world->p.radius, p->n * sizeof *p->radius);
  assert_int_equal(d->world->p.n, 1001);
  assert_true(memcmp(p->pos + 1, d->world->p.pos + 1, 1000 * sizeof *p->pos) != 0);
  for (size_t i = 1; i < p->n; ++i) {
    adem_vec3 x = p->pos[i];
    double r = p->radius[i];
    assert_true(r >= 0.0003 && r <= 0.0006);
    assert_true(x.x - r >= 0 && x.y - r >= 0 && x.z - r >= 0);
    assert_true(x.x + r <= 0.02 && x.y + r <= 0.02 && x.z + r <= 0.04);
  }
  for (size_t i = 0; i < p->n; ++i)
    for (size_t j = i + 1; j < p->n; ++j) {
      double s = p->radius[i] + p->radius[j];
      adem_vec3 dx = v3_sub(p->pos[i], p->pos[j]);
      if (v3_norm2(dx) < s * s) fail_msg("spheres %zu and %zu overlap", i, j);
    }
  adem_error err;
  assert_int_equal(adem_world_prepare(a->world, &err), ADEM_OK);
  adem_case_free(a);
  adem_case_free(b);
  adem_case_free(d);
}

/* Claim: 20,000 spheres fill in well under a second (the grid makes each try O(1)). */
static void test_random_fill_fast(void **state) {
  (void)state;
  clock_t t0 = clock();
  adem_case *c = case_file_load(RANDOM_FILL, WORDS("particles.1.count=20000", "particles.1.max=[0.04, 0.04, 0.04]"), 2);
  double seconds = (double)(clock() - t0) / CLOCKS_PER_SEC;
  printf("# 20000 spheres in %.3f s\n", seconds);
  assert_int_equal(c->world->p.n, 20001);
  assert_true(seconds < 5.0); /* generous: Debug builds, slow machines, valgrind off */
  adem_case_free(c);
}

/* Claim: when max_attempts runs out the fill keeps what it placed and warns with both counts. */
static void test_random_fill_gives_up(void **state) {
  (void)state;
  adem_case *c = case_file_load(RANDOM_FILL, WORDS("particles.1.max_attempts=200"), 1);
  size_t n = c->world->p.n - 1;
  assert_true(n > 0 && n <= 200);
  char expect[128];
  snprintf(expect, sizeof expect, "placed %zu of 1000 spheres", n);
  assert_contains(logged, expect);
  assert_contains(logged, "particles[1]");
  adem_case_free(c);
}

/* Claim: the size distributions have the asked mean and spread. 4000 draws: the sample mean is
 * within 1 % (more than 4 standard errors for std/mean = 0.2), the sample std within 10 %. */
static void test_radius_distributions(void **state) {
  (void)state;
  const char *dists[] = {"{distribution: normal, mean: 0.0005, std: 0.0001}",
                         "{distribution: lognormal, mean: 0.0005, std: 0.0001}",
                         "{distribution: constant, value: 0.0005}"};
  for (int k = 0; k < 3; ++k) {
    char radius[128];
    snprintf(radius, sizeof radius, "particles.1.radius=%s", dists[k]);
    adem_case *c = case_file_load(RANDOM_FILL,
                                  WORDS(radius, "particles.1.count=4000", "particles.1.max=[0.1, 0.1, 0.1]"), 3);
    const adem_particles *p = &c->world->p;
    assert_int_equal(p->n, 4001);
    double s = 0, s2 = 0;
    for (size_t i = 1; i < p->n; ++i) s += p->radius[i];
    double mean = s / 4000.0;
    for (size_t i = 1; i < p->n; ++i) s2 += (p->radius[i] - mean) * (p->radius[i] - mean);
    double std = sqrt(s2 / 3999.0);
    printf("# %s: mean %g std %g\n", dists[k], mean, std);
    assert_float_equal(mean, 0.0005, 0.01 * 0.0005);
    assert_float_equal(std, k == 2 ? 0.0 : 0.0001, 0.1 * 0.0001);
    adem_case_free(c);
  }
  const char *fill = case_file_text(RANDOM_FILL);
  expect_error_sets(fill, WORDS("particles.1.radius={distribution: constant, value: 0.011}"), 1,
                    WORDS("particles[1].radius.value", "does not fit the box"));
  expect_error_sets(fill, WORDS("particles.1.radius.max=0.0002"), 1,
                    WORDS("particles[1].radius.max", "greater than `min`"));
  expect_error_sets(fill, WORDS("particles.1.radius.mean=1"), 1,
                    WORDS("particles[1].radius.mean", "does not apply to distribution `uniform`"));
}

/* Claim: the reference page lists every key of the schema with its unit, default and range, and
 * docs/case-reference.md is that page (ADEM_UPDATE_DOCS=1 rewrites it). */
static void test_reference(void **state) {
  (void)state;
  char *text = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&text, &len);
  assert_non_null(f);
  adem_case_write_reference(f);
  fclose(f);
  const char *keys[] = {"`materials[].poisson_ratio` | number |  | required unless `rigid: true` | in (-1, 0.5)",
                        "`materials[].density` | number | kg/m^3 |",
                        "`time.step` | `auto` or number | s | `auto` | > 0",
                        "`interactions[].rolling` | `none` \\| `dtk` \\| `model_a` \\| `model_c` \\| `model_c_capped` \\| `brof`",
                        "`particles[].spacing`", "*(type: lattice)*", "`particles[].radius.std`",
                        "`output.frame_interval`", "time.end / 100", "`limits.max_overlap_ratio`",
                        "`gravity` | [x, y, z] | m/s^2 | `[0, 0, -9.81]`", "sqrt(2 |g| H)"};
  for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k) assert_contains(text, keys[k]);
  char path[4096];
  snprintf(path, sizeof path, "%s/docs/case-reference.md", ADEM_SOURCE_DIR);
  const char *update = getenv("ADEM_UPDATE_DOCS");
  if (update && *update == '1') {
    FILE *out = fopen(path, "w");
    assert_non_null(out);
    fputs(text, out);
    fclose(out);
  }
  FILE *in = fopen(path, "r");
  if (!in) fail_msg("%s is missing; run this test with ADEM_UPDATE_DOCS=1", path);
  char *doc = calloc(len + 2, 1);
  assert_non_null(doc);
  size_t got = fread(doc, 1, len + 1, in);
  fclose(in);
  if (got != len || memcmp(doc, text, len) != 0)
    fail_msg("%s is out of date; run this test with ADEM_UPDATE_DOCS=1", path);
  free(doc);
  free(text);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_good_case, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_full_case, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_step_too_large_warns, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_unknown_key, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_wrong_type, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_missing_required, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_out_of_range, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_bad_names, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_bad_geometry, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_bad_files, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_load_file, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_set_overrides, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_set_errors, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_interaction_names, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_unused_law_params_warned, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_brof_turning_wall_warned, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_random_fill, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_random_fill_fast, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_random_fill_gives_up, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_radius_distributions, capture_setup, capture_teardown),
      cmocka_unit_test_setup_teardown(test_reference, capture_setup, capture_teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
