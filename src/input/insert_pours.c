/* Insertion: pours, batches of spheres dropped into a region at a rate during the run, and their
 * state in checkpoints. */
#include "insert.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cylinder.h"
#include "mesh_contact.h"
#include "dmath.h"
#include "log.h"
#include "adem/vec3.h"
#include "stl.h"
#include "world_internal.h"

/* ---------------------------------------------------------------- pours */

adem_status adem_pours_add(adem_pours **ps, adem_pour_def *def, double density, adem_error *err) {
  if (!*ps) {
    *ps = calloc(1, sizeof **ps);
    if (!*ps) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  adem_pours *s = *ps;
  adem_pour *p = realloc(s->p, (size_t)(s->n + 1) * sizeof *p);
  if (!p) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  s->p = p;
  adem_pour *q = &p[s->n++];
  memset(q, 0, sizeof *q);
  q->def = *def;
  q->density = density;
  q->rng = adem_rng_seed(def->seed);
  memset(&def->region, 0, sizeof def->region); /* moved */
  memset(&def->dist, 0, sizeof def->dist);
  return ADEM_OK;
}

void adem_pours_free(adem_pours *ps) {
  if (!ps) return;
  for (int k = 0; k < ps->n; ++k) {
    adem_insert_region_free(&ps->p[k].def.region);
    adem_insert_dist_free(&ps->p[k].def.dist);
  }
  free(ps->p);
  free(ps);
}

double adem_pour_total(const adem_pour *p) {
  double window = p->def.end - p->def.start;
  return p->def.rate > 0.0 ? (double)llround(p->def.rate * window) : p->def.mass_rate * window;
}

/* Batch schedule on step counts: batch j at step s_a + j k, for j < nbatches; it brings the total
 * to the fraction min(1, (j + 1) k / (s_b - s_a)) of the pour. */
typedef struct pour_steps {
  uint64_t s_a, s_b, k, nbatches;
} pour_steps;

static pour_steps steps_of(const adem_pour *p, double dt) {
  pour_steps s;
  s.s_a = (uint64_t)llround(p->def.start / dt);
  s.s_b = (uint64_t)llround(p->def.end / dt);
  if (s.s_b < s.s_a) s.s_b = s.s_a;
  double k = round(p->def.interval / dt);
  s.k = k < 1.0 ? 1 : (uint64_t)k;
  uint64_t span = s.s_b - s.s_a;
  s.nbatches = span == 0 ? 1 : (span + s.k - 1) / s.k;
  return s;
}

uint64_t adem_pours_next_step(const adem_pours *ps, double dt, uint64_t step) {
  uint64_t next = UINT64_MAX;
  for (int i = 0; ps && i < ps->n; ++i) {
    const adem_pour *p = &ps->p[i];
    pour_steps s = steps_of(p, dt);
    uint64_t j = p->next_batch;
    if (j >= s.nbatches) continue;
    if (s.s_a + j * s.k <= step) j = step < s.s_a ? 0 : (step - s.s_a) / s.k + 1;
    if (j < s.nbatches && s.s_a + j * s.k < next) next = s.s_a + j * s.k;
  }
  return next;
}

/* Mass of a sphere, computed as the world computes it. */
static double pour_mass(const adem_pour *p, double r) {
  return p->density * (4.0 / 3.0) * ADEM_PI * r * r * r;
}

/* One batch: radii for the batch, placed among the world's particles and walls. */
static adem_status pour_batch(adem_pour *p, adem_world *w, const pour_steps *s, adem_error *err) {
  uint64_t j = p->next_batch;
  p->density = w->mat.m[p->def.material].def.density; /* a stage may have changed it */
  uint64_t span = s->s_b - s->s_a;
  double frac = span == 0 ? 1.0 : fmin(1.0, (double)((j + 1) * s->k) / (double)span);
  if (j + 1 >= s->nbatches) frac = 1.0;
  double *radii = NULL;
  size_t n = 0, cap = 0;
  adem_status st = ADEM_OK;
  if (p->def.rate > 0.0) {
    double target = j + 1 >= s->nbatches ? adem_pour_total(p) : (double)llround(adem_pour_total(p) * frac);
    double need = target - (double)p->inserted;
    for (double k = 0; k < need && !st; ++k) {
      double r;
      if ((st = adem_insert_draw_radius(&p->def.dist, &p->rng, &r, err))) break;
      if (adem_insert_push_radius(&radii, &n, &cap, r)) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    }
  } else {
    double target = adem_pour_total(p) * frac, planned = 0.0;
    while (!st) {
      double r;
      if ((st = adem_insert_draw_radius(&p->def.dist, &p->rng, &r, err))) break;
      double m = pour_mass(p, r);
      if (p->mass + planned + 0.5 * m > target) break;
      if ((double)n >= ADEM_INSERT_MAX_SPHERES) break;
      if (adem_insert_push_radius(&radii, &n, &cap, r)) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      planned += m;
    }
  }
  if (st) {
    char why[ADEM_MSG_MAX];
    snprintf(why, sizeof why, "%s", err ? err->message : "");
    free(radii);
    return adem_error_set(err, st, "pour `%s`: %s", p->def.name, why);
  }
  if (n > 1) qsort(radii, n, sizeof *radii, adem_insert_compare_descending); /* none: radii may be NULL */
  adem_vec3 *pos = NULL;
  double *rad = NULL;
  size_t placed = 0;
  uint64_t attempts = 0;
  bool *keep = malloc((n + 1) * sizeof *keep);
  adem_placer pl = {&p->def.region, w, p->def.max_attempts, true};
  if (!keep) st = ADEM_ERR_NOMEM;
  if (!st)
    st = adem_insert_place(&pl, &p->rng, radii, n, w->p.pos, w->p.radius, w->p.n, &pos, &rad,
                           keep, &placed, &attempts);
  if (st) {
    free(radii);
    free(keep);
    return adem_error_set(err, ADEM_ERR_NOMEM, "pour `%s`: out of memory", p->def.name);
  }
  for (size_t k = 0; k < placed && !st; ++k) {
    adem_particle_def d = adem_default_particle_def();
    d.position = pos[k];
    d.radius = rad[k];
    d.velocity = p->def.velocity;
    d.angular_velocity = p->def.angular_velocity;
    d.material = p->def.material;
    d.group = p->def.group;
    st = adem_world_add_particle(w, &d, NULL, err);
    if (!st) p->mass += pour_mass(p, rad[k]);
  }
  p->inserted += placed;
  if (placed < n) p->short_batches++;
  bool last = j + 1 >= s->nbatches;
  if (!st && last && placed < n) {
    if (p->def.rate > 0.0)
      adem_log(ADEM_LOG_WARN,
               "pour `%s`: inserted %llu of %.0f particles by t = %g s: the region had no room for "
               "the rest within max_attempts (%llu per particle); %d of %llu batches fell short",
               p->def.name, (unsigned long long)p->inserted, adem_pour_total(p), w->time,
               (unsigned long long)p->def.max_attempts, p->short_batches,
               (unsigned long long)s->nbatches);
    else
      adem_log(ADEM_LOG_WARN,
               "pour `%s`: inserted %.6g of %.6g kg (%llu particles) by t = %g s: the region had "
               "no room for the rest within max_attempts (%llu per particle); %d of %llu batches "
               "fell short",
               p->def.name, p->mass, adem_pour_total(p), (unsigned long long)p->inserted, w->time,
               (unsigned long long)p->def.max_attempts, p->short_batches,
               (unsigned long long)s->nbatches);
  }
  free(radii);
  free(keep);
  free(pos);
  free(rad);
  return st;
}

adem_status adem_pours_run(adem_pours *ps, adem_world *w, adem_error *err) {
  if (!ps || ps->n == 0) return ADEM_OK;
  bool prepared = w->prepared;
  size_t first = w->p.n;
  adem_status st = ADEM_OK;
  for (int i = 0; i < ps->n && !st; ++i) {
    adem_pour *p = &ps->p[i];
    pour_steps s = steps_of(p, w->dt);
    while (!st && p->next_batch < s.nbatches && s.s_a + p->next_batch * s.k <= w->step) {
      st = pour_batch(p, w, &s, err);
      p->next_batch++;
    }
  }
  if (st || w->p.n == first || !prepared) return st;
  return adem_world_admit_particles(w, first, err);
}

unsigned char *adem_pours_pack(const adem_pours *ps, size_t *len) {
  int n = ps ? ps->n : 0;
  size_t bytes = 8 + (size_t)n * 8 * 8;
  unsigned char *b = malloc(bytes);
  if (!b) return NULL;
  uint64_t v = (uint64_t)n;
  memcpy(b, &v, 8);
  for (int k = 0; k < n; ++k) {
    const adem_pour *p = &ps->p[k];
    uint64_t rec[8] = {p->rng.s[0], p->rng.s[1], p->rng.s[2], p->rng.s[3], p->inserted, 0,
                       p->next_batch, (uint64_t)p->short_batches};
    memcpy(&rec[5], &p->mass, 8);
    memcpy(b + 8 + (size_t)k * 64, rec, 64);
  }
  *len = bytes;
  return b;
}

adem_status adem_pours_unpack(adem_pours *ps, const unsigned char *buf, size_t len,
                              adem_error *err) {
  uint64_t n = 0;
  if (len >= 8) memcpy(&n, buf, 8);
  int have = ps ? ps->n : 0;
  if (len < 8 || n != (uint64_t)have || len != 8 + n * 64)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "its pour state does not match the pours of its own case text");
  for (int k = 0; k < have; ++k) {
    adem_pour *p = &ps->p[k];
    uint64_t rec[8];
    memcpy(rec, buf + 8 + (size_t)k * 64, 64);
    for (int i = 0; i < 4; ++i) p->rng.s[i] = rec[i];
    p->inserted = rec[4];
    memcpy(&p->mass, &rec[5], 8);
    p->next_batch = rec[6];
    p->short_batches = (int)rec[7];
  }
  return ADEM_OK;
}
