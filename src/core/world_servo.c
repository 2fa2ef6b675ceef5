/* Servo-controlled walls: each step's move from the last force pass's loads, and the warning
 * when a servo's gain is too high for the stiffness it presses on. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fpenv.h"
#include "hertz.h"
#include "history_switch.h"
#include "jkr.h"
#include "log.h"
#include "parallel.h"
#include "rng.h"
#include "step_limit.h"
#include "world_internal.h"
#include "world_parts.h"
#include "cylinder.h"
#include "mesh_periodic.h"

/* Stiffness of a touching contact for the servo's stability rule: 1.5 F / delta, exact for Hertz
 * (F ~ delta^1.5), of the order for the other laws. */
static double contact_stiffness(const adem_pair_list *l, size_t k, const adem_particles *p) {
  const adem_pair_result *r = &l->res[adem_pairs_slot(l, k)];
  double delta = r->overlap_ratio * p->radius[l->a[k]];
  return l->touching[k] && delta > 0.0 ? 1.5 * v3_norm(r->force_a) / delta : 0.0;
}

static void servo_warn(adem_motion *m, const char *name, double K, double dt) {
  double g = m->servo.gain * K * dt;
  if (m->servo_warned || !(g > 0.5)) return;
  m->servo_warned = true;
  adem_log(ADEM_LOG_WARN,
           "the servo of wall '%s' may be unstable: gain x stiffness x dt = %.3g x %.3g N/m x %.3g s "
           "= %.3g (> 0.5, the rule is < 1 with the stiffness of all it presses on, estimated "
           "from its contacts); lower the gain",
           name, m->servo.gain, K, dt, g);
}

/* The mesh wall (index among the mesh walls) whose measuring servo group g is, or -1. */
static int measuring_wall(const adem_walls *wl, int g) {
  if (!wl->mesh_motion[g].servo.on || wl->mesh_motion[g].servo.unmeasured) return -1;
  for (int k = 0; k < wl->nmesh_walls; ++k)
    if (g >= wl->mesh_walls[k].first && g < wl->mesh_walls[k].first + wl->mesh_walls[k].count)
      return k;
  return -1;
}

/* Warns once per servo whose gain K dt exceeds 0.5, K the sum of its contacts' stiffnesses:
 * slot k of the sums a plane's, nplanes + k mesh wall k's, each over the particles by id and
 * their contacts in order, as every sum (order independence); a split world adds the terms of
 * every process so (adem_world_split.sum_terms). */
static void servo_check(adem_world *w) {
  adem_walls *wl = &w->walls;
  int np = wl->nplanes, ns = np + wl->nmesh_walls;
  adem_motion **lead = calloc((size_t)ns + 1, sizeof *lead);
  double *K = calloc((size_t)ns + 1, sizeof *K);
  size_t n = 0, cap = 64;
  adem_id_term *t = malloc(cap * sizeof *t);
  bool ok = lead && K && t;
  for (int k = 0; ok && k < ns; ++k) {
    adem_motion *m = k < np ? &wl->planes[k].motion
                            : (adem_motion *)adem_walls_mesh_wall_servo(wl, k - np);
    lead[k] = m && m->servo.on && !m->servo_warned ? m : NULL;
  }
  for (size_t r = 0; ok && r < w->nb.gathered; ++r) {
    size_t i = w->nb.id_order[r];
    uint32_t seq = 0;
    size_t e0 = w->nb.pw_start[i], e1 = w->nb.pw_start[i + 1];
    size_t j0 = w->pm.start ? w->pm.start[i] : 0, j1 = w->pm.start ? w->pm.start[i + 1] : 0;
    for (size_t e = e0; ok && e < e1 + (j1 - j0); ++e) {
      int slot;
      double v;
      if (e < e1) { /* a plane contact */
        size_t j = w->nb.pw_entries[e];
        slot = w->pw.b[j] < (uint32_t)np ? (int)w->pw.b[j] : -1;
        v = slot >= 0 && lead[slot] ? contact_stiffness(&w->pw, j, &w->p) : 0.0;
      } else { /* a mesh slot: the touching ones come first */
        size_t j = j0 + (e - e1);
        if (!w->pm.l.touching[j]) break;
        int k = measuring_wall(wl, (int)wl->mesh.group[w->pm.owner[j]]);
        slot = k < 0 ? -1 : np + k;
        v = slot >= 0 && lead[slot] ? contact_stiffness(&w->pm.l, j, &w->p) : 0.0;
      }
      if (slot < 0 || !lead[slot]) continue;
      if (n == cap) {
        adem_id_term *q = realloc(t, 2 * cap * sizeof *q);
        if (!q) {
          ok = false;
          break;
        }
        t = q;
        cap *= 2;
      }
      t[n++] = (adem_id_term){w->p.id[i], (uint32_t)i, seq++, (uint32_t)slot, 0, v};
    }
  }
  const adem_world_split *sp = w->split;
  if (sp) { /* every process, even one out of memory: the sums are collective */
    adem_error ignored;
    if (sp->sum_terms(sp->ctx, w, ok ? t : NULL, ok ? n : 0, K, ns, &ignored)) ok = false;
  } else {
    for (size_t k = 0; ok && k < n; ++k) K[t[k].slot] += t[k].v;
  }
  for (int k = 0; ok && k < ns; ++k)
    if (lead[k])
      servo_warn(lead[k], k < np ? wl->planes[k].def.name : wl->mesh_walls[k - np].name, K[k], w->dt);
  free(lead);
  free(K);
  free(t);
}

/* The servos move by their laws from the last force pass's loads, before the walls are placed. */
adem_status adem_world_servo_step(adem_world *w, double dt, adem_error *err) {
  const adem_world_split *sp = w->split;
  if (w->step % 64 == 0) servo_check(w); /* a warning: now and then is enough */
  adem_vec3 *f = malloc((size_t)(w->walls.nplanes > 0 ? w->walls.nplanes : 1) * sizeof *f);
  adem_status st = ADEM_OK;
  if (sp) st = sp->plane_forces(sp->ctx, w, f, err); /* the whole system's (collective) */
  else if (f) adem_world_plane_forces(w, f);
  if (!f && !st) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  if (!st) adem_walls_servo_step(&w->walls, f, dt);
  free(f);
  return st;
}
