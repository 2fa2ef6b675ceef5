/* adem analyze repose (src/studies/repose.c) end to end: a cone of spheres written as a case, run
 * for a few steps without gravity (its frame), measured by the command, every measure in
 * repose_measures.csv. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdbool.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>

#include "cli_run.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_analyze");
}

/* Claim: a 35-degree cone of spheres (0.05 m apart on a cubic lattice with alternate layers
 * shifted by half a spacing, radius 0.022 m, base radius 0.6 m) is measured by the command at 35
 * degrees within 3 by the laboratory measure and within 2 by the surface fit (one pile of
 * 12 diameters: the resolution of test_pile.c's cones of that size, a lattice's staircase
 * added), the figures in repose_measures.csv are those printed, and a folder without frames is
 * refused with exit 2. */
static void test_cone(void **state) {
  (void)state;
  const double d = 0.05, r = 0.022, base = 0.6, t = tan(35.0 * 3.14159265358979 / 180.0);
  size_t cap = 1 << 20, n = 0;
  char *text = malloc(cap);
  assert_non_null(text);
  n += (size_t)snprintf(text + n, cap - n,
                        "name: cone\nmaterials:\n  - {name: stone, density: 2700, youngs_modulus: "
                        "1.0e8, poisson_ratio: 0.2, restitution: 0.4, friction: 0.6}\n"
                        "particles:\n  - type: list\n    material: stone\n    spheres:\n");
  int count = 0;
  for (int k = 0; k * d * 0.8 + r <= base * t; ++k) {
    double z = r + k * d * 0.8, off = (k % 2) * 0.5 * d; /* layers 0.8 d apart, staggered */
    for (int i = -14; i <= 14; ++i)
      for (int j = -14; j <= 14; ++j) {
        double x = i * d + off, y = j * d + off, rho = sqrt(x * x + y * y);
        if (z > (base - rho) * t) continue;
        n += (size_t)snprintf(text + n, cap - n,
                              "      - {position: [%.6f, %.6f, %.6f], radius: %.6f}\n", x, y, z, r);
        ++count;
      }
  }
  n += (size_t)snprintf(text + n, cap - n,
                        "gravity: [0, 0, 0]\ntime:\n  end: 1.0e-4\noutput:\n  frame_interval: "
                        "1.0e-4\n  plot: false\n  plot_loads: false\n");
  assert_true(n < cap);
  printf("# %d spheres\n", count);
  char *path = write_case("cone.yaml", text);
  char *out;
  assert_int_equal(adem(&out, "run '%s' --quiet --out '%s/cone'", path, tmpdir), 0);
  assert_int_equal(adem(&out, "analyze repose '%s/cone'", tmpdir), 0);
  printf("%s", out);
  assert_true(mentions(out, "laboratory") && mentions(out, "ring-top line"));
  char *csv = path_in_tmp("cone/repose_measures.csv");
  double lab = csv_value(csv, 1, "angle_lab_deg"), surf = csv_value(csv, 1, "angle_surface_deg");
  double ring = csv_value(csv, 1, "angle_ringtop_deg");
  printf("# laboratory %.2f, surface %.2f, ring-top %.2f deg\n", lab, surf, ring);
  assert_true(fabs(lab - 35.0) < 3.0);
  assert_true(fabs(surf - 35.0) < 2.0);
  char want[64];
  snprintf(want, sizeof want, "laboratory       %.2f deg", lab);
  assert_true(mentions(out, want));
  assert_int_equal(adem(&out, "analyze repose '%s'", tmpdir), 2);
  assert_true(mentions(out, "frames"));
  free(csv);
  free(path);
  free(text);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_cone)};
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
