/* Single collisions in bulk (notes section 7). Each collision is a world of one or two spheres
 * built through the public API and stepped by the engine itself, so what is measured is what a
 * run computes. */
#include "collide.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "contact/jkr.h"
#include "log.h"
#include "world.h"

#ifdef ADEM_HAVE_OPENMP
#include <omp.h>
#endif

adem_collision_spec adem_default_collision_spec(void) {
  adem_collision_spec s;
  memset(&s, 0, sizeof s);
  s.kind = ADEM_COLLISION_PAIR;
  s.radius = 1e-6;
  s.size_ratio = 1.0;
  s.density = 1000.0;
  s.young = 1e9;
  s.poisson = 0.3;
  s.restitution = 1.0;
  s.friction = 0.0;
  s.stiffness_factor = 1.0;
  s.speed = 1.0;
  s.angle = 0.5 * ADEM_PI;
  s.steps_per_tc = 200.0;
  s.max_periods = 2000.0;
  return s;
}

static double sin2_angle(const adem_collision_spec *s) {
  if (s->kind != ADEM_COLLISION_WALL) return 1.0;
  double sp = sin(s->angle);
  return sp * sp;
}

/* (1 + b^3)/((1 + b^2) b) of the text's Ad (H section 5.1); 1 for equal spheres. */
static double ad_size_factor(const adem_collision_spec *s) {
  if (s->kind == ADEM_COLLISION_WALL) return 1.0;
  double b = s->size_ratio;
  return (1.0 + b * b * b) / ((1.0 + b * b) * b);
}

double adem_collide_lambda(const adem_collision_spec *s) {
  return s->young / (s->density * s->speed * s->speed * sin2_angle(s));
}

double adem_collide_ad(const adem_collision_spec *s) {
  return 3.0 * s->surface_energy / (s->density * s->speed * s->speed * sin2_angle(s) * s->radius) *
         ad_size_factor(s);
}

void adem_collide_set_lambda(adem_collision_spec *s, double lambda) {
  s->young = lambda * s->density * s->speed * s->speed * sin2_angle(s);
}

void adem_collide_set_ad(adem_collision_spec *s, double ad) {
  s->surface_energy =
      ad * s->density * s->speed * s->speed * sin2_angle(s) * s->radius / (3.0 * ad_size_factor(s));
}

double adem_collide_hertz_time(double mstar, double R, double E, double v) {
  return 2.86827 * pow(mstar * mstar / (R * E * E * v), 0.2);
}

static double sphere_mass(double rho, double r) { return rho * (4.0 / 3.0) * ADEM_PI * r * r * r; }

adem_collision_params adem_collide_params(const adem_collision_spec *s) {
  adem_collision_params p;
  memset(&p, 0, sizeof p);
  double ri = s->radius, mi = sphere_mass(s->density, ri);
  if (s->kind == ADEM_COLLISION_WALL) {
    p.R = ri;
    p.mstar = mi;
  } else {
    double rj = ri * s->size_ratio, mj = sphere_mass(s->density, rj);
    p.R = ri * rj / (ri + rj);
    p.mstar = mi * mj / (mi + mj);
  }
  double f = s->stiffness_factor;
  p.E_mod = f * s->young;                                                 /* H24 */
  p.gamma_mod = s->keep_gamma ? s->surface_energy : s->surface_energy * pow(f, 0.4); /* H24 */
  p.v_n = s->speed * sqrt(sin2_angle(s));
  double v_in = p.v_n;
  if (p.gamma_mod > 0.0) {
    double a0 = adem_jkr_a0(p.gamma_mod, p.R, p.E_mod);
    p.u_min = adem_jkr_energy(p.gamma_mod, p.R, p.E_mod, a0);
    /* Adhesion speeds the spheres up in contact: the step follows the fastest approach. */
    v_in = sqrt(p.v_n * p.v_n - 2.0 * p.u_min / p.mstar);
    /* Stiffness at equilibrium dF/ddelta = 6 E a0 / 5 (from H8-H10 at a = a0). */
    p.t_osc = 2.0 * ADEM_PI * sqrt(p.mstar / (1.2 * p.E_mod * a0));
  }
  p.t_c = adem_collide_hertz_time(p.mstar, p.R, p.E_mod, v_in);
  return p;
}

