/* Claim: the force pass's block kernels (touching particle pairs of the common laws, packed
 * arithmetic: src/core/pair_blocks.c) give every pair the bits the one-at-a-time path gives it.
 * The settle case with each law combination that has a kernel (every row of
 * ADEM_PAIR_BLOCK_LAWS, the list the kernels are built from), run with the blocks and without
 * them, must reach the same state bit for bit, and the blocks must have taken pairs (else the
 * comparison would hold by construction). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "bitwise/settle_case.h"
#include "pair_block_laws.h"
#include "world_internal.h"

/* The settle case with glass-glass contacts under the given laws (and glass on the walls under
 * Hertz with the same rolling law); damped: a rolling damping given (only model C reads it). */
static char *case_with_laws(const char *normal, const char *rolling, bool damped) {
  static const char *const glass_friction = "    friction: 0.5\n";
  static const char *const particles = "particles:\n";
  const char *f = strstr(settle_case, glass_friction);
  const char *p = strstr(settle_case, particles);
  assert_non_null(f);
  assert_non_null(p);
  char extra_material[128], interactions[256];
  snprintf(extra_material, sizeof extra_material,
           "    rolling_friction: 0.1\n    surface_energy: 0.01\n%s",
           damped ? "    rolling_damping: 0.3\n" : "");
  snprintf(interactions, sizeof interactions,
           "interactions:\n"
           "  - {materials: [glass, glass], normal: %s, rolling: %s}\n"
           "  - {materials: [glass, steel], rolling: %s}\n",
           normal, rolling, rolling);
  size_t n = strlen(settle_case) + strlen(extra_material) + strlen(interactions) + 1;
  char *text = malloc(n);
  assert_non_null(text);
  size_t upto_f = (size_t)(f - settle_case) + strlen(glass_friction);
  size_t upto_p = (size_t)(p - settle_case);
  snprintf(text, n, "%.*s%s%.*s%s%s", (int)upto_f, settle_case, extra_material,
           (int)(upto_p - upto_f), settle_case + upto_f, interactions, settle_case + upto_p);
  return text;
}

static adem_case *run_laws(const char *text, bool blocks, int nthreads) {
  adem_case *c = NULL;
  adem_error err;
  if (adem_case_load_string(text, "settle.yaml", NULL, 0, &c, &err))
    fail_msg("case does not load: %s", err.message);
  c->world->pair_blocks = blocks;
  adem_world_set_threads(c->world, nthreads);
  c->world->parallel_min = 0;
  if (adem_world_prepare(c->world, &err)) fail_msg("%s", err.message);
  if (adem_world_step(c->world, SETTLE_STEPS, &err)) fail_msg("%s", err.message);
  return c;
}

static void compare_as(const char *normal, const char *rolling, bool damped) {
  char *text = case_with_laws(normal, rolling, damped);
  adem_case *one = run_laws(text, false, 1);
  adem_case *blocks = run_laws(text, true, 1);
  adem_case *blocks2 = run_laws(text, true, 2);
  uint64_t taken = blocks->world->pair_block_pairs;
  printf("# %s + %s%s: %zu loaded contacts, %llu pairs in blocks over %d steps\n", normal, rolling,
         damped ? " (rolling damping given)" : "", settle_loaded_contacts(one->world),
         (unsigned long long)taken, SETTLE_STEPS);
  assert_true(one->world->pair_block_pairs == 0);
  assert_true(taken > 100u * SETTLE_STEPS); /* most contacts of most steps */
  const char *what = "";
  if (!settle_same_state(one->world, blocks->world, &what))
    fail_msg("%s + %s: blocks differ from one at a time in %s", normal, rolling, what);
  if (!settle_same_state(one->world, blocks2->world, &what))
    fail_msg("%s + %s: blocks on 2 threads differ in %s", normal, rolling, what);
  adem_case_free(one);
  adem_case_free(blocks);
  adem_case_free(blocks2);
  free(text);
}

typedef struct laws {
  const char *normal, *rolling;
  bool damped;
} laws;
/* Every law combination with a block kernel, by its rows' names ... */
static const int block_laws[][2] = {
#define BLOCK_ROW(name, normal, rolling) {normal, rolling},
    ADEM_PAIR_BLOCK_LAWS(BLOCK_ROW)
#undef BLOCK_ROW
};
enum { NBLOCK = sizeof block_laws / sizeof block_laws[0] };
/* ... and BROF with a rolling damping (which only model C reads: its kernels leave I_r 0, so
 * BROF keeps its kernel), JKR without surface energy (the interaction's own 0: Hertz's radius
 * by a select) */
static const laws extras[] = {
    {"hertz", "brof", true},
    {"jkr, surface_energy: 0", "none", false},
};
enum { NEXTRA = sizeof extras / sizeof extras[0] };
static laws combinations[NBLOCK + NEXTRA];

static void test_combination(void **state) {
  const laws *l = *state;
  compare_as(l->normal, l->rolling, l->damped);
}

int main(void) {
  enum { N = NBLOCK + NEXTRA };
  for (int k = 0; k < NBLOCK; ++k)
    combinations[k] = (laws){adem_law_get(ADEM_SLOT_NORMAL, block_laws[k][0])->name,
                             adem_law_get(ADEM_SLOT_ROLLING, block_laws[k][1])->name, false};
  for (int k = 0; k < NEXTRA; ++k) combinations[NBLOCK + k] = extras[k];
  struct CMUnitTest tests[N];
  for (int k = 0; k < N; ++k)
    tests[k] = (struct CMUnitTest)cmocka_unit_test_prestate(test_combination,
                                                            (void *)&combinations[k]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
