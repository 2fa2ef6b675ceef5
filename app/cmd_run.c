/* adem run */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "adem/case.h"
#include "adem/run.h"
#include "adem/world.h"
#include "adem/vec3.h"
#include "cli.h"

const char *const run_help =
    "Usage:\n"
    "  adem run CASE.yaml [--set key.path=value ...] [--out DIR] [--threads N] [--quiet]\n"
    "  adem run --resume DIR/checkpoint [--set time.end=T] [--set output.X_interval=S]\n"
    "                                   [--threads N] [--quiet]\n"
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
    "  loads.png                    wall loads against time, if output.plot_loads is true;\n"
    "                               both plots are drawn from the CSV however the run ends\n"
    "                               (done, Ctrl-C/SIGTERM, a failure, a resumed run's end)\n"
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
    "                        and the result is bit for bit that of an uninterrupted run. With\n"
    "                        --set time.end=T a finished (or stopped) run goes on to a later\n"
    "                        end, bit for bit as a run that had that end from the start (its\n"
    "                        frames and rows continue on the same steps); --set may also change\n"
    "                        output.frame_interval, output.csv_interval and\n"
    "                        output.checkpoint_interval from the resume on, nothing else\n"
    "  -q, --quiet           print only warnings and errors, no progress\n"
    "  -h, --help            show this help\n"
    "\n"
    "Progress goes to standard error: one updating line on a terminal, otherwise a line about\n"
    "every 10 s. The steps/s and the ETA are those of the last 30 s of wall time; the ETA is\n"
    "marked rough (ETA ~M:SS) in the first seconds and while the contact count or the number\n"
    "of particles still rises (a filling bed gets slower). Ctrl-C (or SIGTERM) stops the run\n"
    "after the current few steps and writes a checkpoint (and the plots).\n"
    "\n"
    "Examples:\n"
    "  adem run cases/pour.yaml\n"
    "  adem run cases/pour.yaml --set time.end=0.5 --set output.frame_interval=0.01 --out out/s\n"
    "  adem run --resume out/s/checkpoint --threads 4\n"
    "  adem run --resume out/s --set time.end=1.0      # go on to t = 1 s\n"
    "\n"
    "Exit status: 0 done; 2 bad input or output folder; 3 the run failed (the message names the\n"
    "particle and the time; the output written before is kept); 4 a file could not be written;\n"
    "130/143 interrupted by SIGINT/SIGTERM with a checkpoint written; 1 out of memory.\n";

/* ---------------------------------------------------------------- run */

double cli_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* DIR or DIR/checkpoint -> the checkpoint file. */
char *checkpoint_path(const char *arg) {
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

int cmd_run(int argc, char **argv) {
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
    if (o.case_path || o.out) {
      free(o.sets);
      return fail(EXIT_INPUT, "--resume continues the case stored in the checkpoint, in the "
                              "checkpoint's folder: it takes no case file or --out (--set may "
                              "change time.end and the output intervals)");
    }
    char *path = checkpoint_path(o.resume);
    if (!path) {
      free(o.sets);
      return fail(EXIT_INTERNAL, "out of memory");
    }
    st = adem_checkpoint_read_with(path, (const char *const *)o.sets, o.nsets, &c, &err);
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
    fprintf(stderr, "adem: %s %s: %zu particles, dt = %.6g s%s, end time %.6g s (%llu steps%s), "
                    "output in %s\n",
            o.resume ? "resuming" : "running", c->name, adem_world_particle_count(w),
            adem_world_dt(w), c->dt_auto ? " (auto)" : "", c->end_time,
            (unsigned long long)adem_case_total_steps(c),
            c->until ? ", fewer if time.until is met" : "", c->output.dir);
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
  double t0 = cli_now();
  st = adem_run(c, &opt, &err);
  double spent = cli_now() - t0;
  end_progress_line();
  /* steps that may have carried a particle through a mesh wall, however the run ended */
  const adem_tunnel_event *te = adem_world_tunnel_first(w);
  if (te)
    fprintf(stderr,
            "adem: warning: tunnelling: %llu times a particle moved more than its radius in one "
            "step next to a mesh wall (first: particle id %llu at t = %.9g s, at (%.6g, %.6g, "
            "%.6g) m); a smaller time.step avoids it\n",
            (unsigned long long)adem_world_tunnel_count(w), (unsigned long long)te->id, te->time,
            te->pos.x, te->pos.y, te->pos.z);

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
