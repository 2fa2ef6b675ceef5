/* The simulated world: materials, particles, walls, and the time stepper. */
#ifndef ADEM_WORLD_H
#define ADEM_WORLD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/base.h"
#include "adem/laws.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The world (opaque): made by adem_world_create, or by loading a case (adem/case.h). */
typedef struct adem_world adem_world;

/* A material. Walls have one too; a rigid wall material has E = infinity. */
typedef struct adem_material_def {
  char name[ADEM_NAME_MAX];
  double density;          /* kg/m^3 */
  double young;            /* E, Pa (the real one; see stiffness_factor) */
  double poisson;          /* nu, in (-1, 0.5) */
  double restitution;      /* e, in (0, 1] */
  double friction;         /* sliding friction coefficient mu_s */
  double stiffness_factor; /* f = E_mod/E in (0, 1]; H24 */
  bool rigid;              /* true: E = infinity (walls only) */
  /* The contact laws' parameters (adem/laws.h), by id: param[ADEM_PARAM_SURFACE_ENERGY] is
   * gamma, J/m^2, per surface; ... Defaults from the parameter rows. */
  double param[ADEM_PARAM_COUNT];
} adem_material_def;
adem_material_def adem_default_material_def(void);

/* How two materials interact: the law of each slot (adem/laws.h) and values that replace the
 * materials' mixed ones. restitution and friction < 0 and param[k] NaN mean "derive from the
 * materials". */
typedef struct adem_interaction_def {
  int material_a, material_b;
  double restitution;
  double friction;
  adem_normal_model normal;
  adem_damping_model damping;
  adem_tangential_model tangential;
  adem_rolling_model rolling;
  double param[ADEM_PARAM_COUNT];
  /* DTK under reduced stiffness: true (default) keeps F_C, a0 and xi_crit of the real material and
   * takes only (a/a0)^(3/2) from the modified one (H section 3.2); false takes all from the modified
   * material, for comparison. */
  bool dtk_rolling_modification;
} adem_interaction_def;
adem_interaction_def adem_default_interaction_def(void);

typedef struct adem_particle_def {
  adem_vec3 position, velocity, angular_velocity;
  double radius;
  int material;
  int group; /* external-force group, 0 = default group */
} adem_particle_def;
adem_particle_def adem_default_particle_def(void);

/* An infinite plane; the particles live on the side its normal points to. */
typedef struct adem_plane_def {
  char name[ADEM_NAME_MAX];
  adem_vec3 point, normal;
  adem_vec3 velocity; /* translation velocity, enters the contact's relative velocity */
  int material;
  /* Shape (adem_wall_shape): 0, the default, is the infinite plane above. A cylinder: axis
   * through point along normal, radius, length from point along the axis (0: infinite). A disc:
   * the plane within radius of point (0: unbounded), less a hole of hole_radius about point.
   * flags: ADEM_WALL_OUTSIDE, ADEM_WALL_CAPPED, ADEM_WALL_TWO_SIDED (src/core/cylinder.h). */
  int shape;
  double radius, length, hole_radius;
  int flags;
} adem_plane_def;
typedef enum adem_wall_shape {
  ADEM_WALL_PLANE = 0,
  ADEM_WALL_CYLINDER = 1,
  ADEM_WALL_DISC = 2
} adem_wall_shape;
enum {
  ADEM_WALL_OUTSIDE = 1,  /* cylinder: the particles are outside it (default: inside) */
  ADEM_WALL_CAPPED = 2,   /* cylinder: discs close its ends (its own rims are not touched) */
  ADEM_WALL_TWO_SIDED = 4 /* disc: a sheet touched from both sides (default: one, like a plane) */
};
adem_plane_def adem_default_plane_def(void);

/* Servo (force-controlled) motion of a wall along one axis, from the particles' force on the wall
 * in the previous force pass: v = clamp(gain (F - target_force), +-max_speed) along axis, the
 * position integrated (x += v dt). Stable for gain K dt < 1, K the stiffness of what the wall
 * presses on. */
