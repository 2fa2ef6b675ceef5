/* Contact forces. One pass computes every candidate pair's force and torques into the pair
 * lists; a second pass sums them per particle in a fixed order. Conventions (physics notes 2-3):
 * n points from i to j (or from the particle into the wall), the overlap is positive in contact,
 * positive normal force is repulsive, and w = v_i,c - v_j,c is the velocity of i's contact point
 * relative to j's. */
#include <math.h>
#include <string.h>

#include "laws_kernels.h"
#include "adem/vec3.h"
#include "parallel.h"
#include "contacts.h"
#include "cylinder.h"

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
  adem_vec3 force;    /* on i */
  adem_vec3 rolling;  /* rolling couple on i (j takes the opposite) */
  double capacity;    /* per-particle rolling resistance this contact offers (BROF) */
  double elastic;     /* stored energy, J */
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
#define ADEM_X(ID, name, kernel, hist, req, ppart, params, eq, doc) \
  case ID:                                                       \
    nr = kernel(pp, g, a);                                       \
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
#define ADEM_X(ID, name, kernel, hist, req, ppart, params, eq, doc) \
  case ID:                                                       \
    kernel(pp, &din, &dout);                                     \
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
  double f_limit = pp->friction * f_load;                     /* H17 */
  adem_tangential_input tin = {g->n, vt, vt_d, dt, St, ct, f_limit, g->mob_t};
  adem_tangential_output tout = {v3_zero(), v3_zero(), 0.0, 0.0, false};
  switch (laws.tangential) {
#define ADEM_X(ID, name, kernel, hist, req, ppart, params, eq, doc)        \
  case ID:                                                              \
    kernel(&tin, &h->tangential, &h->tangential_aux, &tout);            \
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
#define ADEM_X(ID, name, kernel, hist, req, ppart, params, eq, doc) \
  case ID:                                                       \
    kernel(&in, &h->rolling, &h->rolling_aux, &ro);                               \
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
  l->touching[k] = true;
  pair_records(g, r, balance, &l->res[k], balance ? &l->bal[k] : NULL);
  if (g->energy) l->elastic[k] = r->elastic; /* only the diagnostics read it */
}

/* A wall contact's power: the wall's material at the contact point moves at V and turns at
 * Omega; it pushes the particle with F and the couple R, so it gives F.V + R.Omega; the
 * dissipative forces' share is what the particle's kicks count as their work but the relative
 * motion did not take (the particle-side sums subtract it back). */
static inline void store_wall_power(adem_pair_list *l, size_t k, const contact_result *r,
                                    adem_vec3 v_wall, adem_vec3 omega_wall) {
  l->bal[k].wall_power = v3_dot(r->force, v_wall) + v3_dot(r->rolling, omega_wall);
  l->bal[k].wall_damping_power = v3_dot(r->damping, v_wall) + v3_dot(r->damping_couple, omega_wall);
}



/* A contact that opened since the last pass: its history's spring energy is gone (dissipated),
 * and an adhesive law's jump gets its break correction (a force on a; no torque). */
static inline void open_pair(adem_pair_list *l, size_t k, const adem_interaction *it,
                             const contact_geometry *g, bool onset, double dt, bool balance,
                             int *breaks) {
  double lost = l->hist[k].elastic;
  double f = onset ? break_correction(it, g, dt) : 0.0;
  adem_pairs_clear(l, k);
  if (balance) l->bal[k].dissipated = lost;
  l->res[k].force_a = v3_scale(g->n, -f);
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
 * sync_balance_records). Zeroing those is the same as clearing the pair; a pair apart for longer
 * is not written at all (its records stay out of the cache). */
