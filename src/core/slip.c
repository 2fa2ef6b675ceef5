/* How fast the wall layer slips on a wall: the mean over the particles that touch it (a plane, a
 * mesh group's faces, or a frozen particle attached to it) of the tangential part of their
 * centre's velocity relative to the wall's material there, v - v_wall(x), the contact normal's
 * component removed. A rough wall that drags its layer along reads near 0; a smooth drum whose
 * bed slips reads a large fraction of the wall's speed. */
#include <math.h>
#include <stdlib.h>

#include "mesh_contact.h"
#include "world_internal.h"

static adem_vec3 tangential(adem_vec3 v, adem_vec3 n) { return v3_sub(v, v3_scale(n, v3_dot(v, n))); }

static adem_vec3 wall_velocity(const adem_motion *m, double t, adem_vec3 x) {
  return m && m->moving ? adem_motion_point_velocity(m, t, x) : v3_zero();
}

void adem_world_wall_slip(const adem_world *w, double *plane_slip, double *group_slip) {
  const adem_particles *p = &w->p;
  const adem_walls *wl = &w->walls;
  const adem_neighbors *nb = &w->nb;
  int np = wl->nplanes, ng = wl->mesh.ngroups;
  double *sum = calloc((size_t)(np + ng) + 1, sizeof *sum);
  double *cnt = calloc((size_t)(np + ng) + 1, sizeof *cnt);
  int *seen = malloc(((size_t)(np + ng) + 1) * sizeof *seen);
  bool ok = sum && cnt && seen;
  for (int s = 0; ok && s < np + ng; ++s) seen[s] = -1;
  double t = wl->time;
  for (size_t r = 0; ok && r < nb->gathered; ++r) {
    size_t i = nb->id_order[r];
    if (p->frozen[i]) continue;
    adem_vec3 x = p->pos[i];
    /* each wall once per particle: the first contact found gives the normal */
#define TAKE(slot, motion, normal)                                   \
  do {                                                               \
    if (seen[slot] != (int)r) {                                      \
      seen[slot] = (int)r;                                           \
      adem_vec3 vr = v3_sub(p->vel[i], wall_velocity(motion, t, x)); \
      sum[slot] += v3_norm(tangential(vr, normal));                  \
      cnt[slot] += 1.0;                                              \
    }                                                                \
  } while (0)
    for (size_t e = nb->pw_start[i]; e < nb->pw_start[i + 1]; ++e) {
      size_t k = nb->pw_entries[e];
      uint32_t b = w->pw.b[k];
      if (!w->pw.touching[k] || b >= (uint32_t)np) continue;
      TAKE((int)b, &wl->planes[b].motion, wl->planes[b].def.normal);
    }
    if (w->pm.start)
      for (size_t k = w->pm.start[i]; k < w->pm.start[i + 1]; ++k) {
        if (!w->pm.l.touching[k]) break; /* the touching slots come first */
        uint32_t tri = w->pm.owner[k];
        if (tri >= wl->mesh.ntris) continue;
        int g = (int)wl->mesh.group[tri];
        adem_vec3 q;
        adem_triangle_feature f;
        adem_triangle_distance2(&wl->mesh, tri, x, &q, &f);
        adem_vec3 d = v3_sub(x, q);
        double dn = v3_norm(d);
        adem_vec3 n = dn > 0.0 ? v3_scale(d, 1.0 / dn) : wl->mesh.normal[tri];
        TAKE(np + g, &wl->mesh_motion[g], n);
      }
    for (size_t e = nb->pp_start[i]; e < nb->pp_start[i + 1]; ++e) {
      uint32_t code = nb->pp_entries[e];
      size_t k = code >> 1, j = (code & 1u) ? w->pp.a[k] : w->pp.b[k];
      if (!w->pp.touching[k] || !p->frozen[j]) continue;
      int32_t a = adem_particles_attach(p, j);
      int slot = a > 0 ? np + a - 1 : a < 0 ? -a - 1
                                            : -1;
      if (slot < 0 || slot >= np + ng) continue;
      const adem_motion *m = a > 0 ? &wl->mesh_motion[a - 1] : &wl->planes[-a - 1].motion;
      adem_vec3 d = adem_periodic_min_image(&w->periodic, v3_sub(x, p->pos[j]));
      double dn = v3_norm(d);
      if (dn > 0.0) TAKE(slot, m, v3_scale(d, 1.0 / dn));
    }
#undef TAKE
  }
  for (int s = 0; s < np + ng; ++s) {
    double v = ok && cnt[s] > 0.0 ? sum[s] / cnt[s] : NAN;
    if (s < np && plane_slip) plane_slip[s] = v;
    if (s >= np && group_slip) group_slip[s - np] = v;
  }
  free(sum);
  free(cnt);
  free(seen);
}
