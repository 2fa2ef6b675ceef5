/* Materials and the table of material pairs (H2, H12, H15, H24). */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dmath.h"
#include "log.h"
#include "materials.h"

adem_material_def adem_default_material_def(void) {
  adem_material_def d;
  memset(&d, 0, sizeof d);
  d.density = 2500.0;
  d.young = 1e7;
  d.poisson = 0.25;
  d.restitution = 0.5;
  d.friction = 0.5;
  d.stiffness_factor = 1.0;
  for (int k = 0; k < ADEM_PARAM_COUNT; ++k) d.param[k] = adem_law_param_get((adem_law_param_id)k)->def;
  return d;
}

adem_interaction_def adem_default_interaction_def(void) {
  adem_interaction_def d;
  d.material_a = d.material_b = -1;
  d.restitution = -1.0;
  d.friction = -1.0;
  /* each slot's first row is its default law (adem/laws.h) */
  d.normal = (adem_normal_model)0;
  d.damping = (adem_damping_model)0;
  d.tangential = (adem_tangential_model)0;
  d.rolling = (adem_rolling_model)0;
  for (int k = 0; k < ADEM_PARAM_COUNT; ++k) d.param[k] = NAN;
  d.dtk_rolling_modification = 1;
  return d;
}

/* Compliance terms: a rigid material contributes nothing (E = infinity). */
static double young_compliance(const adem_material *m, bool modified) {
  if (m->def.rigid) return 0.0;
  double E = modified ? m->young_mod : m->def.young;
  return (1.0 - m->def.poisson * m->def.poisson) / E;
}

static double shear_compliance(const adem_material *m, bool modified) {
  if (m->def.rigid) return 0.0;
  double G = modified ? m->shear_mod : m->def.young / (2.0 * (1.0 + m->def.poisson));
  return (2.0 - m->def.poisson) / G;
}

/* The pair's values from its two materials (the mixing rules: the mean of the two unless a
 * parameter's row says otherwise). */
static adem_interaction derive_pair(const adem_material *a, const adem_material *b) {
  adem_interaction it;
  memset(&it, 0, sizeof it);
  adem_pair_params *pp = &it.pp;
  double cE = young_compliance(a, true) + young_compliance(b, true); /* H2 */
  double cG = shear_compliance(a, true) + shear_compliance(b, true); /* H15 */
  pp->E = cE > 0.0 ? 1.0 / cE : INFINITY;
  pp->G = cG > 0.0 ? 1.0 / cG : INFINITY;
  double cEr = young_compliance(a, false) + young_compliance(b, false);
  double cGr = shear_compliance(a, false) + shear_compliance(b, false);
  pp->E_real = cEr > 0.0 ? 1.0 / cEr : INFINITY;
  pp->G_real = cGr > 0.0 ? 1.0 / cGr : INFINITY;
  pp->restitution = 0.5 * (a->def.restitution + b->def.restitution);
  pp->friction = 0.5 * (a->def.friction + b->def.friction);
  for (int k = 0; k < ADEM_PARAM_COUNT; ++k) {
    pp->param_a[k] = a->def.param[k];
    pp->param_b[k] = b->def.param[k];
    pp->param[k] = adem_law_param_mix((adem_law_param_id)k, pp->param_a[k], pp->param_b[k]);
  }
  adem_interaction_def d = adem_default_interaction_def();
  it.normal = d.normal;
  it.damping = d.damping;
  it.tangential = d.tangential;
  it.rolling = d.rolling;
  pp->dtk_rolling_modification = true;
  return it;
}

/* What follows from the pair's values once the entries have replaced some: beta (H12), the
 * surface energy of the real and the modified material, and what its laws derive (their hooks:
 * the clamped damping's beta). */
