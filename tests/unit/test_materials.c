/* Pair properties derived from two materials (H2, H15, H24). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "helpers.h"
#include "world_internal.h"

/* Claim (H24): a stiffness factor f on the spheres only, against a rigid wall, gives the pair
 * E_mod/E = f and so gamma_mod = gamma f^(2/5), not the f^(1/5) a mean of per-material values
 * would give. */
static void test_reduced_stiffness_on_rigid_wall(void **state) {
  (void)state;
  adem_world *w = adem_world_create();
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "psl");
  m.young = 271e6;
  m.poisson = 0.0;
  m.param[ADEM_PARAM_SURFACE_ENERGY] = 0.11;
  m.stiffness_factor = 0.01;
  adem_error err;
  int psl = -1;
  assert_int_equal(adem_world_add_material(w, &m, &psl, &err), ADEM_OK);
  snprintf(m.name, sizeof m.name, "quartz");
  m.rigid = 1;
  m.stiffness_factor = 1.0;
  int quartz = -1;
  assert_int_equal(adem_world_add_material(w, &m, &quartz, &err), ADEM_OK);
  assert_int_equal(adem_materials_derive(&w->mat, &err), ADEM_OK);
  const adem_interaction *it = adem_world_interaction(w, psl, quartz);
  printf("# E = %.6g Pa (real %.6g), gamma = %.6g J/m^2 (real %.6g)\n", it->pp.E, it->pp.E_real,
         it->pp.gamma, it->pp.gamma_real);
  assert_true(fabs(it->pp.E / it->pp.E_real - 0.01) < 1e-14);
  assert_true(fabs(it->pp.gamma / (0.11 * pow(0.01, 0.4)) - 1.0) < 1e-14);
  /* two spheres of the same reduced material: the same rule */
  const adem_interaction *pp = adem_world_interaction(w, psl, psl);
  assert_true(fabs(pp->pp.gamma / (0.11 * pow(0.01, 0.4)) - 1.0) < 1e-14);
  adem_world_free(w);
}

/* Claim (H2, H15): effective moduli of two equal materials, 1/E = 2(1-nu^2)/E_i and
 * 1/G = 2(2-nu)/G_i; a rigid wall contributes nothing. */
static void test_effective_moduli(void **state) {
  (void)state;
  adem_world *w = adem_world_create();
  int a = test_material(w, "a", 1e7, 0.25, 0.5, 0.5);
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "wall");
  m.rigid = 1;
  adem_error err;
  int wall = -1;
  assert_int_equal(adem_world_add_material(w, &m, &wall, &err), ADEM_OK);
  assert_int_equal(adem_materials_derive(&w->mat, &err), ADEM_OK);
  double G = 1e7 / (2.0 * 1.25);
  const adem_interaction *pp = adem_world_interaction(w, a, a);
  assert_true(fabs(pp->pp.E / (1e7 / (2.0 * (1.0 - 0.0625))) - 1.0) < 1e-14);
  assert_true(fabs(pp->pp.G / (G / (2.0 * 1.75)) - 1.0) < 1e-14);
  const adem_interaction *pw = adem_world_interaction(w, a, wall);
  assert_true(fabs(pw->pp.E / (1e7 / (1.0 - 0.0625)) - 1.0) < 1e-14);
  assert_true(fabs(pw->pp.G / (G / 1.75) - 1.0) < 1e-14);
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reduced_stiffness_on_rigid_wall),
      cmocka_unit_test(test_effective_moduli),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
