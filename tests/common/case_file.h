/* The tests' cases live as YAML files in tests/cases/ and are loaded by the loader itself:
 * adem_case_load_file with --set overrides (a test that varies a case says so as `adem run --set`
 * would). case_file_text gives a case's text for the tests that write it out or run the command on
 * it. Include after cmocka.h; the target defines ADEM_SOURCE_DIR. */
#ifndef ADEM_TEST_CASE_FILE_H
#define ADEM_TEST_CASE_FILE_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"

#ifndef ADEM_SOURCE_DIR
#error "case_file.h needs ADEM_SOURCE_DIR (the test target defines it)"
#endif

/* The path of tests/cases/NAME.yaml (a static buffer, valid until the next call). */
static inline const char *case_file_path(const char *name) {
  static char path[1024];
  snprintf(path, sizeof path, "%s/tests/cases/%s.yaml", ADEM_SOURCE_DIR, name);
  return path;
}

/* The text of tests/cases/NAME.yaml, read once and kept for the program's life. */
static inline const char *case_file_text(const char *name) {
  enum { SLOTS = 16 };
  static char names[SLOTS][64];
  static char *texts[SLOTS];
  int k = 0;
  for (; k < SLOTS && texts[k]; ++k)
    if (!strcmp(names[k], name)) return texts[k];
  if (k == SLOTS) fail_msg("case_file_text: more than %d cases in one test", SLOTS);
  FILE *f = fopen(case_file_path(name), "rb");
  if (!f) fail_msg("case_file_text: cannot open %s", case_file_path(name));
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *s = malloc((size_t)n + 1);
  assert_non_null(s);
  assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
  fclose(f);
  s[n] = '\0';
  snprintf(names[k], sizeof names[k], "%s", name);
  texts[k] = s;
  return s;
}

/* tests/cases/NAME.yaml loaded with the overrides SETS (as `adem run --set`); fails the test
 * with the loader's message if it is refused. */
static inline adem_case *case_file_load(const char *name, const char *const *sets, int nsets) {
  adem_case *c = NULL;
  adem_error err;
  memset(&err, 0, sizeof err);
  if (adem_case_load_file(case_file_path(name), sets, nsets, &c, &err) != ADEM_OK)
    fail_msg("%s: %s", name, err.message);
  return c;
}

#endif
