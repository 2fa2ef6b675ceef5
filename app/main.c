/* The adem command: run, resume and check cases. The only code of adem that prints or exits. */
#include <errno.h>
#include <stddef.h>
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
#include "adem/adem.h"
#include "fileio.h"
#include "insert.h"
#include "parallel.h"
#include "schedule.h"
#include "stages.h"
#include "adem/adem.h"
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
    "  adem collide [--kind pair|wall] [--speed LIST] [--lambda LIST] [--ad LIST] ...\n"
    "  adem validate [NAME ...] [--out DIR] [--quick] [--list]\n"
    "  adem reference\n"
    "  adem --help | --version\n"
    "\n"
    "Commands:\n"
    "  run        simulate a case, writing VTU frames, a CSV time series and checkpoints;\n"
    "             or continue an interrupted run from its checkpoint (see: adem run --help)\n"
    "  check      validate a case and print what the run would use: effective material\n"
    "             pair properties, collision and Rayleigh times, the time step, the number\n"
    "             of steps, memory and disk estimates (see: adem check --help)\n"
    "  collide    run single collisions in bulk (pair head-on or sphere on a wall) over lists\n"
    "             of speeds, angles, lambda, Ad or stiffness factors; e_eff, stuck, contact\n"
    "             duration and overlap as CSV (see: adem collide --help)\n"
    "  validate   reproduce the papers' figures and check their claims: CSV, PNG and a\n"
    "             summary per figure (see: adem validate --help)\n"
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
    "  frames/mesh_NNNNNN.vtu       mesh walls with the force and pressure on each face, and\n"
    "  mesh.pvd                     their collection (only when the case has mesh walls)\n"
    "  timeseries.csv               energies, contact counts, largest overlap, the force on\n"
    "                               every wall and the force and torque on every mesh group,\n"
    "                               every output.csv_interval\n"
    "  checkpoint                   the whole state, every output.checkpoint_interval, on\n"
    "                               Ctrl-C and at the end\n"
    "  energy.png                   energy against time, if output.plot is true (gnuplot)\n"
    "  loads.png                    wall loads against time, if output.plot_loads is true\n"
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
    "    and rolling models;\n"
    "  - for each JKR pair, at its smallest spheres, real and modified (stiffness_factor, H24):\n"
    "    E*, gamma, a0, the equilibrium overlap a0^2/(3R), F_C = 3 pi gamma R, the pull-off\n"
    "    force (8/9) F_C, the Hertz collision time and the step t_c/50, the speed-up of the step\n"
    "    (E/E_mod)^(2/5), the Tabor parameter (a warning below 3, where JKR does not apply) and\n"
    "    the largest external force that stays below 10% of the modified pull-off force;\n"
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

/* What a JKR pair implies, at its smallest spheres (notes sections 1, 5, 6; H section 6.2). */
static void print_jkr(const adem_world *w, int a, int b, bool wall, const double *rmin,
                      double v_ref) {
  const adem_interaction *it = adem_world_interaction(w, a, b);
  if (it->normal != ADEM_NORMAL_JKR) return;
  const char *pad = "";
  if (!(it->pp.gamma_real > 0.0)) {
    printf("  %-26s jkr without surface energy: the contact is Hertz\n", pad);
    return;
  }
  double ra = rmin[a], ma = w->mat.m[a].def.density * (4.0 / 3.0) * ADEM_PI * ra * ra * ra;
  double R = ra, mstar = ma;
  if (!wall) {
    double rb = rmin[b], mb = w->mat.m[b].def.density * (4.0 / 3.0) * ADEM_PI * rb * rb * rb;
    R = ra * rb / (ra + rb);
    mstar = ma * mb / (ma + mb);
  }
  adem_jkr_pair_summary s =
      adem_jkr_pair_summarize(it->pp.E_real, it->pp.E, it->pp.gamma_real, it->pp.gamma, R, mstar, v_ref);
  char mod[64];
  snprintf(mod, sizeof mod, "modified (E_mod/E = %.3g)", it->pp.E / it->pp.E_real);
  printf("  %-26s simplified JKR (H7-H10) for the smallest spheres: R* = %.4g m, m* = %.4g kg\n",
         pad, R, mstar);
  printf("  %-26s   %-36s %-12s %s\n", pad, "", "real", mod);
  const struct {
    const char *label;
    double real, modified;
  } rows[] = {
      {"E* (Pa)", s.E, s.E_mod},
      {"gamma (J/m^2)", s.gamma, s.gamma_mod},
      {"a0 = (9 pi gamma R^2/E)^(1/3) (m)", s.a0, s.a0_mod},
      {"delta_eq = a0^2/(3R) (m)", s.delta_eq, s.delta_eq_mod},
      {"F_C = 3 pi gamma R (N)", s.f_c, s.f_c_mod},
      {"pull-off force (8/9) F_C (N)", s.pull_off, s.pull_off_mod},
      {"Hertz t_c at v_ref (s)", s.t_c, s.t_c_mod},
      {"time step t_c/50 (s)", s.dt, s.dt_mod},
  };
  for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k)
    printf("  %-26s   %-36s %-12.4g %.4g\n", pad, rows[k].label, rows[k].real, rows[k].modified);
  printf("  %-26s   step speed-up (E/E_mod)^(2/5) = %.4g\n", pad, s.speedup);
  printf("  %-26s   Tabor parameter lambda_T = %.3g (real material, D_min = 1.65e-10 m)%s\n", pad,
         s.tabor, s.tabor < 3.0 ? ": below 3, JKR is outside its range (H1)" : ", JKR valid (> 3)");
  printf("  %-26s   external forces pulling these spheres apart must stay below %.3g N (%.0f%% "
         "of the modified pull-off force)\n",
         pad, s.f_ext_max, 100.0 * ADEM_PULLOFF_SAFETY);
  if (s.tabor < 3.0) {
    fflush(stdout);
    fprintf(stderr,
            "adem: warning: %s-%s%s: Tabor parameter %.3g is below 3: the JKR model is outside "
            "its range (H1); the contact is closer to DMT/Maugis\n",
            w->mat.m[a].def.name, w->mat.m[b].def.name, wall ? " (wall)" : "", s.tabor);
  }
}

