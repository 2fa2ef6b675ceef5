/* Running a case: stepping, output, checkpoints, progress. */
#ifndef ADEM_RUN_H
#define ADEM_RUN_H

#include <signal.h>
#include <stdio.h>
#include "adem/adem.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct adem_progress {
  double time, end_time;
  uint64_t step, total_steps;
  double wall_seconds;     /* since the run (or resume) started */
  double eta_seconds;      /* < 0 while unknown */
  double steps_per_second;
  size_t contacts;
} adem_progress;
typedef void adem_progress_fn(const adem_progress *p, void *user);

typedef struct adem_run_options {
  int nthreads;                        /* 0: leave as is */
  adem_progress_fn *progress;          /* called about once a second; may be NULL */
  void *progress_user;
  volatile sig_atomic_t *stop_flag;    /* set non-zero (from a signal handler) to stop cleanly */
} adem_run_options;
adem_run_options adem_default_run_options(void);

/* Steps from the start to the case's end time at the world's step. */
uint64_t adem_case_total_steps(const adem_case *c);

/* Runs the case to its end time, writing frames, CSV and checkpoints into c->output.dir.
 * On ADEM_INTERRUPTED a checkpoint has been written. On ADEM_ERR_RUNTIME the files already
 * written are kept and err names the particle and time. */
adem_status adem_run(adem_case *c, const adem_run_options *opt, adem_error *err);

/* What a loaded, prepared case will do, written as text to f (`adem check`): particles, walls,
 * pours, stages, every material pair's effective values and laws (with the JKR quantities of
 * H7-H10, H24 and the Tabor parameter), the time step, the outputs, memory and disk. */
adem_status adem_case_report(const adem_case *c, FILE *f, adem_error *err);

/* Checkpoints: the case text and the whole dynamic state, written atomically. */
adem_status adem_checkpoint_write(const adem_case *c, const char *path, adem_error *err);
/* Rebuilds the case from a checkpoint so that adem_run continues bit for bit. */
adem_status adem_checkpoint_read(const char *path, adem_case **out, adem_error *err);
/* A world made through the API (adem/world.h), set-up and state, written atomically; reading it
 * gives a world that steps on bit for bit as the one written would have. Only prepared worlds
 * (or worlds before their first step) can be written. */
adem_status adem_world_checkpoint_write(const adem_world *w, const char *path, adem_error *err);
adem_status adem_world_checkpoint_read(const char *path, adem_world **out, adem_error *err);

/* The same from the bytes of a checkpoint file in memory; path only names it in messages. */
adem_status adem_checkpoint_read_bytes(const char *data, size_t len, const char *path,
                                       adem_case **out, adem_error *err);

#ifdef __cplusplus
}
#endif
#endif
