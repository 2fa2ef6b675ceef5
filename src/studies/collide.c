/* Single collisions in bulk (notes section 7). Each collision is a world of one or two spheres
 * built through the public API and stepped by the engine itself, so what is measured is what a
 * run computes. */
#include "adem/case.h"
#include "adem/laws.h"
#include "adem/studies.h"
#include "adem/world.h"
#include "adem/vec3.h"
#include "embedded.h"

#include <math.h>
#include <stdio.h>
#include <string.h>


#ifdef ADEM_HAVE_OPENMP
#include <omp.h>
#endif

adem_collide_spec adem_default_collide_spec(void) {
  adem_collide_spec s;
  memset(&s, 0, sizeof s);
  s.kind = ADEM_COLLIDE_PAIR;
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
  s.dtk_modification = true;
  s.rest_periods = 3.0;
  s.max_roll_periods = 400.0;
  s.tangential = ADEM_TANGENTIAL_INCREMENTAL;
  s.scheme = ADEM_CONTACTS_SECOND_ORDER;
  s.approach_steps = 1.5;
  s.normal_law = -1;
  s.rolling_law = -1;
  return s;
}

adem_status adem_collide_psl_quartz(adem_collide_spec *s, adem_error *err) {
  adem_case *c = NULL;
  adem_status st = adem_case_load_string(adem_case_haervig_psl_quartz_yaml,
                                         "cases/haervig/psl-quartz.yaml", NULL, 0, &c, err);
  if (st) return st;
  const adem_world *w = c->world;
  int k = adem_world_find_material(w, "psl");
  double r = 0.0;
  if (k < 0 || adem_world_particle_count(w) != 1 ||
      adem_world_get_particles(w, ADEM_FIELD_RADIUS, &r, 1, NULL)) {
    adem_case_free(c);
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "cases/haervig/psl-quartz.yaml must hold material `psl` and one sphere");
  }
  const adem_material_def *m = adem_world_material(w, k);
  s->kind = ADEM_COLLIDE_WALL;
  s->radius = r;
  s->density = m->density;
  s->poisson = m->poisson;
  s->young = m->young / (1.0 - m->poisson * m->poisson); /* E* of a sphere on a rigid wall (H2) */
  s->restitution = m->restitution;
  s->surface_energy = m->param[ADEM_PARAM_SURFACE_ENERGY];
  adem_case_free(c);
  return ADEM_OK;
}

const char *adem_collide_outcome_name(adem_collide_outcome o) {
  switch (o) {
    case ADEM_OUTCOME_REBOUND: return "rebound";
    case ADEM_OUTCOME_CAPTURED: return "captured";
    case ADEM_OUTCOME_ROLLING: return "rolling";
    case ADEM_OUTCOME_STUCK: return "stuck";
  }
  return "?";
}

static double sin2_angle(const adem_collide_spec *s) {
  if (s->kind != ADEM_COLLIDE_WALL) return 1.0;
  double sp = sin(s->angle);
  return sp * sp;
}

/* (1 + b^3)/((1 + b^2) b) of the text's Ad (H section 5.1); 1 for equal spheres. */
static double ad_size_factor(const adem_collide_spec *s) {
  if (s->kind == ADEM_COLLIDE_WALL) return 1.0;
  double b = s->size_ratio;
  return (1.0 + b * b * b) / ((1.0 + b * b) * b);
}

double adem_collide_lambda(const adem_collide_spec *s) {
  return s->young / (s->density * s->speed * s->speed * sin2_angle(s));
}

double adem_collide_ad(const adem_collide_spec *s) {
  return 3.0 * s->surface_energy / (s->density * s->speed * s->speed * sin2_angle(s) * s->radius) *
         ad_size_factor(s);
}

void adem_collide_set_lambda(adem_collide_spec *s, double lambda) {
  s->young = lambda * s->density * s->speed * s->speed * sin2_angle(s);
}

void adem_collide_set_ad(adem_collide_spec *s, double ad) {
  s->surface_energy =
      ad * s->density * s->speed * s->speed * sin2_angle(s) * s->radius / (3.0 * ad_size_factor(s));
}

double adem_collide_yield_force(const adem_collide_spec *s) {
  if (s->kind != ADEM_COLLIDE_WALL || !s->dtk || !(s->surface_energy > 0.0)) return 0.0;
  double r = s->radius;
  double f_c = adem_law_jkr_critical_force(s->surface_energy, r);
  double xi_crit = adem_law_jkr_a0(s->surface_energy, r, s->young) / 12.0 * s->hysteresis; /* H18 */
  return 4.0 * f_c * xi_crit / r;                                                          /* k_r xi_crit / R at a = a0 (H20-H21, notes section 4) */
}

