/* adem calibrate: vary one case value until a measured target is met (include/adem/calibrate.h).
 * The command runs each value as a child `adem run` (this same program), up to --jobs at a time,
 * its output in the run's folder and its messages in RUN/run.log. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "adem/calibrate.h"
#include "adem/files.h"
#include "cli.h"

extern char **environ;

const char *const calibrate_help =
    "Usage: adem calibrate CASE.yaml --vary KEY=LO:HI --target KIND:WHAT=VALUE+-TOL [options]\n"
    "\n"
    "Varies one value of the case over [LO, HI], runs the case for each value (each run in its\n"
    "own folder OUT/runs/run-NNN, as adem run would), measures the target on each run, brackets\n"
    "the target and narrows the bracket until a run is within the tolerance. Writes\n"
    "  OUT/runs.csv      every run: value, measured, within the tolerance, wall time, folder\n"
    "  OUT/response.png  measured against value, with the target band (gnuplot)\n"
    "  OUT/best.yaml     the case with the value of the run nearest the target written in\n"
    "  OUT/summary.md    the outcome: found or not and why, the bracket, every run, and the\n"
    "                    response fit: the least-squares line through the runs of the first\n"
    "                    scan's bracket, where it meets the target +- its standard error (a\n"
    "                    noisy response, such as a pile's angle, is better read off the fit\n"
    "                    than off the one run that happened to fall within the tolerance)\n"
    "\n"
    "Targets:\n"
    "  repose:lab=40+-1         angle of repose of the pile in the last frame, deg, by the\n"
    "                           laboratory measure (the primary; also repose:primary), or\n"
    "                           repose:surface, :slices, :ringtop, :footprint (adem analyze repose)\n"
    "  density:REGION=V+-T      bulk density of an output.regions region, kg/m^3 (its particles'\n"
    "                           mass over its volume, mean over the window)\n"
    "  rate:REGION=V+-T         discharge rate, particles/s: |slope| of the region's count\n"
    "  load:WALL.z=V+-T         a wall's steady load, N (mean over the window of its force;\n"
    "                           .x/.y/.z a component, none the magnitude); WALL a plane's name\n"
    "                           or a mesh group's\n"
    "\n"
    "Options:\n"
    "  --vary KEY=LO:HI   the case value to vary (a key path as --set takes it)\n"
    "  --target SPEC      what to meet (above)\n"
    "  --out DIR          output folder (default out/calibrate)\n"
    "  --set key=value    a fixed override of the case, as adem run --set; may be repeated\n"
    "  --jobs N           runs at a time (default 1); each step runs the false-position value\n"
    "                     (safeguarded) and N - 1 values cutting the bracket evenly\n"
    "  --threads N        threads of each run (default 1)\n"
    "  --resume           go on with the runs already in DIR: measured runs are read back,\n"
    "                     an interrupted run continues from its checkpoint\n"
    "  --points N         values of the first scan, evenly over [LO, HI] (default 3)\n"
    "  --max-runs N       at most N runs in all (default 12)\n"
    "  --xtol X           stop when the bracket is narrower than X (default (HI - LO) / 1000)\n"
    "  --window T0:T1     time window of the CSV for density, rate, load (default: the\n"
    "                     last quarter of the run)\n"
    "  --zmax Z           repose: centres above Z are not the pile (spheres in a hopper)\n"
    "\n"
    "Example:\n"
    "  adem calibrate cases/irazabal/repose.yaml --vary materials.ballast.rolling_friction=0.1:0.4 \\\n"
    "      --target repose:lab=40+-1 --zmax 0.65 --jobs 2 --out out/cal-eta\n"
    "\n"
    "Exit status: 0 the target was met; 3 it was not (not bracketed, or the budget spent: see\n"
    "summary.md) or a run failed; 2 bad options or case; 1 out of memory.\n";

typedef struct spawn_ctx {
  int jobs;
  int threads;
  const char *self;
} spawn_ctx;

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Each job as a child `adem run` (or `adem run --resume`), at most ctx->jobs at a time. */
static void spawn_runner(void *user, const char *case_path, int n, const adem_calib_job *jobs,
                         adem_status *status, double *wall_s, adem_error *err) {
  spawn_ctx *sc = user;
  pid_t *pid = calloc((size_t)n, sizeof *pid);
  double *t0 = calloc((size_t)n, sizeof *t0);
  if (!pid || !t0) {
    for (int k = 0; k < n; ++k) status[k] = ADEM_ERR_NOMEM;
    adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    free(pid);
    free(t0);
    return;
  }
  char threads[32];
  snprintf(threads, sizeof threads, "%d", sc->threads);
  int next = 0, running = 0, failed = 0;
  while (next < n || running > 0) {
    while (next < n && running < sc->jobs) {
      const adem_calib_job *j = &jobs[next];
      int argc = 0;
      const char **argv = malloc((size_t)(2 * j->nsets + 12) * sizeof *argv);
      if (!argv) {
        status[next++] = ADEM_ERR_NOMEM;
        continue;
      }
      argv[argc++] = "adem";
      argv[argc++] = "run";
      if (j->resume) {
        argv[argc++] = "--resume";
        argv[argc++] = j->dir;
      } else {
        argv[argc++] = case_path;
        for (int k = 0; k < j->nsets; ++k) {
          argv[argc++] = "--set";
          argv[argc++] = j->sets[k];
        }
        argv[argc++] = "--out";
        argv[argc++] = j->dir;
      }
      argv[argc++] = "--threads";
      argv[argc++] = threads;
      argv[argc++] = "--quiet";
      argv[argc] = NULL;
      char *log = adem_file_join(j->dir, "run.log");
      posix_spawn_file_actions_t fa;
      posix_spawn_file_actions_init(&fa);
      if (log) {
        posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log, O_WRONLY | O_CREAT | O_APPEND, 0644);
        posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
      }
      t0[next] = now_s();
      int rc = posix_spawn(&pid[next], sc->self, &fa, NULL, (char *const *)argv, environ);
      posix_spawn_file_actions_destroy(&fa);
      free(log);
      free(argv);
      if (rc) {
        status[next] = ADEM_ERR_RUNTIME;
        if (!failed++) adem_error_set(err, ADEM_ERR_RUNTIME, "cannot start %s: %s", sc->self, strerror(rc));
        pid[next] = 0;
      } else {
        ++running;
      }
      ++next;
    }
    if (running == 0) continue;
    int ws = 0;
    pid_t p = waitpid(-1, &ws, 0);
    if (p < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int k = 0; k < n; ++k)
      if (pid[k] == p) {
        pid[k] = 0;
        --running;
        wall_s[k] = now_s() - t0[k];
        int code = WIFEXITED(ws) ? WEXITSTATUS(ws) : 128 + (WIFSIGNALED(ws) ? WTERMSIG(ws) : 0);
        status[k] = code == 0 ? ADEM_OK : code == EXIT_INPUT ? ADEM_ERR_INPUT
                                                             : ADEM_ERR_RUNTIME;
        if (code && !failed++)
          adem_error_set(err, status[k], "adem run exited with %d (its messages: %s/run.log)", code,
                         jobs[k].dir);
      }
  }
  free(pid);
  free(t0);
}

