/* Running the built adem command (ADEM_BINARY) from a test, with its files in tmpdir: write a
 * case, run `adem ARGS` with the output captured, read the CSV it wrote. Include after cmocka.h. */
#ifndef ADEM_TEST_CLI_RUN_H
#define ADEM_TEST_CLI_RUN_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "case_text.h"
#include "tmpdir.h"

/* Writes N bytes of DATA to tmpdir/NAME; returns the path (free it). */
static inline char *write_file(const char *name, const void *data, size_t n) {
  char *p = path_in_tmp(name);
  FILE *f = fopen(p, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(data, 1, n, f), n);
  fclose(f);
  return p;
}

/* Writes TEXT to tmpdir/NAME; returns the path (free it). */
static inline char *write_case(const char *name, const char *text) {
  return write_file(name, text, strlen(text));
}

/* Runs `adem ARGS` (printf-style) with stdout and stderr captured; returns the exit status, *out
 * the text (a static buffer, valid until the next call); prints the command and its first line. */
static inline int adem(char **out, const char *fmt, ...) {
  char args[4096], cmd[8192];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(args, sizeof args, fmt, ap);
  va_end(ap);
  char *log = path_in_tmp("output.txt");
  snprintf(cmd, sizeof cmd, "'%s' %s > '%s' 2>&1 < /dev/null", ADEM_BINARY, args, log);
  int status = system(cmd);
  assert_true(status != -1 && WIFEXITED(status));
  FILE *f = fopen(log, "r");
  assert_non_null(f);
  static char buf[1 << 17];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  buf[n] = '\0';
  fclose(f);
  free(log);
  *out = buf;
  printf("# adem %s -> %d\n#   %.*s\n", args, WEXITSTATUS(status), (int)strcspn(buf, "\n"), buf);
  /* adem's own exit codes are below 10; anything above is a crash or a sanitizer's abort (134):
   * show all of it */
  if (WEXITSTATUS(status) >= 10) printf("# full output:\n%s\n", buf);
  return WEXITSTATUS(status);
}

/* Cell NAME of CSV row ROW (1 = first data row) of PATH, as text (a static buffer). */
static inline const char *csv_cell(const char *path, int row, const char *name) {
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  static char line[1 << 14], cell[256];
  int col = -1;
  assert_non_null(fgets(line, sizeof line, f));
  int k = 0;
  for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), ++k)
    if (!strcmp(tok, name)) col = k;
  if (col < 0) fail_msg("no column %s in %s", name, path);
  for (int r = 1; r <= row; ++r) assert_non_null(fgets(line, sizeof line, f));
  fclose(f);
  cell[0] = '\0';
  k = 0;
  for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), ++k)
    if (k == col) snprintf(cell, sizeof cell, "%s", tok);
  return cell;
}

/* Cell NAME of CSV row ROW (1 = first data row) of PATH, as a number. */
static inline double csv_value(const char *path, int row, const char *name) {
  return strtod(csv_cell(path, row, name), NULL);
}

#endif
