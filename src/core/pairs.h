/* Candidate contacts in flat arrays: particle-particle, particle-plane and particle-mesh pairs,
 * their history and the results of the last force pass. The per-pair arrays are listed once in
 * ADEM_PAIR_FIELDS (with the role of each: key, state carried from step to step, or result of a
 * force pass), and the extra per-slot arrays of mesh pairs in ADEM_MESH_SLOT_FIELDS; growing,
 * clearing, saving and loading walk those lists. */
#ifndef ADEM_PAIRS_H
#define ADEM_PAIRS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "adem/base.h"
#include "adem/laws.h"
#include "mesh_contact.h"
#include "soa.h"
#include "stream.h"

/* Contact history carried from step to step, keyed by the pair's stable ids. */
typedef struct adem_contact_history {
  adem_vec3 tangential;  /* incremental law: spring force on i (N); total law: accumulated
                          * tangential displacement of i relative to j (H14, m) */
  adem_vec3 rolling;     /* rolling displacement (DTK) or spring torque (model C) */
  double tangential_aux; /* incremental law: the S_t its force was stored with (N/m) */
  double rolling_aux;    /* models C and DTK: the rolling stiffness their spring was stored with */
  /* the tangential force on i the contact applied at the last pass, N (second-order scheme: its
   * dashpot takes the slip velocity at the full step implicitly, with the contact's own force of
   * this pass in place of this one, contact_force.h) */
  adem_vec3 tangential_force;
  double elastic; /* energy the history's springs (tangential, rolling) stored at the
                   * last force pass, J: what is lost when the contact opens or a mesh
                   * contact moves to another region (the normal energy follows the
                   * overlap, not the history) */
} adem_contact_history;

/* What a force pass writes for a pair and the per-particle sums read back: one record, so that
 * the sums gather one or two cache lines per pair rather than one per quantity. Zero when the
 * pair does not touch (but see forget_opened in contact_force.h). Only what every pass needs is here;
 * the stored energy and the energy balance's terms are apart (elastic, adem_pair_balance), written
 * only by the passes that want them. */
typedef struct adem_pair_result {
  adem_vec3 force_a;       /* force on a (on b it is the opposite), N */
  double rolling_capacity; /* BROF: e_c |F_n| this contact offers (I9) */
  double overlap_ratio;    /* overlap / smaller radius */
  adem_vec3 moment;        /* n x F_t, N: the tangential force's moment per metre of arm. It
                            * acts at r_a n from a's centre and (as -F_t) at -r_b n from b's,
                            * so a takes r_a n x F_t and b r_b n x F_t; each particle's sum
                            * scales it by its own radius (a wall takes none) */
  adem_vec3 rolling_a;     /* rolling couple on a (on b: the opposite), N m */
} adem_pair_result;

/* The energy balance's terms of a pair at the last force pass, written while the balance is on.
 * A list keeps these records only then (adem_pairs_keep_balance): they are most of a pair's
 * bytes, and a run without the balance never reads them. */
typedef struct adem_pair_balance {
  double dissipated;          /* energy the laws took in the step by slip or a spring's limit, J */
  adem_vec3 damping_a;        /* dissipative force on a, the dashpots (b: the opposite), N */
  adem_vec3 damping_torque_a; /* dissipative torque on a: the dashpots' moments and dissipative
                               * couples, N m */
  adem_vec3 damping_torque_b; /* the same on b, N m (0 for a wall) */
  double wall_power;          /* walls: power the wall gives through the contact, F.V + R.Omega
                               * (V, Omega the wall's), W */
  double wall_damping_power;  /* walls: the dissipative forces' and couples' share of wall_power */
} adem_pair_balance;

/* Roles of the per-pair arrays. */
enum {
  ADEM_PAIR_KEY = 0,   /* who the pair is: set by the neighbour build */
  ADEM_PAIR_STATE = 1, /* carried from step to step and across rebuilds */
  ADEM_PAIR_RESULT = 2 /* written by every force pass; zero when the pair does not touch */
};

/* Per candidate: X(type, name, role, what it holds) */
// clang-format off
#define ADEM_PAIR_FIELDS(X)                                                                    \
  X(uint32_t, a, ADEM_PAIR_KEY, "particle index; for particle pairs id[a] < id[b]")             \
  X(uint32_t, b, ADEM_PAIR_KEY, "particle, plane or triangle index")                            \
  X(bool, touching, ADEM_PAIR_STATE, "in contact after the last force pass")                   \
  X(bool, opened, ADEM_PAIR_STATE, "opened at the last force pass: its results hold what the pass left (a break correction, the lost spring energy) for the next pass to clear")
