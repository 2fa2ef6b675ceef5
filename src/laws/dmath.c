/* adem's elementary functions in double-double arithmetic (dmath.h). Each value is carried as an
 * unevaluated sum hi + lo of two doubles (Dekker 1971: exact sums and products from + - * alone,
 * which is why contraction must be off), the series are summed to 2^-104 and the result is
 * rounded once. Argument reduction for sin, cos and tan is exact for every double (Payne-Hanek:
 * the bits of 2/pi that matter, multiplied in 64-bit integers). */
#include "dmath.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

/* The same bits everywhere needs each operation rounded to double as written. */
_Static_assert(FLT_EVAL_METHOD == 0,
               "adem needs FLT_EVAL_METHOD == 0 (SSE2 or NEON doubles, no x87)");
_Static_assert(DBL_MANT_DIG == 53, "adem needs IEEE binary64 doubles");

typedef struct dd {
  double h, l;
} dd;

static dd two_sum(double a, double b) {
  double s = a + b, bb = s - a;
  return (dd){s, (a - (s - bb)) + (b - bb)};
}

static dd fast_two_sum(double a, double b) { /* |a| >= |b| */
  double s = a + b;
  return (dd){s, b - (s - a)};
}

/* Veltkamp's split: a = hi + lo with 26 bits each (|a| < 2^995) */
static void split(double a, double *hi, double *lo) {
  double c = 134217729.0 * a; /* 2^27 + 1 */
  *hi = c - (c - a);
  *lo = a - *hi;
}

