/* Tangential spring-dashpot with history and a Coulomb limit (H14, H16, H17). */
#ifndef ADEM_CONTACT_TANGENTIAL_H
#define ADEM_CONTACT_TANGENTIAL_H

#include <stdbool.h>
#include "adem/vec3.h"

/* Keeps the history xi in the tangent plane of the unit normal n, with its length unchanged, so a
 * rotating contact does not lose or gain stored spring energy. */
static inline adem_vec3 adem_tangential_project(adem_vec3 xi, adem_vec3 n) {
  double len2 = v3_norm2(xi);
  if (len2 == 0.0) return xi;
  adem_vec3 p = v3_axpy(xi, -v3_dot(xi, n), n);
  double p2 = v3_norm2(p);
  if (p2 == 0.0) return v3_zero();
  return v3_scale(p, sqrt(len2 / p2));
}

/* Advances the history by the slip vt*dt and returns the tangential force on i:
 * F = -S_t xi - c_t vt (H14, H16), limited to |F| <= f_limit (H17). When sliding, xi is reset so
 * that the spring alone carries the limit. vt is the slip velocity of i's surface relative to j's. */
static inline adem_vec3 adem_tangential_force(adem_vec3 *xi, adem_vec3 n, adem_vec3 vt, double dt,
                                              double stiffness, double damping, double f_limit,
                                              bool *sliding) {
  adem_vec3 h = v3_axpy(adem_tangential_project(*xi, n), dt, vt);
  adem_vec3 f = v3_sub(v3_scale(h, -stiffness), v3_scale(vt, damping));
  double fmag2 = v3_norm2(f);
  *sliding = false;
  if (fmag2 > f_limit * f_limit) {
    double s = f_limit / sqrt(fmag2);
    f = v3_scale(f, s);
    h = stiffness > 0.0 ? v3_scale(f, -1.0 / stiffness) : v3_zero();
    *sliding = true;
  }
  *xi = h;
  return f;
}

#endif