typedef struct adem_servo_def {
  bool on;                       /* false: no servo (the rest is ignored) */
  adem_vec3 axis;                /* any length > 0; unit once set */
  double target_force;           /* N: wanted force of the particles on the wall along axis */
  double gain;                   /* m/s per N, > 0 */
  double max_speed;              /* m/s, > 0 */
  double filter;                 /* s >= 0: time constant of a low-pass on the measured force */
  double travel_min, travel_max; /* m: limits of the servo displacement (min <= 0 <= max) */
  bool unmeasured;               /* true: a mesh group that moves with its file's servo but whose
                                    load is not measured (`servo.groups` leaves it out) */
} adem_servo_def;

/* Prescribed motion of a wall: a translation, given either as a piecewise-linear velocity in
 * time or as a piecewise-linear displacement (positions; the velocity is its derivative, and
 * the wall is exactly at each knot's position at its time), and a constant rotation about an
 * axis through a centre that travels with the translation. Positions are a function of time
 * alone, so a restarted run places the walls exactly. */
typedef struct adem_motion_def {
  size_t n;                  /* knots of the table; 0: no translation */
  const double *time;        /* s, strictly increasing */
  const adem_vec3 *velocity; /* m/s at each knot; constant before the first and after the last */
  adem_vec3 axis;            /* rotation axis (any length > 0 when angular_speed != 0) */
  double angular_speed;      /* rad/s, right-handed about axis */
  adem_vec3 center;          /* a point of the axis at t = 0, m */
  /* Instead of velocity (which must then be NULL): the displacement at each knot from where the
   * wall is placed (m), linear in between, held at the first before it and at the last after
   * it (the wall stops there). */
  const adem_vec3 *position;
  /* A servo (force control) along one axis, replacing the translation's component along it. */
  adem_servo_def servo;
} adem_motion_def;

/* What loading a mesh does to its coordinates, x' = R (s x) + t, and what its triangles are made
 * of. Fill from adem_default_mesh_transform(). */
typedef struct adem_mesh_transform {
  double scale;          /* s > 0: file units to metres (0.001 for a file in mm) */
  double rotation[3][3]; /* R, a proper rotation (orthonormal, det +1), row-major: x'_i = R_ij x_j */
  adem_vec3 translation; /* t, m */
  int material;          /* world material index of every triangle */
  bool own_vertices;     /* true: share no vertex with other groups, so that the group can move on
                            its own (a pushed sleeper); 0: join equal vertices of other groups */
} adem_mesh_transform;
/* s = 1, R = identity, t = 0, material 0, shared vertices. */
adem_mesh_transform adem_default_mesh_transform(void);
/* Turns the transform's rotation by angle_deg degrees about axis (any length > 0), after the
 * rotation it already has: R <- Rot(axis, angle) R. Multiples of 90 degrees about a coordinate
 * axis are exact (cos and sin are taken as 0 and +-1), so axis-aligned faces stay axis-aligned. */
adem_status adem_mesh_transform_rotate(adem_mesh_transform *tf, adem_vec3 axis, double angle_deg,
                                       adem_error *err);

/* Summed state of the world, computed on demand. Energies in J. */
typedef struct adem_diagnostics {
  double time;
  double kinetic, rotational, potential, elastic;
  /* Energy balance: initial + wall_work = (kinetic + rotational + potential + elastic) +
   * dissipated + balance_error. dissipated and wall_work are accumulated every step, contact by
   * contact (dashpots, friction slip, rolling resistance, the laws' own limits; the work of
   * moving walls), so balance_error measures the integration's and the laws' energy errors. */
  double dissipated; /* energy the contacts dissipated since prepare, J */
  double wall_work;  /* energy moving walls gave to the particles since prepare, J */
  double initial;    /* E_total at prepare, with particles added since and external work */
  double balance_error;
  /* Angular momentum of the particles about the origin, sum of x m v + I omega (N m s), and
   * the angular impulse BROF has added through particle contacts since the start, which no
   * partner takes back (I9-I10 act on each particle alone): a couple-based rolling law adds none. */
  adem_vec3 angular_momentum;
  adem_vec3 brof_impulse;
  size_t contacts_pp, contacts_pw;
  double max_overlap_ratio; /* max over contacts of overlap / smaller radius */
} adem_diagnostics;

