/* The 1-D normal equation of a simplified JKR collision, integrated by an adaptive
 * Dormand-Prince 5(4) method (normal_ode.h). */
#include "normal_ode.h"

#include <math.h>
#include <string.h>

#include "adem/vec3.h"

/* Contact radius: the largest root of g(a) = a^2/R - 2 sqrt(pi gamma a/E) - delta (H10). g is
 * convex for a > 0, so Newton's method from the right of the root converges monotonically. */
static double contact_radius(const adem_normal_ode *p, double delta) {
  if (p->gamma <= 0.0) return sqrt(p->R * fmax(delta, 0.0));
  double k = ADEM_PI * p->gamma / p->E;
  double a_form = cbrt(4.0 * k * p->R * p->R); /* the root at delta = 0 */
  double a = 2.0 * (a_form + sqrt(p->R * fmax(delta, 0.0)));
  for (int it = 0; it < 200; ++it) {
    double g = a * a / p->R - 2.0 * sqrt(k * a) - delta;
    double dg = 2.0 * a / p->R - sqrt(k / a);
    double step = g / dg;
    a -= step;
    if (fabs(step) <= 1e-16 * a) break;
  }
  return a;
}

double adem_normal_ode_force(const adem_normal_ode *p, double delta) {
  double a = contact_radius(p, delta);
  double a3 = a * a * a;
  double f = 4.0 * p->E * a3 / (3.0 * p->R);
  if (p->gamma > 0.0) f -= 4.0 * sqrt(ADEM_PI * p->gamma * p->E * a3);
  return f;
}

/* State: overlap, approach speed, stored energy. */
typedef struct state {
  double d, v, u;
} state;

static state deriv(const adem_normal_ode *p, state y) {
  double f = adem_normal_ode_force(p, y.d);
  double sn = 2.0 * p->E * sqrt(p->R * fmax(y.d, 0.0));
  double c = -2.0 * sqrt(5.0 / 6.0) * p->beta * sqrt(sn * p->mstar);
  state dy = {y.v, -(f + c * y.v) / p->mstar, f * y.v};
  return dy;
}

static state axpy(state y, double h, state k) {
  state r = {y.d + h * k.d, y.v + h * k.v, y.u + h * k.u};
  return r;
}

/* One Dormand-Prince step of size h from y (k1 = f(y)); the fifth-order result and the error
 * estimate (difference with the fourth-order one). */
static state dp_step(const adem_normal_ode *p, state y, state k1, double h, state *err) {
  static const double a21 = 1.0 / 5.0;
  static const double a31 = 3.0 / 40.0, a32 = 9.0 / 40.0;
  static const double a41 = 44.0 / 45.0, a42 = -56.0 / 15.0, a43 = 32.0 / 9.0;
  static const double a51 = 19372.0 / 6561.0, a52 = -25360.0 / 2187.0, a53 = 64448.0 / 6561.0,
                      a54 = -212.0 / 729.0;
  static const double a61 = 9017.0 / 3168.0, a62 = -355.0 / 33.0, a63 = 46732.0 / 5247.0,
                      a64 = 49.0 / 176.0, a65 = -5103.0 / 18656.0;
  static const double b1 = 35.0 / 384.0, b3 = 500.0 / 1113.0, b4 = 125.0 / 192.0,
                      b5 = -2187.0 / 6784.0, b6 = 11.0 / 84.0;
  static const double e1 = 71.0 / 57600.0, e3 = -71.0 / 16695.0, e4 = 71.0 / 1920.0,
                      e5 = -17253.0 / 339200.0, e6 = 22.0 / 525.0, e7 = -1.0 / 40.0;
  state k2 = deriv(p, axpy(y, h * a21, k1));
  state t = axpy(axpy(y, h * a31, k1), h * a32, k2);
  state k3 = deriv(p, t);
  t = axpy(axpy(axpy(y, h * a41, k1), h * a42, k2), h * a43, k3);
  state k4 = deriv(p, t);
  t = axpy(axpy(axpy(axpy(y, h * a51, k1), h * a52, k2), h * a53, k3), h * a54, k4);
  state k5 = deriv(p, t);
  t = axpy(axpy(axpy(axpy(axpy(y, h * a61, k1), h * a62, k2), h * a63, k3), h * a64, k4), h * a65,
           k5);
  state k6 = deriv(p, t);
  state n = axpy(axpy(axpy(axpy(axpy(y, h * b1, k1), h * b3, k3), h * b4, k4), h * b5, k5), h * b6,
                 k6);
  state k7 = deriv(p, n);
  state e = {0.0, 0.0, 0.0};
  e = axpy(e, h * e1, k1);
  e = axpy(e, h * e3, k3);
  e = axpy(e, h * e4, k4);
  e = axpy(e, h * e5, k5);
  e = axpy(e, h * e6, k6);
  e = axpy(e, h * e7, k7);
  *err = e;
  return n;
}

