/* What every command of adem shares: messages and exit codes, signals, the progress line and
 * option parsing. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "adem/run.h"
#include "adem/vec3.h"
#include "cli.h"
#include <signal.h>
#include <sys/stat.h>
#include <time.h>

/* ---------------------------------------------------------------- messages */

int quiet = 0;
static int progress_on_line = 0; /* a progress line without newline is on the terminal */
int stderr_tty = 0;

void end_progress_line(void) {
  if (progress_on_line) {
    fputc('\n', stderr);
    progress_on_line = 0;
  }
}

void log_hook(adem_log_level level, const char *message, void *user) {
  (void)user;
  if (level == ADEM_LOG_INFO && quiet) return;
  end_progress_line();
  fprintf(stderr, "adem: %s%s\n", level == ADEM_LOG_WARN ? "warning: " : "", message);
}

int fail(int code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
int fail(int code, const char *fmt, ...) {
  end_progress_line();
  va_list ap;
  va_start(ap, fmt);
  fputs("adem: error: ", stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
  return code;
}

int exit_code(adem_status st) {
  switch (st) {
    case ADEM_OK: return EXIT_OK;
    case ADEM_ERR_INPUT: return EXIT_INPUT;
    case ADEM_ERR_RUNTIME: return EXIT_RUNTIME;
    case ADEM_ERR_IO: return EXIT_IO;
    default: return EXIT_INTERNAL;
  }
}

/* ---------------------------------------------------------------- progress */

volatile sig_atomic_t stop_signal = 0;

static void on_signal(int sig) { stop_signal = sig; }

void install_signals(void) {
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


void on_progress(const adem_progress *p, void *user) {
  progress_state *ps = user;
  if (quiet) return;
  double pct = p->total_steps ? 100.0 * (double)p->step / (double)p->total_steps : 100.0;
  char eta[32], eta_text[96];
  format_duration(eta, sizeof eta, p->eta_seconds);
  /* The ETA comes from the last half minute's rate: say when that rate will not last. */
  static const char *const why[] = {"", "just started", "contacts rising", "particles added"};
  const char *most = p->may_end_early ? " at most" : ""; /* time.until may end it sooner */
  if (p->eta_seconds >= 0.0 && p->eta_rough > 0 && p->eta_rough < 4)
    snprintf(eta_text, sizeof eta_text, "ETA ~%s%s (rough: %s)", eta, most, why[p->eta_rough]);
  else
    snprintf(eta_text, sizeof eta_text, "ETA %s%s", eta, most);
  int dec = time_decimals(p->end_time);
  char line[448];
  snprintf(line, sizeof line, "t=%.*f/%.*f s  %5.1f%%  %.0f steps/s  %zu contacts  %s%s%s", dec,
           p->time, dec, p->end_time, pct, p->steps_per_second, p->contacts, eta_text,
           p->until[0] ? "  " : "", p->until);
  if (stderr_tty) {
    /* \033[K clears what a longer previous line left. */
    fprintf(stderr, "\r %s\033[K", line);
    fflush(stderr);
    progress_on_line = 1;
  } else if (p->wall_seconds - ps->last_line >= 10.0 || p->final) {
    fprintf(stderr, "adem: %s\n", line);
    ps->last_line = p->wall_seconds;
  }
}

/* ---------------------------------------------------------------- options */


/* "--name value" or "--name=value": the value, or NULL when this is not that option. */
const char *option_value(int argc, char **argv, int *i, const char *name, int *missing) {
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

int parse_options(int argc, char **argv, cli_options *o, int allow_run, const char *cmd) {
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