static inline void forget_opened(adem_pair_list *l, size_t k, bool balance) {
  if (!l->opened[k]) return;
  if (balance) l->bal[k].dissipated = 0.0;
  l->res[k].force_a = v3_zero();
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

/* A particle pair one contact at a time, through the laws of its interaction: every pair that
 * pair_block does not take (other laws, an opening pair, a pass that wants the energies). Out of
 * line: the rare path, which inlined into the chunk loop made it spill registers. */
static __attribute__((noinline)) void particle_pair(const adem_force_scope *w, size_t k,
                                                    adem_vec3 d, double dist, bool was,
                                                    const adem_interaction *it) {
  adem_particles *p = w->p;
  adem_pair_list *l = w->pp;
  double dt = w->dt;
  size_t i = l->a[k], j = l->b[k];
  double hp = w->second_order ? dt : 0.0; /* first order: the half step's velocities */
  pair_kinematics kin = particle_kinematics(p, w->predicted, i, j, d, dist, hp);
  contact_geometry g = kinematic_geometry(&kin, w->energy, false, 0.5 * hp);
  /* I_r = [1/(I_i + m_i r_i^2) + 1/(I_j + m_j r_j^2)]^-1: moments about the contact point */
  if (needs_rolling_inertia(it)) {
    double ri = g.ri, rj = g.rj;
    double Ici = 1.0 / p->inv_inertia[i] + ri * ri / p->inv_mass[i];
    double Icj = 1.0 / p->inv_inertia[j] + rj * rj / p->inv_mass[j];
    g.inertia_r = Ici * Icj / (Ici + Icj);
  }
  if (g.delta <= 0.0) { /* it opened since the last pass */
    open_pair(l, k, it, &g, onset_pass(w), dt, w->balance, w->break_forces);
    return;
  }
  adem_contact_history h = l->hist[k];
  contact_result r = contact_force(it, laws_of(it), &g, &h, law_step(w), onset_pass(w) && !was);
  if (!w->hold_history) l->hist[k] = h;
  store_pair(l, k, &g, &r, w->balance);
  note_overlap(w, l->res[k].overlap_ratio);
}

/* Touching particle pairs of one interaction in blocks: the same geometry and laws as
 * particle_pair, lane by lane, in a loop the compiler turns into packed arithmetic (SSE2, and
 * AVX2 or AVX-512 where the processor has them: the clones below). Lanes are independent and
 * packed instructions round each lane as the scalar ones do (no fused multiply-add:
 * -ffp-contract=off), so a pair's results are the same bits by either path and in any clone
 * (docs/architecture.md, "Block kernels"). The block kernels exist for the laws most runs use
 * (PAIR_BLOCK_LAWS); the rest go one at a time. */
enum { PAIR_BLOCK = 64 };
/* The per-particle sums ask for a pair's records this many entries ahead (__builtin_prefetch). */
enum { PREFETCH_AHEAD = 8 };

/* The block's inputs, a pair per lane: pair_kinematics and the history, one array per number
 * (contiguous lanes are what packed loads read). */
// clang-format off
#define PAIR_BLOCK_INPUTS(X)                                                                    \
  X(dx, d.x) X(dy, d.y) X(dz, d.z) X(dist, dist) X(ri, ri) X(rj, rj) X(mi, mi) X(mj, mj)         \
  X(vix, vi.x) X(viy, vi.y) X(viz, vi.z) X(vjx, vj.x) X(vjy, vj.y) X(vjz, vj.z)                  \
  X(oix, oi.x) X(oiy, oi.y) X(oiz, oi.z) X(ojx, oj.x) X(ojy, oj.y) X(ojz, oj.z)                  \
  X(vpix, vpi.x) X(vpiy, vpi.y) X(vpiz, vpi.z) X(vpjx, vpj.x) X(vpjy, vpj.y) X(vpjz, vpj.z)      \
  X(opix, opi.x) X(opiy, opi.y) X(opiz, opi.z) X(opjx, opj.x) X(opjy, opj.y) X(opjz, opj.z)
#define PAIR_BLOCK_HISTORY(X)                                                                   \
  X(tx, tangential.x) X(ty, tangential.y) X(tz, tangential.z) X(rx, rolling.x)                  \
  X(ry, rolling.y) X(rz, rolling.z) X(taux, tangential_aux) X(raux, rolling_aux)                \
  X(ftx, tangential_force.x) X(fty, tangential_force.y) X(ftz, tangential_force.z)               \
  X(elastic, elastic)
// clang-format on

typedef struct pair_block {
  int m;                        /* pairs held */
  int kind;                     /* the kernel's index in pair_block_kernels */
  const adem_interaction *it;   /* the interaction of every pair of the block */
  size_t k[PAIR_BLOCK];         /* pair index */
  double fresh[PAIR_BLOCK];     /* 1: not touching at the last pass */
  struct {
#define PAIR_BLOCK_ARRAY(a, f) double a[PAIR_BLOCK];
    struct { PAIR_BLOCK_INPUTS(PAIR_BLOCK_ARRAY) } kin;
    struct { PAIR_BLOCK_HISTORY(PAIR_BLOCK_ARRAY) } hist;
#undef PAIR_BLOCK_ARRAY
  } in;
  adem_contact_history hist[PAIR_BLOCK]; /* the histories after the pass */
  adem_pair_result res[PAIR_BLOCK];
  adem_pair_balance bal[PAIR_BLOCK];
} pair_block;

/* Puts a pair's kinematics and history in lane q. */
static inline __attribute__((always_inline)) void
pair_block_put(pair_block *b, int q, const pair_kinematics *kin, const adem_contact_history *h) {
#define PAIR_BLOCK_PUT_KIN(a, f) b->in.kin.a[q] = kin->f;
#define PAIR_BLOCK_PUT_HIST(a, f) b->in.hist.a[q] = h->f;
  PAIR_BLOCK_INPUTS(PAIR_BLOCK_PUT_KIN)
  PAIR_BLOCK_HISTORY(PAIR_BLOCK_PUT_HIST)
#undef PAIR_BLOCK_PUT_KIN
#undef PAIR_BLOCK_PUT_HIST
}

/* The loop the compiler packs: laws and balance are constants of each kernel below. */
static inline __attribute__((always_inline)) void
pair_block_laws(const adem_force_scope *w, pair_block *restrict b, law_set laws, bool balance) {
  const adem_interaction *it = b->it;
  double dt = law_step(w); /* 0 while the pass holds histories (prepare) */
  double h_close = w->second_order ? 0.5 * w->dt : 0.0; /* as particle_pair's 0.5 hp */
  int m = b->m;
  for (int q = 0; q < m; ++q) {
    pair_kinematics kin;
    adem_contact_history h;
#define PAIR_BLOCK_GET_KIN(a, f) kin.f = b->in.kin.a[q];
#define PAIR_BLOCK_GET_HIST(a, f) h.f = b->in.hist.a[q];
    PAIR_BLOCK_INPUTS(PAIR_BLOCK_GET_KIN)
    PAIR_BLOCK_HISTORY(PAIR_BLOCK_GET_HIST)
#undef PAIR_BLOCK_GET_KIN
#undef PAIR_BLOCK_GET_HIST
    contact_geometry g = kinematic_geometry(&kin, false, true, h_close);
    contact_result r = contact_force(it, laws, &g, &h, dt, b->fresh[q] != 0.0);
    b->hist[q] = h;
    pair_records(&g, &r, balance, &b->res[q], &b->bal[q]);
  }
}

/* flatten: every law inlined into the loop (a call keeps it from packing); the clones: one per
 * instruction set, chosen when the program loads (GCC on x86-64; ADEM_NO_CLONES: SSE2 only) */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ADEM_NO_CLONES)
