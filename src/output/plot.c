/* PNG plots through gnuplot, written to a temporary file and renamed into place. */
#include "adem/internal/plot.h"

#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "adem/files.h"
#include "log.h"

extern char **environ;

char *adem_plot_quote(const char *s, char *buf, size_t n) {
  size_t k = 0;
  if (n < 3) {
    if (n) buf[0] = '\0';
    return buf;
  }
  buf[k++] = '\'';
  for (; *s && k + 3 < n; ++s) {
    if (*s == '\n' || *s == '\r') continue;
    if (*s == '\'') buf[k++] = '\'';
    buf[k++] = *s;
  }
  buf[k++] = '\'';
  buf[k] = '\0';
  return buf;
}

/* Runs "gnuplot script" with its errors into errfile. Returns the exit status, 127 when gnuplot
 * cannot be started, or -1 on another failure. */
static int run_gnuplot(const char *script, const char *errfile) {
  posix_spawn_file_actions_t fa;
  if (posix_spawn_file_actions_init(&fa) != 0) return -1;
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, errfile, O_WRONLY | O_TRUNC, 0);
  char *argv[] = {"gnuplot", (char *)script, NULL};
  pid_t pid;
  int rc = posix_spawnp(&pid, "gnuplot", &fa, NULL, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return rc == ENOENT ? 127 : -1;
  int status;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

adem_status adem_plot_png(const char *png_path, int width, int height, const char *body,
                          adem_error *err) {
  char *png_tmp = NULL, *script_path = NULL, *err_path = NULL;
  adem_status st = adem_file_temp_next_to(png_path, &png_tmp, err);
  if (st) return st;
  adem_error e2;
  if (adem_file_temp_next_to(png_path, &script_path, &e2) ||
      adem_file_temp_next_to(png_path, &err_path, &e2)) {
    unlink(png_tmp);
    free(png_tmp);
    if (script_path) {
      unlink(script_path);
      free(script_path);
    }
    return adem_error_set(err, e2.status, "%s", e2.message);
  }
  size_t qn = 2 * strlen(png_tmp) + 3;
  char *quoted = malloc(qn);
  size_t n = strlen(body) + qn + 512;
  char *script = malloc(n);
  int rc = -1;
  if (quoted && script) {
    snprintf(script, n,
             "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
             "  set terminal pngcairo size %d,%d noenhanced\n"
             "} else {\n"
             "  set terminal png size %d,%d noenhanced\n"
             "}\n"
             "set output %s\n"
             "set datafile separator ','\n"
             "%s\n",
             width, height, width, height, adem_plot_quote(png_tmp, quoted, qn), body);
    adem_error we;
    if (adem_file_write_all(script_path, script, strlen(script), &we) == ADEM_OK)
      rc = run_gnuplot(script_path, err_path);
  }
  free(quoted);
  free(script);
  if (rc == 0) {
    st = adem_file_rename_into_place(png_tmp, png_path, err);
  } else if (rc == 127) {
    adem_log(ADEM_LOG_WARN, "gnuplot was not found: %s is not drawn", png_path);
  } else {
    /* Say what gnuplot said: its error output, on one line. */
    char *msg = NULL;
    size_t len = 0;
    adem_error ignored;
    if (adem_file_read_all(err_path, &msg, &len, &ignored) == ADEM_OK)
      for (char *c = msg; *c; ++c)
        if (*c == '\n') *c = ' ';
    adem_log(ADEM_LOG_WARN, "gnuplot failed (status %d): %s is not drawn%s%.300s", rc, png_path,
             msg && *msg ? ": " : "", msg ? msg : "");
    free(msg);
  }
  if (rc != 0 || st) unlink(png_tmp);
  unlink(script_path);
  unlink(err_path);
  free(png_tmp);
  free(script_path);
  free(err_path);
  return st;
}
