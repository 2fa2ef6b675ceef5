/* A small pour driven through the public API only (include/adem): no case file.
 *
 * Glass spheres are dropped in layers into a square box of planes with a chute (a mesh of two
 * triangles) across it; a lid plane comes down on a prescribed motion at the end. The program
 * reads positions, velocities and contact counts back as arrays, writes a checkpoint, and checks
 * that the run read back from it steps on bit for bit as the one that wrote it.
 *
 *   cc pour.c -I PREFIX/include -L PREFIX/lib -ladem -lyaml -lm -fopenmp -o pour && ./pour [DIR]
 *
 * Exit status 0 when the pour settled (the floor carries the spheres' weight within 1%) and the
 * restart was exact; 1 otherwise. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <adem/adem.h>
#include <adem/vec3.h>

#define CHECK(call)                                                              \
  do {                                                                           \
    adem_status st_ = (call);                                                    \
    if (st_) {                                                                   \
      fprintf(stderr, "pour: %s (line %d): %s\n", #call, __LINE__, err.message); \
      return 1;                                                                  \
    }                                                                            \
  } while (0)

static adem_error err;

/* A layer of n x n spheres of radius r at height z, jittered so that they do not stack. */
static adem_status add_layer(adem_world *w, int material, int n, double r, double z, int layer) {
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      adem_particle_def p = adem_default_particle_def();
      p.material = material;
      p.radius = r * (0.9 + 0.2 * ((i * 7 + j * 3 + layer) % 5) / 4.0);
      p.position = (adem_vec3){0.012 + 0.0125 * i + 0.001 * (layer % 2),
                               0.012 + 0.0125 * j + 0.001 * ((layer / 2) % 2), z};
      p.velocity = (adem_vec3){0.0, 0.0, -0.5};
      adem_status st = adem_world_add_particle(w, &p, NULL, &err);
      if (st) return st;
    }
  return ADEM_OK;
}

/* Sum over every particle of a field component (in id order: the same for any thread count). */
static double sum_of(const adem_world *w, adem_particle_field f, int component) {
  size_t n = adem_world_particle_count(w);
  int nc = adem_particle_field_components(f);
  double *a = malloc(n * (size_t)nc * sizeof *a + 1), s = 0.0;
  if (!a || adem_world_get_particles(w, f, a, n * (size_t)nc, NULL)) {
    free(a);
    return NAN;
  }
  for (size_t k = 0; k < n; ++k) s += a[k * (size_t)nc + (size_t)component];
  free(a);
  return s;
}

