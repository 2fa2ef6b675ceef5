/* Paper reproductions (`adem validate`): each writes DIR/NAME.csv and DIR/NAME.png and reports
 * the paper's claim, the figure measured here and pass/fail; adem_validate_run collects them in
 * DIR/summary.json and DIR/summary.md. */
#ifndef ADEM_VALIDATE_H
#define ADEM_VALIDATE_H

#include <stdbool.h>
#include <stddef.h>
#include "adem/adem.h"

typedef struct adem_validation_context {
  const char *out_dir;
  int nthreads;   /* threads the validation may use (collisions in bulk run in parallel) */
  bool quick;     /* a smaller version, for the test suite */
} adem_validation_context;

typedef struct adem_validation_report {
  char claim[1024];    /* what the paper says, with its figure or section */
  char measured[1024]; /* the figure measured here, with numbers */
  char notes[1024];    /* parameters the paper omits and the choice made, missing data, ... */
  bool pass;
} adem_validation_report;

typedef adem_status adem_validation_fn(const adem_validation_context *ctx, const char *name,
                                       adem_validation_report *report, adem_error *err);

typedef struct adem_validation {
  const char *name;   /* "haervig-fig5" */
  const char *source; /* "Haervig et al. 2017, Fig. 5" */
  const char *title;  /* one line: what is plotted */
  adem_validation_fn *run;
} adem_validation;

size_t adem_validation_count(void);
const adem_validation *adem_validation_at(size_t i);
const adem_validation *adem_validation_find(const char *name);

/* Runs the named validations (all when n == 0) and writes the summaries. *failed counts the
 * validations whose claim did not hold. */
adem_status adem_validate_run(const char *const *names, int n, const adem_validation_context *ctx,
                              int *failed, adem_error *err);

/* DIR/NAME.EXT; a fresh string. */
char *adem_validate_path(const adem_validation_context *ctx, const char *name, const char *ext);

/* DIR/NAME.png drawn by gnuplot from `body`, in which the gnuplot variable f holds the path of
 * DIR/NAME.csv. */
adem_status adem_validate_plot(const adem_validation_context *ctx, const char *name, int width,
                               int height, const char *body, adem_error *err);

/* A table written to CSV atomically: header names quantity and unit ("v_impact_m_s,e_eff"). */
typedef struct adem_table {
  size_t ncols, nrows, cap;
  char *header;
  double *data; /* row-major */
} adem_table;
adem_status adem_table_init(adem_table *t, const char *header);
adem_status adem_table_add(adem_table *t, const double *row);
adem_status adem_table_write_csv(const adem_table *t, const char *path, adem_error *err);
void adem_table_free(adem_table *t);

/* Validations of each paper (validate_haervig.c, validate_irazabal.c). */
extern const adem_validation adem_validations_haervig[];
extern const size_t adem_validations_haervig_count;
extern const adem_validation adem_validations_irazabal[];
extern const size_t adem_validations_irazabal_count;

#endif
