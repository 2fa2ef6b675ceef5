/* Cylinder and disc walls (cylinder.h): their checks, bounds, periodic images and loads. */
#include <math.h>
#include <string.h>

#include "cylinder.h"
#include "world_internal.h"

adem_status adem_wall_check_shape(const adem_plane_def *d, adem_error *err) {
  switch (d->shape) {
    case ADEM_WALL_PLANE:
      return ADEM_OK;
    case ADEM_WALL_CYLINDER:
      if (!(d->radius > 0.0) || !isfinite(d->radius) || !(d->length >= 0.0) || !isfinite(d->length))
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "cylinder wall '%s': the radius must be > 0 and the length >= 0 "
                              "(0: infinite), both finite",
                              d->name);
      if ((d->flags & ADEM_WALL_CAPPED) && d->length <= 0.0)
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "cylinder wall '%s': end caps need a finite length", d->name);
      return ADEM_OK;
    case ADEM_WALL_DISC:
      if (!(d->radius >= 0.0) || !isfinite(d->radius) || !(d->hole_radius >= 0.0) ||
          !isfinite(d->hole_radius) || (d->radius > 0.0 && d->hole_radius >= d->radius))
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "plate wall '%s': the hole radius (%g m) must be >= 0 and below the "
                              "outer radius (%g m; 0: unbounded)",
                              d->name, d->hole_radius, d->radius);
      return ADEM_OK;
    default:
      return adem_error_set(err, ADEM_ERR_INPUT, "wall '%s': unknown shape %d", d->name, d->shape);
  }
}

/* Half the extent along axis k of a circle of radius r whose plane has the unit normal a. */
static double circle_half(adem_vec3 a, int k, double r) {
  double c = k == 0 ? a.x : k == 1 ? a.y
                                   : a.z;
  return r * sqrt(fmax(0.0, 1.0 - c * c));
}

void adem_wall_bounds(const adem_plane_def *d, adem_vec3 *lo, adem_vec3 *hi) {
  *lo = *hi = d->point;
  if (d->shape == ADEM_WALL_PLANE) return;
  adem_vec3 a = d->normal;
  double r = d->shape == ADEM_WALL_CYLINDER ? d->radius : fmax(d->radius, d->hole_radius);
  adem_vec3 p1 = d->shape == ADEM_WALL_CYLINDER ? v3_axpy(d->point, d->length, a) : d->point;
  double l[3], h[3];
  const double p0v[3] = {d->point.x, d->point.y, d->point.z}, p1v[3] = {p1.x, p1.y, p1.z};
  for (int k = 0; k < 3; ++k) {
    double e = circle_half(a, k, r);
    l[k] = fmin(p0v[k], p1v[k]) - e;
    h[k] = fmax(p0v[k], p1v[k]) + e;
  }
  *lo = v3(l[0], l[1], l[2]);
  *hi = v3(h[0], h[1], h[2]);
}

adem_status adem_wall_check_periodic(const adem_plane_def *d, int axis, double box_lo,
                                     double box_len, double reach, adem_error *err) {
  const double a[3] = {d->normal.x, d->normal.y, d->normal.z};
  bool cyl = d->shape == ADEM_WALL_CYLINDER;
  /* An infinite cylinder along the periodic axis is its own image: nothing to do. */
  if (cyl && d->length <= 0.0 && fabs(a[axis]) >= 1.0 - 1e-12) return ADEM_OK;
  /* Unbounded along the axis: an infinite cylinder across it, an unbounded plate not parallel. */
  bool unbounded = cyl ? d->length <= 0.0 && fabs(a[axis]) > 1e-12
                       : d->radius <= 0.0 && fabs(a[axis]) > 1e-12;
  adem_vec3 lo, hi;
  adem_wall_bounds(d, &lo, &hi);
  double l = axis == 0 ? lo.x : axis == 1 ? lo.y
                                          : lo.z,
         h = axis == 0 ? hi.x : axis == 1 ? hi.y
                                          : hi.z;
  if (!cyl && d->radius <= 0.0 && !unbounded) {
    /* an unbounded plate parallel to the axis: only its hole is not imaged */
    if (d->hole_radius <= 0.0) return ADEM_OK;
  }
  if (unbounded || l < box_lo + reach || h > box_lo + box_len - reach)
    return adem_error_set(
        err, ADEM_ERR_INPUT,
        "%s wall '%s' reaches across the periodic faces along %c (it spans %g .. %g m, the box "
        "%g .. %g m): curved walls are not imaged; only an infinite cylinder (no `length`) whose "
        "axis is the periodic axis is the same in every image. Keep other cylinders and plates "
        "%g m (largest radius + skin) inside the faces, or make the axis not periodic",
        cyl ? "cylinder" : "plate", d->name, "xyz"[axis], unbounded ? -INFINITY : l,
        unbounded ? INFINITY : h, box_lo, box_lo + box_len, reach);
  return ADEM_OK;
}

bool adem_wall_plane_turns_in_place(const adem_plane *pl) {
  const adem_motion *mo = &pl->motion;
  if (pl->def.shape == ADEM_WALL_PLANE || mo->omega == 0.0) return false;
  adem_plane_def d0 = pl->def;
  d0.point = pl->point0;
  d0.normal = pl->normal0;
  return adem_wall_turns_in_place(&d0, mo->axis, mo->center);
}

/* The torque of the particles on each plane wall about its point where it is now: the opposite
 * of each contact's force at its contact point (x_i + r_i n: (x_i - p) x F + r_i n x F_t) and of
 * its rolling couple, summed over the particles by id (the CSV's order, any thread count). */
void adem_world_plane_torques(const adem_world *w, adem_vec3 *out) {
  for (int k = 0; k < w->walls.nplanes; ++k) out[k] = v3_zero();
  const adem_pair_list *l = &w->pw;
  const adem_neighbors *nb = &w->nb;
  const adem_particles *p = &w->p;
  for (size_t r = 0; r < nb->gathered; ++r) {
    size_t i = nb->id_order[r];
    for (size_t e = nb->pw_start[i]; e < nb->pw_start[i + 1]; ++e) {
      size_t k = nb->pw_entries[e];
      uint32_t wall = l->b[k];
      if (wall >= (uint32_t)w->walls.nplanes || !l->touching[k]) continue;
      const adem_pair_result *res = &l->res[k];
      adem_vec3 arm = v3_sub(p->pos[i], w->walls.planes[wall].def.point);
      adem_vec3 t = v3_add(v3_cross(arm, res->force_a), v3_scale(res->moment, p->radius[i]));
      out[wall] = v3_sub(out[wall], v3_add(t, res->rolling_a));
    }
  }
}

double adem_world_plane_rotation(const adem_world *w, int index, adem_vec3 *axis,
                                 adem_vec3 *center) {
  if (index < 0 || index >= w->walls.nplanes) return 0.0;
  const adem_motion *mo = &w->walls.planes[index].motion;
  if (axis) *axis = mo->axis;
  if (center) *center = adem_motion_place(mo, w->walls.time, mo->center);
  return mo->omega;
}

adem_vec3 adem_world_gravity(const adem_world *w) { return w->gravity; }
