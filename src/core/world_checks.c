/* Checks of the world: at the start (overlaps, particles behind walls, periodic boxes the run
 * cannot use, the escape box) and after each step (non-finite or escaped particles, overlaps
 * above the limit, tunnelling next to a mesh). */
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

/* Rejects particles that cut into a mesh face at the start, naming the first by index (as the
 * pp check does): a wall cannot push a particle out gently, it would shoot it off. */
static adem_status check_initial_mesh(const adem_world *w, adem_error *err) {
  const adem_particles *p = &w->p;
  const adem_mesh_pairs *pm = &w->pm;
  if (w->walls.mesh.ntris == 0 || !pm->start) return ADEM_OK;
  for (size_t i = 0; i < p->n; ++i)
    for (size_t k = pm->start[i]; k < pm->start[i + 1]; ++k) {
      uint32_t t = pm->l.b[k];
      adem_vec3 q;
      adem_triangle_feature f;
      double d = sqrt(adem_triangle_distance2(&w->walls.mesh, t, p->pos[i], &q, &f));
      double overlap = p->radius[i] - d;
      if (overlap > fmax(1e-9, w->initial_overlap) * p->radius[i])
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "particle id %llu at (%g, %g, %g) overlaps mesh group '%s' (triangle "
                              "%u) by %g m (%.3g of its radius, allowed %.3g by "
                              "limits.initial_overlap) at the start; move it off the wall or shrink "
                              "it. Particles from another run's checkpoint (`type: state`) keep "
                              "their places but the walls start where this case puts them: a wall "
                              "that moved or turned in that run is back at its file placement",
                              (unsigned long long)p->id[i], p->pos[i].x, p->pos[i].y, p->pos[i].z,
                              w->walls.mesh.groups[w->walls.mesh.group[t]].name, t, overlap,
                              overlap / p->radius[i], w->initial_overlap);
    }
  return ADEM_OK;
}

/* Rejects overlapping particles and particles behind a wall, naming them. */
adem_status adem_world_check_initial_state(const adem_world *w, adem_error *err) {
  const adem_particles *p = &w->p;
  for (size_t k = 0; k < w->pp.n; ++k) {
    size_t i = w->pp.a[k], j = w->pp.b[k];
    double dist = v3_norm(adem_periodic_min_image(&w->periodic, v3_sub(p->pos[j], p->pos[i])));
    double overlap = p->radius[i] + p->radius[j] - dist;
    double tol = fmax(1e-9, w->initial_overlap) * fmin(p->radius[i], p->radius[j]);
    if (overlap > tol)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "initial particles overlap: id %llu at (%g, %g, %g) and id %llu at "
                            "(%g, %g, %g) overlap by %g m (%.3g of the smaller radius, allowed "
                            "%.3g); move them apart or shrink them, or allow overlaps from a "
                            "settled bed with limits.initial_overlap",
                            (unsigned long long)p->id[i], p->pos[i].x, p->pos[i].y, p->pos[i].z,
                            (unsigned long long)p->id[j], p->pos[j].x, p->pos[j].y, p->pos[j].z,
                            overlap, overlap / fmin(p->radius[i], p->radius[j]), w->initial_overlap);
  }
  for (size_t i = 0; i < p->n; ++i)
    for (int k = 0; k < w->walls.nplanes; ++k) {
      const adem_plane_def *pl = &w->walls.planes[k].def;
      if (w->walls.planes[k].inactive || p->frozen[i]) continue; /* a frozen one is wall */
      adem_wall_near near = adem_wall_nearest(pl, p->pos[i]);
      double d = near.live ? near.gap : 0.0;
      if (d < 0.0)
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "particle id %llu at (%g, %g, %g) is outside wall '%s' (its centre "
                              "is %g m behind its surface)",
                              (unsigned long long)p->id[i], p->pos[i].x, p->pos[i].y, p->pos[i].z,
                              pl->name, -d);
    }
  return check_initial_mesh(w, err);
}

