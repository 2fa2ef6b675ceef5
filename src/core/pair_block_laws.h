/* The law combinations that have a block kernel (pair_blocks.c), in one place: the force pass
 * builds its kernels and their table from this list, and tests/bitwise/test_pair_blocks.c runs
 * every row of it with the blocks and without. Each row is normal x rolling; the damping is
 * viscoelastic and the tangential law incremental for all of them. */
#ifndef ADEM_PAIR_BLOCK_LAWS_H
#define ADEM_PAIR_BLOCK_LAWS_H

#include "adem/laws.h"

/* X(name, normal law id, rolling law id) */
// clang-format off
#define ADEM_PAIR_BLOCK_LAWS(X)                                                                  \
  X(hertz_none, ADEM_NORMAL_HERTZ, ADEM_ROLLING_NONE)                                          \
  X(hertz_model_a, ADEM_NORMAL_HERTZ, ADEM_ROLLING_A)                                          \
  X(hertz_model_c, ADEM_NORMAL_HERTZ, ADEM_ROLLING_C)                                          \
  X(hertz_model_c_capped, ADEM_NORMAL_HERTZ, ADEM_ROLLING_C_CAPPED)                            \
  X(hertz_brof, ADEM_NORMAL_HERTZ, ADEM_ROLLING_BROF)                                          \
  X(jkr_none, ADEM_NORMAL_JKR, ADEM_ROLLING_NONE)                                              \
  X(jkr_model_a, ADEM_NORMAL_JKR, ADEM_ROLLING_A)                                              \
  X(jkr_model_c, ADEM_NORMAL_JKR, ADEM_ROLLING_C)                                              \
  X(jkr_model_c_capped, ADEM_NORMAL_JKR, ADEM_ROLLING_C_CAPPED)                                \
  X(jkr_brof, ADEM_NORMAL_JKR, ADEM_ROLLING_BROF)
// clang-format on

#endif