int main(int argc, char **argv) {
  const char *dir = argc > 1 ? argv[1] : ".";
  adem_world *w = adem_world_create();
  if (!w) return 1;
  adem_world_set_threads(w, 1);

  adem_material_def glass = adem_default_material_def();
  snprintf(glass.name, sizeof glass.name, "glass");
  glass.density = 2500.0;
  glass.young = 5e6;
  glass.poisson = 0.25;
  glass.restitution = 0.4;
  glass.friction = 0.5;
  glass.param[ADEM_PARAM_ROLLING_FRICTION] = 0.1;
  adem_material_def steel = glass;
  snprintf(steel.name, sizeof steel.name, "steel");
  steel.rigid = 1;
  int mg = 0, ms = 0;
  CHECK(adem_world_add_material(w, &glass, &mg, &err));
  CHECK(adem_world_add_material(w, &steel, &ms, &err));
  /* BROF between the spheres and on the walls (Irazabal et al. 2017): a heap that comes to rest */
  for (int b = 0; b < 2; ++b) {
    adem_interaction_def it = adem_default_interaction_def();
    it.material_a = mg;
    it.material_b = b ? ms : mg;
    it.rolling = ADEM_ROLLING_BROF;
    CHECK(adem_world_set_interaction(w, &it, &err));
  }

  const double L = 0.075; /* box side, m */
  int floor = 0;
  CHECK(adem_world_add_box(w, "box", (adem_vec3){0, 0, 0}, (adem_vec3){L, L, 0.4}, ms, &floor,
                           &err));
  floor += 4; /* NAME.zmin: the fifth plane */

  /* the chute: a plate tilted 20 degrees across half the box at mid-height */
  adem_vec3 c[6] = {{0.0, 0.0, 0.10}, {0.04, 0.0, 0.10 - 0.04 * tan(20 * ADEM_PI / 180)}, {0.04, L, 0.10 - 0.04 * tan(20 * ADEM_PI / 180)}, {0.0, 0.0, 0.10}, {0.04, L, 0.10 - 0.04 * tan(20 * ADEM_PI / 180)}, {0.0, L, 0.10}};
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.material = ms;
  tf.own_vertices = 1;
  CHECK(adem_world_add_mesh(w, c, 2, "chute", &tf, &err));
  /* a lid that waits above the box, then comes down at 0.2 m/s from t = 0.35 s to 0.6 s */
  adem_plane_def lid = adem_default_plane_def();
  snprintf(lid.name, sizeof lid.name, "lid");
  lid.point = (adem_vec3){0, 0, 0.36};
  lid.normal = (adem_vec3){0, 0, -1};
  lid.material = ms;
  int lid_index = 0;
  CHECK(adem_world_add_plane(w, &lid, &lid_index, &err));
  /* piecewise-linear velocity: at rest until 0.35 s, -0.2 m/s from 0.36 s to 0.6 s, then at rest */
  double knots[4] = {0.35, 0.36, 0.6, 0.61};
  adem_vec3 speeds[4] = {{0, 0, 0}, {0, 0, -0.2}, {0, 0, -0.2}, {0, 0, 0}};
  adem_motion_def motion = {4, knots, speeds, {0, 0, 1}, 0.0, {0, 0, 0}, NULL, {0}}; /* no servo */
  CHECK(adem_world_set_plane_motion(w, lid_index, &motion, &err));

  /* the first layer, then the step: 1/50 of the collision time at the fall's speed */
  CHECK(add_layer(w, mg, 5, 0.005, 0.30, 0));
  adem_step_estimate est = adem_world_estimate_step(w, 3.0);
  adem_world_set_dt(w, est.dt);
  CHECK(adem_world_prepare(w, &err));
  printf("pour: dt %.3g s (t_c %.3g s, t_R %.3g s)\n", est.dt, est.t_collision, est.t_rayleigh);

  /* a new layer every 0.04 s while the run goes on, for 0.32 s */
  const double t_end = 1.5;
  uint64_t every = (uint64_t)llround(0.04 / est.dt);
  int layer = 1;
  while (adem_world_time(w) < t_end) {
    CHECK(adem_world_step(w, every, &err));
    if (layer < 8) CHECK(add_layer(w, mg, 5, 0.005, 0.30, layer++));
  }
  size_t n = adem_world_particle_count(w);
  double mass = sum_of(w, ADEM_FIELD_MASS, 0), contacts = sum_of(w, ADEM_FIELD_CONTACTS, 0);
  int np = adem_world_plane_count(w);
  adem_vec3 *pf = malloc((size_t)np * sizeof *pf);
  adem_world_plane_forces(w, pf);
  double weight = 9.81 * mass, load = -pf[floor].z, walls = 0.0;
  for (int k = 0; k < np; ++k) walls -= pf[k].z;
  adem_vec3 chute_force;
  adem_world_mesh_loads(w, &chute_force, NULL, NULL, NULL);
  adem_diagnostics d = adem_world_diagnostics(w);
  printf("pour: %zu spheres at t = %.3f s, kinetic energy %.3g J, %.2f contacts per sphere\n", n,
         adem_world_time(w), d.kinetic + d.rotational, contacts / (double)n);
  printf("pour: floor %.5g N, side walls %.5g N, chute %.5g N: %.5g N against the weight %.5g N\n",
         load, walls - load, -chute_force.z, walls - chute_force.z, weight);
  free(pf);

  /* checkpoint, then 0.05 s on from the world in memory and from the file: the same bits */
  char path[4096];
  snprintf(path, sizeof path, "%s/pour.ckpt", dir);
  CHECK(adem_world_checkpoint_write(w, path, &err));
  adem_world *r = NULL;
  CHECK(adem_world_checkpoint_read(path, &r, &err));
  uint64_t more = (uint64_t)llround(0.05 / est.dt);
  CHECK(adem_world_step(w, more, &err));
  CHECK(adem_world_step(r, more, &err));
  double *a = malloc(3 * n * sizeof *a), *b = malloc(3 * n * sizeof *b);
  int same = a && b;
  for (int f = ADEM_FIELD_POSITION; same && f <= ADEM_FIELD_ANGULAR_VELOCITY; ++f) {
    adem_world_get_particles(w, (adem_particle_field)f, a, 3 * n, NULL);
    adem_world_get_particles(r, (adem_particle_field)f, b, 3 * n, NULL);
    same = memcmp(a, b, 3 * n * sizeof *a) == 0;
  }
  printf("pour: restart from %s %s\n", path, same ? "is bitwise equal" : "DIFFERS");
  free(a);
  free(b);
  adem_world_free(r);
  adem_world_free(w);
  /* at rest the walls and the chute carry the spheres' weight */
  int settled = fabs(walls - chute_force.z - weight) < 0.01 * weight;
  return same && settled ? 0 : 1;
}
