#define _GNU_SOURCE /* memfd_create */
#include "fuzz_common.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

static void no_log(adem_log_level level, const char *message, void *user) {
  (void)level;
  (void)message;
  (void)user;
}

void fuzz_quiet(void) {
  if (!getenv("ADEM_FUZZ_VERBOSE")) adem_log_set_hook(no_log, NULL);
}

enum { SLOTS = 4 };

const char *fuzz_file(int slot, const uint8_t *data, size_t size) {
  static int fd[SLOTS] = {-1, -1, -1, -1};
  static char path[SLOTS][64];
  if (slot < 0 || slot >= SLOTS) return NULL;
  if (fd[slot] < 0) {
    fd[slot] = memfd_create("adem-fuzz", MFD_CLOEXEC);
    if (fd[slot] < 0) {
      perror("memfd_create");
      abort();
    }
    snprintf(path[slot], sizeof path[slot], "/proc/self/fd/%d", fd[slot]);
  }
  if (ftruncate(fd[slot], 0) != 0) abort();
  size_t done = 0;
  while (done < size) {
    ssize_t m = pwrite(fd[slot], data + done, size - done, (off_t)done);
    if (m <= 0) abort();
    done += (size_t)m;
  }
  return path[slot];
}

const char *fuzz_scratch_dir(void) {
  static char dir[256];
  if (!dir[0]) {
    const char *base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : getenv("TMPDIR");
    snprintf(dir, sizeof dir, "%s/adem-fuzz-XXXXXX", base ? base : "/tmp");
    if (!mkdtemp(dir)) {
      perror("mkdtemp");
      abort();
    }
  }
  return dir;
}

void fuzz_check_status(adem_status st, const adem_error *err, const char *what) {
  if (getenv("ADEM_FUZZ_VERBOSE")) fprintf(stderr, "%s: status %d%s%s\n", what, (int)st,
                                           st ? ": " : "", st ? err->message : "");
  if (st == ADEM_OK) return;
  if (st != ADEM_ERR_INPUT && st != ADEM_ERR_NOMEM && st != ADEM_ERR_RUNTIME) {
    fprintf(stderr, "%s: unexpected status %d: %s\n", what, (int)st, err->message);
    abort();
  }
  if (!err->message[0]) {
    fprintf(stderr, "%s: status %d without a message\n", what, (int)st);
    abort();
  }
}
