/* The simulated world: materials, particles, walls, and the time stepper. */
#ifndef ADEM_WORLD_H
#define ADEM_WORLD_H

#include "adem/adem.h"
#include "adem/laws.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A material. Walls have one too; a rigid wall material has E = infinity. */
typedef struct adem_material_def {
  char name[ADEM_NAME_MAX];
  double density;          /* kg/m^3 */
  double young;            /* E, Pa (the real one; see stiffness_factor) */
  double poisson;          /* nu, in (-1, 0.5) */
  double restitution;      /* e, in (0, 1] */
  double friction;         /* sliding friction coefficient mu_s */
  double stiffness_factor; /* f = E_mod/E in (0, 1]; H24 */
  int rigid;               /* 1: E = infinity (walls only) */
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
  /* DTK under reduced stiffness: 1 (default) keeps F_C, a0 and xi_crit of the real material and
   * takes only (a/a0)^(3/2) from the modified one (H section 3.2); 0 takes all from the modified
   * material, for comparison. */
  int dtk_rolling_modification;
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
} adem_plane_def;
adem_plane_def adem_default_plane_def(void);

/* Summed state of the world, computed on demand. Energies in J. */
typedef struct adem_diagnostics {
  double time;
  double kinetic, rotational, potential, elastic;
  double dissipated; /* energy balance: E_total(0) - E_total(t) */
  size_t contacts_pp, contacts_pw;
  double max_overlap_ratio; /* max over contacts of overlap / smaller radius */
} adem_diagnostics;

adem_world *adem_world_create(void);
void adem_world_free(adem_world *w);

int adem_world_add_material(adem_world *w, const adem_material_def *def, adem_error *err);
int adem_world_find_material(const adem_world *w, const char *name);
int adem_world_set_interaction(adem_world *w, const adem_interaction_def *def, adem_error *err);
int adem_world_add_group(adem_world *w, const char *name, adem_vec3 external_force);
int adem_world_find_group(const adem_world *w, const char *name);
/* Returns the new particle's stable id, or -1 with err set. */
int64_t adem_world_add_particle(adem_world *w, const adem_particle_def *def, adem_error *err);
int adem_world_add_plane(adem_world *w, const adem_plane_def *def, adem_error *err);
/* Six planes facing inwards, named NAME.xmin, NAME.xmax, ... */
int adem_world_add_box(adem_world *w, const char *name, adem_vec3 lo, adem_vec3 hi, int material,
                       adem_error *err);

void adem_world_set_gravity(adem_world *w, adem_vec3 g);
void adem_world_set_threads(adem_world *w, int nthreads);
void adem_world_set_skin(adem_world *w, double skin_fraction); /* skin as a fraction of max diameter */
void adem_world_set_max_overlap_ratio(adem_world *w, double ratio);
void adem_world_set_domain(adem_world *w, adem_vec3 lo, adem_vec3 hi); /* escape check */
void adem_world_use_brute_force(adem_world *w, int on);

/* Time step from the Hertz collision time and the Rayleigh time (notes section 6). */
typedef struct adem_step_estimate {
  double v_ref;        /* impact speed the collision time is evaluated at, m/s */
  double t_collision;  /* shortest Hertz collision time over material pairs, s */
  double t_rayleigh;   /* shortest Rayleigh time, s */
  double dt;           /* proposed step: min(t_collision/50, 0.2 t_rayleigh) */
} adem_step_estimate;
adem_step_estimate adem_world_estimate_step(const adem_world *w, double v_ref);
/* Hertz collision time (notes section 6): t_c = 2.86827 (m*^2 / (R E^2 v))^(1/5), s. */
double adem_hertz_collision_time(double mstar, double R, double E, double v);

/* What a JKR material pair implies (notes sections 1, 5, 6): `adem check` prints it and the case
 * loader warns from it. */

/* External forces that pull spheres apart should stay below this fraction of the modified
 * pull-off force (H section 6.2: "significantly higher"; a 10% margin). */
#define ADEM_PULLOFF_SAFETY 0.1
/* Minimum atomic separation of the Tabor parameter, m (H1). */
#define ADEM_TABOR_DMIN 1.65e-10

typedef struct adem_jkr_pair_summary {
  double R, mstar;            /* effective radius and mass used */
  double E, E_mod;            /* effective modulus, real and modified (H2, H24) */
  double gamma, gamma_mod;    /* surface energy, real and modified (H24) */
  double a0, a0_mod;          /* equilibrium contact radius (H7) */
  double delta_eq, delta_eq_mod; /* equilibrium overlap a0^2/(3R) */
  double f_c, f_c_mod;        /* critical force 3 pi gamma R */
  double pull_off, pull_off_mod; /* force that breaks the contact, (8/9) F_C */
  double tabor;               /* Tabor parameter of the real material (H1); JKR valid above 3 */
  double t_c, t_c_mod;        /* Hertz collision time at v_ref (notes section 6) */
  double dt, dt_mod;          /* t_c / 50 */
  double speedup;             /* t_c_mod / t_c = (E/E_mod)^(2/5) */
  double f_ext_max;           /* ADEM_PULLOFF_SAFETY * pull_off_mod */
} adem_jkr_pair_summary;
adem_jkr_pair_summary adem_jkr_pair_summarize(double E, double E_mod, double gamma,
                                              double gamma_mod, double R, double mstar,
                                              double v_ref);

void adem_world_set_dt(adem_world *w, double dt);
double adem_world_dt(const adem_world *w);

/* Validates the set-up (overlaps, particles outside walls), derives pair tables, builds the
 * neighbour lists and computes the first forces. Call once before stepping. */
adem_status adem_world_prepare(adem_world *w, adem_error *err);
/* Advances n steps. Stops early with ADEM_ERR_RUNTIME on NaN, runaway overlap or escape. */
adem_status adem_world_step(adem_world *w, uint64_t n, adem_error *err);

double adem_world_time(const adem_world *w);
uint64_t adem_world_step_count(const adem_world *w);
size_t adem_world_particle_count(const adem_world *w);
adem_diagnostics adem_world_diagnostics(const adem_world *w);

#ifdef __cplusplus
}
#endif
#endif
