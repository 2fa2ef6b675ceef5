/* Small inline vector algebra on adem_vec3. */
#ifndef ADEM_VEC3_H
#define ADEM_VEC3_H

#include <math.h>
#include "adem/base.h"

#define ADEM_PI 3.14159265358979323846

static inline adem_vec3 v3(double x, double y, double z) { return (adem_vec3){x, y, z}; }
static inline adem_vec3 v3_add(adem_vec3 a, adem_vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline adem_vec3 v3_sub(adem_vec3 a, adem_vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline adem_vec3 v3_scale(adem_vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline adem_vec3 v3_neg(adem_vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline double v3_dot(adem_vec3 a, adem_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline adem_vec3 v3_cross(adem_vec3 a, adem_vec3 b) {
  return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_norm2(adem_vec3 a) { return v3_dot(a, a); }
static inline double v3_norm(adem_vec3 a) { return sqrt(v3_dot(a, a)); }
/* a + s*b */
static inline adem_vec3 v3_axpy(adem_vec3 a, double s, adem_vec3 b) {
  return v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
}
static inline int v3_isfinite(adem_vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static inline adem_vec3 v3_zero(void) { return v3(0.0, 0.0, 0.0); }

#endif
