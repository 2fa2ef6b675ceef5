/* domain.periodic in a case file and adem_world_set_periodic: what is refused (each message
 * names the file, line and column, the key and what is allowed) and what is only warned about. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <string.h>

#include "adem/adem.h"
#include "bitwise/periodic_case.h"
#include "helpers.h"
#include "log_capture.h"
#include "world_internal.h"

#define WORDS(...) ((const char *const[]){__VA_ARGS__, NULL})

/* The periodic case's text with `from` replaced by `to` (the claim is the file's line and column) must be refused with each of words in the message. */
static void expect_bad(const char *from, const char *to, const char *const *words) {
  const char *at = strstr(periodic_case, from);
  assert_non_null(at);
  char text[4096];
  snprintf(text, sizeof text, "%.*s%s%s", (int)(at - periodic_case), periodic_case, to,
           at + strlen(from));
  adem_case *c = NULL;
  adem_error err = {ADEM_OK, ""};
  adem_status st = adem_case_load_string(text, "periodic.yaml", NULL, 0, &c, &err);
  printf("# %s\n", err.message);
  assert_int_equal(st, ADEM_ERR_INPUT);
  assert_null(c);
  for (; *words; ++words)
    if (!strstr(err.message, *words)) fail_msg("'%s' is not in the message", *words);
}

static void test_loads(void **state) {
  (void)state;
  adem_case *c = periodic_load(NULL, 0);
  assert_int_equal(c->world->periodic.axes, 3u);
  assert_true(c->world->periodic.len[0] == 0.015 && c->world->periodic.lo[1] == 0.0);
  adem_case_free(c);
}

static void test_case_errors(void **state) {
  (void)state;
  /* 2 (2.4 mm + 0.2 x 2.4 mm) = 5.74 mm (the largest drawn radius is 1.197 mm) */
  expect_bad("max: [0.015, 0.015, 0.06]", "max: [0.005, 0.015, 0.06]",
             WORDS("periodic.yaml:30:14", "domain.periodic[0]", "0.005 m long along x",
                   "2 (largest diameter + skin)", "0.00574"));
  expect_bad("normal: [0, 0, 1]", "normal: [0, 0.2, 1]",
             WORDS("periodic.yaml:26:13", "walls[0].normal", "along y", "domain.periodic at line 30:20",
                   "parallel to every periodic axis"));
  expect_bad("periodic: [true, true, false]", "periodic: [true, 1, false]",
             WORDS("periodic.yaml:30:20", "domain.periodic[1]", "expected true or false", "`1`"));
  expect_bad("periodic: [true, true, false]", "periodic: true",
             WORDS("periodic.yaml:30:13", "domain.periodic", "a list [x, y, z] of 3 booleans"));
  expect_bad("periodic: [true, true, false]", "periodic: [true, true]",
             WORDS("periodic.yaml:30:13", "domain.periodic", "a list of 2 items"));
  expect_bad("  - type: plane\n    name: floor\n    material: steel\n    point: [0, 0, 0]\n"
             "    normal: [0, 0, 1]\n",
             "  - {type: box, name: bin, material: steel, min: [0, 0, 0], max: [0.015, 0.015, 0.06]}\n",
             WORDS("periodic.yaml:22:", "walls[0].type", "box wall", "x is periodic"));
}

/* Through the API: a bad box is refused at once; a short one, a cutting plane at prepare; a
 * mesh within reach of a face is run with a warning. */
static void test_api(void **state) {
  (void)state;
  adem_error err;
  adem_world *w = adem_world_create();
  test_material(w, "glass", 1e7, 0.3, 0.5, 0.5);
  assert_int_equal(adem_world_set_periodic(w, v3(0, 0, 0), v3(0, 1, 1), ADEM_PERIODIC_X, &err),
                   ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_int_equal(adem_world_set_periodic(w, v3(0, 0, 0), v3(0.1, 1, 1), ADEM_PERIODIC_X, &err),
                   ADEM_OK);
  test_particle(w, 0, v3(0.05, 0.5, 0.5), v3_zero(), 0.025); /* needs 2 (0.05 + 0.01) = 0.12 */
  assert_int_equal(adem_world_prepare(w, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "0.12 m"));
  assert_int_equal(adem_world_set_periodic(w, v3(0, 0, 0), v3(1, 1, 1), ADEM_PERIODIC_X, &err),
                   ADEM_OK);
  adem_plane_def pl = adem_default_plane_def();
  snprintf(pl.name, sizeof pl.name, "tilted");
  pl.normal = v3(0.6, 0, 0.8);
  pl.point = v3(0, 0, 0);
  assert_int_equal(adem_world_add_plane(w, &pl, NULL, &err), ADEM_OK);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "'tilted'"));
  adem_world_free(w);

  w = adem_world_create();
  test_material(w, "glass", 1e7, 0.3, 0.5, 0.5);
  adem_world_set_periodic(w, v3(0, 0, 0), v3(1, 1, 1), ADEM_PERIODIC_X, &err);
  test_particle(w, 0, v3(0.5, 0.5, 0.5), v3_zero(), 0.025);
  const adem_vec3 tri[3] = {v3(-0.5, 0, 0.1), v3(1.5, 0, 0.1), v3(0.5, 1, 0.1)};
  assert_int_equal(adem_world_add_mesh(w, tri, 1, "floor", NULL, &err), ADEM_OK);
  /* a triangle across the faces is not the same along x: refused (tests/physics/
   * test_periodic_shell.c has the shells that are) */
  assert_int_equal(adem_world_prepare(w, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "not imaged"));
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_loads),
      cmocka_unit_test(test_case_errors),
      cmocka_unit_test(test_api),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
