/* Mesh walls in a periodic box (mesh_periodic.h): a shell that is the same all along a periodic
 * axis (a drum, a pipe, a channel's floor) needs no images, if it reaches past both faces. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "mesh_periodic.h"

/* A triangle of the shell as its cross-section sees it: the segment it projects to (endpoints
 * p < q, lexicographically) and its extent along the axis. */
typedef struct strip_tri {
  double p[2], q[2];
  double a, b, area;
} strip_tri;

static int compare_strip(const void *x, const void *y) {
  const strip_tri *s = x, *t = y;
  const double u[4] = {s->p[0], s->p[1], s->q[0], s->q[1]}, v[4] = {t->p[0], t->p[1], t->q[0], t->q[1]};
  for (int k = 0; k < 4; ++k)
    if (u[k] != v[k]) return u[k] < v[k] ? -1 : 1;
  return 0;
}

static double comp(adem_vec3 x, int d) { return d == 0 ? x.x : d == 1 ? x.y
                                                                      : x.z; }

adem_status adem_mesh_check_periodic(const adem_mesh *m, int axis, double lo, double len,
                                     double reach, adem_error *err) {
  if (m->ntris == 0) return ADEM_OK;
  double zlo = lo + reach, zhi = lo + len - reach; /* within reach of a face: outside [zlo, zhi] */
  int e1 = (axis + 1) % 3, e2 = (axis + 2) % 3;
  strip_tri *s = malloc(m->ntris * sizeof *s);
  if (!s) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory checking the periodic meshes");
  size_t n = 0;
  adem_status st = ADEM_OK;
  for (size_t t = 0; t < m->ntris && !st; ++t) {
    adem_vec3 v[3] = {m->vert[m->tri[t][0]], m->vert[m->tri[t][1]], m->vert[m->tri[t][2]]};
    double a = fmin(comp(v[0], axis), fmin(comp(v[1], axis), comp(v[2], axis)));
    double b = fmax(comp(v[0], axis), fmax(comp(v[1], axis), comp(v[2], axis)));
    if (a >= zlo && b <= zhi) continue; /* inside: never within reach of a face */
    /* STL stores float32: a normal along the axis within 1e-6 of perpendicular is a shell's */
    if (fabs(comp(m->normal[t], axis)) > 1e-6) {
      st = adem_error_set(
          err, ADEM_ERR_INPUT,
          "mesh group '%s' reaches within %g m of the periodic faces along %c and is not the same "
          "along that axis (its triangle %zu has the normal (%g, %g, %g)): meshes are not imaged "
          "across periodic faces; only a shell that is the same all along the axis (a drum, a "
          "pipe, extruded along it) and reaches %g m past both faces works. Keep other meshes "
          "%g m inside the faces, or make the axis not periodic",
          m->groups[m->group[t]].name, reach, "xyz"[axis], t, m -> normal[t].x, m->normal[t].y,
          m->normal[t].z, reach, reach);
      break;
    }
    /* the cross-section: the two projected corners farthest apart */
    double P[3][2];
    for (int k = 0; k < 3; ++k) {
      P[k][0] = comp(v[k], e1);
      P[k][1] = comp(v[k], e2);
    }
    int i0 = 0, i1 = 1;
    double best = -1.0;
    for (int x = 0; x < 3; ++x)
      for (int y = x + 1; y < 3; ++y) {
        double d2 = (P[x][0] - P[y][0]) * (P[x][0] - P[y][0]) + (P[x][1] - P[y][1]) * (P[x][1] - P[y][1]);
        if (d2 > best) best = d2, i0 = x, i1 = y;
      }
    bool swap = P[i0][0] > P[i1][0] || (P[i0][0] == P[i1][0] && P[i0][1] > P[i1][1]);
    strip_tri *r = &s[n++];
    memcpy(r->p, P[swap ? i1 : i0], sizeof r->p);
    memcpy(r->q, P[swap ? i0 : i1], sizeof r->q);
    r->a = a;
    r->b = b;
    r->area = m->area[t];
  }
  if (!st) qsort(s, n, sizeof *s, compare_strip);
  /* each strip (triangles of one segment) must tile the band [face - reach, face + reach] on
   * both faces without a gap: its area is its length times its extent, and it spans them */
  for (size_t i = 0; i < n && !st;) {
    size_t j = i;
    double a = s[i].a, b = s[i].b, area = 0.0;
    while (j < n && compare_strip(&s[i], &s[j]) == 0) {
      a = fmin(a, s[j].a);
      b = fmax(b, s[j].b);
      area += s[j].area;
      ++j;
    }
    double l = hypot(s[i].q[0] - s[i].p[0], s[i].q[1] - s[i].p[1]);
    bool spans = a <= lo - reach && b >= lo + len + reach;
    if (!spans || area < l * (b - a) * (1.0 - 1e-6))
      st = adem_error_set(
          err, ADEM_ERR_INPUT,
          "a mesh shell reaches within %g m of the periodic faces along %c but %s (its strip "
          "through (%g, %g)-(%g, %g) in the cross-section spans %g .. %g m, the box %g .. %g m): "
          "meshes are not imaged across periodic faces; a shell the same all along the axis (a "
          "drum, a pipe) must reach %g m (largest radius + skin) past both faces, from %g to %g m",
          reach, "xyz"[axis], spans ? "has a gap along the axis" : "does not reach past both faces",
          s[i].p[0], s[i].p[1], s[i].q[0], s[i].q[1], a, b, lo, lo + len, reach, lo - reach,
          lo + len + reach);
    i = j;
  }
  free(s);
  return st;
}