#define PAIR_BLOCK_CLONES __attribute__((flatten, target_clones("avx512f", "avx2", "default")))
#else
#define PAIR_BLOCK_CLONES __attribute__((flatten))
#endif

/* The laws with a block kernel: normal x rolling (with viscoelastic damping and the incremental
 * tangential law), in the order of pair_block_kernels' rows. */
// clang-format off
#define PAIR_BLOCK_LAWS(X)                                                                       \
  X(hertz_none, ADEM_NORMAL_HERTZ, ADEM_ROLLING_NONE)                                          \
  X(hertz_model_a, ADEM_NORMAL_HERTZ, ADEM_ROLLING_A)                                          \
  X(hertz_model_c, ADEM_NORMAL_HERTZ, ADEM_ROLLING_C)                                          \
  X(hertz_model_c_capped, ADEM_NORMAL_HERTZ, ADEM_ROLLING_C_CAPPED)                            \
  X(hertz_brof, ADEM_NORMAL_HERTZ, ADEM_ROLLING_BROF)                                          \
  X(jkr_none, ADEM_NORMAL_JKR, ADEM_ROLLING_NONE)                                              \
  X(jkr_model_a, ADEM_NORMAL_JKR, ADEM_ROLLING_A)                                              \
  X(jkr_model_c, ADEM_NORMAL_JKR, ADEM_ROLLING_C)                                              \
  X(jkr_model_c_capped, ADEM_NORMAL_JKR, ADEM_ROLLING_C_CAPPED)                                \
  X(jkr_brof, ADEM_NORMAL_JKR, ADEM_ROLLING_BROF)
