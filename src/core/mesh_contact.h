/* Sphere-triangle contact geometry: the closest point on a triangle with the feature it lies on,
 * and the one-contact-per-region rule that turns a sphere's candidate triangles into distinct
 * contacts. Pure inline functions: mesh and sphere in, contacts out. Contacts are two-sided: the
 * normal points from the sphere centre to the closest point, whichever side the centre is on. */
#ifndef ADEM_MESH_CONTACT_H
#define ADEM_MESH_CONTACT_H

#include <math.h>
#include <stdint.h>

#include "mesh.h"
#include "adem/vec3.h"

/* Where on a triangle a closest point lies. Edge k joins vertices k and (k + 1) % 3. */
typedef enum adem_triangle_feature {
  ADEM_TRIANGLE_FACE = 0,
  ADEM_TRIANGLE_EDGE0 = 1,
  ADEM_TRIANGLE_EDGE1 = 2,
  ADEM_TRIANGLE_EDGE2 = 3,
  ADEM_TRIANGLE_VERTEX0 = 4,
  ADEM_TRIANGLE_VERTEX1 = 5,
  ADEM_TRIANGLE_VERTEX2 = 6
} adem_triangle_feature;

static inline int adem_triangle_feature_is_edge(adem_triangle_feature f) {
  return f >= ADEM_TRIANGLE_EDGE0 && f <= ADEM_TRIANGLE_EDGE2;
}
static inline int adem_triangle_feature_is_vertex(adem_triangle_feature f) {
  return f >= ADEM_TRIANGLE_VERTEX0;
}

/* Closest point on segment a + t (b - a) to p, t clamped to [0, 1]; *t returned. */
static inline adem_vec3 adem_triangle_segment_closest(adem_vec3 p, adem_vec3 a, adem_vec3 b,
                                                      double *t) {
  adem_vec3 ab = v3_sub(b, a);
  double l2 = v3_norm2(ab);
  double s = l2 > 0.0 ? v3_dot(v3_sub(p, a), ab) / l2 : 0.0;
  s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0
                              : s;
  *t = s;
  return s == 0.0 ? a : s == 1.0 ? b
                                 : v3_axpy(a, s, ab);
}

/* Closest point on triangle abc to p, by the Voronoi-region tests on barycentric coordinates
 * (Ericson, Real-Time Collision Detection, 5.1.5). Every division is by a quantity the region test
 * has shown positive; a guard catches what rounding could still make zero (p very far from a tiny
 * triangle) and falls back to the nearest edge. */
static inline adem_vec3 adem_triangle_closest_point(adem_vec3 p, adem_vec3 a, adem_vec3 b,
                                                    adem_vec3 c, adem_triangle_feature *feature) {
  adem_vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), ap = v3_sub(p, a);
  double d1 = v3_dot(ab, ap), d2 = v3_dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    *feature = ADEM_TRIANGLE_VERTEX0;
    return a;
  }
  adem_vec3 bp = v3_sub(p, b);
  double d3 = v3_dot(ab, bp), d4 = v3_dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) {
    *feature = ADEM_TRIANGLE_VERTEX1;
    return b;
  }
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    *feature = ADEM_TRIANGLE_EDGE0;
    return v3_axpy(a, d1 / (d1 - d3), ab);
  }
  adem_vec3 cp = v3_sub(p, c);
  double d5 = v3_dot(ab, cp), d6 = v3_dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) {
    *feature = ADEM_TRIANGLE_VERTEX2;
    return c;
  }
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    *feature = ADEM_TRIANGLE_EDGE2;
    return v3_axpy(a, d2 / (d2 - d6), ac);
  }
  double va = d3 * d6 - d5 * d4;
  double e43 = d4 - d3, e56 = d5 - d6;
  if (va <= 0.0 && e43 >= 0.0 && e56 >= 0.0 && e43 + e56 > 0.0) {
    *feature = ADEM_TRIANGLE_EDGE1;
    return v3_axpy(b, e43 / (e43 + e56), v3_sub(c, b));
  }
  double sum = va + vb + vc;
  if (va > 0.0 && vb > 0.0 && vc > 0.0 && sum > 0.0) {
    *feature = ADEM_TRIANGLE_FACE;
    double v = vb / sum, w = vc / sum;
    return v3_add(a, v3_add(v3_scale(ab, v), v3_scale(ac, w)));
  }
  /* Rounding left no region: the nearest of the three edges is within rounding of the answer. */
  adem_vec3 best = a;
  double best2 = INFINITY;
  *feature = ADEM_TRIANGLE_VERTEX0; /* p not finite: no comparison succeeds */
  const adem_vec3 s0[3] = {a, b, c}, s1[3] = {b, c, a};
  for (int k = 0; k < 3; ++k) {
    double t;
    adem_vec3 q = adem_triangle_segment_closest(p, s0[k], s1[k], &t);
    double d = v3_norm2(v3_sub(q, p));
    if (d < best2) {
      best2 = d;
      best = q;
      *feature = t == 0.0   ? (adem_triangle_feature)(ADEM_TRIANGLE_VERTEX0 + k)
                 : t == 1.0 ? (adem_triangle_feature)(ADEM_TRIANGLE_VERTEX0 + (k + 1) % 3)
                            : (adem_triangle_feature)(ADEM_TRIANGLE_EDGE0 + k);
    }
  }
  return best;
}

