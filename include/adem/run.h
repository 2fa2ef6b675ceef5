/* Running a case: stepping, output, checkpoints, progress. */
#ifndef ADEM_RUN_H
#define ADEM_RUN_H

#include <stdbool.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "adem/base.h"
#include "adem/case.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct adem_progress {
  double time, end_time;
  uint64_t step, total_steps;
  double wall_seconds;     /* since the run (or resume) started */
  double eta_seconds;      /* from the recent rate (adem_eta); < 0 while unknown */
  int eta_rough;           /* adem_eta_rough_why: why the ETA may be far off (0: steady) */
  double steps_per_second; /* the recent rate: over the last ADEM_ETA_WINDOW wall seconds */
  size_t contacts;
  size_t particles;
  bool may_end_early; /* true: a run-until condition may end the run before end_time (the ETA
                         is then to end_time: at most) */
  bool final;         /* true: the run's last step (its end time, or a condition met) */
  char until[160];    /* the run-until condition against its threshold at its last check
                         ("until: E_k 4.1e-10 > 1e-10 J/particle"); "" without one */
} adem_progress;
typedef void adem_progress_fn(const adem_progress *p, void *user);

/* The time a run still needs, from its recent rate: the steps done over the last
 * ADEM_ETA_WINDOW seconds of wall time (not since the start: a pour's free fall runs faster
 * than the dense bed that follows). While the number of contacts or particles still grows, each
 * step will cost more than the recent ones did and the estimate is flagged rough. Feed it
 * samples (wall time, step, contacts, particles) in time order. */
#define ADEM_ETA_WINDOW 30.0  /* s of wall time the rate is taken over */
#define ADEM_ETA_SAMPLES 128  /* samples kept (about one a second) */
#define ADEM_ETA_SETTLING 3.0 /* s: less history than this is rough too */
#define ADEM_ETA_GROWTH 0.05  /* contacts (or particles) up by more than this fraction over the \
                                 window: rough */
typedef enum adem_eta_rough_why {
  ADEM_ETA_STEADY = 0,
  ADEM_ETA_STARTING = 1, /* less than ADEM_ETA_SETTLING s of history */
  ADEM_ETA_CONTACTS = 2, /* the contact count is still rising */
  ADEM_ETA_PARTICLES = 3 /* particles are being added (a pour) */
} adem_eta_rough_why;
typedef struct adem_eta {
  int n, head; /* samples held; index of the oldest */
  double wall[ADEM_ETA_SAMPLES];
  uint64_t step[ADEM_ETA_SAMPLES];
  double contacts[ADEM_ETA_SAMPLES], particles[ADEM_ETA_SAMPLES];
} adem_eta;
void adem_eta_init(adem_eta *e);
void adem_eta_add(adem_eta *e, double wall_seconds, uint64_t step, size_t contacts,
                  size_t particles);
/* Steps per wall second over the window; 0 while unknown. */
double adem_eta_rate(const adem_eta *e);
/* Wall seconds to reach total_steps at the recent rate (< 0 while unknown); *rough (may be NULL)
 * says why it may be far off (adem_eta_rough_why). */
double adem_eta_seconds(const adem_eta *e, uint64_t total_steps, int *rough);

typedef struct adem_run_options {
  int nthreads;               /* 0: leave as is */
  adem_progress_fn *progress; /* called about once a second; may be NULL */
  void *progress_user;
  volatile sig_atomic_t *stop_flag; /* set non-zero (from a signal handler) to stop cleanly */
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
/* The same, changing what a resumed run may change ("key.path=value" as adem run --set):
 * time.end (a later end continues the run bit for bit as if it had had that end from the start:
 * outputs on the same steps, the default escape domain widened as that run's) and the output
 * intervals output.frame_interval, output.csv_interval, output.checkpoint_interval (from the
 * resume on). Any other key is ADEM_ERR_INPUT naming the keys that may change; so is an end
 * before the checkpoint's time. The sets are kept with the case (a later resume keeps them). */
adem_status adem_checkpoint_read_with(const char *path, const char *const *sets, int nsets,
                                      adem_case **out, adem_error *err);
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
