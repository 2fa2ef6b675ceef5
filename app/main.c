/* The adem command: one file per subcommand (cmd_*.c), the shared parts in cli.c. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "adem/vec3.h"
#include "cli.h"
#ifdef ADEM_HAVE_MPI
#include <mpi.h>
#endif

static const char *const main_help =
    "adem " ADEM_VERSION_STRING ": a Discrete Element Method engine for adhesive and granular spheres\n"
    "(Hertz and simplified JKR contacts, friction, rolling resistance; plane, box and\n"
    "triangle-mesh walls with prescribed motion; pours and staged runs).\n"
    "\n"
    "Usage:\n"
    "  adem run CASE.yaml [--set key.path=value ...] [--out DIR] [--threads N] [--quiet]\n"
    "  adem run --resume DIR/checkpoint [--set time.end=T] [--threads N] [--quiet]\n"
    "  adem check CASE.yaml [--set key.path=value ...]\n"
    "  adem collide [--kind pair|wall] [--speed LIST] [--lambda LIST] [--ad LIST] ...\n"
    "  adem validate [NAME ...] [--out DIR] [--quick] [--list]\n"
    "  adem analyze repose OUTDIR [--zmax Z]\n"
    "  adem analyze fields OUTDIR [--width 2d] [--average x,y] [--time T0:T1] ...\n"
    "  adem calibrate CASE.yaml --vary KEY=LO:HI --target KIND:WHAT=VALUE+-TOL [--jobs N]\n"
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
    "  analyze    measure a run's result: `repose` measures the pile in its last frame (angle\n"
    "             by five measures, height, base radius) and draws its profile; `fields`\n"
    "             makes coarse-grained fields (stress, density, ...) of its frames and\n"
    "             contact frames (see: adem analyze fields --help)\n"
    "  calibrate  vary one case value over a range until a measured target (repose angle,\n"
    "             bulk density, discharge rate, wall load) is met (see: adem calibrate --help)\n"
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

/* ---------------------------------------------------------------- main */

#ifdef ADEM_HAVE_MPI
/* Started by mpirun (Open MPI's launcher sets this): only then is MPI initialised, so that the
 * MPI build's `adem` run by hand or by the tests behaves as the serial one. */
static bool under_mpirun(void) {
  return getenv("OMPI_COMM_WORLD_SIZE") != NULL || getenv("PMIX_RANK") != NULL;
}

/* The other ranks' warnings are rank 0's again (the case's, every process reads it). */
static void quiet_log(adem_log_level level, const char *message, void *user) {
  (void)level;
  (void)message;
  (void)user;
}

/* `adem run` on every process; rank 0 alone reports progress and warnings (and writes,
 * adem_run). Errors still: the process that failed says why. */
static int mpi_run(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) {
    quiet = 1;
    adem_log_set_hook(quiet_log, NULL);
  }
  int rc = cmd_run(argc - 2, argv + 2);
  MPI_Finalize();
  return rc;
}
#endif

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
    else if (argc > 2 && strcmp(argv[2], "analyze") == 0) fputs(analyze_help, stdout);
    else if (argc > 2 && strcmp(argv[2], "calibrate") == 0) fputs(calibrate_help, stdout);
    else fputs(main_help, stdout);
    return EXIT_OK;
  }
  if (strcmp(cmd, "-V") == 0 || strcmp(cmd, "--version") == 0) {
    printf("adem %s\n", ADEM_VERSION_STRING);
    return EXIT_OK;
  }
#ifdef ADEM_HAVE_MPI
  if (strcmp(cmd, "run") == 0 && under_mpirun()) return mpi_run(argc, argv);
#endif
  if (strcmp(cmd, "run") == 0) return cmd_run(argc - 2, argv + 2);
  if (strcmp(cmd, "check") == 0) return cmd_check(argc - 2, argv + 2);
  if (strcmp(cmd, "collide") == 0) return cmd_collide(argc - 2, argv + 2);
  if (strcmp(cmd, "validate") == 0) return cmd_validate(argc - 2, argv + 2);
  if (strcmp(cmd, "reference") == 0) return cmd_reference(argc - 2, argv + 2);
  if (strcmp(cmd, "analyze") == 0) return cmd_analyze(argc - 2, argv + 2);
  if (strcmp(cmd, "calibrate") == 0) return cmd_calibrate(argc - 2, argv + 2);
  return fail(EXIT_INPUT, "unknown command '%s'; the commands are run, check, collide, validate, "
                          "analyze, calibrate and reference (see: adem --help)",
              cmd);
}
