/* The cell-grid search against the brute-force one, history across rebuilds, and the slots of
 * the sparse particle-pair list. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "helpers.h"
#include "rng.h"
#include "world_internal.h"

typedef struct id_pair {
  uint64_t a, b;
} id_pair;

static int compare_pairs(const void *x, const void *y) {
  const id_pair *p = x, *q = y;
  if (p->a != q->a) return p->a < q->a ? -1 : 1;
  if (p->b != q->b) return p->b < q->b ? -1 : 1;
  return 0;
}

/* Random polydisperse spheres (overlaps allowed: this checks the search, not the set-up). */
static adem_world *random_world(uint64_t seed, int n, int brute) {
  adem_world *w = adem_world_create();
  adem_world_use_brute_force(w, brute);
  int mat = test_material(w, "m", 1e7, 0.3, 0.5, 0.5);
  adem_rng rng = adem_rng_seed(seed);
  double L = 0.02 + 0.03 * adem_rng_uniform(&rng);
  for (int k = 0; k < n; ++k) {
    adem_vec3 x = v3(L * adem_rng_uniform(&rng), L * adem_rng_uniform(&rng),
                     0.3 * L * adem_rng_uniform(&rng));
    double r = 2e-4 + 8e-4 * adem_rng_uniform(&rng);
    test_particle(w, mat, x, v3(0, 0, 0), r);
  }
  adem_error err;
  assert_int_equal(adem_materials_derive(&w->mat, &err), ADEM_OK);
  assert_int_equal(adem_world_build_neighbors(w, &err), ADEM_OK);
  return w;
}

static id_pair *pairs_of(const adem_world *w, size_t *count) {
  id_pair *s = malloc((w->pp.n + 1) * sizeof *s);
  for (size_t k = 0; k < w->pp.n; ++k) {
    s[k].a = w->p.id[w->pp.a[k]];
    s[k].b = w->p.id[w->pp.b[k]];
    assert_true(s[k].a < s[k].b); /* pairs are oriented by id */
  }
  qsort(s, w->pp.n, sizeof *s, compare_pairs);
  *count = w->pp.n;
  return s;
}

/* Claim: the cell grid finds exactly the pairs within cut-off + skin that the O(N^2) search finds. */
static void test_grid_matches_brute_force(void **state) {
  (void)state;
  size_t total = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    int n = 50 + (int)(seed * 37 % 500);
    adem_world *grid = random_world(seed, n, 0);
    adem_world *brute = random_world(seed, n, 1);
    size_t ng, nb;
    id_pair *g = pairs_of(grid, &ng);
    id_pair *b = pairs_of(brute, &nb);
    assert_int_equal(ng, nb);
    for (size_t k = 0; k < ng; ++k) {
      assert_int_equal(g[k].a, b[k].a);
      assert_int_equal(g[k].b, b[k].b);
      if (k > 0) assert_true(compare_pairs(&g[k - 1], &g[k]) < 0); /* no duplicates */
    }
    total += ng;
    free(g);
    free(b);
    adem_world_free(grid);
    adem_world_free(brute);
  }
  printf("# 20 random configurations, %zu pairs, identical sets\n", total);
  assert_true(total > 1000);
}

/* Claim: tangential history survives a rebuild that reorders the particles. */
static void test_history_survives_rebuild(void **state) {
  (void)state;
  adem_world *w = random_world(5, 400, 0);
  adem_error err;
  adem_world_set_dt(w, 1e-7);
  adem_world_compute_forces(w);
  /* Give every touching pair a history keyed by its ids. */
  size_t touching = 0;
  for (size_t k = 0; k < w->pp.n; ++k) {
    if (!w->pp.touching[k]) continue;
    double a = (double)w->p.id[w->pp.a[k]], b = (double)w->p.id[w->pp.b[k]];
    w->pp.hist[adem_pairs_slot(&w->pp, k)].tangential = v3(a, b, a * b);
    ++touching;
  }
  /* Reverse the particle order (remapping the lists), so the rebuild's sort by cell moves every
   * particle; history must follow the ids, not the indices. */
  size_t n = w->p.n;
  size_t *perm = malloc(n * sizeof *perm), *inv = malloc(n * sizeof *inv);
  for (size_t i = 0; i < n; ++i) perm[i] = n - 1 - i;
  for (size_t i = 0; i < n; ++i) inv[perm[i]] = i;
  assert_int_equal(adem_particles_permute(&w->p, perm), ADEM_OK);
  for (size_t k = 0; k < w->pp.n; ++k) {
    w->pp.a[k] = (uint32_t)inv[w->pp.a[k]];
    w->pp.b[k] = (uint32_t)inv[w->pp.b[k]];
  }
  assert_int_equal(adem_world_build_neighbors(w, &err), ADEM_OK);
  free(perm);
  free(inv);
  size_t found = 0;
  for (size_t k = 0; k < w->pp.n; ++k) {
    if (!w->pp.touching[k]) continue;
    double a = (double)w->p.id[w->pp.a[k]], b = (double)w->p.id[w->pp.b[k]];
    adem_vec3 h = w->pp.hist[adem_pairs_slot(&w->pp, k)].tangential;
    assert_true(h.x == a && h.y == b && h.z == a * b);
    ++found;
  }
  printf("# %zu touching pairs kept their history\n", found);
  assert_int_equal(found, touching);
  assert_true(found > 10);
  adem_world_free(w);
}

