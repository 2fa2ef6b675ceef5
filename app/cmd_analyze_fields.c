/* adem analyze fields OUTDIR: coarse-grained fields of a run's frames and contact frames
 * (adem/fields.h, docs/fields.md), written as fields.vti, fields.csv and a PNG. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/fields.h"
#include "adem/internal/plot.h"
#include "cli.h"

const char *const analyze_fields_help =
    "Usage: adem analyze fields OUTDIR [options]\n"
    "\n"
    "Coarse-grained continuum fields (Goldhirsch 2010, Weinhart et al. 2012) of a run's particle\n"
    "frames and contact frames (run the case with output.contacts: true): density, solid\n"
    "fraction, momentum, velocity, kinetic, contact and total stress (compressive positive),\n"
    "pressure, coordination number, fabric and granular temperature on a grid, averaged over the\n"
    "frames of a time window. Writes OUT.vti (ParaView ImageData), OUT.csv (one row per node)\n"
    "and OUT.png (a profile, or a map of a 2-D grid or of the middle y slice of a 3-D one).\n"
    "\n"
    "Options:\n"
    "  --width W        kernel width: the standard deviation along an axis, in m or in mean\n"
    "                   diameters of the first frame used (`2d`, `0.5d`; default 1d)\n"
    "  --kernel K       gaussian (default) or lucy (support sqrt(12) W: the same variance)\n"
    "  --cutoff C       the Gaussian is cut off at C widths along each axis (default 3)\n"
    "  --cell H         grid spacing, m or in diameters (`0.25d`; default W/2)\n"
    "  --time T0:T1     frames with T0 <= t <= T1 (default: the last frame)\n"
    "  --average AXES   average over x, y or z or two of them (`x,y`: profiles along z)\n"
    "  --box X0:X1,Y0:Y1,Z0:Z1  the grid's extent, m (default: a cut-off beyond every centre;\n"
    "                   averaged axes: the particles' extent)\n"
    "  --plot NAME      the field of the PNG: density, solid_fraction, velocity_z, stress_zz,\n"
    "                   contact_stress_xz, pressure, coordination, temperature, ... (default:\n"
    "                   stress_zz for a profile, pressure otherwise)\n"
    "  --out PREFIX     output files PREFIX.vti, .csv, .png (default OUTDIR/fields)\n"
    "\n"
    "Each kernel is normalised on the grid: the grid integral of the density is the mass, and\n"
    "that of the contact stress the sum of f (x) l over the contacts, each contact's f (x) l\n"
    "spread along its branch line (centre to centre, or centre to a wall's contact point).\n"
    "\n"
    "Example:\n"
    "  adem run cases/fields/bed.yaml --out out/bed\n"
    "  adem analyze fields out/bed --average x,y --width 0.5d --cell 0.0002 --time 0.25:0.3\n"
    "\n"
    "Exit status: 0 written; 2 bad options or no usable frames.\n";

/* "2d" (diameters: *diam = 1) or a length in m. */
static int length_or_d(const char *s, double *x, int *diam) {
  char *end;
  *x = strtod(s, &end);
  if (end == s || !isfinite(*x) || *x <= 0.0) return 0;
  *diam = *end == 'd';
  return *end == '\0' || (*diam && end[1] == '\0');
}

static int range(const char *s, double *a, double *b) {
  char *end;
  *a = strtod(s, &end);
  if (end == s || *end != ':') return 0;
  const char *t = end + 1;
  *b = strtod(t, &end);
  return end != t && (*end == '\0' || *end == ',') && isfinite(*a) && isfinite(*b) && *a <= *b;
}

/* The CSV column (1-based) of NAME ("stress_zz", "density", "velocity_z"). */
static int column_of(const bool average[3], const char *name) {
  static const char *const comp9[9] = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
  static const char *const comp3[3] = {"x", "y", "z"};
  int col = 1;
  for (int a = 0; a < 3; ++a) col += !average[a];
  for (int q = 0; q < ADEM_CG_COUNT_; ++q) {
    int nc = adem_cg_field_components((adem_cg_field)q);
    const char *fn = adem_cg_field_name((adem_cg_field)q);
    for (int u = 0; u < nc; ++u, ++col) {
      char full[64];
      snprintf(full, sizeof full, "%s%s%s", fn, nc > 1 ? "_" : "",
               nc == 9 ? comp9[u] : nc == 3 ? comp3[u]
                                            : "");
      if (!strcmp(full, name)) return col;
    }
  }
  return 0;
}