static void print_pair(const adem_world *w, int a, int b, bool wall, const double *rmin,
                       const double *rmax, double v_ref) {
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
  snprintf(name, sizeof name, "%s-%s%s", w->mat.m[a].def.name, w->mat.m[b].def.name,
           wall ? " (wall)" : "");
  char R[64];
  if (Rlo == Rhi) snprintf(R, sizeof R, "%.4g", Rlo);
  else snprintf(R, sizeof R, "%.4g..%.4g", Rlo, Rhi);
  printf("  %-26s %-11.4g %-11.4g %-21s %-6.3g %-9.4g %-6.3g %-6s %s\n", name, it->pp.E, it->pp.G, R,
         it->pp.restitution, it->pp.beta, it->pp.friction, normal_name(it->normal), rolling_name(it->rolling));
  if (it->pp.E != it->pp.E_real)
    printf("  %-26s real material: E* = %.4g Pa, G* = %.4g Pa (stiffness reduced, H24)\n", "",
           it->pp.E_real, it->pp.G_real);
  print_jkr(w, a, b, wall, rmin, v_ref);
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
  int nm = w->mat.n;
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
  for (int k = 0; c->pours && k < c->pours->n; ++k) { /* poured spheres meet them too */
    const adem_pour *q = &c->pours->p[k];
    rmin[q->def.material] = fmin(rmin[q->def.material], adem_insert_dist_smallest(&q->def.dist));
    rmax[q->def.material] = fmax(rmax[q->def.material], adem_insert_dist_largest(&q->def.dist));
  }
  for (int k = 0; k < w->walls.nplanes; ++k) wallmat[w->walls.planes[k].def.material] = true;
  for (int k = 0; k < w->walls.mesh.ngroups; ++k) wallmat[w->walls.mesh.groups[k].material] = true;

  printf("case        %s (%s)\n", c->name, c->path);
  if (p->n)
    printf("particles   %zu, radius %.4g..%.4g m, total mass %.4g kg\n", p->n, rlo, rhi, mass);
  else
    printf("particles   none at the start\n");
  printf("walls       %d plane%s", w->walls.nplanes, w->walls.nplanes == 1 ? "" : "s");
  for (int k = 0; k < w->walls.nplanes && k < 12; ++k)
    printf("%s%s", k ? ", " : ": ", w->walls.planes[k].def.name);
  printf("%s\n", w->walls.nplanes > 12 ? ", ..." : "");
  if (w->walls.mesh.ngroups > 0) {
    printf("meshes      %zu triangles in %d group%s", w->walls.mesh.ntris, w->walls.mesh.ngroups,
           w->walls.mesh.ngroups == 1 ? "" : "s");
    for (int k = 0; k < w->walls.mesh.ngroups && k < 12; ++k)
      printf("%s%s", k ? ", " : ": ", w->walls.mesh.groups[k].name);
    printf("%s\n", w->walls.mesh.ngroups > 12 ? ", ..." : "");
  }
  for (int k = 0; c->pours && k < c->pours->n; ++k) {
    const adem_pour *q = &c->pours->p[k];
    static const char *const shapes[] = {"box", "cylinder", "mesh"};
    printf("pour        %s: %.6g %s from t = %g to %g s into a %s, radius %.4g..%.4g m\n",
           q->def.name, adem_pour_total(q), q->def.rate > 0.0 ? "particles" : "kg", q->def.start,
           q->def.end, shapes[q->def.region.kind], adem_insert_dist_smallest(&q->def.dist),
           adem_insert_dist_largest(&q->def.dist));
  }
  for (int k = 0; c->stages && k < c->stages->n; ++k) {
    const adem_stage *g = &c->stages->s[k];
    double t0 = (double)adem_stages_start_step(c, k) * w->dt;
    printf("stage %-5d %s: from t = %.6g s, %d change%s\n", k + 1, g->name, t0, g->nsets,
           g->nsets == 1 ? "" : "s");
  }
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
      if (rmax[b] > 0.0) print_pair(w, a, b, false, rmin, rmax, c->estimate.v_ref);
    for (int b = 0; b < nm; ++b)
      if (wallmat[b]) print_pair(w, a, b, true, rmin, rmax, c->estimate.v_ref);
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
  double row = (9.0 + 3.0 * w->walls.nplanes) * 24.0;
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

/* ---------------------------------------------------------------- collide */

static const char *const collide_help =
    "Usage:\n"
    "  adem collide [--kind pair|wall] [material options] [--speed LIST] [--angle LIST]\n"
    "               [--lambda LIST] [--ad LIST] [--restitution LIST] [--stiffness-factor LIST]\n"
    "               [--keep-gamma] [deposition options] [--critical-lambda LO:HI[:TOL]]\n"
    "               [--steps-per-tc N] [--out FILE.csv] [--threads N]\n"
    "\n"
    "Runs single collisions in bulk, without a case file: two equal-material spheres head-on\n"
    "(pair) or a sphere on a rigid plane wall at an angle (wall). Every combination of the lists\n"
    "is one collision, in its own world, run in parallel; the rows come out in input order\n"
    "(restitution, then F_hat, then stiffness factor, then Ad, then lambda, then angle, then\n"
    "speed, the last varying fastest). Each row gives e_eff (normal separation/approach speed),\n"
    "whether the spheres stuck, the outcome, the contact duration, the largest overlap and the\n"
    "step used.\n"
    "\n"
    "A LIST is  a,b,c  or  lo:hi:n  (n values, linear)  or  log:lo:hi:n  (n values, logarithmic).\n"
    "\n"
    "Material and impact (defaults: a PSL sphere on quartz, Haervig et al. Fig. 5):\n"
    "  --kind pair|wall         head-on pair or wall impact (default wall)\n"
    "  --radius R               radius r_i of the (first) sphere, m (default 6.35e-7)\n"
    "  --size-ratio B           r_j / r_i of a pair (default 1)\n"
    "  --density RHO            kg/m^3 (default 1026)\n"
    "  --young E                effective Young's modulus E* of the real materials, Pa\n"
    "                           (H2; default 2.71e8)\n"
    "  --poisson NU             Poisson's ratio of the spheres (default 0.3)\n"
    "  --restitution LIST       coefficient of restitution e (default 0.86)\n"
    "  --friction MU            sliding friction (default 0.3)\n"
    "  --surface-energy G       surface energy gamma, J/m^2; 0 gives Hertz (default 0.11)\n"
    "  --stiffness-factor LIST  f = E_mod/E in (0, 1] (default 1); gamma becomes gamma f^(2/5)\n"
    "  --keep-gamma             reduce E only, keep gamma (not H24), for comparison\n"
    "  --speed LIST             relative impact speed, m/s (default 1)\n"
    "  --angle LIST             wall: angle psi between the velocity and the wall, degrees\n"
    "                           (default 90, a normal impact)\n"
    "  --lambda LIST            set E from lambda = E/(rho v^2 sin^2 psi) at each speed\n"
    "  --ad LIST                set gamma from Ad = 3 gamma/(rho v^2 sin^2 psi r_i)\n"
    "                           (1+B^3)/((1+B^2) B) (pair; wall: without the B factor)\n"
    "  --steps-per-tc N         time steps per collision time (default 200)\n"
    "\n"
    "Deposition on the wall (Haervig et al. section 5.3, Figs. 9-10):\n"
    "  --dtk                    DTK adhesive rolling resistance on the sphere-wall pair\n"
    "                           (H18-H22); needs --hysteresis\n"
    "  --hysteresis X           adhesion hysteresis delta_gamma/gamma (> 0)\n"
    "  --no-dtk-modification    F_C, a0 and xi_crit of the modified material as well; the default\n"
    "                           keeps the real ones and modifies only a/a0 (H section 3.2)\n"
    "  --force-ext F            constant force through the centre, parallel to the wall, N,\n"
    "                           along the tangential impact velocity (+x for a normal impact)\n"
    "  --force-hat LIST         or the force as F_ext/F_yield, F_yield = 4 F_C xi_crit / r at\n"
    "                           a = a0 with the real E and gamma (H section 5.3, with the 1/R\n"
    "                           the paper drops)\n"
    "  --at-rest                no impact: the sphere starts at rest at the JKR equilibrium\n"
    "  --rest-periods N         decision window, in rolling periods T_r (default 3)\n"
    "  --max-roll-periods N     longest rolling phase, in T_r (default 400; then undecided)\n"
    "  With --dtk a captured sphere is followed until it is stuck (|xi| below xi_crit and the\n"
    "  centre slower than 2 omega_r xi_crit for a whole window; the time to rest is the start\n"
    "  of the window) or rolling (the rolling torque saturated at k_r xi_crit, the normal motion\n"
    "  settled and the speed not decaying over a window). T_r = 2 pi sqrt(1.4 m r/(4 F_C)).\n"
    "\n"
    "Critical elasticity (Haervig et al. Figs. 11-12, H25):\n"
    "  --critical-lambda LO:HI[:TOL]  instead of a lambda list: for every other combination,\n"
    "                           the lambda in [LO, HI] where the outcome changes between\n"
    "                           captured and rebound, by multisection in log lambda to a\n"
    "                           relative width TOL (default 1e-4). Rows give lambda_crit and\n"
    "                           c = lambda_crit/Ad^(5/2); the fit lambda_crit = c Ad^k per\n"
    "                           restitution goes to standard error.\n"
    "\n"
    "Output:\n"
    "  --out FILE.csv           write the CSV there (default: standard output)\n"
    "  --threads N              threads (default: OMP_NUM_THREADS or all cores); the results\n"
    "                           are identical for every N\n"
    "\n"
    "Ad is the text's definition in Haervig et al. section 5.1 (the caption of their Fig. 7\n"
    "writes gamma/(rho v^2 R), which disagrees). Stuck: the contact's normal energy (kinetic +\n"
    "JKR) has fallen below its value at delta = 0, so the contact can no longer break.\n"
    "\n"
    "Examples:\n"
    "  adem collide --speed log:0.5:20:40 --stiffness-factor 1,0.1,0.01 --out e_eff.csv\n"
    "  adem collide --kind pair --restitution 0.3 --speed 1 --radius 1e-6 --density 1000 \\\n"
    "      --lambda log:1e2:1e7:41 --ad 1,10\n"
    "  adem collide --speed 2 --angle 45 --dtk --hysteresis 0.5 --force-hat 0.5,0.9,1.1,2 \\\n"
    "      --stiffness-factor 1,0.1,0.01\n"
    "  adem collide --radius 1e-6 --density 1000 --ad 100,300,1000 --restitution 0.1:0.9:9 \\\n"
    "      --critical-lambda 1e3:1e13:1e-5\n"
    "\n"
    "Exit status: 0 done; 2 bad option; 3 a collision could not be run (its row says why);\n"
    "4 the CSV could not be written.\n";

typedef struct value_list {
  double *v;
  size_t n;
} value_list;

/* "a,b,c", "lo:hi:n" or "log:lo:hi:n" into a fresh list. */
static int parse_list(const char *opt, const char *text, value_list *out) {
  free(out->v);
  out->v = NULL;
  out->n = 0;
  bool logscale = strncmp(text, "log:", 4) == 0;
  const char *s = logscale ? text + 4 : (strncmp(text, "lin:", 4) == 0 ? text + 4 : text);
  if (strchr(s, ':')) {
    char *end;
    double lo = strtod(s, &end);
    double hi = *end == ':' ? strtod(end + 1, &end) : NAN;
    long n = *end == ':' ? strtol(end + 1, &end, 10) : 0;
    if (*end || !isfinite(lo) || !isfinite(hi) || n < 1 || n > 1000000 ||
        (logscale && !(lo > 0.0 && hi > 0.0)))
      return fail(EXIT_INPUT,
                  "%s %s: expected lo:hi:n or log:lo:hi:n (n from 1 to 1000000, log needs lo, hi "
                  "> 0)", opt, text);
    out->v = malloc((size_t)n * sizeof *out->v);
    if (!out->v) return fail(EXIT_INTERNAL, "out of memory");
    for (long k = 0; k < n; ++k) {
      double x = n == 1 ? 0.0 : (double)k / (double)(n - 1);
      out->v[k] = logscale ? lo * pow(hi / lo, x) : lo + (hi - lo) * x;
    }
    out->n = (size_t)n;
    return EXIT_OK;
  }
  size_t cap = 1;
  for (const char *c = s; *c; ++c) cap += *c == ',';
  out->v = malloc(cap * sizeof *out->v);
  if (!out->v) return fail(EXIT_INTERNAL, "out of memory");
  for (const char *c = s;;) {
    char *end;
    double x = strtod(c, &end);
    if (end == c || (*end && *end != ',') || !isfinite(x))
      return fail(EXIT_INPUT, "%s %s: expected numbers separated by commas, lo:hi:n or "
                              "log:lo:hi:n", opt, text);
    out->v[out->n++] = x;
    if (!*end) break;
    c = end + 1;
  }
  return EXIT_OK;
}

static int parse_number_option(const char *opt, const char *text, double *x) {
  char *end;
  *x = strtod(text, &end);
  if (end == text || *end || !isfinite(*x))
    return fail(EXIT_INPUT, "%s needs a number, not '%s'", opt, text);
  return EXIT_OK;
}

/* Every value of the list satisfies lo < x (or lo <= x) and x <= hi. */
static int check_list(const char *opt, const value_list *l, double lo, bool lo_open, double hi,
                      const char *allowed) {
  for (size_t k = 0; k < l->n; ++k)
    if ((lo_open ? !(l->v[k] > lo) : !(l->v[k] >= lo)) || !(l->v[k] <= hi))
      return fail(EXIT_INPUT, "%s: %g is out of range: it must be %s", opt, l->v[k], allowed);
  return EXIT_OK;
}

/* "LO:HI" or "LO:HI:TOL" of --critical-lambda. */
static int parse_critical(const char *text, double *lo, double *hi, double *tol) {
  char *end;
  *lo = strtod(text, &end);
  *hi = *end == ':' ? strtod(end + 1, &end) : NAN;
  *tol = 1e-4;
  if (*end == ':') *tol = strtod(end + 1, &end);
  if (*end || !(*lo > 0.0) || !(*hi > *lo) || !isfinite(*hi) || !(*tol > 0.0 && *tol < 1.0))
    return fail(EXIT_INPUT, "--critical-lambda %s: expected LO:HI or LO:HI:TOL with 0 < LO < HI "
                            "and 0 < TOL < 1", text);
  return EXIT_OK;
}

static void set_lambda_cli(adem_collision_spec *s, double x, void *user) {
  (void)user;
  adem_collide_set_lambda(s, x);
}

/* The CSV cell of a message: quoted, inner quotes made single. */
static void status_cell(char *out, size_t n, adem_status st, const char *message) {
  if (!st) {
    snprintf(out, n, "ok");
    return;
  }
  snprintf(out, n, "\"error: %s\"", message);
  for (char *q = out + 1; q[0] && q[1]; ++q)
    if (*q == '"') *q = '\'';
}

static int cmd_collide(int argc, char **argv) {
  adem_collision_spec base = adem_default_collision_spec();
  base.kind = ADEM_COLLISION_WALL;
  base.radius = 0.635e-6;
  base.density = 1026.0;
  base.young = 271e6;
  base.restitution = 0.86;
  base.friction = 0.3;
  base.surface_energy = 0.11;
  value_list speed = {0}, angle = {0}, lambda = {0}, ad = {0}, fs = {0}, rest = {0}, fhat = {0};
  const char *out = NULL, *critical = NULL;
  int threads = 0, rc = EXIT_OK;
  static const struct {
    const char *name;
    size_t offset;
  } numbers[] = {
      {"--radius", offsetof(adem_collision_spec, radius)},
      {"--size-ratio", offsetof(adem_collision_spec, size_ratio)},
      {"--density", offsetof(adem_collision_spec, density)},
      {"--young", offsetof(adem_collision_spec, young)},
      {"--poisson", offsetof(adem_collision_spec, poisson)},
      {"--friction", offsetof(adem_collision_spec, friction)},
      {"--surface-energy", offsetof(adem_collision_spec, surface_energy)},
      {"--steps-per-tc", offsetof(adem_collision_spec, steps_per_tc)},
      {"--hysteresis", offsetof(adem_collision_spec, hysteresis)},
      {"--force-ext", offsetof(adem_collision_spec, force_ext)},
      {"--rest-periods", offsetof(adem_collision_spec, rest_periods)},
      {"--max-roll-periods", offsetof(adem_collision_spec, max_roll_periods)},
  };
  static const char *const list_names[] = {"--speed", "--angle", "--lambda", "--ad",
                                           "--stiffness-factor", "--restitution", "--force-hat"};
  value_list *lists[] = {&speed, &angle, &lambda, &ad, &fs, &rest, &fhat};
  enum { NLISTS = sizeof lists / sizeof lists[0] };
  static const struct {
    const char *name;
    size_t offset;
  } flags[] = {
      {"--keep-gamma", offsetof(adem_collision_spec, keep_gamma)},
      {"--dtk", offsetof(adem_collision_spec, dtk)},
      {"--at-rest", offsetof(adem_collision_spec, at_rest)},
  };
  for (int i = 0; i < argc && !rc; ++i) {
    const char *a = argv[i], *v;
    int missing = 0, done = 0;
    if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      fputs(collide_help, stdout);
      rc = -1;
      break;
    }
    for (size_t k = 0; k < sizeof flags / sizeof flags[0] && !done; ++k)
      if (strcmp(a, flags[k].name) == 0) {
        *(bool *)((char *)&base + flags[k].offset) = true;
        done = 1;
      }
    if (!done && strcmp(a, "--no-dtk-modification") == 0) {
      base.dtk_modification = false;
      done = 1;
    }
    for (size_t k = 0; k < sizeof numbers / sizeof numbers[0] && !done && !rc; ++k)
      if ((v = option_value(argc, argv, &i, numbers[k].name, &missing)) || missing) {
        done = 1;
        rc = missing ? fail(EXIT_INPUT, "%s needs a value", numbers[k].name)
                     : parse_number_option(numbers[k].name, v,
                                           (double *)((char *)&base + numbers[k].offset));
      }
    for (size_t k = 0; k < NLISTS && !done && !rc; ++k)
      if ((v = option_value(argc, argv, &i, list_names[k], &missing)) || missing) {
        done = 1;
        rc = missing ? fail(EXIT_INPUT, "%s needs a value", list_names[k])
                     : parse_list(list_names[k], v, lists[k]);
      }
    if (done || rc) continue;
    if ((v = option_value(argc, argv, &i, "--kind", &missing)) || missing) {
      if (!missing && strcmp(v, "pair") == 0) base.kind = ADEM_COLLISION_PAIR;
      else if (!missing && strcmp(v, "wall") == 0) base.kind = ADEM_COLLISION_WALL;
      else rc = fail(EXIT_INPUT, "--kind needs pair or wall, not '%s'", missing ? "" : v);
    } else if ((v = option_value(argc, argv, &i, "--critical-lambda", &missing)) || missing) {
      if (missing || !*v) rc = fail(EXIT_INPUT, "--critical-lambda needs LO:HI or LO:HI:TOL");
      else critical = v;
    } else if ((v = option_value(argc, argv, &i, "--out", &missing)) || missing) {
      if (missing || !*v) rc = fail(EXIT_INPUT, "--out needs a file name");
      else out = v;
    } else if ((v = option_value(argc, argv, &i, "--threads", &missing)) || missing) {
      char *end = NULL;
      long t = missing ? 0 : strtol(v, &end, 10);
      if (missing || !end || *end || t < 1 || t > 4096)
        rc = fail(EXIT_INPUT, "--threads needs a whole number from 1 to 4096, not '%s'",
                  missing ? "" : v);
      else threads = (int)t;
    } else {
      rc = fail(EXIT_INPUT, "unknown option or argument '%s' for adem collide (see: adem collide "
                            "--help)", a);
    }
  }
  /* Checks of what every collision shares, then of each list. */
  bool wall = base.kind == ADEM_COLLISION_WALL;
  double crit_lo = 0.0, crit_hi = 0.0, crit_tol = 0.0;
  if (!rc && !(base.radius > 0.0)) rc = fail(EXIT_INPUT, "--radius must be > 0");
  if (!rc && !(base.size_ratio > 0.0)) rc = fail(EXIT_INPUT, "--size-ratio must be > 0");
  if (!rc && !(base.density > 0.0)) rc = fail(EXIT_INPUT, "--density must be > 0");
  if (!rc && !(base.young > 0.0)) rc = fail(EXIT_INPUT, "--young must be > 0");
  if (!rc && !(base.poisson > -1.0 && base.poisson < 0.5))
    rc = fail(EXIT_INPUT, "--poisson %g is outside (-1, 0.5)", base.poisson);
  if (!rc && !(base.friction >= 0.0)) rc = fail(EXIT_INPUT, "--friction must be >= 0");
  if (!rc && !(base.surface_energy >= 0.0))
    rc = fail(EXIT_INPUT, "--surface-energy %g must be >= 0 (0: Hertz, no adhesion)",
              base.surface_energy);
  if (!rc && !(base.steps_per_tc >= 10.0))
    rc = fail(EXIT_INPUT, "--steps-per-tc must be at least 10");
  if (!rc && !(base.hysteresis >= 0.0)) rc = fail(EXIT_INPUT, "--hysteresis must be >= 0");
  if (!rc && base.dtk && !(base.hysteresis > 0.0))
    rc = fail(EXIT_INPUT, "--dtk needs --hysteresis X > 0 (xi_crit = a0/12 X, H18)");
  if (!rc && !(base.force_ext >= 0.0))
    rc = fail(EXIT_INPUT, "--force-ext must be >= 0 N (it points along the tangential velocity)");
  if (!rc && !(base.rest_periods > 0.0)) rc = fail(EXIT_INPUT, "--rest-periods must be > 0");
  if (!rc && !(base.max_roll_periods >= base.rest_periods))
    rc = fail(EXIT_INPUT, "--max-roll-periods must be at least --rest-periods");
  if (!rc) rc = check_list("--speed", &speed, 0.0, true, INFINITY, "> 0 m/s");
  if (!rc) rc = check_list("--angle", &angle, 0.0, true, 90.0, "in (0, 90] degrees");
  if (!rc) rc = check_list("--lambda", &lambda, 0.0, true, INFINITY, "> 0");
  if (!rc) rc = check_list("--ad", &ad, 0.0, false, INFINITY, ">= 0");
  if (!rc) rc = check_list("--stiffness-factor", &fs, 0.0, true, 1.0, "in (0, 1]");
  if (!rc) rc = check_list("--restitution", &rest, 0.0, true, 1.0, "in (0, 1]");
  if (!rc) rc = check_list("--force-hat", &fhat, 0.0, false, INFINITY, ">= 0");
  if (!rc && !wall && angle.n)
    rc = fail(EXIT_INPUT, "--angle is for wall impacts (--kind wall); pairs collide head-on");
  if (!rc && !wall && (base.force_ext > 0.0 || fhat.n || base.at_rest || base.dtk))
    rc = fail(EXIT_INPUT, "--dtk, --force-ext, --force-hat and --at-rest are for wall impacts "
                          "(--kind wall)");
  if (!rc && (base.dtk || base.at_rest) && !(base.surface_energy > 0.0 || ad.n))
    rc = fail(EXIT_INPUT, "--dtk and --at-rest need adhesion: --surface-energy > 0 or --ad");
  if (!rc && fhat.n && !base.dtk)
    rc = fail(EXIT_INPUT, "--force-hat needs --dtk (F_yield = 4 F_C xi_crit / r comes from the "
                          "DTK law); give the force in N with --force-ext instead");
  if (!rc && fhat.n && base.force_ext > 0.0)
    rc = fail(EXIT_INPUT, "give the force either in N (--force-ext) or as F_ext/F_yield "
                          "(--force-hat), not both");
  if (!rc && critical && lambda.n)
    rc = fail(EXIT_INPUT, "--critical-lambda finds lambda: do not give --lambda as well");
  if (!rc && critical && base.at_rest)
    rc = fail(EXIT_INPUT, "--critical-lambda needs impacts: it cannot go with --at-rest");
  if (!rc && critical) rc = parse_critical(critical, &crit_lo, &crit_hi, &crit_tol);
  static double one = 1.0, ninety = 90.0, zero = 0.0;
  double e0 = base.restitution;
  value_list dspeed = {&one, 1}, dangle = {&ninety, 1}, dnone = {NULL, 1}, dfs = {&one, 1};
  value_list drest = {&e0, 1}, dfhat = {&zero, 1};
  const value_list *S = speed.n ? &speed : &dspeed, *A = angle.n ? &angle : &dangle;
  const value_list *L = lambda.n ? &lambda : &dnone, *D = ad.n ? &ad : &dnone;
  const value_list *F = fs.n ? &fs : &dfs, *E = rest.n ? &rest : &drest;
  const value_list *H = fhat.n ? &fhat : &dfhat;
  size_t n = S->n * A->n * L->n * D->n * F->n * E->n * H->n;
  adem_collision_spec *sp = NULL;
  adem_collision_result *res = NULL;
  double *lcrit = NULL;
  char (*lmsg)[ADEM_MSG_MAX] = NULL;
  if (!rc && n > 10000000) rc = fail(EXIT_INPUT, "%zu collisions are too many (at most 1e7)", n);
  if (!rc) {
    sp = malloc(n * sizeof *sp);
    res = critical ? NULL : malloc(n * sizeof *res);
    lcrit = critical ? malloc(n * sizeof *lcrit) : NULL;
    lmsg = critical ? calloc(n, sizeof *lmsg) : NULL;
    if (!sp || (critical ? !lcrit || !lmsg : !res)) rc = fail(EXIT_INTERNAL, "out of memory");
  }
  if (!rc) {
    size_t k = 0;
    for (size_t e = 0; e < E->n; ++e)
      for (size_t h = 0; h < H->n; ++h)
        for (size_t f = 0; f < F->n; ++f)
          for (size_t d = 0; d < D->n; ++d)
            for (size_t l = 0; l < L->n; ++l)
              for (size_t g = 0; g < A->n; ++g)
                for (size_t v = 0; v < S->n; ++v, ++k) {
                  adem_collision_spec c = base;
                  c.restitution = E->v[e];
                  c.force_hat = H->v[h];
                  c.stiffness_factor = F->v[f];
                  c.speed = S->v[v];
                  c.angle = A->v[g] * ADEM_PI / 180.0;
                  if (lambda.n) adem_collide_set_lambda(&c, L->v[l]);
                  if (ad.n) adem_collide_set_ad(&c, D->v[d]);
                  sp[k] = c;
                }
    double t0 = wall_now();
    int nt = threads > 0 ? threads : adem_default_threads();
    if (nt < 1) nt = 1;
    size_t failed = 0, first_failed = n;
    if (critical) {
      for (size_t q = 0; q < n; ++q) {
        adem_error err;
        memset(&err, 0, sizeof err);
        adem_status st = adem_collide_threshold(&sp[q], set_lambda_cli, NULL, crit_lo, crit_hi,
                                                crit_tol, nt, &lcrit[q], &err);
        if (st) {
          lcrit[q] = NAN;
          snprintf(lmsg[q], sizeof lmsg[q], "%s", err.message);
          if (!failed++) first_failed = q;
        }
      }
    } else {
      adem_collide_many(sp, res, n, nt);
      for (size_t q = 0; q < n; ++q)
        if (res[q].status && !failed++) first_failed = q;
    }
    double spent = wall_now() - t0;
    adem_afile af;
    adem_error err;
    FILE *f = stdout;
    if (out) {
      adem_status st = adem_fileio_open(&af, out, &err);
      if (st) rc = fail(exit_code(st), "%s", err.message);
      else f = af.f;
    }
    size_t stuck = 0, undecided = 0, counts[4] = {0};
    if (!rc && critical) {
      fputs("kind,radius_m,size_ratio,density_kg_m3,poisson,restitution,friction,speed_m_s,"
            "angle_deg,Ad,stiffness_factor,gamma_by_H24,dtk,hysteresis,F_hat,lambda_crit,c,"
            "rel_tol,status\n", f);
      for (size_t q = 0; q < n; ++q) {
        const adem_collision_spec *c = &sp[q];
        char status[ADEM_MSG_MAX + 16];
        status_cell(status, sizeof status, isnan(lcrit[q]) ? ADEM_ERR_RUNTIME : ADEM_OK, lmsg[q]);
        double a = adem_collide_ad(c);
        fprintf(f, "%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%d,%d,%.10g,"
                   "%.10g,%.10g,%.10g,%.3g,%s\n",
                wall ? "wall" : "pair", c->radius, wall ? 0.0 : c->size_ratio, c->density,
                c->poisson, c->restitution, c->friction, c->speed, c->angle * 180.0 / ADEM_PI, a,
                c->stiffness_factor, c->keep_gamma ? 0 : 1, c->dtk ? 1 : 0, c->hysteresis,
                c->force_hat, lcrit[q], lcrit[q] / pow(a, 2.5), crit_tol, status);
      }
    } else if (!rc) {
      fputs("kind,radius_m,size_ratio,density_kg_m3,E_Pa,poisson,gamma_J_m2,stiffness_factor,"
            "gamma_by_H24,restitution,friction,speed_m_s,angle_deg,lambda,Ad,e_eff,stuck,"
            "undecided,v_n_in_m_s,v_n_out_m_s,v_t_out_m_s,omega_out_rad_s,contact_duration_s,"
            "max_overlap_m,t_c_s,dt_s,steps,dtk,hysteresis,dtk_modification,at_rest,F_ext_N,"
            "F_hat,outcome,outcome_code,roll_distance_m,t_rest_s,v_end_m_s,xi_crit_m,t_roll_s,"
            "status\n", f);
      for (size_t q = 0; q < n; ++q) {
        const adem_collision_spec *c = &sp[q];
        const adem_collision_result *r = &res[q];
        if (!r->status) {
          stuck += r->stuck;
          undecided += r->undecided;
          counts[r->outcome]++;
        }
        char status[300];
        status_cell(status, sizeof status, r->status, r->message);
        double fy = adem_collide_yield_force(c);
        fprintf(f, "%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%d,%.10g,%.10g,%.10g,%.10g,%.10g,"
                   "%.10g,%.10g,%d,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%llu,",
                wall ? "wall" : "pair", c->radius, wall ? 0.0 : c->size_ratio, c->density,
                c->young, c->poisson, c->surface_energy, c->stiffness_factor, c->keep_gamma ? 0 : 1,
                c->restitution, c->friction, c->speed, c->angle * 180.0 / ADEM_PI,
                adem_collide_lambda(c), adem_collide_ad(c), r->e_eff, r->stuck ? 1 : 0,
                r->undecided ? 1 : 0, r->v_n_in, r->v_n_out, r->v_t_out, r->omega_out,
                r->duration, r->max_overlap, r->t_c, r->dt, (unsigned long long)r->steps);
        fprintf(f, "%d,%.10g,%d,%d,%.10g,%.10g,%s,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%s\n",
                c->dtk ? 1 : 0, c->hysteresis, c->dtk_modification ? 1 : 0, c->at_rest ? 1 : 0,
                r->force_ext, fy > 0.0 ? r->force_ext / fy : NAN,
                adem_collision_outcome_name(r->outcome), (int)r->outcome, r->roll_distance,
                r->t_rest, r->v_end, r->xi_crit, r->t_roll, status);
      }
    }
    if (!rc) {
      if (out) {
        adem_status st = adem_fileio_commit(&af, &err);
        if (st) rc = fail(exit_code(st), "%s", err.message);
      } else if (fflush(stdout) != 0) {
        rc = fail(EXIT_IO, "standard output could not be written");
      }
    }
    if (!rc && critical) {
      fprintf(stderr, "adem: %zu critical lambda%s in %.2f s on %d thread%s%s%s\n", n,
              n == 1 ? "" : "s", spent, nt, nt == 1 ? "" : "s", out ? "; CSV in " : "",
              out ? out : "");
      /* H25 per restitution: the fit over the other lists' combinations */
      size_t per = n / E->n;
      double *x = malloc(per * sizeof *x), *y = malloc(per * sizeof *y);
      for (size_t e = 0; x && y && e < E->n; ++e) {
        for (size_t q = 0; q < per; ++q) {
          x[q] = adem_collide_ad(&sp[e * per + q]);
          y[q] = lcrit[e * per + q];
        }
        double c, k;
        size_t used = adem_collide_fit_power(x, y, per, &c, &k);
        if (used >= 2 && isfinite(k))
          fprintf(stderr, "adem: e = %g: lambda_crit = %.5g Ad^%.4f (%zu points)\n", E->v[e], c,
                  k, used);
      }
      free(x);
      free(y);
    } else if (!rc) {
      fprintf(stderr, "adem: %zu collision%s in %.2f s on %d thread%s: %zu stuck%s", n,
              n == 1 ? "" : "s", spent, nt, nt == 1 ? "" : "s", stuck, undecided ? " (" : "");
      if (undecided) fprintf(stderr, "%zu undecided after the time limit)", undecided);
      fprintf(stderr, ", %zu rebounded", counts[ADEM_OUTCOME_REBOUND]);
      if (base.dtk)
        fprintf(stderr, "; on the wall: %zu rolling, %zu at rest", counts[ADEM_OUTCOME_ROLLING],
                counts[ADEM_OUTCOME_STUCK]);
      fprintf(stderr, "%s%s\n", out ? "; CSV in " : "", out ? out : "");
    }
    if (!rc && failed)
      rc = fail(EXIT_RUNTIME, "%zu %s could not be run; the first (row %zu): %s", failed,
                critical ? (failed == 1 ? "threshold" : "thresholds")
                         : (failed == 1 ? "collision" : "collisions"),
                first_failed + 1, critical ? lmsg[first_failed] : res[first_failed].message);
  }
  free(sp);
  free(res);
  free(lcrit);
  free(lmsg);
  for (size_t k = 0; k < NLISTS; ++k) free(lists[k]->v);
  return rc < 0 ? EXIT_OK : rc;
}

