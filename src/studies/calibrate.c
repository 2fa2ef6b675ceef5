/* adem calibrate (include/adem/calibrate.h): vary one case value, run, measure a target, bracket
 * and narrow. Public API only: runs are adem_run (or the command's child processes), measures
 * are adem_repose_analyze and the run's timeseries.csv. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "adem/case.h"
#include "adem/files.h"
#include "adem/internal/plot.h"
#include "adem/pile.h"
#include "adem/run.h"
#include "adem/calibrate.h"

adem_calib_options adem_calib_default_options(void) {
  adem_calib_options o;
  memset(&o, 0, sizeof o);
  o.jobs = 1;
  o.points = 3;
  o.max_runs = 12;
  return o;
}

void adem_calib_result_free(adem_calib_result *res) {
  if (!res) return;
  free(res->runs);
  memset(res, 0, sizeof *res);
}

/* ---------------------------------------------------------------- parsing */

static const char *const repose_measures[] = {"lab", "primary", "surface", "slices", "ringtop",
                                              "footprint"};

adem_status adem_calib_target_parse(const char *spec, adem_calib_target *t, adem_error *err) {
  memset(t, 0, sizeof *t);
  static const char forms[] =
      "expected KIND:WHAT=VALUE+-TOL with KIND:WHAT one of repose:lab (or repose:primary), "
      "repose:surface, repose:slices, repose:ringtop, repose:footprint, density:REGION, "
      "rate:REGION, load:WALL, load:WALL.x, load:WALL.y, load:WALL.z (e.g. repose:lab=40+-1, "
      "load:floor.z=2864+-10)";
  if (!spec || strlen(spec) >= sizeof t->text)
    return adem_error_set(err, ADEM_ERR_INPUT, "--target: %s", forms);
  snprintf(t->text, sizeof t->text, "%s", spec);
  char buf[320];
  snprintf(buf, sizeof buf, "%s", spec);
  char *colon = strchr(buf, ':'), *eq = strchr(buf, '=');
  if (!colon || !eq || eq < colon)
    return adem_error_set(err, ADEM_ERR_INPUT, "--target %s: %s", spec, forms);
  *colon = '\0';
  *eq = '\0';
  const char *kind = buf, *what = colon + 1, *num = eq + 1;
  if (!strcmp(kind, "repose")) t->kind = ADEM_CALIB_REPOSE;
  else if (!strcmp(kind, "density")) t->kind = ADEM_CALIB_DENSITY;
  else if (!strcmp(kind, "rate")) t->kind = ADEM_CALIB_RATE;
  else if (!strcmp(kind, "load")) t->kind = ADEM_CALIB_LOAD;
  else
    return adem_error_set(err, ADEM_ERR_INPUT, "--target %s: unknown kind '%s'; %s", spec, kind,
                          forms);
  if (!*what || strlen(what) >= sizeof t->what)
    return adem_error_set(err, ADEM_ERR_INPUT, "--target %s: no measure, region or wall named; %s",
                          spec, forms);
  snprintf(t->what, sizeof t->what, "%s", what);
  t->component = 3;
  if (t->kind == ADEM_CALIB_REPOSE) {
    size_t k = 0, nm = sizeof repose_measures / sizeof repose_measures[0];
    while (k < nm && strcmp(what, repose_measures[k])) ++k;
    if (k == nm)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "--target %s: unknown repose measure '%s'; there are lab (the "
                            "primary), surface, slices, ringtop, footprint",
                            spec, what);
  } else if (t->kind == ADEM_CALIB_LOAD) {
    size_t len = strlen(t->what);
    if (len > 2 && t->what[len - 2] == '.' && strchr("xyz", t->what[len - 1])) {
      t->component = t->what[len - 1] - 'x';
      t->what[len - 2] = '\0';
    }
  }
  /* VALUE+-TOL or VALUE±TOL */
  char *end;
  t->value = strtod(num, &end);
  const char *tol = NULL;
  if (end != num && !strncmp(end, "+-", 2)) tol = end + 2;
  else if (end != num && !strncmp(end, "\xc2\xb1", 2)) tol = end + 2;
  if (!tol)
    return adem_error_set(err, ADEM_ERR_INPUT, "--target %s: '%s' is not VALUE+-TOL; %s", spec,
                          num, forms);
  t->tol = strtod(tol, &end);
  if (end == tol || *end || !isfinite(t->value) || !isfinite(t->tol) || !(t->tol > 0.0))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "--target %s: '%s' is not VALUE+-TOL with finite numbers and TOL > 0",
                          spec, num);
  return ADEM_OK;
}

