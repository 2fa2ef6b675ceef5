/* The adem command: run, resume and check cases. The only code of adem that prints or exits. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "adem/adem.h"
#include "schedule.h"
#include "world.h"

enum {
  EXIT_OK = 0,
  EXIT_INTERNAL = 1,
  EXIT_INPUT = 2,
  EXIT_RUNTIME = 3,
  EXIT_IO = 4,
};

static const char *const main_help =
    "adem " ADEM_VERSION_STRING ": a Discrete Element Method engine for adhesive and granular spheres\n"
    "(Hertz and simplified JKR contacts, friction, rolling resistance, plane walls).\n"
    "\n"
    "Usage:\n"
    "  adem run CASE.yaml [--set key.path=value ...] [--out DIR] [--threads N] [--quiet]\n"
    "  adem run --resume DIR/checkpoint [--threads N] [--quiet]\n"
    "  adem check CASE.yaml [--set key.path=value ...]\n"
    "  adem reference\n"
    "  adem --help | --version\n"
    "\n"
    "Commands:\n"
    "  run        simulate a case, writing VTU frames, a CSV time series and checkpoints;\n"
    "             or continue an interrupted run from its checkpoint (see: adem run --help)\n"
    "  check      validate a case and print what the run would use: effective material\n"
    "             pair properties, collision and Rayleigh times, the time step, the number\n"
    "             of steps, memory and disk estimates (see: adem check --help)\n"
    "  reference  print the case-file reference (every key, unit, default, range) as Markdown\n"
    "\n"
    "Options:\n"
    "  -h, --help     show this help (each command has its own: adem run --help)\n"
    "  -V, --version  print the version\n"
    "\n"
    "Examples:\n"
    "  adem check cases/pour.yaml\n"
    "  adem run cases/pour.yaml --set time.end=0.5 --out out/pour_short\n"
    "  adem run --resume out/pour_short/checkpoint\n"
    "  adem reference > case-reference.md\n"
    "\n"
    "Exit status:\n"
    "  0    success\n"
    "  1    internal error (out of memory)\n"
    "  2    bad input: case file, option, missing file, output folder that cannot be written\n"
    "  3    the run failed (NaN, runaway overlap, escaped particle); the frames and the\n"
    "       last checkpoint written before the failure are kept\n"
    "  4    a file could not be written (disk full, I/O error)\n"
    "  130  interrupted by Ctrl-C (SIGINT), 143 by SIGTERM: a checkpoint was written\n";

static const char *const run_help =
    "Usage:\n"
    "  adem run CASE.yaml [--set key.path=value ...] [--out DIR] [--threads N] [--quiet]\n"
    "  adem run --resume DIR/checkpoint [--threads N] [--quiet]\n"
    "\n"
    "Simulates the case to its end time (time.end). In the output folder DIR it writes\n"
    "  frames/particles_NNNNNN.vtu  particle frames every output.frame_interval (ParaView)\n"
    "  particles.pvd                the collection of frames with their times (open this one)\n"
    "  timeseries.csv               energies, contact counts, largest overlap and the force on\n"
    "                               every wall, every output.csv_interval\n"
    "  checkpoint                   the whole state, every output.checkpoint_interval, on\n"
    "                               Ctrl-C and at the end\n"
    "  energy.png                   energy against time, if output.plot is true (gnuplot)\n"
    "Every file is written to a temporary name and renamed when complete, so a crash never\n"
    "leaves a half-written file.\n"
    "\n"
    "Options:\n"
    "  --set key.path=value  override one value of the case file, e.g. --set time.end=0.2,\n"
    "                        --set materials.glass.friction=0.3; may be repeated; applied after\n"
    "                        the file is read and validated like it\n"
    "  --out DIR             output folder (default: output.dir of the case, or out/<name>);\n"
    "                        created if missing; the run stops at once if it cannot be written\n"
    "  --threads N           number of threads (default: OMP_NUM_THREADS or all cores); the\n"
    "                        results are identical for every N\n"
    "  --resume CHECKPOINT   continue an interrupted run from DIR/checkpoint (or DIR): the case\n"
    "                        is the one stored in the checkpoint, the output continues in DIR,\n"
    "                        and the result is bit for bit that of an uninterrupted run\n"
    "  -q, --quiet           print only warnings and errors, no progress\n"
    "  -h, --help            show this help\n"
    "\n"
    "Progress goes to standard error: one updating line on a terminal, otherwise a line about\n"
    "every 10 s. Ctrl-C (or SIGTERM) stops the run after the current few steps and writes a\n"
    "checkpoint.\n"
    "\n"
    "Examples:\n"
    "  adem run cases/pour.yaml\n"
    "  adem run cases/pour.yaml --set time.end=0.5 --set output.frame_interval=0.01 --out out/s\n"
    "  adem run --resume out/s/checkpoint --threads 4\n"
    "\n"
    "Exit status: 0 done; 2 bad input or output folder; 3 the run failed (the message names the\n"
    "particle and the time; the output written before is kept); 4 a file could not be written;\n"
    "130/143 interrupted by SIGINT/SIGTERM with a checkpoint written; 1 out of memory.\n";

static const char *const check_help =
    "Usage:\n"
    "  adem check CASE.yaml [--set key.path=value ...]\n"
    "\n"
    "Reads and validates the case exactly as `adem run` would (including overlapping initial\n"
    "particles and particles outside walls), without running it, and prints:\n"
    "  - the particles (count, radius range) and walls;\n"
    "  - per pair of materials that can meet: the effective Young's and shear moduli E*, G*\n"
    "    (the modified ones when stiffness_factor < 1), the range of the effective radius R*,\n"
    "    restitution e, damping factor beta = ln e / sqrt(ln^2 e + pi^2), friction, the normal\n"
    "    and rolling models and, for JKR, the Tabor parameter;\n"
    "  - the Hertz collision time at the reference speed v_ref, the Rayleigh time, the\n"
    "    proposed step min(t_c/50, 0.2 t_R), the chosen step and whether it is automatic;\n"
    "  - the number of steps, frames, CSV rows and checkpoints;\n"
    "  - an estimate of the memory the run needs and of the disk space of its output.\n"
    "\n"
    "Options:\n"
    "  --set key.path=value  override one value of the case file (as for adem run)\n"
    "  -h, --help            show this help\n"
    "\n"
    "Example:\n"
    "  adem check cases/pour.yaml --set time.step=1e-6\n"
    "\n"
    "Exit status: 0 the case is valid; 2 it is not (the message says what and where).\n";

/* ---------------------------------------------------------------- messages */

