/* PNG plots drawn by gnuplot. A missing gnuplot only costs the picture: a warning, not an error. */
#ifndef ADEM_PLOT_H
#define ADEM_PLOT_H

#include "adem/adem.h"

/* Runs gnuplot with `body` (set labels, plot commands, ...) after a PNG terminal of width x height
 * pixels whose output goes to a temporary file renamed to png_path when gnuplot succeeds. */
adem_status adem_plot_png(const char *png_path, int width, int height, const char *body,
                          adem_error *err);

/* Writes s into buf as a single-quoted gnuplot string (quotes doubled); returns buf. */
char *adem_plot_quote(const char *s, char *buf, size_t n);

#endif