/* Periodic boxes the run cannot use: a length below 2 (largest diameter + skin), where a pair
 * could touch through two images at once, a plane cutting a periodic axis, a cylinder or plate
 * or a mesh within reach of a periodic face unless it is the same all along the axis. */
adem_status adem_world_check_periodic(const adem_world *w, adem_error *err) {
  const adem_periodic *pb = &w->periodic;
  if (!pb->axes) return ADEM_OK;
  double rmax = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) rmax = fmax(rmax, w->p.radius[i]);
  double dmax = 2.0 * rmax, skin = w->nb.skin_fraction * dmax;
  for (int d = 0; d < 3; ++d) {
    if (!((pb->axes >> d) & 1u)) continue;
    double need = 2.0 * (dmax + skin);
    if (pb->len[d] < need)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "the periodic box along %c is %g m long; the minimum image needs at "
                            "least 2 (largest diameter + skin) = 2 (%g + %g) = %g m",
                            "xyz"[d], pb -> len[d], dmax, skin, need);
    for (int k = 0; k < w->walls.nplanes; ++k) {
      const adem_plane_def *pl = &w->walls.planes[k].def;
      if (pl->shape != ADEM_WALL_PLANE) { /* a cylinder or disc: cylinder.c */
        adem_status st = adem_wall_check_periodic(pl, d, pb->lo[d], pb->len[d], rmax + skin, err);
        if (st) return st;
        continue;
      }
      double n[3] = {pl->normal.x, pl->normal.y, pl->normal.z};
      if (fabs(n[d]) > 1e-12 * v3_norm(pl->normal))
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "plane wall '%s' (normal (%g, %g, %g)) cuts the periodic axis %c; a "
                              "plane in a periodic box must be parallel to its periodic axes",
                              pl->name, n[0], n[1], n[2], "xyz"[d]);
    }
  }
  /* meshes are not imaged: a shell the same along the axis past both faces, or kept inside them
   * (mesh_periodic.c) */
  for (int d = 0; d < 3; ++d)
    if ((pb->axes >> d) & 1u) {
      adem_status st = adem_mesh_check_periodic(&w->walls.mesh, d, pb->lo[d], pb->len[d],
                                                rmax + skin, err);
      if (st) return st;
    }
  return ADEM_OK;
}

/* Escape check box: the case's domain, or the initial extent of particles and wall points
 * widened generously on each side. */
void adem_world_default_domain(adem_world *w) {
  if (w->has_domain || w->p.n == 0) return;
  adem_vec3 lo = w->p.pos[0], hi = lo;
  double rmax = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) {
    adem_vec3 x = w->p.pos[i];
    lo = v3(fmin(lo.x, x.x), fmin(lo.y, x.y), fmin(lo.z, x.z));
    hi = v3(fmax(hi.x, x.x), fmax(hi.y, x.y), fmax(hi.z, x.z));
    rmax = fmax(rmax, w->p.radius[i]);
  }
  for (int k = 0; k < w->walls.nplanes; ++k) {
    adem_vec3 x0, x1; /* a plane's point; a cylinder's or a disc's box (cylinder.c) */
    adem_wall_bounds(&w->walls.planes[k].def, &x0, &x1);
    lo = v3(fmin(lo.x, x0.x), fmin(lo.y, x0.y), fmin(lo.z, x0.z));
    hi = v3(fmax(hi.x, x1.x), fmax(hi.y, x1.y), fmax(hi.z, x1.z));
  }
  if (w->walls.mesh.nverts > 0) { /* the meshes where they are now */
    adem_vec3 mlo, mhi;
    adem_mesh_bounds(&w->walls.mesh, &mlo, &mhi);
    lo = v3(fmin(lo.x, mlo.x), fmin(lo.y, mlo.y), fmin(lo.z, mlo.z));
    hi = v3(fmax(hi.x, mhi.x), fmax(hi.y, mhi.y), fmax(hi.z, mhi.z));
  }
  double ext = fmax(fmax(hi.x - lo.x, hi.y - lo.y), fmax(hi.z - lo.z, 100.0 * rmax));
  w->domain_lo = v3(lo.x - ext, lo.y - ext, lo.z - ext);
  w->domain_hi = v3(hi.x + ext, hi.y + ext, hi.z + ext);
  w->has_domain = true;
}

