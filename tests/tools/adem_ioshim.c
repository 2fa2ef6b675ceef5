/* LD_PRELOAD shim for scripts/killtest.sh: slows, logs, kills inside, or fails with ENOSPC the
 * writes adem makes to files under one folder. Nothing else is touched.
 *   ADEM_SHIM_DIR=/abs/out   only files whose real path starts with this folder
 *   ADEM_SHIM_DELAY_US=N     sleep N us in each write(2) and fflush, N/10 in each fwrite (a
 *                            checkpoint is hundreds of them), 5 N in each fsync and rename
 *   ADEM_SHIM_LOG=FILE       a line when a call starts, "<us since start> <call> <kind> <path>",
 *                            and one when it returns, with "+<call>": a log that ends on a
 *                            start line was killed inside that call
 *   ADEM_SHIM_KILL=KIND:N    SIGKILL this process in the N-th call (1-based) on a file of KIND
 *                            (frame, mesh, pvd, csv, checkpoint): after half of an fwrite's
 *                            bytes (flushed), before a write(2), fflush, fsync or rename
 *   ADEM_SHIM_ENOSPC=BYTES   after BYTES written under the folder, writes write what fits and
 *                            then fail with ENOSPC (fflush, fsync too once the budget is gone)
 *   ADEM_SHIM_ENOSPC_KIND=K  count and fail only writes to files of kind K (csv: a row cut by
 *                            a full disk)
 * glibc's stdio flushes its buffer through an internal write that no shim sees: fwrite and
 * fflush are caught where adem calls them, which is where every file's bytes leave adem. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static ssize_t (*real_write)(int, const void *, size_t);
static size_t (*real_fwrite)(const void *, size_t, size_t, FILE *);
static int (*real_fflush)(FILE *);
static int (*real_fsync)(int);
static int (*real_rename)(const char *, const char *);

static int ready;
static char dir[PATH_MAX];
static size_t dir_len;
static long delay_us;
static int log_fd = -1;
static char kill_kind[32];
static long kill_at, kill_count;
static long long enospc_budget = -1; /* < 0: off */
static char enospc_kind[32];
static struct timespec t_start;