/* Contact energy of the normal motion relative to the state where the contact forms (delta = 0):
 * kinetic energy of the normal relative motion plus the JKR energy. Damping only lowers it and
 * the simplified contact breaks at delta = 0, so once it is below zero the spheres cannot part. */
static double normal_energy(const adem_collision_params *p, double delta, double v_n) {
  double a = adem_jkr_contact_radius(p->gamma_mod, p->R, p->E_mod, delta); /* H10 */
  return 0.5 * p->mstar * v_n * v_n + adem_jkr_energy(p->gamma_mod, p->R, p->E_mod, a);
}

static adem_collision_result failed(adem_collision_result r, adem_status st, const char *msg) {
  r.status = st;
  snprintf(r.message, sizeof r.message, "%.255s", msg);
  return r;
}

/* Builds the world of one collision: materials with the requested effective values, the spheres
 * just apart (a step and a half of travel), and the wall for a wall impact. */
static adem_status build_world(const adem_collision_spec *s, const adem_collision_params *p,
                               double dt, adem_world *w, adem_error *err) {
  adem_world_set_threads(w, 1);
  adem_world_set_gravity(w, v3_zero());
  adem_world_use_brute_force(w, 1);
  adem_world_set_max_overlap_ratio(w, 1.0); /* soft spheres overlap a lot; H makes no limit */
  adem_world_set_dt(w, dt);
  bool wall = s->kind == ADEM_COLLISION_WALL;
  double nu = s->poisson;
  /* 1/E* = sum (1 - nu^2)/E_k (H2): a rigid wall leaves all compliance to the sphere. */
  double E_sphere = (wall ? 1.0 : 2.0) * (1.0 - nu * nu) * s->young;
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "sphere");
  m.density = s->density;
  m.poisson = nu;
  m.restitution = s->restitution;
  m.friction = s->friction;
  m.surface_energy = s->surface_energy;
  m.young = s->keep_gamma ? E_sphere * s->stiffness_factor : E_sphere;
  m.stiffness_factor = s->keep_gamma ? 1.0 : s->stiffness_factor;
  int ms = adem_world_add_material(w, &m, err);
  if (ms < 0) return err->status;
  int mw = ms;
  if (wall) {
    /* Same f on the wall so that the pair's surface energy (geometric mean) is gamma f^(2/5). */
    snprintf(m.name, sizeof m.name, "wall");
    m.rigid = 1;
    mw = adem_world_add_material(w, &m, err);
    if (mw < 0) return err->status;
  }
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = ms;
  it.material_b = mw;
  it.restitution = s->restitution;
  it.friction = s->friction;
  it.normal = s->surface_energy > 0.0 ? ADEM_NORMAL_JKR : ADEM_NORMAL_HERTZ;
  if (adem_world_set_interaction(w, &it, err) < 0) return err->status;

  double gap = 1.5 * p->v_n * dt;
  double ri = s->radius;
  adem_particle_def a = adem_default_particle_def();
  a.material = ms;
  a.radius = ri;
  if (wall) {
    adem_plane_def pl = adem_default_plane_def();
    snprintf(pl.name, sizeof pl.name, "wall");
    pl.material = mw;
    if (adem_world_add_plane(w, &pl, err) < 0) return err->status;
    a.position = v3(0.0, 0.0, ri + gap);
    a.velocity = v3(s->speed * cos(s->angle), 0.0, -p->v_n);
    if (adem_world_add_particle(w, &a, err) < 0) return err->status;
  } else {
    double rj = ri * s->size_ratio;
    double mi = sphere_mass(s->density, ri), mj = sphere_mass(s->density, rj);
    /* Centre-of-mass frame: zero total momentum. */
    a.position = v3(-ri - 0.5 * gap, 0.0, 0.0);
    a.velocity = v3(s->speed * mj / (mi + mj), 0.0, 0.0);
    if (adem_world_add_particle(w, &a, err) < 0) return err->status;
    adem_particle_def b = a;
    b.radius = rj;
    b.position = v3(rj + 0.5 * gap, 0.0, 0.0);
    b.velocity = v3(-s->speed * mi / (mi + mj), 0.0, 0.0);
    if (adem_world_add_particle(w, &b, err) < 0) return err->status;
  }
  return adem_world_prepare(w, err);
}

