/* Simplified JKR adhesion (H7-H10, notes section 2). Pure functions.
 *
 * The contact radius a(delta) is the largest real root of H10,
 *   a^4 - 2 R delta a^2 - (4 pi gamma / E) R^2 a + R^2 delta^2 = 0,
 * equivalently delta = a^2/R - 2 sqrt(pi gamma a / E). With u = sqrt(a) and c = sqrt(pi gamma/E)
 * this is the depressed quartic u^4 - 2 c R u - R delta = 0, solved in closed form by Ferrari's
 * method: its resolvent cubic m^3 + R delta m - c^2 R^2 / 2 = 0 has one positive root for
 * delta >= 0 (Cardano, written without cancellation), and then
 *   u = (s + sqrt(4 c R / s - s^2)) / 2,  s = sqrt(2 m),  a = u^2. */
#ifndef ADEM_CONTACT_JKR_H
#define ADEM_CONTACT_JKR_H

#include "law_inline.h"
#include "dmath.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>
#include "adem/vec3.h"

/* Cube root of x within 3 ulp of libm's cbrt (7e-16 relative: tests/unit/test_jkr.c), without
 * the library call, whose frexp and scalbn made an eighth of a JKR bed's time. The high word's
 * exponent divided by three (fdlibm's first guess) starts within 3.2 %; two Halley steps (cubic:
 * 3e-5, then 7e-15) and a Newton step (quadratic) finish. 32-bit integer arithmetic and no
 * branch, so that a loop of it packs (the force pass's block kernels). Outside [2^-1000,
 * 2^1000], x <= 0 and NaN: NaN, which the block kernels take as "do this contact one at a time",
 * where adem_jkr_cbrt gives adem_dmath_cbrt's. The same operations in the same order
 * everywhere: the same bits for any thread count and host. */
ADEM_LAW double adem_jkr_cbrt_packed(double x) {
  uint64_t bits;
  memcpy(&bits, &x, sizeof bits);
  uint32_t hi = (uint32_t)(bits >> 32);
  bits = (uint64_t)(hi / 3u + 715094163u) << 32; /* exponent / 3, bias kept */
  double y;
  memcpy(&y, &bits, sizeof y);
  for (int k = 0; k < 2; ++k) {
    double y3 = y * y * y;
    y = y * ((y3 + 2.0 * x) / (2.0 * y3 + x)); /* Halley; the ratio first: no overflow */
  }
  y = y - (y - x / (y * y)) * (1.0 / 3.0); /* Newton */
  return x >= 0x1p-1000 && x <= 0x1p1000 ? y : NAN;
}

/* The same, and adem_dmath_cbrt outside [2^-1000, 2^1000] (not libm's cbrt: dmath.h). */
ADEM_LAW double adem_jkr_cbrt(double x) {
  if (!(x >= 0x1p-1000 && x <= 0x1p1000)) return adem_dmath_cbrt(x);
  return adem_jkr_cbrt_packed(x);
}

/* Critical force F_C = 3 pi gamma R (notes section 1). */
ADEM_LAW double adem_jkr_critical_force(double gamma, double R) {
  return 3.0 * ADEM_PI * gamma * R;
}

/* Equilibrium contact radius a0 = (9 pi gamma R^2 / E)^(1/3) (H7). */
ADEM_LAW double adem_jkr_a0(double gamma, double R, double E) {
  return adem_jkr_cbrt(9.0 * ADEM_PI * gamma * R * R / E);
}

/* Contact radius for overlap delta >= -delta_c (closed form of H10, no iteration; sqrt(R delta)
 * without surface energy). packed: the
 * cube root without the library (adem_jkr_cbrt_packed: NaN where it would be called). */
ADEM_LAW double adem_jkr_contact_radius_as(double gamma, double R, double E, double delta,
                                           bool packed) {
  double c2 = ADEM_PI * gamma / E; /* c^2 */
  double P = R * delta;
  double Q = -0.5 * c2 * R * R; /* < 0 */
  /* Cardano: m = A + B with A = cbrt(-Q/2 + sqrt(Q^2/4 + P^3/27)), A B = -P/3. The sum A + B
   * cancels badly for large P; m = -Q / (A^2 - AB + B^2) does not (all terms positive). */
  double disc = 0.25 * Q * Q + P * P * P / 27.0;
  double x = -0.5 * Q + sqrt(disc > 0.0 ? disc : 0.0);
  double A = packed ? adem_jkr_cbrt_packed(x) : adem_jkr_cbrt(x);
  double B = -P / (3.0 * A);
  double m = -Q / (A * A - A * B + B * B);
  double s = sqrt(2.0 * m);
  double root = 4.0 * sqrt(c2) * R / s - s * s;
  double u = 0.5 * (s + sqrt(root > 0.0 ? root : 0.0));
  /* gamma = 0: m = 0 and 4 c R / s is 0/0; the quartic is then u^4 = R delta, Hertz's a (a
   * select, not a branch: the block kernels' loops stay packed) */
  return c2 > 0.0 ? u * u : sqrt(P);
}

ADEM_LAW double adem_jkr_contact_radius(double gamma, double R, double E, double delta) {
  return adem_jkr_contact_radius_as(gamma, R, E, delta, false);
}

/* Elastic normal force at contact radius a, positive repulsive: 4 E a^3/(3R) - 4 sqrt(pi gamma E
 * a^3) (H8 + H9). */
ADEM_LAW double adem_jkr_force(double gamma, double R, double E, double a) {
  double a3 = a * a * a;
  return 4.0 * E * a3 / (3.0 * R) - 4.0 * sqrt(ADEM_PI * gamma * E * a3);
}

/* Energy stored in the contact relative to the state at delta = 0 where it forms:
 * Phi(a) - Phi(a(0)) with Phi = 8 E a^5/(15 R^2) - (8/3) sqrt(pi gamma E) a^(7/2)/R + 2 pi gamma a^2,
 * the integral of the force over the overlap. */
ADEM_LAW double adem_jkr_potential(double gamma, double R, double E, double a) {
  double k = sqrt(ADEM_PI * gamma * E);
  double a2 = a * a, a3 = a2 * a; /* a^5 and a^3.5 without pow: the same bits on every host */
  return 8.0 * E * (a3 * a2) / (15.0 * R * R) - (8.0 / 3.0) * k * (a3 * sqrt(a)) / R +
         2.0 * ADEM_PI * gamma * a * a;
}
ADEM_LAW double adem_jkr_energy(double gamma, double R, double E, double a) {
  double a_form = adem_jkr_cbrt(4.0 * ADEM_PI * gamma * R * R / E); /* a at delta = 0 */
  return adem_jkr_potential(gamma, R, E, a) - adem_jkr_potential(gamma, R, E, a_form);
}

/* The cold-path hooks of the simplified JKR law (jkr.c), named by its row (include/adem/laws.h;
 * law_hooks.h). */
extern const struct adem_law_hooks adem_jkr_hooks;

#endif
