/* The free surface of a rotating drum (`adem analyze drum`, adem/drum.h). The cross-section is
 * seen along the drum's axis a: e_up is up (against gravity, across a), e_h the horizontal
 * direction the drum's bottom moves to, so that the bed is lifted towards +e_h and its surface
 * rises towards +e_h at the dynamic angle. */
#include <dirent.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/case.h"
#include "adem/frames.h"
#include "adem/files.h"
#include "adem/internal/plot.h"
#include "adem/run.h"
#include "adem/world.h"
#include "adem/drum.h"
#include "adem/vec3.h"

static const double DEG = 57.29577951308232;

adem_drum_options adem_drum_default_options(void) {
  adem_drum_options o;
  memset(&o, 0, sizeof o);
  o.from = NAN;
  return o;
}

void adem_drum_report_free(adem_drum_report *rep) {
  free(rep->frames);
  rep->frames = NULL;
}

static int compare_names(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The particle frames of outdir/frames, in order (names particles_NNNNNN.vtu). */
static adem_status list_frames(const char *outdir, char ***names, size_t *n, adem_error *err) {
  *names = NULL;
  *n = 0;
  char *fdir = adem_file_join(outdir, "frames");
  if (!fdir) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  DIR *d = opendir(fdir);
  if (!d) {
    free(fdir);
    return adem_error_set(err, ADEM_ERR_INPUT, "%s has no frames/ folder: is it the output "
                                               "folder of a run with output.frame_interval > 0?",
                          outdir);
  }
  adem_status st = ADEM_OK;
  size_t cap = 0;
  struct dirent *e;
  while (!st && (e = readdir(d))) {
    size_t len = strlen(e->d_name);
    if (strncmp(e->d_name, "particles_", 10) != 0 || len < 15 || strcmp(e->d_name + len - 4, ".vtu"))
      continue;
    if (*n == cap) {
      cap = cap ? 2 * cap : 64;
      char **nn = realloc(*names, cap * sizeof *nn);
      if (!nn) {
        st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
        break;
      }
      *names = nn;
    }
    if (!((*names)[*n] = adem_file_join(fdir, e->d_name))) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    else ++*n;
  }
  closedir(d);
  free(fdir);
  if (!st && *n == 0) st = adem_error_set(err, ADEM_ERR_INPUT, "%s/frames holds no particles_*.vtu frame", outdir);
  if (!st) qsort(*names, *n, sizeof **names, compare_names);
  return st;
}

/* The drum: a cylinder wall of the run's checkpoint, its rotation, gravity, the masses by id. */
typedef struct drum_setup {
  adem_vec3 point, axis, up, h; /* a point of the axis, the axis, e_up, e_h */
  double radius, omega, g;
  char name[ADEM_NAME_MAX];
  double *mass; /* by particle id */
  size_t nmass;
  double density; /* the bed's mean, for particles without a known id */
} drum_setup;

static bool orient(drum_setup *s, adem_vec3 g);

static adem_status load_setup(const char *outdir, const adem_drum_options *opt, drum_setup *s,
                              adem_error *err) {
  memset(s, 0, sizeof *s);
  char *ck = adem_file_join(outdir, "checkpoint");
  if (!ck) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_case *c = NULL;
  adem_status st = adem_checkpoint_read(ck, &c, err);
  free(ck);
  if (st) return st;
  adem_world *w = c->world;
  int found = -1;
  for (int k = 0; k < adem_world_plane_count(w) && found < 0; ++k) {
    const adem_plane_def *d = adem_world_plane(w, k);
    if (d->shape == ADEM_WALL_CYLINDER && (!opt->wall[0] || !strcmp(opt->wall, d->name))) found = k;
  }
  if (found < 0) {
    st = opt->wall[0] ? adem_error_set(err, ADEM_ERR_INPUT, "%s: no cylinder wall named '%s'", outdir, opt->wall)
                      : adem_error_set(err, ADEM_ERR_INPUT, "%s: the run has no cylinder wall "
                                                            "(`walls[].type: cylinder`) to take as the drum",
                                       outdir);
  }
  const adem_plane_def *d = found >= 0 ? adem_world_plane(w, found) : NULL;
  if (!st && (d->flags & ADEM_WALL_OUTSIDE))
    st = adem_error_set(err, ADEM_ERR_INPUT, "cylinder '%s' is touched from outside: not a drum", d->name);
  adem_vec3 g = adem_world_gravity(w);
  if (!st) {
    s->point = d->point;
    s->axis = d->normal;
    s->radius = d->radius;
    snprintf(s->name, sizeof s->name, "%s", d->name);
    adem_vec3 rax;
    double om = adem_world_plane_rotation(w, found, &rax, NULL);
    s->omega = om * v3_dot(rax, s->axis);
    if (!orient(s, g))
      st = adem_error_set(err, ADEM_ERR_INPUT, "gravity is along the drum's axis (or zero): no free surface");
  }
  size_t n = adem_world_particle_count(w);
  if (!st) {
    s->mass = malloc((n ? n : 1) * sizeof *s->mass);
    double *r = malloc((n ? n : 1) * sizeof *r);
    if (!s->mass || !r) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    if (!st) st = adem_world_get_particles(w, ADEM_FIELD_MASS, s->mass, n, err);
    if (!st) st = adem_world_get_particles(w, ADEM_FIELD_RADIUS, r, n, err);
    double m = 0.0, v = 0.0;
    for (size_t i = 0; !st && i < n; ++i) {
      m += s->mass[i];
      v += 4.0 / 3.0 * 3.14159265358979323846 * r[i] * r[i] * r[i];
    }
    s->density = v > 0.0 ? m / v : 0.0;
    s->nmass = n;
    free(r);
  }
  adem_case_free(c);
  return st;
}

typedef struct xs_particle {
  double u, w, vu, vw, r, m;
} xs_particle;

/* Least squares w = a + b u. */
static void fit_line(const double *u, const double *w, size_t n, double *a, double *b, double *r2) {
  double su = 0, sw = 0, suu = 0, suw = 0, sww = 0;
  for (size_t i = 0; i < n; ++i) {
    su += u[i];
    sw += w[i];
    suu += u[i] * u[i];
    suw += u[i] * w[i];
    sww += w[i] * w[i];
  }
  double dn = (double)n, cuu = suu - su * su / dn, cuw = suw - su * sw / dn, cww = sww - sw * sw / dn;
  *b = cuu > 0.0 ? cuw / cuu : NAN;
  *a = (sw - *b * su) / dn;
  *r2 = cuu > 0.0 && cww > 0.0 ? cuw * cuw / (cuu * cww) : NAN;
}

static adem_status measure_frame(const drum_setup *s, const adem_vtu_frame *f, const double *pmass,
                                 adem_drum_frame *out, double *bed_mass, adem_error *err) {
  size_t n = f->n;
  xs_particle *q = malloc((n ? n : 1) * sizeof *q);
  double *bu = NULL, *bw = NULL;
  if (!q) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  double M = 0.0, mu = 0.0, mw = 0.0, rsum = 0.0, umin = INFINITY, umax = -INFINITY;
  for (size_t i = 0; i < n; ++i) {
    adem_vec3 d = v3_sub(f->pos[i], s->point);
    adem_vec3 v = f->velocity ? f->velocity[i] : v3_zero();
    xs_particle *p = &q[i];
    p->u = v3_dot(d, s->h);
    p->w = v3_dot(d, s->up);
    p->vu = v3_dot(v, s->h);
    p->vw = v3_dot(v, s->up);
    p->r = f->radius[i];
    bool known = f->id && f->id[i] >= 0 && (size_t)f->id[i] < s->nmass;
    p->m = pmass   ? pmass[i]
           : known ? s->mass[f->id[i]]
                   : s->density * 4.0 / 3.0 * 3.14159265358979323846 * p->r * p->r * p->r;
    M += p->m;
    mu += p->m * p->u;
    mw += p->m * p->w;
    rsum += p->r;
    umin = fmin(umin, p->u);
    umax = fmax(umax, p->u);
  }
  memset(out, 0, sizeof *out);
  out->time = f->time;
  *bed_mass = M;
  double rmean = n ? rsum / (double)n : 0.0, dm = 2.0 * rmean;
  /* the centre of mass's angle from the bottom, and the gravity moment about the axis (the
   * drive torque in steady rotation): m g x_cm */
  out->angle_cm_deg = atan2(mu / M, -mw / M) * DEG;
  out->moment_Nm = s->g * mu;
  /* surface: the highest centre in each bin of a diameter across the chord, fitted over the
   * middle half of the chord */
  size_t nb = n && umax > umin ? (size_t)((umax - umin) / dm) + 1 : 0;
  bu = malloc((nb ? nb : 1) * sizeof *bu);
  bw = malloc((nb ? nb : 1) * sizeof *bw);
  size_t *top = malloc((nb ? nb : 1) * sizeof *top);
  if (!bu || !bw || !top) {
    free(q), free(bu), free(bw), free(top);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  for (size_t b = 0; b < nb; ++b) top[b] = SIZE_MAX;
  for (size_t i = 0; i < n; ++i) {
    size_t b = (size_t)((q[i].u - umin) / dm);
    if (b >= nb) b = nb - 1;
    if (top[b] == SIZE_MAX || q[i].w > q[top[b]].w) top[b] = i;
  }
  double lo = umin + 0.25 * (umax - umin), hi = umax - 0.25 * (umax - umin);
  size_t m = 0;
  for (size_t b = 0; b < nb; ++b)
    if (top[b] != SIZE_MAX && q[top[b]].u >= lo && q[top[b]].u <= hi) {
      bu[m] = q[top[b]].u;
      bw[m] = q[top[b]].w;
      ++m;
    }
  double a = NAN, slope = NAN, r2 = NAN;
  if (m >= 3) fit_line(bu, bw, m, &a, &slope, &r2);
  out->angle_fit_deg = atan(slope) * DEG;
  out->fit_r2 = r2;
  /* the flowing layer: on the normal to the surface through the axis, the depth (from the
   * surface particles' tops) at which the mean velocity along the surface changes from downhill
   * to uphill (the bed turning with the drum) */
  out->layer_m = NAN;
  if (isfinite(slope) && f->velocity) {
    double c = 1.0 / sqrt(1.0 + slope * slope), sn = slope * c; /* t = (c, sn) */
    double bin = 0.5 * dm, depth_max = s->radius + a * c;       /* to the drum's wall below the axis */
    size_t nbin = depth_max > 0.0 ? (size_t)(depth_max / bin) + 1 : 0;
    double *sum = calloc(nbin + 1, sizeof *sum);
    size_t *cnt = calloc(nbin + 1, sizeof *cnt);
    if (!sum || !cnt) {
      free(q), free(bu), free(bw), free(top), free(sum), free(cnt);
      return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    }
    for (size_t i = 0; i < n; ++i) {
      double along = q[i].u * c + q[i].w * sn;          /* from the axis's foot, along the surface */
      double depth = (a + slope * q[i].u - q[i].w) * c; /* below the surface line */
      if (fabs(along) > 1.5 * dm || depth < -rmean) continue;
      size_t k = depth < 0.0 ? 0 : (size_t)(depth / bin);
      if (k >= nbin) continue;
      sum[k] += q[i].vu * c + q[i].vw * sn;
      cnt[k]++;
    }
    /* from the top: the first bin with particles that moves downhill, then the first that does
     * not; linear between their centres */
    double prev_d = NAN, prev_v = NAN;
    bool flowing = false;
    for (size_t k = 0; k < nbin; ++k) {
      if (!cnt[k]) continue;
      double v = sum[k] / (double)cnt[k], dk = (k + 0.5) * bin;
      if (v < 0.0) flowing = true;
      else if (flowing) {
        double z = prev_d + (dk - prev_d) * (0.0 - prev_v) / (v - prev_v);
        out->layer_m = z + rmean;
        break;
      }
      prev_d = dk;
      prev_v = v;
    }
    free(sum);
    free(cnt);
  }
  /* the wall layer: centres within a tenth of a radius of touching the drum, two diameters
   * below the surface */
  double vt = 0.0, vd = 0.0;
  size_t nw = 0;
  for (size_t i = 0; f->velocity && i < n; ++i) {
    double rho = hypot(q[i].u, q[i].w);
    if (rho < s->radius - 1.1 * q[i].r || rho <= 0.0) continue;
    if (isfinite(slope) && (a + slope * q[i].u - q[i].w) < 2.0 * dm) continue;
    /* the drum's turning direction at the centre: the bottom (w < 0) moves towards +e_h */
    double tu = -q[i].w / rho, tw = q[i].u / rho;
    vt += q[i].vu * tu + q[i].vw * tw;
    vd += fabs(s->omega) * rho;
    ++nw;
  }
  out->wall_layer = nw;
  out->corotation = nw && vd > 0.0 ? vt / vd : NAN;
  out->slip_m_s = nw ? (vd - vt) / (double)nw : NAN;
  free(q);
  free(bu);
  free(bw);
  free(top);
  return ADEM_OK;
}

/* The cross-section's directions of a drum (axis a, gravity g, rotation omega about a). */
static bool orient(drum_setup *s, adem_vec3 g) {
  adem_vec3 up = v3_axpy(v3_neg(g), v3_dot(g, s->axis), s->axis); /* -g across the axis */
  s->g = v3_norm(up);
  if (!(s->g > 0.0)) return false;
  s->up = v3_scale(up, 1.0 / s->g);
  s->h = v3_cross(s->axis, s->up); /* the bottom moves along -omega (a x up) */
  if (s->omega > 0.0) s->h = v3_neg(s->h);
  return true;
}

adem_status adem_drum_measure(const adem_drum_geometry *geo, const adem_vtu_frame *f,
                              const double *mass, adem_drum_frame *out, adem_error *err) {
  drum_setup s;
  memset(&s, 0, sizeof s);
  s.point = geo->point;
  s.axis = v3_scale(geo->axis, 1.0 / v3_norm(geo->axis));
  s.radius = geo->radius;
  s.omega = geo->omega;
  if (!orient(&s, geo->gravity))
    return adem_error_set(err, ADEM_ERR_INPUT, "gravity is along the drum's axis (or zero): no free surface");
  double M;
  return measure_frame(&s, f, mass, out, &M, err);
}

/* Mean of the CSV column `name` over rows with t0 <= time <= t1; *rows: how many. */
static adem_status csv_mean(const char *path, const char *name, double t0, double t1, double *mean,
                            size_t *rows, adem_error *err) {
  *mean = NAN;
  *rows = 0;
  FILE *fp = fopen(path, "r");
  if (!fp) return ADEM_OK; /* no CSV: no torque */
  size_t cap = 1 << 16;
  char *line = malloc(cap);
  if (!line) {
    fclose(fp);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  int col = -1;
  double sum = 0.0;
  size_t len = 0;
  int c;
  bool header = true;
  for (;;) {
    c = fgetc(fp);
    if (c != EOF && c != '\n') {
      if (len + 1 >= cap) {
        char *nl = realloc(line, cap *= 2);
        if (!nl) break;
        line = nl;
      }
      line[len++] = (char)c;
      continue;
    }
    line[len] = '\0';
    if (len > 0) {
      int k = 0;
      char *save = NULL;
      double t = NAN, x = NAN;
      for (char *tok = strtok_r(line, ",", &save); tok; tok = strtok_r(NULL, ",", &save), ++k) {
        if (header && !strcmp(tok, name)) col = k;
        if (!header && k == 0) t = strtod(tok, NULL);
        if (!header && k == col) x = strtod(tok, NULL);
      }
      if (!header && col >= 0 && t >= t0 && t <= t1 && isfinite(x)) {
        sum += x;
        ++*rows;
      }
      header = false;
    }
    len = 0;
    if (c == EOF || (col < 0 && !header)) break;
  }
  free(line);
  fclose(fp);
  if (*rows) *mean = sum / (double)*rows;
  return ADEM_OK;
}

static adem_status write_outputs(const char *outdir, const drum_setup *s, adem_drum_report *rep,
                                 adem_error *err) {
  char *csv = adem_file_join(outdir, "drum.csv"), *png = adem_file_join(outdir, "drum.png");
  adem_status st = !csv || !png ? adem_error_set(err, ADEM_ERR_NOMEM, "out of memory") : ADEM_OK;
  adem_afile af;
  if (!st) st = adem_file_open(&af, csv, err);
  if (!st) {
    fprintf(af.f, "time_s,angle_fit_deg,fit_r2,angle_cm_deg,flowing_layer_m,wall_corotation,"
                  "wall_slip_m_s,wall_layer_particles,gravity_moment_Nm\n");
    for (size_t k = 0; k < rep->nframes; ++k) {
      const adem_drum_frame *f = &rep->frames[k];
      fprintf(af.f, "%.9g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%zu,%.9g\n", f->time, f->angle_fit_deg,
              f->fit_r2, f->angle_cm_deg, f->layer_m, f->corotation, f->slip_m_s, f->wall_layer,
              f->moment_Nm);
    }
    st = adem_file_commit(&af, err);
  }
  if (!st) {
    char q[4096], body[8192];
    snprintf(body, sizeof body,
             "set datafile separator ','\nset key autotitle columnhead\nset grid\n"
             "set multiplot layout 2,1 title 'drum %s: R = %.4g m, omega = %.4g rad/s, Fr = %.3g; "
             "%s'\n"
             "set ylabel 'angle (deg)'\nunset xlabel\n"
             "set title 'dynamic angle: surface fit %.1f +- %.1f deg, centre of mass %.1f +- %.1f "
             "deg'\n"
             "f = %s\n"
             "plot f using 1:2 with linespoints pt 7 ps 0.5 title 'surface fit', "
             "f using 1:4 with linespoints pt 6 ps 0.5 title 'centre of mass'\n"
             "set xlabel 'time (s)'\nset ylabel 'ratio, mm'\n"
             "set title 'wall layer co-rotation %.2f, flowing layer %.2f mm'\n"
             "plot f using 1:6 with linespoints pt 7 ps 0.5 title 'wall layer co-rotation', "
             "f using 1:($5*1000) with linespoints pt 6 ps 0.5 title 'flowing layer (mm)'\n"
             "unset multiplot\n",
             s->name, s->radius, s->omega, rep->froude, rep->regime, rep->angle_fit_deg,
             rep->angle_fit_sd, rep->angle_cm_deg, rep->angle_cm_sd, adem_plot_quote(csv, q, sizeof q),
             rep->corotation, rep->layer_m * 1000.0);
    st = adem_plot_png(png, 900, 800, body, err);
  }
  if (!st) {
    snprintf(rep->csv, sizeof rep->csv, "%s", csv);
    snprintf(rep->png, sizeof rep->png, "%s", png);
  }
  free(csv);
  free(png);
  return st;
}

/* Mean and standard deviation of the finite values of x (stride bytes apart). */
static void mean_sd(const adem_drum_frame *f, size_t n, size_t off, double *mean, double *sd) {
  double s = 0, ss = 0;
  size_t k = 0;
  for (size_t i = 0; i < n; ++i) {
    double x;
    memcpy(&x, (const char *)&f[i] + off, sizeof x);
    if (!isfinite(x)) continue;
    s += x;
    ss += x * x;
    ++k;
  }
  *mean = k ? s / (double)k : NAN;
  if (sd) *sd = k > 1 ? sqrt(fmax(0.0, (ss - s * s / (double)k) / (double)(k - 1))) : NAN;
}

adem_status adem_drum_analyze(const char *outdir, const adem_drum_options *opt,
                              adem_drum_report *rep, adem_error *err) {
  memset(rep, 0, sizeof *rep);
  drum_setup s;
  adem_status st = load_setup(outdir, opt, &s, err);
  char **names = NULL;
  size_t nn = 0;
  if (!st) st = list_frames(outdir, &names, &nn, err);
  if (!st) {
    rep->frames = calloc(nn, sizeof *rep->frames);
    if (!rep->frames) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  /* the frames from `from`, or the last two thirds (the first third: filling, spin-up) */
  double t_last = NAN;
  if (!st) {
    adem_vtu_frame f;
    st = adem_vtu_read_file(names[nn - 1], &f, err);
    if (!st) t_last = f.time;
    adem_vtu_frame_free(&f);
  }
  double from = isfinite(opt->from) ? opt->from : t_last / 3.0;
  for (size_t k = 0; k < nn && !st; ++k) {
    adem_vtu_frame f;
    if ((st = adem_vtu_read_file(names[k], &f, err))) break;
    if (!f.velocity) st = adem_error_set(err, ADEM_ERR_INPUT, "%s has no particle velocities", names[k]);
    if (!st && f.time >= from && f.n > 0) {
      double M = 0.0;
      st = measure_frame(&s, &f, NULL, &rep->frames[rep->nframes], &M, err);
      if (!st) {
        rep->mass = M;
        rep->particles = f.n;
        rep->nframes++;
      }
    }
    adem_vtu_frame_free(&f);
  }
  if (!st && rep->nframes < 2)
    st = adem_error_set(err, ADEM_ERR_INPUT, "%s: fewer than 2 frames at or after t = %g s", outdir, from);
  if (!st) {
    const adem_drum_frame *f = rep->frames;
    size_t n = rep->nframes;
    rep->radius = s.radius;
    rep->omega = s.omega;
    rep->froude = s.omega * s.omega * s.radius / s.g;
    mean_sd(f, n, offsetof(adem_drum_frame, angle_fit_deg), &rep->angle_fit_deg, &rep->angle_fit_sd);
    mean_sd(f, n, offsetof(adem_drum_frame, angle_cm_deg), &rep->angle_cm_deg, &rep->angle_cm_sd);
    mean_sd(f, n, offsetof(adem_drum_frame, layer_m), &rep->layer_m, NULL);
    mean_sd(f, n, offsetof(adem_drum_frame, corotation), &rep->corotation, NULL);
    mean_sd(f, n, offsetof(adem_drum_frame, slip_m_s), &rep->slip_m_s, NULL);
    mean_sd(f, n, offsetof(adem_drum_frame, moment_Nm), &rep->moment_Nm, NULL);
    /* the regime from the centre of mass's angle: a sawtooth (slow rises, sudden drops) has
     * strongly negative skewed changes and repeated drops */
    double lo = INFINITY, hi = -INFINITY, s1 = 0, s2 = 0, s3 = 0;
    for (size_t k = 0; k < n; ++k) {
      lo = fmin(lo, f[k].angle_cm_deg);
      hi = fmax(hi, f[k].angle_cm_deg);
    }
    for (size_t k = 0; k + 1 < n; ++k) s1 += f[k + 1].angle_cm_deg - f[k].angle_cm_deg;
    double md = s1 / (double)(n - 1);
    for (size_t k = 0; k + 1 < n; ++k) {
      double d = f[k + 1].angle_cm_deg - f[k].angle_cm_deg - md;
      s2 += d * d;
      s3 += d * d * d;
      if (f[k + 1].angle_cm_deg - f[k].angle_cm_deg < -1.0) rep->drops++;
    }
    s2 /= (double)(n - 1);
    rep->excursion_deg = hi - lo;
    rep->skewness = s2 > 0.0 ? s3 / (double)(n - 1) / pow(s2, 1.5) : 0.0;
    /* a bed that slides back along the wall (the wall layer turning at less than half the
     * drum's rate in a tenth of the frames) surges: neither rolling nor slumping */
    size_t slow = 0;
    for (size_t k = 0; k < n; ++k) slow += f[k].corotation < 0.5;
    rep->slipping_frames = slow;
    snprintf(rep->regime, sizeof rep->regime, "%s",
             10 * slow >= n ? "slipping" : rep->drops >= 2 && rep->skewness < -1.0 ? "slumping"
                                                                                   : "rolling");
    /* the drive torque over the frames' times: the torque of the particles on the drum */
    char col[2 * ADEM_NAME_MAX];
    snprintf(col, sizeof col, "%s_t_axis_Nm", s.name);
    char *ts = adem_file_join(outdir, "timeseries.csv");
    if (!ts) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    if (!st) st = csv_mean(ts, col, f[0].time, f[n - 1].time, &rep->torque_Nm, &rep->torque_rows, err);
    free(ts);
    /* signs: both as the moment about the rotation (positive for a bed lifted by the drum) */
    double sgn = s.omega < 0.0 ? -1.0 : 1.0;
    rep->torque_Nm *= -sgn;
    if (!st) st = write_outputs(outdir, &s, rep, err);
  }
  for (size_t k = 0; k < nn; ++k) free(names[k]);
  free(names);
  free(s.mass);
  if (st) adem_drum_report_free(rep);
  return st;
}
