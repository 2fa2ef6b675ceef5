/* Reproductions of Haervig et al. 2017 (simplified JKR with reduced stiffness): Figs. 3, 5, 7, 8
 * and 13. Each writes DIR/NAME.csv and DIR/NAME.png and says whether the paper's claim holds.
 * The collisions run through adem_collide (collide.c), i.e. through the engine's own worlds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"
#include "contact/jkr.h"
#include "log.h"
#include "plot.h"
#include "validate.h"

#define NF 3
static const double stiffness[NF] = {1.0, 0.1, 0.01}; /* E_mod/E of Figs. 5 and 13 */

/* ------------------------------------------------------------------ helpers */

/* PSL sphere on polished quartz (H Fig. 5, notes section 8): the wall is rigid and the sphere's
 * modulus is chosen so that the effective modulus is 271 MPa. */
static adem_collision_spec psl_on_quartz(double f, bool keep_gamma, double speed) {
  adem_collision_spec s = adem_default_collision_spec();
  s.kind = ADEM_COLLISION_WALL;
  s.radius = 0.5 * 1.27e-6;
  s.density = 1026.0;
  s.young = 271e6;
  s.poisson = 0.3;
  s.restitution = 0.86;
  s.surface_energy = 0.11;
  s.stiffness_factor = f;
  s.keep_gamma = keep_gamma;
  s.speed = speed;
  return s;
}

static void set_speed(adem_collision_spec *s, double x, void *user) {
  (void)user;
  s->speed = x;
}

static void set_lambda(adem_collision_spec *s, double x, void *user) {
  (void)user;
  adem_collide_set_lambda(s, x);
}

/* Steps per collision time: the force jump of the simplified model at delta = 0 makes the error
 * first order in the step (about 1e-3 in e_eff at 1000 steps, 5e-3 at 200). */
static double steps_per_tc(const adem_validation_context *ctx) { return ctx->quick ? 200.0 : 1000.0; }

static double log_point(double lo, double hi, size_t k, size_t n) {
  return n < 2 ? lo : lo * pow(hi / lo, (double)k / (double)(n - 1));
}

static adem_status nomem(adem_error *err) {
  return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
}

/* First failed collision of a batch, as an error. */
static adem_status batch_status(const adem_collision_result *r, size_t n, adem_error *err) {
  for (size_t k = 0; k < n; ++k)
    if (r[k].status)
      return adem_error_set(err, r[k].status, "collision %zu: %s", k, r[k].message);
  return ADEM_OK;
}

/* Writes the table as DIR/NAME.csv and draws DIR/NAME.png with a gnuplot body in which every
 * "@CSV@" stands for the quoted CSV path. */
static adem_status write_outputs(const adem_validation_context *ctx, const char *name,
                                 const adem_table *t, const char *body_template, adem_error *err) {
  char *csv = adem_validate_path(ctx, name, "csv");
  char *png = adem_validate_path(ctx, name, "png");
  adem_status st = ADEM_OK;
  if (!csv || !png) st = nomem(err);
  if (!st) st = adem_table_write_csv(t, csv, err);
  if (!st) {
    size_t qn = 2 * strlen(csv) + 3;
    char *q = malloc(qn);
    size_t uses = 0;
    for (const char *s = strstr(body_template, "@CSV@"); s; s = strstr(s + 5, "@CSV@")) ++uses;
    size_t n = strlen(body_template) + uses * qn + 1;
    char *body = malloc(n);
    if (!q || !body) {
      st = nomem(err);
    } else {
      adem_plot_quote(csv, q, qn);
      char *o = body;
      for (const char *s = body_template; *s;) {
        if (strncmp(s, "@CSV@", 5) == 0) {
          o += sprintf(o, "%s", q);
          s += 5;
        } else {
          *o++ = *s++;
        }
      }
      *o = '\0';
      st = adem_plot_png(png, 1000, 700, body, err);
    }
    free(q);
    free(body);
  }
  free(csv);
  free(png);
  return st;
}

/* ------------------------------------------------------------------ Fig. 3 */

/* Work of adhesion: the area between the attractive part of the curve and the axis,
 * integral of -F over [0, delta_eq] by the trapezoid rule on n intervals (H23). */
static double attractive_area(double gamma, double R, double E, int n) {
  double a0 = adem_jkr_a0(gamma, R, E);
  double d_eq = a0 * a0 / (3.0 * R);
  double sum = 0.0, prev = 0.0;
  for (int k = 0; k <= n; ++k) {
    double d = d_eq * k / n;
    double f = -adem_jkr_force(gamma, R, E, adem_jkr_contact_radius(gamma, R, E, d));
    if (k) sum += 0.5 * (f + prev) * d_eq / n;
    prev = f;
  }
  return sum;
}

