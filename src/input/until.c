/* Run-until conditions (until.h). */
#include "until.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/vec3.h"
#include "world_internal.h"

void adem_until_init(adem_until *u, const adem_until_def *def) {
  memset(u, 0, sizeof *u);
  u->def = *def;
  adem_until_reset(u);
  u->met_step = ADEM_UNTIL_NEVER;
}

void adem_until_reset(adem_until *u) {
  u->ratio_now = u->load_now = NAN; /* not checked yet (for the progress line) */
  u->kinetic_since = ADEM_UNTIL_NEVER;
  u->load_since = ADEM_UNTIL_NEVER;
  u->load_lo = u->load_hi = 0.0;
}

uint64_t adem_until_period(const adem_until *u, double dt) {
  double k = round(u->def.interval / dt);
  return k < 1.0 || !isfinite(k) ? 1 : (uint64_t)k;
}

uint64_t adem_until_next_check(const adem_until *u, double dt, uint64_t step) {
  uint64_t p = adem_until_period(u, dt);
  return (step / p + 1) * p;
}

/* (translational + rotational) kinetic energy per particle, summed in order of id: when the run
 * ends must not depend on the storage order (docs/architecture.md, "Order independence"). *ratio:
 * the total over sum m |g| d, the energy it takes to lift every particle by its diameter. */
static double kinetic_per_particle(const adem_world *w, double *ratio) {
  const adem_particles *p = &w->p;
  *ratio = NAN;
  uint32_t *order = adem_world_id_order(w);
  if (!order) return NAN; /* out of memory: not at rest */
  double e = 0.0, lift = 0.0, g = v3_norm(w->gravity);
  for (size_t k = 0; k < p->n; ++k) {
    size_t i = order[k];
    e += 0.5 * v3_norm2(p->vel[i]) / p->inv_mass[i] + 0.5 * v3_norm2(p->omega[i]) / p->inv_inertia[i];
    lift += g * 2.0 * p->radius[i] / p->inv_mass[i];
  }
  free(order);
  *ratio = lift > 0.0 ? e / lift : INFINITY;
  return p->n ? e / (double)p->n : INFINITY;
}

static double wall_load(const adem_until *u, const adem_world *w) {
  adem_vec3 f = v3_zero();
  int k = u->def.wall_index;
  if (u->def.wall_kind == ADEM_UNTIL_PLANE) {
    adem_vec3 *all = malloc((size_t)w->walls.nplanes * sizeof *all);
    if (!all) return NAN;
    adem_world_plane_forces(w, all);
    f = all[k];
    free(all);
  } else {
    size_t ng = (size_t)w->walls.mesh.ngroups, nw = (size_t)w->walls.nmesh_walls;
    adem_vec3 *all = malloc((ng + nw + 1) * sizeof *all);
    if (!all) return NAN;
    adem_world_mesh_loads(w, all, NULL, all + ng, NULL);
    f = u->def.wall_kind == ADEM_UNTIL_MESH_GROUP ? all[k] : all[ng + (size_t)k];
    free(all);
  }
  return v3_dot(f, u->def.direction);
}

bool adem_until_check(adem_until *u, const adem_world *w, bool waiting) {
  uint64_t s = w->step;
  bool ok = !waiting;
  uint64_t hold = (uint64_t)llround(u->def.hold / w->dt);
  if (u->def.kinetic > 0.0 || u->def.kinetic_ratio > 0.0) {
    u->kinetic_now = kinetic_per_particle(w, &u->ratio_now);
    bool below = (u->def.kinetic <= 0.0 || u->kinetic_now < u->def.kinetic) &&
                 (u->def.kinetic_ratio <= 0.0 || u->ratio_now < u->def.kinetic_ratio);
    if (!waiting && below) {
      if (u->kinetic_since == ADEM_UNTIL_NEVER) u->kinetic_since = s;
    } else {
      u->kinetic_since = ADEM_UNTIL_NEVER;
    }
    ok = ok && u->kinetic_since != ADEM_UNTIL_NEVER && s - u->kinetic_since >= hold;
  }
  if (u->def.load) {
    double f = wall_load(u, w);
    u->load_now = f;
    double lo = fmin(u->load_lo, f), hi = fmax(u->load_hi, f);
    double size = fmax(fabs(lo), fabs(hi));
    if (waiting || !isfinite(f)) {
      u->load_since = ADEM_UNTIL_NEVER;
    } else if (u->load_since != ADEM_UNTIL_NEVER && hi - lo <= u->def.tolerance * size && size > 0.0) {
      u->load_lo = lo; /* the streak goes on */
      u->load_hi = hi;
    } else { /* a new streak starts here (a load of zero starts none) */
      u->load_since = f != 0.0 ? s : ADEM_UNTIL_NEVER;
      u->load_lo = u->load_hi = f;
    }
    ok = ok && u->load_since != ADEM_UNTIL_NEVER && s - u->load_since >= hold;
  }
  if (ok) u->met_step = s;
  return ok;
}

