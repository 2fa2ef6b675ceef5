/* The force pass: every candidate pair's force and torques into the pair lists (particle pairs
 * in chunks, touching ones of the common laws in block kernels: pair_blocks.c; planes; meshes),
 * each contact through contact_force.h, then the sums per particle in a fixed order
 * (force_sums.c). */
#include "contact_force.h"
#include "cylinder.h"
#include "force_sums.h"
#include "pair_blocks.h"
#include "parallel.h"

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
  adem_contact_history h = l->hist[adem_pairs_slot(l, k)];
  contact_result r = contact_force(it, laws_of(it), &g, &h, law_step(w), onset_pass(w) && !was);
  size_t s = adem_pairs_own_slot(l, k);
  if (!w->hold_history) l->hist[s] = h;
  store_pair(l, k, &g, &r, w->balance);
  note_overlap(w, l->res[s].overlap_ratio);
}

/* The same for a block's lane whose result is not finite (pair_blocks.c); particle_pair stays
 * static, so that the compiler may tailor its calls in the chunk loop. */
void adem_force_particle_pair(const adem_force_scope *w, size_t k, adem_vec3 d, double dist,
                              bool was, const adem_interaction *it) {
  particle_pair(w, k, d, dist, was, it);
}

/* The particle pairs of chunk c: those apart forgotten, the touching ones of an interaction with
 * a block kernel gathered into blocks, the rest one at a time. Each pair writes only its own
 * records, so the order in which they are done changes nothing. */
