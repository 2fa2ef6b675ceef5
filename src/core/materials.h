/* Materials and the table of material pairs (H2, H12, H15, H24): what every contact between two
 * materials uses that does not depend on the particles. */
#ifndef ADEM_MATERIALS_H
#define ADEM_MATERIALS_H

#include <stdbool.h>
#include <stddef.h>

#include "adem/world.h"
#include "adem/laws.h"
#include "law_hooks.h"
#include "laws_kernels.h"

/* A material after derivation: the real values plus those the contact laws use. */
typedef struct adem_material {
  adem_material_def def;
  double young_mod; /* E_mod = f E (H24) */
  double shear_mod; /* G_mod = E_mod / (2(1+nu)) */
} adem_material;

/* Everything about a pair of materials that does not depend on the particles (H2, H12, H15):
 * the law of each slot and what the laws read. */
typedef struct adem_interaction {
  adem_normal_model normal;
  adem_damping_model damping;
  adem_tangential_model tangential;
  adem_rolling_model rolling;
  adem_pair_params pp;
  bool rolling_inertia;               /* its contacts need the rolling inertia I_r (the rolling law's hook) */
  bool set_restitution, set_friction; /* given by an interaction entry */
  bool set_param[ADEM_PARAM_COUNT];
} adem_interaction;

/* The materials of a world, the interaction entries given for some pairs, and the derived table
 * of every pair (n x n, symmetric). */
typedef struct adem_materials {
  adem_material *m;
  int n;
  adem_interaction *pairs;    /* derived by adem_materials_derive */
  adem_interaction_def *defs; /* as given */
  int ndefs;
} adem_materials;

/* Adds a material; returns its index, or -1 with err set. */
int adem_materials_add(adem_materials *mt, const adem_material_def *def, adem_error *err);
/* *dst = *src with the name's tail and the padding zeroed (checkpoints save the bytes). */
void adem_material_def_store(adem_material_def *dst, const adem_material_def *src);
int adem_materials_find(const adem_materials *mt, const char *name);
/* Records how two materials interact; returns the entry's index, or -1 with err set: the laws
 * must exist and fit together (a law's `requires`, e.g. DTK needs the JKR normal law). */
int adem_materials_set_interaction(adem_materials *mt, const adem_interaction_def *def,
                                   adem_error *err);
/* Whether an interaction entry has a rolling law that acts per particle (BROF); pairs without an
 * entry take none. */
bool adem_materials_per_particle_rolling(const adem_materials *mt);
/* Derives the modified moduli and the pair table. */
adem_status adem_materials_derive(adem_materials *mt, adem_error *err);
void adem_materials_free(adem_materials *mt);

/* The pair's laws, one per slot, for the hooks (law_hooks.h). */
static inline adem_law_set adem_interaction_laws(const adem_interaction *it) {
  return (adem_law_set){(int)it->normal, (int)it->damping, (int)it->tangential, (int)it->rolling};
}

static inline const adem_interaction *adem_materials_pair(const adem_materials *mt, int a, int b) {
  return &mt->pairs[(size_t)a * (size_t)mt->n + (size_t)b];
}

#endif