/* Every function that can fail returns an adem_status (ADEM_OK = 0) and fills err (may be NULL)
 * with a message that says what was wrong; what it creates comes back through an out parameter
 * (may be NULL). */
adem_world *adem_world_create(void);
void adem_world_free(adem_world *w);

/* ---- set-up ---- */
adem_status adem_world_add_material(adem_world *w, const adem_material_def *def, int *index,
                                    adem_error *err);
int adem_world_find_material(const adem_world *w, const char *name); /* -1: none */
int adem_world_material_count(const adem_world *w);
const adem_material_def *adem_world_material(const adem_world *w, int index);
adem_status adem_world_set_interaction(adem_world *w, const adem_interaction_def *def,
                                       adem_error *err);
/* A group of particles with a constant external force; naming an existing group sets its force.
 * Group 0, "default", always exists. */
adem_status adem_world_add_group(adem_world *w, const char *name, adem_vec3 external_force,
                                 int *index, adem_error *err);
int adem_world_find_group(const adem_world *w, const char *name);
/* *id: the particle's stable id, 0, 1, ... in order of creation. Particles may be added to a world
 * that already runs (between steps): they join at the next step with their body forces, like
 * a pour's; they must not overlap particles or walls. */
adem_status adem_world_add_particle(adem_world *w, const adem_particle_def *def, uint64_t *id,
                                    adem_error *err);
adem_status adem_world_add_plane(adem_world *w, const adem_plane_def *def, int *index,
                                 adem_error *err);
/* Six planes facing inwards, named NAME.xmin, NAME.xmax, ...; *first: the index of the first. */
adem_status adem_world_add_box(adem_world *w, const char *name, adem_vec3 lo, adem_vec3 hi,
                               int material, int *first, adem_error *err);
/* A mesh wall of ntri triangles given as 3 corners each (before the transform), one group named
 * name (STL files: adem_world_add_stl in adem/case.h). */
adem_status adem_world_add_mesh(adem_world *w, const adem_vec3 *corners, size_t ntri,
                                const char *name, const adem_mesh_transform *tf, adem_error *err);
int adem_world_plane_count(const adem_world *w);
/* The plane where it is now. */
const adem_plane_def *adem_world_plane(const adem_world *w, int index);
/* A plane's (a cylinder's) rotation now: its rate, rad/s (0: none), with its unit axis and a point
 * of the axis where they are now (either may be NULL). */
double adem_world_plane_rotation(const adem_world *w, int index, adem_vec3 *axis, adem_vec3 *center);
adem_vec3 adem_world_gravity(const adem_world *w);
int adem_world_mesh_group_count(const adem_world *w);
const char *adem_world_mesh_group_name(const adem_world *w, int group);
int adem_world_find_mesh_group(const adem_world *w, const char *name); /* -1: none */
/* Prescribed motion of a plane, or of a mesh group (loaded with its own vertices). */
adem_status adem_world_set_plane_motion(adem_world *w, int plane, const adem_motion_def *def,
                                        adem_error *err);
adem_status adem_world_set_mesh_motion(adem_world *w, int group, const adem_motion_def *def,
                                       adem_error *err);
/* A wall switched off has no contacts (it stays in the world). */
adem_status adem_world_set_plane_active(adem_world *w, int plane, int active, adem_error *err);
adem_status adem_world_set_mesh_active(adem_world *w, int group, int active, adem_error *err);

void adem_world_set_gravity(adem_world *w, adem_vec3 g);
void adem_world_set_threads(adem_world *w, int nthreads); /* results do not depend on it */
/* Threads a world uses unless told otherwise (OMP_NUM_THREADS, else the processors). */
int adem_default_thread_count(void);
void adem_world_set_skin(adem_world *w, double skin_fraction); /* skin as a fraction of max diameter */
void adem_world_set_max_overlap_ratio(adem_world *w, double ratio);
/* Overlaps allowed at the start, as a fraction of the smaller radius (default 0: none): for a
 * settled bed made by another run or code. Larger ones are refused, naming the pair. */
