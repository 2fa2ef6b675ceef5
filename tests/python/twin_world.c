/* The world tests/python/test_adem.py builds through the Python module, built here through the C
 * API: materials, an interaction, 64 particles from a lattice, a box with a moving lid, a mesh
 * ramp, external forces per particle; 1500 steps, then the world checkpoint written to argv[1].
 * The two checkpoints must be the same bytes.   twin_world OUT_FILE */
#include <stdio.h>
#include <string.h>

#include "adem/adem.h"

#define CHECK(call)                                                \
  do {                                                             \
    if ((call) != ADEM_OK) {                                       \
      fprintf(stderr, "twin_world: %s: %s\n", #call, err.message); \
      return 1;                                                    \
    }                                                              \
  } while (0)

int main(int argc, char **argv) {
  if (argc != 2) return 2;
  adem_error err = {ADEM_OK, ""};
  adem_world *w = adem_world_create();
  adem_world_set_threads(w, 1);
  adem_material_def glass = adem_default_material_def();
  snprintf(glass.name, sizeof glass.name, "glass");
  glass.density = 2500.0;
  glass.young = 1e7;
  glass.poisson = 0.3;
  glass.restitution = 0.5;
  glass.friction = 0.4;
  glass.param[ADEM_PARAM_ROLLING_FRICTION] = 0.1;
  adem_material_def steel = adem_default_material_def();
  snprintf(steel.name, sizeof steel.name, "steel");
  steel.density = 7800.0;
  steel.young = 1e7;
  steel.poisson = 0.3;
  steel.restitution = 0.6;
  steel.friction = 0.3;
  int mg, ms;
  CHECK(adem_world_add_material(w, &glass, &mg, &err));
  CHECK(adem_world_add_material(w, &steel, &ms, &err));
  adem_interaction_def it = adem_default_interaction_def();
  it.material_a = mg;
  it.material_b = mg;
  it.rolling = ADEM_ROLLING_C;
  it.param[ADEM_PARAM_ROLLING_DAMPING] = 0.3;
  CHECK(adem_world_set_interaction(w, &it, &err));
  int first;
  CHECK(adem_world_add_box(w, "box", (adem_vec3){0, 0, 0}, (adem_vec3){0.04, 0.04, 0.08}, ms,
                           &first, &err));
  double t[2] = {0.0, 1.0};
  adem_vec3 v[2] = {{0, 0, -0.05}, {0, 0, -0.05}};
  adem_motion_def md;
  memset(&md, 0, sizeof md);
  md.n = 2;
  md.time = t;
  md.velocity = v;
  md.axis = (adem_vec3){0, 0, 1};
  CHECK(adem_world_set_plane_motion(w, first + 5, &md, &err)); /* box.zmax comes down */
  adem_vec3 ramp[6] = {{0, 0, 0.002}, {0.04, 0, 0.012}, {0.04, 0.04, 0.012}, {0, 0, 0.002}, {0.04, 0.04, 0.012}, {0, 0.04, 0.002}};
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.material = ms;
  CHECK(adem_world_add_mesh(w, ramp, 2, "ramp", &tf, &err));
  for (int k = 0; k < 64; ++k) {
    adem_particle_def p = adem_default_particle_def();
    p.material = mg;
    p.radius = 0.0015 + 0.0001 * (k % 4);
    p.position = (adem_vec3){0.004 + 0.009 * (k % 4), 0.004 + 0.009 * ((k / 4) % 4),
                             0.02 + 0.008 * (k / 16)};
    p.velocity = (adem_vec3){0.01 * (k % 3), -0.01 * (k % 5), -0.2};
    CHECK(adem_world_add_particle(w, &p, NULL, &err));
  }
  adem_world_set_dt(w, 2e-5);
  CHECK(adem_world_prepare(w, &err));
  double f[64 * 3];
  for (int k = 0; k < 64; ++k) {
    f[3 * k] = 1e-4 * (k % 3);
    f[3 * k + 1] = -2e-4 * (k % 2);
    f[3 * k + 2] = 0.0;
  }
  CHECK(adem_world_set_particles(w, ADEM_FIELD_EXTERNAL_FORCE, f, 64, &err));
  CHECK(adem_world_step(w, 1500, &err));
  CHECK(adem_world_checkpoint_write(w, argv[1], &err));
  adem_world_free(w);
  return 0;
}