enum { PAIR_PREFETCH = 8 };          /* pairs ahead whose particles the chunk loop asks for */
enum { PAIR_PREFETCH_FROM = 16384 }; /* from this many particles on */

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
  /* the scope's numbers the loop reads, in locals: the flush is a call, after which the compiler
   * would load them again for every pair */
  const adem_periodic *periodic = w->periodic;
  const adem_materials *mat = w->mat;
  const adem_vec3 *predicted = w->predicted;
  const bool blocks = w->pair_blocks && !w->energy, onset = onset_pass(w);
  const double hp = w->second_order ? w->dt : 0.0;
  /* ask ahead only where the particles' numbers outgrow a core's L2 (~100 B each are read):
   * in a smaller system the requests only cost instructions */
  const bool ahead = p->n > PAIR_PREFETCH_FROM;
  for (size_t k = k0; k < k1; ++k) {
    size_t i = l->a[k], j = l->b[k];
    if (ahead && k + PAIR_PREFETCH < k1) { /* a partner a few pairs ahead */
      size_t jn = l->b[k + PAIR_PREFETCH], in = l->a[k + PAIR_PREFETCH];
      __builtin_prefetch(&p->pos[jn]);
      __builtin_prefetch(&p->pos[in]);
      __builtin_prefetch(&p->radius[jn]);
      __builtin_prefetch(&p->material[jn]);
      __builtin_prefetch(&p->inv_mass[jn]);
      __builtin_prefetch(&p->vel[jn]);
      __builtin_prefetch(&p->omega[jn]);
      __builtin_prefetch(&predicted[2 * jn]);
      __builtin_prefetch(&predicted[2 * jn + 1]);
      __builtin_prefetch(&l->hist[adem_pairs_slot(l, k + PAIR_PREFETCH)]);
    }
    adem_vec3 d = adem_periodic_min_image(periodic, v3_sub(p->pos[j], p->pos[i]));
    double rsum = p->radius[i] + p->radius[j];
    double dist2 = v3_norm2(d);
    bool was = l->touching[k];
    if (dist2 >= rsum * rsum && !was) { /* apart now and at the last pass */
      forget_opened(l, k, w->balance);
      continue;
    }
    double dist = sqrt(dist2);
    const adem_interaction *it = adem_materials_pair(mat, p->material[i], p->material[j]);
    if (it != last_it) { /* neighbours mostly share an interaction: look its kernel up once */
      last_it = it;
      last_kind = adem_pair_block_kind(it);
    }
    int kind = !blocks || !(rsum - dist > 0.0) ? -1 : last_kind;
    if (kind < 0) {
      particle_pair(w, k, d, dist, was, it);
      continue;
    }
    if (b.m > 0 && (b.it != it || b.kind != kind)) adem_pair_block_flush(w, &b);
    int q = b.m++;
    b.kind = kind;
    b.it = it;
    b.k[q] = k;
    pair_kinematics kin = particle_kinematics(p, predicted, i, j, d, dist, hp);
    pair_block_put(&b, q, &kin, &l->hist[adem_pairs_slot(l, k)]);
    b.fresh[q] = onset && !was ? 1.0 : 0.0;
    if (b.m == PAIR_BLOCK) adem_pair_block_flush(w, &b);
  }
  adem_pair_block_flush(w, &b);
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
    const adem_motion *mo = &w->walls->planes[l->b[k]].motion;
    adem_vec3 v_wall =
        adem_motion_point_velocity(mo, w->walls->time, v3_axpy(p->pos[i], ri, near.n));
    adem_vec3 spin_wall = motion_spin(mo);
    const adem_interaction *it = adem_materials_pair(w->mat, p->material[i], pl->material);
    contact_geometry g = wall_geometry(w, i, near.n, ri - dist, v_wall, spin_wall, it);
    if (g.delta <= 0.0) {
      open_pair(l, k, it, &g, onset_pass(w), dt, w->balance, w->break_forces);
      return;
    }
    adem_contact_history h = l->hist[k];
    contact_result r = contact_force(it, laws_of(it), &g, &h, law_step(w), onset_pass(w) && !was);
    if (!w->hold_history) l->hist[k] = h;
    store_pair(l, k, &g, &r, w->balance);
    note_overlap(w, l->res[k].overlap_ratio);
    if (w->balance) store_wall_power(l, k, &r, v_wall, spin_wall);
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
      const adem_motion *mo = &w->walls->mesh_motion[grp];
      adem_vec3 v_wall = adem_motion_point_velocity(mo, w->walls->time, c->point);
      adem_vec3 spin_wall = motion_spin(mo);
      const adem_interaction *it = adem_materials_pair(w->mat, p->material[i], m->groups[grp].material);
      contact_geometry g = wall_geometry(w, i, c->normal, c->overlap, v_wall, spin_wall, it);
      adem_contact_history h_held = h;
      contact_result r = contact_force(it, laws_of(it), &g, &h, law_step(w), onset_pass(w) && fresh);
      l->hist[k] = w->hold_history ? h_held : h;
      pm->key[k] = c->key;
      pm->owner[k] = c->tri;
      store_pair(l, k, &g, &r, w->balance); /* a wall's rj is 0: the ratio is delta / r_i */
      note_overlap(w, l->res[k].overlap_ratio);
      if (w->balance) store_wall_power(l, k, &r, v_wall, spin_wall);
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

/* Particle i's predicted velocity and spin, read by each of its particle pairs. */
static inline void predict_particle(const adem_force_scope *w, size_t i) {
  double hp = w->second_order ? w->dt : 0.0;
  w->predicted[2 * i] = predicted_velocity(w->p, i, hp);
  w->predicted[2 * i + 1] = predicted_spin(w->p, i, hp);
}

void adem_force_pass_run(const adem_force_scope *scope) {
  adem_force_scope s = *scope;
  int breaks = 0;
  s.break_forces = &breaks;
  const adem_force_scope *w = &s;
  int nthreads = w->nthreads;
  if (w->predicted) ADEM_FOR(nthreads, w->p->n, predict_particle, w);
  /* chunks of the pair list: a few per thread even on a small system (the static split gives
   * each thread whole chunks), at most 2048 pairs; their size changes no result */
  size_t chunk = w->pp->n / (8 * (size_t)(nthreads > 1 ? nthreads : 1));
  s.pair_chunk = chunk < 4 * PAIR_BLOCK ? 4 * PAIR_BLOCK : chunk > 2048 ? 2048
                                                                        : chunk;
  ADEM_FOR(nthreads, (w->pp->n + s.pair_chunk - 1) / s.pair_chunk, particle_pair_chunk, w);
  ADEM_FOR(nthreads, w->pw->n, wall_pair, w);
  mesh_pairs(w);
  adem_force_sums(w);
}