void adem_world_set_initial_overlap(adem_world *w, double ratio);
void adem_world_set_domain(adem_world *w, adem_vec3 lo, adem_vec3 hi); /* escape check */
/* Periodic boundaries: along the axes in `axes` (ADEM_PERIODIC_X | ...; 0 turns them off) the
 * box lo..hi wraps: a particle leaving through a face comes in through the opposite one (its
 * image counter counts it) and pairs interact through the faces (minimum image). The box is also
 * the escape domain of the other axes. Refused here: lo >= hi along a periodic axis; at prepare:
 * a periodic length below 2 (largest diameter + skin), or a plane wall whose normal has a
 * component along a periodic axis. Mesh walls are not imaged across the faces (a warning says
 * so when one comes within reach of a face). */
enum { ADEM_PERIODIC_X = 1,
       ADEM_PERIODIC_Y = 2,
       ADEM_PERIODIC_Z = 4 };
adem_status adem_world_set_periodic(adem_world *w, adem_vec3 lo, adem_vec3 hi, unsigned axes,
                                    adem_error *err);
/* Periodic faces particle `id` has crossed along x, y, z (out[3]; its unwrapped centre is the
 * position plus out[d] box lengths). */
adem_status adem_world_particle_image(const adem_world *w, uint64_t id, int32_t out[3],
                                      adem_error *err);
/* Neighbour search: a cell grid (default), or every pair (O(N^2): a two-body study is faster
 * without a grid). Results are the same. */
typedef enum adem_neighbor_search { ADEM_SEARCH_GRID = 0,
                                    ADEM_SEARCH_ALL_PAIRS = 1 } adem_neighbor_search;
void adem_world_set_neighbor_search(adem_world *w, adem_neighbor_search how);

/* Time step from the Hertz collision time and the Rayleigh time (notes section 6). */
typedef struct adem_step_estimate {
  double v_ref;       /* impact speed the collision time is evaluated at, m/s */
  double t_collision; /* shortest Hertz collision time over material pairs, s; a simplified JKR
                       * pair takes it at sqrt(v_ref^2 + 2|U_min|/m*), the speed its adhesion
                       * brings the spheres to, or half its period of oscillation about the
                       * equilibrium if that is shorter */
  double t_rayleigh;  /* shortest Rayleigh time, s */
  double dt;          /* proposed step: min(t_collision/50, 0.2 t_rayleigh, dt_stable/5) */
  double dt_stable;   /* shortest step at which a contact's fastest mode (normal; tangential with
                       * the contact point's mass m-star/3.5 and a rolling spring; model C's
                       * explicit dashpot) reaches the integrator's stability limit, linearised at
                       * the collision's peak stiffness (docs/models.md, "Time step"), s */
  double dt_limit;    /* the largest step a case may ask for: min(t_collision/5, dt_stable) */
} adem_step_estimate;
adem_step_estimate adem_world_estimate_step(const adem_world *w, double v_ref);
/* Accuracy limit of a given step: t_collision / ADEM_STEP_LIMIT_DIVISOR. Measured on a
 * two-sphere Hertz collision (docs/reliability.md): up to t_c/5 the restitution is off by
 * 1.6 % at most, at t_c/4 by 3 %, t_c/3 6.5 %, t_c/2.5 15 % (energy created), t_c/2 a factor
 * 2.3. A case asking for more than it or than the stability limit (adem_step_estimate's
 * dt_limit) is refused unless limits.allow_large_step is true. */
#define ADEM_STEP_LIMIT_DIVISOR 5.0
/* The Hertz collision time and the JKR pair summary are the laws' (adem/laws.h). */