double adem_collide_force(const adem_collide_spec *s) {
  return s->force_ext + s->force_hat * adem_collide_yield_force(s);
}


static double sphere_mass(double rho, double r) { return rho * (4.0 / 3.0) * ADEM_PI * r * r * r; }

adem_collide_params adem_collide_derive(const adem_collide_spec *s) {
  adem_collide_params p;
  memset(&p, 0, sizeof p);
  double ri = s->radius, mi = sphere_mass(s->density, ri);
  if (s->kind == ADEM_COLLIDE_WALL) {
    p.R = ri;
    p.mstar = mi;
  } else {
    double rj = ri * s->size_ratio, mj = sphere_mass(s->density, rj);
    p.R = ri * rj / (ri + rj);
    p.mstar = mi * mj / (mi + mj);
  }
  double f = s->stiffness_factor;
  p.E_mod = f * s->young;                                                            /* H24 */
  p.gamma_mod = s->keep_gamma ? s->surface_energy : s->surface_energy * pow(f, 0.4); /* H24 */
  p.v_n = s->speed * sqrt(sin2_angle(s));
  double v_in = p.v_n;
  if (p.gamma_mod > 0.0) {
    double a0 = adem_law_jkr_a0(p.gamma_mod, p.R, p.E_mod);
    p.u_min = adem_law_jkr_energy(p.gamma_mod, p.R, p.E_mod, a0);
    /* Adhesion speeds the spheres up in contact: the step follows the fastest approach. */
    v_in = sqrt(p.v_n * p.v_n - 2.0 * p.u_min / p.mstar);
    /* Stiffness at equilibrium dF/ddelta = 6 E a0 / 5 (from H8-H10 at a = a0). */
    p.t_osc = 2.0 * ADEM_PI * sqrt(p.mstar / (1.2 * p.E_mod * a0));
  }
  p.t_c = adem_hertz_collision_time(p.mstar, p.R, p.E_mod, v_in);
  return p;
}

/* Contact energy of the normal motion relative to the state where the contact forms (delta = 0):
 * kinetic energy of the normal relative motion plus the JKR energy. Damping only lowers it and
 * the simplified contact breaks at delta = 0, so once it is below zero the spheres cannot part. */
static double normal_energy(const adem_collide_params *p, double delta, double v_n) {
  double a = adem_law_jkr_contact_radius(p->gamma_mod, p->R, p->E_mod, delta); /* H10 */
  return 0.5 * p->mstar * v_n * v_n + adem_law_jkr_energy(p->gamma_mod, p->R, p->E_mod, a);
}

static adem_collide_result failed(adem_collide_result r, adem_status st, const char *msg) {
  r.status = st;
  snprintf(r.message, sizeof r.message, "%.255s", msg);
  return r;
}

/* Builds the world of one collision: materials with the requested effective values, the spheres
 * just apart (a step and a half of travel), and the wall for a wall impact. */
