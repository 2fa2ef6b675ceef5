/* One contact's force, shared by particle pairs, planes and meshes (force_pass.c) and the block
 * kernels (pair_blocks.c): the kinematics a contact takes of its particles, its geometry, the laws
 * of its interaction (include/adem/laws.h) and the records it leaves in its pair list.
 * Conventions (physics notes 2-3): n points from i to j (or from the particle into the wall), the
 * overlap is positive in contact, positive normal force is repulsive, and w = v_i,c - v_j,c is the
 * velocity of i's contact point relative to j's. Everything here is inline: the block kernels
 * need every function in their loop to pack it. */
#ifndef ADEM_CONTACT_FORCE_H
#define ADEM_CONTACT_FORCE_H

#include <math.h>
#include <string.h>

#include "laws_kernels.h"
#include "adem/vec3.h"
#include "force_pass.h"

typedef adem_contact_geometry contact_geometry;

/* a where c holds, else b, component by component: a select the block kernels' loops can pack */
static inline adem_vec3 v3_select(bool c, adem_vec3 a, adem_vec3 b) {
  return v3(c ? a.x : b.x, c ? a.y : b.y, c ? a.z : b.z);
}

/* A particle's velocity and spin predicted at the end of the step, from the half step's with
 * the last pass's force (the closing kick will use the new one: the difference is O(dt^2)). A
 * particle BROF holds has its spin set to zero by that kick. Every operand is loaded whatever
 * the branch, so that a block kernel's loop has no branch to a load (pair_block). */
static inline adem_vec3 predicted_velocity(const adem_particles *p, size_t i, double dt) {
  adem_vec3 v = p->vel[i]; /* a frozen particle's is its wall's at the full step already */
  return v3_select(dt == 0.0 || p->frozen[i], v, v3_axpy(v, 0.5 * dt * p->inv_mass[i], p->force[i]));
}
static inline adem_vec3 predicted_spin(const adem_particles *p, size_t i, double dt) {
  adem_vec3 o = p->omega[i];
  adem_vec3 o_pred = v3_axpy(o, 0.5 * dt * p->inv_inertia[i], p->torque[i]);
  return v3_select(dt == 0.0 || p->frozen[i], o, v3_select(p->held[i] != 0, v3_zero(), o_pred));
}

/* The spin of a wall's motion (constant rotation about its axis), rad/s. */
static inline adem_vec3 motion_spin(const adem_motion *m) { return v3_scale(m->axis, m->omega); }

/* The step the laws advance the histories by: the pass's, or 0 in a pass that must leave them
 * as they are (the springs then give the force they hold, and no contact is new: the onset
 * correction is a step's). The predicted velocities and BROF keep the pass's step. */
static inline double law_step(const adem_force_scope *w) { return w->hold_history ? 0.0 : w->dt; }
static inline bool onset_pass(const adem_force_scope *w) {
  return w->second_order && !w->hold_history;
}

typedef struct contact_result {
  adem_vec3 force;   /* on i */
  adem_vec3 rolling; /* rolling couple on i (j takes the opposite) */
  double capacity;   /* per-particle rolling resistance this contact offers (BROF) */
  double elastic;    /* stored energy, J */
  /* energy bookkeeping: the dissipative forces, whose work the per-particle sums take with the
   * velocities of the kicks, and what the laws' own limits took in the step */
  adem_vec3 damping;        /* dashpot force on i (normal and tangential) */
  adem_vec3 damping_couple; /* dissipative part of the rolling couple on i */
  double dissipated;        /* J */
} contact_result;

/* The laws a contact goes through: its interaction's, or constants that a block kernel of one
 * combination passes (pair_block below), so that the switches on them fold away. */
typedef struct law_set {
  int normal, damping, tangential, rolling;
} law_set;
static inline law_set laws_of(const adem_interaction *it) {
  return (law_set){(int)it->normal, (int)it->damping, (int)it->tangential, (int)it->rolling};
}

/* The normal law of the pair at the geometry g (a: the Hertz radius sqrt(R delta)). */
static inline adem_normal_result normal_law(const adem_interaction *it, int normal,
                                            const contact_geometry *g, double a) {
  const adem_pair_params *pp = &it->pp;
  adem_normal_result nr;
  switch (normal) {
#define ADEM_X(ID, kernel, hist, ...) \
  case ID:                            \
    nr = kernel(pp, g, a);            \
    break;
    ADEM_NORMAL_LAWS(ADEM_X)
#undef ADEM_X
    default:
      nr = adem_normal_hertz_law(pp, g, a);
      break;
  }
  return nr;
}