static void finish_pair(adem_interaction *it) {
  adem_pair_params *pp = &it->pp;
  pp->beta = adem_damping_beta(pp->restitution);
  pp->beta_clamped = pp->beta; /* unless the damping law refits it */
  /* Surface energy of a dissimilar pair: the geometric mean (Berthelot's rule). H24 applies to
   * the pair's effective values, gamma_mod = gamma (E_mod/E)^(2/5), so the separation energy is
   * kept whatever the stiffness factors of the two materials (spheres at f on a rigid wall give
   * E_mod/E = f, hence gamma f^(2/5)). */
  pp->gamma_real = pp->param[ADEM_PARAM_SURFACE_ENERGY];
  pp->gamma = isfinite(pp->E_real) ? pp->gamma_real * adem_dmath_pow(pp->E / pp->E_real, 0.4) : pp->gamma_real;
  adem_laws_derive(adem_interaction_laws(it), pp);
  it->rolling_inertia = adem_laws_need_rolling_inertia(adem_interaction_laws(it), pp);
}

/* Whether the laws of an entry exist and fit together; NULL if so, else why not. */
static const char *laws_conflict(const adem_interaction_def *d, char *buf, size_t n) {
  const adem_law *law[4] = {adem_law_get(ADEM_SLOT_NORMAL, (int)d->normal),
                            adem_law_get(ADEM_SLOT_DAMPING, (int)d->damping),
                            adem_law_get(ADEM_SLOT_TANGENTIAL, (int)d->tangential),
                            adem_law_get(ADEM_SLOT_ROLLING, (int)d->rolling)};
  static const adem_law_slot slot[4] = {ADEM_SLOT_NORMAL, ADEM_SLOT_DAMPING, ADEM_SLOT_TANGENTIAL,
                                        ADEM_SLOT_ROLLING};
  for (int s = 0; s < 4; ++s)
    if (!law[s]) {
      snprintf(buf, n, "there is no %s law number %d (%s)", adem_law_slot_name(slot[s]),
               s == 0 ? (int)d->normal : s == 1 ? (int)d->damping
                                     : s == 2   ? (int)d->tangential
                                                : (int)d->rolling,
               adem_law_choices(slot[s]));
      return buf;
    }
  for (int s = 1; s < 4; ++s)
    if (law[s]->requires[0] && strcmp(law[s]->requires, law[0]->name) != 0) {
      snprintf(buf, n, "the %s law `%s` needs the `%s` normal law, not `%s`",
               adem_law_slot_name(slot[s]), law[s]->name, law[s]->requires, law[0]->name);
      return buf;
    }
  return NULL;
}

/* Whether a pair's laws can run with its values (their check hooks: `jkr` needs a surface energy
 * on both materials unless the interaction gives one, DTK a surface energy > 0); NULL if so,
 * else why not. */
static const char *laws_check(const adem_materials *mt, const adem_interaction_def *d, char *buf,
                              size_t n) {
  const adem_material *ma = &mt->m[d->material_a], *mb = &mt->m[d->material_b];
  adem_law_check c = {ma->def.param, mb->def.param, d->param, {ma->def.name, mb->def.name}, {NULL, NULL}, NULL};
  adem_law_set laws = {(int)d->normal, (int)d->damping, (int)d->tangential, (int)d->rolling};
  adem_law_slot slot;
  int side;
  return adem_laws_check(laws, &c, &slot, &side, buf, n);
}

