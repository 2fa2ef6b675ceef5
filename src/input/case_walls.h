/* Building `walls[].type: cylinder` and `plate` (case_walls.c). */
#ifndef ADEM_CASE_WALLS_H
#define ADEM_CASE_WALLS_H

#include <stdbool.h>

#include "case_yaml.h"
#include "insert.h"

/* Adds the wall of mapping m as planes of another shape (a cylinder and its caps NAME.cap0,
 * NAME.cap1, or a plate); *reach: a bound on the distance of its points from its `point`. */
adem_status adem_case_curved_wall(case_ctx *ctx, const map_cursor *m, const char *name, int mat,
                                  bool cylinder, double *reach);

/* particles[].fill_level of a random set filling reg: the solid fraction of reg that makes a bed
 * of `packing` up to `level` (of reg's volume below that height) or of `fraction` of reg. */
adem_status adem_case_fill_level(case_ctx *ctx, const map_cursor *fl, const adem_region *reg,
                                 double *fraction);

#endif
