/* Claim: the CSV's drive columns of a moving mesh wall account for its work: a sphere dragged by
 * friction on a turntable (a mesh plate turning at 20 rad/s about z under a sphere 1 cm off the
 * axis) takes from it, step by step, the power -(F . v_ref + T_ref . omega) the CSV reports,
 * whose time integral (trapezoid over every step's row) equals the energy balance's wall work
 * (wall_work_J); and for a wall that only turns, the power is -T_axis omega at every row, the
 * torque about the axis taken through the axis's point (T_ref + (ref - c) x F), the power
 * through the reference point's velocity: a sign or a lever arm wrong in either column fails. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "world_internal.h"
#include "case_file.h"
#include "cli_run.h"
#include "plate_stl.h"

/* The turntable (tests/cases/turntable.yaml) and the spheres on it (brof-balance.yaml). */

/* The CSV's columns NAMES (n of them) row by row: rows[r * n + c]; returns the row count. */
static int read_columns(const char *path, const char *const *names, int n, double **rows) {
  FILE *g = fopen(path, "r");
  assert_non_null(g);
  static char line[1 << 14];
  assert_non_null(fgets(line, sizeof line, g));
  int col[8], k = 0;
  assert_true(n <= 8);
  for (int c = 0; c < n; ++c) col[c] = -1;
  for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), ++k)
    for (int c = 0; c < n; ++c)
      if (!strcmp(tok, names[c])) col[c] = k;
  for (int c = 0; c < n; ++c)
    if (col[c] < 0) fail_msg("no column %s in %s", names[c], path);
  int nrows = 0, cap = 0;
  *rows = NULL;
  while (fgets(line, sizeof line, g)) {
    if (nrows == cap) {
      cap = cap ? 2 * cap : 1024;
      *rows = realloc(*rows, (size_t)cap * (size_t)n * sizeof **rows);
      assert_non_null(*rows);
    }
    k = 0;
    for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), ++k)
      for (int c = 0; c < n; ++c)
        if (k == col[c]) (*rows)[nrows * n + c] = strtod(tok, NULL);
    nrows++;
  }
  fclose(g);
  return nrows;
}

static void test_turntable_drive_columns(void **state) {
  (void)state;
  assert_int_equal(tmpdir_make("adem_wallpower"), 0);
  char path[600];
  snprintf(path, sizeof path, "%s/plate.stl", tmpdir);
  write_plate(path, 4, 0.0078125); /* 3.1 cm square plate centred on the axis */
  char *out;
  assert_int_equal(adem(&out, "run '%s' --set 'walls.table.file=%s' --quiet --out '%s/out'",
                        case_file_path("turntable"), path, tmpdir),
                   0);
  char csv[700];
  snprintf(csv, sizeof csv, "%s/out/timeseries.csv", tmpdir);
  const char *names[] = {"time_s", "wall_work_J", "table_drive_power_W", "table_axis_torque_Nm"};
  double *v;
  int rows = read_columns(csv, names, 4, &v);
  double integral = 0.0, torque_integral = 0.0;
  double worst = 0.0, pmax = 0.0; /* largest |P + omega T_axis| and |P| */
  for (int r = 0; r < rows; ++r) {
    const double *x = v + 4 * r, *y = x - 4;
    if (r > 0) {
      integral += 0.5 * (y[2] + x[2]) * (x[0] - y[0]);
      torque_integral += 0.5 * (y[3] + x[3]) * (x[0] - y[0]);
    }
    worst = fmax(worst, fabs(x[2] + 20.0 * x[3]));
    pmax = fmax(pmax, fabs(x[2]));
  }
  double work = v[4 * (rows - 1) + 1] - v[1];
  free(v);
  printf("# %d rows: integral of the drive power %.9g J, wall work %.9g J (ratio %.6f); integral "
         "of the axis torque %.6g N m s; |P + omega T_axis| at most %.2e of the largest |P|\n",
         rows, integral, work,
         integral / work, torque_integral, worst / pmax);
  assert_true(work > 0.0);
  /* the balance adds each contact's F . v_wall dt at the kicks: the same forces and velocities
   * the rows give, so the trapezoid sum matches it to round-off over 25,000 rows */
  assert_true(fabs(integral / work - 1.0) < 1e-6);
  assert_true(worst < 1e-12 * pmax);
  /* the drag speeds the sphere up about the axis: the particles' torque on the table about z
   * is against its turning (negative) while it drives them */
  assert_true(torque_integral < 0.0);
}

