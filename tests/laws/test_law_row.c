/* A new rolling law is one row: this program links a build of the library with one extra row
 * (tests/laws/test_law_rows.h, kernel in test_law_kernels.h), registered at build time through
 * ADEM_EXTRA_LAWS_HEADER, and no schema, loader or force-pass code written for it. Checked: the
 * registry lists it, a case file selects it by name (and gets its parameter checked), the
 * reference documents it, and the force pass applies its kernel to a sphere on a plane. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "adem/adem.h"
#include "case_text.h"
#include "world_internal.h"

static const char *case_text =
    "materials:\n"
    "  - {name: grain, density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.3,\n"
    "     restitution: 0.5, friction: 0.5, rolling_friction: 0.2}\n"
    "  - {name: floor, rigid: true, friction: 0.5}\n"
    "interactions:\n"
    "  - {materials: [grain, floor], rolling: test_viscous}\n"
    "particles:\n"
    "  - type: list\n"
    "    material: grain\n"
    "    spheres:\n"
    "      - {position: [0, 0, 0.01], radius: 0.01, angular_velocity: [0, 3.0, 0]}\n"
    "walls:\n"
    "  - {type: plane, name: floor, material: floor, point: [0, 0, 0], normal: [0, 0, 1]}\n"
    "gravity: [0, 0, -9.81]\n"
    "time: {end: 0.001, step: 1.0e-6}\n";

static void test_registry_has_the_row(void **state) {
  (void)state;
  const adem_law *law = adem_law_find(ADEM_SLOT_ROLLING, "test_viscous");
  assert_non_null(law);
  assert_int_equal(law->id, ADEM_ROLLING_TEST_VISCOUS);
  assert_true(adem_law_reads(law, "rolling_friction"));
  assert_non_null(strstr(adem_law_choices(ADEM_SLOT_ROLLING), "brof_objective|test_viscous"));
  /* the built-in rows are untouched */
  assert_int_equal(adem_law_find(ADEM_SLOT_ROLLING, "brof")->id, ADEM_ROLLING_BROF);
}

static void test_reference_lists_it(void **state) {
  (void)state;
  char *buf = NULL;
  size_t n = 0;
  FILE *f = open_memstream(&buf, &n);
  assert_non_null(f);
  adem_case_write_reference(f);
  fclose(f);
  assert_contains(buf, "| rolling | `test_viscous` |");
  assert_contains(buf, "`brof_objective` \\| `test_viscous`");
  free(buf);
}

static void test_case_selects_it(void **state) {
  (void)state;
  adem_case *c = NULL;
  adem_error err;
  memset(&err, 0, sizeof err);
  if (adem_case_load_string(case_text, "law.yaml", NULL, 0, &c, &err)) fail_msg("%s", err.message);
  adem_world *w = c->world;
  assert_int_equal(adem_world_interaction(w, 0, 1)->rolling, ADEM_ROLLING_TEST_VISCOUS);
  /* let the sphere settle onto the floor without spin, then spin it: the couple must be the
   * kernel's -eta R |F_n| omega (the friction's torque is zero at this instant: no slip yet) */
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  w->p.omega[0] = (adem_vec3){0, 0, 0};
  assert_int_equal(adem_world_step(w, 20000, &err), ADEM_OK); /* 20 ms: at rest on the floor */
  double omega = 3.0;
  w->p.omega[0] = (adem_vec3){0, omega, 0};
  w->p.vel[0] = (adem_vec3){omega * 0.01, 0, w->p.vel[0].z}; /* rolling: the contact point is at rest */
  adem_world_compute_forces(w);
  double r = w->p.radius[0];
  double delta = r - w->p.pos[0].z;
  double f_hertz = 4.0 / 3.0 * adem_world_interaction(w, 0, 1)->pp.E * sqrt(r) * pow(delta, 1.5);
  printf("# overlap %.4g m, elastic load %.6g N, rolling torque y %.6g N m\n", delta, f_hertz,
         w->p.rolling_torque[0].y);
  double want = -0.2 * r * f_hertz * omega;
  assert_true(fabs(w->p.rolling_torque[0].y / want - 1.0) < 1e-9);
  assert_true(fabs(w->p.rolling_torque[0].x) < 1e-15 && fabs(w->p.rolling_torque[0].z) < 1e-15);
  adem_case_free(c);

  /* its parameter is validated like any other: a negative rolling_friction on the entry */
  char *bad = replaced(case_text, "rolling: test_viscous}", "rolling: test_viscous, rolling_friction: -1}");
  assert_int_equal(adem_case_load_string(bad, "law.yaml", NULL, 0, &c, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_contains(err.message, "interactions[0].rolling_friction");
  free(bad);
  /* and a name that no row has is refused with the rows' names */
  bad = replaced(case_text, "rolling: test_viscous}", "rolling: test_viscos}");
  assert_int_equal(adem_case_load_string(bad, "law.yaml", NULL, 0, &c, &err), ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_contains(err.message, "test_viscous");
  free(bad);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_registry_has_the_row),
      cmocka_unit_test(test_reference_lists_it),
      cmocka_unit_test(test_case_selects_it),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
