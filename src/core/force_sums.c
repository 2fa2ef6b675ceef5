/* The per-particle sums of the force pass: each particle adds its body forces and its contacts'
 * results in an order fixed by ids (particle partners by id, planes by index, mesh contacts by
 * key), then BROF's couple and the energy balance's terms, whatever the thread count and the
 * storage order (docs/architecture.md, "Order independence"). */
#include "contact_force.h"
#include "force_sums.h"
#include "parallel.h"

/* The per-particle sums ask for a pair's records this many entries ahead (__builtin_prefetch). */
enum { PREFETCH_AHEAD = 8 };

/* The energy a particle's kicks take out through the dissipative forces of its contacts (sum
 * G, torques H) and give through moving walls (wall power P_w, of which P_d is the dissipative
 * forces' share). The force F, T of this pass acts in two half kicks: the closing one of this
 * step (v_half -> v_full) and the opening one of the next (v_full -> v_next). A force's work in
 * a half kick is F.(v_before + v_after)/2 dt/2 exactly (the kinetic energy changes by that sum
 * over all forces), so the dissipation is counted with the same velocities as the kinetic
 * energy: the closing half now, the opening half at the next pass (held back in *_next, so that
 * the totals after a step match the kinetic energy after it). */
typedef struct particle_energy {
  adem_vec3 G, H;    /* dissipative force and torque on the particle */
  double P_w, P_d;   /* wall power and its dissipative share, W */
  double dissipated; /* the laws' own, of the step just done (its share of pairs'), J */
} particle_energy;

static inline void account_energy(adem_particles *p, size_t i, const particle_energy *e,
                                  adem_vec3 f, adem_vec3 t, uint8_t held, double dt) {
  double hm = 0.5 * dt * p->inv_mass[i], hi = 0.5 * dt * p->inv_inertia[i];
  adem_vec3 v_half = p->vel[i], v_full = v3_axpy(v_half, hm, f), v_next = v3_axpy(v_full, hm, f);
  adem_vec3 w_half = p->omega[i], w_full, w_next;
  double zeroed = 0.0;
  if (held) { /* the closing kick sets the spin to zero: BROF took its energy (I9-I10) */
    w_full = w_next = v3_zero();
    zeroed = 0.5 * v3_norm2(w_half) / p->inv_inertia[i];
  } else {
    w_full = v3_axpy(w_half, hi, t);
    w_next = v3_axpy(w_full, hi, t);
  }
  double q = 0.25 * dt;
  double closing = -q * (v3_dot(e->G, v3_add(v_half, v_full)) + v3_dot(e->H, v3_add(w_half, w_full))) +
                   0.5 * dt * e->P_d + zeroed;
  double opening = -q * (v3_dot(e->G, v3_add(v_full, v_next)) + v3_dot(e->H, v3_add(w_full, w_next))) +
                   0.5 * dt * e->P_d;
  p->dissipated[i] += p->dissipated_next[i] + closing + e->dissipated;
  p->dissipated_next[i] = opening;
  p->wall_work[i] += p->wall_work_next[i] + 0.5 * dt * e->P_w;
  p->wall_work_next[i] = 0.5 * dt * e->P_w;
}

/* Per-particle sums in the order of the gather lists: body forces first, then particle
 * contacts by increasing id of the partner, then plane contacts by plane index, then mesh
 * contacts by key. None of these orders depends on where the particles are stored, and each
 * pair's result was computed with the lower id as i: the sums are the same bits whatever the
 * storage order (docs/architecture.md, "Order independence"). */
