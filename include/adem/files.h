/* Files, for programs and studies built on the library: reading a whole file, composing paths,
 * and writing atomically. Every file adem writes goes to a temporary name next to its target and
 * is renamed over it when complete and synced, so that no output is ever seen half-written.
 * (src/core/files.c reads, src/core/fileio.c writes.) */
#ifndef ADEM_FILES_H
#define ADEM_FILES_H

#include <stddef.h>
#include <stdio.h>

#include "adem/base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A file being written atomically. Write through f (stdio), then commit or abort. */
typedef struct adem_afile {
  FILE *f;
  char *path;     /* the target */
  char *tmp_path; /* the temporary file next to it */
} adem_afile;

/* Creates a uniquely named temporary file in the target's directory. */
adem_status adem_file_open(adem_afile *af, const char *path, adem_error *err);
/* Flushes, syncs, closes and renames over the target, then syncs the directory. On failure the
 * target is left as it was and the temporary file is removed. Frees af in every case. */
adem_status adem_file_commit(adem_afile *af, adem_error *err);
/* Drops the temporary file; the target is untouched. Safe on a zeroed or committed af. */
void adem_file_abort(adem_afile *af);

/* Writes a whole buffer atomically. */
adem_status adem_file_write_all(const char *path, const void *data, size_t n, adem_error *err);

/* Makes a unique temporary path next to path (the file is created empty, mode 0666 & ~umask).
 * Used for files written by other programs (gnuplot) that are then renamed into place. */
adem_status adem_file_temp_next_to(const char *path, char **tmp_path, adem_error *err);
/* Renames tmp over path and syncs the directory. */
adem_status adem_file_rename_into_place(const char *tmp, const char *path, adem_error *err);

/* mkdir -p. The status is ADEM_ERR_INPUT: a folder we cannot create is a bad option. */
adem_status adem_file_mkdir_p(const char *path, adem_error *err);
/* Checks that files can be created in dir (by creating and removing one). ADEM_ERR_INPUT with
 * "output folder X cannot be written: <reason>" when not. */
adem_status adem_file_check_writable(const char *dir, adem_error *err);

/* Reads a whole file into a fresh buffer (NUL-terminated, n excludes the NUL). */
adem_status adem_file_read_all(const char *path, char **data, size_t *n, adem_error *err);
/* The directory part of path ("." when there is none); a fresh string. */
char *adem_file_dirname(const char *path);
/* dir + "/" + name; a fresh string. */
char *adem_file_join(const char *dir, const char *name);

#ifdef __cplusplus
}
#endif
#endif