/* Claim: with BROF between particles the CSV closes the bed's angular-momentum balance about a
 * turntable's axis: four spheres in a tetrahedron carried by a mesh table turning at 5 rad/s
 * gain L_z = -integral of the particles' torque on the table about its axis
 * (table_axis_torque_Nm, trapezoid over every step's row) + the angular impulse BROF's particle
 * contacts add (brof_impulse_z_Nms), to 1e-4 of L_z (the orbital term's integration error:
 * 1.2e-5); without the BROF column the balance misses by 5.8e-2, the braking of the spheres'
 * spin. Gravity has no moment about the vertical axis. (The sphere-table pairs have no rolling
 * law here: BROF's wall share does not yet reach the mesh faces' moments, issue 25 item 6.) */
static void test_brof_torque_balance(void **state) {
  (void)state;
  assert_int_equal(tmpdir_make("adem_brofbalance"), 0);
  char path[600];
  snprintf(path, sizeof path, "%s/plate.stl", tmpdir);
  write_plate(path, 4, 0.0078125);
  const double r = 0.001, h = r * sqrt(8.0 / 3.0), x0 = 0.008;
  char spheres[600], table[700];
  snprintf(spheres, sizeof spheres,
           "particles.0.spheres=[{position: [%.17g, 0, %.17g], radius: %g},"
           " {position: [%.17g, %.17g, %.17g], radius: %g},"
           " {position: [%.17g, %.17g, %.17g], radius: %g},"
           " {position: [%.17g, %.17g, %.17g], radius: %g}]",
           x0 + 2.0 * r / sqrt(3.0), r, r, x0 - r / sqrt(3.0), r, r, r, x0 - r / sqrt(3.0), -r, r, r,
           x0, 0.0, r + h, r);
  snprintf(table, sizeof table, "walls.table.file=%s", path);
  const char *sets[] = {spheres, table};
  adem_case *c = case_file_load("brof-balance", sets, 2);
  adem_error err;
  snprintf(c->output.dir, sizeof c->output.dir, "%s/out", tmpdir);
  adem_run_options opt = adem_default_run_options();
  opt.nthreads = 1;
  if (adem_run(c, &opt, &err)) fail_msg("%s", err.message);
  const adem_world *w = c->world;
  double lz = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) {
    double m = 1.0 / w->p.inv_mass[i];
    lz += m * (w->p.pos[i].x * w->p.vel[i].y - w->p.pos[i].y * w->p.vel[i].x) +
          w->p.omega[i].z / w->p.inv_inertia[i];
  }
  char csv[700];
  snprintf(csv, sizeof csv, "%s/out/timeseries.csv", tmpdir);
  const char *names[] = {"time_s", "table_axis_torque_Nm", "brof_impulse_z_Nms"};
  double *v;
  int rows = read_columns(csv, names, 3, &v);
  double wall = 0.0;
  for (int r = 1; r < rows; ++r)
    wall -= 0.5 * (v[3 * (r - 1) + 1] + v[3 * r + 1]) * (v[3 * r] - v[3 * (r - 1)]);
  double brof = v[3 * (rows - 1) + 2];
  free(v);
  printf("# %d rows: L_z %.6e, from the table %.6e, from BROF %.6e: balance %.2e of L_z (without "
         "BROF %.2e)\n",
         rows, lz, wall, brof, (wall + brof - lz) / lz, (wall - lz) / lz);
  assert_true(lz > 0.0);
  assert_true(fabs(wall + brof - lz) < 1e-4 * lz);
  assert_true(fabs(wall - lz) > 10.0 * fabs(wall + brof - lz)); /* BROF's share is not negligible */
  adem_case_free(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_turntable_drive_columns),
                                     cmocka_unit_test(test_brof_torque_balance)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