static inline void sum_particle_as(const adem_force_scope *w, size_t i, bool balance) {
  size_t n_all = w->p->n;
  adem_particles *p = w->p;
  const adem_neighbors *nb = w->nb;
  const adem_pair_list *pp = w->pp, *pw = w->pw, *pm = &w->pm->l;
  const size_t *pm_start = w->walls->mesh.ntris > 0 ? w->pm->start : NULL;
  adem_vec3 g = w->gravity;
  double dt = w->dt;
  bool breaks = *w->break_forces != 0;
  {
    /* body forces: (m g + the group's force) + the particle's own external force */
    adem_vec3 f = v3_add(v3_add(v3_scale(g, 1.0 / p->inv_mass[i]), w->groups[p->group[i]].external_force),
                         adem_particles_ext_force(p, i));
    adem_vec3 t = v3_zero(), roll = v3_zero();
    double ri = p->radius[i]; /* the arm of its contacts' tangential forces */
    particle_energy en = {v3_zero(), v3_zero(), 0.0, 0.0, 0.0};
    double capacity = 0.0, capacity_pp = 0.0;
    adem_vec3 wall_spin = v3_zero();    /* sum of capacity x spin of the walls it touches (BROF) */
    adem_vec3 partner_spin = v3_zero(); /* the same of its particle partners (brof_objective) */
    bool objective = false;
    for (size_t e = nb->pp_start[i]; e < nb->pp_start[i + 1]; ++e) {
      uint32_t code = nb->pp_entries[e];
      size_t k = code >> 1;
      /* the entries a particle ahead: their records are scattered over the list, and a read
       * that waits for memory is most of the sum's time on a large bed */
      if (e + PREFETCH_AHEAD < nb->pp_start[n_all]) {
        size_t ka = nb->pp_entries[e + PREFETCH_AHEAD] >> 1;
        __builtin_prefetch(&pp->slot[ka]);
        __builtin_prefetch(&pp->touching[ka]);
      }
      if (e + PREFETCH_AHEAD / 2 < nb->pp_start[n_all]) /* its slot read by now */
        __builtin_prefetch(&pp->res[pp->slot[nb->pp_entries[e + PREFETCH_AHEAD / 2] >> 1]]);
      size_t s = pp->slot[k]; /* the list is sparse (pairs.h) */
      /* not touched since the build: its records are zeros, and adding +0.0 to a sum that
       * starts at +0.0 changes no bit, so it adds nothing */
      if (s == 0) continue;
      if (balance) en.dissipated += 0.5 * pp->bal[s].dissipated; /* also of one just opened */
      if (!pp->touching[k]) {                                    /* apart; one that just opened may carry a break correction */
        if (!breaks) continue;
        adem_vec3 fb = pp->res[s].force_a;
        if (fb.x != 0.0 || fb.y != 0.0 || fb.z != 0.0) f = (code & 1u) ? v3_sub(f, fb) : v3_add(f, fb);
        continue;
      }
      if (code & 1u) {
        f = v3_sub(f, pp->res[s].force_a);
        t = v3_add(t, v3_sub(v3_scale(pp->res[s].moment, ri), pp->res[s].rolling_a));
        roll = v3_sub(roll, pp->res[s].rolling_a);
        if (balance) {
          en.G = v3_sub(en.G, pp->bal[s].damping_a);
          en.H = v3_add(en.H, pp->bal[s].damping_torque_b);
        }
      } else {
        f = v3_add(f, pp->res[s].force_a);
        t = v3_add(t, v3_add(v3_scale(pp->res[s].moment, ri), pp->res[s].rolling_a));
        roll = v3_add(roll, pp->res[s].rolling_a);
        if (balance) {
          en.G = v3_add(en.G, pp->bal[s].damping_a);
          en.H = v3_add(en.H, pp->bal[s].damping_torque_a);
        }
      }
      capacity += pp->res[s].rolling_capacity;
      if (pp->res[s].rolling_capacity > 0.0) {
        size_t j = (code & 1u) ? pp->a[k] : pp->b[k];
        if (adem_materials_pair(w->mat, p->material[i], p->material[j])->rolling ==
            ADEM_ROLLING_BROF_OBJECTIVE) {
          partner_spin = v3_axpy(partner_spin, pp->res[s].rolling_capacity, p->omega[j]);
          objective = true;
        }
      }
    }
    capacity_pp = capacity;
    for (size_t e = nb->pw_start[i]; e < nb->pw_start[i + 1]; ++e) {
      size_t k = nb->pw_entries[e];
      if (balance) en.dissipated += pw->bal[k].dissipated;
      if (!pw->touching[k]) {
        if (!breaks) continue;
        adem_vec3 fb = pw->res[k].force_a;
        if (fb.x != 0.0 || fb.y != 0.0 || fb.z != 0.0) f = v3_add(f, fb);
        continue;
      }
      f = v3_add(f, pw->res[k].force_a);
      t = v3_add(t, v3_add(v3_scale(pw->res[k].moment, ri), pw->res[k].rolling_a));
      roll = v3_add(roll, pw->res[k].rolling_a);
      capacity += pw->res[k].rolling_capacity;
      if (pw->res[k].rolling_capacity > 0.0) {
        const adem_motion *mo = &w->walls->planes[pw->b[k]].motion;
        if (mo->omega != 0.0) wall_spin = v3_axpy(wall_spin, pw->res[k].rolling_capacity, motion_spin(mo));
      }
      if (balance) {
        en.G = v3_add(en.G, pw->bal[k].damping_a);
        en.H = v3_add(en.H, pw->bal[k].damping_torque_a);
        en.P_w += pw->bal[k].wall_power;
        en.P_d += pw->bal[k].wall_damping_power;
      }
    }
    /* mesh contacts: the first slots of the particle's range, by key */
    for (size_t k = pm_start ? pm_start[i] : 0; pm_start && k < pm_start[i + 1]; ++k) {
      if (!pm->touching[k]) break;
      f = v3_add(f, pm->res[k].force_a);
      t = v3_add(t, v3_add(v3_scale(pm->res[k].moment, ri), pm->res[k].rolling_a));
      roll = v3_add(roll, pm->res[k].rolling_a);
      capacity += pm->res[k].rolling_capacity;
      if (pm->res[k].rolling_capacity > 0.0) {
        const adem_motion *mo = &w->walls->mesh_motion[w->walls->mesh.group[w->pm->owner[k]]];
        if (mo->omega != 0.0) wall_spin = v3_axpy(wall_spin, pm->res[k].rolling_capacity, motion_spin(mo));
      }
      if (balance) {
        en.G = v3_add(en.G, pm->bal[k].damping_a);
        en.H = v3_add(en.H, pm->bal[k].damping_torque_a);
        en.dissipated += pm->bal[k].dissipated;
        en.P_w += pm->bal[k].wall_power;
        en.P_d += pm->bal[k].wall_damping_power;
      }
    }
    uint8_t held = 0;
    if (capacity > 0.0) {
      /* BROF (I9-I10). omega is the half-step spin; -I (omega - omega*)/dt - t would bring it to
       * omega* within the step. omega* is 0 for particle contacts (I resists the absolute spin;
       * brof_objective: the partner's spin) and the wall's spin for a wall contact, weighted by the contacts' capacities: a particle
       * turning with a rotating wall (a drum) is not braked. When the capacity allows it and
       * omega* = 0, the particle is held: the resistance cancels every other torque and the
       * closing half kick sets the spin to exactly zero (a sum of two half kicks would leave a
       * round-off residue that then never dies out). */
      adem_vec3 wall_target = v3_scale(wall_spin, 1.0 / capacity);
      /* brof_objective: its particle partners' spins in the target too (their half-step spins,
       * read before any kick of this step) */
      adem_vec3 target = objective ? v3_scale(v3_add(wall_spin, partner_spin), 1.0 / capacity)
                                   : wall_target;
      adem_vec3 t_stop =
          v3_sub(v3_scale(v3_sub(p->omega[i], target), -1.0 / (p->inv_inertia[i] * dt)), t);
      adem_vec3 t_brof = adem_rolling_brof(t_stop, capacity);
      if (v3_norm2(t_stop) <= capacity * capacity && v3_norm2(target) == 0.0) {
        t_brof = v3_neg(t);
        held = 1;
      }
      t = v3_add(t, t_brof);
      roll = v3_add(roll, t_brof);
      /* BROF resists the spin relative to omega*: that work is dissipation; t_brof . omega* is
       * what the walls' spin gives through it */
      double p_wall = v3_dot(t_brof, wall_target);
      en.H = v3_add(en.H, t_brof);
      en.P_d += p_wall;
      en.P_w += p_wall;
      /* no partner takes the share of the particle contacts back: angular momentum it adds */
      if (p->brof_impulse) /* kept while a law is BROF (world.c); absent only when out of memory */
        p->brof_impulse[i] = v3_axpy(p->brof_impulse[i], dt * capacity_pp / capacity, t_brof);
    }
    if (balance) account_energy(p, i, &en, f, t, held, dt);
    adem_particles_set_loads(p, i, f, t, roll, held);
  }
}

/* The sum with and without the energy balance, each compiled for its case. */
static inline void sum_particle(const adem_force_scope *w, size_t i) { sum_particle_as(w, i, true); }
static inline void sum_particle_loads(const adem_force_scope *w, size_t i) {
  sum_particle_as(w, i, false);
}

void adem_force_sums(const adem_force_scope *w) {
  int nthreads = w->nthreads;
  if (w->balance) ADEM_FOR(nthreads, w->p->n, sum_particle, w);
  else ADEM_FOR(nthreads, w->p->n, sum_particle_loads, w);
}