/* The slots of a sparse list: every pair that touches has one of its own, no two pairs share
 * one, slot 0 stays zeros; a build packs the touching pairs' slots 1 .. m in the list's order. */
static void check_slots(const adem_pair_list *l, bool packed) {
  size_t own = 0, touching = 0;
  unsigned char *seen = calloc(l->nslots + 1, 1);
  for (size_t k = 0; k < l->n; ++k) {
    size_t s = l->slot[k];
    touching += l->touching[k];
    if (l->touching[k] || l->opened[k]) assert_true(s != 0);
    if (s == 0) continue;
    assert_true(s < l->nslots);
    assert_false(seen[s]);
    seen[s] = 1;
    if (packed) assert_int_equal(s, own + 1);
    ++own;
  }
  assert_int_equal(own + 1, l->nslots);
  if (packed) assert_true(own >= touching); /* and the fresh ones: overlapping, no history */
  const unsigned char *z = (const unsigned char *)&l->hist[0];
  for (size_t b = 0; b < sizeof l->hist[0]; ++b) assert_int_equal(z[b], 0);
  z = (const unsigned char *)&l->res[0];
  for (size_t b = 0; b < sizeof l->res[0]; ++b) assert_int_equal(z[b], 0);
  assert_true(l->elastic[0] == 0.0);
  free(seen);
}

/* Claim: the particle pairs' history and results take memory only for pairs that touched since
 * the last build (issue 24, stage 3), and a build packs them. */
static void test_slots_only_for_pairs_that_touched(void **state) {
  (void)state;
  adem_world *w = random_world(7, 3000, 0);
  adem_error err;
  adem_world_set_dt(w, 1e-7);
  assert_true(w->pp.slot != NULL);
  /* built before any force: none touching; the pairs that overlap took fresh slots */
  check_slots(&w->pp, true);
  size_t overlapping = 0;
  for (size_t k = 0; k < w->pp.n; ++k) {
    size_t i = w->pp.a[k], j = w->pp.b[k];
    double rs = w->p.radius[i] + w->p.radius[j];
    bool close = v3_norm2(v3_sub(w->p.pos[j], w->p.pos[i])) < rs * rs;
    assert_true(close == (w->pp.slot[k] != 0));
    overlapping += close;
  }
  assert_int_equal(w->pp.nslots, overlapping + 1);
  assert_true(overlapping > 20 && overlapping < w->pp.n);
  adem_world_compute_forces(w);
  check_slots(&w->pp, false);
  size_t before = w->pp.nslots;
  for (size_t i = 0; i < w->p.n; ++i) w->p.pos[i] = v3_scale(w->p.pos[i], 0.98); /* new contacts */
  adem_world_compute_forces(w);
  check_slots(&w->pp, false);
  assert_true(w->pp.nslots > before);
  for (size_t i = 0; i < w->p.n; ++i) w->p.pos[i] = v3_scale(w->p.pos[i], 1.04); /* some open */
  adem_world_compute_forces(w);
  check_slots(&w->pp, false);
  size_t taken = w->pp.nslots - 1, candidates = w->pp.n;
  /* a permutation (the storage shuffled, pairs moved along) renumbers the slots in the new
   * order, records kept: at most one a pair, so the rest can still take theirs */
  size_t own_before = w->pp.nslots;
  assert_int_equal(adem_world_shuffle_storage(w, 11, &err), ADEM_OK);
  check_slots(&w->pp, true);
  assert_true(w->pp.nslots <= own_before);
  assert_int_equal(adem_world_build_neighbors(w, &err), ADEM_OK);
  check_slots(&w->pp, true);
  printf("# %zu candidates, %zu took a slot, %zu touching after the build\n", candidates, taken,
         w->pp.nslots - 1);
  assert_true(taken > 20 && taken < candidates);
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_grid_matches_brute_force),
      cmocka_unit_test(test_history_survives_rebuild),
      cmocka_unit_test(test_slots_only_for_pairs_that_touched),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
