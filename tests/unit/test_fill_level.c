/* particles[].fill_level: a random set sized by the bed it settles into (case_walls.c). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "adem/adem.h"
#include "case_file.h"

static const double PI = 3.14159265358979323846;

/* tests/cases/fill-level-box.yaml with particles.0.region=REGION (NULL: the box) and
 * particles.0.fill_level=FILL; NULL with *err when it is refused. */
static adem_case *load(const char *region, const char *fill, adem_error *err) {
  char r[256], f[256];
  snprintf(r, sizeof r, "particles.0.region=%s", region ? region : "");
  snprintf(f, sizeof f, "particles.0.fill_level=%s", fill);
  const char *sets[] = {f, r};
  adem_case *c = NULL;
  if (adem_case_load_file(case_file_path("fill-level-box"), sets, region ? 2 : 1, &c, err)) return NULL;
  return c;
}

/* Claim: a box 0.1 x 0.1 x 0.2 m filled to the level z = 0.05 at packing 0.6 gets the spheres
 * whose volume is closest to 0.6 x 0.1 x 0.1 x 0.05 m^3 (within half a sphere's), and a
 * horizontal cylinder region (radius 0.05 m, 0.1 m long) filled to its axis gets half its
 * volume's worth at packing 0.6, to 1 % (the grid's estimate of the volume below the level),
 * and the same as `fraction: 0.5`; `level` with `fraction`, and a solid fraction above 0.45, are
 * refused. */
static void test_fill_level(void **state) {
  (void)state;
  adem_error err;
  double vs = 4.0 / 3.0 * PI * 0.004 * 0.004 * 0.004;
  adem_case *c = load(NULL, "{level: 0.05}", &err);
  if (!c) fail_msg("%s", err.message);
  double want = 0.6 * 0.1 * 0.1 * 0.05 / vs;
  size_t n = adem_world_particle_count(c->world);
  printf("# box to z = 0.05: %zu spheres (%.2f wanted)\n", n, want);
  assert_true(fabs((double)n - want) <= 0.5);
  adem_case_free(c);
  const char *cyl = "{shape: cylinder, start: [0, 0, 0], end: [0.1, 0, 0], radius: 0.05}";
  c = load(cyl, "{level: 0.0}", &err);
  if (!c) fail_msg("%s", err.message);
  want = 0.6 * 0.5 * PI * 0.05 * 0.05 * 0.1 / vs;
  n = adem_world_particle_count(c->world);
  printf("# cylinder to its axis: %zu spheres (%.2f wanted)\n", n, want);
  assert_true(fabs((double)n - want) <= 0.01 * want);
  adem_case_free(c);
  c = load(cyl, "{fraction: 0.5}", &err);
  if (!c) fail_msg("%s", err.message);
  size_t nf = adem_world_particle_count(c->world);
  printf("# cylinder, fraction 0.5: %zu spheres\n", nf);
  assert_true(fabs((double)nf - want) <= 0.5);
  adem_case_free(c);
  assert_null(load(cyl, "{level: 0.0, fraction: 0.5}", &err));
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "either `level` or `fraction`"));
  assert_null(load(cyl, "{fraction: 0.9}", &err));
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "solid fraction of 0.54"));
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_fill_level)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