#define PAIR_BLOCK_KERNEL(name, normal, rolling)                                                  \
  PAIR_BLOCK_CLONES static void pair_block_##name(const adem_force_scope *w, pair_block *b) {     \
    law_set laws = {normal, ADEM_DAMPING_VISCOELASTIC, ADEM_TANGENTIAL_INCREMENTAL, rolling};    \
    pair_block_laws(w, b, laws, false);                                                          \
  }                                                                                               \
  PAIR_BLOCK_CLONES static void pair_block_##name##_balance(const adem_force_scope *w,            \
                                                            pair_block *b) {                      \
    law_set laws = {normal, ADEM_DAMPING_VISCOELASTIC, ADEM_TANGENTIAL_INCREMENTAL, rolling};    \
    pair_block_laws(w, b, laws, true);                                                           \
  }
// clang-format on
PAIR_BLOCK_LAWS(PAIR_BLOCK_KERNEL)
#undef PAIR_BLOCK_KERNEL

typedef void (*pair_block_kernel)(const adem_force_scope *w, pair_block *b);
static const struct {
  int normal, rolling;
  pair_block_kernel laws[2]; /* without and with the energy balance */
} pair_block_kernels[] = {
// clang-format off
#define PAIR_BLOCK_ROW(name, normal, rolling) \
  {normal, rolling, {pair_block_##name, pair_block_##name##_balance}},
// clang-format on
    PAIR_BLOCK_LAWS(PAIR_BLOCK_ROW)
#undef PAIR_BLOCK_ROW
};

/* The block kernel for the interaction's laws, or -1. */
static inline int pair_block_kind(const adem_interaction *it) {
  /* the kernels leave I_r 0: of their rolling laws only model C's dashpot reads it */
  bool dashpot = (it->rolling == ADEM_ROLLING_C || it->rolling == ADEM_ROLLING_C_CAPPED) &&
                 needs_rolling_inertia(it);
  if (it->damping != ADEM_DAMPING_VISCOELASTIC || it->tangential != ADEM_TANGENTIAL_INCREMENTAL ||
      dashpot)
    return -1;
  for (int r = 0; r < (int)(sizeof pair_block_kernels / sizeof pair_block_kernels[0]); ++r)
    if (pair_block_kernels[r].normal == (int)it->normal &&
        pair_block_kernels[r].rolling == (int)it->rolling)
      return r;
  return -1;
}

/* Runs the block's kernel and stores its pairs' results. */
static void pair_block_flush(const adem_force_scope *w, pair_block *b) {
  if (b->m == 0) return;
  pair_block_kernels[b->kind].laws[w->balance](w, b);
#ifdef ADEM_HAVE_OPENMP
#pragma omp atomic
#endif
  *w->block_pairs += (uint64_t)b->m;
  adem_pair_list *l = w->pp;
  for (int q = 0; q < b->m; ++q) {
    size_t k = b->k[q];
    if (!v3_isfinite(b->res[q].force_a)) { /* a law's library call (packed), or a bad state */
      particle_pair(w, k, v3(b->in.kin.dx[q], b->in.kin.dy[q], b->in.kin.dz[q]), b->in.kin.dist[q],
                    b->fresh[q] == 0.0, b->it);
      continue;
    }
    l->touching[k] = true;
    if (!w->hold_history) l->hist[k] = b->hist[q];
    l->res[k] = b->res[q];
    if (w->balance) { /* the fields pair_records writes: a particle pair has no wall power */
      l->bal[k].damping_a = b->bal[q].damping_a;
      l->bal[k].damping_torque_a = b->bal[q].damping_torque_a;
      l->bal[k].damping_torque_b = b->bal[q].damping_torque_b;
      l->bal[k].dissipated = b->bal[q].dissipated;
    }
    note_overlap(w, b->res[q].overlap_ratio);
  }
  b->m = 0;
}

/* The particle pairs of chunk c: those apart forgotten, the touching ones of an interaction with
 * a block kernel gathered into blocks, the rest one at a time. Each pair writes only its own
 * records, so the order in which they are done changes nothing. */
static void particle_pair_chunk(const adem_force_scope *w, size_t c) {
  adem_particles *p = w->p;
  adem_pair_list *l = w->pp;
  size_t k0 = c * w->pair_chunk, k1 = l->n - k0 < w->pair_chunk ? l->n : k0 + w->pair_chunk;
  pair_block b;
  b.m = 0;
  b.kind = -1;
  b.it = NULL;
  const adem_interaction *last_it = NULL; /* the last interaction looked up, and its kernel */
  int last_kind = -1;
  for (size_t k = k0; k < k1; ++k) {
    size_t i = l->a[k], j = l->b[k];
    adem_vec3 d = adem_periodic_min_image(w->periodic, v3_sub(p->pos[j], p->pos[i]));
    double rsum = p->radius[i] + p->radius[j];
    double dist2 = v3_norm2(d);
    bool was = l->touching[k];
    if (dist2 >= rsum * rsum && !was) { /* apart now and at the last pass */
      forget_opened(l, k, w->balance);
      continue;
    }
    double dist = sqrt(dist2);
    const adem_interaction *it = adem_materials_pair(w->mat, p->material[i], p->material[j]);
    if (it != last_it) { /* neighbours mostly share an interaction: look its kernel up once */
      last_it = it;
      last_kind = pair_block_kind(it);
    }
    int kind = !w->pair_blocks || w->energy || !(rsum - dist > 0.0) ? -1 : last_kind;
    if (kind < 0) {
      particle_pair(w, k, d, dist, was, it);
      continue;
    }
    if (b.m > 0 && (b.it != it || b.kind != kind)) pair_block_flush(w, &b);
    int q = b.m++;
    b.kind = kind;
    b.it = it;
    b.k[q] = k;
    pair_kinematics kin =
        particle_kinematics(p, w->predicted, i, j, d, dist, w->second_order ? w->dt : 0.0);
    pair_block_put(&b, q, &kin, &l->hist[k]);
    b.fresh[q] = onset_pass(w) && !was ? 1.0 : 0.0;
    if (b.m == PAIR_BLOCK) pair_block_flush(w, &b);
  }
  pair_block_flush(w, &b);
}

static inline void wall_pair(const adem_force_scope *w, size_t k) {
  adem_particles *p = w->p;
  adem_pair_list *l = w->pw;
  double dt = w->dt;
  {
    size_t i = l->a[k];
    const adem_plane_def *pl = &w->walls->planes[l->b[k]].def;
    double ri = p->radius[i];
    /* the nearest point of the wall's surface (a plane: the plane formula's bits; cylinder.h) */
    adem_wall_near near = adem_wall_nearest(pl, p->pos[i]);
    double dist = adem_wall_contact_gap(&near, ri);
    bool was = l->touching[k];
    if (dist >= ri && !was) {
      forget_opened(l, k, w->balance);
      return;
    }
    contact_geometry g;
    g.n = near.n;
    g.delta = ri - dist;
    g.R = ri;
    g.mstar = 1.0 / p->inv_mass[i];
    adem_vec3 v_wall = adem_motion_point_velocity(&w->walls->planes[l->b[k]].motion, w->walls->time,
                                                  v3_axpy(p->pos[i], ri, g.n));
    g.w = v3_add(v3_sub(p->vel[i], v_wall), v3_cross(v3_scale(p->omega[i], ri), g.n));
    /* rolling laws see the spin relative to the wall's */
    adem_vec3 spin_wall = motion_spin(&w->walls->planes[l->b[k]].motion);
    adem_vec3 om = v3_sub(p->omega[i], spin_wall);
    g.omega_rel = v3_axpy(om, -v3_dot(om, g.n), g.n);
    double hp = w->second_order ? dt : 0.0;
    adem_vec3 opi = predicted_spin(p, i, hp);
    g.w_pred = v3_add(v3_sub(predicted_velocity(p, i, hp), v_wall), v3_cross(v3_scale(opi, ri), g.n));
    adem_vec3 omp = v3_sub(opi, spin_wall);
    g.omega_pred = v3_axpy(omp, -v3_dot(omp, g.n), g.n);
    g.ri = ri;
    g.rj = 0.0;
    g.energy = w->energy;
    g.packed = false;
    set_mobility(&g, p->inv_mass[i], 0.5 * hp);
    const adem_interaction *it = adem_materials_pair(w->mat, p->material[i], pl->material);
    g.inertia_r = needs_rolling_inertia(it) ? 1.0 / p->inv_inertia[i] + ri * ri / p->inv_mass[i] : 0.0;
    if (g.delta <= 0.0) {
      open_pair(l, k, it, &g, onset_pass(w), dt, w->balance, w->break_forces);
      return;
    }
    adem_contact_history h = l->hist[k];
    contact_result r = contact_force(it, laws_of(it), &g, &h, law_step(w), onset_pass(w) && !was);
    if (!w->hold_history) l->hist[k] = h;
    store_pair(l, k, &g, &r, w->balance);
    note_overlap(w, l->res[k].overlap_ratio);
    if (w->balance) store_wall_power(l, k, &r, v_wall, motion_spin(&w->walls->planes[l->b[k]].motion));
  }
}

/* Mesh contacts, per particle: the distinct contacts of its candidate triangles (one per flat
 * region, convex edge or vertex: contact/triangle.h), each with the history its key had at the
 * last step, then the force as for a plane moving with the triangle's group. */
static void mesh_pairs(const adem_force_scope *w) {
  adem_particles *p = w->p;
  adem_mesh_pairs *pm = w->pm;
  adem_pair_list *l = &pm->l;
  const adem_mesh *m = &w->walls->mesh;
  if (m->ntris == 0 || !pm->start) return;
  /* the last step's contacts become the previous ones */
  adem_contact_history *hs = l->hist;
  l->hist = pm->hist_prev;
  pm->hist_prev = hs;
  bool *ts = l->touching;
  l->touching = pm->touching_prev;
  pm->touching_prev = ts;
  uint64_t *ks = pm->key;
  pm->key = pm->key_prev;
  pm->key_prev = ks;
  int nthreads = w->nthreads;
  double dt = w->dt;
  size_t n = p->n;
  ADEM_PARALLEL_FOR
  for (size_t i = 0; i < n; ++i) {
    size_t s = pm->start[i], e = pm->start[i + 1];
    if (s == e) continue;
    double ri = p->radius[i];
    size_t nc = adem_triangle_sphere_contacts(m, p->pos[i], ri, &l->b[s], e - s, &pm->found[s]);
    /* The stored energy of a last-step contact whose key is not found again (it opened, or moved
     * to another region of the mesh and starts afresh) is gone: dissipated. */
    double lost = 0.0;
    for (size_t q = s, k = s; q < e && pm->touching_prev[q]; ++q) {
      while (k < s + nc && pm->found[k].key < pm->key_prev[q]) ++k;
      if (k >= s + nc || pm->found[k].key != pm->key_prev[q]) lost += pm->hist_prev[q].elastic;
    }
    if (w->balance) p->dissipated[i] += lost;
    size_t q = s; /* the previous contacts fill the first slots, sorted by key */
    for (size_t k = s; k < e; ++k) {
      if (k >= s + nc) {
        adem_mesh_pairs_clear(pm, k);
        continue;
      }
      const adem_mesh_contact *c = &pm->found[k];
      while (q < e && pm->touching_prev[q] && pm->key_prev[q] < c->key) ++q;
      adem_contact_history h;
      bool fresh = !(q < e && pm->touching_prev[q] && pm->key_prev[q] == c->key);
      if (!fresh) h = pm->hist_prev[q];
      else memset(&h, 0, sizeof h);
      uint32_t grp = m->group[c->tri];
      contact_geometry g;
      g.n = c->normal;
      g.delta = c->overlap;
      g.R = ri;
      g.mstar = 1.0 / p->inv_mass[i];
      adem_vec3 v_wall = adem_motion_point_velocity(&w->walls->mesh_motion[grp], w->walls->time, c->point);
      g.w = v3_add(v3_sub(p->vel[i], v_wall), v3_cross(v3_scale(p->omega[i], ri), g.n));
      adem_vec3 spin_wall = motion_spin(&w->walls->mesh_motion[grp]);
      adem_vec3 om = v3_sub(p->omega[i], spin_wall);
      g.omega_rel = v3_axpy(om, -v3_dot(om, g.n), g.n);
      double hp = w->second_order ? dt : 0.0;
      adem_vec3 opi = predicted_spin(p, i, hp);
      g.w_pred = v3_add(v3_sub(predicted_velocity(p, i, hp), v_wall), v3_cross(v3_scale(opi, ri), g.n));
      adem_vec3 omp = v3_sub(opi, spin_wall);
      g.omega_pred = v3_axpy(omp, -v3_dot(omp, g.n), g.n);
      g.ri = ri;
      g.rj = 0.0;
      g.energy = w->energy;
      g.packed = false;
      set_mobility(&g, p->inv_mass[i], 0.5 * hp);
      const adem_interaction *it = adem_materials_pair(w->mat, p->material[i], m->groups[grp].material);
      g.inertia_r = needs_rolling_inertia(it) ? 1.0 / p->inv_inertia[i] + ri * ri / p->inv_mass[i] : 0.0;
      adem_contact_history h_held = h;
      contact_result r = contact_force(it, laws_of(it), &g, &h, law_step(w), onset_pass(w) && fresh);
      adem_vec3 ft = v3_axpy(r.force, -v3_dot(r.force, g.n), g.n);
      l->hist[k] = w->hold_history ? h_held : h;
      pm->key[k] = c->key;
      pm->owner[k] = c->tri;
      l->touching[k] = true;
      l->res[k].force_a = r.force;
      l->res[k].moment = v3_cross(g.n, ft);
      l->res[k].rolling_a = r.rolling;
      l->res[k].rolling_capacity = r.capacity;
      l->res[k].overlap_ratio = g.delta / ri;
      if (g.energy) l->elastic[k] = r.elastic;
      note_overlap(w, l->res[k].overlap_ratio);
      if (!w->balance) continue;
      l->bal[k].damping_a = r.damping;
      l->bal[k].damping_torque_a = v3_add(v3_cross(v3_scale(g.n, ri), r.damping), r.damping_couple);
      l->bal[k].damping_torque_b = v3_zero();
      l->bal[k].dissipated = r.dissipated;
      store_wall_power(l, k, &r, v_wall, motion_spin(&w->walls->mesh_motion[grp]));
    }
  }
  /* Force on each face, and its moment about the face's group's reference point: the force acts
   * at the contact point, and the wall takes the opposite of the rolling couple. Summed over the
   * particles by id, each one's contacts by key: an order neither the thread count nor the
   * storage order changes. */
  adem_walls_clear_face_loads(w->walls);
  const uint32_t *by_id = w->nb->id_order;
  for (size_t r = 0; r < n; ++r) {
    size_t i = by_id[r];
    for (size_t k = pm->start[i]; k < pm->start[i + 1] && l->touching[k]; ++k) {
      size_t t = pm->owner[k];
      adem_vec3 fw = v3_neg(l->res[k].force_a);
      adem_vec3 arm = v3_sub(pm->found[k].point, w->walls->mesh_ref[m->group[t]]);
      adem_walls_add_face_load(w->walls, t, fw, v3_sub(v3_cross(arm, fw), l->res[k].rolling_a));
    }
  }
}

/* The energy a particle's kicks take out through the dissipative forces of its contacts (sum
 * G, torques H) and give through moving walls (wall power P_w, of which P_d is the dissipative
 * forces' share). The force F, T of this pass acts in two half kicks: the closing one of this
 * step (v_half -> v_full) and the opening one of the next (v_full -> v_next). A force's work in
 * a half kick is F.(v_before + v_after)/2 dt/2 exactly (the kinetic energy changes by that sum
 * over all forces), so the dissipation is counted with the same velocities as the kinetic
 * energy: the closing half now, the opening half at the next pass (held back in *_next, so that
 * the totals after a step match the kinetic energy after it). */
typedef struct particle_energy {
  adem_vec3 G, H;       /* dissipative force and torque on the particle */
  double P_w, P_d;      /* wall power and its dissipative share, W */
  double dissipated;    /* the laws' own, of the step just done (its share of pairs'), J */
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
                         p->ext_force[i]);
    adem_vec3 t = v3_zero(), roll = v3_zero();
    double ri = p->radius[i]; /* the arm of its contacts' tangential forces */
    particle_energy en = {v3_zero(), v3_zero(), 0.0, 0.0, 0.0};
    double capacity = 0.0, capacity_pp = 0.0;
    adem_vec3 wall_spin = v3_zero(); /* sum of capacity x spin of the walls it touches (BROF) */
    adem_vec3 partner_spin = v3_zero(); /* the same of its particle partners (brof_objective) */
    bool objective = false;
    for (size_t e = nb->pp_start[i]; e < nb->pp_start[i + 1]; ++e) {
      uint32_t code = nb->pp_entries[e];
      size_t k = code >> 1;
      /* the entries a particle ahead: their records are scattered over the list, and a read
       * that waits for memory is most of the sum's time on a large bed */
      if (e + PREFETCH_AHEAD < nb->pp_start[n_all]) {
        size_t ka = nb->pp_entries[e + PREFETCH_AHEAD] >> 1;
        __builtin_prefetch(&pp->res[ka]);
        __builtin_prefetch(&pp->touching[ka]);
      }
      if (balance) en.dissipated += 0.5 * pp->bal[k].dissipated; /* also of one just opened */
      if (!pp->touching[k]) { /* apart; one that just opened may carry a break correction */
        if (!breaks) continue;
        adem_vec3 fb = pp->res[k].force_a;
        if (fb.x != 0.0 || fb.y != 0.0 || fb.z != 0.0) f = (code & 1u) ? v3_sub(f, fb) : v3_add(f, fb);
        continue;
      }
      if (code & 1u) {
        f = v3_sub(f, pp->res[k].force_a);
        t = v3_add(t, v3_sub(v3_scale(pp->res[k].moment, ri), pp->res[k].rolling_a));
        roll = v3_sub(roll, pp->res[k].rolling_a);
        if (balance) {
          en.G = v3_sub(en.G, pp->bal[k].damping_a);
          en.H = v3_add(en.H, pp->bal[k].damping_torque_b);
        }
      } else {
        f = v3_add(f, pp->res[k].force_a);
        t = v3_add(t, v3_add(v3_scale(pp->res[k].moment, ri), pp->res[k].rolling_a));
        roll = v3_add(roll, pp->res[k].rolling_a);
        if (balance) {
          en.G = v3_add(en.G, pp->bal[k].damping_a);
          en.H = v3_add(en.H, pp->bal[k].damping_torque_a);
        }
      }
      capacity += pp->res[k].rolling_capacity;
      if (pp->res[k].rolling_capacity > 0.0) {
        size_t j = (code & 1u) ? pp->a[k] : pp->b[k];
        if (adem_materials_pair(w->mat, p->material[i], p->material[j])->rolling ==
            ADEM_ROLLING_BROF_OBJECTIVE) {
          partner_spin = v3_axpy(partner_spin, pp->res[k].rolling_capacity, p->omega[j]);
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

/* Particle i's predicted velocity and spin, read by each of its particle pairs. */
static inline void predict_particle(const adem_force_scope *w, size_t i) {
  double hp = w->second_order ? w->dt : 0.0;
  w->predicted[2 * i] = predicted_velocity(w->p, i, hp);
  w->predicted[2 * i + 1] = predicted_spin(w->p, i, hp);
}

void adem_contacts_compute(const adem_force_scope *scope) {
  adem_force_scope s = *scope;
  int breaks = 0;
  s.break_forces = &breaks;
  const adem_force_scope *w = &s;
  int nthreads = w->nthreads;
  if (w->predicted) ADEM_FOR(nthreads, w->p->n, predict_particle, w);
  /* chunks of the pair list: a few per thread even on a small system (the static split gives
   * each thread whole chunks), at most 2048 pairs; their size changes no result */
  size_t chunk = w->pp->n / (8 * (size_t)(nthreads > 1 ? nthreads : 1));
  s.pair_chunk = chunk < 4 * PAIR_BLOCK ? 4 * PAIR_BLOCK : chunk > 2048 ? 2048 : chunk;
  ADEM_FOR(nthreads, (w->pp->n + s.pair_chunk - 1) / s.pair_chunk, particle_pair_chunk, w);
  ADEM_FOR(nthreads, w->pw->n, wall_pair, w);
  mesh_pairs(w);
  if (w->balance) ADEM_FOR(nthreads, w->p->n, sum_particle, w);
  else ADEM_FOR(nthreads, w->p->n, sum_particle_loads, w);
}