/* The simplified JKR force jumps from 0 to F(0) = -(8/9) F_C when a contact forms at delta = 0
 * and back when it breaks there (H7-H10). The kicks apply a pass's force from half a step before
 * to half a step after it, so a jump between two passes lands up to half a step early or late,
 * an impulse error of F dt/2 at most: first order. Onset at the crossing time t* interpolated in
 * the overlap: the pass after the contact forms adds F (phi - 1/2), phi = delta_{n+1}/(v_n dt) the
 * fraction of the step in contact (t_{n+1/2} - t* = (phi - 1/2) dt); the pass after it breaks
 * adds F(delta_n) (psi - 1/2), psi = delta_n/(delta_n - delta_{n+1}) the fraction still in
 * contact. Then the impulse is right to second order, and so is the collision. Only a contact
 * whose overlap crossed zero in the step has phi <= 1: a new contact that was already
 * overlapping (a mesh contact that moved to another region of the mesh, an overlap at the start)
 * gets nothing. */
static inline double onset_correction(double f_elastic, double delta, double vn, double dt) {
  double phi = vn > 0.0 ? delta / (vn * dt) : 0.5;
  return phi <= 1.0 ? f_elastic * (phi - 0.5) : 0.0; /* a select: block loops stay packed */
}

static inline double break_correction(const adem_interaction *it, const contact_geometry *g,
                                      double dt) {
  double vn = v3_dot(g->w, g->n);   /* < 0 while separating */
  double prev = g->delta - vn * dt; /* the overlap at the last pass, > 0 */
  if (!(prev > 0.0) || !(g->delta < 0.0)) return 0.0;
  contact_geometry gp = *g;
  gp.delta = prev;
  adem_normal_result nr = normal_law(it, it->normal, &gp, adem_hertz_radius(g->R, prev));
  if (nr.f_critical == 0.0) return 0.0; /* no jump: the Hertz force is 0 at delta = 0 */
  return nr.f_elastic * (prev / (prev - g->delta) - 0.5);
}

/* One contact through the laws of its pair (include/adem/laws.h): normal, damping, tangential,
 * rolling, each dispatched by a switch generated from the rows, updating the history. fresh: the
 * contact formed since the last pass (onset correction of an adhesive law, when asked for). */
/* always inlined: GCC kept it out of line and copied the geometry and the result through the
 * stack for every contact (2.5% of a step's instructions) */
static inline __attribute__((always_inline)) contact_result
contact_force(const adem_interaction *it, law_set laws, const contact_geometry *g,
              adem_contact_history *h, double dt, bool fresh) {
  const adem_pair_params *pp = &it->pp;
  contact_result r;
  double vn = v3_dot(g->w, g->n); /* > 0 while approaching */
  adem_vec3 vt = v3_axpy(g->w, -vn, g->n);
  /* the dashpots take the velocity at the full step, where their force acts: with the half step's
   * they would lag by half a step (first order); v + F_old dt/(2m) is second order. The
   * tangential dashpot's own share of it is solved for (implicit): w_pred less what this
   * contact's tangential force of the last pass gave it, plus what its spring of this pass gives
   * (the law adds that), then the dashpot's own part divided out. On w_pred as it is, the dashpot
   * is a two-step recurrence that a sticking contact at e = 0.2 (damping ratio of the tangential
   * mode sqrt(3.5) times the normal one's) makes unstable above t_c/11.7 (docs/models.md). The
   * normal dashpot keeps the explicit form: its mode is slower and less damped, the guard covers
   * it (step_limit.c), and the implicit form made the JKR capture threshold first order */
  double vn_d = v3_dot(g->w_pred, g->n);
  adem_vec3 ft_old = v3_axpy(h->tangential_force, -v3_dot(h->tangential_force, g->n), g->n);
  adem_vec3 vt_d = v3_axpy(v3_axpy(g->w_pred, -vn_d, g->n), -g->mob_t, ft_old);

  double a = adem_hertz_radius(g->R, g->delta); /* sqrt(R delta): S_n, S_t use it (H13, H14) */
  adem_normal_result nr = normal_law(it, laws.normal, g, a);
  double Sn = adem_hertz_normal_stiffness(pp->E, a);
  double St = adem_hertz_tangential_stiffness(pp->G, a);
  adem_damping_input din = {Sn, St, g->mstar, vn_d, nr.f_elastic, nr.f_critical};
  adem_damping_output dout = {nr.f_elastic, 0.0};
  switch (laws.damping) {
#define ADEM_X(ID, kernel, hist, ...) \
  case ID:                            \
    kernel(pp, &din, &dout);          \
    break;
    ADEM_DAMPING_LAWS(ADEM_X)
#undef ADEM_X
    default:
      break;
  }
  double fn = dout.f_normal; /* H5 with H11: damping opposes the normal motion */
  double ct = dout.ct;
  double f_damp = fn - nr.f_elastic;
  if (fresh && nr.f_critical != 0.0) fn += onset_correction(nr.f_elastic, g->delta, vn, dt);

  double f_load = fabs(nr.f_elastic + 2.0 * nr.f_critical); /* the load the contact carries */
  double f_limit = pp->friction * f_load;                   /* H17 */
  adem_tangential_input tin = {g->n, vt, vt_d, dt, St, ct, f_limit, g->mob_t};
  adem_tangential_output tout = {v3_zero(), v3_zero(), 0.0, 0.0, false};
  switch (laws.tangential) {
#define ADEM_X(ID, kernel, hist, ...)                        \
  case ID:                                                   \
    kernel(&tin, &h->tangential, &h->tangential_aux, &tout); \
    break;
    ADEM_TANGENTIAL_LAWS(ADEM_X)
#undef ADEM_X
    default:
      break;
  }

  r.force = v3_axpy(tout.force, -fn, g->n);
  h->tangential_force = tout.force;
  r.elastic = nr.e_elastic + tout.elastic;
  r.damping = v3_axpy(tout.dashpot, -f_damp, g->n);
  adem_rolling_input in = {g, pp, dt, f_load, nr.a, Sn};
  adem_rolling_output ro = {v3_zero(), v3_zero(), 0.0, 0.0, 0.0};
  switch (laws.rolling) {
#define ADEM_X(ID, kernel, hist, ...)               \
  case ID:                                          \
    kernel(&in, &h->rolling, &h->rolling_aux, &ro); \
    break;
    ADEM_ROLLING_LAWS(ADEM_X)
#undef ADEM_X
    default:
      break;
  }
  r.rolling = ro.torque;
  r.capacity = ro.capacity;
  r.elastic += ro.elastic; /* the elastic part is never -0: adding 0 changes nothing */
  r.damping_couple = ro.dashpot;
  r.dissipated = tout.dissipated + ro.dissipated;
  h->elastic = tout.elastic + ro.elastic; /* the springs of the history, not the normal law's */
  return r;
}

