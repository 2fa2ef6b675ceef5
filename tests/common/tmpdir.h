/* A scratch folder for a test program: made in a group setup, removed with what it holds in the
 * group teardown. Include after cmocka.h. */
#ifndef ADEM_TEST_TMPDIR_H
#define ADEM_TEST_TMPDIR_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[256];

/* Makes a fresh folder /tmp/PREFIX_XXXXXX, its name in tmpdir; 0 on success, -1 otherwise. */
static inline int tmpdir_make(const char *prefix) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/%s_XXXXXX", prefix);
  return mkdtemp(tmpdir) ? 0 : -1;
}

/* Removes tmpdir and everything in it; 0 on success, -1 otherwise. */
static inline int tmpdir_remove(void) {
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  return system(cmd) == 0 ? 0 : -1;
}

/* A cmocka group teardown that only removes tmpdir. */
static inline int tmpdir_teardown(void **state) {
  (void)state;
  return tmpdir_remove();
}

/* tmpdir/NAME as a fresh string (free it). */
static inline char *path_in_tmp(const char *name) {
  size_t n = strlen(tmpdir) + strlen(name) + 2;
  char *p = malloc(n);
  assert_non_null(p);
  snprintf(p, n, "%s/%s", tmpdir, name);
  return p;
}

/* Whether PATH exists and is not empty. */
static inline int file_exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && st.st_size > 0;
}

#endif