void adem_world_set_dt(adem_world *w, double dt);
/* How contact forces meet the velocity-Verlet step. SECOND_ORDER (the default): the dashpots
 * take the velocity predicted at the full step, v + F_old dt/(2m), where their force acts, and
 * the simplified JKR force's jumps of -(8/9) F_C where a contact forms or breaks at delta = 0
 * take effect at the crossing time interpolated within the step; collisions then converge as
 * dt^2. FIRST_ORDER: the scheme as it was before (dashpots on the half step's velocity, half a
 * step behind; jumps at the force pass after the crossing): errors of order dt. */
typedef enum adem_contact_scheme {
  ADEM_CONTACTS_SECOND_ORDER = 0,
  ADEM_CONTACTS_FIRST_ORDER = 1
} adem_contact_scheme;
void adem_world_set_contact_scheme(adem_world *w, adem_contact_scheme scheme);
/* The energy balance (on by default): every step the contacts' dissipation and the walls' work
 * are accumulated per particle, contact by contact, so that the diagnostics' dissipated,
 * wall_work and balance_error close the balance. It changes no force, position or velocity; off,
 * a step costs less (docs/performance.md) and those three read NaN. Set it before the first
 * step: a balance cannot start in the middle of a run. */
void adem_world_set_energy_balance(adem_world *w, bool on);
bool adem_world_energy_balance(const adem_world *w);
double adem_world_dt(const adem_world *w);

/* Validates the set-up (overlaps, particles outside walls), derives pair tables, builds the
 * neighbour lists and computes the first forces. Call once before stepping. */
adem_status adem_world_prepare(adem_world *w, adem_error *err);
/* Advances n steps. Stops early with ADEM_ERR_RUNTIME on NaN, runaway overlap or escape. */
adem_status adem_world_step(adem_world *w, uint64_t n, adem_error *err);

/* One force pass at the current positions and velocities, without moving anything (the world
 * must be prepared): forces, torques and contacts can then be read. Contact histories (the
 * springs) are left as they are: only a step advances them. */
void adem_world_compute_forces(adem_world *w);
/* The same pass, but every contact history advances by one step of the current relative
 * velocities, as in a step (studies that drive a spring directly: adem_collide_dtk_torque). */
void adem_world_advance_histories(adem_world *w);

/* ---- reading the state ---- */
double adem_world_time(const adem_world *w);
uint64_t adem_world_step_count(const adem_world *w);
size_t adem_world_particle_count(const adem_world *w);
adem_diagnostics adem_world_diagnostics(const adem_world *w);

/* Per-particle quantities, read into arrays in order of particle id (id k at out[k * components],
 * components 3 for vectors, 1 for scalars; once an outlet has removed particles, the k-th
 * smallest id remaining). */
typedef enum adem_particle_field {
  ADEM_FIELD_POSITION = 0,         /* m */
  ADEM_FIELD_VELOCITY = 1,         /* m/s */
  ADEM_FIELD_ANGULAR_VELOCITY = 2, /* rad/s */
  ADEM_FIELD_FORCE = 3,            /* total force of the last force pass, N */
  ADEM_FIELD_TORQUE = 4,           /* total torque, N m */
  ADEM_FIELD_ROLLING_TORQUE = 5,   /* rolling resistance torque, N m */
  ADEM_FIELD_RADIUS = 6,           /* m */
  ADEM_FIELD_MASS = 7,             /* kg */
  ADEM_FIELD_MATERIAL = 8,         /* material index */
  ADEM_FIELD_CONTACTS = 9,         /* contacts touching now (particles and walls) */
  ADEM_FIELD_PATH_LENGTH = 10,     /* distance the centre has travelled, m */
  ADEM_FIELD_INVERSE_MASS = 11,    /* 1/kg, as the integrator uses it */
  ADEM_FIELD_INVERSE_INERTIA = 12, /* 1/(kg m^2), as the integrator uses it */
  ADEM_FIELD_EXTERNAL_FORCE = 13   /* the particle's own external force, N (set below) */
} adem_particle_field;
int adem_particle_field_components(adem_particle_field field);
/* out holds capacity doubles, at least count x components. */
adem_status adem_world_get_particles(const adem_world *w, adem_particle_field field, double *out,
                                     size_t capacity, adem_error *err);