static adem_status build_world(const adem_collide_spec *s, const adem_collide_params *p,
                               double dt, adem_world *w, adem_error *err) {
  adem_world_set_threads(w, 1);
  adem_world_set_gravity(w, v3_zero());
  adem_world_set_neighbor_search(w, ADEM_SEARCH_ALL_PAIRS);
  adem_world_set_max_overlap_ratio(w, 1.0); /* soft spheres overlap a lot; H makes no limit */
  adem_world_set_dt(w, dt);
  adem_world_set_contact_scheme(w, s->scheme);
  bool wall = s->kind == ADEM_COLLIDE_WALL;
  double nu = s->poisson;
  /* 1/E* = sum (1 - nu^2)/E_k (H2): a rigid wall leaves all compliance to the sphere. */
  double E_sphere = (wall ? 1.0 : 2.0) * (1.0 - nu * nu) * s->young;
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "sphere");
  m.density = s->density;
  m.poisson = nu;
  m.restitution = s->restitution;
  m.friction = s->friction;
  m.param[ADEM_PARAM_SURFACE_ENERGY] = s->surface_energy;
  m.param[ADEM_PARAM_ADHESION_HYSTERESIS] = s->hysteresis; /* on the wall too: the pair takes the mean */
  m.young = s->keep_gamma ? E_sphere * s->stiffness_factor : E_sphere;
  m.stiffness_factor = s->keep_gamma ? 1.0 : s->stiffness_factor;
  int ms = 0, mw = 0;
  adem_status st = adem_world_add_material(w, &m, &ms, err);
  if (st) return st;
  mw = ms;
  if (wall) {
    /* Same f on the wall so that the pair's surface energy (geometric mean) is gamma f^(2/5). */
    snprintf(m.name, sizeof m.name, "wall");
    m.rigid = 1;
    if ((st = adem_world_add_material(w, &m, &mw, err))) return st;
  }
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = ms;
  it.material_b = mw;
  it.restitution = s->restitution;
  it.friction = s->friction;
  it.normal = s->normal_law >= 0        ? (adem_normal_model)s->normal_law
              : s->surface_energy > 0.0 ? ADEM_NORMAL_JKR
                                        : ADEM_NORMAL_HERTZ;
  it.rolling = !s->dtk               ? ADEM_ROLLING_NONE
               : s->rolling_law >= 0 ? (adem_rolling_model)s->rolling_law
                                     : ADEM_ROLLING_DTK;
  it.tangential = s->tangential;
  it.dtk_rolling_modification = s->dtk_modification ? 1 : 0;
  if ((st = adem_world_set_interaction(w, &it, err))) return st;

  double gap = s->approach_steps * p->v_n * dt;
  double ri = s->radius;
  adem_particle_def a = adem_default_particle_def();
  a.material = ms;
  a.radius = ri;
  if (wall) {
    adem_plane_def pl = adem_default_plane_def();
    snprintf(pl.name, sizeof pl.name, "wall");
    pl.material = mw;
    if ((st = adem_world_add_plane(w, &pl, NULL, err))) return st;
    /* F_ext through the centre along the wall, in the direction of the tangential velocity */
    double force = adem_collide_force(s);
    if (force != 0.0 && (st = adem_world_add_group(w, "pushed", v3(force, 0.0, 0.0), &a.group, err)))
      return st;
    if (s->at_rest) {
      /* JKR equilibrium: a = a0, delta = a0^2/(3R) (notes section 2) */
      double a0 = adem_law_jkr_a0(p->gamma_mod, p->R, p->E_mod);
      a.position = v3(0.0, 0.0, ri - a0 * a0 / (3.0 * p->R));
    } else {
      a.position = v3(0.0, 0.0, ri + gap);
      a.velocity = v3(s->speed * cos(s->angle), 0.0, -p->v_n);
    }
    if ((st = adem_world_add_particle(w, &a, NULL, err))) return st;
    /* a rolling sphere may travel far along the wall */
    adem_world_set_domain(w, v3(-1e7 * ri, -1e7 * ri, -1e3 * ri), v3(1e7 * ri, 1e7 * ri, 1e7 * ri));
  } else {
    double rj = ri * s->size_ratio;
    double mi = sphere_mass(s->density, ri), mj = sphere_mass(s->density, rj);
    /* Centre-of-mass frame: zero total momentum. */
    a.position = v3(-ri - 0.5 * gap, 0.0, 0.0);
    a.velocity = v3(s->speed * mj / (mi + mj), 0.0, 0.0);
    if ((st = adem_world_add_particle(w, &a, NULL, err))) return st;
    adem_particle_def b = a;
    b.radius = rj;
    b.position = v3(rj + 0.5 * gap, 0.0, 0.0);
    b.velocity = v3(-s->speed * mi / (mi + mj), 0.0, 0.0);
    if ((st = adem_world_add_particle(w, &b, NULL, err))) return st;
  }
  return adem_world_prepare(w, err);
}

/* The state of the one or two spheres, read through the public API in order of id. */
typedef struct bodies {
  size_t n;
  adem_vec3 x[2], v[2], om[2], f[2], t[2], roll[2];
  double r[2], inv_m[2], inv_i[2];
} bodies;

static void read_vectors(const adem_world *w, adem_particle_field field, size_t n, adem_vec3 *out) {
  double buf[6];
  adem_world_get_particles(w, field, buf, 6, NULL);
  for (size_t k = 0; k < n; ++k) out[k] = v3(buf[3 * k], buf[3 * k + 1], buf[3 * k + 2]);
}

