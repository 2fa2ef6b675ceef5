/* adem analyze: measurements on a run's output folder. `adem analyze repose OUTDIR` measures the
 * pile in the last frame (angle of repose by two methods, height, base radius); `adem analyze
 * drum OUTDIR` the free surface of a rotating drum over its frames (adem/drum.h); `adem analyze
 * push PUSH_DIR` a sleeper push's shares by face (adem/studies.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/pile.h"
#include "adem/drum.h"
#include "adem/studies.h"
#include "cli.h"

const char *const analyze_help =
    "Usage: adem analyze repose OUTDIR [options]\n"
    "       adem analyze fields OUTDIR [options]   (coarse-grained fields: adem analyze fields --help)\n"
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
    "Exit status: 0 measured; 2 bad options or no usable frame or pile.\n"
    "\n"
    "Usage: adem analyze drum OUTDIR [--from T] [--wall NAME]\n"
    "\n"
    "Measures the free surface of a rotating drum (a `type: cylinder` wall, from the run's\n"
    "checkpoint) over the particle frames at or after T s (default: the last two thirds of the\n"
    "run): the dynamic angle by a line fit of the surface particles over the middle half of the\n"
    "chord and by the bed's centre of mass, the regime (rolling, or slumping: the angle's\n"
    "sawtooth), the flowing layer's thickness on the normal to the surface through the axis\n"
    "(where the velocity along the surface turns from downhill to uphill), the wall layer's\n"
    "co-rotation (its mean tangential speed over the drum's at its centres) and slip speed, and\n"
    "the drive torque (the CSV's WALL_t_axis_Nm) against the bed's gravity moment m g x_cm.\n"
    "Writes OUTDIR/drum.csv (per frame) and OUTDIR/drum.png (docs/walls.md).\n"
    "\n"
    "Usage: adem analyze push PUSH_DIR\n"
    "\n"
    "The lateral resistance of a sleeper push of cases/irazabal/ballast (push.yaml, or a variant\n"
    "such as ballast/vertical-crib.sh's) and its shares by face group, read from the push's\n"
    "timeseries.csv as `adem validate irazabal-fig17` reads its own: base, cribs, shoulder end\n"
    "and far end at 0-0.3, 1, 3 and 6 mm, and the displacement from which the shoulder carries\n"
    "the most (Irazabal et al. 2017, Fig. 17). Writes PUSH_DIR/shares.csv and shares.png.\n";

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

static int analyze_drum(int argc, char **argv) {
  if (argc < 2) return fail(EXIT_INPUT, "adem analyze drum needs a run's output folder");
  adem_drum_options opt = adem_drum_default_options();
  for (int i = 2; i < argc; i += 2) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    int ok = v != NULL;
    if (ok && !strcmp(a, "--from")) ok = number(v, &opt.from);
    else if (ok && !strcmp(a, "--wall")) ok = snprintf(opt.wall, sizeof opt.wall, "%s", v) < (int)sizeof opt.wall;
    else
      return fail(EXIT_INPUT, "unknown option or missing value '%s' for adem analyze drum (see: "
                              "adem analyze --help)",
                  a);
    if (!ok) return fail(EXIT_INPUT, "%s: bad value '%s'", a, v);
  }
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_drum_report r;
  adem_status st = adem_drum_analyze(argv[1], &opt, &r, &err);
  if (st) return fail(exit_code(st), "%s", err.message);
  const adem_drum_frame *f = r.frames;
  printf("drum             R = %.4g m, omega = %.4g rad/s, Froude omega^2 R/g = %.3g\n", r.radius,
         r.omega, r.froude);
  printf("bed              %zu particles, %.6g kg; %zu frames, t = %.4g .. %.4g s\n", r.particles,
         r.mass, r.nframes, f[0].time, f[r.nframes - 1].time);
  printf("dynamic angle    surface fit %.2f +- %.2f deg, centre of mass %.2f +- %.2f deg\n",
         r.angle_fit_deg, r.angle_fit_sd, r.angle_cm_deg, r.angle_cm_sd);
  printf("regime           %s (angle excursion %.2f deg, skewness of its changes %.2f, %zu drops "
         "> 1 deg, %zu of %zu frames with the wall layer below half the drum's rate)\n",
         r.regime,
         r.excursion_deg, r.skewness, r.drops, r.slipping_frames, r.nframes);
  printf("flowing layer    %.3g mm thick (mean over the frames that flow)\n", r.layer_m * 1000.0);
  printf("wall layer       co-rotation %.3f (1: turns with the drum), slip %.4g m/s\n",
         r.corotation, r.slip_m_s);
  if (r.torque_rows)
    printf("torque balance   drive torque %.6g N m (%zu CSV rows), gravity moment m g x_cm %.6g N m: "
           "ratio %.4f\n",
           r.torque_Nm, r.torque_rows, r.moment_Nm, r.torque_Nm / r.moment_Nm);
  else
    printf("torque balance   gravity moment m g x_cm %.6g N m (no drive torque column in the CSV)\n",
           r.moment_Nm);
  printf("written          %s, %s\n", r.csv, r.png);
  adem_drum_report_free(&r);
  return EXIT_OK;
}

static int analyze_push(int argc, char **argv) {
  if (argc != 2) return fail(EXIT_INPUT, "adem analyze push needs a push's output folder and nothing else");
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_push_shares r;
  adem_status st = adem_push_shares_analyze(argv[1], &r, &err);
  if (st) return fail(exit_code(st), "%s", err.message);
  static const char *const at[4] = {"0-0.3 mm", "1 mm", "3 mm", "6 mm"};
  printf("push             %s, to u = %.2f mm\n", argv[1], r.u_end * 1e3);
  printf("%-16s %9s %8s %8s %8s %8s\n", "share at", "R (kN)", "base", "cribs", "shoulder", "far end");
  for (int k = 0; k < 4; ++k) {
    printf("%-16s %9.2f", at[k], r.R[k] * 1e-3);
    for (int q = 0; q < 4; ++q) printf(" %7.1f%%", 100.0 * r.share[k][q]);
    printf("\n");
  }
  if (isfinite(r.crossing)) printf("shoulder         carries the most from u = %.1f mm\n", r.crossing * 1e3);
  else printf("shoulder         does not carry the most at the end\n");
  printf("written          %s%s%s\n", r.csv, r.png[0] ? ", " : "", r.png);
  return EXIT_OK;
}

int cmd_analyze(int argc, char **argv) {
  if (argc < 1 || !strcmp(argv[0], "-h") || !strcmp(argv[0], "--help")) {
    fputs(analyze_help, argc < 1 ? stderr : stdout);
    return argc < 1 ? EXIT_INPUT : EXIT_OK;
  }
  if (strcmp(argv[0], "fields") == 0) return cmd_analyze_fields(argc - 1, argv + 1);
  if (!strcmp(argv[0], "drum")) return analyze_drum(argc, argv);
  if (!strcmp(argv[0], "push")) return analyze_push(argc, argv);
  if (strcmp(argv[0], "repose") != 0)
    return fail(EXIT_INPUT, "unknown analysis '%s'; there are: repose, fields, drum, push (see: adem "
                            "analyze --help)",
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
                              "adem analyze --help)",
                  a);
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