/* Flags an overlap above the run's limit: the check after the step then looks for it, instead of
 * scanning every pair's result every step (a serial pass over the whole list). */
static inline void note_overlap(const adem_force_scope *w, double ratio) {
  if (!(ratio > w->overlap_limit)) return;
#ifdef ADEM_HAVE_OPENMP
#pragma omp atomic write
#endif
  *w->overlap_exceeded = 1;
}

/* A contact's results as its records hold them. The tangential force acts at r_a n from a's
 * centre and at -r_b n from b's, so its moments are r_a n x F_t on a and r_b n x F_t on b: the
 * pair keeps n x F_t and the sums scale it by the particle's radius; the rolling couple is equal
 * and opposite. A wall takes no torque. bal: the energy balance's terms, written when balance. */
static inline __attribute__((always_inline)) void
pair_records(const contact_geometry *g, const contact_result *r, bool balance, adem_pair_result *res,
             adem_pair_balance *bal) {
  adem_vec3 ft = v3_axpy(r->force, -v3_dot(r->force, g->n), g->n);
  res->force_a = r->force;
  res->moment = v3_cross(g->n, ft);
  res->rolling_a = r->rolling;
  res->rolling_capacity = r->capacity;
  /* the smaller radius (a wall's rj is 0); not fmin, which is a library call without
   * -ffast-math: radii are positive and finite, so the two agree */
  res->overlap_ratio = g->delta / (g->rj > 0.0 && g->rj < g->ri ? g->rj : g->ri);
  if (!balance) return; /* the rest is only the energy balance's, and only it reads them */
  /* the dashpots' moments (their normal part has none) and the dissipative couple */
  bal->damping_a = r->damping;
  bal->damping_torque_a = v3_add(v3_cross(v3_scale(g->n, g->ri), r->damping), r->damping_couple);
  bal->damping_torque_b =
      g->rj > 0.0 ? v3_sub(v3_cross(v3_scale(g->n, g->rj), r->damping), r->damping_couple) : v3_zero();
  bal->dissipated = r->dissipated;
}

/* Stores a contact's results in its list. */
static inline void store_pair(adem_pair_list *l, size_t k, const contact_geometry *g,
                              const contact_result *r, bool balance) {
  size_t s = adem_pairs_own_slot(l, k);
  l->touching[k] = true;
  pair_records(g, r, balance, &l->res[s], balance ? &l->bal[s] : NULL);
  if (g->energy) l->elastic[s] = r->elastic; /* only the diagnostics read it */
}