static void read_scalars(const adem_world *w, adem_particle_field field, size_t n, double *out) {
  double buf[2];
  adem_world_get_particles(w, field, buf, 2, NULL);
  for (size_t k = 0; k < n; ++k) out[k] = buf[k];
}

static void read_bodies(const adem_world *w, bodies *b) {
  b->n = adem_world_particle_count(w);
  read_vectors(w, ADEM_FIELD_POSITION, b->n, b->x);
  read_vectors(w, ADEM_FIELD_VELOCITY, b->n, b->v);
  read_vectors(w, ADEM_FIELD_ANGULAR_VELOCITY, b->n, b->om);
  read_vectors(w, ADEM_FIELD_FORCE, b->n, b->f);
  read_vectors(w, ADEM_FIELD_TORQUE, b->n, b->t);
  read_vectors(w, ADEM_FIELD_ROLLING_TORQUE, b->n, b->roll);
  read_scalars(w, ADEM_FIELD_RADIUS, b->n, b->r);
  read_scalars(w, ADEM_FIELD_INVERSE_MASS, b->n, b->inv_m);
  read_scalars(w, ADEM_FIELD_INVERSE_INERTIA, b->n, b->inv_i);
}

/* Overlap, normal approach speed and normal contact force of the current state. */
typedef struct normal_state {
  double delta, v_n, f_n;
} normal_state;

static normal_state read_normal(const bodies *b, bool wall) {
  normal_state s;
  if (wall) {
    s.delta = b->r[0] - b->x[0].z;
    s.v_n = -b->v[0].z;
    s.f_n = b->f[0].z; /* force on the sphere = F_N along the wall normal */
    return s;
  }
  adem_vec3 d = v3_sub(b->x[1], b->x[0]);
  double dist = v3_norm(d);
  adem_vec3 n = v3_scale(d, 1.0 / dist);
  s.delta = b->r[0] + b->r[1] - dist;
  s.v_n = v3_dot(v3_sub(b->v[0], b->v[1]), n);
  s.f_n = -v3_dot(b->f[0], n); /* force on i = -F_N n */
  return s;
}

static double kinetic_energy(const bodies *b) {
  double e = 0.0;
  for (size_t i = 0; i < b->n; ++i)
    e += 0.5 * v3_norm2(b->v[i]) / b->inv_m[i] + 0.5 * v3_norm2(b->om[i]) / b->inv_i[i];
  return e;
}

/* Work of the step from state a to state b, trapezoid rule: with velocity Verlet its sum equals
 * the change of kinetic energy up to terms in F^2 that cancel between a force-free start and end.
 * The rolling couples' share is summed apart (its sign says whether they ever add energy). */
static void step_work(const bodies *a, const bodies *b, double dt, double *work,
                      double *rolling_work) {
  double h = 0.5 * dt;
  for (size_t i = 0; i < b->n; ++i) {
    adem_vec3 dx = v3_sub(b->x[i], a->x[i]);
    adem_vec3 om_half = v3_axpy(b->om[i], -h * b->inv_i[i], b->t[i]);
    *work += 0.5 * v3_dot(v3_add(a->f[i], b->f[i]), dx) +
             0.5 * dt * v3_dot(v3_add(a->t[i], b->t[i]), om_half);
    *rolling_work += 0.5 * dt * v3_dot(v3_add(a->roll[i], b->roll[i]), om_half);
  }
}

/* |xi| of the wall contact (0 when it does not touch). */
static double wall_rolling_distance(const adem_world *w) {
  adem_contact_info c;
  if (adem_world_contacts(w, &c, 1) == 0) return 0.0;
  return v3_norm(c.rolling_history);
}

/* Scales of the DTK contact at a = a0, with the F_C and a0 the contact uses (real ones under the
 * rolling modification, H section 3.2): xi_crit (H18), the period of rolling oscillations on the
 * spring k_r = 4 F_C (H20) about the contact point, (7/5) m r^2 theta'' = -k_r r theta with
 * xi = r theta, and v_rest = 2 omega_r xi_crit. An elastic oscillation confined to
 * |xi| <= xi_crit has an amplitude of at most xi_crit, hence a speed of at most omega_r xi_crit;
 * the factor 2 is a margin for the coupling with the tangential spring. */
typedef struct rolling_scales {
  double xi_crit, t_roll, v_rest;
} rolling_scales;

