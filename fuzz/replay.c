/* Replays inputs through a fuzz target's entry function without libFuzzer (any C compiler):
 *   replay_TARGET FILE_OR_FOLDER ...
 * A folder stands for every file in it (sorted by name; README and dot files skipped). An input
 * that crashes or trips a sanitizer ends the process as it would end the fuzzer. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz_common.h"

static int replay_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) {
    fprintf(stderr, "replay: cannot read %s\n", path);
    return 1;
  }
  size_t cap = 4096, n = 0;
  unsigned char *buf = malloc(cap);
  for (;;) {
    if (!buf) {
      fclose(f);
      fprintf(stderr, "replay: out of memory reading %s\n", path);
      return 1;
    }
    n += fread(buf + n, 1, cap - n, f);
    if (n < cap) break;
    unsigned char *b = realloc(buf, 2 * cap);
    if (!b) free(buf);
    buf = b;
    cap *= 2;
  }
  fclose(f);
  /* An exact-size copy, so that reading past the input is caught as in the fuzzer. */
  unsigned char *exact = malloc(n ? n : 1);
  if (!exact) {
    free(buf);
    return 1;
  }
  memcpy(exact, buf, n);
  free(buf);
  LLVMFuzzerTestOneInput(exact, n);
  free(exact);
  return 0;
}

static int by_name(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}

static int skipped(const char *name) { return name[0] == '.' || !strncmp(name, "README", 6); }

int main(int argc, char **argv) {
  LLVMFuzzerInitialize(&argc, &argv);
  int failed = 0, count = 0;
  for (int i = 1; i < argc; ++i) {
    struct stat st;
    if (stat(argv[i], &st) != 0) {
      fprintf(stderr, "replay: no such file or folder: %s\n", argv[i]);
      failed = 1;
      continue;
    }
    if (!S_ISDIR(st.st_mode)) {
      failed |= replay_file(argv[i]);
      ++count;
      continue;
    }
    DIR *d = opendir(argv[i]);
    if (!d) {
      failed = 1;
      continue;
    }
    char **names = NULL;
    size_t n = 0;
    for (struct dirent *e; (e = readdir(d));) {
      if (skipped(e->d_name)) continue;
      char **nn = realloc(names, (n + 1) * sizeof *nn);
      if (!nn) break;
      names = nn;
      size_t len = strlen(argv[i]) + strlen(e->d_name) + 2;
      names[n] = malloc(len);
      if (!names[n]) break;
      snprintf(names[n++], len, "%s/%s", argv[i], e->d_name);
    }
    closedir(d);
    if (n) qsort(names, n, sizeof *names, by_name);
    for (size_t k = 0; k < n; ++k) {
      failed |= replay_file(names[k]);
      ++count;
      free(names[k]);
    }
    free(names);
  }
  printf("replayed %d input%s without a crash\n", count, count == 1 ? "" : "s");
  return failed;
}
