/* The coarse-grained stress of a bed at rest balances its weight (docs/fields.md).
 * cases/fields/bed.yaml: 450 spheres settled on a floor in a box periodic along x and y (no side
 * wall carries weight), run by the adem command with output.contacts; the fields averaged over
 * x, y of its last six frames (t = 0.25 .. 0.30 s, kinetic energy below 6e-10 J):
 * - sigma_zz(z) equals the weight per area of the material above z, g int_z rho dz', within 2%
 *   at every node from 3 diameters above the floor to 3 below the top centre (away from the floor
 *   and the free surface);
 * - the floor's sigma_zz, the stress the bed carries at the floor (sigma_zz just above the reach
 *   of the floor contacts plus the weight per area below that height), equals the floor's force
 *   over its area from the time series (column floor_fz_N, mean of the rows over the frames'
 *   window) within 2%.
 * Perturbed once each (recorded in docs/fields.md): particle pairs' f (x) l with half the branch
 * gives 50.0% in the first and 36.3% in the second; each contact's stress put at a's centre only
 * (no line integral) gives 7.0% in the first. Unperturbed: 0.06% and 0.02%. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli_run.h"
#include "adem/fields.h"

#define G 9.81
#define LXY 0.015 /* the periodic box's sides */

static char outdir[512];

static int setup(void **state) {
  (void)state;
  if (tmpdir_make("adem_fieldsbed")) return -1;
  snprintf(outdir, sizeof outdir, "%s/bed", tmpdir);
  return 0;
}

static void test_bed_balances_its_weight(void **state) {
  (void)state;
  char *out;
  assert_int_equal(adem(&out, "run %s/cases/fields/bed.yaml --out %s --threads 1", ADEM_SOURCE_DIR,
                        outdir),
                   0);
  adem_fields_run_options o = adem_fields_default_run_options();
  o.grid.average[0] = o.grid.average[1] = 1;
  o.width_diameters = 0.5;
  o.grid.cell = 0.0001;
  o.t0 = 0.25;
  o.t1 = 0.31;
  o.box_given = 1;
  double box_lo[3] = {0.0, 0.0, -0.004}, box_hi[3] = {LXY, LXY, 0.03};
  memcpy(o.grid.lo, box_lo, sizeof box_lo);
  memcpy(o.grid.hi, box_hi, sizeof box_hi);
  adem_fields *f = NULL;
  adem_fields_run_info info;
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_status st = adem_fields_run(outdir, &o, &f, &info, &err);
  if (st) fail_msg("%s", err.message);
  assert_int_equal(info.frames, 6);
  size_t n[3];
  double origin[3], h;
  adem_fields_grid(f, n, origin, &h);
  size_t nz = n[2];
  double *rho = malloc(nz * sizeof *rho), *sig = malloc(9 * nz * sizeof *sig);
  assert_int_equal(adem_fields_get(f, ADEM_CG_DENSITY, rho, nz, &err), ADEM_OK);
  assert_int_equal(adem_fields_get(f, ADEM_CG_STRESS, sig, 9 * nz, &err), ADEM_OK);
  /* the weight per area above node k: g times the density's integral from k up (the midpoint
   * rule on the nodes: half of node k's cell, then the cells above) */
  double *above = malloc(nz * sizeof *above);
  double s = 0.0;
  for (size_t k = nz; k-- > 0;) {
    above[k] = G * (s + 0.5 * rho[k] * h);
    s += rho[k] * h;
  }
  double total = G * s; /* = M g / A */
  printf("mass per area from the density %.6g kg/m^2, particles %.6g kg/m^2\n", s,
         info.mass / (LXY * LXY));
  /* the top: the highest centre of the last frame, from the solid fraction profile's extent is
   * not needed: the density falls to zero above the bed */
  double d = info.mean_diameter, ztop = origin[2];
  for (size_t k = 0; k < nz; ++k)
    if (rho[k] > 0.5 * rho[nz / 4]) ztop = origin[2] + (double)k * h;
  double worst = 0.0, zworst = 0.0;
  size_t used = 0;
  for (size_t k = 0; k < nz; ++k) {
    double z = origin[2] + (double)k * h;
    if (z < 3.0 * d || z > ztop - 3.0 * d) continue;
    double e = fabs(sig[9 * k + 8] - above[k]) / above[k];
    if (e > worst) worst = e, zworst = z;
    used++;
  }
  printf("sigma_zz against the weight above: %zu nodes from z = %.4g to %.4g m, largest error "
         "%.3f%% at z = %.4g m\n",
         used, 3.0 * d, ztop - 3.0 * d, 100.0 * worst, zworst);

  /* the floor: sigma_zz where the floor contacts (reaching 1 radius + 3 widths) no longer reach,
   * plus the weight per area below it */
  double zs = 0.5 * d + o.grid.cutoff * info.width + 2.0 * h;
  size_t ks = (size_t)ceil((zs - origin[2]) / h);
  double floor_sigma = sig[9 * ks + 8] + (total - above[ks]);
  /* the floor's force from the time series at the frames' times */
  char *csv = path_in_tmp("bed/timeseries.csv");
  FILE *fp = fopen(csv, "r");
  assert_non_null(fp);
  static char line[1 << 14];
  assert_non_null(fgets(line, sizeof line, fp));
  int col = -1, c = 0;
  for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), ++c)
    if (!strcmp(tok, "floor_fz_N")) col = c;
  assert_true(col > 0);
  double fsum = 0.0;
  int rows = 0;
  while (fgets(line, sizeof line, fp)) {
    double t = strtod(line, NULL), v = 0.0;
    if (t < info.t_first - 1e-9 || t > info.t_last + 1e-9) continue;
    c = 0;
    for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), ++c)
      if (c == col) v = strtod(tok, NULL);
    fsum += v;
    rows++;
  }
  fclose(fp);
  free(csv);
  assert_true(rows >= 40); /* the rows over the frames' window */
  double floor_load = fabs(fsum / rows) / (LXY * LXY);
  double ef = fabs(floor_sigma - floor_load) / floor_load;
  printf("floor: sigma_zz %.5g Pa (at z = %.4g m plus the weight below), force / area from the "
         "time series %.5g Pa: %.3f%%; weight per area %.5g Pa\n",
         floor_sigma,
         origin[2] + (double)ks * h, floor_load, 100.0 * ef, total);
  assert_true(used > 20);
  assert_true(worst < 0.02);
  assert_true(ef < 0.02);
  free(rho);
  free(sig);
  free(above);
  adem_fields_free(f);

  /* the command: writes its files and reports the mass */
  assert_int_equal(adem(&out, "analyze fields %s --average x,y --width 0.5d --cell 0.0002 "
                              "--time 0.25:0.31",
                        outdir),
                   0);
  assert_non_null(strstr(out, "frames           6"));
  char *vti = path_in_tmp("bed/fields.vti");
  FILE *vf = fopen(vti, "r");
  assert_non_null(vf);
  fclose(vf);
  free(vti);
  assert_int_equal(adem(&out, "analyze fields %s --width -1", outdir), 2);
  assert_int_equal(adem(&out, "analyze fields %s --plot nosuch", outdir), 2);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_bed_balances_its_weight)};
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