static rolling_scales rolling_scales_of(const adem_collide_spec *s,
                                        const adem_collide_params *p) {
  /* with keep_gamma the world's real material is the softened one: (E_mod, gamma) */
  bool real = s->dtk_modification && !s->keep_gamma;
  double g = real ? s->surface_energy : p->gamma_mod, E = real ? s->young : p->E_mod;
  double f_c = adem_law_jkr_critical_force(g, p->R);
  rolling_scales rs;
  rs.xi_crit = adem_law_jkr_a0(g, p->R, E) / 12.0 * s->hysteresis; /* H18 */
  double omega = sqrt(4.0 * f_c / (1.4 * p->mstar * s->radius));
  rs.t_roll = 2.0 * ADEM_PI / omega;
  rs.v_rest = 2.0 * omega * rs.xi_crit;
  return rs;
}

static double along_wall(adem_vec3 a, adem_vec3 b) { return hypot(b.x - a.x, b.y - a.y); }

static const char *check_spec(const adem_collide_spec *s) {
  bool wall = s->kind == ADEM_COLLIDE_WALL;
  if (!(s->radius > 0.0) || !(s->density > 0.0) || !(s->young > 0.0) ||
      !(s->at_rest || s->speed > 0.0) || !(s->steps_per_tc >= 10.0) || !(s->max_periods > 0.0) ||
      !(s->surface_energy >= 0.0) || (!wall && !(s->size_ratio > 0.0)))
    return "radius, density, modulus, speed and size ratio must be > 0, surface energy >= 0, "
           "steps per collision time >= 10";
  if (wall && !(sin(s->angle) > 0.0)) return "the impact angle must be in (0, 180) degrees";
  if (!(s->approach_steps > 0.0) || !(s->dt >= 0.0)) return "the approach must take > 0 steps, the step be >= 0";
  if (s->dtk && !(s->surface_energy > 0.0))
    return "DTK rolling needs the JKR contact: a surface energy > 0";
  if (!(s->hysteresis >= 0.0)) return "the adhesion hysteresis must be >= 0";
  if (!wall && (s->force_ext != 0.0 || s->force_hat != 0.0 || s->at_rest))
    return "the external force and the start at rest are for wall impacts";
  if (!isfinite(s->force_ext) || !isfinite(s->force_hat) || s->force_ext < 0.0 ||
      s->force_hat < 0.0)
    return "the external force must be finite and >= 0 (it points along the tangential velocity)";
  if (s->force_ext != 0.0 && s->force_hat != 0.0)
    return "give the external force in N or as F_ext/F_yield, not both";
  if (s->force_hat != 0.0 && !(s->dtk && s->hysteresis > 0.0))
    return "F_ext/F_yield needs DTK rolling with a hysteresis > 0 (F_yield = 4 F_C xi_crit/R)";
  if (s->at_rest && !(s->surface_energy > 0.0))
    return "a start at rest needs the JKR equilibrium: a surface energy > 0";
  if (!(s->rest_periods > 0.0) || !(s->max_roll_periods >= s->rest_periods))
    return "the decision window must be > 0 and at most the longest rolling phase";
  return NULL;
}