/* A wall contact's power: the wall's material at the contact point moves at V and turns at
 * Omega; it pushes the particle with F and the couple R, so it gives F.V + R.Omega; the
 * dissipative forces' share is what the particle's kicks count as their work but the relative
 * motion did not take (the particle-side sums subtract it back). */
static inline void store_wall_power(adem_pair_list *l, size_t k, const contact_result *r,
                                    adem_vec3 v_wall, adem_vec3 omega_wall) {
  size_t s = adem_pairs_slot(l, k); /* a wall's list is dense: k */
  l->bal[s].wall_power = v3_dot(r->force, v_wall) + v3_dot(r->rolling, omega_wall);
  l->bal[s].wall_damping_power = v3_dot(r->damping, v_wall) + v3_dot(r->damping_couple, omega_wall);
}


/* A contact that opened since the last pass: its history's spring energy is gone (dissipated),
 * and an adhesive law's jump gets its break correction (a force on a; no torque). */
static inline void open_pair(adem_pair_list *l, size_t k, const adem_interaction *it,
                             const contact_geometry *g, bool onset, double dt, bool balance,
                             int *breaks) {
  size_t s = adem_pairs_slot(l, k);
  double lost = l->hist[s].elastic;
  double f = onset ? break_correction(it, g, dt) : 0.0;
  adem_pairs_clear(l, k);
  if (lost == 0.0 && f == 0.0 && s == 0 && l->slot) return; /* nothing left: zeros already */
  s = adem_pairs_own_slot(l, k);
  if (balance) l->bal[s].dissipated = lost;
  l->res[s].force_a = v3_scale(g->n, -f);
  l->opened[k] = true;
  if (f != 0.0) {
#ifdef ADEM_HAVE_OPENMP
#pragma omp atomic write
#endif
    *breaks = 1;
  }
}

/* The rolling inertia I_r enters only model C's dashpot, c_r = beta_r 2 sqrt(I_r k_r): with
 * beta_r = 0 it is 0 whatever I_r, and its five divisions are skipped. */
static inline bool needs_rolling_inertia(const adem_interaction *it) {
  return it->pp.param[ADEM_PARAM_ROLLING_DAMPING] != 0.0;
}

/* A candidate apart now and at the last pass. Every field of a pair that is not touching is
 * zero (the build clears new pairs, open_pair clears an opening one) except what open_pair left
 * for the pass in which it opened, and marked opened: its break correction, and with the balance
 * on its lost spring energy (a balance switched on starts from zeroed records: world.c,
 * sync_optional_fields). Zeroing those is the same as clearing the pair; a pair apart for longer
 * is not written at all (its records stay out of the cache). */
static inline void forget_opened(adem_pair_list *l, size_t k, bool balance) {
  if (!l->opened[k]) return;
  size_t s = adem_pairs_slot(l, k); /* its own: it opened */
  if (balance) l->bal[s].dissipated = 0.0;
  l->res[s].force_a = v3_zero();
  l->opened[k] = false;
}

/* What the geometry of a particle pair takes of its two particles, read where the particles are
 * read (one pair at a time), so that the arithmetic (kinematic_geometry) works on these numbers
 * alone. */
typedef struct pair_kinematics {
  adem_vec3 d;                  /* x_j - x_i (minimum image) */
  double dist;                  /* |d|, below r_i + r_j */
  double ri, rj, mi, mj;        /* radii and inverse masses */
  adem_vec3 vi, vj, oi, oj;     /* velocities and spins at the half step */
  adem_vec3 vpi, vpj, opi, opj; /* the same predicted at the full step */
} pair_kinematics;

/* pred: the pass's predicted velocities and spins, or NULL (predicted here, with step hp). */
static inline __attribute__((always_inline)) pair_kinematics
particle_kinematics(const adem_particles *p, const adem_vec3 *pred, size_t i, size_t j,
                    adem_vec3 d, double dist, double hp) {
  pair_kinematics k;
  k.d = d;
  k.dist = dist;
  k.ri = p->radius[i];
  k.rj = p->radius[j];
  k.mi = p->inv_mass[i];
  k.mj = p->inv_mass[j];
  k.vi = p->vel[i];
  k.vj = p->vel[j];
  k.oi = p->omega[i];
  k.oj = p->omega[j];
  if (pred) {
    k.vpi = pred[2 * i];
    k.opi = pred[2 * i + 1];
    k.vpj = pred[2 * j];
    k.opj = pred[2 * j + 1];
  } else {
    k.vpi = predicted_velocity(p, i, hp);
    k.vpj = predicted_velocity(p, j, hp);
    k.opi = predicted_spin(p, i, hp);
    k.opj = predicted_spin(p, j, hp);
  }
  return k;
}