/* Overlap, normal approach speed and normal contact force of the current state. Particles may be
 * reordered by the neighbour search, so they are found by id. */
typedef struct normal_state {
  double delta, v_n, f_n;
} normal_state;

static normal_state read_normal(const adem_world *w, bool wall) {
  const adem_particles *pp = &w->p;
  normal_state s;
  if (wall) {
    s.delta = pp->radius[0] - pp->pos[0].z;
    s.v_n = -pp->vel[0].z;
    s.f_n = pp->force[0].z; /* force on the sphere = F_N along the wall normal */
    return s;
  }
  size_t i = pp->id[0] == 0 ? 0 : 1, j = 1 - i;
  adem_vec3 d = v3_sub(pp->pos[j], pp->pos[i]);
  double dist = v3_norm(d);
  adem_vec3 n = v3_scale(d, 1.0 / dist);
  s.delta = pp->radius[i] + pp->radius[j] - dist;
  s.v_n = v3_dot(v3_sub(pp->vel[i], pp->vel[j]), n);
  s.f_n = -v3_dot(pp->force[i], n); /* force on i = -F_N n */
  return s;
}

static double kinetic_energy(const adem_world *w) {
  const adem_particles *p = &w->p;
  double e = 0.0;
  for (size_t i = 0; i < p->n; ++i)
    e += 0.5 * v3_norm2(p->vel[i]) / p->inv_mass[i] + 0.5 * v3_norm2(p->omega[i]) / p->inv_inertia[i];
  return e;
}

