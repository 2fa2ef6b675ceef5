/* Small builders shared by the tests: worlds made through the public API. */
#ifndef ADEM_TEST_HELPERS_H
#define ADEM_TEST_HELPERS_H

#include <math.h>
#include <string.h>

#include "adem/adem.h"

/* A material with the given modulus, restitution and friction (glass-like density). */
static inline int test_material(adem_world *w, const char *name, double E, double nu, double e,
                                double mu) {
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "%s", name);
  m.density = 2500.0;
  m.young = E;
  m.poisson = nu;
  m.restitution = e;
  m.friction = mu;
  adem_error err;
  int index = -1;
  if (adem_world_add_material(w, &m, &index, &err)) return -1;
  return index;
}

static inline int64_t test_particle(adem_world *w, int mat, adem_vec3 x, adem_vec3 v, double r) {
  adem_particle_def p = adem_default_particle_def();
  p.material = mat;
  p.position = x;
  p.velocity = v;
  p.radius = r;
  adem_error err;
  uint64_t id = 0;
  if (adem_world_add_particle(w, &p, &id, &err)) return -1;
  return (int64_t)id;
}

static inline double test_sphere_mass(double r, double rho) {
  return rho * 4.0 / 3.0 * 3.14159265358979323846 * r * r * r;
}

#endif
