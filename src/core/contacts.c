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

typedef adem_contact_geometry contact_geometry;

typedef struct contact_result {
  adem_vec3 force;    /* on i */
  adem_vec3 rolling;  /* rolling couple on i (j takes the opposite) */
  double capacity;    /* per-particle rolling resistance this contact offers (BROF) */
  double elastic;     /* stored energy, J */
} contact_result;

/* One contact through the laws of its pair (include/adem/laws.h): normal, damping, tangential,
 * rolling, each dispatched by a switch generated from the rows, updating the history. */
static inline contact_result contact_force(const adem_interaction *it, const contact_geometry *g,
                                           adem_contact_history *h, double dt) {
  const adem_pair_params *pp = &it->pp;
  contact_result r;
  double vn = v3_dot(g->w, g->n); /* > 0 while approaching */
  adem_vec3 vt = v3_axpy(g->w, -vn, g->n);

  double a = adem_hertz_radius(g->R, g->delta); /* sqrt(R delta): S_n, S_t use it (H13, H14) */
  adem_normal_result nr;
  switch (it->normal) {
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
  double Sn = adem_hertz_normal_stiffness(pp->E, a);
  double St = adem_hertz_tangential_stiffness(pp->G, a);
  adem_damping_input din = {Sn, St, g->mstar, vn, nr.f_elastic, nr.f_critical};
  adem_damping_output dout = {nr.f_elastic, 0.0};
  switch (it->damping) {
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

  double f_load = fabs(nr.f_elastic + 2.0 * nr.f_critical); /* the load the contact carries */
  double f_limit = pp->friction * f_load;                     /* H17 */
  adem_tangential_input tin = {g->n, vt, dt, St, ct, f_limit};
  adem_tangential_output tout = {v3_zero(), v3_zero(), 0.0, 0.0, false};
  switch (it->tangential) {
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
  r.elastic = nr.e_elastic + tout.elastic;
  adem_rolling_input in = {g, pp, dt, f_load, nr.a, Sn};
  adem_rolling_output ro = {v3_zero(), 0.0, 0.0};
  switch (it->rolling) {
#define ADEM_X(ID, name, kernel, hist, req, ppart, params, eq, doc) \
  case ID:                                                       \
    kernel(&in, &h->rolling, &ro);                               \
    break;
    ADEM_ROLLING_LAWS(ADEM_X)
#undef ADEM_X
    default:
      break;
  }
  r.rolling = ro.torque;
  r.capacity = ro.capacity;
  r.elastic += ro.elastic; /* the elastic part is never -0: adding 0 changes nothing */
  return r;
}

/* Stores a contact's results. The tangential force acts at r_a n from a's centre and at -r_b n
 * from b's, so its moments are r_a n x F_t on a and r_b n x F_t on b; the rolling couple is
 * equal and opposite. A wall (r_b = 0) takes no torque. */
static inline void store_pair(adem_pair_list *l, size_t k, const contact_geometry *g,
                              const contact_result *r) {
  adem_vec3 ft = v3_axpy(r->force, -v3_dot(r->force, g->n), g->n);
  l->touching[k] = true;
  l->force_a[k] = r->force;
  l->torque_a[k] = v3_add(v3_cross(v3_scale(g->n, g->ri), ft), r->rolling);
  l->torque_b[k] = g->rj > 0.0 ? v3_sub(v3_cross(v3_scale(g->n, g->rj), ft), r->rolling) : v3_zero();
  l->rolling_a[k] = r->rolling;
  l->rolling_capacity[k] = r->capacity;
  l->elastic[k] = r->elastic;
  l->overlap_ratio[k] = g->delta / (g->rj > 0.0 ? fmin(g->ri, g->rj) : g->ri);
}

static inline void particle_pair(const adem_force_scope *w, size_t k) {
  adem_particles *p = w->p;
  adem_pair_list *l = w->pp;
  double dt = w->dt;
  {
    size_t i = l->a[k], j = l->b[k];
    adem_vec3 d = v3_sub(p->pos[j], p->pos[i]);
    double ri = p->radius[i], rj = p->radius[j];
    double rsum = ri + rj;
    double dist2 = v3_norm2(d);
    if (dist2 >= rsum * rsum) {
      adem_pairs_clear(l, k);
      return;
    }
    double dist = sqrt(dist2);
    contact_geometry g;
    g.n = v3_scale(d, 1.0 / dist);
    g.delta = rsum - dist;
    g.R = ri * rj / rsum;
    g.mstar = 1.0 / (p->inv_mass[i] + p->inv_mass[j]);
    /* contact points: i's at +r_i n, j's at -r_j n */
    adem_vec3 spin = v3_add(v3_scale(p->omega[i], ri), v3_scale(p->omega[j], rj));
    g.w = v3_add(v3_sub(p->vel[i], p->vel[j]), v3_cross(spin, g.n));
    adem_vec3 om = v3_sub(p->omega[i], p->omega[j]);
    g.omega_rel = v3_axpy(om, -v3_dot(om, g.n), g.n);
    g.ri = ri;
    g.rj = rj;
    /* I_r = [1/(I_i + m_i r_i^2) + 1/(I_j + m_j r_j^2)]^-1: moments about the contact point */
    double Ici = 1.0 / p->inv_inertia[i] + ri * ri / p->inv_mass[i];
    double Icj = 1.0 / p->inv_inertia[j] + rj * rj / p->inv_mass[j];
    g.inertia_r = Ici * Icj / (Ici + Icj);
    const adem_interaction *it = adem_materials_pair(w->mat, p->material[i], p->material[j]);
    contact_result r = contact_force(it, &g, &l->hist[k], dt);
    store_pair(l, k, &g, &r);
  }
}

static inline void wall_pair(const adem_force_scope *w, size_t k) {
  adem_particles *p = w->p;
  adem_pair_list *l = w->pw;
  double dt = w->dt;
  {
    size_t i = l->a[k];
    const adem_plane_def *pl = &w->walls->planes[l->b[k]].def;
    double ri = p->radius[i];
    double dist = v3_dot(v3_sub(p->pos[i], pl->point), pl->normal);
    if (dist >= ri) {
      adem_pairs_clear(l, k);
      return;
    }
    contact_geometry g;
    g.n = v3_neg(pl->normal);
    g.delta = ri - dist;
    g.R = ri;
    g.mstar = 1.0 / p->inv_mass[i];
    adem_vec3 v_wall = adem_motion_point_velocity(&w->walls->planes[l->b[k]].motion, w->walls->time,
                                                  v3_axpy(p->pos[i], ri, g.n));
    g.w = v3_add(v3_sub(p->vel[i], v_wall), v3_cross(v3_scale(p->omega[i], ri), g.n));
    g.omega_rel = v3_axpy(p->omega[i], -v3_dot(p->omega[i], g.n), g.n);
    g.ri = ri;
    g.rj = 0.0;
    g.inertia_r = 1.0 / p->inv_inertia[i] + ri * ri / p->inv_mass[i];
    const adem_interaction *it = adem_materials_pair(w->mat, p->material[i], pl->material);
    contact_result r = contact_force(it, &g, &l->hist[k], dt);
    store_pair(l, k, &g, &r);
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
    size_t q = s; /* the previous contacts fill the first slots, sorted by key */
    for (size_t k = s; k < e; ++k) {
      if (k >= s + nc) {
        adem_mesh_pairs_clear(pm, k);
        continue;
      }
      const adem_mesh_contact *c = &pm->found[k];
      while (q < e && pm->touching_prev[q] && pm->key_prev[q] < c->key) ++q;
      adem_contact_history h;
      if (q < e && pm->touching_prev[q] && pm->key_prev[q] == c->key) h = pm->hist_prev[q];
      else memset(&h, 0, sizeof h);
      uint32_t grp = m->group[c->tri];
      contact_geometry g;
      g.n = c->normal;
      g.delta = c->overlap;
      g.R = ri;
      g.mstar = 1.0 / p->inv_mass[i];
      adem_vec3 v_wall = adem_motion_point_velocity(&w->walls->mesh_motion[grp], w->walls->time, c->point);
      g.w = v3_add(v3_sub(p->vel[i], v_wall), v3_cross(v3_scale(p->omega[i], ri), g.n));
      g.omega_rel = v3_axpy(p->omega[i], -v3_dot(p->omega[i], g.n), g.n);
      g.ri = ri;
      g.rj = 0.0;
      g.inertia_r = 1.0 / p->inv_inertia[i] + ri * ri / p->inv_mass[i];
      const adem_interaction *it = adem_materials_pair(w->mat, p->material[i], m->groups[grp].material);
      contact_result r = contact_force(it, &g, &h, dt);
      adem_vec3 ft = v3_axpy(r.force, -v3_dot(r.force, g.n), g.n);
      l->hist[k] = h;
      pm->key[k] = c->key;
      pm->owner[k] = c->tri;
      l->touching[k] = true;
      l->force_a[k] = r.force;
      l->torque_a[k] = v3_add(v3_cross(v3_scale(g.n, ri), ft), r.rolling);
      l->torque_b[k] = v3_zero();
      l->rolling_a[k] = r.rolling;
      l->rolling_capacity[k] = r.capacity;
      l->elastic[k] = r.elastic;
      l->overlap_ratio[k] = g.delta / ri;
    }
  }
  /* Force on each face, and its moment about the face's group's reference point: the force acts
   * at the contact point, and the wall takes the opposite of the rolling couple. In slot order
   * (fixed for any thread count). */
  adem_walls_clear_face_loads(w->walls);
  for (size_t k = 0; k < l->n; ++k) {
    if (!l->touching[k]) continue;
    size_t t = pm->owner[k];
    adem_vec3 fw = v3_neg(l->force_a[k]);
    adem_vec3 arm = v3_sub(pm->found[k].point, w->walls->mesh_ref[m->group[t]]);
    adem_walls_add_face_load(w->walls, t, fw, v3_sub(v3_cross(arm, fw), l->rolling_a[k]));
  }
}

/* Per-particle sums in the order of the gather lists: body forces first, then particle
 * contacts by increasing pair index, then wall contacts, then mesh contacts by key. */
static inline void sum_particle(const adem_force_scope *w, size_t i) {
  adem_particles *p = w->p;
  const adem_neighbors *nb = w->nb;
  const adem_pair_list *pp = w->pp, *pw = w->pw, *pm = &w->pm->l;
  const size_t *pm_start = w->walls->mesh.ntris > 0 ? w->pm->start : NULL;
  adem_vec3 g = w->gravity;
  double dt = w->dt;
  {
    adem_vec3 f = v3_add(v3_scale(g, 1.0 / p->inv_mass[i]), w->groups[p->group[i]].external_force);
    adem_vec3 t = v3_zero(), roll = v3_zero();
    double capacity = 0.0;
    for (size_t e = nb->pp_start[i]; e < nb->pp_start[i + 1]; ++e) {
      uint32_t code = nb->pp_entries[e];
      size_t k = code >> 1;
      if (!pp->touching[k]) continue;
      if (code & 1u) {
        f = v3_sub(f, pp->force_a[k]);
        t = v3_add(t, pp->torque_b[k]);
        roll = v3_sub(roll, pp->rolling_a[k]);
      } else {
        f = v3_add(f, pp->force_a[k]);
        t = v3_add(t, pp->torque_a[k]);
        roll = v3_add(roll, pp->rolling_a[k]);
      }
      capacity += pp->rolling_capacity[k];
    }
    for (size_t e = nb->pw_start[i]; e < nb->pw_start[i + 1]; ++e) {
      size_t k = nb->pw_entries[e];
      if (!pw->touching[k]) continue;
      f = v3_add(f, pw->force_a[k]);
      t = v3_add(t, pw->torque_a[k]);
      roll = v3_add(roll, pw->rolling_a[k]);
      capacity += pw->rolling_capacity[k];
    }
    /* mesh contacts: the first slots of the particle's range, by key */
    for (size_t k = pm_start ? pm_start[i] : 0; pm_start && k < pm_start[i + 1]; ++k) {
      if (!pm->touching[k]) break;
      f = v3_add(f, pm->force_a[k]);
      t = v3_add(t, pm->torque_a[k]);
      roll = v3_add(roll, pm->rolling_a[k]);
      capacity += pm->rolling_capacity[k];
    }
    uint8_t held = 0;
    if (capacity > 0.0) {
      /* BROF (I9-I10). omega is the half-step spin; -I omega/dt - t would stop it within the
       * step. When the capacity allows that, the particle is held: the resistance cancels every
       * other torque and the closing half kick sets the spin to exactly zero (a sum of two half
       * kicks would leave a round-off residue that then never dies out). */
      adem_vec3 t_stop = v3_sub(v3_scale(p->omega[i], -1.0 / (p->inv_inertia[i] * dt)), t);
      adem_vec3 t_brof = adem_rolling_brof(t_stop, capacity);
      if (v3_norm2(t_stop) <= capacity * capacity) {
        t_brof = v3_neg(t);
        held = 1;
      }
      t = v3_add(t, t_brof);
      roll = v3_add(roll, t_brof);
    }
    adem_particles_set_loads(p, i, f, t, roll, held);
  }
}

void adem_contacts_compute(const adem_force_scope *w) {
  int nthreads = w->nthreads;
  ADEM_FOR(nthreads, w->pp->n, particle_pair, w);
  ADEM_FOR(nthreads, w->pw->n, wall_pair, w);
  mesh_pairs(w);
  ADEM_FOR(nthreads, w->p->n, sum_particle, w);
}