static dd two_prod(double a, double b) {
  double p = a * b, ah, al, bh, bl;
  split(a, &ah, &al);
  split(b, &bh, &bl);
  return (dd){p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}

static dd dd_add(dd a, dd b) {
  dd s = two_sum(a.h, b.h), t = two_sum(a.l, b.l);
  s.l += t.h;
  s = fast_two_sum(s.h, s.l);
  s.l += t.l;
  return fast_two_sum(s.h, s.l);
}

static dd dd_mul(dd a, dd b) {
  dd p = two_prod(a.h, b.h);
  p.l += a.h * b.l + a.l * b.h;
  return fast_two_sum(p.h, p.l);
}

static dd dd_mul_d(dd a, double b) {
  dd p = two_prod(a.h, b);
  p.l += a.l * b;
  return fast_two_sum(p.h, p.l);
}

static dd dd_div(dd a, dd b) {
  double q1 = a.h / b.h;
  dd r = dd_add(a, dd_mul_d(b, -q1));
  double q2 = r.h / b.h;
  r = dd_add(r, dd_mul_d(b, -q2));
  double q3 = r.h / b.h;
  return dd_add(fast_two_sum(q1, q2), (dd){q3, 0.0});
}

static dd dd_div_d(dd a, double b) { return dd_div(a, (dd){b, 0.0}); }

/* ln 2 and pi/2 to 106 bits */
static const dd LN2 = {0x1.62e42fefa39efp-1, 0x1.abc9e3b39803fp-56};
static const dd PIO2 = {0x1.921fb54442d18p+0, 0x1.1a62633145c07p-54};

static double round_dd(dd a) { return a.h + a.l; }

/* ------------------------------------------------------------------------------------ log */

/* log(m) for m = num/den + 1 ... written as 2 atanh(s), s = (m - 1)/(m + 1) = num/den, |s| <=
 * 0.172: 2 (s + s^3/3 + s^5/5 + ...), the terms summed until they fall below 2^-110 of the sum. */
static dd log_atanh(dd num, dd den) {
  if (num.h == 0.0) return (dd){0.0, 0.0};
  dd s = dd_div(num, den), s2 = dd_mul(s, s), term = s, sum = s;
  for (int j = 1; j < 40; ++j) {
    term = dd_mul(term, s2);
    dd t = dd_div_d(term, 2.0 * j + 1.0);
    sum = dd_add(sum, t);
    if (fabs(t.h) < 0x1p-110 * fabs(sum.h)) break;
  }
  return (dd){2.0 * sum.h, 2.0 * sum.l};
}

/* 2^k as a double, k in [-1022, 1023] */
static double pow2(int k) {
  uint64_t bits = (uint64_t)(k + 1023) << 52;
  double d;
  memcpy(&d, &bits, sizeof d);
  return d;
}

/* y 2^k for any k in [-2044, 2046]: exact unless the result is subnormal or overflows */
static double scale2(double y, int k) {
  if (k > 1000) return y * pow2(1000) * pow2(k - 1000 > 1023 ? 1023 : k - 1000);
  if (k < -1000) return y * pow2(-1000) * pow2(k + 1000 < -1022 ? -1022 : k + 1000);
  return y * pow2(k);
}

/* log(x.h + x.l) for a positive, finite, normal x.h: x = 2^k m with m in [sqrt(1/2), sqrt(2)). */
static dd dd_log(dd x) {
  uint64_t bits;
  memcpy(&bits, &x.h, sizeof bits);
  int k = (int)((bits >> 52) & 0x7ff) - 1023;
  bits = (bits & ((1ull << 52) - 1)) | (1023ull << 52);
  dd m;
  memcpy(&m.h, &bits, sizeof m.h);          /* x.h 2^-k, in [1, 2) */
  m.l = x.l == 0.0 ? 0.0 : scale2(x.l, -k); /* below an ulp of m.h: its rounding is harmless */
  if (m.h > 0x1.6a09e667f3bcdp+0) {         /* sqrt(2) */
    m.h *= 0.5;
    m.l *= 0.5;
    ++k;
  }
  dd num = dd_add((dd){m.h - 1.0, 0.0}, (dd){m.l, 0.0}); /* m.h - 1 is exact (Sterbenz) */
  dd den = dd_add(two_sum(m.h, 1.0), (dd){m.l, 0.0});
  dd lm = log_atanh(num, den);
  dd kl = dd_mul_d(LN2, (double)k);
  return dd_add(kl, lm);
}

double adem_dmath_log(double x) {
  if (isnan(x)) return x;
  if (x < 0.0) return NAN;
  if (x == 0.0) return -INFINITY;
  if (isinf(x)) return x;
  if (x < DBL_MIN) { /* subnormal: scale into the normal range */
    dd r = dd_log((dd){x * 0x1p54, 0.0});
    return round_dd(dd_add(r, dd_mul_d(LN2, -54.0)));
  }
  return round_dd(dd_log((dd){x, 0.0}));
}

double adem_dmath_log1p(double x) {
  if (isnan(x) || x == 0.0) return x; /* keeps -0 */
  if (x < -1.0) return NAN;
  if (x == -1.0) return -INFINITY;
  if (isinf(x)) return x;
  if (fabs(x) < 0x1p-54) return x; /* x - x^2/2 rounds to x */
  if (x > -0.29 && x < 0.41)       /* 1 + x in [sqrt(1/2), sqrt(2)): m - 1 = x exactly */
    return round_dd(log_atanh((dd){x, 0.0}, two_sum(2.0, x)));
  return round_dd(dd_log(two_sum(1.0, x)));
}

/* ------------------------------------------------------------------------------------ exp */

/* exp(z) for a finite double-double z with |z.h| < 746; *k2 gets the power of two apart:
 * exp(z) = (result) 2^k2. z = k ln2 + r, |r| <= ln2/2; e^r = (e^(r/256))^256 with
 * e^(r/256) - 1 = p from its series and 1 + p squared eight times as p <- 2p + p^2. */
static dd dd_exp_scaled(dd z, int *k2) {
  double k = floor(z.h * 0x1.71547652b82fep+0 + 0.5); /* z / ln 2, nearest */
  dd r = dd_add(z, dd_mul_d(LN2, -k));
  r.h *= 0x1p-8;
  r.l *= 0x1p-8;
  dd term = r, p = r;
  for (int n = 2; n < 20; ++n) {
    term = dd_div_d(dd_mul(term, r), (double)n);
    p = dd_add(p, term);
    if (fabs(term.h) < 0x1p-110 * fabs(p.h) || term.h == 0.0) break;
  }
  for (int s = 0; s < 8; ++s) p = dd_add((dd){2.0 * p.h, 2.0 * p.l}, dd_mul(p, p));
  *k2 = (int)k;
  return dd_add((dd){1.0, 0.0}, p);
}

static double dd_exp(dd z) {
  if (z.h > 709.8) return INFINITY;
  if (z.h < -745.2) return 0.0;
  int k;
  dd e = dd_exp_scaled(z, &k);
  if (k < -1021) { /* subnormal result: round once, at the final scale */
    double t = pow2(-1000);
    dd s = {e.h * t, e.l * t}; /* exact: e in [0.7, 1.5], 2^-1000 e is normal */
    int rest = k + 1000;
    double f = pow2(rest < -1022 ? -1022 : rest);
    double lo = s.l * f;
    return s.h * f + lo;
  }
  return scale2(round_dd(e), k);
}

double adem_dmath_exp(double x) {
  if (isnan(x)) return x;
  return dd_exp((dd){x, 0.0});
}

/* ------------------------------------------------------------------------------------ pow */

static int is_odd_integer(double y) {
  return y == floor(y) && fabs(y) < 0x1p53 && fmod(y, 2.0) != 0.0;
}

double adem_dmath_pow(double x, double y) {
  if (y == 0.0 || x == 1.0) return 1.0;
  if (isnan(x) || isnan(y)) return NAN;
  if (isinf(y)) {
    double ax = fabs(x);
    if (ax == 1.0) return 1.0;
    return (ax < 1.0) == (y > 0.0) ? 0.0 : INFINITY;
  }
  double sign = 1.0;
  if (signbit(x)) { /* negative, -0 or -inf */
    if (y != floor(y)) {
      if (x != 0.0 && !isinf(x)) return NAN;
    } else if (is_odd_integer(y)) {
      sign = -1.0;
    }
    x = -x;
  }
  if (x == 1.0) return sign; /* (-1)^integer */
  if (x == 0.0) return sign * (y > 0.0 ? 0.0 : INFINITY);
  if (isinf(x)) return sign * (y > 0.0 ? INFINITY : 0.0);
  dd l;
  if (x < DBL_MIN)
    l = dd_add(dd_log((dd){x * 0x1p54, 0.0}), dd_mul_d(LN2, -54.0));
  else
    l = dd_log((dd){x, 0.0});
  double p = y * l.h;
  if (!(fabs(p) < 800.0)) return sign * (p > 0.0 ? INFINITY : 0.0);
  dd z = dd_mul_d(l, y);
  return sign * dd_exp(z);
}

/* ----------------------------------------------------------------------- sin, cos and tan */

/* Bits of 2/pi after the point, 64 to a word, most significant first (enough for the largest
 * double: bit 971 + 192). Computed from pi by Machin's formula in exact integers. */
static const uint64_t TWO_OVER_PI[20] = {
    0xa2f9836e4e441529ull, 0xfc2757d1f534ddc0ull, 0xdb6295993c439041ull, 0xfe5163abdebbc561ull,
    0xb7246e3a424dd2e0ull, 0x06492eea09d1921cull, 0xfe1deb1cb129a73eull, 0xe88235f52ebb4484ull,
    0xe99c7026b45f7e41ull, 0x3991d639835339f4ull, 0x9c845f8bbdf9283bull, 0x1ff897ffde05980full,
    0xef2f118b5a0a6d1full, 0x6d367ecf27cb09b7ull, 0x4f463f669e5fea2dull, 0x7527bac7ebe5f17bull,
    0x3d0739f78a5292eaull, 0x6bfb5fb11f8d5d08ull, 0x56033046fc7b6babull, 0xf0cfbc209af4361dull};

/* bits s+1 .. s+64 of 2/pi (bit i weighs 2^-i; none before the point) */
static uint64_t two_over_pi_bits(int s) {
  if (s <= -64) return 0;
  if (s < 0) return TWO_OVER_PI[0] >> -s;
  int q = s / 64, r = s % 64;
  if (r == 0) return TWO_OVER_PI[q];
  return (TWO_OVER_PI[q] << r) | (TWO_OVER_PI[q + 1] >> (64 - r));
}

/* a = n pi/2 + r for a finite a >= pi/4: r in [-pi/4, pi/4] as a double-double, n mod 4.
 * a = M 2^E (M a 53-bit integer); a 2/pi mod 4 = M W 2^-190 mod 4 with W the 192 bits of 2/pi
 * from bit E - 1 on (the bits before give multiples of 4, those after less than 2^-137). */
static int reduce_pio2(double a, dd *r) {
  uint64_t bits;
  memcpy(&bits, &a, sizeof bits);
  int E = (int)((bits >> 52) & 0x7ff) - 1075;
  uint64_t M = (bits & ((1ull << 52) - 1)) | (1ull << 52);
  int s = E - 2;
  uint64_t w0 = two_over_pi_bits(s), w1 = two_over_pi_bits(s + 64), w2 = two_over_pi_bits(s + 128);
  unsigned __int128 p2 = (unsigned __int128)M * w2, p1 = (unsigned __int128)M * w1;
  uint64_t p0 = M * w0; /* low 64 bits suffice: the rest is a multiple of 4 */
  uint64_t r2 = (uint64_t)p2;
  unsigned __int128 mid = (p2 >> 64) + (uint64_t)p1;
  uint64_t r1 = (uint64_t)mid;
  uint64_t r0 = p0 + (uint64_t)(p1 >> 64) + (uint64_t)(mid >> 64);
  int n = (int)(r0 >> 62);
  /* the fraction: 128 bits after the two integer bits */
  unsigned __int128 F =
      ((unsigned __int128)((r0 << 2) | (r1 >> 62)) << 64) | ((r1 << 2) | (r2 >> 62));
  int neg = 0;
  if (F >> 127) { /* fraction >= 1/2: round n up, r negative */
    F = -F;
    n = (n + 1) & 3;
    neg = 1;
  }
  uint64_t fh = (uint64_t)(F >> 64), fl = (uint64_t)F;
  int lz = fh ? __builtin_clzll(fh) : 64 + (fl ? __builtin_clzll(fl) : 64);
  if (lz >= 128) { /* cannot happen for a double (pi is irrational); keep r defined */
    *r = (dd){0.0, 0.0};
    return n;
  }
  unsigned __int128 G = F << lz;
  double hi = (double)(uint64_t)(G >> 75);                        /* 53 bits */
  double lo = (double)(uint64_t)((G >> 22) & ((1ull << 53) - 1)); /* the next 53 */
  /* f = G 2^(-128 - lz): hi 2^(-53 - lz) + lo 2^(-106 - lz); lz <= 70, so both scales are normal */
  dd f = fast_two_sum(hi * pow2(-53 - lz), lo * pow2(-53 - lz) * 0x1p-53);
  dd x = dd_mul(f, PIO2);
  *r = neg ? (dd){-x.h, -x.l} : x;
  return n;
}

/* sin(r) and cos(r) for |r| <= pi/4 by their series, in double-double */
static dd sin_series(dd r) {
  dd r2 = dd_mul(r, r), term = r, sum = r;
  for (int n = 3; n < 40; n += 2) {
    term = dd_div_d(dd_mul(term, r2), -(double)(n * (n - 1)));
    sum = dd_add(sum, term);
    if (fabs(term.h) < 0x1p-110 * fabs(sum.h) || term.h == 0.0) break;
  }
  return sum;
}

static dd cos_series(dd r) {
  dd r2 = dd_mul(r, r), term = {1.0, 0.0}, sum = {1.0, 0.0};
  for (int n = 2; n < 40; n += 2) {
    term = dd_div_d(dd_mul(term, r2), -(double)(n * (n - 1)));
    sum = dd_add(sum, term);
    if (fabs(term.h) < 0x1p-110 || term.h == 0.0) break;
  }
  return sum;
}

/* |x| = n pi/2 + r */
static int reduce(double ax, dd *r) {
  if (ax <= 0x1.921fb54442d18p-1) { /* pi/4 */
    *r = (dd){ax, 0.0};
    return 0;
  }
  return reduce_pio2(ax, r);
}

double adem_dmath_sin(double x) {
  if (isnan(x) || isinf(x)) return x - x; /* NaN */
  if (x == 0.0) return x;
  dd r;
  int n = reduce(fabs(x), &r);
  dd v = n & 1 ? cos_series(r) : sin_series(r);
  double s = round_dd(v);
  if (n & 2) s = -s;
  return signbit(x) ? -s : s;
}

double adem_dmath_cos(double x) {
  if (isnan(x) || isinf(x)) return x - x;
  dd r;
  int n = reduce(fabs(x), &r);
  dd v = n & 1 ? sin_series(r) : cos_series(r);
  double c = round_dd(v);
  return (n == 1 || n == 2) ? -c : c; /* cos(r + pi/2) = -sin r, cos(r + pi) = -cos r */
}

double adem_dmath_tan(double x) {
  if (isnan(x) || isinf(x)) return x - x;
  if (x == 0.0) return x;
  dd r;
  int n = reduce(fabs(x), &r);
  dd s = sin_series(r), c = cos_series(r);
  double t = n & 1 ? -round_dd(dd_div(c, s)) : round_dd(dd_div(s, c));
  return signbit(x) ? -t : t;
}

/* ------------------------------------------------------------------------------------ cbrt */

double adem_dmath_cbrt(double x) {
  if (isnan(x) || isinf(x) || x == 0.0) return x;
  double a = fabs(x), back = 1.0;
  if (a < 0x1p-900) { /* into the range where the first guess and y^3 are normal */
    a *= 0x1p600;
    back = 0x1p-200;
  } else if (a > 0x1p900) {
    a *= 0x1p-600;
    back = 0x1p200;
  }
  uint64_t bits;
  memcpy(&bits, &a, sizeof bits);
  uint32_t hi = (uint32_t)(bits >> 32);
  bits = (uint64_t)(hi / 3u + 715094163u) << 32; /* exponent / 3, bias kept: within 3.2 % */
  double y;
  memcpy(&y, &bits, sizeof y);
  for (int k = 0; k < 3; ++k) { /* Halley: 3e-5, 1e-15, then to rounding */
    double y3 = y * y * y;
    y = y * ((y3 + 2.0 * a) / (2.0 * y3 + a));
  }
  /* one Newton step on the exact residual: y - (y^3 - a)/(3 y^2) */
  dd y3 = dd_mul_d(two_prod(y, y), y);
  double res = round_dd(dd_add(y3, (dd){-a, 0.0}));
  y = y - res / (3.0 * y * y);
  y *= back;
  return signbit(x) ? -y : y;
}

double adem_dmath_contraction_probe(double a, double b, double c) { return a * b - c; }