/* The box a particle must stay in, per axis: the domain's faces, or none (infinite) along a
 * periodic axis (crossing a periodic face is no escape), at an outlet face (leaving through it
 * is no escape either) or without a domain. */
typedef struct state_bounds {
  adem_vec3 lo, hi;
} state_bounds;
static state_bounds state_bounds_of(const adem_world *w) {
  unsigned per = w->has_domain ? w->periodic.axes : 7u, o = w->has_domain ? w->open_faces : 63u;
  state_bounds b;
  b.lo.x = (per & 1u) || (o & 1u) ? -INFINITY : w->domain_lo.x;
  b.hi.x = (per & 1u) || (o & 2u) ? INFINITY : w->domain_hi.x;
  b.lo.y = (per & 2u) || (o & 4u) ? -INFINITY : w->domain_lo.y;
  b.hi.y = (per & 2u) || (o & 8u) ? INFINITY : w->domain_hi.y;
  b.lo.z = (per & 4u) || (o & 16u) ? -INFINITY : w->domain_lo.z;
  b.hi.z = (per & 4u) || (o & 32u) ? INFINITY : w->domain_hi.z;
  return b;
}

/* A finite state inside the bounds. Without branches, so that the sweep over every particle
 * after each step is a few instructions a particle: x - x is +0 for a finite x and NaN for an
 * infinite or NaN one, and a NaN sum fails the compare (as does a NaN position any bound). */
static inline bool particle_ok(const adem_particles *p, const state_bounds *b, size_t i) {
  adem_vec3 x = p->pos[i], v = p->vel[i], o = p->omega[i];
  double z = (x.x - x.x) + (x.y - x.y) + (x.z - x.z) + (v.x - v.x) + (v.y - v.y) + (v.z - v.z) +
             (o.x - o.x) + (o.y - o.y) + (o.z - o.z);
  return (z == 0.0) & (x.x >= b->lo.x) & (x.x <= b->hi.x) & (x.y >= b->lo.y) & (x.y <= b->hi.y) &
         (x.z >= b->lo.z) & (x.z <= b->hi.z);
}

/* After a step: the first particle (lowest index) with a non-finite state, an overlap above the
 * limit, or a position outside the domain. Returns ADEM_OK when all is well. */