adem_collide_result adem_collide(const adem_collide_spec *s) {
  adem_collide_result r;
  memset(&r, 0, sizeof r);
  r.t_rest = NAN;
  bool wall = s->kind == ADEM_COLLIDE_WALL;
  const char *bad = check_spec(s);
  if (bad) return failed(r, ADEM_ERR_INPUT, bad);
  adem_collide_params p = adem_collide_derive(s);
  bool adhesive = p.gamma_mod > 0.0;
  /* at rest only the oscillation about the equilibrium sets the step */
  double t_ref = s->at_rest ? 0.5 * p.t_osc : adhesive ? fmin(p.t_c, 0.5 * p.t_osc)
                                                       : p.t_c;
  double dt = s->dt > 0.0 ? s->dt : t_ref / s->steps_per_tc;
  r.t_c = p.t_c;
  r.dt = dt;
  r.v_n_in = s->at_rest ? 0.0 : p.v_n;
  r.force_ext = adem_collide_force(s);

  adem_world *w = adem_world_create();
  if (!w) return failed(r, ADEM_ERR_NOMEM, "out of memory");
  adem_error err;
  memset(&err, 0, sizeof err);
  adem_status st = build_world(s, &p, dt, w, &err);
  if (st) {
    adem_world_free(w);
    return failed(r, st, err.message);
  }
  bodies now, start;
  read_bodies(w, &now);
  r.ke_in = kinetic_energy(&now);

  /* Energy below which a capture is sure: a margin well above the step's energy error. */
  double stuck_below = -1e-3 * fabs(p.u_min);
  double t_limit = s->max_periods * fmax(p.t_c, p.t_osc);
  normal_state prev = read_normal(&now, wall);
  bool touched = s->at_rest, done = s->at_rest;
  double t_in = 0.0;
  adem_vec3 x_touch = now.x[0], x_sep = now.x[0];
  r.stuck = s->at_rest;
  uint64_t max_steps = (uint64_t)(t_limit / dt) + (uint64_t)(20.0 * s->steps_per_tc) + 100;
  for (uint64_t k = 0; k < max_steps && !done; ++k) {
    start = now;
    st = adem_world_step(w, 1, &err);
    if (st) break;
    r.steps++;
    read_bodies(w, &now);
    step_work(&start, &now, dt, &r.work, &r.rolling_work);
    double t = adem_world_time(w);
    normal_state cur = read_normal(&now, wall);
    if (s->sample) s->sample(t, cur.delta, cur.v_n, cur.f_n, s->sample_user);
    if (!touched && cur.delta > 0.0) {
      touched = true;
      t_in = t - dt * cur.delta / (cur.delta - prev.delta); /* where the overlap crossed 0 */
      x_touch = now.x[0];
    }
    if (wall && s->track)
      s->track(t, touched ? along_wall(x_touch, now.x[0]) : 0.0,
               hypot(now.v[0].x, now.v[0].y), wall_rolling_distance(w), s->track_user);
    if (touched) {
      r.max_overlap = fmax(r.max_overlap, cur.delta);
      if (cur.delta <= 0.0) { /* separated: no force acts after the next kick */
        double t_out = t - dt * cur.delta / (cur.delta - prev.delta);
        r.duration = t_out - t_in;
        /* the force of this pass (an adhesive contact's break correction) still acts in the next
         * opening half kick: take that step, then read the speed */
        start = now;
        st = adem_world_step(w, 1, &err);
        if (st) break;
        r.steps++;
        read_bodies(w, &now);
        step_work(&start, &now, dt, &r.work, &r.rolling_work);
        cur = read_normal(&now, wall);
        r.v_n_out = -cur.v_n;
        x_sep = now.x[0];
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

  /* Rolling phase (the rule is in collide.h). */
  r.outcome = r.stuck ? ADEM_OUTCOME_CAPTURED : ADEM_OUTCOME_REBOUND;
  if (!st && done && wall && s->dtk && r.stuck && !s->capture_only) {
    rolling_scales rs = rolling_scales_of(s, &p);
    r.xi_crit = rs.xi_crit;
    r.t_roll = rs.t_roll;
    double window = s->rest_periods * rs.t_roll;
    double t_end = adem_world_time(w) + s->max_roll_periods * rs.t_roll;
    double settled_below = p.u_min + 0.01 * fabs(p.u_min);
    double calm_since = NAN, sat_since = NAN, v_sat_start = 0.0;
    adem_vec3 x_calm = now.x[0];
    bool decided = false, sat = false;
    while (!decided) {
      start = now;
      st = adem_world_step(w, 1, &err);
      if (st) break;
      r.steps++;
      read_bodies(w, &now);
      step_work(&start, &now, dt, &r.work, &r.rolling_work);
      double t = adem_world_time(w);
      normal_state cur = read_normal(&now, wall);
      if (s->sample) s->sample(t, cur.delta, cur.v_n, cur.f_n, s->sample_user);
      r.max_overlap = fmax(r.max_overlap, cur.delta);
      if (cur.delta <= 0.0) { /* cannot happen after a sure capture; reported if it does */
        r.stuck = r.undecided = false;
        r.outcome = ADEM_OUTCOME_REBOUND;
        r.v_n_out = -cur.v_n;
        r.duration = t - t_in;
        x_sep = now.x[0];
        break;
      }
      double xi = wall_rolling_distance(w);
      double v = hypot(now.v[0].x, now.v[0].y);
      if (s->track) s->track(t, along_wall(x_touch, now.x[0]), v, xi, s->track_user);
      sat = xi >= rs.xi_crit * (1.0 - 1e-9);
      bool settled = normal_energy(&p, cur.delta, cur.v_n) <= settled_below;
      /* stuck: elastic rolling spring and a slow centre for a whole window */
      if (!sat && v < rs.v_rest) {
        if (isnan(calm_since)) {
          calm_since = t;
          x_calm = now.x[0];
        } else if (t - calm_since >= window) {
          r.outcome = ADEM_OUTCOME_STUCK;
          r.t_rest = calm_since - t_in;
          r.roll_distance = along_wall(x_touch, x_calm);
          decided = true;
        }
      } else {
        calm_since = NAN;
      }
      /* rolling: saturated torque, settled normal motion, speed not decaying over a window */
      if (sat && settled) {
        if (isnan(sat_since)) {
          sat_since = t;
          v_sat_start = v;
        } else if (t - sat_since >= window) {
          if (v >= v_sat_start) {
            r.outcome = ADEM_OUTCOME_ROLLING;
            decided = true;
          } else { /* decelerating: watch on */
            sat_since = t;
            v_sat_start = v;
          }
        }
      } else {
        sat_since = NAN;
      }
      if (!decided && t >= t_end) {
        r.undecided = true;
        r.outcome = sat ? ADEM_OUTCOME_ROLLING : ADEM_OUTCOME_STUCK;
        if (!sat) {
          r.t_rest = (isnan(calm_since) ? t : calm_since) - t_in;
          r.roll_distance = along_wall(x_touch, isnan(calm_since) ? now.x[0] : x_calm);
        }
        decided = true;
      }
    }
    if (!st) r.duration = adem_world_time(w) - t_in;
  }
  if (st) {
    read_bodies(w, &now);
    normal_state last = read_normal(&now, wall);
    double rmin = wall ? s->radius : s->radius * fmin(1.0, s->size_ratio);
    if (st == ADEM_ERR_RUNTIME && !(last.delta < 0.99 * rmin))
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
  r.e_eff = r.stuck || s->at_rest ? 0.0 : r.v_n_out / r.v_n_in;
  if (r.stuck) r.v_n_out = 0.0;
  if (wall) {
    r.v_t_out = hypot(now.v[0].x, now.v[0].y);
    r.omega_out = v3_norm(now.om[0]);
    r.v_end = r.v_t_out;
    if (r.outcome == ADEM_OUTCOME_REBOUND) r.roll_distance = along_wall(x_touch, x_sep);
    else if (r.outcome != ADEM_OUTCOME_STUCK) r.roll_distance = along_wall(x_touch, now.x[0]);
  }
  r.ke_out = kinetic_energy(&now);
  adem_world_free(w);
  return r;
}

adem_status adem_collide_dtk_torque(const adem_collide_spec *spec, double xi, double *torque,
                                    adem_error *err) {
  adem_collide_spec s = *spec;
  s.at_rest = true;
  s.force_ext = s.force_hat = 0.0;
  const char *bad = check_spec(&s);
  if (!bad && !(s.kind == ADEM_COLLIDE_WALL && s.dtk))
    bad = "the DTK torque needs a wall spec with DTK";
  if (!bad && !(xi >= 0.0 && isfinite(xi))) bad = "the rolling distance must be finite and >= 0";
  if (bad) return adem_error_set(err, ADEM_ERR_INPUT, "%s", bad);
  adem_collide_params p = adem_collide_derive(&s);
  double dt = 0.5 * p.t_osc / s.steps_per_tc;
  adem_world *w = adem_world_create();
  if (!w) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_status st = build_world(&s, &p, dt, w, err);
  if (!st) {
    /* Rolling without slip along x at v = xi/dt: one advancing force pass adds xi to the empty
     * history. */
    double v = xi / dt;
    adem_vec3 vel = v3(v, 0.0, 0.0), spin = v3(0.0, v / s.radius, 0.0);
    st = adem_world_set_particle(w, 0, NULL, &vel, &spin, err);
    adem_world_clear_history(w);
    adem_world_advance_histories(w);
    bodies b;
    read_bodies(w, &b);
    *torque = v3_norm(b.roll[0]);
  }
  adem_world_free(w);
  return st;
}

adem_status adem_collide_normal_force(const adem_collide_spec *spec, double delta, double *force,
                                      adem_error *err) {
  adem_collide_spec s = *spec;
  s.at_rest = s.surface_energy > 0.0; /* built at the JKR equilibrium, then moved */
  s.dtk = false;
  s.force_ext = s.force_hat = 0.0;
  const char *bad = check_spec(&s);
  if (!bad && s.kind != ADEM_COLLIDE_WALL) bad = "the normal force needs a wall spec";
  if (!bad && !(delta >= 0.0 && delta < s.radius)) bad = "the overlap must be in [0, r)";
  if (bad) return adem_error_set(err, ADEM_ERR_INPUT, "%s", bad);
  adem_collide_params p = adem_collide_derive(&s);
  double t_ref = p.gamma_mod > 0.0 ? 0.5 * p.t_osc : p.t_c;
  adem_world *w = adem_world_create();
  if (!w) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_status st = build_world(&s, &p, t_ref / s.steps_per_tc, w, err);
  if (!st) {
    adem_vec3 x = v3(0.0, 0.0, s.radius - delta), zero = v3(0.0, 0.0, 0.0);
    st = adem_world_set_particle(w, 0, &x, &zero, &zero, err);
    adem_world_clear_history(w);
    adem_world_compute_forces(w);
    bodies b;
    read_bodies(w, &b);
    *force = b.f[0].z; /* the force on the sphere along the wall normal: F_N */
  }
  adem_world_free(w);
  return st;
}

void adem_collide_many(const adem_collide_spec *specs, adem_collide_result *out, size_t n,
                       int nthreads) {
  if (nthreads < 1) nthreads = 1;
  long long count = (long long)n;
#ifdef ADEM_HAVE_OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
#endif
  for (long long k = 0; k < count; ++k) out[k] = adem_collide(&specs[k]);
  (void)nthreads;
}

adem_status adem_collide_threshold(const adem_collide_spec *base, adem_collide_param_fn *set,
                                   void *user, double lo, double hi, double rel_tol, int nthreads,
                                   double *x_crit, adem_error *err) {
  return adem_collide_threshold_split(base, set, user, ADEM_SPLIT_CAPTURE, lo, hi, rel_tol,
                                      nthreads, x_crit, err);
}

static bool split_side(adem_collide_split split, const adem_collide_result *r) {
  return split == ADEM_SPLIT_REST ? r->outcome == ADEM_OUTCOME_STUCK : r->stuck;
}

adem_status adem_collide_threshold_split(const adem_collide_spec *base,
                                         adem_collide_param_fn *set, void *user,
                                         adem_collide_split split, double lo, double hi,
                                         double rel_tol, int nthreads, double *x_crit,
                                         adem_error *err) {
  enum { INNER = 3 }; /* fixed, so the result does not depend on the thread count */
  adem_collide_spec sp[INNER + 2];
  adem_collide_result res[INNER + 2];
  double x[INNER + 2] = {lo, hi};
  adem_collide_spec base_copy = *base;
  if (split == ADEM_SPLIT_CAPTURE) base_copy.capture_only = true;
  base = &base_copy;
  for (int k = 0; k < 2; ++k) {
    sp[k] = *base;
    set(&sp[k], x[k], user);
  }
  adem_collide_many(sp, res, 2, nthreads);
  for (int k = 0; k < 2; ++k)
    if (res[k].status)
      return adem_error_set(err, res[k].status, "collision at x = %g: %s", x[k], res[k].message);
  bool side_lo = split_side(split, &res[0]);
  if (side_lo == split_side(split, &res[1])) {
    const char *what = split == ADEM_SPLIT_REST ? (side_lo ? "come to rest" : "do not come to rest")
                                                : (side_lo ? "stick" : "rebound");
    return adem_error_set(err, ADEM_ERR_INPUT, "no threshold in [%g, %g]: the spheres %s at both "
                                               "ends",
                          lo, hi, what);
  }
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
      if (split_side(split, &res[k]) == side_lo) na = log(x[k]);
    }
    /* The first point with the other outcome above the last with lo's outcome closes it. */
    for (int k = INNER - 1; k >= 0; --k)
      if (split_side(split, &res[k]) != side_lo && log(x[k]) > na) nb = log(x[k]);
    a = na;
    b = nb;
  }
  *x_crit = exp(0.5 * (a + b));
  return ADEM_OK;
}

size_t adem_collide_fit_power(const double *x, const double *y, size_t n, double *c, double *k) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!(x[i] > 0.0 && y[i] > 0.0 && isfinite(x[i]) && isfinite(y[i]))) continue;
    double lx = log(x[i]), ly = log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
    ++m;
  }
  *c = *k = NAN;
  if (m < 2) return m;
  double den = (double)m * sxx - sx * sx;
  if (!(den > 0.0)) return m;
  *k = ((double)m * sxy - sx * sy) / den;
  *c = exp((sy - *k * sx) / (double)m);
  return m;
}
