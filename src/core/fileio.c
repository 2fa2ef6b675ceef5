/* Atomic writes (adem/files.h): a temporary file next to the target, renamed over it when
 * complete and synced. */
#include "adem/files.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "log.h"

static char *str_dup(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

/* Creates and opens a new file named ".BASE.tmp.PID.N" next to path. Returns the fd or -1 with
 * errno set. The name is unique within the process (counter) and between processes (pid); a
 * leftover from a crashed process with a recycled pid is skipped by O_EXCL. */
static int open_temp(const char *path, char **tmp_out) {
  static atomic_uint counter;
  char *dir = adem_file_dirname(path);
  if (!dir) {
    errno = ENOMEM;
    return -1;
  }
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  size_t cap = strlen(dir) + strlen(base) + 64;
  char *tmp = malloc(cap);
  if (!tmp) {
    free(dir);
    errno = ENOMEM;
    return -1;
  }
  int fd = -1;
  for (int attempt = 0; attempt < 1000; ++attempt) {
    unsigned k = atomic_fetch_add(&counter, 1u);
    snprintf(tmp, cap, "%s/.%s.tmp.%ld.%u", dir, base, (long)getpid(), k);
    fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0 || errno != EEXIST) break;
  }
  free(dir);
  if (fd < 0) {
    int e = errno;
    free(tmp);
    errno = e;
    return -1;
  }
  *tmp_out = tmp;
  return fd;
}

/* Makes a rename durable. Some file systems refuse fsync on a directory: that is not an error. */
static int sync_dir_of(const char *path) {
  char *dir = adem_file_dirname(path);
  if (!dir) return ENOMEM;
  int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  free(dir);
  if (fd < 0) return 0;
  int e = 0;
  if (fsync(fd) != 0 && errno != EINVAL && errno != EROFS && errno != ENOTSUP) e = errno;
  close(fd);
  return e;
}

adem_status adem_file_open(adem_afile *af, const char *path, adem_error *err) {
  memset(af, 0, sizeof *af);
  char *tmp = NULL;
  int fd = open_temp(path, &tmp);
  if (fd < 0) return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", path, strerror(errno));
  af->f = fdopen(fd, "wb");
  af->path = str_dup(path);
  af->tmp_path = tmp;
  if (!af->f || !af->path) {
    int e = af->f ? ENOMEM : errno;
    if (af->f) fclose(af->f);
    else close(fd);
    unlink(tmp);
    free(tmp);
    free(af->path);
    memset(af, 0, sizeof *af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", path, strerror(e));
  }
  return ADEM_OK;
}

void adem_file_abort(adem_afile *af) {
  if (af->f) fclose(af->f);
  if (af->tmp_path) unlink(af->tmp_path);
  free(af->tmp_path);
  free(af->path);
  memset(af, 0, sizeof *af);
}

adem_status adem_file_commit(adem_afile *af, adem_error *err) {
  int e = 0;
  if (ferror(af->f)) e = errno ? errno : EIO;
  if (!e && fflush(af->f) != 0) e = errno;
  if (!e && fsync(fileno(af->f)) != 0) e = errno;
  if (fclose(af->f) != 0 && !e) e = errno;
  af->f = NULL;
  if (!e && rename(af->tmp_path, af->path) != 0) e = errno;
  if (e) {
    adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", af->path, strerror(e));
    adem_file_abort(af);
    return ADEM_ERR_IO;
  }
  free(af->tmp_path);
  af->tmp_path = NULL; /* renamed: nothing to remove */
  e = sync_dir_of(af->path);
  adem_status st = ADEM_OK;
  if (e) st = adem_error_set(err, ADEM_ERR_IO, "cannot sync the folder of %s: %s", af->path, strerror(e));
  adem_file_abort(af);
  return st;
}

adem_status adem_file_write_all(const char *path, const void *data, size_t n, adem_error *err) {
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  if (n > 0 && fwrite(data, 1, n, af.f) != n) {
    int e = errno;
    adem_file_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", path, strerror(e ? e : EIO));
  }
  return adem_file_commit(&af, err);
}

adem_status adem_file_temp_next_to(const char *path, char **tmp_path, adem_error *err) {
  int fd = open_temp(path, tmp_path);
  if (fd < 0) return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", path, strerror(errno));
  close(fd);
  return ADEM_OK;
}

adem_status adem_file_rename_into_place(const char *tmp, const char *path, adem_error *err) {
  if (rename(tmp, path) != 0)
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", path, strerror(errno));
  int e = sync_dir_of(path);
  if (e) return adem_error_set(err, ADEM_ERR_IO, "cannot sync the folder of %s: %s", path, strerror(e));
  return ADEM_OK;
}

static adem_status folder_error(adem_error *err, const char *dir, int e) {
  return adem_error_set(err, ADEM_ERR_INPUT, "output folder %s cannot be written: %s", dir, strerror(e));
}

adem_status adem_file_mkdir_p(const char *path, adem_error *err) {
  if (!path || !*path) return adem_error_set(err, ADEM_ERR_INPUT, "output folder is empty");
  char *p = str_dup(path);
  if (!p) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  /* Create each prefix in turn; an existing prefix must be a directory. */
  for (char *s = p + 1;; ++s) {
    if (*s != '/' && *s != '\0') continue;
    char saved = *s;
    *s = '\0';
    if (mkdir(p, 0777) != 0) {
      int e = errno;
      struct stat st;
      if (e != EEXIST) {
        /* mkdir on an existing path may fail with EACCES/EROFS before EEXIST: accept a dir. */
        if (stat(p, &st) != 0 || !S_ISDIR(st.st_mode)) {
          free(p);
          return folder_error(err, path, e);
        }
      } else if (stat(p, &st) != 0 || !S_ISDIR(st.st_mode)) {
        free(p);
        return folder_error(err, path, ENOTDIR);
      }
    }
    *s = saved;
    if (saved == '\0') break;
    while (s[1] == '/') ++s; /* collapse "a//b" */
  }
  free(p);
  return ADEM_OK;
}

adem_status adem_file_check_writable(const char *dir, adem_error *err) {
  char *probe = adem_file_join(dir, "write_probe");
  if (!probe) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  char *tmp = NULL;
  int fd = open_temp(probe, &tmp);
  int e = errno;
  free(probe);
  if (fd < 0) return folder_error(err, dir, e);
  close(fd);
  unlink(tmp);
  free(tmp);
  return ADEM_OK;
}