static int quiet = 0;
static int progress_on_line = 0; /* a progress line without newline is on the terminal */
static int stderr_tty = 0;

static void end_progress_line(void) {
  if (progress_on_line) {
    fputc('\n', stderr);
    progress_on_line = 0;
  }
}

static void log_hook(adem_log_level level, const char *message, void *user) {
  (void)user;
  if (level == ADEM_LOG_INFO && quiet) return;
  end_progress_line();
  fprintf(stderr, "adem: %s%s\n", level == ADEM_LOG_WARN ? "warning: " : "", message);
}

static int fail(int code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(int code, const char *fmt, ...) {
  end_progress_line();
  va_list ap;
  va_start(ap, fmt);
  fputs("adem: error: ", stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
  return code;
}

static int exit_code(adem_status st) {
  switch (st) {
    case ADEM_OK: return EXIT_OK;
    case ADEM_ERR_INPUT: return EXIT_INPUT;
    case ADEM_ERR_RUNTIME: return EXIT_RUNTIME;
    case ADEM_ERR_IO: return EXIT_IO;
    default: return EXIT_INTERNAL;
  }
}

/* ---------------------------------------------------------------- progress */

static volatile sig_atomic_t stop_signal = 0;

static void on_signal(int sig) { stop_signal = sig; }

static void install_signals(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

static void format_duration(char *buf, size_t n, double s) {
  if (!(s >= 0.0) || s > 1e9) {
    snprintf(buf, n, "?");
    return;
  }
  unsigned long t = (unsigned long)(s + 0.5);
  if (t >= 3600)
    snprintf(buf, n, "%lu:%02lu:%02lu", t / 3600, (t / 60) % 60, t % 60);
  else
    snprintf(buf, n, "%lu:%02lu", t / 60, t % 60);
}

/* Decimals that show the end time with four significant digits. */
static int time_decimals(double end) {
  int d = end > 0.0 ? 3 - (int)floor(log10(end)) : 3;
  return d < 0 ? 0 : (d > 9 ? 9 : d);
}

typedef struct progress_state {
  double last_line; /* wall time of the last plain line */
} progress_state;

static void on_progress(const adem_progress *p, void *user) {
  progress_state *ps = user;
  if (quiet) return;
  double pct = p->total_steps ? 100.0 * (double)p->step / (double)p->total_steps : 100.0;
  char eta[32];
  format_duration(eta, sizeof eta, p->eta_seconds);
  int dec = time_decimals(p->end_time);
  char line[256];
  snprintf(line, sizeof line, "t=%.*f/%.*f s  %5.1f%%  %.0f steps/s  %zu contacts  ETA %s", dec,
           p->time, dec, p->end_time, pct, p->steps_per_second, p->contacts, eta);
  if (stderr_tty) {
    /* \033[K clears what a longer previous line left. */
    fprintf(stderr, "\r %s\033[K", line);
    fflush(stderr);
    progress_on_line = 1;
  } else if (p->wall_seconds - ps->last_line >= 10.0 || p->step >= p->total_steps) {
    fprintf(stderr, "adem: %s\n", line);
    ps->last_line = p->wall_seconds;
  }
}

/* ---------------------------------------------------------------- options */

typedef struct cli_options {
  const char *case_path;
  const char *resume;
  const char *out;
  const char **sets;
  int nsets;
  int threads;
  int help;
} cli_options;

/* "--name value" or "--name=value": the value, or NULL when this is not that option. */
static const char *option_value(int argc, char **argv, int *i, const char *name, int *missing) {
  size_t n = strlen(name);
  const char *a = argv[*i];
  if (strncmp(a, name, n) != 0) return NULL;
  if (a[n] == '=') return a + n + 1;
  if (a[n] != '\0') return NULL;
  if (*i + 1 >= argc) {
    *missing = 1;
    return NULL;
  }
  return argv[++*i];
}

static int parse_options(int argc, char **argv, cli_options *o, int allow_run, const char *cmd) {
  memset(o, 0, sizeof o[0]);
  o->sets = calloc((size_t)argc + 1, sizeof *o->sets);
  if (!o->sets) return fail(EXIT_INTERNAL, "out of memory");
  for (int i = 0; i < argc; ++i) {
    const char *a = argv[i], *v;
    int missing = 0;
    if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      o->help = 1;
    } else if ((v = option_value(argc, argv, &i, "--set", &missing)) || missing) {
      if (missing) return fail(EXIT_INPUT, "--set needs a key.path=value argument");
      if (!strchr(v, '='))
        return fail(EXIT_INPUT, "--set %s: expected key.path=value, e.g. --set time.end=0.5", v);
      o->sets[o->nsets++] = v;
    } else if (allow_run && ((v = option_value(argc, argv, &i, "--out", &missing)) || missing)) {
      if (missing || !*v) return fail(EXIT_INPUT, "--out needs a folder");
      o->out = v;
    } else if (allow_run && ((v = option_value(argc, argv, &i, "--resume", &missing)) || missing)) {
      if (missing || !*v) return fail(EXIT_INPUT, "--resume needs a checkpoint file or its folder");
      o->resume = v;
    } else if (allow_run && ((v = option_value(argc, argv, &i, "--threads", &missing)) || missing)) {
      char *end = NULL;
      long t = missing ? 0 : strtol(v, &end, 10);
      if (missing || !end || *end || t < 1 || t > 4096)
        return fail(EXIT_INPUT, "--threads needs a whole number from 1 to 4096, not '%s'",
                    missing ? "" : v);
      o->threads = (int)t;
    } else if (allow_run && (strcmp(a, "-q") == 0 || strcmp(a, "--quiet") == 0)) {
      quiet = 1;
    } else if (a[0] == '-' && a[1] != '\0') {
      return fail(EXIT_INPUT, "unknown option %s for adem %s (see: adem %s --help)", a, cmd, cmd);
    } else if (!o->case_path) {
      o->case_path = a;
    } else {
      return fail(EXIT_INPUT, "adem %s takes one case file; '%s' is one too many", cmd, a);
    }
  }
  return EXIT_OK;
}

/* ---------------------------------------------------------------- run */

static double wall_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* DIR or DIR/checkpoint -> the checkpoint file. */
static char *checkpoint_path(const char *arg) {
  struct stat st;
  size_t n = strlen(arg);
  char *p;
  if (stat(arg, &st) == 0 && S_ISDIR(st.st_mode)) {
    p = malloc(n + 12);
    if (p) snprintf(p, n + 12, "%s%scheckpoint", arg, n && arg[n - 1] == '/' ? "" : "/");
  } else {
    p = malloc(n + 1);
    if (p) memcpy(p, arg, n + 1);
  }
  return p;
}

static int cmd_run(int argc, char **argv) {
  cli_options o;
  int rc = parse_options(argc, argv, &o, 1, "run");
  if (rc || o.help) {
    free(o.sets);
    if (o.help && !rc) fputs(run_help, stdout);
    return rc;
  }
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_case *c = NULL;
  adem_status st;
  if (o.resume) {
    if (o.case_path || o.nsets || o.out) {
      free(o.sets);
      return fail(EXIT_INPUT, "--resume continues the case stored in the checkpoint, in the "
                              "checkpoint's folder: it takes no case file, --set or --out");
    }
    char *path = checkpoint_path(o.resume);
    if (!path) {
      free(o.sets);
      return fail(EXIT_INTERNAL, "out of memory");
    }
    st = adem_checkpoint_read(path, &c, &err);
    if (!st) {
      /* The output continues next to the checkpoint, wherever the folder has been moved. */
      const char *slash = strrchr(path, '/');
      if (!slash) snprintf(c->output.dir, sizeof c->output.dir, ".");
      else if (slash == path) snprintf(c->output.dir, sizeof c->output.dir, "/");
      else snprintf(c->output.dir, sizeof c->output.dir, "%.*s", (int)(slash - path), path);
    }
    free(path);
  } else {
    if (!o.case_path) {
      free(o.sets);
      return fail(EXIT_INPUT, "adem run needs a case file (or --resume CHECKPOINT); see: adem "
                              "run --help");
    }
    st = adem_case_load_file(o.case_path, o.sets, o.nsets, &c, &err);
    if (!st && o.out) {
      if (strlen(o.out) >= sizeof c->output.dir) {
        adem_case_free(c);
        free(o.sets);
        return fail(EXIT_INPUT, "--out: the folder name is longer than %d characters",
                    ADEM_PATH_MAX - 1);
      }
      snprintf(c->output.dir, sizeof c->output.dir, "%s", o.out);
    }
  }
  free(o.sets);
  if (st) {
    adem_case_free(c);
    return fail(exit_code(st), "%s", err.message);
  }

  adem_world *w = c->world;
  if (!quiet) {
    fprintf(stderr, "adem: %s %s: %zu particles, dt = %.6g s%s, end time %.6g s (%llu steps), "
                    "output in %s\n",
            o.resume ? "resuming" : "running", c->name, adem_world_particle_count(w),
            c->dt, c->dt_auto ? " (auto)" : "", c->end_time,
            (unsigned long long)adem_schedule_total_steps(c->end_time, c->dt), c->output.dir);
    if (o.resume)
      fprintf(stderr, "adem: continuing from t = %.9g s (step %llu)\n", adem_world_time(w),
              (unsigned long long)adem_world_step_count(w));
  }

  install_signals();
  progress_state ps = {0.0};
  adem_run_options opt = adem_default_run_options();
  opt.nthreads = o.threads;
  opt.progress = on_progress;
  opt.progress_user = &ps;
  opt.stop_flag = &stop_signal;
  double t0 = wall_now();
  st = adem_run(c, &opt, &err);
  double spent = wall_now() - t0;
  end_progress_line();

  if (st == ADEM_INTERRUPTED) {
    fprintf(stderr, "adem: %s\nadem: continue with: adem run --resume %s/checkpoint\n",
            err.message, c->output.dir);
    rc = 128 + (stop_signal ? (int)stop_signal : SIGINT);
  } else if (st) {
    rc = fail(exit_code(st), "%s", err.message);
  } else {
    if (!quiet)
      fprintf(stderr, "adem: done: t = %.9g s after %llu steps in %.1f s; output in %s\n",
              adem_world_time(w), (unsigned long long)adem_world_step_count(w), spent,
              c->output.dir);
    rc = EXIT_OK;
  }
  adem_case_free(c);
  return rc;
}

/* ---------------------------------------------------------------- check */

static const char *normal_name(adem_normal_model m) { return m == ADEM_NORMAL_JKR ? "jkr" : "hertz"; }

static const char *rolling_name(adem_rolling_model m) {
  switch (m) {
    case ADEM_ROLLING_DTK: return "dtk";
    case ADEM_ROLLING_A: return "model_a";
    case ADEM_ROLLING_C: return "model_c";
    case ADEM_ROLLING_BROF: return "brof";
    default: return "none";
  }
}

static double mib(double bytes) { return bytes / (1024.0 * 1024.0); }

/* Tabor parameter lambda_T = (4 R gamma^2 / (E^2 D^3))^(1/3), D = 1.65 A (H1). */
static double tabor(double R, double gamma, double E) {
  const double D = 1.65e-10;
  return cbrt(4.0 * R * gamma * gamma / (E * E * D * D * D));
}

static void print_pair(const adem_world *w, int a, int b, bool wall, const double *rmin,
                       const double *rmax) {
  const adem_interaction *it = adem_world_interaction(w, a, b);
  double Rlo, Rhi;
  if (wall) {
    Rlo = rmin[a];
    Rhi = rmax[a];
  } else {
    Rlo = rmin[a] * rmin[b] / (rmin[a] + rmin[b]);
    Rhi = rmax[a] * rmax[b] / (rmax[a] + rmax[b]);
  }
  char name[2 * ADEM_NAME_MAX + 16];
  snprintf(name, sizeof name, "%s-%s%s", w->materials[a].def.name, w->materials[b].def.name,
           wall ? " (wall)" : "");
  char R[64];
  if (Rlo == Rhi) snprintf(R, sizeof R, "%.4g", Rlo);
  else snprintf(R, sizeof R, "%.4g..%.4g", Rlo, Rhi);
  printf("  %-26s %-11.4g %-11.4g %-21s %-6.3g %-9.4g %-6.3g %-6s %s\n", name, it->E, it->G, R,
         it->restitution, it->beta, it->friction, normal_name(it->normal), rolling_name(it->rolling));
  if (it->E != it->E_real)
    printf("  %-26s real material: E* = %.4g Pa, G* = %.4g Pa (stiffness reduced, H24)\n", "",
           it->E_real, it->G_real);
  if (it->normal == ADEM_NORMAL_JKR && it->gamma_real > 0.0) {
    double tlo = tabor(Rlo, it->gamma_real, it->E_real), thi = tabor(Rhi, it->gamma_real, it->E_real);
    printf("  %-26s gamma = %.4g J/m^2, Tabor parameter %.3g..%.3g%s\n", "", it->gamma_real, tlo,
           thi, tlo < 3.0 ? " (below 3: outside the JKR range, H1)" : "");
  }
}

static int cmd_check(int argc, char **argv) {
  cli_options o;
  int rc = parse_options(argc, argv, &o, 0, "check");
  if (rc || o.help) {
    free(o.sets);
    if (o.help && !rc) fputs(check_help, stdout);
    return rc;
  }
  if (!o.case_path) {
    free(o.sets);
    return fail(EXIT_INPUT, "adem check needs a case file; see: adem check --help");
  }
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_case *c = NULL;
  adem_status st = adem_case_load_file(o.case_path, o.sets, o.nsets, &c, &err);
  free(o.sets);
  if (!st) {
    if (c->dt > 0.0) adem_world_set_dt(c->world, c->dt);
    st = adem_world_prepare(c->world, &err); /* overlaps, particles behind walls */
  }
  if (st) {
    adem_case_free(c);
    return fail(exit_code(st), "%s", err.message);
  }
  const adem_world *w = c->world;
  const adem_particles *p = &w->p;
  int nm = w->nmaterials;
  double *rmin = malloc((size_t)(nm > 0 ? nm : 1) * sizeof *rmin);
  double *rmax = malloc((size_t)(nm > 0 ? nm : 1) * sizeof *rmax);
  bool *wallmat = calloc((size_t)(nm > 0 ? nm : 1), sizeof *wallmat);
  if (!rmin || !rmax || !wallmat) {
    free(rmin);
    free(rmax);
    free(wallmat);
    adem_case_free(c);
    return fail(EXIT_INTERNAL, "out of memory");
  }
  for (int k = 0; k < nm; ++k) {
    rmin[k] = INFINITY;
    rmax[k] = 0.0;
  }
  double rlo = INFINITY, rhi = 0.0, mass = 0.0;
  for (size_t i = 0; i < p->n; ++i) {
    int m = p->material[i];
    rmin[m] = fmin(rmin[m], p->radius[i]);
    rmax[m] = fmax(rmax[m], p->radius[i]);
    rlo = fmin(rlo, p->radius[i]);
    rhi = fmax(rhi, p->radius[i]);
    mass += 1.0 / p->inv_mass[i];
  }
  for (int k = 0; k < w->nplanes; ++k) wallmat[w->planes[k].def.material] = true;

  printf("case        %s (%s)\n", c->name, c->path);
  printf("particles   %zu, radius %.4g..%.4g m, total mass %.4g kg\n", p->n, rlo, rhi, mass);
  printf("walls       %d plane%s", w->nplanes, w->nplanes == 1 ? "" : "s");
  for (int k = 0; k < w->nplanes && k < 12; ++k)
    printf("%s%s", k ? ", " : ": ", w->planes[k].def.name);
  printf("%s\n", w->nplanes > 12 ? ", ..." : "");
  printf("gravity     (%g, %g, %g) m/s^2\n", w->gravity.x, w->gravity.y, w->gravity.z);
  printf("contacts    %zu particle pairs and %zu wall pairs within reach at the start\n",
         w->pp.n, w->pw.n);

  printf("\nmaterial pairs (effective values: E*, G* from H2 and H15, R* = r_i r_j/(r_i+r_j), "
         "beta from H12)\n");
  printf("  %-26s %-11s %-11s %-21s %-6s %-9s %-6s %-6s %s\n", "pair", "E* (Pa)", "G* (Pa)",
         "R* (m)", "e", "beta", "mu", "normal", "rolling");
  for (int a = 0; a < nm; ++a) {
    if (!(rmax[a] > 0.0)) continue;
    for (int b = a; b < nm; ++b)
      if (rmax[b] > 0.0) print_pair(w, a, b, false, rmin, rmax);
    for (int b = 0; b < nm; ++b)
      if (wallmat[b]) print_pair(w, a, b, true, rmin, rmax);
  }

  const adem_step_estimate *e = &c->estimate;
  double dt = w->dt;
  uint64_t total = adem_schedule_total_steps(c->end_time, dt);
  printf("\ntime step (notes section 6)\n");
  printf("  reference speed v_ref     %.4g m/s\n", e->v_ref);
  printf("  Hertz collision time t_c  %.4g s\n", e->t_collision);
  printf("  Rayleigh time t_R         %.4g s\n", e->t_rayleigh);
  printf("  proposed step             %.4g s = min(t_c/50, 0.2 t_R)\n", e->dt);
  if (c->dt_auto)
    printf("  chosen step               %.4g s (auto)\n", dt);
  else
    printf("  chosen step               %.4g s (time.step: %.3g times the proposed one)%s\n", dt,
           c->dt_user_ratio, c->dt_user_ratio > 1.0 ? " -- larger than proposed" : "");
  printf("  end time                  %.6g s: %llu steps\n", c->end_time, (unsigned long long)total);

  const adem_output_settings *os = &c->output;
  uint64_t kf = adem_schedule_period(os->frame_interval, dt);
  uint64_t kc = adem_schedule_period(os->csv_interval, dt);
  uint64_t kk = adem_schedule_period(os->checkpoint_interval, dt);
  uint64_t nframes = adem_schedule_count(kf, total), nrows = adem_schedule_count(kc, total);
  printf("\noutput in %s\n", os->dir);
  if (kf) printf("  frames       every %.4g s (%llu steps): %llu frames\n", os->frame_interval,
                 (unsigned long long)kf, (unsigned long long)nframes);
  else printf("  frames       off\n");
  if (kc) printf("  CSV rows     every %.4g s (%llu steps): %llu rows\n", os->csv_interval,
                 (unsigned long long)kc, (unsigned long long)nrows);
  else printf("  CSV rows     off\n");
  if (kk) printf("  checkpoints  every %.4g s (%llu steps), on Ctrl-C and at the end\n",
                 os->checkpoint_interval, (unsigned long long)kk);
  else printf("  checkpoints  on Ctrl-C and at the end\n");
  printf("  energy plot  %s\n", os->plot ? "yes (gnuplot)" : "no");

  /* Bytes per particle and per candidate pair in the arrays of src/world.h. */
  double per_particle = 6.0 * sizeof(adem_vec3) + 3.0 * sizeof(double) + sizeof(uint64_t) +
                        2.0 * sizeof(uint16_t) + 2.0 * sizeof(size_t) /* gather starts */ +
                        3.0 * sizeof(size_t) /* neighbour build scratch */;
  double per_pair = 2.0 * sizeof(uint32_t) + sizeof(adem_contact_history) + sizeof(bool) +
                    3.0 * sizeof(adem_vec3) + 2.0 * sizeof(double);
  double memory = (double)p->n * per_particle + (double)w->pp.n * (per_pair + 8.0) +
                  (double)w->pw.n * (per_pair + 4.0) + (double)w->nb.ncells * sizeof(size_t);
  double frame = 1500.0 + (double)p->n * (8 + 8 + 4 + 4 * 24 + 8 + 8 + 1);
  double row = (9.0 + 3.0 * w->nplanes) * 24.0;
  double ckpt = (double)strlen(c->source) + (double)p->n * (6 * 24 + 3 * 8 + 8 + 4) +
                (double)(w->pp.n + w->pw.n) * per_pair;
  printf("\nestimates\n");
  printf("  memory       %.1f MiB at the start (%zu particles, %zu candidate pairs; grows with "
         "the number of contacts)\n", mib(memory), p->n, w->pp.n + w->pw.n);
  printf("  disk         %.1f MiB: frames %llu x %.2f MiB, CSV %.2f MiB, checkpoint %.2f MiB\n",
         mib((double)nframes * frame + (double)nrows * row + ckpt), (unsigned long long)nframes,
         mib(frame), mib((double)nrows * row), mib(ckpt));
  printf("\nthe case is valid\n");
  free(rmin);
  free(rmax);
  free(wallmat);
  adem_case_free(c);
  return EXIT_OK;
}

/* ---------------------------------------------------------------- main */

int main(int argc, char **argv) {
  stderr_tty = isatty(STDERR_FILENO);
  adem_log_set_hook(log_hook, NULL);
  if (argc < 2) {
    fputs(main_help, stderr);
    return EXIT_INPUT;
  }
  const char *cmd = argv[1];
  if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0) {
    if (argc > 2 && strcmp(argv[2], "run") == 0) fputs(run_help, stdout);
    else if (argc > 2 && strcmp(argv[2], "check") == 0) fputs(check_help, stdout);
    else fputs(main_help, stdout);
    return EXIT_OK;
  }
  if (strcmp(cmd, "-V") == 0 || strcmp(cmd, "--version") == 0) {
    printf("adem %s\n", ADEM_VERSION_STRING);
    return EXIT_OK;
  }
  if (strcmp(cmd, "run") == 0) return cmd_run(argc - 2, argv + 2);
  if (strcmp(cmd, "check") == 0) return cmd_check(argc - 2, argv + 2);
  if (strcmp(cmd, "reference") == 0) {
    if (argc > 2 && (strcmp(argv[2], "-h") == 0 || strcmp(argv[2], "--help") == 0)) {
      puts("Usage: adem reference\n\nPrints the case-file reference (every key with its type, "
           "unit, default,\nrange and meaning) as Markdown on standard output.\n\nExample:\n"
           "  adem reference > case-reference.md");
      return EXIT_OK;
    }
    adem_case_write_reference(stdout);
    return fflush(stdout) == 0 ? EXIT_OK : EXIT_IO;
  }
  return fail(EXIT_INPUT, "unknown command '%s'; the commands are run, check and reference (see: "
                          "adem --help)", cmd);
}