/* The mobility of a contact's slip velocity (contact_geometry's mob_t) for a pass of closing half
 * kick h (0: the first-order scheme) and the inverse masses' sum (a wall's is 0): a tangential
 * force F on i at the contact point changes v_i - v_j by F (1/m_i + 1/m_j) h and, through the
 * spins, the slip by F (r_i^2/I_i + r_j^2/I_j) h = 2.5 F (1/m_i + 1/m_j) h (spheres). */
static inline void set_mobility(contact_geometry *g, double inv_mass_sum, double h) {
  g->mob_t = 3.5 * inv_mass_sum * h;
}

/* The contact as the laws see it. I_r is left 0: the caller sets it when a law needs it. h: the
 * closing half kick of the second-order scheme, 0 in the first-order one. */
static inline __attribute__((always_inline)) contact_geometry
kinematic_geometry(const pair_kinematics *k, bool energy, bool packed, double h) {
  double ri = k->ri, rj = k->rj;
  double rsum = ri + rj;
  contact_geometry g;
  g.n = v3_scale(k->d, 1.0 / k->dist);
  g.delta = rsum - k->dist;
  g.R = ri * rj / rsum;
  g.mstar = 1.0 / (k->mi + k->mj);
  /* contact points: i's at +r_i n, j's at -r_j n */
  adem_vec3 spin = v3_add(v3_scale(k->oi, ri), v3_scale(k->oj, rj));
  g.w = v3_add(v3_sub(k->vi, k->vj), v3_cross(spin, g.n));
  adem_vec3 om = v3_sub(k->oi, k->oj);
  g.omega_rel = v3_axpy(om, -v3_dot(om, g.n), g.n);
  g.w_pred = v3_add(v3_sub(k->vpi, k->vpj),
                    v3_cross(v3_add(v3_scale(k->opi, ri), v3_scale(k->opj, rj)), g.n));
  adem_vec3 omp = v3_sub(k->opi, k->opj);
  g.omega_pred = v3_axpy(omp, -v3_dot(omp, g.n), g.n);
  g.ri = ri;
  g.rj = rj;
  g.energy = energy;
  g.packed = packed;
  g.inertia_r = 0.0;
  set_mobility(&g, k->mi + k->mj, h);
  return g;
}

/* A contact of particle i with a wall (a plane or a mesh region) as the laws see it: normal n
 * into the wall, overlap delta, the wall's material moving at v_wall at the contact point and
 * turning at spin_wall; I_r set when the interaction's laws need it. The plane and mesh paths
 * share it (force_pass.c). */
static inline contact_geometry wall_geometry(const adem_force_scope *w, size_t i, adem_vec3 n,
                                             double delta, adem_vec3 v_wall, adem_vec3 spin_wall,
                                             const adem_interaction *it) {
  const adem_particles *p = w->p;
  double ri = p->radius[i];
  contact_geometry g;
  g.n = n;
  g.delta = delta;
  g.R = ri;
  g.mstar = 1.0 / p->inv_mass[i];
  g.w = v3_add(v3_sub(p->vel[i], v_wall), v3_cross(v3_scale(p->omega[i], ri), g.n));
  /* rolling laws see the spin relative to the wall's */
  adem_vec3 om = v3_sub(p->omega[i], spin_wall);
  g.omega_rel = v3_axpy(om, -v3_dot(om, g.n), g.n);
  double hp = w->second_order ? w->dt : 0.0;
  /* the pass's predictions when it made them (adem_force_pass_run: the same functions, the
   * same hp, so the same bits) */
  adem_vec3 vpi = w->predicted ? w->predicted[2 * i] : predicted_velocity(p, i, hp);
  adem_vec3 opi = w->predicted ? w->predicted[2 * i + 1] : predicted_spin(p, i, hp);
  g.w_pred = v3_add(v3_sub(vpi, v_wall), v3_cross(v3_scale(opi, ri), g.n));
  adem_vec3 omp = v3_sub(opi, spin_wall);
  g.omega_pred = v3_axpy(omp, -v3_dot(omp, g.n), g.n);
  g.ri = ri;
  g.rj = 0.0;
  g.energy = w->energy;
  g.packed = false;
  set_mobility(&g, p->inv_mass[i], 0.5 * hp);
  g.inertia_r = needs_rolling_inertia(it) ? 1.0 / p->inv_inertia[i] + ri * ri / p->inv_mass[i] : 0.0;
  return g;
}

#endif
