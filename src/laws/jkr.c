/* The simplified JKR law's cold path (law_hooks.h): what a JKR pair implies (notes sections 1, 5,
 * 6; H section 6.2), its collision time, pull-off force, check and report lines. */
#include "jkr.h"

#include <math.h>
#include <stdio.h>

#include "adem/laws.h"
#include "adem/vec3.h"
#include "law_hooks.h"

adem_jkr_pair_summary adem_jkr_pair_summarize(double E, double E_mod, double gamma,
                                              double gamma_mod, double R, double mstar,
                                              double v_ref) {
  adem_jkr_pair_summary s;
  s.R = R;
  s.mstar = mstar;
  s.E = E;
  s.E_mod = E_mod;
  s.gamma = gamma;
  s.gamma_mod = gamma_mod;
  s.a0 = adem_jkr_a0(gamma, R, E); /* H7 */
  s.a0_mod = adem_jkr_a0(gamma_mod, R, E_mod);
  s.delta_eq = s.a0 * s.a0 / (3.0 * R);
  s.delta_eq_mod = s.a0_mod * s.a0_mod / (3.0 * R);
  s.f_c = adem_jkr_critical_force(gamma, R);
  s.f_c_mod = adem_jkr_critical_force(gamma_mod, R);
  s.pull_off = 8.0 / 9.0 * s.f_c;
  s.pull_off_mod = 8.0 / 9.0 * s.f_c_mod;
  const double D = ADEM_TABOR_DMIN;
  s.tabor = adem_dmath_cbrt(4.0 * R * gamma * gamma / (E * E * D * D * D)); /* H1 */
  s.t_c = adem_hertz_collision_time(mstar, R, E, v_ref);
  s.t_c_mod = adem_hertz_collision_time(mstar, R, E_mod, v_ref);
  s.dt = s.t_c / 50.0; /* about 50 steps a collision (Silbert et al. 2001, used by H) */
  s.dt_mod = s.t_c_mod / 50.0;
  s.speedup = adem_dmath_pow(E / E_mod, 0.4);
  s.f_ext_max = ADEM_PULLOFF_SAFETY * s.pull_off_mod;
  return s;
}

/* Collision time (notes section 6). A simplified JKR contact speeds the spheres up to
 * sqrt(v_ref^2 + 2|U_min|/m*) as it pulls them in (U_min the JKR energy at equilibrium,
 * H7-H10), and once captured they oscillate about the equilibrium with the period
 * 2 pi sqrt(m* / (1.2 E a0)) (dF/d delta = 6 E a0/5 there): the shortest of t_c at that speed
 * and half that period. Without surface energy it is Hertz's. */
static double collision_time(const adem_pair_params *pp, double m_eff, double r_eff,
                             double v_ref) {
  if (!(pp->gamma > 0.0)) return adem_hertz_collision_time(m_eff, r_eff, pp->E, v_ref);
  double a0 = adem_jkr_a0(pp->gamma, r_eff, pp->E);
  double u_min = adem_jkr_energy(pp->gamma, r_eff, pp->E, a0); /* < 0 */
  double v = sqrt(v_ref * v_ref - 2.0 * u_min / m_eff);
  double t_osc = 2.0 * ADEM_PI * sqrt(m_eff / (1.2 * pp->E * a0));
  return fmin(adem_hertz_collision_time(m_eff, r_eff, pp->E, v), 0.5 * t_osc);
}

/* H section 6.2: under a reduced stiffness the force that breaks a contact is (8/9) F_C of the
 * modified surface energy, (8/9) 3 pi gamma_mod R. */
static double pull_off(const adem_pair_params *pp, double R) {
  return pp->gamma > 0.0 ? 8.0 / 9.0 * adem_jkr_critical_force(pp->gamma, R) : 0.0;
}

/* A surface energy on both materials: the pair's is the geometric mean of the two
 * (core/materials.c), so a side without one (typically a wall material) silently makes it
 * Hertz. An interaction's own surface energy is the pair's, 0 included (simplified JKR without
 * adhesion is Hertz). */
