/* Outlets and mass flows (docs/outlets-and-flow.md).
 *
 * An outlet removes, every `interval` (a whole number of steps, counted from step 0), the
 * particles whose centre is inside a region of output.regions or beyond a face of the domain box
 * (which the escape check then lets them cross); it counts them and their mass. The checks are
 * run events like pour batches (adem_stages_next_step, adem_stages_events): after the outputs of
 * their step and before its checkpoint, on the whole system (split over MPI processes, the run
 * gathers it on every process at such a step and splits it again after a removal).
 *
 * A mass flow is a CSV column: the mass through a plane (each particle's side is kept by id and
 * compared at every CSV row and outlet check, mass crossing along the normal counted positive, in
 * id order), or the rate of change of a region's mass; rates over a window of CSV rows.
 *
 * Their state (counts, masses, sides, the rows of the window) is in checkpoints. */
#ifndef ADEM_OUTLETS_H
#define ADEM_OUTLETS_H

#include <stdint.h>

#include "adem/case.h"
#include "stream.h"

struct case_ctx;
struct map_cursor;
/* Reads `outlets` and `output.mass_flow` (after output.regions and the domain; case_yaml.h). */
adem_status adem_outlets_read(struct case_ctx *ctx, const struct map_cursor *root,
                              const struct map_cursor *out);
void adem_outlets_free(adem_outlets *o);

/* The next step after `step` with an outlet check (UINT64_MAX: none). */
uint64_t adem_outlets_next_step(const adem_outlets *o, double dt, uint64_t step);
/* The checks due at the world's step: flows brought up to date, particles removed. */
adem_status adem_outlets_run(adem_case *c, adem_error *err);

/* CSV columns: how many, and the name of column k (NAME_deleted_count, ...). */
int adem_outlets_columns(const adem_outlets *o);
void adem_outlets_column_name(const adem_outlets *o, int k, char *buf, size_t n);
/* The values of a CSV row now (at the whole world's step), the flows brought up to date. */
adem_status adem_outlets_sample(adem_case *c, double *values, adem_error *err);
/* A log line per outlet: how many particles it removed and their mass. */
void adem_outlets_log(const adem_case *c);

void adem_outlets_save(adem_writer *wr, const adem_outlets *o);
adem_status adem_outlets_load(adem_reader *rd, adem_outlets *o, adem_error *err);

#endif