/* Per slot (the place of a pair's state and results, adem_pairs_slot): X(type, name, role, doc) */
#define ADEM_PAIR_SLOT_FIELDS(X)                                                               \
  X(adem_contact_history, hist, ADEM_PAIR_STATE, "tangential and rolling history")             \
  X(adem_pair_result, res, ADEM_PAIR_RESULT, "the results of the last force pass")          \
  X(double, elastic, ADEM_PAIR_RESULT, "elastic energy stored in the contact, J, written by the passes after which the diagnostics can be read")
// clang-format on

/* A list of candidate pairs within cut-off + skin. Per-pair results are written by the force pass
 * and summed per particle afterwards in a fixed order, so any thread count gives the same sums.
 *
 * Where a pair's state and results are (issue 24, stage 3): a dense list (walls, meshes) keeps
 * them at the pair's own index. The particle pairs' list is sparse: of its candidates about a
 * third never touch between two builds, and their 200 bytes of history and results would be
 * zeros. A sparse list keeps them in slots: slot 0 holds zeros for every pair that has not touched
 * since the build (it is read, never written); a pair takes a slot of its own when it first
 * touches (adem_pairs_own_slot) and keeps it to the next build, which packs the slots of the
 * touching pairs in the list's order. A slot's number depends on the order in which the threads
 * took them; no result does. */
typedef struct adem_pair_list {
  size_t n, cap;
#define ADEM_X(type, name, role, doc) type *name;
  ADEM_PAIR_FIELDS(ADEM_X)
  uint32_t *slot; /* sparse: each candidate's slot (0: none of its own); NULL: dense */
  ADEM_PAIR_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
  bool sparse;             /* state and results in slots (set before the list first grows) */
  size_t nslots, slot_cap; /* sparse: slots in use (slot 0 included) and allocated */
  bool keeps_balance;      /* bal is kept (the energy balance is on) */
  adem_pair_balance *bal;  /* the energy balance's terms, a result like res (per slot); NULL unless kept */
} adem_pair_list;

/* The slot of pair k: where its hist, res, elastic and bal are. */
static inline size_t adem_pairs_slot(const adem_pair_list *l, size_t k) {
  return l->slot ? l->slot[k] : k;
}

/* Zeroes slot s's records (history and results). */
static inline void adem_pairs_clear_slot(adem_pair_list *l, size_t s) {
#define ADEM_X(type, name, role, doc) memset(&l->name[s], 0, sizeof l->name[s]);
  ADEM_PAIR_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
  if (l->bal) memset(&l->bal[s], 0, sizeof l->bal[s]);
}

/* The slot pair k writes to: its own, taken now (zeroed) if it has none. Safe from several
 * threads: the build reserved a slot for every candidate. */
static inline size_t adem_pairs_own_slot(adem_pair_list *l, size_t k) {
  if (!l->slot) return k;
  if (l->slot[k] != 0) return l->slot[k];
  size_t s = __atomic_fetch_add(&l->nslots, 1, __ATOMIC_RELAXED);
  adem_pairs_clear_slot(l, s);
  l->slot[k] = (uint32_t)s;
  return s;
}

/* A sparse list's slots all free again (slot 0 stays), for a list filled anew: each pair then
 * gets slot 0 (set slot[k] = 0) or takes its own. */
static inline void adem_pairs_free_slots(adem_pair_list *l) {
  if (l->slot) l->nslots = 1;
}

/* Forgets the pair's state and results: a candidate out of contact. */
static inline void adem_pairs_clear(adem_pair_list *l, size_t k) {
  l->touching[k] = false;
  l->opened[k] = false;
  size_t s = adem_pairs_slot(l, k);
  if (s != 0 || !l->slot) adem_pairs_clear_slot(l, s);
}

/* Clears every pair out of contact except what the pass in which it opened left (its lost
 * spring energy and break correction), and marks it opened so that the next pass clears that
 * too: what the force pass expects of a pair it skips. A checkpoint adem wrote already is so;
 * one from elsewhere is made so. */
static inline void adem_pairs_clear_apart(adem_pair_list *l) {
  for (size_t k = 0; k < l->n; ++k) {
    if (l->touching[k]) continue;
    size_t s = adem_pairs_slot(l, k);
    if (l->slot && s == 0) continue; /* zeros already */
    double lost = l->bal ? l->bal[s].dissipated : 0.0;
    adem_vec3 f = l->res[s].force_a;
    adem_pairs_clear(l, k);
    if (l->bal) l->bal[s].dissipated = lost;
    l->res[s].force_a = f;
    l->opened[k] = true;
  }
}