static adem_status fig3(const adem_validation_context *ctx, const char *name,
                        adem_validation_report *rep, adem_error *err) {
  const adem_collision_spec s = psl_on_quartz(1.0, false, 1.0);
  const double f = 0.1, R = s.radius, E = s.young, g = s.surface_energy;
  /* the three laws: original; E reduced, gamma kept; E and gamma reduced by H24 */
  const double Es[3] = {E, f * E, f * E};
  const double gs[3] = {g, g, g * pow(f, 0.4)};
  adem_table t;
  if (adem_table_init(&t, "overlap_m,F_original_N,F_E_reduced_N,F_E_gamma_reduced_H24_N"))
    return nomem(err);
  double a0_soft = adem_jkr_a0(g, R, f * E);
  double d_max = 1.3 * a0_soft * a0_soft / (3.0 * R); /* past the softest curve's equilibrium */
  int n = ctx->quick ? 200 : 600;
  adem_status st = ADEM_OK;
  for (int k = 0; k <= n && !st; ++k) {
    double d = d_max * k / n, row[4] = {d};
    for (int c = 0; c < 3; ++c)
      row[c + 1] = adem_jkr_force(gs[c], R, Es[c], adem_jkr_contact_radius(gs[c], R, Es[c], d));
    if (adem_table_add(&t, row)) st = nomem(err);
  }
  double area[3], area_exact[3], pull[3];
  int nint = ctx->quick ? 2000 : 20000;
  for (int c = 0; c < 3; ++c) {
    area[c] = attractive_area(gs[c], R, Es[c], nint);
    area_exact[c] = -adem_jkr_energy(gs[c], R, Es[c], adem_jkr_a0(gs[c], R, Es[c]));
    pull[c] = 8.0 / 9.0 * adem_jkr_critical_force(gs[c], R); /* -F at delta = 0 */
  }
  if (!st)
    st = write_outputs(ctx, name, &t,
                       "set title 'Force-overlap of the simplified JKR contact, PSL on quartz, "
                       "E_mod/E = 0.1 (H Fig. 3)'\n"
                       "set xlabel 'overlap delta (nm)'\nset ylabel 'normal force F (uN), "
                       "positive repulsive'\nset grid\nset key top left\nset xzeroaxis lt -1\n"
                       "plot @CSV@ skip 1 using ($1*1e9):($2*1e6) with lines lw 2 title "
                       "'original (E, gamma)', \\\n"
                       "  @CSV@ skip 1 using ($1*1e9):($3*1e6) with lines lw 2 dt 3 title "
                       "'E reduced, gamma kept', \\\n"
                       "  @CSV@ skip 1 using ($1*1e9):($4*1e6) with lines lw 2 dt 2 title "
                       "'E and gamma reduced by H24'\n",
                       err);
  adem_table_free(&t);
  if (st) return st;
  double kept = area[2] / area[0], eonly = area[1] / area[0];
  double quad_err = 0.0;
  for (int c = 0; c < 3; ++c) quad_err = fmax(quad_err, fabs(area[c] / area_exact[c] - 1.0));
  snprintf(rep->claim, sizeof rep->claim,
           "H Fig. 3 and section 3.1: reducing E alone keeps the pull-off force (8/9)F_C but "
           "enlarges the area of the attractive part (the separation energy, H23); reducing E and "
           "gamma by H24 lowers the pull-off force by f^(2/5) and keeps the area.");
  snprintf(rep->measured, sizeof rep->measured,
           "f = 0.1: attractive area (trapezoid, %d intervals) original %.5g J, E reduced %.5g J "
           "(x%.4f; f^(-2/3) = %.4f), H24 %.5g J (x%.8f). Pull-off force original %.4g N, E "
           "reduced %.4g N, H24 %.4g N (x%.5f; f^(2/5) = %.5f). Quadrature vs closed form: %.1e.",
           nint, area[0], area[1], eonly, pow(f, -2.0 / 3.0), area[2], kept, pull[0], pull[1],
           pull[2], pull[2] / pull[0], pow(f, 0.4), quad_err);
  snprintf(rep->notes, sizeof rep->notes,
           "Pure evaluation of the contact law (H8-H10, closed-form a(delta)) for the PSL-on-quartz "
           "values of Fig. 5 (R = 0.635 um, E = 271 MPa, gamma = 0.11 J/m^2); the paper does not "
           "give the f of its Fig. 3, f = 0.1 is used. The simplified model has no neck: the "
           "curves start at delta = 0 with F = -(8/9)F_C.");
  rep->pass = fabs(kept - 1.0) < 1e-6 && fabs(pull[1] / pull[0] - 1.0) < 1e-12 &&
              fabs(pull[2] / pull[0] / pow(f, 0.4) - 1.0) < 1e-9 &&
              fabs(eonly / pow(f, -2.0 / 3.0) - 1.0) < 1e-6;
  return ADEM_OK;
}

