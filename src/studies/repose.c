/* Measuring a pile in a result folder (`adem analyze repose`): the last particle frame, the pile
 * measurement of adem/pile.h, and the profile as CSV and PNG beside the run's files. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/frames.h"
#include "adem/files.h"
#include "adem/internal/plot.h"
#include "adem/pile.h"

adem_status adem_frames_last(const char *outdir, char **path, adem_error *err) {
  *path = NULL;
  char *fdir = adem_file_join(outdir, "frames");
  if (!fdir) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  DIR *d = opendir(fdir);
  if (!d) {
    adem_status st = adem_error_set(err, ADEM_ERR_INPUT,
                                    "%s has no frames/ folder: is it the output folder of a run "
                                    "with output.frame_interval > 0?",
                                    outdir);
    free(fdir);
    return st;
  }
  char *best = NULL;
  struct dirent *e;
  while ((e = readdir(d))) {
    size_t len = strlen(e->d_name);
    if (strncmp(e->d_name, "particles_", 10) != 0 || len < 15 || strcmp(e->d_name + len - 4, ".vtu"))
      continue;
    if (!best || strcmp(e->d_name, best) > 0) {
      /* names are particles_NNNNNN.vtu: the largest name is the last frame */
      char *nb = realloc(best, len + 1);
      if (!nb) break;
      best = nb;
      memcpy(best, e->d_name, len + 1);
    }
  }
  closedir(d);
  adem_status st = ADEM_OK;
  if (!best) st = adem_error_set(err, ADEM_ERR_INPUT, "%s holds no particles_*.vtu frame", fdir);
  else if (!(*path = adem_file_join(fdir, best))) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  free(best);
  free(fdir);
  return st;
}

/* The profile: surface particles (kind 0), slice radii (kind 1) and ring tops (kind 2), with
 * whether each entered its fit. */
static adem_status write_profile(const char *csv, const adem_pile_result *r, adem_error *err) {
  adem_afile af;
  adem_status st = adem_file_open(&af, csv, err);
  if (st) return st;
  fprintf(af.f, "kind,rho_m,z_m,used\n");
  for (size_t i = 0; i < r->n_surface_pts; ++i)
    fprintf(af.f, "0,%.9g,%.9g,%d\n", r->surface_pts[i].rho, r->surface_pts[i].z,
            r->surface_pts[i].used);
  for (size_t i = 0; i < r->n_slice_pts; ++i)
    fprintf(af.f, "1,%.9g,%.9g,%d\n", r->slice_pts[i].rho, r->slice_pts[i].z, r->slice_pts[i].used);
  for (size_t i = 0; i < r->n_ring_pts; ++i)
    fprintf(af.f, "2,%.9g,%.9g,%d\n", r->ring_pts[i].rho, r->ring_pts[i].z, r->ring_pts[i].used);
  return adem_file_commit(&af, err);
}

/* Every measure of the pile as one row (docs/validation.md, "The measure"). */
static adem_status write_measures(const char *csv, double time, const adem_pile_result *r,
                                  adem_error *err) {
  adem_afile af;
  adem_status st = adem_file_open(&af, csv, err);
  if (st) return st;
  fprintf(af.f, "time_s,particles,height_m,mean_diameter_m,angle_lab_deg,angle_lab_plain_deg,"
                "skirt_level_m,lab_base_radius_m,lab_base_sd_m,base_rings,angle_surface_deg,"
                "r2_surface,angle_slices_deg,r2_slices,angle_ringtop_deg,r2_ringtop,rings_in_fit,"
                "angle_footprint_deg,footprint_radius_m,base_radius_slices_m,axis_x_m,axis_y_m\n");
  fprintf(af.f, "%.9g,%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,"
                "%zu,%.9g,%.9g,%.9g,%.9g,%.9g\n",
          time, r->n_pile, r->height, r->mean_diameter, r->angle_lab_deg, r->angle_lab_plain_deg,
          r->skirt_level, r->lab_base_radius, r->lab_base_sd, r->base_rings, r->angle_surface_deg,
          r->surface.r2, r->angle_slices_deg, r->slices.r2, r->angle_ringtop_deg, r->ringtop.r2,
          r->ringtop.n, r->angle_footprint_deg, r->footprint_radius, r->base_radius, r->axis_x,
          r->axis_y);
  return adem_file_commit(&af, err);
}