/* Grows to at least cap pairs (with headroom: lists are rebuilt often with similar sizes). */
adem_status adem_pairs_reserve(adem_pair_list *l, size_t cap);
/* Keeps the balance records (on: allocated for the capacity and zeroed, as a balance switched on
 * finds no terms from before) or frees them (off). */
adem_status adem_pairs_keep_balance(adem_pair_list *l, bool on);
void adem_pairs_free(adem_pair_list *l);
/* Reorders the pairs: new pair k is old pair perm[k] (the particle indices are not remapped). */
adem_status adem_pairs_permute(adem_pair_list *l, const size_t *perm);
/* A sparse list's state carried to its new candidates (the neighbour build): src[k] is the slot
 * whose history new pair k takes, 0 (no slot) or ADEM_PAIR_FRESH_SLOT (a zeroed slot of its own).
 * The histories move to slots 1, 2, ... in the order of the pairs, every other record is
 * cleared, and the pairs with a history are touching. */
enum { ADEM_PAIR_FRESH_SLOT = UINT32_MAX };
adem_status adem_pairs_pack_slots(adem_pair_list *l, const uint32_t *src);
void adem_pairs_save(adem_writer *wr, const adem_pair_list *l);
adem_status adem_pairs_load(adem_reader *rd, adem_pair_list *l, adem_error *err);
/* Bytes per pair over every array; with_balance: the balance records too (a sparse list's slots
 * counted as one per pair: what it holds at most). */
size_t adem_pairs_item_bytes(bool with_balance);

/* Particle-mesh contacts. The pair list holds each particle's candidate triangles (b = triangle
 * index) in one range, start[i] .. start[i+1]. After a force pass the first k slots of a range
 * hold the particle's k distinct contacts (mesh_contact.h): region key, owning triangle, history
 * and results; touching marks them. History follows a contact by its key from step to step (the
 * last step's arrays are kept in the _prev arrays) and across rebuilds (by id and key).
 * X(type, name, saved, what it holds): saved = 1 for what a checkpoint must keep. */
// clang-format off
#define ADEM_MESH_SLOT_FIELDS(X)                                                       \
  X(uint64_t, key, 1, "region key of the contact in the slot")                          \
  X(uint32_t, owner, 1, "triangle owning the contact in the slot")                      \
  X(uint64_t, key_prev, 0, "key at the last step (swapped with key each step)")         \
  X(adem_contact_history, hist_prev, 0, "history at the last step (swapped likewise)")  \
  X(bool, touching_prev, 0, "touching at the last step (swapped likewise)")             \
  X(adem_mesh_contact, found, 0, "scratch: the contacts found this step")
// clang-format on

typedef struct adem_mesh_pairs {
  adem_pair_list l;
  size_t *start; /* particles + 1 */
  size_t start_cap, cap;
#define ADEM_X(type, name, saved, doc) type *name;
  ADEM_MESH_SLOT_FIELDS(ADEM_X)
#undef ADEM_X
} adem_mesh_pairs;

/* Grows the per-slot arrays to the capacity of the pair list. */
adem_status adem_mesh_pairs_reserve(adem_mesh_pairs *pm);
void adem_mesh_pairs_free(adem_mesh_pairs *pm);
/* Reorders the slots (pair list and slot arrays): new slot k is old slot perm[k]; the ranges in
 * start are the caller's to set. */
adem_status adem_mesh_pairs_permute(adem_mesh_pairs *pm, const size_t *perm);
/* Bytes per slot of the extra per-slot arrays. */
size_t adem_mesh_pairs_slot_bytes(void);
/* Forgets slot k (state, results, key and owner). */
static inline void adem_mesh_pairs_clear(adem_mesh_pairs *pm, size_t k) {
  adem_pairs_clear(&pm->l, k);
  pm->key[k] = 0;
  pm->owner[k] = 0;
}
/* The pair list, the saved slot arrays and the slot ranges of nparticles particles. */
void adem_mesh_pairs_save(adem_writer *wr, const adem_mesh_pairs *pm, size_t nparticles);
adem_status adem_mesh_pairs_load(adem_reader *rd, adem_mesh_pairs *pm, size_t nparticles,
                                 adem_error *err);
/* Slot ranges that tile the list in particle order, with particles and triangles that exist. */
bool adem_mesh_pairs_consistent(const adem_mesh_pairs *pm, size_t nparticles, size_t ntris);

#endif
