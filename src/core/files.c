/* Reading whole files and composing paths (writing atomically: fileio.c beside it). */
#include "adem/files.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "adem/world.h"
#include "log.h"

static char *str_dup(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

char *adem_file_dirname(const char *path) {
  const char *slash = strrchr(path, '/');
  if (!slash) return str_dup(".");
  if (slash == path) return str_dup("/");
  size_t n = (size_t)(slash - path);
  char *d = malloc(n + 1);
  if (!d) return NULL;
  memcpy(d, path, n);
  d[n] = '\0';
  return d;
}

char *adem_file_join(const char *dir, const char *name) {
  size_t nd = strlen(dir), nn = strlen(name);
  int slash = nd > 0 && dir[nd - 1] != '/';
  char *s = malloc(nd + (size_t)slash + nn + 1);
  if (!s) return NULL;
  memcpy(s, dir, nd);
  if (slash) s[nd] = '/';
  memcpy(s + nd + (size_t)slash, name, nn + 1);
  return s;
}

adem_status adem_file_read_all(const char *path, char **data, size_t *n, adem_error *err) {
  *data = NULL;
  *n = 0;
  FILE *f = fopen(path, "rb");
  if (!f) return adem_error_set(err, ADEM_ERR_INPUT, "cannot read %s: %s", path, strerror(errno));
  size_t cap = 1 << 16, len = 0;
  char *buf = malloc(cap + 1);
  while (buf) {
    size_t got = fread(buf + len, 1, cap - len, f);
    len += got;
    if (len < cap) break;
    char *nb = realloc(buf, 2 * cap + 1);
    if (!nb) {
      free(buf);
      buf = NULL;
      break;
    }
    buf = nb;
    cap *= 2;
  }
  int failed = !buf || ferror(f);
  int e = errno;
  fclose(f);
  if (!buf) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory reading %s", path);
  if (failed) {
    free(buf);
    return adem_error_set(err, ADEM_ERR_INPUT, "cannot read %s: %s", path, strerror(e ? e : EIO));
  }
  buf[len] = '\0';
  *data = buf;
  *n = len;
  return ADEM_OK;
}


/* adem_memory_available (include/adem/world.h): the kernel's estimate of what a new program can
 * use without swapping, else the free pages. */
double adem_memory_available(void) {
  FILE *f = fopen("/proc/meminfo", "r");
  if (f) {
    char line[256];
    double kib = -1.0;
    while (fgets(line, sizeof line, f))
      if (sscanf(line, "MemAvailable: %lf kB", &kib) == 1) break;
    fclose(f);
    if (kib >= 0.0) return kib * 1024.0;
  }
#if defined(_SC_AVPHYS_PAGES) && defined(_SC_PAGESIZE)
  long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  if (pages > 0 && size > 0) return (double)pages * (double)size;
#endif
  return 0.0;
}
