/* Contact histories across a change of laws (history_switch.h; docs/models.md, "Laws switched
 * under live contacts"). */
#include <stdlib.h>
#include <string.h>

#include "adem/laws.h"
#include "history_switch.h"
#include "materials.h"

/* What a law's history holds (its row's .history_kind; "" for none known). */
static const char *kind(adem_law_slot slot, int law) {
  const adem_law *row = adem_law_get(slot, law);
  return row ? row->history_kind : "";
}

/* The tangential spring's energy as its law stores it (the same expressions as the laws':
 * tangential.h), with S_t the stiffness the history was stored with: the spring force F_s
 * (incremental) or the displacement xi (total); 0 for a history it does not know. */
static double tangential_energy(const adem_contact_history *h, int law) {
  double S = h->tangential_aux;
  if (!(S > 0.0)) return 0.0;
  const char *k = kind(ADEM_SLOT_TANGENTIAL, law);
  if (!strcmp(k, "spring_force")) return 0.5 * v3_norm2(h->tangential) / S;
  if (!strcmp(k, "displacement")) return 0.5 * S * v3_norm2(h->tangential);
  return 0.0;
}

/* Rolling laws whose histories are the same quantity: a kind in common (model C and its capped
 * form keep the spring torque with the same stiffness and limit). */
static bool same_rolling_history(int a, int b) {
  const char *ka = kind(ADEM_SLOT_ROLLING, a), *kb = kind(ADEM_SLOT_ROLLING, b);
  return a == b || (ka[0] && !strcmp(ka, kb));
}

static bool tangential_known(const char *k) {
  return !strcmp(k, "spring_force") || !strcmp(k, "displacement");
}

double adem_history_switch(adem_contact_history *h, int tangential_old, int tangential_new,
                           int rolling_old, int rolling_new, bool *cleared) {
  double before = h->elastic;
  double e_t = tangential_energy(h, tangential_old);
  double e_r = before - e_t > 0.0 ? before - e_t : 0.0; /* the rolling spring's, the rest */
  double lost = 0.0;
  *cleared = false;
  if (tangential_old != tangential_new) {
    /* incremental: F_s = -S_t xi, with the S_t it was stored with (H14); exact both ways */
    double S = h->tangential_aux;
    const char *ko = kind(ADEM_SLOT_TANGENTIAL, tangential_old);
    const char *kn = kind(ADEM_SLOT_TANGENTIAL, tangential_new);
    if (tangential_known(ko) && tangential_known(kn) && S > 0.0) {
      if (strcmp(ko, kn)) /* xi = -F_s / S_t, F_s = -S_t xi */
        h->tangential = !strcmp(kn, "displacement") ? v3_scale(h->tangential, -1.0 / S)
                                                    : v3_scale(h->tangential, -S);
    } else if (v3_norm2(h->tangential) > 0.0 || e_t > 0.0) {
      h->tangential = v3_zero();
      h->tangential_aux = 0.0;
      lost += e_t;
      *cleared = true;
    }
  }
  if (!same_rolling_history(rolling_old, rolling_new) && v3_norm2(h->rolling) > 0.0) {
    h->rolling = v3_zero();
    lost += e_r;
    *cleared = true;
  }
  h->elastic = before - lost > 0.0 ? before - lost : 0.0;
  return lost;
}

int *adem_history_laws(const adem_materials *mt) {
  size_t n = (size_t)mt->n * (size_t)mt->n;
  int *laws = malloc((2 * n > 0 ? 2 * n : 1) * sizeof *laws);
  if (!laws) return NULL;
  for (size_t k = 0; k < n; ++k) {
    laws[2 * k] = mt->pairs ? (int)mt->pairs[k].tangential : -1;
    laws[2 * k + 1] = mt->pairs ? (int)mt->pairs[k].rolling : -1;
  }
  return laws;
}

/* One contact of materials a and b; the energy that went. */
static double switch_one(const adem_materials *mt, const int *old, int a, int b,
                         adem_contact_history *h, size_t *cleared) {
  size_t k = (size_t)a * (size_t)mt->n + (size_t)b;
  if (old[2 * k] < 0) return 0.0;
  const adem_interaction *it = adem_materials_pair(mt, a, b);
  bool c = false;
  double lost = adem_history_switch(h, old[2 * k], (int)it->tangential, old[2 * k + 1],
                                    (int)it->rolling, &c);
  *cleared += c;
  return lost;
}

size_t adem_history_switch_all(const adem_materials *mt, const int *old, adem_particles *p,
                               adem_pair_list *pp, adem_pair_list *pw, adem_mesh_pairs *pm,
                               const adem_walls *walls, bool balance) {
  size_t cleared = 0;
  for (size_t k = 0; k < pp->n; ++k) {
    if (!pp->touching[k]) continue;
    size_t i = pp->a[k], j = pp->b[k];
    double lost = switch_one(mt, old, p->material[i], p->material[j], &pp->hist[adem_pairs_slot(pp, k)], &cleared);
    if (balance && lost > 0.0) {
      p->dissipated[i] += 0.5 * lost;
      p->dissipated[j] += 0.5 * lost;
    }
  }
  for (size_t k = 0; k < pw->n; ++k) {
    if (!pw->touching[k]) continue;
    size_t i = pw->a[k];
    int wm = walls->planes[pw->b[k]].def.material;
    double lost = switch_one(mt, old, p->material[i], wm, &pw->hist[k], &cleared);
    if (balance && lost > 0.0) p->dissipated[i] += lost;
  }
  adem_pair_list *l = &pm->l; /* a particle's slots: start[i] .. start[i + 1], touching first */
  for (size_t i = 0; i < p->n && walls->mesh.ntris > 0 && pm->start; ++i)
    for (size_t k = pm->start[i]; k < pm->start[i + 1] && l->touching[k]; ++k) {
      int wm = walls->mesh.groups[walls->mesh.group[pm->owner[k]]].material;
      double lost = switch_one(mt, old, p->material[i], wm, &l->hist[k], &cleared);
      if (balance && lost > 0.0) p->dissipated[i] += lost;
    }
  return cleared;
}
