/* Touching particle pairs of the common laws in blocks (pair_blocks.c): the lanes of a block
 * are pairs of one interaction whose law combination has a kernel (pair_block_laws.h); the
 * kernel runs the same inline functions as the one-at-a-time path (contact_force.h) lane by
 * lane in a loop the compiler packs, so every pair gets the same bits by either path
 * (docs/architecture.md, "Block kernels"). */
#ifndef ADEM_PAIR_BLOCKS_H
#define ADEM_PAIR_BLOCKS_H

#include "contact_force.h"

enum { PAIR_BLOCK = 64 };

/* The block's inputs, a pair per lane: pair_kinematics and the history, one array per number
 * (contiguous lanes are what packed loads read). */
// clang-format off
#define PAIR_BLOCK_INPUTS(X)                                                                    \
  X(dx, d.x) X(dy, d.y) X(dz, d.z) X(dist, dist) X(ri, ri) X(rj, rj) X(mi, mi) X(mj, mj)         \
  X(vix, vi.x) X(viy, vi.y) X(viz, vi.z) X(vjx, vj.x) X(vjy, vj.y) X(vjz, vj.z)                  \
  X(oix, oi.x) X(oiy, oi.y) X(oiz, oi.z) X(ojx, oj.x) X(ojy, oj.y) X(ojz, oj.z)                  \
  X(vpix, vpi.x) X(vpiy, vpi.y) X(vpiz, vpi.z) X(vpjx, vpj.x) X(vpjy, vpj.y) X(vpjz, vpj.z)      \
  X(opix, opi.x) X(opiy, opi.y) X(opiz, opi.z) X(opjx, opj.x) X(opjy, opj.y) X(opjz, opj.z)
#define PAIR_BLOCK_HISTORY(X)                                                                   \
  X(tx, tangential.x) X(ty, tangential.y) X(tz, tangential.z) X(rx, rolling.x)                  \
  X(ry, rolling.y) X(rz, rolling.z) X(taux, tangential_aux) X(raux, rolling_aux)                \
  X(ftx, tangential_force.x) X(fty, tangential_force.y) X(ftz, tangential_force.z)               \
  X(elastic, elastic)
// clang-format on

typedef struct pair_block {
  int m;                      /* pairs held */
  int kind;                   /* the kernel's index in pair_block_kernels */
  const adem_interaction *it; /* the interaction of every pair of the block */
  size_t k[PAIR_BLOCK];       /* pair index */
  double fresh[PAIR_BLOCK];   /* 1: not touching at the last pass */
  struct {
#define PAIR_BLOCK_ARRAY(a, f) double a[PAIR_BLOCK];
    struct {
      PAIR_BLOCK_INPUTS(PAIR_BLOCK_ARRAY)
    } kin;
    struct {
      PAIR_BLOCK_HISTORY(PAIR_BLOCK_ARRAY)
    } hist;
#undef PAIR_BLOCK_ARRAY
  } in;
  adem_contact_history hist[PAIR_BLOCK]; /* the histories after the pass */
  adem_pair_result res[PAIR_BLOCK];
  adem_pair_balance bal[PAIR_BLOCK];
} pair_block;

/* Puts a pair's kinematics and history in lane q. */
static inline __attribute__((always_inline)) void
pair_block_put(pair_block *b, int q, const pair_kinematics *kin, const adem_contact_history *h) {
#define PAIR_BLOCK_PUT_KIN(a, f) b->in.kin.a[q] = kin->f;
#define PAIR_BLOCK_PUT_HIST(a, f) b->in.hist.a[q] = h->f;
  PAIR_BLOCK_INPUTS(PAIR_BLOCK_PUT_KIN)
  PAIR_BLOCK_HISTORY(PAIR_BLOCK_PUT_HIST)
#undef PAIR_BLOCK_PUT_KIN
#undef PAIR_BLOCK_PUT_HIST
}

/* The block kernel for the interaction's laws (a row of ADEM_PAIR_BLOCK_LAWS), or -1. */
int adem_pair_block_kind(const adem_interaction *it);
/* Runs the block's kernel, stores its pairs' results and empties it (a block with pairs). */
void adem_pair_block_run(const adem_force_scope *w, pair_block *b);
static inline void adem_pair_block_flush(const adem_force_scope *w, pair_block *b) {
  if (b->m > 0) adem_pair_block_run(w, b);
}

/* A particle pair one contact at a time (force_pass.c): what a block's lane falls back to when
 * its result is not finite (a law's library call, or a bad state). */
void adem_force_particle_pair(const adem_force_scope *w, size_t k, adem_vec3 d, double dist,
                              bool was, const adem_interaction *it);

#endif