adem_status adem_calib_vary_parse(const char *spec, adem_calib_vary *v, adem_error *err) {
  memset(v, 0, sizeof *v);
  const char *eq = spec ? strchr(spec, '=') : NULL;
  if (!eq || eq == spec || (size_t)(eq - spec) >= sizeof v->key)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "--vary %s: expected key.path=LO:HI, e.g. "
                          "materials.ballast.rolling_friction=0.1:0.4",
                          spec ? spec : "");
  memcpy(v->key, spec, (size_t)(eq - spec));
  v->key[eq - spec] = '\0';
  char *end;
  v->lo = strtod(eq + 1, &end);
  if (end == eq + 1 || *end != ':')
    return adem_error_set(err, ADEM_ERR_INPUT, "--vary %s: expected key.path=LO:HI", spec);
  const char *h = end + 1;
  v->hi = strtod(h, &end);
  if (end == h || *end || !isfinite(v->lo) || !isfinite(v->hi) || !(v->lo < v->hi))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "--vary %s: LO:HI must be two finite numbers with LO < HI", spec);
  return ADEM_OK;
}

/* ---------------------------------------------------------------- measuring */

/* The columns of timeseries.csv named col[0..nc) (NULL: absent), as arrays over its rows. */
typedef struct series {
  size_t n;
  double *t;
  double *v[3];
} series;

static void series_free(series *s) {
  free(s->t);
  for (int k = 0; k < 3; ++k) free(s->v[k]);
  memset(s, 0, sizeof *s);
}

static adem_status read_series(const char *dir, const char *const *col, int nc, series *s,
                               adem_error *err) {
  memset(s, 0, sizeof *s);
  char *path = adem_file_join(dir, "timeseries.csv");
  char *text = NULL;
  size_t len = 0;
  adem_status st = path ? adem_file_read_all(path, &text, &len, err)
                        : adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  if (st) {
    free(path);
    return st;
  }
  char *nl = strchr(text, '\n');
  if (!nl) {
    st = adem_error_set(err, ADEM_ERR_INPUT, "%s has no header", path);
    goto done;
  }
  int idx[3] = {-1, -1, -1};
  {
    *nl = '\0';
    int k = 0;
    for (char *f = text; f; ++k) {
      char *c = strchr(f, ',');
      if (c) *c = '\0';
      for (int j = 0; j < nc; ++j)
        if (!strcmp(f, col[j])) idx[j] = k;
      f = c ? c + 1 : NULL;
    }
    for (int j = 0; j < nc; ++j)
      if (idx[j] < 0) {
        st = adem_error_set(err, ADEM_ERR_INPUT,
                            "%s has no column %s: is the region or wall named so in the case "
                            "(output.regions, walls)?",
                            path, col[j]);
        goto done;
      }
  }
  size_t cap = 0;
  for (char *line = nl + 1; *line;) {
    char *e = strchr(line, '\n');
    if (!e) break; /* a row being written: not complete */
    *e = '\0';
    if (s->n == cap) {
      cap = cap ? 2 * cap : 1024;
      double *t = realloc(s->t, cap * sizeof *t);
      if (t) s->t = t;
      int ok = t != NULL;
      for (int j = 0; j < nc && ok; ++j) {
        double *v = realloc(s->v[j], cap * sizeof *v);
        if (v) s->v[j] = v;
        ok = v != NULL;
      }
      if (!ok) {
        st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
        goto done;
      }
    }
    int k = 0;
    for (char *f = line; f; ++k) {
      char *c = strchr(f, ',');
      double x = strtod(f, NULL);
      if (k == 0) s->t[s->n] = x;
      for (int j = 0; j < nc; ++j)
        if (k == idx[j]) s->v[j][s->n] = x;
      f = c ? c + 1 : NULL;
    }
    s->n++;
    line = e + 1;
  }
  if (s->n == 0) st = adem_error_set(err, ADEM_ERR_INPUT, "%s has no rows", path);
done:
  if (st) series_free(s);
  free(text);
  free(path);
  return st;
}

