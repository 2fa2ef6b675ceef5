/* Diagnostics: the energies of the world (kinetic, rotational, potential, elastic) and its
 * energy balance, summed in an order the storage and the thread count do not change. */
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

double adem_world_total_energy(const adem_diagnostics *d) {
  return d->kinetic + d->rotational + d->potential + d->elastic;
}

/* The stored energies of the contacts, in an order the storage does not change: particles by id
 * (as at the last gather, which the lists follow), and each one's pairs as its gather list has
 * them, a particle pair under its lower id; mesh slots by key. Summed as streams (no array of
 * every pair's term: the diagnostics would add it to a run's peak memory). */
static void sum_elastic(const adem_world *w, double out[3]) {
  const adem_neighbors *nb = &w->nb;
  const adem_mesh_pairs *pm = &w->pm;
  adem_block_sum b[3] = {ADEM_BLOCK_SUM_START, ADEM_BLOCK_SUM_START, ADEM_BLOCK_SUM_START};
  for (size_t r = 0; r < nb->gathered; ++r) {
    size_t i = nb->id_order[r];
    for (size_t e = nb->pp_start[i]; e < nb->pp_start[i + 1]; ++e)
      if (!(nb->pp_entries[e] & 1u))
        adem_block_sum_add(&b[0], w->pp.elastic[adem_pairs_slot(&w->pp, nb->pp_entries[e] >> 1)]);
    for (size_t e = nb->pw_start[i]; e < nb->pw_start[i + 1]; ++e)
      adem_block_sum_add(&b[1], w->pw.elastic[nb->pw_entries[e]]);
    for (size_t k = pm->start ? pm->start[i] : 0; pm->start && k < pm->start[i + 1]; ++k)
      adem_block_sum_add(&b[2], pm->l.elastic[k]);
  }
  for (int s = 0; s < 3; ++s) out[s] = adem_block_sum_result(&b[s]);
}

/* Every sum over particles or contacts runs in order of id (docs/architecture.md, "Order
 * independence"): the same bits whatever the storage order or the thread count. */
adem_diagnostics adem_world_diagnostics(const adem_world *w) {
  adem_diagnostics d;
  memset(&d, 0, sizeof d);
  d.time = w->time;
  const adem_particles *p = &w->p;
  size_t n = p->n;
  uint32_t *order = adem_world_id_order(w);
  if (!order) return d;
  /* one walk over the particles by id, each sum a stream of its own (adem_block_sum) */
  enum { KINETIC,
         ROTATIONAL,
         POTENTIAL,
         DISSIPATED,
         WALL_WORK,
         MOMENTUM,
         IMPULSE = MOMENTUM + 3,
         SUMS = IMPULSE + 3 };
  adem_block_sum sum[SUMS];
  for (int k = 0; k < SUMS; ++k) sum[k] = (adem_block_sum)ADEM_BLOCK_SUM_START;
  for (size_t r = 0; r < n; ++r) {
    size_t i = order[r];
    adem_block_sum_add(&sum[KINETIC], 0.5 * v3_norm2(p->vel[i]) / p->inv_mass[i]);
    adem_block_sum_add(&sum[ROTATIONAL], 0.5 * v3_norm2(p->omega[i]) / p->inv_inertia[i]);
    /* Potential of the body forces: -(m g + F_group + F_ext) . x (a change of F_ext is
     * external work: adem_world_set_particles) */
    adem_vec3 f = v3_add(v3_add(v3_scale(w->gravity, 1.0 / p->inv_mass[i]),
                                w->groups[p->group[i]].external_force),
                         adem_particles_ext_force(p, i));
    adem_vec3 xi = adem_periodic_unwrap(&w->periodic, p->pos[i], adem_particles_image(p, i));
    adem_block_sum_add(&sum[POTENTIAL], -v3_dot(f, xi));
    /* accumulated per particle every step (force_sums.c): the dissipative forces' work and the
     * laws' own losses, and the work of moving walls */
    adem_block_sum_add(&sum[DISSIPATED], adem_particles_dissipated(p, i));
    adem_block_sum_add(&sum[WALL_WORK], adem_particles_wall_work(p, i));
    adem_vec3 l = v3_add(v3_scale(v3_cross(xi, p->vel[i]), 1.0 / p->inv_mass[i]),
                         v3_scale(p->omega[i], 1.0 / p->inv_inertia[i]));
    adem_vec3 b = adem_particles_brof_impulse(p, i);
    double c[6] = {l.x, l.y, l.z, b.x, b.y, b.z};
    for (int a = 0; a < 6; ++a) adem_block_sum_add(&sum[MOMENTUM + a], c[a]);
  }
  free(order);
  double total[SUMS];
  for (int k = 0; k < SUMS; ++k) total[k] = adem_block_sum_result(&sum[k]);
  d.kinetic = total[KINETIC];
  d.rotational = total[ROTATIONAL];
  d.potential = total[POTENTIAL];
  d.dissipated = total[DISSIPATED];
  d.wall_work = total[WALL_WORK];
  d.angular_momentum = v3(total[MOMENTUM], total[MOMENTUM + 1], total[MOMENTUM + 2]);
  d.brof_impulse = v3(total[IMPULSE], total[IMPULSE + 1], total[IMPULSE + 2]);
  double elastic[3];
  sum_elastic(w, elastic);
  d.elastic = elastic[0] + elastic[1] + elastic[2];
  for (size_t k = 0; k < w->pp.n; ++k) {
    d.contacts_pp += w->pp.touching[k];
    d.max_overlap_ratio = fmax(d.max_overlap_ratio, w->pp.res[adem_pairs_slot(&w->pp, k)].overlap_ratio);
  }
  for (size_t k = 0; k < w->pw.n; ++k) {
    d.contacts_pw += w->pw.touching[k];
    d.max_overlap_ratio = fmax(d.max_overlap_ratio, w->pw.res[k].overlap_ratio);
  }
  for (size_t k = 0; k < w->pm.l.n; ++k) { /* mesh contacts count as wall contacts */
    d.contacts_pw += w->pm.l.touching[k];
    d.max_overlap_ratio = fmax(d.max_overlap_ratio, w->pm.l.res[k].overlap_ratio);
  }
  d.balance_error = w->prepared ? adem_world_total_energy(&d) + d.dissipated - w->energy_initial - d.wall_work : 0.0;
  if (!w->energy_balance) d.dissipated = d.wall_work = d.balance_error = NAN;
  d.initial = w->prepared ? w->energy_initial : adem_world_total_energy(&d);
  return d;
}