static adem_status plot_profile(const char *png, const char *csv, const adem_pile_result *r,
                                adem_error *err) {
  char q[8192];
  char body[12288];
  double a = r->surface.intercept, b = r->surface.slope, c = r->slices.intercept, k = r->slices.slope;
  /* the ring-top line over its band, when there is one (else a point off the plot) */
  double ra = r->ringtop.intercept, rb = r->ringtop.slope;
  int ring_ok = isfinite(r->angle_ringtop_deg);
  double rx0 = ring_ok ? (0.8 * r->height - ra) / rb : 0.0, rx1 = ring_ok ? (0.2 * r->height - ra) / rb : 1e-9;
  if (!ring_ok) ra = rb = 0.0;
  snprintf(body, sizeof body,
           "set datafile separator ','\nset xlabel 'distance from the axis (m)'\n"
           "set ylabel 'height above the floor (m)'\nset key top right\nset size ratio -1\nset grid\n"
           "set title 'laboratory %.1f deg; surface fit %.1f (R^2 %.3f); slices %.1f (R^2 "
           "%.3f); ring tops %.1f deg'\nf = %s\n"
           "plot f using ($1 == 0 ? $2 : 1/0):3 with points pt 7 ps 0.5 lc rgb '#999999' "
           "title 'surface particles', \\\n"
           " f using ($1 == 0 && $4 == 1 ? $2 : 1/0):3 with points pt 7 ps 0.6 lc rgb '#1f77b4' "
           "title 'used in the fit', \\\n"
           " f using ($1 == 1 ? $2 : 1/0):3 with linespoints pt 6 lc rgb '#d62728' "
           "title 'slice r_{eq}', \\\n"
           " [x=%.17g:%.17g] %.17g + %.17g * x with lines lw 3 lc rgb '#1f77b4' title 'surface fit', \\\n"
           " [x=%.17g:%.17g] (x - %.17g) / %.17g with lines lw 3 dt 2 lc rgb '#d62728' "
           "title 'slice fit', \\\n"
           " f using ($1 == 2 ? $2 : 1/0):3 with steps lc rgb '#2ca02c' title 'ring tops', \\\n"
           " [x=%.17g:%.17g] %.17g + %.17g * x with lines lw 2 dt 3 lc rgb '#2ca02c' "
           "title 'ring-top line', \\\n"
           " '-' using 1:2 with linespoints pt 5 lw 2 lc rgb 'black' "
           "title 'laboratory: apex to base edge at the skirt level'\n"
           "0,%.17g\n%.17g,%.17g\ne\n",
           r->angle_lab_deg, r->angle_surface_deg, r->surface.r2, r->angle_slices_deg,
           r->slices.r2, r->angle_ringtop_deg, adem_plot_quote(csv, q, sizeof q),
           (r->band_zmax - a) / b, (r->band_zmin - a) / b, a, b, c + k * r->band_zmax,
           c + k * r->band_zmin, c, k, rx0, rx1, ra, rb, r->height, r->lab_base_radius,
           r->skirt_level);
  return adem_plot_png(png, 900, 600, body, err);
}

adem_status adem_repose_analyze(const char *outdir, const adem_pile_options *opt,
                                adem_repose_report *rep, adem_error *err) {
  memset(rep, 0, sizeof *rep);
  char *frame = NULL;
  adem_status st = adem_frames_last(outdir, &frame, err);
  adem_vtu_frame f;
  memset(&f, 0, sizeof f);
  if (!st) st = adem_vtu_read_file(frame, &f, err);
  if (!st) st = adem_pile_measure(f.pos, f.radius, f.n, opt, &rep->pile, err);
  if (!st) {
    rep->time = f.time;
    rep->particles = f.n;
    snprintf(rep->frame, sizeof rep->frame, "%s", frame);
    char *csv = adem_file_join(outdir, "repose_profile.csv");
    char *png = adem_file_join(outdir, "repose_profile.png");
    char *mcsv = adem_file_join(outdir, "repose_measures.csv");
    if (!csv || !png || !mcsv) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    if (!st) st = write_profile(csv, &rep->pile, err);
    if (!st) st = write_measures(mcsv, f.time, &rep->pile, err);
    if (!st) st = plot_profile(png, csv, &rep->pile, err);
    if (!st) {
      snprintf(rep->profile_csv, sizeof rep->profile_csv, "%s", csv);
      snprintf(rep->profile_png, sizeof rep->profile_png, "%s", png);
      snprintf(rep->measures_csv, sizeof rep->measures_csv, "%s", mcsv);
    }
    free(csv);
    free(png);
    free(mcsv);
    if (st) adem_pile_result_free(&rep->pile);
  }
  adem_vtu_frame_free(&f);
  free(frame);
  return st;
}

void adem_repose_report_free(adem_repose_report *rep) { adem_pile_result_free(&rep->pile); }
