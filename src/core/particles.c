/* Per-particle arrays (the table in particles.h) and the velocity-Verlet integrator. */
#include "particles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "adem/vec3.h"
#include "log.h"
#include "parallel.h"

static const adem_soa_field particle_fields[] = {
#define ADEM_X(type, name, kind, doc) {#name, offsetof(adem_particles, name), sizeof(type), kind},
    ADEM_PARTICLE_FIELDS(ADEM_X)
#undef ADEM_X
};

adem_soa_layout adem_particles_layout(void) {
  adem_soa_layout L = {particle_fields, sizeof particle_fields / sizeof particle_fields[0]};
  return L;
}

adem_status adem_particles_reserve(adem_particles *p, size_t cap) {
  if (cap <= p->cap) return ADEM_OK;
  adem_status st = adem_soa_grow(p, adem_particles_layout(), cap);
  if (!st) p->cap = cap;
  return st;
}

void adem_particles_free(adem_particles *p) {
  adem_soa_free(p, adem_particles_layout());
  memset(p, 0, sizeof *p);
}

adem_status adem_particles_keep(adem_particles *p, adem_particle_kind kind) {
  if (kind == ADEM_PART_ALWAYS) return ADEM_OK; /* allocated by adem_particles_reserve */
  adem_soa_layout L = adem_particles_layout();
  for (size_t k = 0; k < L.count; ++k) {
    void **a = (void **)((char *)p + L.fields[k].offset);
    if (L.fields[k].kind != (int)kind || *a) continue;
    *a = calloc(p->cap ? p->cap : 1, L.fields[k].elem); /* no particle yet: grown with the table */
    if (!*a) {
      adem_particles_drop(p, kind); /* all of a kind or none */
      return ADEM_ERR_NOMEM;
    }
  }
  return ADEM_OK;
}

void adem_particles_drop(adem_particles *p, adem_particle_kind kind) {
  if (kind == ADEM_PART_ALWAYS) return;
  adem_soa_layout L = adem_particles_layout();
  for (size_t k = 0; k < L.count; ++k) {
    void **a = (void **)((char *)p + L.fields[k].offset);
    if (L.fields[k].kind != (int)kind) continue;
    free(*a);
    *a = NULL;
  }
}

bool adem_particles_has(const adem_particles *p, adem_particle_kind kind) {
  adem_soa_layout L = adem_particles_layout();
  for (size_t k = 0; k < L.count; ++k)
    if (L.fields[k].kind == (int)kind) return *(void *const *)((const char *)p + L.fields[k].offset) != NULL;
  return false;
}

size_t adem_particles_kind_bytes(adem_particle_kind kind) {
  adem_soa_layout L = adem_particles_layout();
  size_t b = 0;
  for (size_t k = 0; k < L.count; ++k)
    if (L.fields[k].kind == (int)kind) b += L.fields[k].elem;
  return b;
}

adem_status adem_particles_permute(adem_particles *p, const size_t *perm) {
  return adem_soa_permute(p, adem_particles_layout(), p->n, perm);
}

typedef struct id_index {
  uint64_t id;
  uint32_t i;
} id_index;

static int compare_id(const void *x, const void *y) {
  const id_index *a = x, *b = y;
  if (a->id != b->id) return a->id < b->id ? -1 : 1;
  return a->i < b->i ? -1 : a->i > b->i;
}

adem_status adem_particles_id_order(const adem_particles *p, uint32_t *order) {
  size_t n = p->n;
  if (n >= UINT32_MAX) return ADEM_ERR_NOMEM;
  for (size_t k = 0; k < n; ++k) order[k] = UINT32_MAX;
  size_t i = 0;
  for (; i < n; ++i) { /* ids 0 .. n-1: each goes to its own place */
    uint64_t id = p->id[i];
    if (id >= n || order[id] != UINT32_MAX) break;
    order[id] = (uint32_t)i;
  }
  if (i == n) return ADEM_OK;
  id_index *s = malloc(n * sizeof *s);
  if (!s) return ADEM_ERR_NOMEM;
  for (size_t k = 0; k < n; ++k) s[k] = (id_index){p->id[k], (uint32_t)k};
  qsort(s, n, sizeof *s, compare_id);
  for (size_t k = 0; k < n; ++k) order[k] = s[k].i;
  free(s);
  return ADEM_OK;
}

size_t adem_particles_append(adem_particles *p, uint64_t id, adem_vec3 pos, adem_vec3 vel,
                             adem_vec3 omega, double radius, double density, int material,
                             int group) {
  if (p->n == p->cap && adem_particles_reserve(p, p->cap ? 2 * p->cap : 64)) return SIZE_MAX;
  size_t i = p->n++;
  adem_soa_layout L = adem_particles_layout();
  for (size_t k = 0; k < L.count; ++k) { /* every field starts at zero (an absent one reads so) */
    char *a = *(char **)((char *)p + L.fields[k].offset);
    if (a) memset(a + i * L.fields[k].elem, 0, L.fields[k].elem);
  }
  double mass = density * (4.0 / 3.0) * ADEM_PI * radius * radius * radius;
  p->pos[i] = pos;
  p->vel[i] = vel;
  p->omega[i] = omega;
  p->radius[i] = radius;
  p->inv_mass[i] = 1.0 / mass;
  p->inv_inertia[i] = 1.0 / (0.4 * mass * radius * radius); /* solid sphere */
  p->id[i] = id;
  p->material[i] = (uint16_t)material;
  p->group[i] = (uint16_t)group;
  p->pos_at_build[i] = pos;
  return i;
}