int cmd_analyze_fields(int argc, char **argv) {
  if (argc < 1 || !strcmp(argv[0], "-h") || !strcmp(argv[0], "--help")) {
    fputs(analyze_fields_help, argc < 1 ? stderr : stdout);
    return argc < 1 ? EXIT_INPUT : EXIT_OK;
  }
  const char *dir = argv[0];
  adem_fields_run_options o = adem_fields_default_run_options();
  o.last_only = 1;
  double width = 1.0, cell = 0.5;
  int width_d = 1, cell_d = -1; /* cell: -1 = half the width */
  const char *plot = NULL, *out = NULL;
  for (int i = 1; i < argc; i += 2) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    int ok = v != NULL;
    if (ok && !strcmp(a, "--width")) ok = length_or_d(v, &width, &width_d);
    else if (ok && !strcmp(a, "--cell")) ok = length_or_d(v, &cell, &cell_d);
    else if (ok && !strcmp(a, "--kernel")) {
      if (!strcmp(v, "gaussian")) o.grid.kernel = ADEM_KERNEL_GAUSSIAN;
      else if (!strcmp(v, "lucy")) o.grid.kernel = ADEM_KERNEL_LUCY;
      else ok = 0;
    } else if (ok && !strcmp(a, "--cutoff")) {
      char *end;
      o.grid.cutoff = strtod(v, &end);
      ok = end != v && *end == '\0' && o.grid.cutoff >= 1.0 && o.grid.cutoff <= 10.0;
    } else if (ok && !strcmp(a, "--time")) {
      ok = range(v, &o.t0, &o.t1);
      o.last_only = 0;
    } else if (ok && !strcmp(a, "--average")) {
      for (const char *c = v; *c && ok; ++c) {
        if (*c >= 'x' && *c <= 'z' && !o.grid.average[*c - 'x']) o.grid.average[*c - 'x'] = 1;
        else if (*c != ',') ok = 0;
      }
      ok = ok && o.grid.average[0] + o.grid.average[1] + o.grid.average[2] <= 2;
    } else if (ok && !strcmp(a, "--box")) {
      const char *c = v;
      for (int ax = 0; ax < 3 && ok; ++ax) {
        ok = range(c, &o.grid.lo[ax], &o.grid.hi[ax]) && o.grid.lo[ax] < o.grid.hi[ax];
        c = strchr(c, ',');
        if (ax < 2) ok = ok && c && *++c;
      }
      o.box_given = 1;
    } else if (ok && !strcmp(a, "--plot")) plot = v;
    else if (ok && !strcmp(a, "--out")) out = v;
    else
      return fail(EXIT_INPUT, "unknown option or missing value '%s' for adem analyze fields (see: "
                              "adem analyze fields --help)",
                  a);
    if (!ok) return fail(EXIT_INPUT, "%s: bad value '%s' (see: adem analyze fields --help)", a, v);
  }
  int navg = o.grid.average[0] + o.grid.average[1] + o.grid.average[2];
  if (!plot) plot = navg == 2 ? "stress_zz" : "pressure";
  if (!column_of(o.grid.average, plot))
    return fail(EXIT_INPUT, "--plot: no field '%s' (e.g. density, velocity_z, stress_zz, "
                            "pressure)",
                plot);
  /* widths and cells in diameters are resolved by the library from the first frame */
  o.width_diameters = width_d ? width : 0.0;
  o.grid.width = width_d ? 1.0 : width;
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_fields *f = NULL;
  adem_fields_run_info info;
  adem_status st;
  if (cell_d > 0) o.cell_diameters = cell;
  else if (cell_d == 0) o.grid.cell = cell;
  else o.grid.cell = 0.0; /* half the width */
  st = adem_fields_run(dir, &o, &f, &info, &err);
  if (st) return fail(exit_code(st), "%s", err.message);
  char prefix[4096], vti[4200], csv[4200], png[4200];
  if (out) snprintf(prefix, sizeof prefix, "%s", out);
  else snprintf(prefix, sizeof prefix, "%s/fields", dir);
  snprintf(vti, sizeof vti, "%s.vti", prefix);
  snprintf(csv, sizeof csv, "%s.csv", prefix);
  snprintf(png, sizeof png, "%s.png", prefix);
  st = adem_fields_write_vti(f, vti, &err);
  if (!st) st = adem_fields_write_csv(f, csv, &err);
  size_t n[3];
  double origin[3], h;
  adem_fields_grid(f, n, origin, &h);
  double mass = 0.0, cs[9] = {0};
  if (!st) st = adem_fields_integral(f, ADEM_CG_DENSITY, &mass, &err);
  if (!st) st = adem_fields_integral(f, ADEM_CG_CONTACT_STRESS, cs, &err);
  if (!st) {
    /* the PNG: a profile, a map, or the middle y slice of a 3-D grid */
    int col = column_of(o.grid.average, plot);
    char body[12000], qcsv[8600];
    int free_axes[3], nf = 0;
    for (int a = 0; a < 3; ++a)
      if (!o.grid.average[a]) free_axes[nf++] = a;
    adem_plot_quote(csv, qcsv, sizeof qcsv);
    if (nf == 1)
      snprintf(body, sizeof body,
               "set datafile separator ','\nset grid\nset key off\nset xlabel '%s'\n"
               "set ylabel '%c (m)'\nset title '%s, %zu frame(s) t = %.4g..%.4g s, w = %.3g m'\n"
               "plot %s skip 1 using %d:1 with lines lw 2\n",
               plot, 'x' + free_axes[0], plot, info.frames, info.t_first, info.t_last, info.width,
               qcsv, col);
    else if (nf == 2)
      snprintf(body, sizeof body,
               "set datafile separator ','\nset size ratio -1\nset xlabel '%c (m)'\n"
               "set ylabel '%c (m)'\nset title '%s, %zu frame(s) t = %.4g..%.4g s, w = %.3g m'\n"
               "set palette rgb 33,13,10\nplot %s skip 1 using 1:2:%d with image notitle\n",
               'x' + free_axes[0], 'x' + free_axes[1], plot, info.frames, info.t_first,
               info.t_last, info.width, qcsv, col);
    else {
      double ymid = origin[1] + (double)(n[1] / 2) * h;
      snprintf(body, sizeof body,
               "set datafile separator ','\nset size ratio -1\nset xlabel 'x (m)'\n"
               "set ylabel 'z (m)'\nset title '%s at y = %.4g m, %zu frame(s), w = %.3g m'\n"
               "set palette rgb 33,13,10\n"
               "plot %s skip 1 using 1:($2 > %.17g && $2 < %.17g ? $3 : 1/0):%d with points "
               "pt 5 ps 0.5 palette notitle\n",
               plot, ymid, info.frames, info.width, qcsv, ymid - 0.5 * h, ymid + 0.5 * h, col);
    }
    adem_error perr;
    memset(&perr, 0, sizeof perr);
    if (adem_plot_png(png, 900, 700, body, &perr)) fprintf(stderr, "adem: %s\n", perr.message);
  }
  if (st) {
    adem_fields_free(f);
    return fail(exit_code(st), "%s", err.message);
  }
  printf("frames           %zu (t = %.6g .. %.6g s), last: %zu particles, %zu contacts\n",
         info.frames, info.t_first, info.t_last, info.particles, info.contacts);
  printf("kernel           %s, width %.4g m (mean diameter %.4g m)%s\n",
         o.grid.kernel == ADEM_KERNEL_LUCY ? "Lucy" : "Gaussian", info.width, info.mean_diameter,
         o.grid.kernel == ADEM_KERNEL_LUCY ? "" : ", cut off at the given widths");
  printf("grid             %zu x %zu x %zu nodes, cell %.4g m, origin (%.4g, %.4g, %.4g) m\n",
         n[0], n[1], n[2], h, origin[0], origin[1], origin[2]);
  printf("mass             grid integral %.12g kg, particles %.12g kg (last frame)\n", mass,
         info.mass);
  printf("contact stress   grid integral (xx yy zz) %.6g %.6g %.6g N m\n", cs[0], cs[4], cs[8]);
  printf("files            %s, %s, %s\n", vti, csv, png);
  adem_fields_free(f);
  return EXIT_OK;
}