/* ------------------------------------------------------------------ Fig. 5 */

enum { FIG5_COLS = 5 }; /* H24 at f = 1, 0.1, 0.01; gamma kept at f = 0.1, 0.01 */

static adem_collision_spec fig5_spec(int col, double v, double steps) {
  static const double f[FIG5_COLS] = {1.0, 0.1, 0.01, 0.1, 0.01};
  adem_collision_spec s = psl_on_quartz(f[col], col >= NF, v);
  s.steps_per_tc = steps;
  return s;
}

static adem_status fig5(const adem_validation_context *ctx, const char *name,
                        adem_validation_report *rep, adem_error *err) {
  size_t nv = ctx->quick ? 12 : 60;
  size_t n = nv * FIG5_COLS;
  adem_collision_spec *sp = malloc(n * sizeof *sp);
  adem_collision_result *res = malloc(n * sizeof *res);
  if (!sp || !res) {
    free(sp);
    free(res);
    return nomem(err);
  }
  for (size_t k = 0; k < nv; ++k)
    for (int c = 0; c < FIG5_COLS; ++c) sp[k * FIG5_COLS + c] = fig5_spec(c, log_point(0.5, 20.0, k, nv), steps_per_tc(ctx));
  adem_collide_many(sp, res, n, ctx->nthreads);
  /* With E reduced 100 times and gamma kept, fast spheres flatten to their centre: those
   * collisions cannot be run and are left out (NaN); any other failure is an error. */
  adem_status st = ADEM_OK;
  size_t lost = 0;
  for (size_t k = 0; k < n && !st; ++k) {
    if (!res[k].status) continue;
    if (k % FIG5_COLS >= NF && res[k].status == ADEM_ERR_RUNTIME) {
      res[k].e_eff = NAN;
      ++lost;
    } else {
      st = batch_status(&res[k], 1, err);
    }
  }
  /* Capture speed: the scan brackets it, multisection narrows it. */
  double vc[FIG5_COLS];
  for (int c = 0; c < FIG5_COLS && !st; ++c) {
    vc[c] = NAN;
    size_t lo = nv, hi = nv; /* last stuck speed, first rebound after it (runs that worked) */
    for (size_t k = 0; k < nv; ++k) {
      const adem_collision_result *r = &res[k * FIG5_COLS + c];
      if (r->status) continue;
      if (r->stuck) lo = k, hi = nv;
      else if (lo < nv && hi == nv) hi = k;
    }
    if (lo == nv) continue;
    if (hi == nv) { /* no rebound among the runs that worked: a lower bound */
      vc[c] = -sp[lo * FIG5_COLS].speed;
      continue;
    }
    adem_collision_spec base = fig5_spec(c, 1.0, steps_per_tc(ctx));
    st = adem_collide_threshold(&base, set_speed, NULL, sp[lo * FIG5_COLS].speed,
                                sp[hi * FIG5_COLS].speed, ctx->quick ? 1e-4 : 1e-6, ctx->nthreads,
                                &vc[c], err);
  }
  adem_table t;
  if (!st && adem_table_init(&t, "v_impact_m_s,e_eff_f1,e_eff_f0.1,e_eff_f0.01,"
                                 "e_eff_f0.1_gamma_kept,e_eff_f0.01_gamma_kept"))
    st = nomem(err);
  double dmax = 0.0, e_top = 0.0;
  if (!st) {
    for (size_t k = 0; k < nv && !st; ++k) {
      const adem_collision_result *r = &res[k * FIG5_COLS];
      double row[1 + FIG5_COLS] = {sp[k * FIG5_COLS].speed};
      for (int c = 0; c < FIG5_COLS; ++c) row[1 + c] = r[c].e_eff;
      for (int c = 1; c < NF; ++c) dmax = fmax(dmax, fabs(r[c].e_eff - r[0].e_eff));
      e_top = r[0].e_eff;
      if (adem_table_add(&t, row)) st = nomem(err);
    }
    char body[2048];
    snprintf(body, sizeof body,
             "set title 'PSL sphere (1.27 um) on quartz: effective restitution (H Fig. 5)'\n"
             "set xlabel 'impact speed v (m/s)'\nset ylabel 'e_eff = v_out/v_in'\nset logscale x\n"
             "set xrange [0.5:20]\nset yrange [0:1]\nset grid\nset key bottom right\n"
             "set arrow from %g, graph 0 to %g, graph 1 nohead dt 3 lc rgb 'gray40'\n"
             "plot @CSV@ skip 1 using 1:2 with lines lw 3 title 'E_mod/E = 1', \\\n"
             "  @CSV@ skip 1 using 1:3 with points pt 6 ps 1.2 title 'E_mod/E = 0.1, gamma by H24', \\\n"
             "  @CSV@ skip 1 using 1:4 with points pt 2 ps 1.2 title 'E_mod/E = 0.01, gamma by H24', \\\n"
             "  @CSV@ skip 1 using 1:5 with lines dt 2 lc rgb 'gray50' title 'E_mod/E = 0.1, gamma kept', \\\n"
             "  @CSV@ skip 1 using 1:6 with lines dt 4 lc rgb 'gray30' title 'E_mod/E = 0.01, gamma kept'\n",
             vc[0], vc[0]);
    st = write_outputs(ctx, name, &t, body, err);
    adem_table_free(&t);
  }
  free(sp);
  free(res);
  if (st) return st;
  char kept[2][64];
  for (int c = NF; c < FIG5_COLS; ++c) {
    if (vc[c] < 0.0) /* only a lower bound was found */
      snprintf(kept[c - NF], sizeof kept[0], "above %.3f m/s (%.2fx)", -vc[c], -vc[c] / vc[0]);
    else
      snprintf(kept[c - NF], sizeof kept[0], "%.3f m/s (%.2fx)", vc[c], vc[c] / vc[0]);
  }
  double lo = fmin(vc[0], fmin(vc[1], vc[2])), hi = fmax(vc[0], fmax(vc[1], vc[2]));
  double spread = hi / lo - 1.0;
  snprintf(rep->claim, sizeof rep->claim,
           "H Fig. 5 and section 4: with gamma_mod = gamma (E_mod/E)^(2/5) (H24) the effective "
           "restitution of a 1.27 um PSL sphere on quartz is the same for E_mod/E = 1, 0.1 and "
           "0.01 at every impact speed, and so is the capture (critical sticking) speed.");
  snprintf(rep->measured, sizeof rep->measured,
           "%zu speeds 0.5-20 m/s: largest |e_eff(f) - e_eff(1)| = %.2e; capture speed (bisection) "
           "%.5f, %.5f, %.5f m/s for f = 1, 0.1, 0.01 (spread %.2e); e_eff(20 m/s) = %.4f (e = "
           "0.86). With E reduced and gamma kept the capture speed is %s for f = 0.1 and %s for "
           "f = 0.01 (v_c^2 ~ gamma^(5/3) E^(-2/3) predicts f^(-1/3) = 2.15x and 4.64x).",
           nv, dmax, vc[0], vc[1], vc[2], spread, e_top, kept[0], kept[1]);
  snprintf(rep->notes, sizeof rep->notes,
           "Dahneke's (1975) measurements are not available as numbers: the plot shows the model "
           "only. Normal impact on a rigid wall, the sphere's E set so that E/(1-nu^2) = 271 MPa "
           "(nu = 0.3), rho = 1026 kg/m^3, gamma = 0.11 J/m^2, e = 0.86; the wall carries the same "
           "f so that the pair's gamma is gamma f^(2/5). %g steps per collision time; captured = "
           "the contact's normal energy (kinetic + JKR) is below its value at delta = 0, so it "
           "cannot break. %zu gamma-kept collisions (f = 0.01, fast) overlapped by the whole radius "
           "and are left out. Pass: spread of e_eff < 0.005 and of the capture speed < 1%%, and "
           "the gamma-kept runs capture above 1.05x the real capture speed.",
           steps_per_tc(ctx), lost);
  rep->pass = dmax < 0.005 && spread < 0.01 && fabs(vc[3]) / vc[0] > 1.05 &&
              fabs(vc[4]) / vc[0] > 1.05;
  return ADEM_OK;
}

