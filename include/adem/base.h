/* adem's base: what every other header builds on, and nothing else. Status codes and the error a
 * failing function fills, the log hook, the vector type, the limits of names and messages. */
#ifndef ADEM_BASE_H
#define ADEM_BASE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ADEM_VERSION_STRING "0.1.0"
#define ADEM_NAME_MAX 64
#define ADEM_MSG_MAX 1024

/* Status codes. The numeric values of the first three are the command's exit codes. */
typedef enum adem_status {
  ADEM_OK = 0,
  ADEM_ERR_INPUT = 2,   /* bad case file, bad option, missing file */
  ADEM_ERR_RUNTIME = 3, /* the run went wrong: NaN, runaway overlap, escaped particle */
  ADEM_ERR_IO = 4,      /* a file could not be written */
  ADEM_ERR_NOMEM = 5,
  ADEM_INTERRUPTED = 6 /* SIGINT/SIGTERM asked the run to stop; a checkpoint was written */
} adem_status;

/* Where a failure happened and why: filled by every function that can fail. */
typedef struct adem_error {
  adem_status status;
  char message[ADEM_MSG_MAX];
} adem_error;

/* Log hook: the library never prints; it calls this (default: stderr for warnings). */
typedef enum adem_log_level { ADEM_LOG_INFO = 0,
                              ADEM_LOG_WARN = 1 } adem_log_level;
typedef void adem_log_fn(adem_log_level level, const char *message, void *user);
void adem_log_set_hook(adem_log_fn *fn, void *user);

#if defined(__GNUC__)
#define ADEM_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define ADEM_PRINTF(a, b)
#endif
/* A message through the hook (studies and programs built on the library speak this way too). */
void adem_log(adem_log_level level, const char *fmt, ...) ADEM_PRINTF(2, 3);
/* Fills err (if not NULL) with status and the message, and returns status. */
adem_status adem_error_set(adem_error *err, adem_status status, const char *fmt, ...)
    ADEM_PRINTF(3, 4);

/* A vector in space (m, m/s, N, ...); its algebra is in adem/vec3.h. */
typedef struct adem_vec3 {
  double x, y, z;
} adem_vec3;

#ifdef __cplusplus
}
#endif
#endif
