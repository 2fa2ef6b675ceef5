/* Claims: the optional kinds of particle field (particles.h: the energy balance's terms, BROF's
 * impulse, the frozen particles' wall and anchor, the external force, the periodic image) are
 * allocated only while a run needs them, and an absent one reads as zeros; a checkpoint holds
 * every field whatever a run keeps (the same bytes as with the kind present and zero), and its
 * load keeps a kind only when some of its bytes are not zero. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "adem/adem.h"
#include "adem/vec3.h"
#include "helpers.h"
#include "world_internal.h"

/* 27 spheres of radius 1 mm on a 2.05 mm lattice, the middle column along x meeting its
 * neighbours. */
static adem_world *cloud(void) {
  adem_world *w = adem_world_create();
  int m = test_material(w, "glass", 1e7, 0.3, 0.5, 0.5);
  assert_true(m >= 0);
  for (int k = 0; k < 27; ++k) {
    adem_vec3 x = v3(2.05e-3 * (k % 3), 2.05e-3 * ((k / 3) % 3), 2e-3 + 2.05e-3 * (k / 9));
    adem_vec3 v = v3(k % 3 == 1 ? 0.5 : 0.0, 0.0, 0.0);
    assert_true(test_particle(w, m, x, v, 1e-3) == k);
  }
  adem_world_set_dt(w, 1e-5);
  return w;
}

static void assert_kinds(const adem_particles *p, bool balance, bool brof, bool frozen,
                         bool external, bool periodic) {
  assert_true(adem_particles_has(p, ADEM_PART_BALANCE) == balance);
  assert_true(adem_particles_has(p, ADEM_PART_BROF) == brof);
  assert_true(adem_particles_has(p, ADEM_PART_FROZEN) == frozen);
  assert_true(adem_particles_has(p, ADEM_PART_EXTERNAL) == external);
  assert_true(adem_particles_has(p, ADEM_PART_PERIODIC) == periodic);
}

/* Each kind comes when the run needs it; the balance's goes when the balance is switched off. */
static void test_kinds_follow_the_run(void **state) {
  (void)state;
  adem_error err;
  adem_world *w = cloud();
  adem_world_set_energy_balance(w, false);
  assert_int_equal(adem_world_step(w, 20, &err), ADEM_OK);
  assert_kinds(&w->p, false, false, false, false, false);
  adem_diagnostics d = adem_world_diagnostics(w);
  assert_true(d.brof_impulse.x == 0.0 && d.brof_impulse.y == 0.0 && d.brof_impulse.z == 0.0);

  adem_world_set_energy_balance(w, true);
  assert_int_equal(adem_world_step(w, 200, &err), ADEM_OK);
  assert_kinds(&w->p, true, false, false, false, false);
  d = adem_world_diagnostics(w);
  assert_true(d.dissipated > 0.0); /* the collisions' damping */
  adem_world_set_energy_balance(w, false);
  assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
  assert_kinds(&w->p, false, false, false, false, false);

  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = it.material_b = 0;
  it.rolling = ADEM_ROLLING_BROF;
  it.param[ADEM_PARAM_ROLLING_FRICTION] = 0.1;
  assert_int_equal(adem_world_set_interaction(w, &it, &err), ADEM_OK);
  assert_int_equal(adem_world_step(w, 20, &err), ADEM_OK);
  assert_kinds(&w->p, false, true, false, false, false);

  assert_int_equal(adem_world_set_external_force(w, 4, v3(0.0, 1e-6, 0.0), &err), ADEM_OK);
  assert_kinds(&w->p, false, true, false, true, false);
  assert_int_equal(adem_world_freeze_particle(w, 0, 0, &err), ADEM_OK);
  assert_kinds(&w->p, false, true, true, true, false);
  assert_int_equal(adem_world_step(w, 20, &err), ADEM_OK);
  adem_world_free(w);

  w = cloud();
  assert_int_equal(adem_world_set_periodic(w, v3(-2e-3, -2e-3, -1.0), v3(1.6e-2, 1.6e-2, 1.0),
                                           ADEM_PERIODIC_X | ADEM_PERIODIC_Y, &err),
                   ADEM_OK);
  assert_int_equal(adem_world_step(w, 20, &err), ADEM_OK);
  assert_kinds(&w->p, true, false, false, false, true); /* the balance is on by default */
  adem_world_free(w);
}

typedef struct buffer {
  unsigned char *d;
  size_t n, cap;
} buffer;

static int sink(void *ctx, const void *data, size_t n) {
  buffer *b = ctx;
  if (b->n + n > b->cap) {
    b->cap = 2 * (b->n + n);
    b->d = realloc(b->d, b->cap);
    if (!b->d) return 0;
  }
  memcpy(b->d + b->n, data, n);
  b->n += n;
  return 1;
}

static buffer saved(const adem_particles *p) {
  buffer b = {NULL, 0, 0};
  adem_writer wr = adem_writer_make(sink, &b);
  adem_particles_save(&wr, p);
  assert_false(wr.failed);
  return b;
}

static void load(const buffer *b, adem_particles *q) {
  adem_reader rd = {b->d, b->d + b->n, 0};
  adem_error err;
  assert_int_equal(adem_particles_load(&rd, q, &err), ADEM_OK);
  assert_false(rd.failed);
  assert_true(rd.at == rd.end);
}

/* A checkpoint's particles: every field, zeros for an absent one; a kind comes back only with
 * a byte that is not zero. */
static void test_checkpoint_holds_every_field(void **state) {
  (void)state;
  adem_error err;
  adem_world *w = cloud();
  adem_world_set_energy_balance(w, false);
  assert_int_equal(adem_world_step(w, 20, &err), ADEM_OK);
  adem_particles *p = &w->p;
  assert_kinds(p, false, false, false, false, false);
  buffer absent = saved(p);
  size_t n = p->n;
  assert_true(absent.n == 8 + adem_soa_item_bytes(adem_particles_layout()) * n +
                              8 * adem_particles_layout().count);
  for (int k = 1; k < ADEM_PART_KINDS; ++k)
    assert_int_equal(adem_particles_keep(p, (adem_particle_kind)k), ADEM_OK);
  buffer zero = saved(p);
  assert_true(zero.n == absent.n && memcmp(zero.d, absent.d, absent.n) == 0);

  adem_particles q;
  memset(&q, 0, sizeof q);
  load(&absent, &q);
  assert_true(q.n == n);
  assert_kinds(&q, false, false, false, false, false);
  assert_memory_equal(q.pos, p->pos, n * sizeof *p->pos);

  p->ext_force[5] = v3(1.0, 2.0, 3.0);
  p->image[7].n[1] = -2;
  buffer some = saved(p);
  load(&some, &q);
  assert_kinds(&q, false, false, false, true, true);
  assert_memory_equal(q.ext_force, p->ext_force, n * sizeof *p->ext_force);
  assert_memory_equal(q.image, p->image, n * sizeof *p->image);
  buffer again = saved(&q);
  assert_true(again.n == some.n && memcmp(again.d, some.d, some.n) == 0);
  /* loading the absent ones again drops them */
  load(&absent, &q);
  assert_kinds(&q, false, false, false, false, false);
  adem_particles_free(&q);
  free(absent.d);
  free(zero.d);
  free(some.d);
  free(again.d);
  adem_world_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_kinds_follow_the_run),
      cmocka_unit_test(test_checkpoint_holds_every_field),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