adem_normal_ode_result adem_normal_ode_collide(const adem_normal_ode *p, double v0, double rtol,
                                               adem_normal_ode_trace_fn *trace, void *user) {
  adem_normal_ode_result r;
  memset(&r, 0, sizeof r);
  /* scales: Hertz collision time and overlap at v0 (with the adhesive speed-up) */
  double fc = 3.0 * ADEM_PI * p->gamma * p->R;
  double v_eff = v0;
  double u_scale = 0.5 * p->mstar * v0 * v0;
  if (p->gamma > 0.0) {
    double a0 = cbrt(9.0 * ADEM_PI * p->gamma * p->R * p->R / p->E);
    double d_eq = a0 * a0 / (3.0 * p->R);
    /* |U_min| ~ F_C delta_eq: a scale, not the value */
    u_scale = fmax(u_scale, fc * d_eq);
    v_eff = sqrt(v0 * v0 + 2.0 * fc * d_eq / p->mstar);
  }
  double tc = 2.86827 * pow(p->mstar * p->mstar / (p->R * p->E * p->E * v_eff), 0.2);
  double d_scale = v_eff * tc, v_scale = v_eff;
  double t_max = 2000.0 * tc;
  state y = {0.0, v0, 0.0};
  state k1 = deriv(p, y);
  double t = 0.0, h = 1e-4 * tc;
  while (t < t_max) {
    state err;
    state n = dp_step(p, y, k1, h, &err);
    double en = fmax(fabs(err.d) / (rtol * fmax(fabs(n.d), d_scale)),
                     fmax(fabs(err.v) / (rtol * v_scale), fabs(err.u) / (rtol * u_scale)));
    if (!(en <= 1.0)) { /* reject (NaN too) */
      h *= fmax(0.1, 0.9 * pow(isfinite(en) ? en : 1e10, -0.2));
      continue;
    }
    if (n.d < 0.0 && n.v < 0.0 && t > 0.0) {
      /* parted within the step: find the h that ends at delta = 0 (secant, then Newton on v) */
      double lo = 0.0, hi = h, hh = h * y.d / (y.d - n.d);
      state m = n;
      for (int it = 0; it < 60; ++it) {
        state e2;
        m = dp_step(p, y, k1, hh, &e2);
        if (fabs(m.d) <= 1e-13 * d_scale) break;
        if (m.d > 0.0) lo = hh;
        else hi = hh;
        double nh = hh - m.d / m.v;
        hh = nh > lo && nh < hi ? nh : 0.5 * (lo + hi);
      }
      r.steps++;
      r.duration = t + hh;
      r.v_out = -m.v;
      r.e_eff = r.v_out / v0;
      if (trace) trace(r.duration, 0.0, m.v, user);
      return r;
    }
    y = n;
    t += h;
    r.steps++;
    k1 = deriv(p, y);
    if (trace) trace(t, y.d, y.v, user);
    if (0.5 * p->mstar * y.v * y.v + y.u < -1e-12 * u_scale) { /* can never reach delta = 0 */
      r.stuck = true;
      r.duration = t;
      return r;
    }
    h *= fmin(5.0, 0.9 * pow(fmax(en, 1e-10), -0.2));
  }
  r.stuck = true; /* never parted in 2000 collision times */
  r.duration = t;
  return r;
}

adem_normal_ode adem_normal_ode_of(const adem_collide_spec *s) {
  adem_collide_params cp = adem_collide_derive(s);
  double l = log(s->restitution);
  adem_normal_ode p = {cp.mstar, cp.R, cp.E_mod, cp.gamma_mod, l / sqrt(l * l + ADEM_PI * ADEM_PI)};
  return p;
}

static bool ode_stuck(const adem_collide_spec *base, adem_normal_ode_param_fn *set, void *user,
                      double x) {
  adem_collide_spec s = *base;
  set(&s, x, user);
  adem_normal_ode p = adem_normal_ode_of(&s);
  return adem_normal_ode_collide(&p, adem_collide_derive(&s).v_n, 1e-10, NULL, NULL).stuck;
}

double adem_normal_ode_threshold(const adem_collide_spec *base, adem_normal_ode_param_fn *set,
                                 void *user, double lo, double hi, double rel_tol) {
  bool side = ode_stuck(base, set, user, lo);
  if (side == ode_stuck(base, set, user, hi)) return NAN;
  double a = log(lo), b = log(hi);
  while (b - a > rel_tol) {
    double m = 0.5 * (a + b);
    if (ode_stuck(base, set, user, exp(m)) == side) a = m;
    else b = m;
  }
  return exp(0.5 * (a + b));
}
