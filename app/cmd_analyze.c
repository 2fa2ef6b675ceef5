/* adem analyze: measurements on a run's output folder. `adem analyze repose OUTDIR` measures the
 * pile in the last frame (angle of repose by two methods, height, base radius). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "cli.h"

const char *const analyze_help =
    "Usage: adem analyze repose OUTDIR [options]\n"
    "\n"
    "Measures the pile in the last particle frame of a run's output folder (frames/) and writes\n"
    "its profile as OUTDIR/repose_profile.csv and OUTDIR/repose_profile.png. The angle comes by\n"
    "two methods: (a) a fit of the surface particles' height against their distance from the\n"
    "pile's axis over the middle band of its height; (b) the slope of horizontal slices'\n"
    "equivalent radii against height; (c) the laboratory angle atan((H - h_e) / R_base), H the\n"
    "height, R_base the radius of the continuous base (rings out to the first one whose top is\n"
    "below the skirt level h_e: spheres that rolled away are not the base), the primary measure;\n"
    "(d) the least-squares line of the ring tops over 20-80 % of H; (e) height over footprint.\n"
    "Every measure goes to OUTDIR/repose_measures.csv (docs/validation.md, \"The measure\").\n"
    "\n"
    "Options:\n"
    "  --floor Z        height of the floor, m (default 0)\n"
    "  --axis X,Y       the pile's axis (default: its centroid)\n"
    "  --band LO,HI     fit band as fractions of the height (default 0.25,0.75)\n"
    "  --zmax Z         leave out centres above floor + Z (spheres still in a hopper)\n"
    "  --rmax R         leave out centres farther than R from the axis (spheres that rolled away)\n"
    "\n"
    "Example:\n"
    "  adem run cases/irazabal/repose.yaml --out out/repose && adem analyze repose out/repose --zmax 0.65\n"
    "\n"
    "Exit status: 0 measured; 2 bad options or no usable frame or pile.\n";

static int pair(const char *s, double *a, double *b) {
  char *end;
  *a = strtod(s, &end);
  if (end == s || *end != ',') return 0;
  const char *t = end + 1;
  *b = strtod(t, &end);
  return end != t && *end == '\0' && isfinite(*a) && isfinite(*b);
}

static int number(const char *s, double *x) {
  char *end;
  *x = strtod(s, &end);
  return end != s && *end == '\0' && isfinite(*x);
}

int cmd_analyze(int argc, char **argv) {
  if (argc < 1 || !strcmp(argv[0], "-h") || !strcmp(argv[0], "--help")) {
    fputs(analyze_help, argc < 1 ? stderr : stdout);
    return argc < 1 ? EXIT_INPUT : EXIT_OK;
  }
  if (strcmp(argv[0], "repose") != 0)
    return fail(EXIT_INPUT, "unknown analysis '%s'; there is: repose (see: adem analyze --help)",
                argv[0]);
  if (argc < 2) return fail(EXIT_INPUT, "adem analyze repose needs a run's output folder");
  const char *dir = argv[1];
  adem_pile_options opt = adem_pile_default_options();
  for (int i = 2; i < argc; i += 2) { /* option and value */
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    int ok = v != NULL;
    if (ok && !strcmp(a, "--floor")) ok = number(v, &opt.floor_z);
    else if (ok && !strcmp(a, "--zmax")) ok = number(v, &opt.zmax);
    else if (ok && !strcmp(a, "--rmax")) ok = number(v, &opt.rmax);
    else if (ok && !strcmp(a, "--axis")) ok = opt.axis_given = pair(v, &opt.axis_x, &opt.axis_y);
    else if (ok && !strcmp(a, "--band")) ok = pair(v, &opt.band_lo, &opt.band_hi);
    else
      return fail(EXIT_INPUT, "unknown option or missing value '%s' for adem analyze repose (see: "
                              "adem analyze --help)", a);
    if (!ok) return fail(EXIT_INPUT, "%s: bad value '%s'", a, v);
  }
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_repose_report rep;
  adem_status st = adem_repose_analyze(dir, &opt, &rep, &err);
  if (st) return fail(exit_code(st), "%s", err.message);
  const adem_pile_result *r = &rep.pile;
  printf("frame            %s (t = %.4f s, %zu particles)\n", rep.frame, rep.time, rep.particles);
  printf("pile             %zu particles, axis (%.4f, %.4f) m, mean diameter %.4f m\n", r->n_pile,
         r->axis_x, r->axis_y, r->mean_diameter);
  printf("height           %.4f m; fit band %.4f..%.4f m\n", r->height, r->band_zmin, r->band_zmax);
  printf("base radius      %.4f m (slice fit at the floor); footprint %.4f m (first layer)\n",
         r->base_radius, r->footprint_radius);
  printf("surface fit      %.2f deg (R^2 %.4f, %zu surface particles)\n", r->angle_surface_deg,
         r->surface.r2, r->surface.n);
  printf("slice radii      %.2f deg (R^2 %.4f, %zu slices)\n", r->angle_slices_deg, r->slices.r2,
         r->slices.n);
  printf("laboratory       %.2f deg = atan((H - h_e) / R_base), h_e %.4f m, R_base %.4f m (sd %.4f "
         "over the sectors), %zu base rings; plain atan(H / R_base) %.2f deg  [primary]\n",
         r->angle_lab_deg, r->skirt_level, r->lab_base_radius, r->lab_base_sd, r->base_rings,
         r->angle_lab_plain_deg);
  printf("ring-top line    %.2f deg (R^2 %.4f, %zu rings over 20-80 %% of H)\n",
         r->angle_ringtop_deg, r->ringtop.r2, r->ringtop.n);
  printf("height/footprint %.2f deg (footprint %.4f m, spheres that rolled away included)\n",
         r->angle_footprint_deg, r->footprint_radius);
  printf("profile          %s, %s\nmeasures         %s\n", rep.profile_csv, rep.profile_png,
         rep.measures_csv);
  adem_repose_report_free(&rep);
  return EXIT_OK;
}