static void setup(void) {
  if (ready) return;
  ready = 1;
  real_write = (ssize_t(*)(int, const void *, size_t))dlsym(RTLD_NEXT, "write");
  real_fwrite = (size_t(*)(const void *, size_t, size_t, FILE *))dlsym(RTLD_NEXT, "fwrite");
  real_fflush = (int (*)(FILE *))dlsym(RTLD_NEXT, "fflush");
  real_fsync = (int (*)(int))dlsym(RTLD_NEXT, "fsync");
  real_rename = (int (*)(const char *, const char *))dlsym(RTLD_NEXT, "rename");
  clock_gettime(CLOCK_MONOTONIC, &t_start);
  const char *s = getenv("ADEM_SHIM_DIR");
  if (s && realpath(s, dir)) dir_len = strlen(dir);
  else if (s) snprintf(dir, sizeof dir, "%s", s), dir_len = strlen(dir);
  if ((s = getenv("ADEM_SHIM_DELAY_US"))) delay_us = atol(s);
  if ((s = getenv("ADEM_SHIM_LOG"))) log_fd = open(s, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if ((s = getenv("ADEM_SHIM_KILL"))) {
    const char *colon = strchr(s, ':');
    if (colon && (size_t)(colon - s) < sizeof kill_kind) {
      memcpy(kill_kind, s, (size_t)(colon - s));
      kill_at = atol(colon + 1);
    }
  }
  if ((s = getenv("ADEM_SHIM_ENOSPC"))) enospc_budget = atoll(s);
  if ((s = getenv("ADEM_SHIM_ENOSPC_KIND"))) snprintf(enospc_kind, sizeof enospc_kind, "%s", s);
}

/* The kind of an output file from its name (temporary names keep the target's name inside). */
static const char *kind_of(const char *path) {
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  if (!strcmp(path, dir) || !strcmp(base, "frames")) return "folder"; /* fsync of a folder */
  if (strstr(base, "checkpoint")) return "checkpoint";
  if (strstr(base, "timeseries.csv")) return "csv";
  if (strstr(base, ".pvd")) return "pvd";
  if (strstr(base, "mesh_") && strstr(base, ".vtu")) return "mesh";
  if (strstr(base, ".vtu")) return "frame";
  return "other";
}

/* Fills path for fd; 1 if the file is under the watched folder. */
static int watched_fd(int fd, char *path, size_t cap) {
  if (!dir_len || fd < 0) return 0;
  char link[64];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  ssize_t n = readlink(link, path, cap - 1);
  if (n <= 0) return 0;
  path[n] = '\0';
  return strncmp(path, dir, dir_len) == 0 && (path[dir_len] == '/' || path[dir_len] == '\0');
}

static int watched_path(const char *p, char *path, size_t cap) {
  if (!dir_len || !p) return 0;
  char *slash = strrchr(p, '/');
  char parent[PATH_MAX];
  if (!slash) snprintf(parent, sizeof parent, ".");
  else snprintf(parent, sizeof parent, "%.*s", (int)(slash - p), p);
  char real[PATH_MAX - 256];
  if (!realpath(parent, real)) return 0;
  snprintf(path, cap, "%s/%s", real, slash ? slash + 1 : p);
  return strncmp(path, dir, dir_len) == 0 && (path[dir_len] == '/' || path[dir_len] == '\0');
}

static void note(const char *call, const char *path) {
  if (log_fd < 0) return;
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  long long us = (long long)(t.tv_sec - t_start.tv_sec) * 1000000LL + (t.tv_nsec - t_start.tv_nsec) / 1000;
  char line[PATH_MAX + 96];
  int n = snprintf(line, sizeof line, "%lld %s %s %s\n", us, call, kind_of(path), path);
  if (n > 0) real_write(log_fd, line, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1);
}

static void pause_us(long us) {
  if (us <= 0) return;
  struct timespec ts = {us / 1000000, (us % 1000000) * 1000};
  nanosleep(&ts, NULL);
}

/* 1 when this call is the one to be killed in. */
static int kill_due(const char *path) {
  if (!kill_at || strcmp(kind_of(path), kill_kind) != 0) return 0;
  return ++kill_count == kill_at;
}

static void die(const char *call, const char *path) {
  note("SIGKILL-in", path);
  (void)call;
  kill(getpid(), SIGKILL);
}

/* Bytes of n that the disk still takes (all when the budget is off or is for another kind). */
static size_t budget_take(const char *path, size_t n) {
  if (enospc_budget < 0 || (enospc_kind[0] && strcmp(kind_of(path), enospc_kind) != 0)) return n;
  size_t k = (long long)n <= enospc_budget ? n : (size_t)enospc_budget;
  enospc_budget -= (long long)k;
  return k;
}

ssize_t write(int fd, const void *buf, size_t n) {
  setup();
  char path[PATH_MAX];
  if (!watched_fd(fd, path, sizeof path)) return real_write(fd, buf, n);
  note("write", path);
  pause_us(delay_us);
  /* A SIGKILL does not tear a small write(2) to a regular file: it lands before or after it. */
  if (kill_due(path)) die("write", path);
  size_t k = budget_take(path, n);
  if (k == 0 && n > 0) {
    errno = ENOSPC;
    return -1;
  }
  ssize_t r = real_write(fd, buf, k);
  note("+write", path);
  return r;
}

size_t fwrite(const void *buf, size_t size, size_t count, FILE *f) {
  setup();
  char path[PATH_MAX];
  if (!watched_fd(fileno(f), path, sizeof path)) return real_fwrite(buf, size, count, f);
  note("fwrite", path);
  pause_us(delay_us / 10);
  size_t n = size * count;
  if (kill_due(path)) {
    real_fwrite(buf, 1, n / 2, f);
    real_fflush(f);
    die("fwrite", path);
  }
  size_t k = budget_take(path, n);
  if (k < n) {
    if (size > 0) real_fwrite(buf, 1, k, f);
    errno = ENOSPC;
    return size ? k / size : 0;
  }
  size_t r = real_fwrite(buf, size, count, f);
  note("+fwrite", path);
  return r;
}

int fflush(FILE *f) {
  setup();
  char path[PATH_MAX];
  if (!f || !watched_fd(fileno(f), path, sizeof path)) return real_fflush(f);
  note("fflush", path);
  pause_us(delay_us);
  if (kill_due(path)) die("fflush", path);
  if (enospc_budget == 0 && budget_take(path, 1) == 0) {
    errno = ENOSPC;
    return EOF;
  }
  int r = real_fflush(f);
  note("+fflush", path);
  return r;
}

int fsync(int fd) {
  setup();
  char path[PATH_MAX];
  if (!watched_fd(fd, path, sizeof path)) return real_fsync(fd);
  note("fsync", path);
  pause_us(5 * delay_us);
  if (kill_due(path)) die("fsync", path);
  if (enospc_budget == 0 && budget_take(path, 1) == 0) {
    errno = ENOSPC;
    return -1;
  }
  int r = real_fsync(fd);
  note("+fsync", path);
  return r;
}

int rename(const char *from, const char *to) {
  setup();
  char path[PATH_MAX];
  if (!watched_path(to, path, sizeof path)) return real_rename(from, to);
  note("rename", path);
  pause_us(5 * delay_us);
  if (kill_due(path)) die("rename", path);
  int r = real_rename(from, to);
  note("+rename", path);
  return r;
}
