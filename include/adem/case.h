/* Case files: YAML read with libyaml and validated against one schema table. */
#ifndef ADEM_CASE_H
#define ADEM_CASE_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "adem/base.h"
#include "adem/world.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ADEM_PATH_MAX 4096
#define ADEM_TRACK_MAX 32 /* particles output.track may name */

/* What a run writes and how often. Intervals are simulated seconds; 0 switches that output off. */
typedef struct adem_output_settings {
  char dir[ADEM_PATH_MAX];
  double frame_interval;      /* VTU frames + PVD */
  double csv_interval;        /* CSV time series rows */
  double checkpoint_interval; /* checkpoint rewrites */
  bool plot;                  /* true: write an energy-time PNG with gnuplot at the end */
  bool plot_loads;            /* true: write a PNG of the wall loads against time at the end */
  bool pieces;                /* true: split over processes, a frame is a .pvtu of one piece each */
  int contacts_every;         /* output.contacts: contact frames with every N-th frame (0: off) */
  bool contacts_csv;          /* true: each contact frame also as CSV */
  /* output.track: particles whose rolling torque, angular velocity and distance from their
   * initial centre get CSV columns. */
  int ntrack;
  uint64_t track[ADEM_TRACK_MAX]; /* stable ids */
} adem_output_settings;

/* Particles poured while running (src/input/insert.h) and consecutive stages (src/input/stages.h). */
typedef struct adem_pours adem_pours;
typedef struct adem_stages adem_stages;
/* Named regions (src/input/insert.h): output.regions, and the regions random sets were filled in. */
typedef struct adem_regions adem_regions;
typedef struct adem_outlets adem_outlets;
/* A run-until condition (src/input/until.h). */
typedef struct adem_until adem_until;

/* A loaded case: the world, ready to prepare, plus what the run needs. */
typedef struct adem_case {
  char path[ADEM_PATH_MAX];     /* file it came from, for messages */
  char base_dir[ADEM_PATH_MAX]; /* absolute folder that relative paths in it start from */
  char name[ADEM_NAME_MAX];
  char *source; /* the YAML text as read (kept for checkpoints) */
  char **sets;  /* --set overrides applied on top of the text */
  int nsets;
  adem_world *world;
  double end_time;      /* s */
  bool dt_auto;         /* true when time.step was "auto" */
  double dt_user_ratio; /* user dt / proposed dt (> 1 means too large) */
  adem_step_estimate estimate;
  adem_memory_estimate memory; /* of every particle, the pours' totals included */
  double memory_limit;         /* bytes the run may use: limits.max_memory, or what is available */
  bool memory_auto;            /* true when memory_limit is what the machine has available */
  adem_output_settings output;
  uint64_t seed;
  adem_pours *pours;     /* NULL: nothing is poured */
  adem_stages *stages;   /* NULL: one stage, the case as written */
  adem_until *until;     /* time.until (NULL: the run lasts until time.end) */
  adem_regions *regions; /* output.regions (NULL: none): CSV columns of count and mass */
  adem_regions *fills;   /* regions of the random particle sets, for `adem check` */
  adem_outlets *outlets; /* outlets and output.mass_flow (NULL: none; input/outlets.h) */
  /* What adem_run has written up to the current step (kept in checkpoints, so that a resumed
   * run, even one given a later end time, continues the files as one run would have). */
  uint64_t frames_written; /* frames at t = 0 and at every frame interval (not one written
                              only because the run ended at this step) */
  bool csv_last_extra;     /* true: this step's CSV row was written only because the run ended */
} adem_case;

/* Reads, validates and builds a case. The sets are "key.path=value" overrides (adem run --set). */
adem_status adem_case_load_file(const char *path, const char *const *sets, int nsets,
                                adem_case **out, adem_error *err);
adem_status adem_case_load_string(const char *text, const char *name_for_messages,
                                  const char *const *sets, int nsets, adem_case **out,
                                  adem_error *err);
/* As adem_case_load_string, with relative file paths of the case (mesh files) taken from
 * base_dir (NULL: the folder of name_for_messages, or the working folder). */
adem_status adem_case_load_string_at(const char *text, const char *name_for_messages,
                                     const char *base_dir, const char *const *sets, int nsets,
                                     adem_case **out, adem_error *err);
void adem_case_free(adem_case *c);
/* The volume (m^3) of the output.regions region called name; ADEM_ERR_INPUT naming the regions
 * there are when there is none of that name. */
adem_status adem_case_region_volume(const adem_case *c, const char *name, double *volume,
                                    adem_error *err);
/* The case text with the sets written into it, as YAML (comments are lost); *out a fresh
 * string. Only the sets' syntax and paths are checked here, not the case (load it to check). */
adem_status adem_case_text_with_sets(const char *text, const char *name_for_messages,
                                     const char *const *sets, int nsets, char **out,
                                     adem_error *err);

/* Adds the triangles of an STL file (ASCII or binary) to the world as one mesh wall, one group
 * per solid (docs/meshes.md names them), moving with velocity
 * (non-zero needs tf->own_vertices); tf NULL: the default transform. */
adem_status adem_world_add_stl(adem_world *w, const char *path, const adem_mesh_transform *tf,
                               const char *name, adem_vec3 velocity, adem_error *err);

/* The case-file reference (every key, type, unit, default, range, doc) as Markdown. */
void adem_case_write_reference(FILE *f);

#ifdef __cplusplus
}
#endif
#endif
