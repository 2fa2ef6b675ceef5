/* Estimates before a run: the time step (collision and Rayleigh times, the stability limit) and
 * the memory a number of particles needs. */
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

/* Collision time of a material pair: its normal law's (the hook: Hertz's, notes section 6, by
 * default; simplified JKR's at the speed its adhesion brings the spheres to). */
static double pair_collision_time(const adem_interaction *it, double m_eff, double r_eff,
                                  double v_ref) {
  return adem_laws_collision_time(adem_interaction_laws(it), &it->pp, m_eff, r_eff, v_ref);
}

adem_step_estimate adem_world_estimate_step(const adem_world *w, double v_ref) {
  adem_step_estimate est = {v_ref, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};
  adem_world *mw = (adem_world *)w; /* derive the pair table if the caller has not prepared */
  if (!w->mat.pairs) adem_materials_derive(&mw->mat, NULL);
  int nm = w->mat.n;
  /* Smallest particle of each material sets the shortest times (t_c and t_R scale with r). */
  double *rmin = malloc((size_t)(nm > 0 ? nm : 1) * sizeof *rmin);
  if (!rmin) return est;
  for (int k = 0; k < nm; ++k) rmin[k] = INFINITY;
  for (size_t i = 0; i < w->p.n; ++i)
    rmin[w->p.material[i]] = fmin(rmin[w->p.material[i]], w->p.radius[i]);
  if (w->insert_rmin) /* particles poured later count as present */
    for (int k = 0; k < nm; ++k) rmin[k] = fmin(rmin[k], w->insert_rmin[k]);
  for (int a = 0; a < nm; ++a) {
    if (!isfinite(rmin[a])) continue;
    const adem_material *ma = &w->mat.m[a];
    double r = rmin[a];
    double m = ma->def.density * (4.0 / 3.0) * ADEM_PI * r * r * r;
    /* Rayleigh time with the modified shear modulus (notes section 6). */
    double tR = ADEM_PI * r * sqrt(ma->def.density / ma->shear_mod) /
                (0.1631 * ma->def.poisson + 0.8766);
    est.t_rayleigh = fmin(est.t_rayleigh, tR);
    for (int b = 0; b < nm; ++b) {
      const adem_interaction *it = adem_world_interaction(w, a, b);
      if (isfinite(rmin[b])) {
        double rb = rmin[b];
        double mb = w->mat.m[b].def.density * (4.0 / 3.0) * ADEM_PI * rb * rb * rb;
        double tc = pair_collision_time(it, m * mb / (m + mb), r * rb / (r + rb), v_ref);
        est.t_collision = fmin(est.t_collision, tc);
        est.dt_stable = fmin(est.dt_stable, adem_step_limit_pair(it, tc, m, r, mb, rb));
      }
    }
    for (int k = 0; k < w->walls.nplanes; ++k) {
      const adem_interaction *it = adem_world_interaction(w, a, w->walls.planes[k].def.material);
      double tc = pair_collision_time(it, m, r, v_ref);
      est.t_collision = fmin(est.t_collision, tc);
      est.dt_stable = fmin(est.dt_stable, adem_step_limit_pair(it, tc, m, r, 0.0, 0.0));
    }
    for (int k = 0; k < w->walls.mesh.ngroups; ++k) {
      const adem_interaction *it = adem_world_interaction(w, a, w->walls.mesh.groups[k].material);
      double tc = pair_collision_time(it, m, r, v_ref);
      est.t_collision = fmin(est.t_collision, tc);
      est.dt_stable = fmin(est.dt_stable, adem_step_limit_pair(it, tc, m, r, 0.0, 0.0));
    }
  }
  free(rmin);
  est.dt = fmin(est.t_collision / 50.0, 0.2 * est.t_rayleigh); /* about 50 steps a collision */
  /* and a fifth of the stability limit: the rolling spring DTK keeps real under reduced
   * stiffness outruns the normal mode below f ~ 1e-2 (docs/models.md, "Time step") */
  est.dt = fmin(est.dt, 0.2 * est.dt_stable);
  est.dt_limit = fmin(est.t_collision / ADEM_STEP_LIMIT_DIVISOR, est.dt_stable);
  return est;
}

size_t adem_world_bytes_per_particle(void) {
  /* the particle table with every optional kind of field (no world to ask which a run keeps:
   * adem_world_memory_estimate counts those), the per-particle entries of the neighbour and
   * mesh-slot ranges and the order by id */
  return adem_soa_item_bytes(adem_particles_layout()) + 2 * sizeof(size_t) + sizeof(size_t) +
         sizeof(uint32_t);
}

/* Bytes per particle of the particle table as the world will keep it: the fields of every run,
 * the energy balance's while it is on, and each other optional kind once the world needs it
 * (particles.h). */
static size_t kept_particle_bytes(const adem_world *w) {
  size_t b = adem_particles_kind_bytes(ADEM_PART_ALWAYS);
  bool need[ADEM_PART_KINDS] = {false};
  need[ADEM_PART_BALANCE] = w->energy_balance;
  need[ADEM_PART_BROF] = adem_materials_per_particle_rolling(&w->mat);
  need[ADEM_PART_FROZEN] = w->frozen_any;
  need[ADEM_PART_PERIODIC] = w->periodic.axes != 0;
  for (int k = 1; k < ADEM_PART_KINDS; ++k)
    if (need[k] || adem_particles_has(&w->p, (adem_particle_kind)k))
      b += adem_particles_kind_bytes((adem_particle_kind)k);
  return b;
}

size_t adem_world_bytes_per_pair(const adem_world *w) {
  /* the pair table and the gather entries (two for a particle pair) */
  return adem_pairs_item_bytes(w->energy_balance) + 2 * sizeof(uint32_t);
}

/* Capacity appending grows a table of n to: doubling from 64 (adem_particles_append). */
static double grown_capacity(double n) {
  double cap = 64.0;
  while (cap < n) cap *= 2.0;
  return cap;
}

adem_memory_estimate adem_world_memory_estimate(const adem_world *w, double n) {
  adem_memory_estimate e;
  memset(&e, 0, sizeof e);
  if (!(n >= 0.0)) n = 0.0;
  e.particles = n;
  double f = w->nb.skin_fraction;
  double pp = ADEM_PAIRS_PER_PARTICLE * (1.0 + f) * (1.0 + f) * (1.0 + f) * n;
  double pw = w->walls.nplanes > 0 ? n : 0.0;
  double pm = w->walls.mesh.ntris > 0 ? ADEM_MESH_SLOTS_PER_PARTICLE * n : 0.0;
  e.pairs = pp + pw + pm;
  e.particle_bytes = grown_capacity(n) * (double)kept_particle_bytes(w) +
                     (n + 1.0) * (double)sizeof(size_t) +         /* mesh slot ranges */
                     1.125 * n * 2.0 * (double)sizeof(adem_vec3); /* the predicted velocities */
  /* the lists keep a quarter more than they hold (adem_pairs_reserve) */
  e.pair_bytes = 1.25 * (e.pairs * (double)adem_pairs_item_bytes(w->energy_balance) +
                         pm * (double)adem_mesh_pairs_slot_bytes());
  adem_neighbors_estimate_bytes(n, e.pairs, w->walls.mesh.ntris > 0, &e.grid_bytes, &e.build_bytes);
  e.total = e.particle_bytes + e.pair_bytes + e.grid_bytes + e.build_bytes;
  return e;
}
