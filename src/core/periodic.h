/* Periodic boundaries: which axes wrap, the box along them, the minimum image of a separation and
 * the wrapping of a position. Positions are wrapped into [lo, lo + len) at every neighbour build
 * (neighbors.c); between builds a particle may stand up to half the skin beyond a face. */
#ifndef ADEM_PERIODIC_H
#define ADEM_PERIODIC_H

#include <math.h>
#include <stdint.h>

#include "adem/vec3.h"

typedef struct adem_periodic {
  unsigned axes;        /* bit d set: axis d (x, y, z) wraps; 0: no periodic axis */
  double lo[3], len[3]; /* lower face and length of the box along each axis */
} adem_periodic;

/* Periodic images a particle's centre has crossed along x, y, z: the unwrapped centre is
 * pos + image len. */
typedef struct adem_image {
  int32_t n[3];
} adem_image;

static inline double adem_periodic_component(double d, double len) {
  /* |d| < len + skin < 1.5 len for a pair of the neighbour list (positions are wrapped at the
   * build, the box is at least 2 (diameter + skin)), so one rounding brings it to [-len/2, len/2];
   * d - len is exact there (Sterbenz). A separation within half the box is left untouched. */
  if (fabs(d) > 0.5 * len) d -= len * nearbyint(d / len);
  return d;
}

/* The minimum-image separation: d with whole box lengths taken off along the periodic axes.
 * Without periodic axes d is returned unchanged, bit for bit. */
static inline adem_vec3 adem_periodic_min_image(const adem_periodic *pb, adem_vec3 d) {
  if (!pb || !pb->axes) return d;
  if (pb->axes & 1u) d.x = adem_periodic_component(d.x, pb->len[0]);
  if (pb->axes & 2u) d.y = adem_periodic_component(d.y, pb->len[1]);
  if (pb->axes & 4u) d.z = adem_periodic_component(d.z, pb->len[2]);
  return d;
}

/* One coordinate into [lo, lo + len), counting the box lengths taken off in *image. */
static inline double adem_periodic_wrap_component(double x, double lo, double len, int32_t *image) {
  if (x >= lo && x < lo + len) return x;
  double k = floor((x - lo) / len);
  x -= k * len;
  if (x >= lo + len) { /* round-off of x just below lo */
    x -= len;
    k += 1.0;
  }
  if (x < lo) x = lo;
  *image += (int32_t)k;
  return x;
}

/* The centre as if no face had been crossed (diagnostics: potential, angular momentum). */
static inline adem_vec3 adem_periodic_unwrap(const adem_periodic *pb, adem_vec3 x, adem_image im) {
  if (!pb || !pb->axes) return x;
  if (pb->axes & 1u) x.x += im.n[0] * pb->len[0];
  if (pb->axes & 2u) x.y += im.n[1] * pb->len[1];
  if (pb->axes & 4u) x.z += im.n[2] * pb->len[2];
  return x;
}

#endif
