/* The Hertz normal law's cold path (law_hooks.h): its collision time. */
#include "hertz.h"

#include "law_hooks.h"

/* notes section 6 */
double adem_hertz_collision_time(double mstar, double R, double E, double v) {
  return 2.86827 * adem_dmath_pow(mstar * mstar / (R * E * E * v), 0.2);
}

static double collision_time(const adem_pair_params *pp, double mstar, double R, double v_ref) {
  return adem_hertz_collision_time(mstar, R, pp->E, v_ref);
}

const adem_law_hooks adem_hertz_hooks = {.collision_time = collision_time};
