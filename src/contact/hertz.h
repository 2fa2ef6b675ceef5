/* Hertz normal contact with the damping of Haervig et al. (H8-H9 without adhesion, H11-H13).
 * Pure functions: inputs in, force out. Positive normal force is repulsive. */
#ifndef ADEM_CONTACT_HERTZ_H
#define ADEM_CONTACT_HERTZ_H

#include <math.h>
#include "vec3.h"

/* Elastic Hertz force (4/3) E sqrt(R) delta^(3/2): H9 with a = sqrt(R delta). */
static inline double adem_hertz_force(double E, double R, double delta) {
  return (4.0 / 3.0) * E * sqrt(R) * delta * sqrt(delta);
}

/* Elastic energy stored at overlap delta: the integral of the force, (8/15) E sqrt(R) delta^(5/2). */
static inline double adem_hertz_energy(double E, double R, double delta) {
  return (8.0 / 15.0) * E * sqrt(R) * delta * delta * sqrt(delta);
}

/* Normal tangent stiffness S_n = 2 E sqrt(R delta) (H13). */
static inline double adem_hertz_normal_stiffness(double E, double R, double delta) {
  return 2.0 * E * sqrt(R * delta);
}

/* Tangential stiffness S_t = 8 G sqrt(R delta) (H14). */
static inline double adem_hertz_tangential_stiffness(double G, double R, double delta) {
  return 8.0 * G * sqrt(R * delta);
}

/* beta = ln e / sqrt(ln^2 e + pi^2) (H12); 0 for e = 1, negative otherwise. */
static inline double adem_damping_beta(double e) {
  double l = log(e);
  return l / sqrt(l * l + ADEM_PI * ADEM_PI);
}

/* Viscous coefficient c = -2 sqrt(5/6) beta sqrt(S m*) >= 0 (H11 with the square root that the
 * OCR lost, as in H16); the damping force is -c v. */
static inline double adem_damping_coefficient(double beta, double stiffness, double mstar) {
  return -2.0 * sqrt(5.0 / 6.0) * beta * sqrt(stiffness * mstar);
}

#endif