/* ------------------------------------------------------------------ Figs. 7 and 8 */

enum { NAD = 6 };
static const double fig7_ad[NAD] = {1.0, 2.0, 5.0, 10.0, 20.0, 50.0};
static const double LAMBDA0 = 1e6; /* base of Fig. 8 */

/* Two equal spheres head-on (H Fig. 6): r = 1 um, rho = 1000 kg/m^3, v = 1 m/s, e = 0.3; E and
 * gamma follow from lambda and Ad (text definitions). */
static adem_collision_spec pair_spec(double lambda, double ad, double steps) {
  adem_collision_spec s = adem_default_collision_spec();
  s.steps_per_tc = steps;
  s.kind = ADEM_COLLISION_PAIR;
  s.radius = 1e-6;
  s.density = 1000.0;
  s.speed = 1.0;
  s.restitution = 0.3;
  s.poisson = 0.3;
  adem_collide_set_lambda(&s, lambda);
  adem_collide_set_ad(&s, ad);
  return s;
}

/* Fig. 8: the material of lambda0 and Ad, made stiffer or softer to lambda with H24 applied to
 * gamma (what stiffness_factor = lambda/lambda0 does for lambda <= lambda0). */
static adem_collision_spec pair_spec_h24(double lambda, double ad0, double steps) {
  adem_collision_spec s = pair_spec(LAMBDA0, ad0, steps);
  double f = lambda / LAMBDA0;
  adem_collide_set_lambda(&s, lambda);
  s.surface_energy *= pow(f, 0.4); /* H24 */
  return s;
}

