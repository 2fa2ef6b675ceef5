/* The library's log messages collected in a buffer, for tests that check what was warned. */
#ifndef ADEM_TEST_LOG_CAPTURE_H
#define ADEM_TEST_LOG_CAPTURE_H

#include <stdio.h>
#include <string.h>

#include "adem/adem.h"

/* The messages logged since the last reset, one a line, each after "W " (warning) or "I ". */
static char logged[8192];

/* Log hook that appends MESSAGE to `logged`. */
static inline void capture(adem_log_level level, const char *message, void *user) {
  (void)user;
  size_t n = strlen(logged);
  snprintf(logged + n, sizeof logged - n, "%s%s\n", level == ADEM_LOG_WARN ? "W " : "I ", message);
}

/* A cmocka setup that empties `logged` and sets capture as the log hook. */
static inline int capture_setup(void **state) {
  (void)state;
  logged[0] = '\0';
  adem_log_set_hook(capture, NULL);
  return 0;
}

/* A cmocka teardown that restores the default log hook. */
static inline int capture_teardown(void **state) {
  (void)state;
  adem_log_set_hook(NULL, NULL);
  return 0;
}

#endif
