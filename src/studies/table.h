/* Not installed: what the validations share to write their figures (src/studies/validate.c):
 * paths in the output folder, plots of their CSV and tables written to CSV atomically. */
#ifndef ADEM_STUDIES_TABLE_H
#define ADEM_STUDIES_TABLE_H

#include <stddef.h>

#include "adem/base.h"
#include "adem/studies.h"

/* DIR/NAME.EXT; a fresh string. */
char *adem_validation_path(const adem_validation_context *ctx, const char *name, const char *ext);

/* DIR/NAME.png drawn by gnuplot from `body`, in which the gnuplot variable f holds the path of
 * DIR/NAME.csv. */
adem_status adem_validation_plot(const adem_validation_context *ctx, const char *name, int width,
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

#endif