/* ---------------------------------------------------------------- validate */

static const char *const validate_help =
    "Usage:\n"
    "  adem validate [NAME ...] [--out DIR] [--threads N] [--quick]\n"
    "  adem validate --list\n"
    "\n"
    "Reproduces figures of the two source papers (all of them, or the NAMEs given) and checks\n"
    "each paper's claim. For each NAME it writes DIR/NAME.csv (the numbers, with a header\n"
    "naming quantity and unit) and DIR/NAME.png (gnuplot), and for the whole run\n"
    "DIR/summary.md and DIR/summary.json: the claim with its figure, what was measured, notes\n"
    "(parameters the paper omits, data that are not available) and pass/fail.\n"
    "\n"
    "Options:\n"
    "  --out DIR     output folder (default out/validate); created if missing\n"
    "  --threads N   threads (default: OMP_NUM_THREADS or all cores)\n"
    "  --quick       smaller versions (fewer points, coarser bisection), as the tests run them\n"
    "  --list        list the validations and exit\n"
    "  -h, --help    show this help\n"
    "\n"
    "Examples:\n"
    "  adem validate --list\n"
    "  adem validate haervig-fig5 haervig-fig13 --out out/v\n"
    "  adem validate --quick\n"
    "\n"
    "Exit status: 0 every claim holds; 3 at least one validation failed its claim or could not\n"
    "run (summary.md says which); 2 bad option or unknown name; 4 a file could not be written.\n";