/* Closest point of mesh triangle t to p; returns the squared distance. */
static inline double adem_triangle_distance2(const adem_mesh *m, uint32_t t, adem_vec3 p,
                                             adem_vec3 *q, adem_triangle_feature *f) {
  const uint32_t *v = m->tri[t];
  *q = adem_triangle_closest_point(p, m->vert[v[0]], m->vert[v[1]], m->vert[v[2]], f);
  return v3_norm2(v3_sub(*q, p));
}

/* What a contact touches; the high half of its key. */
typedef enum adem_mesh_contact_kind {
  ADEM_MESH_CONTACT_PLANE = 0, /* a face, or an edge or vertex inside a flat region: key = region */
  ADEM_MESH_CONTACT_EDGE = 1,  /* a non-flat edge: key = edge id */
  ADEM_MESH_CONTACT_VERTEX = 2 /* a vertex that is not inside a flat region: key = vertex index */
} adem_mesh_contact_kind;

/* Region key: kind in the high 32 bits, the region/edge/vertex index in the low ones. Stable while
 * a contact slides within a flat region, so contact history can stay keyed by it. */
static inline uint64_t adem_mesh_contact_key(adem_mesh_contact_kind kind, uint32_t id) {
  return (uint64_t)kind << 32 | (uint64_t)id;
}
static inline adem_mesh_contact_kind adem_mesh_contact_key_kind(uint64_t key) {
  return (adem_mesh_contact_kind)(key >> 32);
}

/* One sphere-mesh contact, in the conventions of contact_force.h (n from the particle into the wall). */
typedef struct adem_mesh_contact {
  adem_vec3 point;               /* on the mesh surface */
  adem_vec3 normal;              /* unit, from the sphere centre towards point */
  double overlap;                /* radius - distance, > 0 */
  uint32_t tri;                  /* owning triangle (its group gives the material) */
  adem_triangle_feature feature; /* where on tri the closest point lies */
  uint64_t key;                  /* region key, unique among one sphere's contacts */
} adem_mesh_contact;

/* Insertion sort of a few contacts: by key, then deepest, then triangle (by_depth = 0); or deepest,
 * then key, then triangle (by_depth = 1). */
static inline int adem_mesh_contact_before(const adem_mesh_contact *a, const adem_mesh_contact *b,
                                           int by_depth) {
  if (by_depth && a->overlap != b->overlap) return a->overlap > b->overlap;
  if (a->key != b->key) return a->key < b->key;
  if (a->overlap != b->overlap) return a->overlap > b->overlap;
  return a->tri < b->tri;
}

static inline void adem_mesh_contact_sort(adem_mesh_contact *c, size_t n, int by_depth) {
  for (size_t i = 1; i < n; ++i) {
    adem_mesh_contact x = c[i];
    size_t j = i;
    while (j > 0 && adem_mesh_contact_before(&x, &c[j - 1], by_depth)) {
      c[j] = c[j - 1];
      --j;
    }
    c[j] = x;
  }
}

/* 1 if no other triangle at the edge (both of its vertices) or at the vertex is strictly closer to
 * p than d2: the feature's point is then a local minimum of the distance to the surface. Each
 * triangle is convex, so a strictly closer neighbour means the point is not where the sphere
 * touches; a tie means the neighbour's closest point is the same point. */
static inline int adem_triangle_feature_is_local_min(const adem_mesh *m, uint32_t t,
                                                     adem_triangle_feature f, adem_vec3 p,
                                                     double d2) {
  int edge = adem_triangle_feature_is_edge(f);
  int k = edge ? (int)f - ADEM_TRIANGLE_EDGE0 : (int)f - ADEM_TRIANGLE_VERTEX0;
  uint32_t va = m->tri[t][k], vb = edge ? m->tri[t][(k + 1) % 3] : va;
  for (size_t i = m->vt_start[va]; i < m->vt_start[va + 1]; ++i) {
    uint32_t s = m->vt_tri[i];
    if (s == t) continue;
    if (edge && m->tri[s][0] != vb && m->tri[s][1] != vb && m->tri[s][2] != vb) continue;
    adem_vec3 q;
    adem_triangle_feature fs;
    if (adem_triangle_distance2(m, s, p, &q, &fs) < d2) return 0;
  }
  return 1;
}

