/* What every command of adem shares (cli.c). The command is the only code of adem that prints or
 * exits; it uses only the public API (include/adem). */
#ifndef ADEM_APP_CLI_H
#define ADEM_APP_CLI_H

#include <signal.h>
#include <stdio.h>

#include "adem/run.h"

enum {
  EXIT_OK = 0,
  EXIT_INTERNAL = 1,
  EXIT_INPUT = 2,
  EXIT_RUNTIME = 3,
  EXIT_IO = 4,
};

extern int quiet;
extern int stderr_tty;
extern volatile sig_atomic_t stop_signal;

typedef struct cli_options {
  const char *case_path;
  const char *resume;
  const char *out;
  const char **sets;
  int nsets;
  int threads;
  int help;
} cli_options;

typedef struct progress_state {
  double last_line; /* wall time of the last plain line */
} progress_state;

/* Messages: the library's log hook, and "adem: MESSAGE" on standard error with the exit code. */
void log_hook(adem_log_level level, const char *message, void *user);
void end_progress_line(void);
int fail(int code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
int exit_code(adem_status st);
/* SIGINT and SIGTERM set stop_signal; a run then stops cleanly with a checkpoint. */
void install_signals(void);
/* The progress line (about once a second while a run goes on). */
void on_progress(const adem_progress *p, void *user);
/* "--name value" or "--name=value": the value, or NULL when argv[*i] is not that option. */
const char *option_value(int argc, char **argv, int *i, const char *name, int *missing);
/* The options of run and check. */
int parse_options(int argc, char **argv, cli_options *o, int allow_run, const char *cmd);
double cli_now(void);
/* OUTDIR/checkpoint for a folder, or the path itself. */
char *checkpoint_path(const char *arg);

/* The commands (cmd_*.c), with their help texts. */
int cmd_run(int argc, char **argv);
int cmd_check(int argc, char **argv);
int cmd_collide(int argc, char **argv);
int cmd_validate(int argc, char **argv);
int cmd_reference(int argc, char **argv);
int cmd_analyze(int argc, char **argv);
int cmd_analyze_fields(int argc, char **argv); /* adem analyze fields */
int cmd_calibrate(int argc, char **argv);
extern const char *const run_help, *const check_help, *const collide_help, *const validate_help,
                                                                               *const analyze_help, *const calibrate_help;

#endif