adem_status adem_calib_measure(const char *run_dir, const adem_calib_target *t,
                               const adem_calib_options *o, double region_volume, double *value,
                               adem_error *err) {
  *value = NAN;
  if (t->kind == ADEM_CALIB_REPOSE) {
    adem_pile_options po = adem_pile_default_options();
    if (o->zmax > 0.0) po.zmax = o->zmax;
    adem_repose_report rep;
    adem_status st = adem_repose_analyze(run_dir, &po, &rep, err);
    if (st) return st;
    const adem_pile_result *r = &rep.pile;
    const char *m = t->what;
    *value = !strcmp(m, "surface")     ? r->angle_surface_deg
             : !strcmp(m, "slices")    ? r->angle_slices_deg
             : !strcmp(m, "ringtop")   ? r->angle_ringtop_deg
             : !strcmp(m, "footprint") ? r->angle_footprint_deg
                                       : r->angle_lab_deg;
    adem_repose_report_free(&rep);
    return ADEM_OK;
  }
  char cols[3][300];
  const char *col[3];
  int nc = 1;
  if (t->kind == ADEM_CALIB_LOAD) {
    nc = 3;
    for (int k = 0; k < 3; ++k) {
      snprintf(cols[k], sizeof cols[k], "%s_f%c_N", t->what, 'x' + k);
      col[k] = cols[k];
    }
  } else {
    snprintf(cols[0], sizeof cols[0], "%s_%s", t->what,
             t->kind == ADEM_CALIB_DENSITY ? "mass_kg" : "count");
    col[0] = cols[0];
  }
  series s;
  adem_status st = read_series(run_dir, col, nc, &s, err);
  if (st) return st;
  double w0 = o->window_lo, w1 = o->window_hi;
  if (!(w1 > w0)) { /* the last quarter of the run */
    w1 = s.t[s.n - 1];
    w0 = s.t[0] + 0.75 * (w1 - s.t[0]);
  }
  double sum[3] = {0, 0, 0}, st_ = 0.0, stt = 0.0, sty = 0.0;
  size_t m = 0;
  for (size_t i = 0; i < s.n; ++i) {
    if (s.t[i] < w0 || s.t[i] > w1) continue;
    for (int k = 0; k < nc; ++k) sum[k] += s.v[k][i];
    st_ += s.t[i];
    stt += s.t[i] * s.t[i];
    sty += s.t[i] * s.v[0][i];
    ++m;
  }
  if (m < 2) {
    series_free(&s);
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: fewer than 2 CSV rows in the window [%g, %g] s", run_dir, w0, w1);
  }
  double mean[3];
  for (int k = 0; k < 3; ++k) mean[k] = sum[k] / (double)m;
  if (t->kind == ADEM_CALIB_LOAD) {
    *value = t->component < 3 ? mean[t->component]
                              : sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
  } else if (t->kind == ADEM_CALIB_DENSITY) {
    *value = mean[0] / region_volume;
  } else { /* least-squares slope of the count against time */
    double dm = (double)m, var = stt - st_ * st_ / dm;
    *value = var > 0.0 ? fabs((sty - st_ * sum[0] / dm) / var) : NAN;
  }
  series_free(&s);
  return ADEM_OK;
}

/* ---------------------------------------------------------------- running */

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void own_runner(void *user, const char *case_path, int n, const adem_calib_job *jobs,
                       adem_status *status, double *wall_s, adem_error *err) {
  (void)user;
  int failed = 0;
  for (int k = 0; k < n; ++k) {
    adem_error e;
    memset(&e, 0, sizeof e);
    double t0 = now_s();
    adem_case *c = NULL;
    char *ck = jobs[k].resume ? adem_file_join(jobs[k].dir, "checkpoint") : NULL;
    adem_status st = jobs[k].resume
                         ? (ck ? adem_checkpoint_read(ck, &c, &e)
                               : adem_error_set(&e, ADEM_ERR_NOMEM, "out of memory"))
                         : adem_case_load_file(case_path, jobs[k].sets, jobs[k].nsets, &c, &e);
    free(ck);
    if (!st) {
      adem_run_options ro = adem_default_run_options();
      ro.nthreads = 1;
      st = adem_run(c, &ro, &e);
    }
    adem_case_free(c);
    status[k] = st;
    wall_s[k] = now_s() - t0;
    if (st && !failed) {
      failed = 1;
      *err = e;
    }
  }
}

static int exists(const char *path) {
  struct stat s;
  return stat(path, &s) == 0;
}

/* A measured run: dir/calibrate.row holds "VALUE_TEXT measured wall_s". */
static int read_row(const char *dir, char *xtext, size_t xn, double *y, double *wall) {
  char *path = adem_file_join(dir, "calibrate.row");
  char *text = NULL;
  size_t len = 0;
  char xs[64];
  int ok = path && adem_file_read_all(path, &text, &len, NULL) == ADEM_OK &&
           sscanf(text, "%63s %lf %lf", xs, y, wall) == 3;
  if (ok) snprintf(xtext, xn, "%s", xs);
  free(path);
  free(text);
  return ok;
}

typedef struct calib {
  const adem_calib_options *o;
  adem_calib_result *res;
  size_t cap;
  char runs_dir[4096];
  double volume;
  adem_calib_runner *runner;
  void *ruser;
} calib;