void adem_until_summary(const adem_until *u, char *buf, size_t n) {
  char a[160] = "", b[200] = "";
  if (u->def.kinetic > 0.0)
    snprintf(a, sizeof a, "kinetic energy per particle below %g J", u->def.kinetic);
  if (u->def.kinetic_ratio > 0.0)
    snprintf(a + strlen(a), sizeof a - strlen(a), "%skinetic energy below %g x sum m |g| d",
             a[0] ? " and " : "", u->def.kinetic_ratio);
  if (u->def.load)
    snprintf(b, sizeof b, "the load on `%s` along (%g, %g, %g) steady within %g %%", u->def.wall,
             u->def.direction.x, u->def.direction.y, u->def.direction.z, 100.0 * u->def.tolerance);
  snprintf(buf, n, "%s%s%s for %g s (checked every %g s)", a, a[0] && b[0] ? " and " : "", b,
           u->def.hold, u->def.interval);
}

void adem_until_describe(const adem_until *u, char *buf, size_t n) {
  char a[160] = "", b[200] = "";
  if (u->def.kinetic > 0.0)
    snprintf(a, sizeof a, "kinetic energy per particle %.3g J < %g J", u->kinetic_now, u->def.kinetic);
  if (u->def.kinetic_ratio > 0.0)
    snprintf(a + strlen(a), sizeof a - strlen(a), "%skinetic energy %.3g x sum m |g| d < %g",
             a[0] ? " and " : "", u->ratio_now, u->def.kinetic_ratio);
  if (u->def.load)
    snprintf(b, sizeof b, "the load on `%s` steady within %g %% (%.6g N, range %.6g..%.6g N)",
             u->def.wall, 100.0 * u->def.tolerance, u->load_now, u->load_lo, u->load_hi);
  snprintf(buf, n, "%s%s%s for %g s", a, a[0] && b[0] ? " and " : "", b, u->def.hold);
}

void adem_until_status(const adem_until *u, double dt, uint64_t step, char *buf, size_t n) {
  size_t len = 0;
  buf[0] = '\0';
#define STATUS(...) (len += (size_t)snprintf(buf + len, len < n ? n - len : 0, __VA_ARGS__))
  bool kinetic = u->def.kinetic > 0.0 || u->def.kinetic_ratio > 0.0;
  if (kinetic ? isnan(u->ratio_now) : isnan(u->load_now)) { /* NaN: no check yet */
    STATUS("until: not checked yet");
    return;
  }
  STATUS("until:");
  if (u->def.kinetic > 0.0)
    STATUS(" E_k %.2g %s %.2g J/particle", u->kinetic_now,
           u->kinetic_now < u->def.kinetic ? "<" : ">", u->def.kinetic);
  if (u->def.kinetic_ratio > 0.0)
    STATUS(" E_k/mgd %.2g %s %.2g", u->ratio_now, u->ratio_now < u->def.kinetic_ratio ? "<" : ">",
           u->def.kinetic_ratio);
  if (u->def.load) {
    double size = fmax(fabs(u->load_lo), fabs(u->load_hi));
    STATUS(" load %.4g N spread %.2g%% (%.2g%%)", u->load_now,
           size > 0.0 ? 100.0 * (u->load_hi - u->load_lo) / size : 0.0, 100.0 * u->def.tolerance);
  }
  uint64_t since = kinetic ? u->kinetic_since : 0;
  if (u->def.load && (since == ADEM_UNTIL_NEVER || u->load_since == ADEM_UNTIL_NEVER))
    since = ADEM_UNTIL_NEVER;
  else if (u->def.load && u->load_since > since)
    since = u->load_since;
  if (since != ADEM_UNTIL_NEVER && step >= since)
    STATUS(", held %.3g/%g s", (double)(step - since) * dt, u->def.hold);
#undef STATUS
}

void adem_until_save(adem_writer *wr, const adem_until *u) {
  adem_put_u64(wr, u->kinetic_since);
  adem_put_u64(wr, u->load_since);
  adem_put_f64(wr, u->load_lo);
  adem_put_f64(wr, u->load_hi);
  adem_put_f64(wr, u->kinetic_now);
  adem_put_f64(wr, u->load_now);
  adem_put_u64(wr, u->met_step);
}

void adem_until_load(adem_reader *rd, adem_until *u) {
  u->kinetic_since = adem_get_u64(rd);
  u->load_since = adem_get_u64(rd);
  u->load_lo = adem_get_f64(rd);
  u->load_hi = adem_get_f64(rd);
  u->kinetic_now = adem_get_f64(rd);
  u->load_now = adem_get_f64(rd);
  u->met_step = adem_get_u64(rd);
}
