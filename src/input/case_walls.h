/* Building `walls[].type: cylinder` and `plate` (case_walls.c). */
#ifndef ADEM_CASE_WALLS_H
#define ADEM_CASE_WALLS_H

#include <stdbool.h>

#include "case_yaml.h"

/* Adds the wall of mapping m as planes of another shape (a cylinder and its caps NAME.cap0,
 * NAME.cap1, or a plate); *reach: a bound on the distance of its points from its `point`. */
adem_status adem_case_curved_wall(case_ctx *ctx, const map_cursor *m, const char *name, int mat,
                                  bool cylinder, double *reach);

#endif