adem_status adem_materials_derive(adem_materials *mt, adem_error *err) {
  int nm = mt->n;
  for (int k = 0; k < nm; ++k) {
    adem_material *m = &mt->m[k];
    double f = m->def.stiffness_factor;
    m->young_mod = f * m->def.young; /* H24: E_mod = f E */
    m->shear_mod = m->young_mod / (2.0 * (1.0 + m->def.poisson));
  }
  for (int k = 0; k < mt->ndefs; ++k) { /* entries a stage replaced are checked again */
    char why[256];
    if (laws_conflict(&mt->defs[k], why, sizeof why))
      return adem_error_set(err, ADEM_ERR_INPUT, "interaction of materials '%s' and '%s': %s",
                            mt->m[mt->defs[k].material_a].def.name,
                            mt->m[mt->defs[k].material_b].def.name, why);
  }
  free(mt->pairs);
  mt->pairs = calloc((size_t)nm * (size_t)nm, sizeof *mt->pairs);
  if (!mt->pairs && nm > 0) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b)
      mt->pairs[(size_t)a * nm + b] = derive_pair(&mt->m[a], &mt->m[b]);
  for (int k = 0; k < mt->ndefs; ++k) {
    const adem_interaction_def *d = &mt->defs[k];
    adem_interaction *p[2] = {&mt->pairs[(size_t)d->material_a * nm + d->material_b],
                              &mt->pairs[(size_t)d->material_b * nm + d->material_a]};
    for (int s = 0; s < 2; ++s) {
      if (d->restitution > 0.0) {
        p[s]->pp.restitution = d->restitution;
        p[s]->set_restitution = true;
      }
      if (d->friction >= 0.0) {
        p[s]->pp.friction = d->friction;
        p[s]->set_friction = true;
      }
      for (int j = 0; j < ADEM_PARAM_COUNT; ++j) {
        if (isnan(d->param[j])) continue;
        p[s]->pp.param[j] = p[s]->pp.param_a[j] = p[s]->pp.param_b[j] = d->param[j];
        p[s]->set_param[j] = true;
      }
      p[s]->normal = d->normal;
      p[s]->damping = d->damping;
      p[s]->tangential = d->tangential;
      p[s]->rolling = d->rolling;
      p[s]->pp.dtk_rolling_modification = d->dtk_rolling_modification != 0;
    }
  }
  for (size_t k = 0; k < (size_t)nm * nm; ++k) finish_pair(&mt->pairs[k]);
  for (int k = 0; k < mt->ndefs; ++k) { /* what its laws need of the pair's values */
    const adem_interaction_def *d = &mt->defs[k];
    char why[512];
    if (laws_check(mt, d, why, sizeof why))
      return adem_error_set(err, ADEM_ERR_INPUT, "interaction of materials '%s' and '%s': %s",
                            mt->m[d->material_a].def.name, mt->m[d->material_b].def.name, why);
  }
  return ADEM_OK;
}

void adem_material_def_store(adem_material_def *dst, const adem_material_def *src) {
  /* checkpoints save the defs' bytes: the name after its end and the padding are zeroed, so
   * that they do not depend on what the caller's memory held */
  memset(dst, 0, sizeof *dst);
  snprintf(dst->name, sizeof dst->name, "%s", src->name);
  dst->density = src->density;
  dst->young = src->young;
  dst->poisson = src->poisson;
  dst->restitution = src->restitution;
  dst->friction = src->friction;
  dst->stiffness_factor = src->stiffness_factor;
  dst->rigid = src->rigid;
  memcpy(dst->param, src->param, sizeof dst->param);
}

