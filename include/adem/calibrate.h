/* adem calibrate: one case value varied over a range until a measured target is met.
 *
 * The case runs once per value (each run in its own folder, OUT/runs/run-NNN, as `adem run
 * CASE --set ... --set KEY=VALUE` would), the target is measured on each run's output, and the
 * search brackets the target and narrows the bracket (safeguarded false position, and with
 * N > 1 jobs N - 1 more values cutting the bracket evenly) until a run is within the target's tolerance, the bracket
 * is narrower than xtol, or max_runs runs have been made. It writes OUT/runs.csv,
 * OUT/response.png (measured against value, the target band drawn), OUT/best.yaml (the case with
 * the best value written in) and OUT/summary.md. A stopped calibration resumes: the sequence of
 * values is a function of the measured responses, so a run already measured is read back and an
 * interrupted run continues from its checkpoint.
 *
 * Targets (adem_calib_target_parse), "KIND:WHAT=VALUE+-TOL" (also "±"):
 *   repose:MEASURE   the pile's angle in the last frame, deg; MEASURE is lab (the primary,
 *                    also "primary"), surface, slices, ringtop or footprint (include/adem/pile.h)
 *   density:REGION   bulk density of an output.regions region, kg/m^3: the mean over the
 *                    window of its particles' mass over its volume
 *   rate:REGION      discharge rate, particles/s: |slope| of the least-squares line of the
 *                    region's particle count against time over the window
 *   load:WALL[.x|.y|.z]  a wall's steady load, N: the mean over the window of the wall's force
 *                    (a plane's or a mesh group's CSV columns); without a component, the
 *                    magnitude of the mean force
 * The window is [window_lo, window_hi] s of the run's CSV; by default its last quarter. */
#ifndef ADEM_CALIBRATE_H
#define ADEM_CALIBRATE_H

#include <stdbool.h>
#include <stddef.h>

#include "adem/base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum adem_calib_kind {
  ADEM_CALIB_REPOSE = 0,
  ADEM_CALIB_DENSITY = 1,
  ADEM_CALIB_RATE = 2,
  ADEM_CALIB_LOAD = 3
} adem_calib_kind;

typedef struct adem_calib_target {
  adem_calib_kind kind;
  char what[128]; /* the measure (repose), region (density, rate) or wall (load) */
  int component;  /* load: 0 x, 1 y, 2 z, 3 the magnitude */
  double value, tol;
  char text[320]; /* as given */
} adem_calib_target;

/* "KIND:WHAT=VALUE+-TOL"; ADEM_ERR_INPUT with the accepted forms on anything else. */
adem_status adem_calib_target_parse(const char *spec, adem_calib_target *t, adem_error *err);

typedef struct adem_calib_vary {
  char key[256]; /* a case key path as adem run --set takes it */
  double lo, hi;
} adem_calib_vary;

/* "key.path=LO:HI" with LO < HI. */
adem_status adem_calib_vary_parse(const char *spec, adem_calib_vary *v, adem_error *err);

/* One run to make: in dir, the case with sets (the fixed ones and KEY=VALUE), or, with resume,
 * continued from dir/checkpoint. */
typedef struct adem_calib_job {
  const char *dir;
  const char *const *sets;
  int nsets;
  bool resume;
} adem_calib_job;

/* Runs jobs[0..n) (at most `jobs` at a time, in any order) and sets status[k] (ADEM_OK when
 * run k finished) and wall_s[k]; err holds the first failure's message. The library's own
 * runner (runner NULL) runs them one after the other in this process; the command runs each as
 * a child `adem run`. */
typedef void adem_calib_runner(void *user, const char *case_path, int n, const adem_calib_job *jobs,
                               adem_status *status, double *wall_s, adem_error *err);

typedef struct adem_calib_options {
  const char *case_path;
  const char *const *sets; /* fixed --set overrides */
  int nsets;
  adem_calib_vary vary;
  adem_calib_target target;
  const char *out_dir;
  int jobs;                    /* runs at a time (>= 1); with more than 1 each narrowing step
                                  runs the false-position value and jobs - 1 values cutting the
                                  bracket evenly */
  bool resume;                 /* false: out_dir must hold no runs; true: go on with the runs there */
  int points;                  /* values of the first scan, evenly over [lo, hi] (>= 2; default 3) */
  int max_runs;                /* at most this many runs in all (default 12) */
  double xtol;                 /* stop when the bracket is narrower (<= 0: (hi - lo) / 1000) */
  double window_lo, window_hi; /* measurement window, s (window_hi <= window_lo: last quarter) */
  double zmax;                 /* repose: centres above floor + zmax are not the pile (<= 0: all) */
  adem_calib_runner *runner;
  void *runner_user;
} adem_calib_options;

adem_calib_options adem_calib_default_options(void);

typedef struct adem_calib_run {
  double x, y; /* value and measured response (NaN: not measured) */
  double wall_s;
  char dir[4200];
} adem_calib_run;

/* A noisy response (a pile's angle changes by degrees between neighbouring values, as a
 * different seed changes it) cannot be read off one run: the least-squares line through the runs
 * of a window [lo, hi] of the value, where it meets the target, and how well the runs place it. */
typedef struct adem_calib_fit {
  int n;            /* runs in the window (0: no fit) */
  double lo, hi;    /* the window of values */
  double slope;     /* response per unit of value */
  double intercept; /* response at value 0 */
  double x;         /* where the line meets the target (NaN: slope 0) */
  double noise;     /* sd of the responses about the line, n - 2 degrees of freedom (NaN: n < 3) */
  double x_scatter; /* noise / |slope|: one run's scatter expressed as a value */
  double x_se;      /* standard error of x: x_scatter sqrt(1/n + (x - mean)^2 / Sxx) */
} adem_calib_fit;

/* The fit of the n points (x[k], y[k]) whose x lies in [lo, hi], against target. */
adem_calib_fit adem_calib_fit_line(const double *x, const double *y, size_t n, double lo, double hi,
                                   double target);

typedef struct adem_calib_result {
  bool found;                  /* a run's response is within the target's tolerance */
  bool bracketed;              /* two runs' responses lie on either side of the target */
  double x_best, y_best;       /* the run whose response is nearest the target */
  double x_lo, x_hi;           /* the final bracket (NaN when not bracketed) */
  double x_interp;             /* the value where the line through the bracket's ends meets the
                                  target (NaN when not bracketed) */
  double x_band_lo, x_band_hi; /* where that line is within the tolerance */
  adem_calib_fit fit;          /* the least-squares line through the runs of the first scan's
                                  bracket (adem_calib_fit_line) */
  size_t nruns;
  adem_calib_run *runs; /* in the order they were asked for */
} adem_calib_result;

/* Calibrates. Before any run the case is loaded once with the first value, so that a bad key
 * or value is ADEM_ERR_INPUT naming it. ADEM_OK also when the target is not met (found = 0):
 * the summary says why (not bracketed over the range, or the run budget spent). */
adem_status adem_calibrate(const adem_calib_options *o, adem_calib_result *res, adem_error *err);
void adem_calib_result_free(adem_calib_result *res);

/* The target measured on one run's output folder (used by adem_calibrate; exposed for tests):
 * zmax for repose, the window for the others; case_path and sets find a region's volume. */
adem_status adem_calib_measure(const char *run_dir, const adem_calib_target *t,
                               const adem_calib_options *o, double region_volume, double *value,
                               adem_error *err);

#ifdef __cplusplus
}
#endif

#endif
