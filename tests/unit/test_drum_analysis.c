/* adem analyze drum's measures on a frame made to order (adem/drum.h): a bed of spheres on a
 * square grid filling a drum's cross-section below a surface at a known angle, turning with the
 * drum below a flowing layer of known depth, and a wall layer at a known rate. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "adem/adem.h"
#include "adem/drum.h"

static const double PI = 3.14159265358979323846;
static const double R = 0.05, RP = 0.001, OMEGA = 2.0;

/* The frame: drum about x through the origin, gravity -z, turning at +OMEGA (its bottom moves
 * to +y, so the bed is lifted to +y): grid spheres (spacing 2 RP) at y^2 + z^2 <= (R - 3 RP)^2
 * on and below z = z0 + tan(theta) y, the layer within `layer` of that line flowing downhill at speed
 * falling linearly from U at the top to 0 at its base, the rest turning with the drum; a wall
 * layer of spheres at R - RP below the surface, moving at `wall` times the drum's speed there. */
static void make_frame(adem_vtu_frame *f, double theta, double z0, double layer, double wall) {
  size_t cap = 20000, n = 0;
  f->pos = calloc(cap, sizeof *f->pos);
  f->velocity = calloc(cap, sizeof *f->velocity);
  f->radius = calloc(cap, sizeof *f->radius);
  assert_non_null(f->pos);
  double c = cos(theta), s = sin(theta), d = 2.0 * RP;
  for (int k = -60; k <= 60; ++k)
    for (int j = 0; j <= 60; ++j) { /* rows parallel to the surface, j rows below it */
      double depth = j * d, y = k * d * c + depth * s, z = z0 + k * d * s - depth * c;
      if (y * y + z * z > (R - 3.0 * RP) * (R - 3.0 * RP)) continue;
      f->pos[n] = (adem_vec3){0.0, y, z};
      if (depth < layer) { /* downhill: along -(c, s) in (y, z) */
        double u = 0.1 * (1.0 - depth / layer);
        f->velocity[n] = (adem_vec3){0.0, -u * c, -u * s};
      } else { /* omega x r, omega along +x */
        f->velocity[n] = (adem_vec3){0.0, -OMEGA * z, OMEGA * y};
      }
      f->radius[n++] = RP;
    }
  for (double a = -PI; a < PI; a += d / (R - RP)) {
    double y = (R - RP) * sin(a), z = -(R - RP) * cos(a);
    if ((z0 + tan(theta) * y - z) * c < 3.0 * d) continue;
    f->pos[n] = (adem_vec3){0.0, y, z};
    f->velocity[n] = (adem_vec3){0.0, -wall * OMEGA * z, wall * OMEGA * y};
    f->radius[n++] = RP;
  }
  f->n = n;
  f->time = 1.0;
}

/* Claim: for a surface at 30 deg through z0 = -0.2 R, the surface fit gives 30 deg to 1 deg (the
 * columns' highest centres), the centre of mass's angle 30 deg to 1 deg (a uniform circular segment's
 * centre of mass lies on the normal to its chord through the axis), the flowing layer (rows at
 * 0, 2 and 4 mm below the surface row flow: 6 mm from the top row's tops to the first row
 * turning with the drum) 6 mm to a radius (the interpolation between bins of a radius), the wall layer's co-rotation
 * is 1 and its slip 0 to round-off when it turns with the drum, 0.4 and 0.6 omega rho when it
 * lags, and the gravity moment is g sum m y. */
static void test_measures(void **state) {
  (void)state;
  adem_drum_geometry g = {{0, 0, 0}, {1, 0, 0}, R, OMEGA, {0, 0, -9.81}};
  for (int lag = 0; lag < 2; ++lag) {
    adem_vtu_frame f;
    memset(&f, 0, sizeof f);
    make_frame(&f, 30.0 * PI / 180.0, -0.2 * R, 0.006, lag ? 0.4 : 1.0);
    double *m = malloc(f.n * sizeof *m), moment = 0.0;
    for (size_t i = 0; i < f.n; ++i) {
      m[i] = 1e-5;
      moment += 9.81 * m[i] * f.pos[i].y;
    }
    adem_drum_frame out;
    adem_error err;
    if (adem_drum_measure(&g, &f, m, &out, &err)) fail_msg("%s", err.message);
    printf("# %zu spheres: fit %.3f deg (R^2 %.4f), centre of mass %.3f deg, layer %.3f mm, "
           "wall layer %zu co-rotation %.6f slip %.3g m/s, moment %.6g (%.6g) N m\n",
           f.n, out.angle_fit_deg, out.fit_r2, out.angle_cm_deg, out.layer_m * 1000.0,
           out.wall_layer, out.corotation, out.slip_m_s, out.moment_Nm, moment);
    assert_true(fabs(out.angle_fit_deg - 30.0) <= 1.0);
    assert_true(fabs(out.angle_cm_deg - 30.0) <= 1.0);
    assert_true(fabs(out.layer_m - 0.006) <= RP);
    assert_true(out.wall_layer >= 50);
    if (!lag) assert_true(fabs(out.corotation - 1.0) <= 1e-12 && fabs(out.slip_m_s) <= 1e-12);
    else assert_true(fabs(out.corotation - 0.4) <= 1e-12 &&
                     fabs(out.slip_m_s - 0.6 * OMEGA * (R - RP)) <= 1e-12);
    assert_true(fabs(out.moment_Nm - moment) <= 1e-12 * fabs(moment));
    free(m);
    adem_vtu_frame_free(&f);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_measures)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
