/* Staged runs: consecutive stages, each with a duration and changes written as case-file paths
 * (the --set syntax: `materials.ballast.friction: 0`). Stage k's configuration is the case loaded
 * again with the changes of stages 0..k applied on top of it (so a value stays until a later
 * stage changes it); the loader validates it like any case. At the step where a stage begins,
 * what may change is carried into the running world: materials and interactions (the pair table
 * is derived again), gravity, group forces, walls (on/off, material, position, motion), limits,
 * the neighbour skin and the output intervals. Particles never change.
 *
 * A wall whose motion a stage changes starts the new motion where it is at the stage's start, and
 * the motion's times count from there. A checkpoint records the stage in force; reading it loads
 * the case (stage 0) and replays the stage starts up to that stage, so a resumed run continues
 * bit for bit. */
#ifndef ADEM_STAGES_H
#define ADEM_STAGES_H

#include <stdbool.h>
#include <stdint.h>

#include "adem/case.h"
#include "adem/world.h"
#include "motion.h"
#include "stream.h"
#include "until.h"
#include "walls.h"

/* What a stage sets in the running world, taken from its configuration. */

typedef struct adem_stage_config {
  adem_material_def *materials;
  int nmaterials;
  adem_interaction_def *interactions;
  int ninteractions;
  adem_vec3 *group_force;
  int ngroups;
  adem_vec3 gravity;
  adem_plane_setting *planes;
  int nplanes;
  adem_mesh_setting *meshes;
  int nmeshes;
  double frame_interval, csv_interval, checkpoint_interval;
  double max_overlap_ratio, skin_fraction;
  double dt_proposed; /* the step the stage's materials propose (for a warning) */
} adem_stage_config;

typedef struct adem_stage {
  char name[ADEM_NAME_MAX];
  double duration;   /* s; < 0: until time.end (the last stage only); with `until`: the most */
  adem_until *until; /* stages[].until, or NULL */
  char where[640];   /* file:line:column of the stage, for messages */
  char **sets;       /* "path=value" */
  int nsets;
  adem_stage_config config;
} adem_stage;

struct adem_stages {
  int n;
  int current; /* stage in force */
  adem_stage *s;
  adem_stage_config base; /* the case as written, before stage 0 */
  /* When stages began: start[k] for k < nrecorded (the stages begun so far, and the one a met
   * condition has just set going). Later stages are planned from their durations: from the
   * start (no stage cut short: round(sum of the earlier durations / dt)), or from the last
   * recorded start. In checkpoints. */
  uint64_t *start;
  int nrecorded;
  bool cut; /* a stage has been ended by its `until` */
};

/* ---- building (case.c) ---- */

adem_status adem_stages_add(adem_stages **s, const char *name, double duration, const char *where,
                            adem_error *err);
/* Gives the last stage a run-until condition (copied). */
adem_status adem_stages_set_until(adem_stages *s, const adem_until_def *def, adem_error *err);
/* Adds "path=value" to the last stage. */
adem_status adem_stages_add_set(adem_stages *s, const char *set, adem_error *err);
/* NULL if a stage may set the key path; otherwise why not (a static string). */
const char *adem_stages_check_path(const char *path);
void adem_stages_free(adem_stages *s);
void adem_stage_config_free(adem_stage_config *g);
/* Puts stage k in force at its start. live: during a run (energy balance kept, neighbour lists
 * rebuilt); otherwise the configuration only (at load, or replaying for a checkpoint). The case
 * loader builds every stage's configuration (case.c) and puts stage 0 in force with this. */
adem_status adem_stages_enter(adem_case *c, int k, bool live, adem_error *err);


/* ---- running (run.c, checkpoint.c) ---- */

/* Step at which stage k begins: the recorded one for a stage begun, else planned from the
 * durations (round(sum of the earlier durations / dt) when no stage has been cut short). */
uint64_t adem_stages_start_step(const adem_case *c, int k);
/* Smallest step > step at which a stage begins or a pour batch is due (UINT64_MAX: none). */
uint64_t adem_stages_next_step(const adem_case *c, uint64_t step);
/* Everything due at the world's current step: the start of a stage, then pour batches. */
adem_status adem_stages_events(adem_case *c, adem_error *err);
/* True when some stage (or the case) writes that output: 0 frames, 1 CSV rows, 2 checkpoints. */
bool adem_stages_output_on(const adem_case *c, int which);
int adem_stages_current(const adem_case *c);
/* Puts stage `current` in force in a case just read from a checkpoint (no rebuild, no energy
 * change: the checkpoint holds that state). */
adem_status adem_stages_resume(adem_case *c, int current, adem_error *err);

/* ---- run-until conditions (time.until, stages[].until) ---- */

typedef enum adem_until_outcome {
  ADEM_UNTIL_NOTHING = 0,
  ADEM_UNTIL_STAGE_ENDS = 1, /* the stage in force ends: the next begins at this step */
  ADEM_UNTIL_RUN_ENDS = 2    /* time.until, or the last stage's condition: the run ends here */
} adem_until_outcome;
/* Smallest step > step at which a condition in force is checked (UINT64_MAX: none). */
uint64_t adem_stages_until_next(const adem_case *c, uint64_t step);
/* The checks due at the world's current step (before its outputs): what ends; msg says what
 * was met. A stage that ends records the next one's start at this step (adem_stages_events
 * then puts it in force). */
adem_until_outcome adem_stages_until(adem_case *c, char *msg, size_t n);
/* Whether the run has ended on a condition (a checkpoint of a finished run); msg says when. */
bool adem_stages_ended(const adem_case *c, char *msg, size_t n);
/* The run-until condition that can end the run or the current stage against its threshold, for
 * the progress line (adem_until_status); "" when there is none. */
void adem_stages_until_status(const adem_case *c, char *buf, size_t n);
/* The start steps and the conditions' state, for checkpoints. */
void adem_stages_save(adem_writer *wr, const adem_case *c);
adem_status adem_stages_load(adem_reader *rd, adem_case *c, adem_error *err);

#endif
