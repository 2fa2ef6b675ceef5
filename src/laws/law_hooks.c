/* Each slot's row's cold-path hook, or its default (law_hooks.h). */
#include "law_hooks.h"

#include <math.h>
#include <stdio.h>

static const adem_law_hooks none = {0};

static const adem_law_hooks *hooks_of(adem_law_slot slot, int id) {
  const adem_law *law = adem_law_get(slot, id);
  return law && law->hooks ? law->hooks : &none;
}

static const adem_law_hooks *normal_hooks(adem_law_set laws) {
  return hooks_of(ADEM_SLOT_NORMAL, laws.normal);
}

void adem_laws_derive(adem_law_set laws, adem_pair_params *pp) {
  const int ids[4] = {laws.normal, laws.damping, laws.tangential, laws.rolling};
  for (int s = 0; s < 4; ++s) {
    const adem_law_hooks *h = hooks_of((adem_law_slot)s, ids[s]);
    if (h->derive) h->derive(pp);
  }
}

double adem_laws_collision_time(adem_law_set laws, const adem_pair_params *pp, double mstar,
                                double R, double v_ref) {
  const adem_law_hooks *h = normal_hooks(laws);
  if (h->collision_time) return h->collision_time(pp, mstar, R, v_ref);
  return adem_hertz_collision_time(mstar, R, pp->E, v_ref);
}

double adem_laws_pull_off(adem_law_set laws, const adem_pair_params *pp, double R) {
  const adem_law_hooks *h = normal_hooks(laws);
  return h->pull_off ? h->pull_off(pp, R) : 0.0;
}

double adem_laws_normal_beta(adem_law_set laws, const adem_pair_params *pp) {
  const adem_law_hooks *h = hooks_of(ADEM_SLOT_DAMPING, laws.damping);
  return h->normal_beta ? h->normal_beta(pp) : pp->beta;
}

void adem_laws_rolling_mode(adem_law_set laws, const adem_law_mode_input *in, double *k_theta,
                            double *zeta_r) {
  const adem_law_hooks *h = hooks_of(ADEM_SLOT_ROLLING, laws.rolling);
  *k_theta = *zeta_r = 0.0;
  if (h->rolling_mode) h->rolling_mode(in, k_theta, zeta_r);
}

bool adem_laws_need_rolling_inertia(adem_law_set laws, const adem_pair_params *pp) {
  const adem_law_hooks *h = hooks_of(ADEM_SLOT_ROLLING, laws.rolling);
  return h->needs_rolling_inertia && h->needs_rolling_inertia(pp);
}

const char *adem_laws_check(adem_law_set laws, const adem_law_check *c, adem_law_slot *slot,
                            int *side, char *buf, size_t n) {
  const int ids[4] = {laws.normal, laws.damping, laws.tangential, laws.rolling};
  for (int s = 0; s < 4; ++s) {
    const adem_law_hooks *h = hooks_of((adem_law_slot)s, ids[s]);
    adem_law_check cs = *c;
    cs.law = adem_law_get((adem_law_slot)s, ids[s])->name;
    *side = -1;
    *slot = (adem_law_slot)s;
    if (h->check && h->check(&cs, side, buf, n)) return buf;
  }
  return NULL;
}

void adem_laws_report(adem_law_set laws, const adem_law_report *r) {
  const int ids[4] = {laws.normal, laws.damping, laws.tangential, laws.rolling};
  for (int s = 0; s < 4; ++s) {
    const adem_law_hooks *h = hooks_of((adem_law_slot)s, ids[s]);
    adem_law_report rs = *r;
    rs.law = h->report ? adem_law_get((adem_law_slot)s, ids[s])->name : NULL;
    if (h->report) h->report(&rs);
  }
}

void adem_laws_friction_line(adem_law_set laws, const adem_law_report *r) {
  const adem_law_hooks *h = hooks_of(ADEM_SLOT_ROLLING, laws.rolling);
  if (h->friction_line) {
    adem_law_report rs = *r;
    rs.law = adem_law_get(ADEM_SLOT_ROLLING, laws.rolling)->name;
    h->friction_line(&rs);
    return;
  }
  char text[512];
  snprintf(text, sizeof text, "rolling friction eta_r = %g%s, R_r = r_i r_j/(r_i + r_j) (%s)",
           0.5 * (r->eta_a + r->eta_b), r->eta_a == r->eta_b ? "" : " (the mean)", r->from);
  r->line(r->ctx, text);
}

bool adem_laws_absolute_spin(int rolling) {
  const adem_law *law = adem_law_get(ADEM_SLOT_ROLLING, rolling);
  return law && law->absolute_spin;
}

double adem_law_param_mix(adem_law_param_id id, double a, double b) {
  return adem_law_param_get(id)->mixing == ADEM_MIX_GEOMETRIC ? sqrt(a * b) : 0.5 * (a + b);
}
