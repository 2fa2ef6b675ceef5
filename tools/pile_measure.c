/* adem_pile: measures the pile in the last particle frame of a result folder (or in one frame),
 * and counts particles below a height in every frame (the hopper's discharge). A stopgap for
 * issue 12 until `adem analyze repose` exists; it uses only src/studies.
 *
 *   adem_pile OUTDIR [--zmax 0.65] [--axis 0,0] [--profile prof.csv] [--png prof.png]
 *   adem_pile OUTDIR --count-below 0.7          # time, particles, below 0.7 m, per frame
 */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "studies/pile.h"
#include "studies/vtu_read.h"

static void usage(void) {
  fprintf(stderr,
          "usage: adem_pile OUTDIR|FRAME.vtu [--floor Z] [--axis X,Y] [--zmax Z] [--rmax R]\n"
          "                 [--band LO,HI] [--profile FILE.csv] [--png FILE.png]\n"
          "       adem_pile OUTDIR --count-below Z\n");
}

static int cmp_str(const void *a, const void *b) {
  return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* The sorted paths of OUTDIR/frames/particles_*.vtu; *n their count. */
static char **list_frames(const char *dir, size_t *n) {
  char fdir[4096];
  snprintf(fdir, sizeof fdir, "%s/frames", dir);
  DIR *d = opendir(fdir);
  *n = 0;
  if (!d) return NULL;
  size_t cap = 0;
  char **v = NULL;
  struct dirent *e;
  while ((e = readdir(d))) {
    size_t len = strlen(e->d_name);
    if (strncmp(e->d_name, "particles_", 10) != 0 || len < 5 || strcmp(e->d_name + len - 4, ".vtu"))
      continue;
    if (*n == cap) {
      cap = cap ? 2 * cap : 64;
      char **nv = realloc(v, cap * sizeof *v);
      if (!nv) break;
      v = nv;
    }
    size_t m = strlen(fdir) + len + 2;
    v[*n] = malloc(m);
    if (!v[*n]) break;
    snprintf(v[*n], m, "%s/%s", fdir, e->d_name);
    ++*n;
  }
  closedir(d);
  if (*n) qsort(v, *n, sizeof *v, cmp_str);
  return v;
}

static int parse_pair(const char *s, double *a, double *b) {
  return sscanf(s, "%lf,%lf", a, b) == 2 && isfinite(*a) && isfinite(*b);
}

static int write_png(const char *png, const char *csv, const adem_pile_result *r) {
  FILE *g = popen("gnuplot", "w");
  if (!g) return 0;
  fprintf(g,
          "set terminal pngcairo size 900,600\nset output '%s'\nset datafile separator ','\n"
          "set xlabel 'distance from the axis (m)'\nset ylabel 'height above the floor (m)'\n"
          "set key top right\nset size ratio -1\n"
          "set title sprintf('surface fit %%.1f deg (R^2 %%.3f), slices %%.1f deg (R^2 %%.3f)', "
          "%.6f, %.6f, %.6f, %.6f)\n"
          "a = %.17g; b = %.17g; c = %.17g; k = %.17g\n"
          "plot '%s' using ($1 == 0 ? $2 : 1/0):3 with points pt 7 ps 0.5 lc rgb '#999999' "
          "title 'surface particles', \\\n"
          " '%s' using ($1 == 0 && $4 == 1 ? $2 : 1/0):3 with points pt 7 ps 0.6 lc rgb '#1f77b4' "
          "title 'used in the fit', \\\n"
          " '%s' using ($1 == 1 ? $2 : 1/0):3 with linespoints pt 6 lc rgb '#d62728' "
          "title 'slice r_{eq}', \\\n"
          " [x=%.17g:%.17g] a + b * x with lines lw 2 lc rgb '#1f77b4' title 'surface fit', \\\n"
          " [x=%.17g:%.17g] (x - c) / k with lines lw 2 dt 2 lc rgb '#d62728' title 'slice fit'\n",
          png, r->angle_surface_deg, r->surface.r2, r->angle_slices_deg, r->slices.r2,
          r->surface.intercept, r->surface.slope, r->slices.intercept, r->slices.slope, csv, csv,
          csv, (r->band_zmax - r->surface.intercept) / r->surface.slope,
          (r->band_zmin - r->surface.intercept) / r->surface.slope,
          r->slices.intercept + r->slices.slope * r->band_zmax,
          r->slices.intercept + r->slices.slope * r->band_zmin);
  return pclose(g) == 0;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    usage();
    return 2;
  }
  const char *in = argv[1], *profile = NULL, *png = NULL;
  double count_below = NAN;
  adem_pile_options opt = adem_pile_default_options();
  for (int i = 2; i < argc; ++i) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (!v) {
      usage();
      return 2;
    }
    ++i;
    if (!strcmp(a, "--floor")) opt.floor_z = atof(v);
    else if (!strcmp(a, "--zmax")) opt.zmax = atof(v);
    else if (!strcmp(a, "--rmax")) opt.rmax = atof(v);
    else if (!strcmp(a, "--axis") && parse_pair(v, &opt.axis_x, &opt.axis_y)) opt.axis_given = 1;
    else if (!strcmp(a, "--band") && parse_pair(v, &opt.band_lo, &opt.band_hi)) {}
    else if (!strcmp(a, "--profile")) profile = v;
    else if (!strcmp(a, "--png")) png = v;
    else if (!strcmp(a, "--count-below")) count_below = atof(v);
    else {
      usage();
      return 2;
    }
  }
  struct stat sb;
  if (stat(in, &sb) != 0) {
    fprintf(stderr, "adem_pile: cannot read %s\n", in);
    return 2;
  }
  size_t nf = 0;
  char **frames = NULL;
  if (S_ISDIR(sb.st_mode)) {
    frames = list_frames(in, &nf);
    if (!nf) {
      fprintf(stderr, "adem_pile: no frames/particles_*.vtu in %s\n", in);
      return 2;
    }
  } else {
    frames = malloc(sizeof *frames);
    frames[0] = strdup(in);
    nf = 1;
  }
  adem_error err;
  adem_vtu_frame f;
  int rc = 0;
  if (!isnan(count_below)) {
    printf("time_s,particles,below_%g_m\n", count_below);
    for (size_t k = 0; k < nf && !rc; ++k) {
      if (adem_vtu_read_file(frames[k], &f, &err)) {
        fprintf(stderr, "adem_pile: %s\n", err.message);
        rc = 2;
        break;
      }
      size_t below = 0;
      for (size_t i = 0; i < f.n; ++i) below += f.pos[i].z < count_below;
      printf("%.6f,%zu,%zu\n", f.time, f.n, below);
      adem_vtu_frame_free(&f);
    }
  } else {
    const char *last = frames[nf - 1];
    adem_pile_result r;
    if (adem_vtu_read_file(last, &f, &err) ||
        adem_pile_measure(f.pos, f.radius, f.n, &opt, &r, &err)) {
      fprintf(stderr, "adem_pile: %s\n", err.message);
      rc = 2;
    } else {
      printf("frame            %s (t = %.4f s, %zu particles)\n", last, f.time, f.n);
      printf("pile             %zu particles, axis (%.4f, %.4f) m, mean diameter %.4f m\n",
             r.n_pile, r.axis_x, r.axis_y, r.mean_diameter);
      printf("height           %.4f m; fit band %.4f..%.4f m\n", r.height, r.band_zmin,
             r.band_zmax);
      printf("base radius      %.4f m (slice fit at the floor); footprint %.4f m (first layer)\n",
             r.base_radius, r.footprint_radius);
      printf("surface fit      %.2f deg (R^2 %.4f, %zu surface particles)\n", r.angle_surface_deg,
             r.surface.r2, r.surface.n);
      printf("slice radii      %.2f deg (R^2 %.4f, %zu slices)\n", r.angle_slices_deg,
             r.slices.r2, r.slices.n);
      if (profile || png) {
        /* --png alone: the profile CSV goes beside the PNG (FILE.png -> FILE.csv) */
        char beside[4096];
        if (!profile) {
          snprintf(beside, sizeof beside, "%s", png);
          size_t L = strlen(beside);
          if (L > 4 && !strcmp(beside + L - 4, ".png")) beside[L - 4] = '\0';
          strncat(beside, ".csv", sizeof beside - strlen(beside) - 1);
        }
        const char *csv = profile ? profile : beside;
        FILE *o = fopen(csv, "w");
        if (!o) {
          fprintf(stderr, "adem_pile: cannot write %s\n", csv);
          rc = 4;
        } else {
          fprintf(o, "kind,rho_m,z_m,used\n");
          for (size_t i = 0; i < r.n_surface_pts; ++i)
            fprintf(o, "0,%.9g,%.9g,%d\n", r.surface_pts[i].rho, r.surface_pts[i].z,
                    r.surface_pts[i].used);
          for (size_t i = 0; i < r.n_slice_pts; ++i)
            fprintf(o, "1,%.9g,%.9g,%d\n", r.slice_pts[i].rho, r.slice_pts[i].z,
                    r.slice_pts[i].used);
          fclose(o);
          if (png && !write_png(png, csv, &r)) {
            fprintf(stderr, "adem_pile: gnuplot could not write %s\n", png);
            rc = 4;
          }
        }
      }
      adem_pile_result_free(&r);
    }
    adem_vtu_frame_free(&f);
  }
  for (size_t k = 0; k < nf; ++k) free(frames[k]);
  free(frames);
  return rc;
}