static int range(const char *s, double *a, double *b) {
  char *end;
  *a = strtod(s, &end);
  if (end == s || *end != ':') return 0;
  const char *t = end + 1;
  *b = strtod(t, &end);
  return end != t && *end == '\0' && isfinite(*a) && isfinite(*b) && *a < *b;
}

static int integer(const char *s, int lo, int hi, int *x) {
  char *end;
  long v = strtol(s, &end, 10);
  if (end == s || *end || v < lo || v > hi) return 0;
  *x = (int)v;
  return 1;
}

int cmd_calibrate(int argc, char **argv) {
  if (argc < 1 || !strcmp(argv[0], "-h") || !strcmp(argv[0], "--help")) {
    fputs(calibrate_help, argc < 1 ? stderr : stdout);
    return argc < 1 ? EXIT_INPUT : EXIT_OK;
  }
  adem_calib_options o = adem_calib_default_options();
  o.case_path = argv[0];
  o.out_dir = "out/calibrate";
  const char **sets = calloc((size_t)argc, sizeof *sets);
  if (!sets) return fail(EXIT_INTERNAL, "out of memory");
  const char *vary = NULL, *target = NULL;
  spawn_ctx sc = {1, 1, "/proc/self/exe"};
  adem_error err;
  memset(&err, 0, sizeof err);
  int rc = EXIT_OK;
  for (int i = 1; i < argc && rc == EXIT_OK; ++i) {
    const char *a = argv[i];
    if (!strcmp(a, "--resume")) {
      o.resume = 1;
      continue;
    }
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (!v || strncmp(a, "--", 2)) {
      rc = fail(EXIT_INPUT, "unknown option or missing value '%s' for adem calibrate (see: adem "
                            "calibrate --help)",
                a);
      break;
    }
    ++i;
    int ok = 1;
    if (!strcmp(a, "--vary")) vary = v;
    else if (!strcmp(a, "--target")) target = v;
    else if (!strcmp(a, "--out")) o.out_dir = v;
    else if (!strcmp(a, "--set")) sets[o.nsets++] = v;
    else if (!strcmp(a, "--jobs")) ok = integer(v, 1, 256, &o.jobs);
    else if (!strcmp(a, "--threads")) ok = integer(v, 1, 1024, &sc.threads);
    else if (!strcmp(a, "--points")) ok = integer(v, 2, 1000, &o.points);
    else if (!strcmp(a, "--max-runs")) ok = integer(v, 2, 100000, &o.max_runs);
    else if (!strcmp(a, "--xtol")) ok = (o.xtol = strtod(v, NULL)) > 0.0;
    else if (!strcmp(a, "--zmax")) ok = (o.zmax = strtod(v, NULL)) > 0.0;
    else if (!strcmp(a, "--window")) ok = range(v, &o.window_lo, &o.window_hi);
    else {
      rc = fail(EXIT_INPUT, "unknown option '%s' for adem calibrate (see: adem calibrate --help)", a);
      break;
    }
    if (!ok) rc = fail(EXIT_INPUT, "%s: bad value '%s' (see: adem calibrate --help)", a, v);
  }
  if (rc == EXIT_OK && (!vary || !target))
    rc = fail(EXIT_INPUT, "adem calibrate needs --vary KEY=LO:HI and --target SPEC (see: adem "
                          "calibrate --help)");
  if (rc == EXIT_OK && adem_calib_vary_parse(vary, &o.vary, &err)) rc = fail(EXIT_INPUT, "%s", err.message);
  if (rc == EXIT_OK && adem_calib_target_parse(target, &o.target, &err))
    rc = fail(EXIT_INPUT, "%s", err.message);
  if (rc != EXIT_OK) {
    free(sets);
    return rc;
  }
  if (o.max_runs < o.points) o.max_runs = o.points;
  o.sets = sets;
  sc.jobs = o.jobs;
  o.runner = spawn_runner;
  o.runner_user = &sc;
  adem_calib_result res;
  adem_status st = adem_calibrate(&o, &res, &err);
  free(sets);
  if (st) return fail(exit_code(st), "%s", err.message);
  if (res.found)
    printf("found            %s = %.10g: %.6g (target %.6g +- %.6g), %zu runs\n", o.vary.key,
           res.x_best, res.y_best, o.target.value, o.target.tol, res.nruns);
  else
    printf("not found        nearest run %s = %.10g: %.6g (target %.6g +- %.6g), %zu runs\n",
           o.vary.key, res.x_best, res.y_best, o.target.value, o.target.tol, res.nruns);
  if (res.bracketed)
    printf("bracket          [%.10g, %.10g]; the line meets the target at %.10g\n", res.x_lo,
           res.x_hi, res.x_interp);
  if (res.fit.n >= 3 && isfinite(res.fit.x))
    printf("response fit     %.6g +- %.3g (standard error; %d runs in [%.6g, %.6g], scatter %.3g "
           "about the line)\n",
           res.fit.x, res.fit.x_se, res.fit.n, res.fit.lo, res.fit.hi, res.fit.noise);
  else if (res.fit.n == 2 && isfinite(res.fit.x))
    printf("response fit     %.6g (2 runs in [%.6g, %.6g]: no scatter estimate)\n", res.fit.x,
           res.fit.lo, res.fit.hi);
  printf("written          %s/runs.csv, response.png, best.yaml, summary.md\n", o.out_dir);
  int found = res.found;
  adem_calib_result_free(&res);
  return found ? EXIT_OK : EXIT_RUNTIME;
}