typedef struct kick_args {
  adem_particles *p;
  double h;
  bool closing;
} kick_args;

static inline void kick_one(const kick_args *a, size_t i) {
  adem_particles *p = a->p;
  if (p->frozen[i]) return;                                           /* its wall's motion sets its velocity and spin */
  p->vel[i] = v3_axpy(p->vel[i], a->h * p->inv_mass[i], p->force[i]); /* H3 */
  if (a->closing && p->held[i])
    p->omega[i] = v3_zero();
  else
    p->omega[i] = v3_axpy(p->omega[i], a->h * p->inv_inertia[i], p->torque[i]); /* H4 */
}

void adem_particles_kick(adem_particles *p, double h, bool closing, int nthreads) {
  kick_args a = {p, h, closing};
  ADEM_FOR(nthreads, p->n, kick_one, &a);
}

/* Kicks (opening half kick h) and moves particle i; returns how much farther than its radius
 * it went. */
static inline double kick_drift_one(adem_particles *p, double h, double dt, size_t i) {
  if (p->frozen[i]) return -p->radius[i];                            /* placed with its wall (adem_world_place_frozen) */
  adem_vec3 v = v3_axpy(p->vel[i], h * p->inv_mass[i], p->force[i]); /* H3 */
  p->vel[i] = v;
  p->omega[i] = v3_axpy(p->omega[i], h * p->inv_inertia[i], p->torque[i]); /* H4 */
  p->pos[i] = v3_axpy(p->pos[i], dt, v);
  double moved = dt * v3_norm(v); /* the drift is a straight segment */
  p->path_length[i] += moved;
  return moved - p->radius[i];
}

double adem_particles_kick_drift(adem_particles *p, double h, double dt, int nthreads) {
  double worst = -INFINITY;
  size_t n = p->n;
  if (nthreads > 1) {
    ADEM_PARALLEL_FOR_MAX(worst)
    for (size_t i = 0; i < n; ++i) {
      double e = kick_drift_one(p, h, dt, i);
      worst = e > worst ? e : worst;
    }
  } else {
    for (size_t i = 0; i < n; ++i) {
      double e = kick_drift_one(p, h, dt, i);
      worst = e > worst ? e : worst;
    }
  }
  return worst;
}

typedef struct wrap_args {
  adem_particles *p;
  const adem_periodic *pb;
} wrap_args;

static inline void wrap_one(const wrap_args *a, size_t i) {
  adem_particles *p = a->p;
  const adem_periodic *pb = a->pb;
  adem_vec3 x = p->pos[i];
  int32_t *im = p->image[i].n;
  if (pb->axes & 1u) x.x = adem_periodic_wrap_component(x.x, pb->lo[0], pb->len[0], &im[0]);
  if (pb->axes & 2u) x.y = adem_periodic_wrap_component(x.y, pb->lo[1], pb->len[1], &im[1]);
  if (pb->axes & 4u) x.z = adem_periodic_wrap_component(x.z, pb->lo[2], pb->len[2], &im[2]);
  p->pos[i] = x;
}

adem_status adem_particles_wrap(adem_particles *p, const adem_periodic *pb, int nthreads) {
  if (!pb || !pb->axes) return ADEM_OK;
  adem_status st = adem_particles_keep(p, ADEM_PART_PERIODIC); /* the crossings start at zero */
  if (st) return st;
  wrap_args a = {p, pb};
  ADEM_FOR(nthreads, p->n, wrap_one, &a);
  return ADEM_OK;
}

void adem_particles_mark_build(adem_particles *p) {
  if (p->n) memcpy(p->pos_at_build, p->pos, p->n * sizeof *p->pos); /* none yet: both NULL */
}

void adem_particles_save(adem_writer *wr, const adem_particles *p) {
  adem_put_u64(wr, p->n);
  adem_soa_save(wr, p, adem_particles_layout(), p->n);
}

adem_status adem_particles_load(adem_reader *rd, adem_particles *p, adem_error *err) {
  adem_soa_layout L = adem_particles_layout();
  uint64_t n = adem_get_count(rd, adem_soa_item_bytes(L));
  if (rd->failed) return ADEM_OK;
  if (n > p->cap && adem_particles_reserve(p, (size_t)n) != ADEM_OK)
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %llu particles",
                          (unsigned long long)n);
  p->n = (size_t)n;
  /* every kind present to take the bytes; one whose bytes are all zero leaves again */
  for (int kind = 1; kind < ADEM_PART_KINDS; ++kind)
    if (adem_particles_keep(p, (adem_particle_kind)kind))
      return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %llu particles",
                            (unsigned long long)n);
  adem_soa_load(rd, p, L, p->n);
  for (int kind = 1; kind < ADEM_PART_KINDS; ++kind) {
    bool zero = true;
    for (size_t k = 0; k < L.count && zero; ++k)
      if (L.fields[k].kind == kind) zero = adem_soa_all_zero(p, &L.fields[k], p->n);
    if (zero) adem_particles_drop(p, (adem_particle_kind)kind);
  }
  return ADEM_OK;
}