adem_collision_result adem_collide(const adem_collision_spec *s) {
  adem_collision_result r;
  memset(&r, 0, sizeof r);
  bool wall = s->kind == ADEM_COLLISION_WALL;
  if (!(s->radius > 0.0) || !(s->density > 0.0) || !(s->young > 0.0) || !(s->speed > 0.0) ||
      !(s->steps_per_tc >= 10.0) || !(s->max_periods > 0.0) || !(s->surface_energy >= 0.0) ||
      (!wall && !(s->size_ratio > 0.0)))
    return failed(r, ADEM_ERR_INPUT,
                  "radius, density, modulus, speed and size ratio must be > 0, surface energy >= "
                  "0, steps per collision time >= 10");
  if (wall && !(sin(s->angle) > 0.0))
    return failed(r, ADEM_ERR_INPUT, "the impact angle must be in (0, 180) degrees");
  adem_collision_params p = adem_collide_params(s);
  bool adhesive = p.gamma_mod > 0.0;
  double t_ref = adhesive ? fmin(p.t_c, 0.5 * p.t_osc) : p.t_c;
  double dt = t_ref / s->steps_per_tc;
  r.t_c = p.t_c;
  r.dt = dt;
  r.v_n_in = p.v_n;

  adem_world *w = adem_world_create();
  if (!w) return failed(r, ADEM_ERR_NOMEM, "out of memory");
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_status st = build_world(s, &p, dt, w, &err);
  if (st) {
    adem_world_free(w);
    return failed(r, st, err.message);
  }
  r.ke_in = kinetic_energy(w);

  /* Energy below which a capture is sure: a margin well above the step's energy error. */
  double stuck_below = -1e-3 * fabs(p.u_min);
  double t_limit = s->max_periods * fmax(p.t_c, p.t_osc);
  adem_particles *pa = &w->p;
  size_t np = pa->n;
  adem_vec3 x0[2], f0[2], t0[2];
  normal_state prev = read_normal(w, wall);
  bool touched = false, done = false;
  double t_in = 0.0;
  uint64_t max_steps = (uint64_t)(t_limit / dt) + (uint64_t)(20.0 * s->steps_per_tc) + 100;
  for (uint64_t k = 0; k < max_steps && !done; ++k) {
    for (size_t i = 0; i < np; ++i) {
      x0[pa->id[i]] = pa->pos[i];
      f0[pa->id[i]] = pa->force[i];
      t0[pa->id[i]] = pa->torque[i];
    }
    st = adem_world_step(w, 1, &err);
    if (st) break;
    r.steps++;
    /* Work of the step, trapezoid rule: with velocity Verlet its sum equals the change of kinetic
     * energy up to terms in F^2 that cancel between a force-free start and end. */
    double h = 0.5 * dt;
    for (size_t i = 0; i < np; ++i) {
      uint64_t id = pa->id[i];
      adem_vec3 dx = v3_sub(pa->pos[i], x0[id]);
      adem_vec3 om_half = v3_axpy(pa->omega[i], -h * pa->inv_inertia[i], pa->torque[i]);
      r.work += 0.5 * v3_dot(v3_add(f0[id], pa->force[i]), dx) +
                0.5 * dt * v3_dot(v3_add(t0[id], pa->torque[i]), om_half);
    }
    double t = adem_world_time(w);
    normal_state cur = read_normal(w, wall);
    if (s->sample) s->sample(t, cur.delta, cur.v_n, cur.f_n, s->sample_user);
    if (!touched && cur.delta > 0.0) {
      touched = true;
      t_in = t - dt * cur.delta / (cur.delta - prev.delta); /* where the overlap crossed 0 */
    }
    if (touched) {
      r.max_overlap = fmax(r.max_overlap, cur.delta);
      if (cur.delta <= 0.0) { /* separated: no force acts any more */
        double t_out = t - dt * cur.delta / (cur.delta - prev.delta);
        r.duration = t_out - t_in;
        r.v_n_out = -cur.v_n;
        done = true;
      } else if (adhesive && normal_energy(&p, cur.delta, cur.v_n) < stuck_below) {
        r.stuck = true;
        r.duration = t - t_in;
        done = true;
      } else if (t - t_in > t_limit) {
        r.stuck = r.undecided = true;
        r.duration = t - t_in;
        done = true;
      }
    }
    prev = cur;
  }
  if (st) {
    normal_state now = read_normal(w, wall);
    double rmin = wall ? s->radius : s->radius * fmin(1.0, s->size_ratio);
    if (st == ADEM_ERR_RUNTIME && !(now.delta < 0.99 * rmin))
      snprintf(err.message, sizeof err.message,
               "the overlap reached the radius of the sphere at t = %.4g s: it is too soft for "
               "this impact (E_mod/(rho v_n^2) = %.3g), where the contact laws do not apply",
               adem_world_time(w), p.E_mod / (s->density * p.v_n * p.v_n));
    adem_world_free(w);
    return failed(r, st, err.message);
  }
  if (!done) {
    adem_world_free(w);
    return failed(r, ADEM_ERR_RUNTIME, "the spheres never touched");
  }
  r.t_touch = t_in;
  r.e_eff = r.stuck ? 0.0 : r.v_n_out / r.v_n_in;
  if (r.stuck) r.v_n_out = 0.0;
  if (wall) {
    r.v_t_out = hypot(pa->vel[0].x, pa->vel[0].y);
    r.omega_out = v3_norm(pa->omega[0]);
  }
  r.ke_out = kinetic_energy(w);
  adem_world_free(w);
  return r;
}