/* Runs (or reads back, or resumes) the values xs[0..n) as the next runs. */
static adem_status evaluate(calib *cb, const double *xs, int n, adem_error *err) {
  adem_calib_result *res = cb->res;
  if (res->nruns + (size_t)n > cb->cap) {
    size_t cap = 2 * (res->nruns + (size_t)n) + 8;
    adem_calib_run *r = realloc(res->runs, cap * sizeof *r);
    if (!r) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    res->runs = r;
    cb->cap = cap;
  }
  const adem_calib_options *o = cb->o;
  int nsets = o->nsets + 2;
  const char **sets = malloc((size_t)n * (size_t)nsets * sizeof *sets);
  char(*own)[4400] = malloc((size_t)n * 2 * sizeof *own);
  adem_calib_job *jobs = malloc((size_t)n * sizeof *jobs);
  int *which = malloc((size_t)n * sizeof *which);
  adem_status *status = malloc((size_t)n * sizeof *status);
  double *wall = malloc((size_t)n * sizeof *wall);
  adem_status st = ADEM_OK;
  if (!sets || !own || !jobs || !which || !status || !wall) {
    st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    goto out;
  }
  int nj = 0;
  for (int k = 0; k < n && !st; ++k) {
    size_t i = res->nruns + (size_t)k;
    adem_calib_run *r = &res->runs[i];
    memset(r, 0, sizeof *r);
    r->x = xs[k];
    r->y = NAN;
    snprintf(r->dir, sizeof r->dir, "%s/run-%03zu", cb->runs_dir, i + 1);
    char xtext[64], got[64];
    snprintf(xtext, sizeof xtext, "%.17g", xs[k]);
    double y, w;
    if (read_row(r->dir, got, sizeof got, &y, &w)) {
      if (strcmp(got, xtext))
        st = adem_error_set(err, ADEM_ERR_INPUT,
                            "%s was run with %s = %s, and this calibration asks for %s there: the "
                            "folder holds another calibration (choose another --out)",
                            r->dir, o->vary.key, got, xtext);
      r->y = y;
      r->wall_s = w;
      adem_log(ADEM_LOG_INFO, "calibrate: run %zu (%s = %s) measured before: %.6g", i + 1,
               o->vary.key, xtext, y);
      continue;
    }
    if ((st = adem_file_mkdir_p(r->dir, err))) break;
    const char **js = sets + (size_t)k * (size_t)nsets;
    for (int j = 0; j < o->nsets; ++j) js[j] = o->sets[j];
    snprintf(own[2 * k], sizeof own[0], "%s=%s", o->vary.key, xtext);
    snprintf(own[2 * k + 1], sizeof own[0], "output.dir=%s", r->dir);
    js[o->nsets] = own[2 * k];
    js[o->nsets + 1] = own[2 * k + 1];
    char *ck = adem_file_join(r->dir, "checkpoint");
    int resume = ck && exists(ck);
    free(ck);
    /* a checkpoint of the same value (its folder says so) continues; the value is in the
     * folder's calibrate.value, written before the run starts */
    char *vpath = adem_file_join(r->dir, "calibrate.value");
    char *vtext = NULL;
    size_t vlen = 0;
    if (vpath && adem_file_read_all(vpath, &vtext, &vlen, NULL) == ADEM_OK) {
      if (strncmp(vtext, xtext, strlen(xtext)))
        st = adem_error_set(err, ADEM_ERR_INPUT,
                            "%s was started with %s = %s and this calibration asks for %s there: "
                            "the folder holds another calibration (choose another --out)",
                            r->dir, o->vary.key, vtext, xtext);
    } else {
      resume = 0;
      if (vpath) st = adem_file_write_all(vpath, xtext, strlen(xtext), err);
    }
    free(vpath);
    free(vtext);
    if (st) break;
    adem_log(ADEM_LOG_INFO, "calibrate: run %zu: %s = %s%s", i + 1, o->vary.key, xtext,
             resume ? " (continued from its checkpoint)" : "");
    jobs[nj] = (adem_calib_job){r->dir, js, nsets, resume};
    which[nj++] = k;
  }
  if (!st && nj > 0) {
    adem_error e;
    memset(&e, 0, sizeof e);
    cb->runner(cb->ruser, o->case_path, nj, jobs, status, wall, &e);
    for (int j = 0; j < nj && !st; ++j) {
      adem_calib_run *r = &res->runs[res->nruns + (size_t)which[j]];
      if (status[j]) {
        st = adem_error_set(err, status[j], "calibrate: the run in %s (%s = %.17g) failed: %s",
                            r->dir, o->vary.key, r->x, e.message);
        break;
      }
      r->wall_s = wall[j];
      st = adem_calib_measure(r->dir, &o->target, o, cb->volume, &r->y, err);
      if (st) break;
      char row[256];
      int len = snprintf(row, sizeof row, "%.17g %.17g %.6f\n", r->x, r->y, r->wall_s);
      char *path = adem_file_join(r->dir, "calibrate.row");
      st = path ? adem_file_write_all(path, row, (size_t)len, err)
                : adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      free(path);
      adem_log(ADEM_LOG_INFO, "calibrate: run %zu (%s = %.6g): %.6g in %.0f s",
               res->nruns + (size_t)which[j] + 1, o->vary.key, r->x, r->y, r->wall_s);
    }
  }
  if (!st) res->nruns += (size_t)n;
out:
  free(sets);
  free(own);
  free(jobs);
  free(which);
  free(status);
  free(wall);
  return st;
}

