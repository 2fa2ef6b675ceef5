/* Not installed: PNG plots drawn by gnuplot, shared by the output and run layers, the studies and
 * the command (src/output/plot.c). A missing gnuplot only costs the picture: a warning. */
#ifndef ADEM_INTERNAL_PLOT_H
#define ADEM_INTERNAL_PLOT_H

#include <stddef.h>

#include "adem/base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Runs gnuplot with `body` (set labels, plot commands, ...) after a PNG terminal of width x height
 * pixels whose output goes to a temporary file renamed to png_path when gnuplot succeeds. */
adem_status adem_plot_png(const char *png_path, int width, int height, const char *body,
                          adem_error *err);

/* Writes s into buf as a single-quoted gnuplot string (quotes doubled); returns buf. */
char *adem_plot_quote(const char *s, char *buf, size_t n);


#ifdef __cplusplus
}
#endif
#endif
