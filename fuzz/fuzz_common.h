/* What the fuzz targets share: a quiet log, inputs handed to path-based readers through an
 * in-memory file, and a check that a failure is reported the way adem reports failures. */
#ifndef ADEM_FUZZ_COMMON_H
#define ADEM_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>

#include "adem/adem.h"

/* The libFuzzer entry points; the replay driver (replay.c) calls the same ones. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

/* Silences adem's log (warnings about bad input are expected by the thousand). */
void fuzz_quiet(void);

/* A file whose contents are replaced on each call: an anonymous in-memory file (memfd) named by
 * /proc/self/fd/N, so that readers that take a path read exactly these bytes. Returns the path
 * (static storage) or NULL. */
const char *fuzz_file(int slot, const uint8_t *data, size_t size);

/* A fresh empty folder under /dev/shm (or TMPDIR) for targets that write; the same one on every
 * call of a process. */
const char *fuzz_scratch_dir(void);

/* Aborts (a finding) unless st is a status a reader may return for bad input, with a message
 * when it is not ADEM_OK. */
void fuzz_check_status(adem_status st, const adem_error *err, const char *what);

#endif