/* ---------------------------------------------------------------- the search */

typedef struct xy {
  double x, y;
} xy;

static int cmp_x(const void *a, const void *b) {
  const xy *p = a, *q = b;
  return (p->x > q->x) - (p->x < q->x);
}

/* Best run, bracket and the line's crossing, from the runs so far. */
static void assess(calib *cb) {
  adem_calib_result *res = cb->res;
  const adem_calib_target *t = &cb->o->target;
  size_t n = res->nruns;
  xy *p = malloc((n ? n : 1) * sizeof *p);
  res->found = res->bracketed = 0;
  res->x_lo = res->x_hi = res->x_interp = res->x_band_lo = res->x_band_hi = NAN;
  res->x_best = res->y_best = NAN;
  if (!p) return;
  size_t m = 0;
  double best = INFINITY;
  for (size_t i = 0; i < n; ++i) {
    if (!isfinite(res->runs[i].y)) continue;
    p[m++] = (xy){res->runs[i].x, res->runs[i].y};
    double d = fabs(res->runs[i].y - t->value);
    if (d < best) {
      best = d;
      res->x_best = res->runs[i].x;
      res->y_best = res->runs[i].y;
    }
  }
  res->found = best <= t->tol;
  qsort(p, m, sizeof *p, cmp_x);
  /* the narrowest bracket: adjacent values whose responses lie on either side */
  double width = INFINITY;
  for (size_t i = 0; i + 1 < m; ++i) {
    double a = p[i].y - t->value, b = p[i + 1].y - t->value;
    if (a * b <= 0.0 && p[i + 1].x - p[i].x < width && p[i].y != p[i + 1].y) {
      width = p[i + 1].x - p[i].x;
      res->bracketed = 1;
      res->x_lo = p[i].x;
      res->x_hi = p[i + 1].x;
      double k = (p[i + 1].y - p[i].y) / (p[i + 1].x - p[i].x);
      res->x_interp = p[i].x + (t->value - p[i].y) / k;
      double u = p[i].x + (t->value - t->tol - p[i].y) / k, v = p[i].x + (t->value + t->tol - p[i].y) / k;
      res->x_band_lo = u < v ? u : v;
      res->x_band_hi = u < v ? v : u;
    }
  }
  free(p);
}

adem_calib_fit adem_calib_fit_line(const double *x, const double *y, size_t n, double lo, double hi,
                                   double target) {
  adem_calib_fit f = {0, lo, hi, NAN, NAN, NAN, NAN, NAN, NAN};
  double sx = 0.0, sy = 0.0;
  for (size_t k = 0; k < n; ++k)
    if (x[k] >= lo && x[k] <= hi && isfinite(y[k])) sx += x[k], sy += y[k], ++f.n;
  if (f.n < 2) return f;
  double mx = sx / f.n, my = sy / f.n, sxx = 0.0, sxy = 0.0;
  for (size_t k = 0; k < n; ++k)
    if (x[k] >= lo && x[k] <= hi && isfinite(y[k]))
      sxx += (x[k] - mx) * (x[k] - mx), sxy += (x[k] - mx) * (y[k] - my);
  if (!(sxx > 0.0)) return f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  if (f.slope != 0.0) f.x = (target - f.intercept) / f.slope;
  if (f.n < 3) return f; /* a line through two points says nothing of the scatter */
  double ssr = 0.0;
  for (size_t k = 0; k < n; ++k)
    if (x[k] >= lo && x[k] <= hi && isfinite(y[k])) {
      double r = y[k] - (f.intercept + f.slope * x[k]);
      ssr += r * r;
    }
  f.noise = sqrt(ssr / (f.n - 2));
  f.x_scatter = f.noise / fabs(f.slope);
  f.x_se = f.x_scatter * sqrt(1.0 / f.n + (f.x - mx) * (f.x - mx) / sxx);
  return f;
}

/* The line through the runs of the first scan's bracket that holds the final bracket: every
 * narrowing run lies in it, so the fit uses them all, and no run of a far, curved part of the
 * range. */
static void fit_response(calib *cb) {
  adem_calib_result *res = cb->res;
  res->fit = adem_calib_fit_line(NULL, NULL, 0, NAN, NAN, NAN);
  if (!res->bracketed) return;
  size_t scan = (size_t)cb->o->points < res->nruns ? (size_t)cb->o->points : res->nruns;
  double lo = -INFINITY, hi = INFINITY;
  for (size_t k = 0; k < scan; ++k) {
    const adem_calib_run *r = &res->runs[k];
    if (!isfinite(r->y)) continue;
    if (r->x <= res->x_lo && r->x > lo) lo = r->x;
    if (r->x >= res->x_hi && r->x < hi) hi = r->x;
  }
  if (!isfinite(lo) || !isfinite(hi)) return;
  double *x = malloc((res->nruns + 1) * sizeof *x), *y = malloc((res->nruns + 1) * sizeof *y);
  if (x && y) {
    for (size_t k = 0; k < res->nruns; ++k) x[k] = res->runs[k].x, y[k] = res->runs[k].y;
    res->fit = adem_calib_fit_line(x, y, res->nruns, lo, hi, cb->o->target.value);
  }
  free(x);
  free(y);
}