adem_status adem_world_check_state(const adem_world *w, adem_error *err) {
  const adem_particles *p = &w->p;
  size_t n = p->n;
  size_t bad = n;
  int nthreads = adem_world_threads(w);
  state_bounds sb = state_bounds_of(w);
  /* The lowest index found is the same for every thread count. */
  if (nthreads > 1) {
#ifdef ADEM_HAVE_OPENMP
#pragma omp parallel for schedule(static) num_threads(nthreads) reduction(min \
                                                                          : bad)
#endif
    for (size_t i = 0; i < n; ++i)
      if (!particle_ok(p, &sb, i) && i < bad) bad = i;
  } else {
    /* blocks without an early exit (a loop the compiler can pack); the first bad one's found
     * again in its block */
    for (size_t i0 = 0; i0 < n && bad == n; i0 += 256) {
      size_t i1 = n - i0 < 256 ? n : i0 + 256;
      bool all = true;
      for (size_t i = i0; i < i1; ++i) all &= particle_ok(p, &sb, i);
      for (size_t i = i0; !all && i < i1; ++i)
        if (!particle_ok(p, &sb, i)) {
          bad = i;
          break;
        }
    }
  }
  if (bad < n) {
    adem_vec3 x = p->pos[bad];
    if (!v3_isfinite(x) || !v3_isfinite(p->vel[bad]) || !v3_isfinite(p->omega[bad]))
      return adem_error_set(err, ADEM_ERR_RUNTIME,
                            "particle id %llu has a non-finite position or velocity at t = %.9g s "
                            "(step %llu); reduce the time step",
                            (unsigned long long)p->id[bad], w->time, (unsigned long long)w->step);
    return adem_error_set(err, ADEM_ERR_RUNTIME,
                          "particle id %llu escaped the domain at t = %.9g s (step %llu): position "
                          "(%g, %g, %g)",
                          (unsigned long long)p->id[bad], w->time, (unsigned long long)w->step,
                          x.x, x.y, x.z);
  }
  if (!w->overlap_exceeded) return ADEM_OK; /* the force pass saw none above the limit */
  const adem_pair_list *lists[2] = {&w->pp, &w->pw};
  for (int s = 0; s < 2; ++s) {
    const adem_pair_list *l = lists[s];
    for (size_t k = 0; k < l->n; ++k) {
      double ratio = l->res[adem_pairs_slot(l, k)].overlap_ratio;
      if (!(ratio > w->max_overlap_ratio)) continue;
      const char *other = s == 0 ? "particle" : "wall";
      char name[ADEM_NAME_MAX + 32];
      if (s == 0)
        snprintf(name, sizeof name, "id %llu", (unsigned long long)p->id[l->b[k]]);
      else
        snprintf(name, sizeof name, "'%s'", w->walls.planes[l->b[k]].def.name);
      return adem_error_set(err, ADEM_ERR_RUNTIME,
                            "particle id %llu overlaps %s %s by %.3g of its radius (limit %.3g) at "
                            "t = %.9g s (step %llu); the time step is probably too large",
                            (unsigned long long)p->id[l->a[k]], other, name, ratio,
                            w->max_overlap_ratio, w->time, (unsigned long long)w->step);
    }
  }
  const adem_pair_list *lm = &w->pm.l;
  for (size_t k = 0; k < lm->n; ++k) {
    if (!(lm->res[k].overlap_ratio > w->max_overlap_ratio)) continue;
    return adem_error_set(err, ADEM_ERR_RUNTIME,
                          "particle id %llu overlaps mesh group '%s' by %.3g of its radius (limit "
                          "%.3g) at t = %.9g s (step %llu); the time step is probably too large",
                          (unsigned long long)p->id[lm->a[k]],
                          w->walls.mesh.groups[w->walls.mesh.group[w->pm.owner[k]]].name, lm->res[k].overlap_ratio,
                          w->max_overlap_ratio, w->time, (unsigned long long)w->step);
  }
  return ADEM_OK;
}

/* Particles that moved more than their radius in this step while they had candidate mesh
 * triangles (within radius + skin at the last build; the ranges still follow that build's
 * order): each may have passed through the wall between two force passes. */
void adem_world_note_tunnelling(adem_world *w, double dt) {
  const adem_particles *p = &w->p;
  const adem_mesh_pairs *pm = &w->pm;
  if (!pm->start) return;
  double t = (double)(w->step + 1) * dt;
  for (size_t i = 0; i < p->n; ++i) {
    double moved = dt * v3_norm(p->vel[i]);
    if (!(moved > p->radius[i]) || pm->start[i + 1] == pm->start[i]) continue;
    adem_tunnel_event e = {p->id[i], p->pos[i], t, moved, p->radius[i]};
    if (w->tunnel_count == 0) w->tunnel_first = e;
    if (w->tunnel_count < ADEM_TUNNEL_LOGGED)
      adem_log(ADEM_LOG_WARN,
               "particle id %llu moved %.3g m in one step (more than its radius %.3g m) next to a "
               "mesh wall at t = %.9g s, now at (%.6g, %.6g, %.6g) m: it may have passed through "
               "the wall; a smaller time.step avoids it",
               (unsigned long long)e.id, moved, e.radius, t, e.pos.x, e.pos.y, e.pos.z);
    w->tunnel_count++;
  }
}

uint64_t adem_world_tunnel_count(const adem_world *w) { return w->tunnel_count; }

const adem_tunnel_event *adem_world_tunnel_first(const adem_world *w) {
  return w->tunnel_count ? &w->tunnel_first : NULL;
}