void adem_collide_many(const adem_collision_spec *specs, adem_collision_result *out, size_t n,
                       int nthreads) {
  if (nthreads < 1) nthreads = 1;
  long long count = (long long)n;
#ifdef ADEM_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
#endif
  for (long long k = 0; k < count; ++k) out[k] = adem_collide(&specs[k]);
  (void)nthreads;
}

adem_status adem_collide_threshold(const adem_collision_spec *base, adem_collision_param_fn *set,
                                   void *user, double lo, double hi, double rel_tol, int nthreads,
                                   double *x_crit, adem_error *err) {
  enum { INNER = 3 }; /* fixed, so the result does not depend on the thread count */
  adem_collision_spec sp[INNER + 2];
  adem_collision_result res[INNER + 2];
  double x[INNER + 2] = {lo, hi};
  for (int k = 0; k < 2; ++k) {
    sp[k] = *base;
    set(&sp[k], x[k], user);
  }
  adem_collide_many(sp, res, 2, nthreads);
  for (int k = 0; k < 2; ++k)
    if (res[k].status)
      return adem_error_set(err, res[k].status, "collision at x = %g: %s", x[k], res[k].message);
  if (res[0].stuck == res[1].stuck)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "no threshold in [%g, %g]: the spheres %s at both ends", lo, hi,
                          res[0].stuck ? "stick" : "rebound");
  bool stuck_lo = res[0].stuck;
  double a = log(lo), b = log(hi);
  while (b - a > rel_tol) {
    for (int k = 0; k < INNER; ++k) {
      x[k] = exp(a + (b - a) * (k + 1) / (INNER + 1));
      sp[k] = *base;
      set(&sp[k], x[k], user);
    }
    adem_collide_many(sp, res, INNER, nthreads);
    double na = a, nb = b;
    for (int k = 0; k < INNER; ++k) {
      if (res[k].status)
        return adem_error_set(err, res[k].status, "collision at x = %g: %s", x[k], res[k].message);
      if (res[k].stuck == stuck_lo) na = log(x[k]);
    }
    /* The first point with the other outcome above the last with lo's outcome closes it. */
    for (int k = INNER - 1; k >= 0; --k)
      if (res[k].stuck != stuck_lo && log(x[k]) > na) nb = log(x[k]);
    a = na;
    b = nb;
  }
  *x_crit = exp(0.5 * (a + b));
  return ADEM_OK;
}

adem_jkr_pair_summary adem_jkr_pair_summarize(double E, double E_mod, double gamma,
                                              double gamma_mod, double R, double mstar,
                                              double v_ref) {
  adem_jkr_pair_summary s;
  s.R = R;
  s.mstar = mstar;
  s.E = E;
  s.E_mod = E_mod;
  s.gamma = gamma;
  s.gamma_mod = gamma_mod;
  s.a0 = adem_jkr_a0(gamma, R, E); /* H7 */
  s.a0_mod = adem_jkr_a0(gamma_mod, R, E_mod);
  s.delta_eq = s.a0 * s.a0 / (3.0 * R);
  s.delta_eq_mod = s.a0_mod * s.a0_mod / (3.0 * R);
  s.f_c = adem_jkr_critical_force(gamma, R);
  s.f_c_mod = adem_jkr_critical_force(gamma_mod, R);
  s.pull_off = 8.0 / 9.0 * s.f_c;
  s.pull_off_mod = 8.0 / 9.0 * s.f_c_mod;
  const double D = ADEM_TABOR_DMIN;
  s.tabor = cbrt(4.0 * R * gamma * gamma / (E * E * D * D * D)); /* H1 */
  s.t_c = adem_collide_hertz_time(mstar, R, E, v_ref);
  s.t_c_mod = adem_collide_hertz_time(mstar, R, E_mod, v_ref);
  s.dt = s.t_c / 50.0; /* about 50 steps a collision (Silbert et al. 2001, used by H) */
  s.dt_mod = s.t_c_mod / 50.0;
  s.speedup = pow(E / E_mod, 0.4);
  s.f_ext_max = ADEM_PULLOFF_SAFETY * s.pull_off_mod;
  return s;
}