/* The response of the bracket's ends, to place the next value. */
static double y_at(const adem_calib_result *res, double x) {
  for (size_t i = 0; i < res->nruns; ++i)
    if (res->runs[i].x == x) return res->runs[i].y;
  return NAN;
}

static adem_status write_outputs(calib *cb, const char *stop_reason, adem_error *err);

adem_status adem_calibrate(const adem_calib_options *o, adem_calib_result *res, adem_error *err) {
  memset(res, 0, sizeof *res);
  if (!o->case_path || !o->out_dir || o->jobs < 1 || o->points < 2 || o->max_runs < o->points)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "calibrate: a case, an output folder, jobs >= 1, points >= 2 and "
                          "max_runs >= points are needed (points %d, max_runs %d)",
                          o->points,
                          o->max_runs);
  calib cb;
  memset(&cb, 0, sizeof cb);
  cb.o = o;
  cb.res = res;
  cb.runner = o->runner ? o->runner : own_runner;
  cb.ruser = o->runner_user;
  snprintf(cb.runs_dir, sizeof cb.runs_dir, "%s/runs", o->out_dir);
  if (!o->resume && exists(cb.runs_dir))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s already holds runs of a calibration: go on with --resume, or choose "
                          "another --out",
                          o->out_dir);
  /* The case loads with the first value (a bad key or value is named now, before any run);
   * the region's volume for a density target comes from it. */
  {
    const char **sets = malloc((size_t)(o->nsets + 1) * sizeof *sets);
    char own[4400];
    if (!sets) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    for (int j = 0; j < o->nsets; ++j) sets[j] = o->sets[j];
    snprintf(own, sizeof own, "%s=%.17g", o->vary.key, o->vary.lo);
    sets[o->nsets] = own;
    adem_case *c = NULL;
    adem_status st = adem_case_load_file(o->case_path, sets, o->nsets + 1, &c, err);
    free(sets);
    if (st) {
      char msg[sizeof err->message];
      snprintf(msg, sizeof msg, "%s", err->message);
      return adem_error_set(err, st, "--vary %s=%.6g:%.6g: the case does not load with its first "
                                     "value: %s",
                            o->vary.key, o->vary.lo, o->vary.hi, msg);
    }
    if (o->target.kind == ADEM_CALIB_DENSITY)
      st = adem_case_region_volume(c, o->target.what, &cb.volume, err);
    adem_case_free(c);
    if (st) return st;
  }
  adem_status st = adem_file_mkdir_p(cb.runs_dir, err);
  if (st) return st;

  const double lo = o->vary.lo, hi = o->vary.hi;
  const double xtol = o->xtol > 0.0 ? o->xtol : (hi - lo) / 1000.0;
  double *xs = malloc((size_t)(o->points > o->jobs ? o->points : o->jobs) * sizeof *xs);
  if (!xs) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  for (int k = 0; k < o->points; ++k) xs[k] = lo + (hi - lo) * k / (o->points - 1);
  xs[o->points - 1] = hi;
  st = evaluate(&cb, xs, o->points, err);
  const char *why = NULL;
  while (!st) {
    assess(&cb);
    if (res->found) {
      why = "a run is within the target's tolerance";
      break;
    }
    if (!res->bracketed) {
      why = "the target is not bracketed: every response over the range lies on one side of it";
      break;
    }
    if (res->x_hi - res->x_lo <= xtol) {
      why = "the bracket is narrower than xtol and no run is within the tolerance (the response "
            "jumps there, or the tolerance is below its noise)";
      break;
    }
    int left = o->max_runs - (int)res->nruns;
    if (left <= 0) {
      why = "the run budget (--max-runs) is spent";
      break;
    }
    int m = o->jobs < left ? o->jobs : left;
    double a = res->x_lo, b = res->x_hi;
    /* false position, kept at least a tenth of the bracket from either end so that a curved
     * response cannot stall it on one side; with more jobs, the others cut the bracket evenly
     * (a bisection with two jobs), which a noisy response needs */
    double ya = y_at(res, a), yb = y_at(res, b);
    double x = a + (o->target.value - ya) * (b - a) / (yb - ya);
    double g = 0.1 * (b - a);
    if (!(x >= a + g)) x = a + g;
    if (!(x <= b - g)) x = b - g;
    xs[0] = x;
    for (int k = 1; k < m; ++k) xs[k] = a + (b - a) * k / m;
    st = evaluate(&cb, xs, m, err);
  }
  free(xs);
  if (st) return st;
  fit_response(&cb);
  return write_outputs(&cb, why, err);
}