static adem_status ehat_table(const adem_validation_context *ctx, bool h24, size_t nl,
                              adem_collision_spec **sp_out, adem_collision_result **res_out,
                              adem_error *err) {
  size_t n = nl * NAD;
  adem_collision_spec *sp = malloc(n * sizeof *sp);
  adem_collision_result *res = malloc(n * sizeof *res);
  if (!sp || !res) {
    free(sp);
    free(res);
    return nomem(err);
  }
  for (size_t k = 0; k < nl; ++k)
    for (int a = 0; a < NAD; ++a) {
      double lambda = log_point(1e2, 1e7, k, nl);
      sp[k * NAD + a] = h24 ? pair_spec_h24(lambda, fig7_ad[a], steps_per_tc(ctx))
                             : pair_spec(lambda, fig7_ad[a], steps_per_tc(ctx));
    }
  adem_collide_many(sp, res, n, ctx->nthreads);
  *sp_out = sp;
  *res_out = res;
  return batch_status(res, n, err);
}

static const char *fig78_header =
    "lambda,ehat_Ad1,ehat_Ad2,ehat_Ad5,ehat_Ad10,ehat_Ad20,ehat_Ad50";

static adem_status fig78_write(const adem_validation_context *ctx, const char *name, bool h24,
                               size_t nl, const adem_collision_spec *sp,
                               const adem_collision_result *res, adem_error *err) {
  adem_table t;
  if (adem_table_init(&t, fig78_header)) return nomem(err);
  adem_status st = ADEM_OK;
  for (size_t k = 0; k < nl && !st; ++k) {
    double row[1 + NAD];
    row[0] = adem_collide_lambda(&sp[k * NAD]);
    for (int a = 0; a < NAD; ++a) row[1 + a] = res[k * NAD + a].e_eff / sp[k * NAD + a].restitution;
    if (adem_table_add(&t, row)) st = nomem(err);
  }
  char body[3072];
  int len = snprintf(body, sizeof body,
                     "set title '%s'\nset xlabel 'elasticity lambda = E/(rho v^2)'\n"
                     "set ylabel 'scaled restitution e_eff/e'\nset logscale x\nset xrange [1e2:1e7]\n"
                     "set yrange [0:1.05]\nset grid\nset key outside right\nplot ",
                     h24 ? "Head-on pairs, gamma rescaled by H24 from lambda = 1e6, e = 0.3 (H Fig. 8)"
                         : "Head-on pairs, e = 0.3 (H Fig. 7); Ad = 3 gamma/(rho v^2 r) (text)");
  for (int a = 0; a < NAD && len < (int)sizeof body; ++a)
    len += snprintf(body + len, sizeof body - (size_t)len,
                    "@CSV@ skip 1 using 1:%d with linespoints pt 7 ps 0.6 lw 2 title 'Ad = %g%s'%s",
                    a + 2, fig7_ad[a], h24 ? " at 1e6" : "", a + 1 < NAD ? ", \\\n  " : "\n");
  if (!st) st = write_outputs(ctx, name, &t, body, err);
  adem_table_free(&t);
  return st;
}

