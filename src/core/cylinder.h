/* Curved and bounded analytic walls, carried as planes of another shape (adem_plane_def.shape):
 * a cylinder (inside or outside, finite or infinite, open or capped) and a disc (a plane bounded
 * by an outer radius, with a circular hole, one- or two-sided: a drum's end cap, a plate with an
 * orifice). A plane's point and normal are the cylinder's axis point and direction (the disc's
 * centre and normal), so that the planes' motion, switches, stages, checkpoints and MPI sharing
 * carry them unchanged.
 *
 * The contact is at the nearest point of the surface: the gap is the distance from the sphere's
 * centre to it, n the unit vector from the centre to it (from the particle into the wall, as for a
 * plane). Where the nearest point is on a rim (an open cylinder's end, a disc's edge or hole) it
 * is the nearest point of that circle, so that a sphere rolling over a rim sees the gap and the
 * normal turn continuously. */
#ifndef ADEM_CYLINDER_H
#define ADEM_CYLINDER_H

#include <math.h>
#include <stdbool.h>

#include "adem/vec3.h"
#include "adem/world.h"
#include "walls.h"

typedef struct adem_wall_near {
  double gap;  /* distance from the centre to the nearest point; < 0: the centre is behind */
  adem_vec3 n; /* unit, from the centre towards the surface (into the wall) */
  adem_vec3 q; /* the nearest point */
  bool live;   /* false: the point cannot touch this part (a one-sided disc seen from behind off
                * its face, a capped cylinder's side beyond its ends: the cap takes the rim);
                * gap is still the distance, for the neighbour lists */
} adem_wall_near;

/* A unit vector normal to the unit vector a (for a point on the axis, where any is nearest). */
static inline adem_vec3 adem_wall_any_normal(adem_vec3 a) {
  adem_vec3 e = fabs(a.x) < 0.9 ? v3(1.0, 0.0, 0.0) : v3(0.0, 1.0, 0.0);
  adem_vec3 t = v3_axpy(e, -v3_dot(e, a), a);
  return v3_scale(t, 1.0 / v3_norm(t));
}

/* The nearest point of a circle (centre c, radius rr, in the plane normal to a at c) to x, u the
 * unit radial direction of x in that plane. */
static inline adem_wall_near adem_wall_rim(adem_vec3 x, adem_vec3 c, double rr, adem_vec3 u,
                                           adem_vec3 a) {
  adem_wall_near r;
  r.q = v3_axpy(c, rr, u);
  adem_vec3 e = v3_sub(r.q, x);
  r.gap = v3_norm(e);
  r.n = r.gap > 0.0 ? v3_scale(e, 1.0 / r.gap) : v3_neg(a);
  r.live = true;
  return r;
}

/* Where the point x is from the wall pl (placed where it is now). A plane gives the bits of the
 * plane formula: gap = (x - p).n. */
static inline adem_wall_near adem_wall_nearest(const adem_plane_def *pl, adem_vec3 x) {
  adem_wall_near r;
  adem_vec3 d = v3_sub(x, pl->point);
  double h = v3_dot(d, pl->normal);
  if (pl->shape == ADEM_WALL_PLANE) {
    r.gap = h;
    r.n = v3_neg(pl->normal);
    r.q = v3_axpy(x, -h, pl->normal);
    r.live = true;
    return r;
  }
  adem_vec3 rad = v3_axpy(d, -h, pl->normal); /* from the axis (the disc's centre), across it */
  double rho = v3_norm(rad);
  adem_vec3 u = rho > 0.0 ? v3_scale(rad, 1.0 / rho) : adem_wall_any_normal(pl->normal);
  double R = pl->radius;
  if (pl->shape == ADEM_WALL_CYLINDER) {
    double L = pl->length;
    if (L <= 0.0 || (h >= 0.0 && h <= L)) { /* beside the side: radially */
      bool out = (pl->flags & ADEM_WALL_OUTSIDE) != 0;
      r.gap = out ? rho - R : R - rho;
      r.n = out ? v3_neg(u) : u;
      r.q = v3_axpy(v3_axpy(pl->point, h, pl->normal), R, u);
      r.live = true;
      return r;
    }
    /* beyond an end: its rim circle */
    r = adem_wall_rim(x, v3_axpy(pl->point, h < 0.0 ? 0.0 : L, pl->normal), R, u, pl->normal);
    r.live = !(pl->flags & ADEM_WALL_CAPPED);
    return r;
  }
  /* a disc: over its face, or at its hole's or outer rim */
  double rh = pl->hole_radius;
  bool two = (pl->flags & ADEM_WALL_TWO_SIDED) != 0;
  if (rho >= rh && (R <= 0.0 || rho <= R)) {
    bool behind = two && h < 0.0; /* a sheet: the side the centre is on */
    r.gap = behind ? -h : h;
    r.n = behind ? pl->normal : v3_neg(pl->normal);
    r.q = v3_axpy(x, -h, pl->normal);
    r.live = true;
    return r;
  }
  r = adem_wall_rim(x, pl->point, rho < rh ? rh : R, u, pl->normal);
  r.live = two || h >= 0.0; /* one-sided: behind it, off its face, nothing to touch */
  return r;
}

/* The gap the contact sees (a part that cannot be touched: never less than the radius r). */
static inline double adem_wall_contact_gap(const adem_wall_near *c, double r) {
  return c->live ? c->gap : fmax(c->gap, r);
}

/* Whether the wall's surface is the same at every rotation of its motion (a cylinder or a disc
 * turning about its own axis): its surface does not sweep the domain. */
static inline bool adem_wall_turns_in_place(const adem_plane_def *pl, adem_vec3 axis,
                                            adem_vec3 center) {
  if (pl->shape == ADEM_WALL_PLANE) return false;
  adem_vec3 a = pl->normal, off = v3_sub(center, pl->point);
  adem_vec3 cr = v3_cross(axis, a), off_n = v3_axpy(off, -v3_dot(off, a), a);
  double scale = fmax(pl->radius, pl->hole_radius) + 1e-300;
  return v3_norm(cr) <= 1e-12 && v3_norm(off_n) <= 1e-12 * scale;
}

/* A cylinder or disc the case can build: radius > 0 (a disc's >= 0, above its hole), length >= 0,
 * caps only on a finite cylinder. A plane passes. */
adem_status adem_wall_check_shape(const adem_plane_def *d, adem_error *err);
/* A box around the wall's finite part (a plane: its point; an infinite cylinder: its circle at
 * the point), for the escape domain. */
void adem_wall_bounds(const adem_plane_def *d, adem_vec3 *lo, adem_vec3 *hi);
/* A cylinder or disc in a box periodic along `axis` (0..2): accepted if it is the same in every
 * image (an infinite cylinder along the axis) or stays reach inside the faces; refused with a
 * message saying which otherwise. */
adem_status adem_wall_check_periodic(const adem_plane_def *d, int axis, double box_lo,
                                     double box_len, double reach, adem_error *err);
/* A cylinder or disc whose rotation is about its own axis: the rotation moves no point of its
 * surface (the neighbour skin need not cover a sweep). */
bool adem_wall_plane_turns_in_place(const adem_plane *pl);
/* Torque of the particles on every plane wall (nplanes entries) about the wall's point where it
 * is now, summed over the particles by id: a cylinder's about its axis point. */
void adem_world_plane_torques(const adem_world *w, adem_vec3 *out);

#endif
