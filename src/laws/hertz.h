/* Hertz normal contact with the damping of Haervig et al. (H8-H9 without adhesion, H11-H13).
 * Pure functions: inputs in, force out. Positive normal force is repulsive. */
#ifndef ADEM_CONTACT_HERTZ_H
#define ADEM_CONTACT_HERTZ_H

#include "law_inline.h"
#include "dmath.h"

#include <math.h>
#include "adem/vec3.h"

/* Hertz contact radius a = sqrt(R delta); the laws below take it so it is computed once. */
ADEM_LAW double adem_hertz_radius(double R, double delta) { return sqrt(R * delta); }

/* Elastic force 4 E a^3 / (3 R) = (4/3) E a delta (H9 without adhesion). */
ADEM_LAW double adem_hertz_force(double E, double a, double delta) {
  return (4.0 / 3.0) * E * a * delta;
}

/* Elastic energy stored at overlap delta, the integral of the force: (8/15) E a delta^2. */
ADEM_LAW double adem_hertz_energy(double E, double a, double delta) {
  return (8.0 / 15.0) * E * a * delta * delta;
}

/* Normal tangent stiffness S_n = 2 E sqrt(R delta) = 2 E a (H13). */
ADEM_LAW double adem_hertz_normal_stiffness(double E, double a) { return 2.0 * E * a; }

/* Tangential stiffness S_t = 8 G sqrt(R delta) = 8 G a (H14). */
ADEM_LAW double adem_hertz_tangential_stiffness(double G, double a) { return 8.0 * G * a; }

/* beta = ln e / sqrt(ln^2 e + pi^2) (H12); 0 for e = 1, negative otherwise. */
ADEM_LAW double adem_damping_beta(double e) {
  double l = adem_dmath_log(e);
  return l / sqrt(l * l + ADEM_PI * ADEM_PI);
}

/* Viscous coefficient c = -2 sqrt(5/6) beta sqrt(S m*) >= 0 (H11 with the square root that the
 * OCR lost, as in H16); the damping force is -c v. */
ADEM_LAW double adem_damping_coefficient(double beta, double stiffness, double mstar) {
  return -2.0 * sqrt(5.0 / 6.0) * beta * sqrt(stiffness * mstar);
}

/* Effective restitution of a Hertz collision with the dashpot of H11 (coefficient from beta),
 * from the 1-D normal equation in units where (4/3) E sqrt(R) = m* = v_in = 1:
 *   x'' = -(x^(3/2) + g x^(1/4) x'),  g = -sqrt(5) beta >= 0,  x(0) = 0, x'(0) = 1,
 * which has beta as its only parameter. clamp: the total normal force never pulls (it is
 * max(0, ...)), so the spheres part where it reaches zero; else they part at x = 0.
 * RK4 with h = 2e-4 from a series start, the end interpolated (laws.c). */
double adem_hertz_restitution(double beta, int clamp);

/* beta that gives e_eff = e with the clamped force (root of adem_hertz_restitution(beta, 1) =
 * e, secant method, |e_eff - e| < 1e-9); 0 for e = 1 (laws.c). */
double adem_damping_beta_clamped(double e);

/* The cold-path hooks of the Hertz normal law (hertz.c) and of the clamped damping (damping.c),
 * named by their rows (include/adem/laws.h; law_hooks.h). */
extern const struct adem_law_hooks adem_hertz_hooks;
extern const struct adem_law_hooks adem_damping_clamped_hooks;

#endif
