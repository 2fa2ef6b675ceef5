/* Reading whole files and composing paths (core): writing files is output/fileio.h. */
#ifndef ADEM_FILES_H
#define ADEM_FILES_H

#include <stddef.h>
#include "adem/adem.h"

/* Reads a whole file into a fresh buffer (NUL-terminated, n excludes the NUL). */
adem_status adem_file_read_all(const char *path, char **data, size_t *n, adem_error *err);
/* The directory part of path ("." when there is none); a fresh string. */
char *adem_file_dirname(const char *path);
/* dir + "/" + name; a fresh string. */
char *adem_file_join(const char *dir, const char *name);

#endif