/* The distinct contacts of a sphere with a mesh. cand lists the triangles to test: it must hold
 * every triangle closer than radius to centre (more, or repeats, are fine; order does not matter).
 * out must have room for ncand contacts; returns how many were written, sorted by key.
 *   1. Each candidate's closest point within radius is a face, edge or vertex contact.
 *   2. An edge or vertex contact is dropped if a triangle sharing that edge or vertex is strictly
 *      closer: it is then not where the sphere touches (a convex edge under a face contact).
 *   3. Face contacts, and edge or vertex contacts inside a flat region, are plane contacts keyed by
 *      the region and computed exactly as an infinite plane would be (normal of the triangle,
 *      signed distance of the centre); other edge and vertex contacts are keyed by the edge or
 *      vertex, with the normal along centre -> point.
 *   4. One contact per key (the deepest), then contacts whose points coincide within 1e-6 radius
 *      (a point on the boundary of two features, seen differently by two triangles) are one. */
static inline size_t adem_triangle_sphere_contacts(const adem_mesh *m, adem_vec3 centre,
                                                   double radius, const uint32_t *cand,
                                                   size_t ncand, adem_mesh_contact *out) {
  size_t n = 0;
  double r2 = radius * radius;
  for (size_t i = 0; i < ncand; ++i) {
    uint32_t t = cand[i];
    adem_vec3 q;
    adem_triangle_feature f;
    double d2 = adem_triangle_distance2(m, t, centre, &q, &f);
    if (!(d2 < r2)) continue;
    int edge = adem_triangle_feature_is_edge(f), vertex = adem_triangle_feature_is_vertex(f);
    if ((edge || vertex) && !adem_triangle_feature_is_local_min(m, t, f, centre, d2)) continue;
    int k = edge ? (int)f - ADEM_TRIANGLE_EDGE0 : vertex ? (int)f - ADEM_TRIANGLE_VERTEX0
                                                         : 0;
    int plane = f == ADEM_TRIANGLE_FACE || (edge && m->edge_kind[t][k] == ADEM_MESH_EDGE_FLAT) ||
                (vertex && m->vert_flat[m->tri[t][k]]);
    adem_mesh_contact c;
    c.tri = t;
    c.feature = f;
    adem_vec3 nt = m->normal[t];
    if (plane) {
      /* As force_pass.c does for a plane: signed distance of the centre, normal into the wall. */
      double h = v3_dot(v3_sub(centre, m->vert[m->tri[t][0]]), nt);
      double dist = fabs(h);
      if (!(dist < radius)) continue;
      c.normal = h >= 0.0 ? v3_neg(nt) : nt;
      c.overlap = radius - dist;
      c.point = v3_axpy(centre, dist, c.normal);
      c.key = adem_mesh_contact_key(ADEM_MESH_CONTACT_PLANE, m->region[t]);
    } else {
      double d = sqrt(d2);
      /* A centre exactly on the edge has no direction: take the face's, as for a plane. */
      c.normal = d > 0.0 ? v3_scale(v3_sub(q, centre), 1.0 / d)
                         : (v3_dot(v3_sub(centre, m->vert[m->tri[t][0]]), nt) >= 0.0 ? v3_neg(nt) : nt);
      c.overlap = radius - d;
      c.point = q;
      c.key = edge ? adem_mesh_contact_key(ADEM_MESH_CONTACT_EDGE, m->edge_id[t][k])
                   : adem_mesh_contact_key(ADEM_MESH_CONTACT_VERTEX, m->tri[t][k]);
    }
    out[n++] = c;
  }
  /* One contact per key, the deepest; the order of the candidates does not matter. */
  adem_mesh_contact_sort(out, n, 0);
  size_t u = 0;
  for (size_t i = 0; i < n; ++i)
    if (u == 0 || out[i].key != out[u - 1].key) out[u++] = out[i];
  /* Coincident points (one point seen as different features by two triangles): the deepest. */
  adem_mesh_contact_sort(out, u, 1);
  double eps2 = 1e-12 * r2; /* (1e-6 radius)^2 */
  n = 0;
  for (size_t i = 0; i < u; ++i) {
    int same = 0;
    for (size_t j = 0; j < n && !same; ++j) same = v3_norm2(v3_sub(out[i].point, out[j].point)) <= eps2;
    if (!same) out[n++] = out[i];
  }
  adem_mesh_contact_sort(out, n, 0);
  return n;
}

#endif