/* ---------------------------------------------------------------- outputs */

static const char *unit_of(const adem_calib_target *t) {
  switch (t->kind) {
    case ADEM_CALIB_REPOSE: return "deg";
    case ADEM_CALIB_DENSITY: return "kg/m^3";
    case ADEM_CALIB_RATE: return "1/s";
    default: return "N";
  }
}

static adem_status write_outputs(calib *cb, const char *why, adem_error *err) {
  const adem_calib_options *o = cb->o;
  adem_calib_result *res = cb->res;
  const adem_calib_target *t = &o->target;
  char *csv = adem_file_join(o->out_dir, "runs.csv");
  char *png = adem_file_join(o->out_dir, "response.png");
  char *best = adem_file_join(o->out_dir, "best.yaml");
  char *md = adem_file_join(o->out_dir, "summary.md");
  adem_status st = csv && png && best && md ? ADEM_OK : adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  /* runs.csv */
  if (!st) {
    adem_afile af;
    st = adem_file_open(&af, csv, err);
    if (!st) {
      fprintf(af.f, "run,value,measured,target,tolerance,within,wall_s,dir\n");
      for (size_t i = 0; i < res->nruns; ++i) {
        const adem_calib_run *r = &res->runs[i];
        fprintf(af.f, "%zu,%.17g,%.17g,%.17g,%.17g,%d,%.3f,%s\n", i + 1, r->x, r->y, t->value,
                t->tol, fabs(r->y - t->value) <= t->tol, r->wall_s, r->dir);
      }
      st = adem_file_commit(&af, err);
    }
  }
  /* response.png: the runs, the target band, the best run */
  if (!st) {
    char q[4200], body[8192], label[200];
    static const char *const kinds[] = {"repose", "density", "rate", "load"};
    snprintf(label, sizeof label, "measured %s:%s%s%s", kinds[t->kind], t->what,
             t->kind == ADEM_CALIB_LOAD && t->component < 3 ? "." : "",
             t->kind == ADEM_CALIB_LOAD && t->component < 3 ? (const char *[]){"x", "y", "z"}[t->component] : "");
    double pad = 0.05 * (o->vary.hi - o->vary.lo);
    /* the response fit's line over its window, when there is one */
    const adem_calib_fit *f = &res->fit;
    char fit_clause[200] = "", fit_data[200] = "";
    if (f->n >= 2 && isfinite(f->x)) {
      snprintf(fit_clause, sizeof fit_clause,
               ", \\\n '-' using 1:2 with lines lw 2 lc rgb '#2ca02c' title 'least-squares line "
               "(%d runs): %.4g'",
               f->n, f->x);
      snprintf(fit_data, sizeof fit_data, "%.17g,%.17g\n%.17g,%.17g\ne\n", f->lo,
               f->intercept + f->slope * f->lo, f->hi, f->intercept + f->slope * f->hi);
    }
    snprintf(body, sizeof body,
             "set datafile separator ','\nset title \"adem calibrate: %s against %s\" noenhanced\n"
             "set xlabel '%s' noenhanced\nset ylabel '%s (%s)' noenhanced\nset grid\n"
             "set key top left\nset xrange [%.17g:%.17g]\n"
             "set object 1 rect from graph 0, first %.17g to graph 1, first %.17g fc rgb '#dddddd' "
             "fs solid 0.6 behind\n"
             "plot %s skip 1 using 2:3 with points pt 7 ps 1.3 lc rgb '#1f77b4' title 'runs', \\\n"
             " %.17g with lines lc rgb 'black' dt 2 title 'target %.6g +- %.6g (grey band)', \\\n"
             " '-' using 1:2 with points pt 6 ps 2.5 lw 2 lc rgb '#d62728' title 'best run'%s\n"
             "%.17g,%.17g\ne\n%s",
             t->text, o->vary.key, o->vary.key, label, unit_of(t), o->vary.lo - pad,
             o->vary.hi + pad, t->value - t->tol, t->value + t->tol,
             adem_plot_quote(csv, q, sizeof q), t->value, t->value, t->tol, fit_clause,
             res->x_best, res->y_best, fit_data);
    /* a machine without gnuplot still gets the CSV and the summary */
    adem_error pe;
    memset(&pe, 0, sizeof pe);
    if (adem_plot_png(png, 900, 600, body, &pe))
      adem_log(ADEM_LOG_WARN, "calibrate: response.png not drawn: %s", pe.message);
  }
  /* best.yaml: the case with the fixed sets and the best value written in */
  if (!st && isfinite(res->x_best)) {
    char *text = NULL, *yaml = NULL;
    size_t len = 0;
    st = adem_file_read_all(o->case_path, &text, &len, err);
    const char **sets = st ? NULL : malloc((size_t)(o->nsets + 1) * sizeof *sets);
    char own[4400];
    if (!st && !sets) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    if (!st) {
      for (int j = 0; j < o->nsets; ++j) sets[j] = o->sets[j];
      snprintf(own, sizeof own, "%s=%.17g", o->vary.key, res->x_best);
      sets[o->nsets] = own;
      st = adem_case_text_with_sets(text, o->case_path, sets, o->nsets + 1, &yaml, err);
    }
    if (!st) {
      size_t cap = strlen(yaml) + 2048;
      char *all = malloc(cap);
      if (!all) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      else {
        int n = snprintf(all, cap,
                         "# adem calibrate: %s with %s = %.17g (the run nearest the target %s: "
                         "measured %.6g%s).\n# Relative file paths are those of %s's folder: run "
                         "it from there or copy it beside that file.\n%s",
                         o->case_path, o->vary.key, res->x_best, t->text, res->y_best,
                         res->found ? ", within the tolerance" : ", NOT within the tolerance",
                         o->case_path, yaml);
        st = adem_file_write_all(best, all, (size_t)n, err);
        free(all);
      }
    }
    free(sets);
    free(text);
    free(yaml);
  }
  /* summary.md */
  if (!st) {
    adem_afile af;
    st = adem_file_open(&af, md, err);
    if (!st) {
      double total = 0.0;
      for (size_t i = 0; i < res->nruns; ++i) total += res->runs[i].wall_s;
      fprintf(af.f, "# adem calibrate\n\n- case: `%s`", o->case_path);
      for (int j = 0; j < o->nsets; ++j) fprintf(af.f, " `--set %s`", o->sets[j]);
      fprintf(af.f, "\n- varied: `%s` over [%.6g, %.6g]\n- target: `%s` (%s)\n", o->vary.key,
              o->vary.lo, o->vary.hi, t->text, unit_of(t));
      fprintf(af.f, "- runs: %zu (%d at a time), %.0f s of run time in all\n", res->nruns,
              o->jobs, total);
      fprintf(af.f, "- stopped because %s\n\n", why ? why : "?");
      if (res->found)
        fprintf(af.f, "**Found**: %s = %.10g gives %.6g %s (target %.6g ± %.6g).\n", o->vary.key,
                res->x_best, res->y_best, unit_of(t), t->value, t->tol);
      else
        fprintf(af.f, "**Not found** within the tolerance: the nearest run, %s = %.10g, gives "
                      "%.6g %s (target %.6g ± %.6g).\n",
                o->vary.key, res->x_best, res->y_best,
                unit_of(t), t->value, t->tol);
      if (res->bracketed)
        fprintf(af.f, "\nBracket: [%.10g, %.10g]; the line through its ends meets the target at "
                      "%.10g and is within the tolerance over [%.10g, %.10g].\n",
                res->x_lo,
                res->x_hi, res->x_interp, res->x_band_lo, res->x_band_hi);
      const adem_calib_fit *f = &res->fit;
      if (f->n >= 2 && isfinite(f->x)) {
        fprintf(af.f, "\nResponse fit: the least-squares line through the %d runs with %s in "
                      "[%.6g, %.6g] (the first scan's bracket) meets the target at **%.6g**",
                f->n, o->vary.key, f->lo, f->hi, f->x);
        if (f->n >= 3)
          fprintf(af.f, " ± %.3g (standard error); slope %.4g %s per unit, scatter of the runs "
                        "about the line %.3g %s, that is %.3g in %s for a single run%s.\n",
                  f->x_se, f->slope, unit_of(t), f->noise, unit_of(t), f->x_scatter, o->vary.key,
                  f->noise > t->tol ? ": the scatter exceeds the tolerance, so the run found "
                                      "within it owes that partly to chance, and the fit is the "
                                      "better estimate (more runs in the window, or more seeds, "
                                      "narrow it)"
                                    : "");
        else
          fprintf(af.f, " (two runs: no estimate of the scatter; slope %.4g %s per unit).\n",
                  f->slope, unit_of(t));
      }
      fprintf(af.f, "\n| run | %s | measured (%s) | within | wall s |\n|---|---|---|---|---|\n",
              o->vary.key, unit_of(t));
      for (size_t i = 0; i < res->nruns; ++i) {
        const adem_calib_run *r = &res->runs[i];
        fprintf(af.f, "| %zu | %.10g | %.6g | %s | %.1f |\n", i + 1, r->x, r->y,
                fabs(r->y - t->value) <= t->tol ? "yes" : "no", r->wall_s);
      }
      fprintf(af.f, "\nFiles: runs.csv, response.png, best.yaml, runs/run-NNN/ (each run's "
                    "output).\n");
      st = adem_file_commit(&af, err);
    }
  }
  free(csv);
  free(png);
  free(best);
  free(md);
  return st;
}