int adem_materials_add(adem_materials *mt, const adem_material_def *def, adem_error *err) {
  if (adem_materials_find(mt, def->name) >= 0) {
    adem_error_set(err, ADEM_ERR_INPUT, "material '%s' is defined twice", def->name);
    return -1;
  }
  if (!def->rigid && !(def->young > 0.0)) {
    adem_error_set(err, ADEM_ERR_INPUT, "material '%s': Young's modulus must be > 0", def->name);
    return -1;
  }
  if (!(def->poisson > -1.0 && def->poisson < 0.5)) {
    adem_error_set(err, ADEM_ERR_INPUT, "material '%s': Poisson ratio %g is outside (-1, 0.5)",
                   def->name, def->poisson);
    return -1;
  }
  if (!(def->restitution > 0.0 && def->restitution <= 1.0)) {
    adem_error_set(err, ADEM_ERR_INPUT, "material '%s': restitution %g is outside (0, 1]",
                   def->name, def->restitution);
    return -1;
  }
  if (!(def->stiffness_factor > 0.0 && def->stiffness_factor <= 1.0)) {
    adem_error_set(err, ADEM_ERR_INPUT, "material '%s': stiffness factor %g is outside (0, 1]",
                   def->name, def->stiffness_factor);
    return -1;
  }
  if (def->friction < 0.0) {
    adem_error_set(err, ADEM_ERR_INPUT, "material '%s': friction must be >= 0", def->name);
    return -1;
  }
  for (int k = 0; k < ADEM_PARAM_COUNT; ++k) {
    const adem_law_param *p = adem_law_param_get((adem_law_param_id)k);
    if (!(def->param[k] >= p->lo) || !isfinite(def->param[k])) {
      adem_error_set(err, ADEM_ERR_INPUT, "material '%s': %s %g must be >= %g", def->name, p->key,
                     def->param[k], p->lo);
      return -1;
    }
  }
  if (mt->n >= 65535) {
    adem_error_set(err, ADEM_ERR_INPUT, "too many materials");
    return -1;
  }
  adem_material *m = realloc(mt->m, (size_t)(mt->n + 1) * sizeof *m);
  if (!m) {
    adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    return -1;
  }
  mt->m = m;
  memset(&m[mt->n], 0, sizeof *m);
  adem_material_def_store(&m[mt->n].def, def);
  return mt->n++;
}

int adem_materials_find(const adem_materials *mt, const char *name) {
  for (int k = 0; k < mt->n; ++k)
    if (strcmp(mt->m[k].def.name, name) == 0) return k;
  return -1;
}

int adem_materials_set_interaction(adem_materials *mt, const adem_interaction_def *def,
                                   adem_error *err) {
  if (def->material_a < 0 || def->material_a >= mt->n || def->material_b < 0 ||
      def->material_b >= mt->n) {
    adem_error_set(err, ADEM_ERR_INPUT, "interaction names a material that does not exist");
    return -1;
  }
  if (def->restitution > 1.0 || def->restitution == 0.0) {
    adem_error_set(err, ADEM_ERR_INPUT, "interaction restitution %g is outside (0, 1]",
                   def->restitution);
    return -1;
  }
  char why[256];
  if (laws_conflict(def, why, sizeof why)) {
    adem_error_set(err, ADEM_ERR_INPUT, "interaction of materials '%s' and '%s': %s",
                   mt->m[def->material_a].def.name, mt->m[def->material_b].def.name, why);
    return -1;
  }
  for (int k = 0; k < ADEM_PARAM_COUNT; ++k) {
    const adem_law_param *p = adem_law_param_get((adem_law_param_id)k);
    if (!isnan(def->param[k]) && !(def->param[k] >= p->lo && isfinite(def->param[k]))) {
      adem_error_set(err, ADEM_ERR_INPUT,
                     "interaction of materials '%s' and '%s': %s %g must be >= %g",
                     mt->m[def->material_a].def.name, mt->m[def->material_b].def.name, p->key,
                     def->param[k], p->lo);
      return -1;
    }
  }
  adem_interaction_def *d =
      realloc(mt->defs, (size_t)(mt->ndefs + 1) * sizeof *d);
  if (!d) {
    adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    return -1;
  }
  mt->defs = d;
  /* stored with its trailing padding zeroed: checkpoints save the defs' bytes, which must not
   * depend on what the caller's stack held */
  memset(&d[mt->ndefs], 0, sizeof *d);
  memcpy(&d[mt->ndefs], def,
         offsetof(adem_interaction_def, dtk_rolling_modification) + sizeof def->dtk_rolling_modification);
  return mt->ndefs++;
}

void adem_materials_free(adem_materials *mt) {
  free(mt->m);
  free(mt->pairs);
  free(mt->defs);
  memset(mt, 0, sizeof *mt);
}

bool adem_materials_per_particle_rolling(const adem_materials *mt) {
  for (int k = 0; k < mt->ndefs; ++k) {
    const adem_law *law = adem_law_get(ADEM_SLOT_ROLLING, (int)mt->defs[k].rolling);
    if (law && law->per_particle) return true;
  }
  return false;
}
