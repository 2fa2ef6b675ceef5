/* adem's own elementary functions: the same bits on every host.
 *
 * glibc picks exp, log, pow, sin, cos, tan, log1p ... by CPU (FMA variants where the CPU has FMA)
 * and they differ in the last bit; other libms, other glibc versions and other architectures
 * differ too. Every transcendental value that feeds the dynamics (damping beta, gamma_mod, the
 * collision time and step, a rotating wall's angle, insertion's radii, DTK's a0) comes from here
 * instead: built from + - * / and integer operations only, in double-double arithmetic (about 104
 * bits) rounded once at the end, so the results are within 1 ulp of the exact value (nearly always
 * the correctly rounded one; tests/unit/test_dmath.c) and identical wherever IEEE binary64 is
 * evaluated without contraction (FLT_EVAL_METHOD 0, -ffp-contract=off: checked in dmath.c).
 * They are slower than libm's (0.1 to 1 microsecond): for set-up values and once-per-step values,
 * not for per-contact inner loops. Special values follow C99 (Annex F). */
#ifndef ADEM_CONTACT_DMATH_H
#define ADEM_CONTACT_DMATH_H

double adem_dmath_exp(double x);
double adem_dmath_log(double x);
double adem_dmath_log1p(double x);
double adem_dmath_pow(double x, double y);
double adem_dmath_sin(double x);
double adem_dmath_cos(double x);
double adem_dmath_tan(double x);
double adem_dmath_cbrt(double x);

/* a * b - c evaluated as written: 2^-54 for (1 + 2^-27, 1 + 2^-27, 1 + 2^-26) where the compiler
 * fused it into an FMA, 0 where it did not (the build must not contract: tests/unit/test_dmath.c).
 */
double adem_dmath_contraction_probe(double a, double b, double c);

#endif