/* Places particle id, or sets its velocity or spin (NULL: keep). Between steps. O(1): the
 * world keeps an id -> index map, checked at each look-up and rebuilt once (O(n)) after the
 * particles were reordered; for every particle at once, adem_world_set_particles. */
adem_status adem_world_set_particle(adem_world *w, uint64_t id, const adem_vec3 *position,
                                    const adem_vec3 *velocity, const adem_vec3 *angular_velocity,
                                    adem_error *err);

/* ---- bulk access in id order (src/core/world_bulk.c) ---- */
/* The particles' ids in increasing order into out (capacity entries, at least count): row k of
 * the arrays adem_world_get_particles and adem_world_set_particles take is particle out[k]. */
adem_status adem_world_get_ids(const adem_world *w, uint64_t *out, size_t capacity,
                               adem_error *err);
/* Sets one field of every particle from in, count x 3 doubles in id order (as
 * adem_world_get_particles reads them; count must be the particle count): ADEM_FIELD_POSITION,
 * ADEM_FIELD_VELOCITY, ADEM_FIELD_ANGULAR_VELOCITY or ADEM_FIELD_EXTERNAL_FORCE. Between steps;
 * every value must be finite (else nothing is changed). O(n).
 * A particle's external force acts with gravity and its group's force in every force pass
 * (summed in that order), stays until changed, and is kept in checkpoints; it starts at zero.
 * Set between steps, it replaces the old one in the last pass's total force too, so the whole
 * next step feels it; the energy balance counts it as the potential -F . x, whose change is
 * work done from outside. */
adem_status adem_world_set_particles(adem_world *w, adem_particle_field field, const double *in,
                                     size_t count, adem_error *err);
/* Adds n particles from arrays, as n calls of adem_world_add_particle: pos, vel, omega n x 3
 * doubles (vel, omega NULL: zero), radius n, material and group n ints (NULL: 0 each); ids (may
 * be NULL) receives their ids. Every row is checked first: a bad one adds none. */
adem_status adem_world_add_particles(adem_world *w, size_t n, const double *pos, const double *vel,
                                     const double *omega, const double *radius,
                                     const int *material, const int *group, uint64_t *ids,
                                     adem_error *err);
/* One particle's external force (N); the same as a row of adem_world_set_particles. */
adem_status adem_world_set_external_force(adem_world *w, uint64_t id, adem_vec3 force,
                                          adem_error *err);

/* A contact of the last force pass. */
typedef enum adem_contact_kind {
  ADEM_CONTACT_PARTICLE = 0, /* b is a particle id */
  ADEM_CONTACT_PLANE = 1,    /* b is a plane index */
  ADEM_CONTACT_MESH = 2      /* b is a mesh group */
} adem_contact_kind;
typedef struct adem_contact_info {
  adem_contact_kind kind;
  uint64_t a, b;                /* particle id a (the lower id of a pair), and b */
  adem_vec3 force;              /* force on a, N */
  double overlap_ratio;         /* overlap / smaller radius */
  double elastic;               /* energy stored, J */
  adem_vec3 tangential_history; /* the tangential law's history: incremental, the spring force on
                                 * a (N); total, the accumulated displacement (m) */
  adem_vec3 rolling_history;    /* the rolling law's (DTK: xi in m; model C: spring torque) */
} adem_contact_info;
/* Writes up to capacity touching contacts into out (particle pairs, then planes, then meshes, each
 * in a fixed order) and returns how many touch. */
size_t adem_world_contacts(const adem_world *w, adem_contact_info *out, size_t capacity);
/* Forgets every contact's history (a fresh start of the same positions). */
void adem_world_clear_history(adem_world *w);

