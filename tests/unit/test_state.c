/* Claims: a case whose particles are `type: state` (another run's checkpoint) starts with that
 * run's particles bit for bit (count, ids, positions, velocities, spins, radii, materials by
 * name), under its own materials (another Young's modulus here) and runs; a missing file, a file
 * that is no checkpoint, a checkpoint of another format version and a material the case lacks
 * are refused with the file named. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "case_file.h"
#include "case_text.h"
#include "adem/files.h"
#include "tmpdir.h"
#include "world_internal.h"


/* Materials in another order and another E: the import goes by name. */
#define import_case case_file_text("state-import") /* tests/cases/state-import.yaml */

static adem_case *source;

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_state")) return -1;
  adem_error err;
  if (adem_case_load_file(case_file_path("state-source"), NULL, 0, &source, &err)) return -1;
  snprintf(source->output.dir, sizeof source->output.dir, "%s/src", tmpdir);
  adem_run_options opt = adem_default_run_options();
  return adem_run(source, &opt, &err) == ADEM_OK ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  adem_case_free(source);
  return tmpdir_remove();
}

static adem_status load_import(const char *text, adem_case **c, adem_error *err) {
  char path[600];
  snprintf(path, sizeof path, "%s/import.yaml", tmpdir);
  return adem_case_load_string_at(text, path, tmpdir, NULL, 0, c, err);
}

static void test_import_bitwise(void **state) {
  (void)state;
  adem_case *c = NULL;
  adem_error err;
  if (load_import(import_case, &c, &err)) fail_msg("%s", err.message);
  const adem_world *a = source->world, *b = c->world;
  printf("# %zu particles imported from t = %g s\n", b->p.n, adem_world_time(a));
  assert_true(a->p.n == 64 && b->p.n == a->p.n);
  int glass = adem_world_find_material(b, "glass");
  for (size_t i = 0; i < a->p.n; ++i) { /* the source in cell order, the import in id order */
    size_t j = (size_t)a->p.id[i];
    assert_true(b->p.id[j] == a->p.id[i]);
    assert_memory_equal(&b->p.pos[j], &a->p.pos[i], sizeof(adem_vec3));
    assert_memory_equal(&b->p.vel[j], &a->p.vel[i], sizeof(adem_vec3));
    assert_memory_equal(&b->p.omega[j], &a->p.omega[i], sizeof(adem_vec3));
    assert_memory_equal(&b->p.radius[j], &a->p.radius[i], sizeof(double));
    assert_int_equal(b->p.material[j], glass);
  }
  assert_true(adem_world_material(b, glass)->young == 5.0e6);
  adem_run_options opt = adem_default_run_options();
  snprintf(c->output.dir, sizeof c->output.dir, "%s/imp", tmpdir);
  if (adem_run(c, &opt, &err)) fail_msg("%s", err.message);
  adem_case_free(c);
}

/* keep_inside keeps exactly the particles whose centre is in the box, in the order of their
 * old ids, renumbered from 0; a box with max <= min is refused with its key. */
static void test_import_trimmed(void **state) {
  (void)state;
  const adem_world *a = source->world;
  double zcut = 0.005;
  size_t want = 0;
  for (size_t i = 0; i < a->p.n; ++i) want += a->p.pos[i].z <= zcut;
  char box[160];
  snprintf(box, sizeof box, "file: src/checkpoint, keep_inside: {min: [-1, -1, -1], max: [1, 1, %.17g]}}", zcut);
  char *t = replaced(import_case, "file: src/checkpoint}", box);
  adem_case *c = NULL;
  adem_error err;
  if (load_import(t, &c, &err)) fail_msg("%s", err.message);
  const adem_world *b = c->world;
  printf("# kept %zu of %zu particles (centre z <= %g m)\n", b->p.n, a->p.n, zcut);
  assert_true(want > 0 && want < a->p.n);
  assert_int_equal(b->p.n, want);
  size_t k = 0; /* walk the source by id; the kept ones come in that order */
  for (uint64_t id = 0; id < a->p.n; ++id)
    for (size_t i = 0; i < a->p.n; ++i)
      if (a->p.id[i] == id && a->p.pos[i].z <= zcut) {
        assert_true(b->p.id[k] == k);
        assert_memory_equal(&b->p.pos[k], &a->p.pos[i], sizeof(adem_vec3));
        ++k;
      }
  assert_int_equal(k, want);
  adem_case_free(c);
  free(t);
  snprintf(box, sizeof box, "file: src/checkpoint, keep_inside: {min: [-1, -1, 1], max: [1, 1, 0.5]}}");
  t = replaced(import_case, "file: src/checkpoint}", box);
  if (load_import(t, &c, &err) == ADEM_OK) fail_msg("accepted");
  printf("# %s\n", err.message);
  assert_mentions(err.message, "particles[0].keep_inside.max");
  assert_mentions(err.message, "greater than `min`");
  free(t);
}

static void expect_refused(const char *text, const char *const *words) {
  adem_case *c = NULL;
  adem_error err;
  if (load_import(text, &c, &err) == ADEM_OK) fail_msg("accepted");
  printf("# %s\n", err.message);
  for (; *words; ++words) assert_mentions(err.message, *words);
}
#define WORDS(...) ((const char *const[]){__VA_ARGS__, NULL})

static void test_import_errors(void **state) {
  (void)state;
  char *t = replaced(import_case, "src/checkpoint", "src/nothere");
  expect_refused(t, WORDS("import.yaml:6:", "particles[0].file", "src/nothere"));
  free(t);
  t = replaced(import_case, "src/checkpoint", "import.yaml");
  char path[600];
  snprintf(path, sizeof path, "%s/import.yaml", tmpdir);
  adem_error err;
  assert_int_equal(adem_file_write_all(path, import_case, strlen(import_case), &err), ADEM_OK);
  expect_refused(t, WORDS("import.yaml is not a usable adem checkpoint", "ADEMCKPT"));
  free(t);
  /* a checkpoint of another format version: the version field set to 6 */
  char *data;
  size_t len;
  char src[600], old[600];
  snprintf(src, sizeof src, "%s/src/checkpoint", tmpdir);
  snprintf(old, sizeof old, "%s/old.ckpt", tmpdir);
  assert_int_equal(adem_file_read_all(src, &data, &len, &err), ADEM_OK);
  uint32_t v = 6;
  memcpy(data + 8, &v, 4);
  assert_int_equal(adem_file_write_all(old, data, len, &err), ADEM_OK);
  free(data);
  t = replaced(import_case, "src/checkpoint", "old.ckpt");
  expect_refused(t, WORDS("old.ckpt is not a usable adem checkpoint", "format version 6", "reads version 11"));
  free(t);
  t = replaced(import_case, "name: glass", "name: sand");
  expect_refused(t, WORDS("particles[0].file", "material `glass`", "does not have"));
  free(t);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_import_bitwise),
      cmocka_unit_test(test_import_errors),
      cmocka_unit_test(test_import_trimmed),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
