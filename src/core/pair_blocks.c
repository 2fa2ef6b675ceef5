/* The block kernels of the force pass: one per row of ADEM_PAIR_BLOCK_LAWS, each cloned per
 * instruction set, and the flush that stores a block's results (pair_blocks.h). */
#include "pair_blocks.h"
#include "pair_block_laws.h"

/* Touching particle pairs of one interaction in blocks: the same geometry and laws as
 * particle_pair, lane by lane, in a loop the compiler turns into packed arithmetic (SSE2, and
 * AVX2 or AVX-512 where the processor has them: the clones below). Lanes are independent and
 * packed instructions round each lane as the scalar ones do (no fused multiply-add:
 * -ffp-contract=off), so a pair's results are the same bits by either path and in any clone
 * (docs/architecture.md, "Block kernels"). The block kernels exist for the laws most runs use
 * (ADEM_PAIR_BLOCK_LAWS, pair_block_laws.h); the rest go one at a time. */

/* The loop the compiler packs: laws and balance are constants of each kernel below. */
static inline __attribute__((always_inline)) void
pair_block_laws(const adem_force_scope *w, pair_block *restrict b, law_set laws, bool balance) {
  const adem_interaction *it = b->it;
  double dt = law_step(w);                              /* 0 while the pass holds histories (prepare) */
  double h_close = w->second_order ? 0.5 * w->dt : 0.0; /* as particle_pair's 0.5 hp */
  int m = b->m;
  for (int q = 0; q < m; ++q) {
    pair_kinematics kin;
    adem_contact_history h;
#define PAIR_BLOCK_GET_KIN(a, f) kin.f = b->in.kin.a[q];
#define PAIR_BLOCK_GET_HIST(a, f) h.f = b->in.hist.a[q];
    PAIR_BLOCK_INPUTS(PAIR_BLOCK_GET_KIN)
    PAIR_BLOCK_HISTORY(PAIR_BLOCK_GET_HIST)
#undef PAIR_BLOCK_GET_KIN
#undef PAIR_BLOCK_GET_HIST
    contact_geometry g = kinematic_geometry(&kin, false, true, h_close);
    contact_result r = contact_force(it, laws, &g, &h, dt, b->fresh[q] != 0.0);
    b->hist[q] = h;
    pair_records(&g, &r, balance, &b->res[q], &b->bal[q]);
  }
}

/* flatten: every law inlined into the loop (a call keeps it from packing); the clones: one per
 * instruction set, chosen when the program loads (GCC on x86-64; ADEM_NO_CLONES: SSE2 only) */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ADEM_NO_CLONES)
#define PAIR_BLOCK_CLONES __attribute__((flatten, target_clones("avx512f", "avx2", "default")))
#else
#define PAIR_BLOCK_CLONES __attribute__((flatten))
#endif

#define PAIR_BLOCK_KERNEL(name, normal, rolling)                                              \
  PAIR_BLOCK_CLONES static void pair_block_##name(const adem_force_scope *w, pair_block *b) { \
    law_set laws = {normal, ADEM_DAMPING_VISCOELASTIC, ADEM_TANGENTIAL_INCREMENTAL, rolling}; \
    pair_block_laws(w, b, laws, false);                                                       \
  }                                                                                           \
  PAIR_BLOCK_CLONES static void pair_block_##name##_balance(const adem_force_scope *w,        \
                                                            pair_block *b) {                  \
    law_set laws = {normal, ADEM_DAMPING_VISCOELASTIC, ADEM_TANGENTIAL_INCREMENTAL, rolling}; \
    pair_block_laws(w, b, laws, true);                                                        \
  }
ADEM_PAIR_BLOCK_LAWS(PAIR_BLOCK_KERNEL)
#undef PAIR_BLOCK_KERNEL

typedef void (*pair_block_kernel)(const adem_force_scope *w, pair_block *b);
static const struct {
  int normal, rolling;
  pair_block_kernel laws[2]; /* without and with the energy balance */
} pair_block_kernels[] = {
#define PAIR_BLOCK_ROW(name, normal, rolling) \
  {normal, rolling, {pair_block_##name, pair_block_##name##_balance}},
    ADEM_PAIR_BLOCK_LAWS(PAIR_BLOCK_ROW)
#undef PAIR_BLOCK_ROW
};

int adem_pair_block_kind(const adem_interaction *it) {
  /* the kernels leave I_r 0: of their rolling laws only model C's dashpot reads it */
  bool dashpot = (it->rolling == ADEM_ROLLING_C || it->rolling == ADEM_ROLLING_C_CAPPED) &&
                 needs_rolling_inertia(it);
  if (it->damping != ADEM_DAMPING_VISCOELASTIC || it->tangential != ADEM_TANGENTIAL_INCREMENTAL ||
      dashpot)
    return -1;
  for (int r = 0; r < (int)(sizeof pair_block_kernels / sizeof pair_block_kernels[0]); ++r)
    if (pair_block_kernels[r].normal == (int)it->normal &&
        pair_block_kernels[r].rolling == (int)it->rolling)
      return r;
  return -1;
}

void adem_pair_block_run(const adem_force_scope *w, pair_block *b) {
  pair_block_kernels[b->kind].laws[w->balance](w, b);
#ifdef ADEM_HAVE_OPENMP
#pragma omp atomic
#endif
  *w->block_pairs += (uint64_t)b->m;
  adem_pair_list *l = w->pp;
  for (int q = 0; q < b->m; ++q) {
    size_t k = b->k[q];
    if (!v3_isfinite(b->res[q].force_a)) { /* a law's library call (packed), or a bad state */
      adem_force_particle_pair(w, k, v3(b->in.kin.dx[q], b->in.kin.dy[q], b->in.kin.dz[q]),
                               b->in.kin.dist[q], b->fresh[q] == 0.0, b->it);
      continue;
    }
    size_t s = adem_pairs_own_slot(l, k);
    l->touching[k] = true;
    if (!w->hold_history) l->hist[s] = b->hist[q];
    l->res[s] = b->res[q];
    if (w->balance) { /* the fields pair_records writes: a particle pair has no wall power */
      l->bal[s].damping_a = b->bal[q].damping_a;
      l->bal[s].damping_torque_a = b->bal[q].damping_torque_a;
      l->bal[s].damping_torque_b = b->bal[q].damping_torque_b;
      l->bal[s].dissipated = b->bal[q].dissipated;
    }
    note_overlap(w, b->res[q].overlap_ratio);
  }
  b->m = 0;
}