static const char *check(const adem_law_check *c, int *side, char *buf, size_t n) {
  const int k = ADEM_PARAM_SURFACE_ENERGY;
  if (!isnan(c->param_entry[k])) return NULL;
  const double v[2] = {c->param_a[k], c->param_b[k]};
  for (int s = 0; s < 2; ++s) {
    if (v[s] > 0.0) continue;
    char at[96] = "";
    if (c->where[s]) snprintf(at, sizeof at, " (at %.80s)", c->where[s]);
    snprintf(buf, n,
             "`%s` between `%s` and `%s` needs a surface energy on both materials (the pair's is "
             "the geometric mean of the two), but `%s`%s has surface_energy 0; give it a "
             "`surface_energy` > 0 (for a wall, the wall material's), give the interaction "
             "one, or use `normal: hertz`",
             c->law, c->name[0], c->name[1], c->name[s], at);
    *side = s;
    return buf;
  }
  return NULL;
}

/* What the pair implies at its smallest spheres: real and modified values side by side. */
static void report(const adem_law_report *r) {
  const adem_pair_params *pp = r->pp;
  char text[512];
  if (!(pp->gamma_real > 0.0)) {
    snprintf(text, sizeof text, "%s without surface energy: the contact is Hertz", r->law);
    r->line(r->ctx, text);
    return;
  }
  adem_jkr_pair_summary s =
      adem_jkr_pair_summarize(pp->E_real, pp->E, pp->gamma_real, pp->gamma, r->R, r->mstar, r->v_ref);
  char mod[64];
  snprintf(mod, sizeof mod, "modified (E_mod/E = %.3g)", pp->E / pp->E_real);
  snprintf(text, sizeof text,
           "simplified JKR (H7-H10) for the smallest spheres: R* = %.4g m, m* = %.4g kg", r->R,
           r->mstar);
  r->line(r->ctx, text);
  snprintf(text, sizeof text, "  %-36s %-12s %s", "", "real", mod);
  r->line(r->ctx, text);
  const struct {
    const char *label;
    double real, modified;
  } rows[] = {
      {"E* (Pa)", s.E, s.E_mod},
      {"gamma (J/m^2)", s.gamma, s.gamma_mod},
      {"a0 = (9 pi gamma R^2/E)^(1/3) (m)", s.a0, s.a0_mod},
      {"delta_eq = a0^2/(3R) (m)", s.delta_eq, s.delta_eq_mod},
      {"F_C = 3 pi gamma R (N)", s.f_c, s.f_c_mod},
      {"pull-off force (8/9) F_C (N)", s.pull_off, s.pull_off_mod},
      {"Hertz t_c at v_ref (s)", s.t_c, s.t_c_mod},
      {"time step t_c/50 (s)", s.dt, s.dt_mod},
  };
  for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k) {
    snprintf(text, sizeof text, "  %-36s %-12.4g %.4g", rows[k].label, rows[k].real,
             rows[k].modified);
    r->line(r->ctx, text);
  }
  snprintf(text, sizeof text, "  step speed-up (E/E_mod)^(2/5) = %.4g", s.speedup);
  r->line(r->ctx, text);
  snprintf(text, sizeof text,
           "  Tabor parameter lambda_T = %.3g (real material, D_min = 1.65e-10 m)%s", s.tabor,
           s.tabor < 3.0 ? ": below 3, JKR is outside its range (H1)" : ", JKR valid (> 3)");
  r->line(r->ctx, text);
  snprintf(text, sizeof text,
           "  external forces pulling these spheres apart must stay below %.3g N (%.0f%% of the "
           "modified pull-off force)",
           s.f_ext_max, 100.0 * ADEM_PULLOFF_SAFETY);
  r->line(r->ctx, text);
  if (s.tabor < 3.0) {
    snprintf(text, sizeof text,
             "%s: Tabor parameter %.3g is below 3: the JKR model is outside its range (H1); the "
             "contact is closer to DMT/Maugis",
             r->pair, s.tabor);
    r->warn(r->ctx, text);
  }
}

const adem_law_hooks adem_jkr_hooks = {.collision_time = collision_time,
                                       .pull_off = pull_off,
                                       .check = check,
                                       .report = report};