/* What the laws of a material pair see (derived at prepare, or now if needed). */
typedef struct adem_pair_info {
  adem_normal_model normal;
  adem_damping_model damping;
  adem_tangential_model tangential;
  adem_rolling_model rolling;
  double E, G;           /* effective moduli, modified stiffness (H2, H15, H24), Pa */
  double E_real, G_real; /* of the real material */
  double restitution, beta, friction;
  double gamma, gamma_real;         /* surface energy, modified (H24) and real, J/m^2 */
  double param[ADEM_PARAM_COUNT];   /* the pair's value of each law parameter */
  double param_a[ADEM_PARAM_COUNT]; /* material a's (or the interaction's) value */
  double param_b[ADEM_PARAM_COUNT];
  bool set_restitution, set_friction, set_param[ADEM_PARAM_COUNT]; /* from an interaction entry */
} adem_pair_info;
adem_status adem_world_pair_info(adem_world *w, int material_a, int material_b,
                                 adem_pair_info *out, adem_error *err);

/* Force of the particles on each plane (plane_count entries), summed in a fixed order. */
void adem_world_plane_forces(const adem_world *w, adem_vec3 *out);
/* Force and torque of the particles on each mesh group (mesh_group_count entries each) and on
 * each mesh wall (one per file or adem_world_add_mesh; mesh_wall_count entries); any pointer may
 * be NULL. Torques about the groups' reference points where their motion has them now. */
int adem_world_mesh_wall_count(const adem_world *w);
void adem_world_mesh_loads(const adem_world *w, adem_vec3 *group_force, adem_vec3 *group_torque,
                           adem_vec3 *wall_force, adem_vec3 *wall_torque);

/* Neighbour-list builds since the world was made (performance figures). */
uint64_t adem_world_neighbor_builds(const adem_world *w);

/* Memory: bytes per particle and per candidate pair of the world's arrays (a pair's energy
 * balance terms count only while the world keeps the balance). */
size_t adem_world_bytes_per_particle(void);
size_t adem_world_bytes_per_pair(const adem_world *w);

/* Memory a run of n particles needs, estimated before anything is allocated from the sizes of
 * the real arrays (particles.h, pairs.h, neighbors.c): the particle table at the capacity that
 * appending grows it to, ADEM_PAIRS_PER_PARTICLE (1 + skin)^3 candidate particle pairs per
 * particle (a settled pour with skin 0.2 has 4.7; the bound is 6.9 there), a wall pair per
 * particle when there are planes and ADEM_MESH_SLOTS_PER_PARTICLE candidate triangles when
 * there are mesh walls, the pair lists' headroom, the neighbour grid (at most 8 n + 1024
 * cells) and what a neighbour build allocates while it runs. Bytes. */
#define ADEM_PAIRS_PER_PARTICLE 4.0
#define ADEM_MESH_SLOTS_PER_PARTICLE 4.0
typedef struct adem_memory_estimate {
  double particles; /* particle count the estimate is for */
  double pairs;     /* candidate pairs of every kind */
  double particle_bytes, pair_bytes, grid_bytes, build_bytes;
  double total; /* bytes */
} adem_memory_estimate;
adem_memory_estimate adem_world_memory_estimate(const adem_world *w, double nparticles);
/* Memory the machine can give a new run, bytes: MemAvailable of /proc/meminfo, else the free
 * physical pages (sysconf); 0 when neither is known. */
double adem_memory_available(void);

/* Tunnelling: a particle that moved more than its radius in one step while it had candidate
 * mesh triangles (within radius + skin at the last neighbour build) may have passed through a
 * mesh wall. Counted since the world was made or loaded (not kept in checkpoints); the first
 * ADEM_TUNNEL_LOGGED are logged as warnings with id, position and time. */
#define ADEM_TUNNEL_LOGGED 5
typedef struct adem_tunnel_event {
  uint64_t id;
  adem_vec3 pos; /* centre after the step, m */
  double time;   /* s */
  double moved;  /* |v| dt of the step, m */
  double radius; /* m */
} adem_tunnel_event;
uint64_t adem_world_tunnel_count(const adem_world *w);
/* The first event (NULL when there was none). */
const adem_tunnel_event *adem_world_tunnel_first(const adem_world *w);

#ifdef __cplusplus
}
#endif
#endif