static int cmd_validate(int argc, char **argv) {
  const char **names = calloc((size_t)argc + 1, sizeof *names);
  if (!names) return fail(EXIT_INTERNAL, "out of memory");
  int nnames = 0, threads = 0, list = 0, rc = EXIT_OK;
  adem_validation_context ctx = {"out/validate", 0, false};
  for (int i = 0; i < argc && !rc; ++i) {
    const char *a = argv[i], *v;
    int missing = 0;
    if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      fputs(validate_help, stdout);
      free(names);
      return EXIT_OK;
    } else if (strcmp(a, "--quick") == 0) {
      ctx.quick = true;
    } else if (strcmp(a, "--list") == 0) {
      list = 1;
    } else if ((v = option_value(argc, argv, &i, "--out", &missing)) || missing) {
      if (missing || !*v) rc = fail(EXIT_INPUT, "--out needs a folder");
      else ctx.out_dir = v;
    } else if ((v = option_value(argc, argv, &i, "--threads", &missing)) || missing) {
      char *end = NULL;
      long t = missing ? 0 : strtol(v, &end, 10);
      if (missing || !end || *end || t < 1 || t > 4096)
        rc = fail(EXIT_INPUT, "--threads needs a whole number from 1 to 4096, not '%s'",
                  missing ? "" : v);
      else threads = (int)t;
    } else if (a[0] == '-' && a[1] != '\0') {
      rc = fail(EXIT_INPUT, "unknown option %s for adem validate (see: adem validate --help)", a);
    } else if (!adem_validation_find(a)) {
      rc = fail(EXIT_INPUT, "unknown validation '%s'; adem validate --list shows them", a);
    } else {
      names[nnames++] = a;
    }
  }
  if (!rc && list) {
    for (size_t k = 0; k < adem_validation_count(); ++k) {
      const adem_validation *v = adem_validation_at(k);
      printf("%-16s %-34s %s\n", v->name, v->source, v->title);
    }
  } else if (!rc) {
    ctx.nthreads = threads > 0 ? threads : adem_default_threads();
    if (ctx.nthreads < 1) ctx.nthreads = 1;
    adem_error err;
    memset(&err, 0, sizeof err);
    int failed = 0;
    adem_status st = adem_validate_run(names, nnames, &ctx, &failed, &err);
    if (st) {
      rc = fail(exit_code(st), "%s", err.message);
    } else {
      size_t total = nnames ? (size_t)nnames : adem_validation_count();
      fprintf(stderr, "adem: %zu of %zu validation%s passed; summary in %s/summary.md\n",
              total - (size_t)failed, total, total == 1 ? "" : "s", ctx.out_dir);
      rc = failed ? EXIT_RUNTIME : EXIT_OK;
    }
  }
  free(names);
  return rc;
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
    else if (argc > 2 && strcmp(argv[2], "collide") == 0) fputs(collide_help, stdout);
    else if (argc > 2 && strcmp(argv[2], "validate") == 0) fputs(validate_help, stdout);
    else fputs(main_help, stdout);
    return EXIT_OK;
  }
  if (strcmp(cmd, "-V") == 0 || strcmp(cmd, "--version") == 0) {
    printf("adem %s\n", ADEM_VERSION_STRING);
    return EXIT_OK;
  }
  if (strcmp(cmd, "run") == 0) return cmd_run(argc - 2, argv + 2);
  if (strcmp(cmd, "check") == 0) return cmd_check(argc - 2, argv + 2);
  if (strcmp(cmd, "collide") == 0) return cmd_collide(argc - 2, argv + 2);
  if (strcmp(cmd, "validate") == 0) return cmd_validate(argc - 2, argv + 2);
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
  return fail(EXIT_INPUT, "unknown command '%s'; the commands are run, check, collide, validate and "
                          "reference (see: adem --help)", cmd);
}
