/* One home per value: the defaults a case file gets from the schema table (src/input/schema.c, the
 * `def` column) and the ones a program gets from adem_default_material_def(),
 * adem_default_interaction_def() and adem_world_create() must agree. Each pair is compared here;
 * a default changed in one place only fails this test. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "adem/adem.h"
#include "schema.h"
#include "world_internal.h"

static double schema_number(const char *prefix, const char *key) {
  const adem_schema_entry *e = adem_schema_find(prefix, key, NULL);
  if (!e || !e->def) fail_msg("no default for %s.%s in the schema", prefix, key);
  char *end;
  double x = strtod(e->def, &end);
  if (*end) fail_msg("default of %s.%s is not a number: %s", prefix, key, e->def);
  return x;
}

static const char *schema_text(const char *prefix, const char *key) {
  const adem_schema_entry *e = adem_schema_find(prefix, key, NULL);
  if (!e || !e->def) fail_msg("no default for %s.%s in the schema", prefix, key);
  return e->def;
}

static void test_material_defaults(void **state) {
  (void)state;
  adem_material_def d = adem_default_material_def();
  assert_true(schema_number("materials[]", "restitution") == d.restitution);
  assert_true(schema_number("materials[]", "friction") == d.friction);
  assert_true(schema_number("materials[]", "stiffness_factor") == d.stiffness_factor);
  assert_string_equal(schema_text("materials[]", "rigid"), d.rigid ? "true" : "false");
  for (int k = 0; k < ADEM_PARAM_COUNT; ++k) {
    const adem_law_param *p = adem_law_param_get((adem_law_param_id)k);
    printf("# materials[].%s: schema %s, default %g\n", p->key, schema_text("materials[]", p->key),
           d.param[k]);
    assert_true(schema_number("materials[]", p->key) == d.param[k]);
  }
}

static void test_interaction_defaults(void **state) {
  (void)state;
  adem_interaction_def d = adem_default_interaction_def();
  assert_string_equal(schema_text("interactions[]", "normal"),
                      adem_law_get(ADEM_SLOT_NORMAL, (int)d.normal)->name);
  assert_string_equal(schema_text("interactions[]", "damping"),
                      adem_law_get(ADEM_SLOT_DAMPING, (int)d.damping)->name);
  assert_string_equal(schema_text("interactions[]", "tangential"),
                      adem_law_get(ADEM_SLOT_TANGENTIAL, (int)d.tangential)->name);
  assert_string_equal(schema_text("interactions[]", "rolling"),
                      adem_law_get(ADEM_SLOT_ROLLING, (int)d.rolling)->name);
  /* a pair without an entry gets the same laws as an entry that names none */
  adem_world *w = adem_world_create();
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "a");
  assert_int_equal(adem_world_add_material(w, &m, NULL, NULL), ADEM_OK);
  adem_pair_info info;
  assert_int_equal(adem_world_pair_info(w, 0, 0, &info, NULL), ADEM_OK);
  assert_int_equal(info.normal, d.normal);
  assert_int_equal(info.damping, d.damping);
  assert_int_equal(info.tangential, d.tangential);
  assert_int_equal(info.rolling, d.rolling);
  adem_world_free(w);
}

static void test_world_defaults(void **state) {
  (void)state;
  adem_world *w = adem_world_create();
  assert_true(schema_number("neighbor", "skin") == w->nb.skin_fraction);
  assert_true(schema_number("limits", "max_overlap_ratio") == w->max_overlap_ratio);
  const char *g = schema_text("", "gravity");
  double gx, gy, gz;
  assert_int_equal(sscanf(g, "[%lf, %lf, %lf]", &gx, &gy, &gz), 3);
  assert_true(gx == w->gravity.x && gy == w->gravity.y && gz == w->gravity.z);
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_material_defaults),
      cmocka_unit_test(test_interaction_defaults),
      cmocka_unit_test(test_world_defaults),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