static adem_status fig7(const adem_validation_context *ctx, const char *name,
                        adem_validation_report *rep, adem_error *err) {
  size_t nl = ctx->quick ? 11 : 41;
  adem_collision_spec *sp = NULL;
  adem_collision_result *res = NULL;
  adem_status st = ehat_table(ctx, false, nl, &sp, &res, err);
  if (!st) st = fig78_write(ctx, name, false, nl, sp, res, err);
  /* Critical lambda per Ad: the grid brackets it, bisection narrows it. */
  double lc[NAD], sx = 0, sy = 0, sxx = 0, sxy = 0;
  int nfit = 0;
  bool monotonic = true;
  for (int a = 0; a < NAD && !st; ++a) {
    lc[a] = NAN;
    for (size_t k = 0; k + 1 < nl; ++k)
      if (res[k * NAD + a].stuck && !res[(k + 1) * NAD + a].stuck) {
        adem_collision_spec base = pair_spec(1e6, fig7_ad[a], steps_per_tc(ctx));
        st = adem_collide_threshold(&base, set_lambda, NULL, adem_collide_lambda(&sp[k * NAD + a]),
                                    adem_collide_lambda(&sp[(k + 1) * NAD + a]),
                                    ctx->quick ? 1e-3 : 1e-5, ctx->nthreads, &lc[a], err);
        break;
      }
    if (st || isnan(lc[a])) continue;
    double x = log(fig7_ad[a]), y = log(lc[a]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++nfit;
    if (a > 0 && !isnan(lc[a - 1]) && !(lc[a] > lc[a - 1])) monotonic = false;
  }
  double slope = nfit >= 2 ? (nfit * sxy - sx * sy) / (nfit * sxx - sx * sx) : NAN;
  double c = nfit >= 1 ? exp((sy - slope * sx) / nfit) : NAN;
  /* ehat at the stiffest point of the least adhesive curve, and the change along it */
  double ehat_top = 0.0, ehat_low = 1.0;
  if (!st) {
    ehat_top = res[(nl - 1) * NAD].e_eff / 0.3;
    for (size_t k = 0; k < nl; ++k)
      if (!res[k * NAD].stuck) {
        ehat_low = res[k * NAD].e_eff / 0.3;
        break;
      }
  }
  free(sp);
  free(res);
  if (st) return st;
  char list[512] = "";
  for (int a = 0, len = 0; a < NAD; ++a)
    len += snprintf(list + len, sizeof list - (size_t)len, "%s%g: %.4g", a ? ", " : "",
                    fig7_ad[a], lc[a]);
  snprintf(rep->claim, sizeof rep->claim,
           "H Fig. 7 and section 5.2: head-on pairs stay attached below a critical elasticity "
           "lambda_crit that grows with Ad (lambda_crit = c Ad^(5/2), H25); above it e_eff/e rises "
           "towards 1, so with gamma kept a change of stiffness changes the outcome.");
  snprintf(rep->measured, sizeof rep->measured,
           "%zu lambdas 1e2-1e7 x %d Ad. lambda_crit (bisection) for Ad = %s. Fit: lambda_crit = "
           "%.4g Ad^%.5f. Least adhesive curve (Ad = 1): e_eff/e from %.3f just above lambda_crit to "
           "%.4f at 1e7.",
           nl, NAD, list, c, slope, ehat_low, ehat_top);
  snprintf(rep->notes, sizeof rep->notes,
           "Ad is the text's 3 gamma/(rho v^2 r) (1+b^3)/((1+b^2) b) with b = 1 (notes section 7), "
           "not the caption's gamma/(rho v^2 R), which is 2/3 of it for equal spheres. The paper's "
           "Ad values are not given: these are chosen so that lambda_crit falls in the plotted "
           "range. r = 1 um, rho = 1000 kg/m^3, v = 1 m/s, nu = 0.3, e = 0.3. Pass: lambda_crit "
           "grows with Ad and the fitted exponent is 5/2 within 0.05.");
  rep->pass = monotonic && nfit >= 3 && fabs(slope - 2.5) < 0.05;
  return ADEM_OK;
}

static adem_status fig8(const adem_validation_context *ctx, const char *name,
                        adem_validation_report *rep, adem_error *err) {
  size_t nl = ctx->quick ? 11 : 41;
  adem_collision_spec *sp = NULL;
  adem_collision_result *res = NULL;
  adem_status st = ehat_table(ctx, true, nl, &sp, &res, err);
  if (!st) st = fig78_write(ctx, name, true, nl, sp, res, err);
  /* reference: the same Ad at lambda0 exactly */
  adem_collision_spec ref_sp[NAD];
  adem_collision_result ref[NAD];
  for (int a = 0; a < NAD; ++a) ref_sp[a] = pair_spec(LAMBDA0, fig7_ad[a], steps_per_tc(ctx));
  if (!st) {
    adem_collide_many(ref_sp, ref, NAD, ctx->nthreads);
    st = batch_status(ref, NAD, err);
  }
  double dev[NAD] = {0}, worst = 0.0;
  bool same_outcome = true;
  for (int a = 0; a < NAD && !st; ++a)
    for (size_t k = 0; k < nl; ++k) {
      const adem_collision_result *r = &res[k * NAD + a];
      dev[a] = fmax(dev[a], fabs(r->e_eff - ref[a].e_eff) / 0.3);
      if (r->stuck != ref[a].stuck) same_outcome = false;
    }
  for (int a = 0; a < NAD; ++a) worst = fmax(worst, dev[a]);
  free(sp);
  free(res);
  if (st) return st;
  char list[512] = "";
  for (int a = 0, len = 0; a < NAD; ++a)
    len += snprintf(list + len, sizeof list - (size_t)len, "%s%g: %.4f (max dev %.1e)",
                    a ? ", " : "", fig7_ad[a], ref[a].e_eff / 0.3, dev[a]);
  snprintf(rep->claim, sizeof rep->claim,
           "H Fig. 8 and section 5.2: when the stiffness is changed from lambda = 1e6 and gamma "
           "follows H24, e_eff/e keeps its value at lambda = 1e6 for every lambda in 1e2-1e7.");
  snprintf(rep->measured, sizeof rep->measured,
           "%zu lambdas x %d Ad; e_eff/e at lambda = 1e6 and largest deviation over lambda: Ad = "
           "%s. Worst deviation %.2e; stick/rebound outcome %s.",
           nl, NAD, list, worst, same_outcome ? "the same everywhere" : "CHANGES");
  snprintf(rep->notes, sizeof rep->notes,
           "Ad is the value at lambda = 1e6 (text definition, notes section 7); at lambda the "
           "surface energy is gamma (lambda/1e6)^(2/5). For lambda > 1e6 this is a stiffer "
           "material (f > 1), which stiffness_factor does not allow, so E and gamma are set "
           "directly. Pass: deviation < 0.005 and the same outcome everywhere.");
  rep->pass = worst < 0.005 && same_outcome;
  return ADEM_OK;
}

/* ------------------------------------------------------------------ Fig. 13 */

typedef struct trace {
  size_t n, cap;
  double *t, *v;
  bool oom;
} trace;

static void trace_sample(double t, double overlap, double v_n, double force_n, void *user) {
  (void)overlap;
  (void)force_n;
  trace *tr = user;
  if (tr->n == tr->cap) {
    size_t cap = tr->cap ? 2 * tr->cap : 1024;
    double *a = realloc(tr->t, cap * sizeof *a);
    if (a) tr->t = a;
    double *b = a ? realloc(tr->v, cap * sizeof *b) : NULL;
    if (b) tr->v = b;
    if (!a || !b) {
      tr->oom = true;
      return;
    }
    tr->cap = cap;
  }
  tr->t[tr->n] = t;
  tr->v[tr->n] = -v_n; /* velocity along the wall normal: < 0 towards the wall */
  tr->n++;
}

/* Velocity at time t (linear between samples, constant outside). */
static double trace_at(const trace *tr, double t, double v_before) {
  if (tr->n == 0 || t < tr->t[0]) return v_before;
  if (t >= tr->t[tr->n - 1]) return tr->v[tr->n - 1];
  size_t lo = 0, hi = tr->n - 1;
  while (hi - lo > 1) {
    size_t mid = (lo + hi) / 2;
    if (tr->t[mid] <= t) lo = mid;
    else hi = mid;
  }
  double w = (t - tr->t[lo]) / (tr->t[hi] - tr->t[lo]);
  return tr->v[lo] + w * (tr->v[hi] - tr->v[lo]);
}

static adem_status fig13(const adem_validation_context *ctx, const char *name,
                         adem_validation_report *rep, adem_error *err) {
  const double v0 = 5.0;
  trace tr[NF];
  memset(tr, 0, sizeof tr);
  adem_collision_spec sp[NF];
  adem_collision_result res[NF];
  for (int k = 0; k < NF; ++k) {
    sp[k] = psl_on_quartz(stiffness[k], false, v0);
    sp[k].steps_per_tc = steps_per_tc(ctx);
    sp[k].sample = trace_sample;
    sp[k].sample_user = &tr[k];
  }
  adem_collide_many(sp, res, NF, ctx->nthreads);
  adem_status st = batch_status(res, NF, err);
  for (int k = 0; k < NF && !st; ++k) {
    if (tr[k].oom) st = nomem(err);
    else if (res[k].stuck)
      st = adem_error_set(err, ADEM_ERR_RUNTIME, "the sphere stuck at 5 m/s (f = %g)", stiffness[k]);
  }
  adem_table t;
  if (!st && adem_table_init(&t, "time_ns,v_normal_f1_m_s,v_normal_f0.1_m_s,v_normal_f0.01_m_s"))
    st = nomem(err);
  if (!st) {
    double T = res[NF - 1].duration;
    int n = ctx->quick ? 200 : 700;
    for (int i = 0; i <= n && !st; ++i) {
      double tt = -0.1 * T + 1.4 * T * i / n; /* time since the first touch */
      double row[1 + NF] = {tt * 1e9};
      for (int k = 0; k < NF; ++k) row[1 + k] = trace_at(&tr[k], tt + res[k].t_touch, -v0);
      if (adem_table_add(&t, row)) st = nomem(err);
    }
    if (!st)
      st = write_outputs(ctx, name, &t,
                         "set title 'PSL sphere on quartz at 5 m/s: velocity during the impact "
                         "(H Fig. 13)'\nset xlabel 'time since first contact (ns)'\n"
                         "set ylabel 'velocity normal to the wall (m/s)'\nset grid\n"
                         "set key bottom right\n"
                         "plot @CSV@ skip 1 using 1:2 with lines lw 2 title 'E_mod/E = 1', \\\n"
                         "  @CSV@ skip 1 using 1:3 with lines lw 2 dt 2 title 'E_mod/E = 0.1', \\\n"
                         "  @CSV@ skip 1 using 1:4 with lines lw 2 dt 3 title 'E_mod/E = 0.01'\n",
                         err);
    adem_table_free(&t);
  }
  for (int k = 0; k < NF; ++k) {
    free(tr[k].t);
    free(tr[k].v);
  }
  if (st) return st;
  double r1 = res[1].duration / res[0].duration, r2 = res[2].duration / res[0].duration;
  double dv = fmax(fabs(res[1].v_n_out / res[0].v_n_out - 1.0),
                   fabs(res[2].v_n_out / res[0].v_n_out - 1.0));
  snprintf(rep->claim, sizeof rep->claim,
           "H Fig. 13 and section 6.2: a PSL sphere hitting quartz at 5 m/s leaves with the same "
           "speed for E_mod/E = 1, 0.1 and 0.01 (gamma by H24), while the contact lasts "
           "(E/E_mod)^(2/5) times longer: 10^0.4 = 2.512 and 10^0.8 = 6.310.");
  snprintf(rep->measured, sizeof rep->measured,
           "rebound speed %.5f, %.5f, %.5f m/s (largest relative difference %.1e); contact "
           "duration %.4g, %.4g, %.4g ns; ratios %.4f and %.4f (%+.3f%% and %+.3f%% from 10^0.4 "
           "and 10^0.8).",
           res[0].v_n_out, res[1].v_n_out, res[2].v_n_out, dv, res[0].duration * 1e9,
           res[1].duration * 1e9, res[2].duration * 1e9, r1, r2,
           100.0 * (r1 / pow(10.0, 0.4) - 1.0), 100.0 * (r2 / pow(10.0, 0.8) - 1.0));
  snprintf(rep->notes, sizeof rep->notes,
           "Parameters of Fig. 5 (rigid wall, effective E = 271 MPa). Duration: from the first "
           "touch to the separation, both interpolated at delta = 0. In the simplified JKR model "
           "with H24 every time scale of the contact scales as f^(-2/5) (H appendix A), so the "
           "ratio is exact up to the time step. Pass: rebound speeds within 0.5%% and both ratios "
           "within 2%%.");
  rep->pass = dv < 0.005 && fabs(r1 / pow(10.0, 0.4) - 1.0) < 0.02 &&
              fabs(r2 / pow(10.0, 0.8) - 1.0) < 0.02;
  return ADEM_OK;
}

const adem_validation adem_validations_haervig[] = {
    {"haervig-fig3", "Haervig et al. 2017, Fig. 3",
     "force-overlap curves: original, E reduced, E and gamma reduced (H24)", fig3},
    {"haervig-fig5", "Haervig et al. 2017, Fig. 5",
     "effective restitution against impact speed, PSL on quartz, E_mod/E = 1, 0.1, 0.01", fig5},
    {"haervig-fig7", "Haervig et al. 2017, Fig. 7",
     "head-on pairs: e_eff/e against lambda at several Ad, e = 0.3", fig7},
    {"haervig-fig8", "Haervig et al. 2017, Fig. 8",
     "head-on pairs with gamma rescaled by H24 from lambda = 1e6", fig8},
    {"haervig-fig13", "Haervig et al. 2017, Fig. 13",
     "velocity against time, PSL on quartz at 5 m/s, E_mod/E = 1, 0.1, 0.01", fig13},
};
const size_t adem_validations_haervig_count =
    sizeof adem_validations_haervig / sizeof adem_validations_haervig[0];
