/* `adem check`: what a loaded and prepared case will do, as text. */
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/case.h"
#include "adem/laws.h"
#include "adem/run.h"
#include "adem/world.h"
#include "adem/vec3.h"
#include "insert.h"
#include "log.h"
#include "schedule.h"
#include "stages.h"
#include "world_internal.h"

static double mib(double bytes) { return bytes / (1024.0 * 1024.0); }

/* "12.3 MiB", or KiB below a MiB. */
static const char *mem_text(char *buf, size_t n, double bytes) {
  if (bytes < 1024.0 * 1024.0) snprintf(buf, n, "%.1f KiB", bytes / 1024.0);
  else snprintf(buf, n, "%.1f MiB", mib(bytes));
  return buf;
}


/* The report hooks' sink: lines indented under the pair's row, warnings to the log. */
typedef struct report_sink {
  FILE *f;
} report_sink;

static void sink_line(void *ctx, const char *text) {
  fprintf(((report_sink *)ctx)->f, "  %-26s %s\n", "", text);
}

static void sink_warn(void *ctx, const char *text) {
  fflush(((report_sink *)ctx)->f);
  adem_log(ADEM_LOG_WARN, "%s", text);
}

/* What the pair's laws say of it at its smallest spheres (their report hooks: a JKR pair's real
 * and modified values, notes sections 1, 5, 6; H section 6.2). */
static void print_laws(FILE *f, const adem_world *w, int a, int b, bool wall, const double *rmin,
                       double v_ref, const char *pair) {
  const adem_interaction *it = adem_world_interaction(w, a, b);
  double ra = rmin[a], ma = w->mat.m[a].def.density * (4.0 / 3.0) * ADEM_PI * ra * ra * ra;
  double R = ra, mstar = ma;
  if (!wall) {
    double rb = rmin[b], mb = w->mat.m[b].def.density * (4.0 / 3.0) * ADEM_PI * rb * rb * rb;
    R = ra * rb / (ra + rb);
    mstar = ma * mb / (ma + mb);
  }
  report_sink sink = {f};
  adem_law_report r = {&it->pp, R, mstar, v_ref, wall, pair, NULL, 0.0, 0.0, "",
                       sink_line, sink_warn, &sink};
  adem_laws_report(adem_interaction_laws(it), &r);
}

/* The rolling friction eta_r a pair's rolling law uses (the rule of the rolling_friction row in
 * adem/laws.h): the law's combination of the two sides (by default the mean eta_r with
 * R_r = r_i r_j/(r_i + r_j)); on a wall the particle's eta_r with r_i, the wall material's
 * unused; an interaction entry's value replaces both sides'. */
static void print_rolling_friction(FILE *f, const adem_world *w, int a, int b, bool wall) {
  const adem_interaction *it = adem_world_interaction(w, a, b);
  const adem_law *law = adem_law_get(ADEM_SLOT_ROLLING, (int)it->rolling);
  if (!law || !adem_law_reads(law, "rolling_friction")) return;
  const int k = ADEM_PARAM_ROLLING_FRICTION;
  double ea = it->pp.param_a[k], eb = it->pp.param_b[k];
  const char *na = w->mat.m[a].def.name, *nb = w->mat.m[b].def.name;
  char from[2 * ADEM_NAME_MAX + 96];
  if (it->set_param[k])
    snprintf(from, sizeof from, "the interaction entry's value, for both sides");
  else if (wall)
    snprintf(from, sizeof from, "`%s`'s value; the wall material `%s`'s (%g) is not used", na, nb,
             w->mat.m[b].def.param[k]);
  else if (a == b)
    snprintf(from, sizeof from, "`%s`'s value", na);
  else
    snprintf(from, sizeof from, "`%s`'s and `%s`'s values", na, nb);
  if (wall) {
    fprintf(f, "  %-26s rolling friction eta_r = %g, e_c = %g r_i (%s)\n", "", ea, ea, from);
    return;
  }
  /* how the law combines the two sides (its hook: BROF's min(eta_i r_i, eta_j r_j)) */
  report_sink sink = {f};
  adem_law_report r = {&it->pp, 0.0, 0.0, 0.0, wall, "", NULL, ea, eb, from,
                       sink_line, sink_warn, &sink};
  adem_laws_friction_line(adem_interaction_laws(it), &r);
}

static void print_pair(FILE *f, const adem_world *w, int a, int b, bool wall, const double *rmin,
                       const double *rmax, double v_ref) {
  const adem_interaction *it = adem_world_interaction(w, a, b);
  double Rlo, Rhi;
  if (wall) {
    Rlo = rmin[a];
    Rhi = rmax[a];
  } else {
    Rlo = rmin[a] * rmin[b] / (rmin[a] + rmin[b]);
    Rhi = rmax[a] * rmax[b] / (rmax[a] + rmax[b]);
  }
  char name[2 * ADEM_NAME_MAX + 16];
  snprintf(name, sizeof name, "%s-%s%s", w->mat.m[a].def.name, w->mat.m[b].def.name,
           wall ? " (wall)" : "");
  char R[64];
  if (Rlo == Rhi) snprintf(R, sizeof R, "%.4g", Rlo);
  else snprintf(R, sizeof R, "%.4g..%.4g", Rlo, Rhi);
  fprintf(f, "  %-26s %-11.4g %-11.4g %-21s %-6.3g %-9.4g %-6.3g %-6s %s\n", name, it->pp.E, it->pp.G, R,
          it->pp.restitution, it->pp.beta, it->pp.friction, adem_law_get(ADEM_SLOT_NORMAL, (int)it->normal)->name,
          adem_law_get(ADEM_SLOT_ROLLING, (int)it->rolling)->name);
  if (it->pp.E != it->pp.E_real)
    fprintf(f, "  %-26s real material: E* = %.4g Pa, G* = %.4g Pa (stiffness reduced, H24)\n", "",
            it->pp.E_real, it->pp.G_real);
  print_rolling_friction(f, w, a, b, wall);
  if (it->set_restitution || it->set_friction)
    fprintf(f, "  %-26s %s from the interaction entry (not the materials' mean)\n", "",
            !it->set_friction ? "e" : !it->set_restitution ? "mu"
                                                           : "e and mu");
  print_laws(f, w, a, b, wall, rmin, v_ref, name);
}

/* ---------------------------------------------------------------- geometry */

static void print_vec(FILE *f, adem_vec3 x) { fprintf(f, "(%.4g, %.4g, %.4g)", x.x, x.y, x.z); }

/* Bounding box of a mesh group's triangles at time 0. */
static void group_box(const adem_world *w, int g, adem_vec3 *lo, adem_vec3 *hi) {
  const adem_mesh *m = &w->walls.mesh;
  const adem_mesh_group *grp = &m->groups[g];
  *lo = v3(INFINITY, INFINITY, INFINITY);
  *hi = v3(-INFINITY, -INFINITY, -INFINITY);
  for (uint32_t t = grp->first; t < grp->first + grp->count; ++t)
    for (int k = 0; k < 3; ++k) {
      adem_vec3 x = w->walls.mesh_vert0[m->tri[t][k]];
      *lo = v3(fmin(lo->x, x.x), fmin(lo->y, x.y), fmin(lo->z, x.z));
      *hi = v3(fmax(hi->x, x.x), fmax(hi->y, x.y), fmax(hi->z, x.z));
    }
}

/* The motion and on/off state of plane k (mesh: false) or mesh group k in stage j (-1: the case
 * as written, or the world's own when there are no stages). */
static const adem_motion *wall_motion(const adem_case *c, bool mesh, int k, int j, bool *inactive,
                                      const adem_vec3 **point0) {
  const adem_walls *wl = &c->world->walls;
  const adem_stage_config *g = NULL;
  if (c->stages && c->stages->n > 0) g = j < 0 ? &c->stages->base : &c->stages->s[j].config;
  *point0 = NULL;
  if (mesh) {
    if (!g) {
      *inactive = !adem_walls_mesh_active(wl, (uint32_t)k);
      return &wl->mesh_motion[k];
    }
    *inactive = g->meshes[k].inactive;
    return &g->meshes[k].motion;
  }
  if (!g) {
    *inactive = wl->planes[k].inactive;
    *point0 = &wl->planes[k].point0;
    return &wl->planes[k].motion;
  }
  *inactive = g->planes[k].inactive;
  *point0 = &g->planes[k].point0;
  return &g->planes[k].motion;
}

/* Where a moving wall's reference point (a plane's point, a mesh group's box centre) is over
 * the run: at t = 0, at the knots of its motion table, where a stage gives it a new motion, and
 * at the end; and when stages switch it off or on. Follows the engine's rule: a new motion
 * starts where the wall is, its table's times counting from the stage's start. */
static void print_wall_path(FILE *f, const adem_case *c, bool mesh, int k, adem_vec3 ref) {
  const adem_world *w = c->world;
  int nst = c->stages ? c->stages->n : 0;
  double t_end = (double)adem_schedule_total_steps(c->end_time, w->dt) * w->dt;
  bool any_motion = false, any_switch = false, inactive0, inactive;
  const adem_vec3 *p0;
  const adem_motion *m0 = wall_motion(c, mesh, k, -1, &inactive0, &p0);
  any_motion = m0->moving;
  for (int j = 0; j < nst; ++j) {
    const adem_motion *mj = wall_motion(c, mesh, k, j, &inactive, &p0);
    any_motion |= mj->moving;
    any_switch |= inactive != inactive0;
  }
  if (!any_motion && !any_switch) return;
  const char *name = mesh ? w->walls.mesh.groups[k].name : w->walls.planes[k].def.name;
  fprintf(f, "    %s (%s): ", name, mesh ? "mesh group, centre of its box" : "plane, its point");
  /* segments: stage j's motion from its start; the case's own before the first stage */
  enum { MAX_POINTS = 24 };
  double tp[MAX_POINTS];
  adem_vec3 xp[MAX_POINTS];
  int np = 0;
  adem_vec3 anchor = ref;
  adem_motion cur = nst ? *wall_motion(c, mesh, k, 0, &inactive, &p0) : *m0; /* shallow, read only */
  tp[np] = 0.0;
  xp[np++] = adem_motion_place(&cur, 0.0, anchor);
  for (int j = 0; j < (nst ? nst : 1); ++j) {
    double ws = (double)adem_stages_start_step(c, j) * w->dt;
    double we = j + 1 < nst ? (double)adem_stages_start_step(c, j + 1) * w->dt : t_end;
    if (ws >= t_end) break;
    if (j > 0) {
      const adem_vec3 *q0;
      const adem_motion *prev = wall_motion(c, mesh, k, j - 1, &inactive, &p0);
      const adem_motion *mj = wall_motion(c, mesh, k, j, &inactive, &q0);
      bool moved = p0 && q0 && memcmp(p0, q0, sizeof *p0) != 0; /* a stage puts a plane elsewhere */
      if (moved || !adem_motion_same(prev, mj)) {               /* a new motion from where the wall is */
        anchor = moved ? *q0 : adem_motion_place(&cur, ws, anchor);
        cur = *mj;
        cur.t0 = ws;
        if (np < MAX_POINTS - 1) {
          tp[np] = ws;
          xp[np++] = adem_motion_place(&cur, ws, anchor);
        }
      }
    }
    for (size_t q = 0; q < cur.n && np < MAX_POINTS - 1; ++q) {
      double tk = cur.t0 + cur.time[q];
      if (tk > ws && tk < fmin(we, t_end)) {
        tp[np] = tk;
        xp[np++] = adem_motion_place(&cur, tk, anchor);
      }
    }
  }
  tp[np] = t_end;
  xp[np++] = adem_motion_place(&cur, t_end, anchor);
  for (int q = 0; q < np; ++q) {
    if (q > 0) fputs(", ", f);
    print_vec(f, xp[q]);
    fprintf(f, " at %.6g s%s", tp[q], q == np - 1 ? " (end)" : "");
  }
  /* the rate of every stage that changes it, not only the last one's */
  double rate = m0->omega;
  bool turns = false;
  for (int j = -1; j < nst; ++j) {
    const adem_motion *mj = j < 0 ? m0 : wall_motion(c, mesh, k, j, &inactive, &p0);
    double ws = j < 0 ? 0.0 : (double)adem_stages_start_step(c, j) * w->dt;
    if (ws >= t_end || (j >= 0 && mj->omega == rate && (turns || rate == 0.0))) continue;
    if (j < 0 && rate == 0.0) continue;
    if (j >= 0 && j == 0 && nst && ws == 0.0 && turns && mj->omega == rate) continue;
    fprintf(f, "%s%g rad/s", turns ? ", then " : "; it turns at ", mj->omega);
    if (j >= 0 && ws > 0.0) fprintf(f, " from t = %.6g s (stage `%s`)", ws, c->stages->s[j].name);
    rate = mj->omega;
    turns = true;
  }
  fputc('\n', f);
  bool was = inactive0;
  if (inactive0) fprintf(f, "      switched off at the start\n");
  for (int j = 0; j < nst; ++j) {
    wall_motion(c, mesh, k, j, &inactive, &p0);
    if (inactive != was)
      fprintf(f, "      switched %s at t = %.6g s (stage `%s`)\n", inactive ? "off" : "on",
              (double)adem_stages_start_step(c, j) * w->dt, c->stages->s[j].name);
    was = inactive;
  }
}

/* A closed mesh wall (STL file) as a region, or ADEM_ERR_INPUT when it encloses nothing. */
static adem_status mesh_wall_region(const adem_world *w, int k, adem_region *r) {
  const adem_mesh *m = &w->walls.mesh;
  const adem_mesh_wall *mw = &w->walls.mesh_walls[k];
  size_t n = 0;
  for (int g = mw->first; g < mw->first + mw->count; ++g) n += m->groups[g].count;
  adem_vec3 *corners = malloc((n ? n : 1) * 3 * sizeof *corners);
  if (!corners) return ADEM_ERR_NOMEM;
  size_t q = 0;
  for (int g = mw->first; g < mw->first + mw->count; ++g)
    for (uint32_t t = m->groups[g].first; t < m->groups[g].first + m->groups[g].count; ++t)
      for (int j = 0; j < 3; ++j) corners[q++] = w->walls.mesh_vert0[m->tri[t][j]];
  adem_error e;
  adem_status st = adem_insert_region_triangles(r, corners, n, &e);
  free(corners);
  return st;
}

/* One warning: in the report and through the log. */
static void geometry_warning(FILE *f, int *nwarn, const char *fmt, ...) ADEM_PRINTF(3, 4);
static void geometry_warning(FILE *f, int *nwarn, const char *fmt, ...) {
  char msg[ADEM_MSG_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  fprintf(f, "    warning: %s\n", msg);
  fflush(f);
  adem_log(ADEM_LOG_WARN, "%s", msg);
  ++*nwarn;
}

/* A fill or pour region against the walls at time 0: planes it crosses or lies behind, mesh
 * groups whose triangles pass through it, and closed mesh walls large enough to hold it that it
 * lies outside of. */
static void check_region(FILE *f, const adem_case *c, const char *what, const adem_region *r,
                         const adem_region *closed, const bool *is_closed, int *nwarn) {
  const adem_world *w = c->world;
  int before = *nwarn;
  for (int k = 0; k < w->walls.nplanes; ++k) {
    const adem_plane *pl = &w->walls.planes[k];
    if (pl->inactive) continue; /* a lid put on later */
    int side = adem_insert_region_plane_side(r, pl->point0, pl->normal0);
    if (side == 0)
      geometry_warning(f, nwarn, "%s crosses plane `%s`: spheres are placed only on its front "
                                 "side, and the region's part behind it stays empty",
                       what, pl->def.name);
    else if (side < 0)
      geometry_warning(f, nwarn, "%s lies wholly behind plane `%s` (on the side away from its "
                                 "normal)",
                       what, pl->def.name);
  }
  const adem_mesh *m = &w->walls.mesh;
  for (int g = 0; g < m->ngroups; ++g) {
    if (!adem_walls_mesh_active(&w->walls, (uint32_t)g)) continue;
    size_t cut = 0;
    for (uint32_t t = m->groups[g].first; t < m->groups[g].first + m->groups[g].count; ++t) {
      const adem_vec3 *v = w->walls.mesh_vert0;
      cut += adem_insert_region_cuts_triangle(r, v[m->tri[t][0]], v[m->tri[t][1]], v[m->tri[t][2]]);
    }
    if (cut)
      geometry_warning(f, nwarn, "%s crosses mesh group `%s` (%zu of its triangles pass through "
                                 "it): spheres may be placed on both sides of it",
                       what,
                       m->groups[g].name, cut);
  }
  /* closed mesh walls that could hold it (their volume at least the region's) */
  char names[512] = "";
  bool inside = false, any = false;
  adem_vec3 centre = adem_insert_region_centre(r);
  for (int k = 0; k < w->walls.nmesh_walls; ++k) {
    if (!is_closed[k] || closed[k].volume < r->volume) continue;
    any = true;
    inside |= adem_insert_region_contains(&closed[k], centre);
    size_t len = strlen(names);
    snprintf(names + len, sizeof names - len, "%s`%s`", len ? ", " : "", w->walls.mesh_walls[k].name);
  }
  if (any && !inside)
    geometry_warning(f, nwarn, "%s lies outside every closed mesh wall that could hold it (%s): "
                               "if it is meant to be inside one, check its coordinates and the mesh's "
                               "scale and translate",
                     what, names);
  if (*nwarn == before) fprintf(f, "    %s: clear of every wall\n", what);
}

static void print_geometry(FILE *f, const adem_case *c) {
  const adem_world *w = c->world;
  const adem_mesh *m = &w->walls.mesh;
  int nfill = c->fills ? c->fills->n : 0, npour = c->pours ? c->pours->n : 0;
  bool moving = false;
  for (int k = 0; k < w->walls.nplanes; ++k) moving |= w->walls.planes[k].motion.moving;
  for (int g = 0; g < m->ngroups; ++g) moving |= w->walls.mesh_motion[g].moving;
  if (m->ngroups == 0 && !moving && !c->stages && nfill + npour == 0) return;
  fprintf(f, "\ngeometry\n");
  if (m->ngroups > 0) fprintf(f, "  mesh groups at t = 0 (bounding boxes)\n");
  for (int g = 0; g < m->ngroups; ++g) {
    adem_vec3 lo, hi;
    group_box(w, g, &lo, &hi);
    fprintf(f, "    %-24s %u triangles, ", m->groups[g].name, m->groups[g].count);
    print_vec(f, lo);
    fputs(" .. ", f);
    print_vec(f, hi);
    fputs(" m\n", f);
  }
  /* motions and switches */
  bool header = false;
  for (int pass = 0; pass < 2; ++pass)
    for (int k = 0; k < (pass ? m->ngroups : w->walls.nplanes); ++k) {
      adem_vec3 ref;
      if (pass) {
        adem_vec3 lo, hi;
        group_box(w, k, &lo, &hi);
        ref = v3_scale(v3_add(lo, hi), 0.5);
      } else {
        ref = w->walls.planes[k].point0;
      }
      /* the header once, before the first wall that moves or is switched */
      char *text = NULL;
      size_t len = 0;
      FILE *buf = open_memstream(&text, &len);
      if (!buf) continue;
      print_wall_path(buf, c, pass == 1, k, ref);
      fclose(buf);
      if (len > 0) {
        if (!header) fprintf(f, "  wall paths (where each moving or switched wall is over the run)\n");
        header = true;
        fputs(text, f);
      }
      free(text);
    }
  if (nfill + npour == 0) return;
  /* fill and pour regions against the walls */
  int nw = w->walls.nmesh_walls;
  adem_region *closed = calloc((size_t)(nw > 0 ? nw : 1), sizeof *closed);
  bool *is_closed = calloc((size_t)(nw > 0 ? nw : 1), sizeof *is_closed);
  if (!closed || !is_closed) {
    free(closed);
    free(is_closed);
    return;
  }
  for (int k = 0; k < nw; ++k) is_closed[k] = mesh_wall_region(w, k, &closed[k]) == ADEM_OK;
  fprintf(f, "  fill regions against the walls active at t = 0\n");
  int nwarn = 0;
  for (int k = 0; k < nfill; ++k) {
    char what[200];
    snprintf(what, sizeof what, "%s (a %s)", c->fills->r[k].where, c->fills->r[k].name);
    check_region(f, c, what, &c->fills->r[k].region, closed, is_closed, &nwarn);
  }
  for (int k = 0; k < npour; ++k) {
    char what[200];
    snprintf(what, sizeof what, "pours[%d] (`%s`).region", k, c->pours->p[k].def.name);
    check_region(f, c, what, &c->pours->p[k].def.region, closed, is_closed, &nwarn);
  }
  for (int k = 0; k < nw; ++k)
    if (is_closed[k]) adem_insert_region_free(&closed[k]);
  free(closed);
  free(is_closed);
}

adem_status adem_case_report(const adem_case *c, FILE *f, adem_error *err) {
  const adem_world *w = c->world;
  const adem_particles *p = &w->p;
  int nm = w->mat.n;
  double *rmin = malloc((size_t)(nm > 0 ? nm : 1) * sizeof *rmin);
  double *rmax = malloc((size_t)(nm > 0 ? nm : 1) * sizeof *rmax);
  bool *wallmat = calloc((size_t)(nm > 0 ? nm : 1), sizeof *wallmat);
  if (!rmin || !rmax || !wallmat) {
    free(rmin);
    free(rmax);
    free(wallmat);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  for (int k = 0; k < nm; ++k) {
    rmin[k] = INFINITY;
    rmax[k] = 0.0;
  }
  double rlo = INFINITY, rhi = 0.0, mass = 0.0;
  uint32_t *order = adem_world_id_order(w); /* the mass summed by id, as every sum */
  for (size_t k = 0; k < p->n; ++k) {
    size_t i = order ? order[k] : k;
    int m = p->material[i];
    rmin[m] = fmin(rmin[m], p->radius[i]);
    rmax[m] = fmax(rmax[m], p->radius[i]);
    rlo = fmin(rlo, p->radius[i]);
    rhi = fmax(rhi, p->radius[i]);
    mass += 1.0 / p->inv_mass[i];
  }
  free(order);
  for (int k = 0; c->pours && k < c->pours->n; ++k) { /* poured spheres meet them too */
    const adem_pour *q = &c->pours->p[k];
    rmin[q->def.material] = fmin(rmin[q->def.material], adem_insert_dist_smallest(&q->def.dist));
    rmax[q->def.material] = fmax(rmax[q->def.material], adem_insert_dist_largest(&q->def.dist));
  }
  for (int k = 0; k < w->walls.nplanes; ++k) wallmat[w->walls.planes[k].def.material] = true;
  for (int k = 0; k < w->walls.mesh.ngroups; ++k) wallmat[w->walls.mesh.groups[k].material] = true;

  fprintf(f, "case        %s (%s)\n", c->name, c->path);
  if (p->n)
    fprintf(f, "particles   %zu, radius %.4g..%.4g m, total mass %.4g kg\n", p->n, rlo, rhi, mass);
  else
    fprintf(f, "particles   none at the start\n");
  fprintf(f, "walls       %d plane%s", w->walls.nplanes, w->walls.nplanes == 1 ? "" : "s");
  for (int k = 0; k < w->walls.nplanes && k < 12; ++k)
    fprintf(f, "%s%s", k ? ", " : ": ", w->walls.planes[k].def.name);
  fprintf(f, "%s\n", w->walls.nplanes > 12 ? ", ..." : "");
  if (w->walls.mesh.ngroups > 0) {
    fprintf(f, "meshes      %zu triangles in %d group%s", w->walls.mesh.ntris, w->walls.mesh.ngroups,
            w->walls.mesh.ngroups == 1 ? "" : "s");
    for (int k = 0; k < w->walls.mesh.ngroups && k < 12; ++k)
      fprintf(f, "%s%s", k ? ", " : ": ", w->walls.mesh.groups[k].name);
    fprintf(f, "%s\n", w->walls.mesh.ngroups > 12 ? ", ..." : "");
  }
  for (int k = 0; c->pours && k < c->pours->n; ++k) {
    const adem_pour *q = &c->pours->p[k];
    static const char *const shapes[] = {"box", "cylinder", "mesh"};
    fprintf(f, "pour        %s: %.6g %s from t = %g to %g s into a %s, radius %.4g..%.4g m\n",
            q->def.name, adem_pour_total(q), q->def.rate > 0.0 ? "particles" : "kg", q->def.start,
            q->def.end, shapes[q->def.region.kind], adem_insert_dist_smallest(&q->def.dist),
            adem_insert_dist_largest(&q->def.dist));
  }
  for (int k = 0; c->stages && k < c->stages->n; ++k) {
    const adem_stage *g = &c->stages->s[k];
    double t0 = (double)adem_stages_start_step(c, k) * w->dt;
    fprintf(f, "stage %-5d %s: from t = %.6g s, %d change%s\n", k + 1, g->name, t0, g->nsets,
            g->nsets == 1 ? "" : "s");
    if (g->until) {
      char u[512];
      adem_until_summary(g->until, u, sizeof u);
      fprintf(f, "            ends early when: %s%s\n", u,
              k + 1 < c->stages->n ? "; the next stage begins then" : "; the run ends then");
    }
  }
  if (c->until) {
    char u[512];
    adem_until_summary(c->until, u, sizeof u);
    fprintf(f, "until       the run ends before time.end when: %s\n", u);
  }
  print_geometry(f, c);
  fprintf(f, "gravity     (%g, %g, %g) m/s^2\n", w->gravity.x, w->gravity.y, w->gravity.z);
  if (w->has_domain)
    fprintf(f, "domain      (%g, %g, %g) .. (%g, %g, %g) m: a particle that leaves it stops the run\n",
            w->domain_lo.x, w->domain_lo.y, w->domain_lo.z, w->domain_hi.x, w->domain_hi.y,
            w->domain_hi.z);
  else
    fprintf(f, "domain      none: particles may go anywhere (`domain` bounds them)\n");
  fprintf(f, "contacts    %zu particle pairs, %zu plane pairs and %zu mesh pairs within reach at the "
             "start\n",
          w->pp.n, w->pw.n, w->pm.l.n);

  fprintf(f, "\nmaterial pairs (effective values: E*, G* from H2 and H15, R* = r_i r_j/(r_i+r_j), "
             "beta from H12)\n");
  fprintf(f, "  %-26s %-11s %-11s %-21s %-6s %-9s %-6s %-6s %s\n", "pair", "E* (Pa)", "G* (Pa)",
          "R* (m)", "e", "beta", "mu", "normal", "rolling");
  for (int a = 0; a < nm; ++a) {
    if (!(rmax[a] > 0.0)) continue;
    for (int b = a; b < nm; ++b)
      if (rmax[b] > 0.0) print_pair(f, w, a, b, false, rmin, rmax, c->estimate.v_ref);
    for (int b = 0; b < nm; ++b)
      if (wallmat[b]) print_pair(f, w, a, b, true, rmin, rmax, c->estimate.v_ref);
  }

  const adem_step_estimate *e = &c->estimate;
  double dt = w->dt;
  uint64_t total = adem_schedule_total_steps(c->end_time, dt);
  fprintf(f, "\ntime step (notes section 6)\n");
  fprintf(f, "  reference speed v_ref     %.4g m/s\n", e->v_ref);
  fprintf(f, "  Hertz collision time t_c  %.4g s\n", e->t_collision);
  fprintf(f, "  Rayleigh time t_R         %.4g s\n", e->t_rayleigh);
  fprintf(f, "  proposed step             %.4g s = min(t_c/50, 0.2 t_R, stability limit/5)\n", e->dt);
  fprintf(f, "  stability limit           %.4g s = t_c/%.3g (contact modes with damping)\n",
          e->dt_stable, e->t_collision / e->dt_stable);
  if (c->dt_auto)
    fprintf(f, "  chosen step               %.4g s (auto)\n", dt);
  else
    fprintf(f, "  chosen step               %.4g s (time.step: %.3g times the proposed one)%s\n", dt,
            c->dt_user_ratio, c->dt_user_ratio > 1.0 ? " -- larger than proposed" : "");
  fprintf(f, "  end time                  %.6g s: %llu steps%s\n", c->end_time, (unsigned long long)total,
          c->until ? " at most (time.until)" : "");

  const adem_output_settings *os = &c->output;
  uint64_t kf = adem_schedule_period(os->frame_interval, dt);
  uint64_t kc = adem_schedule_period(os->csv_interval, dt);
  uint64_t kk = adem_schedule_period(os->checkpoint_interval, dt);
  uint64_t nframes = adem_schedule_count(kf, total), nrows = adem_schedule_count(kc, total);
  fprintf(f, "\noutput in %s\n", os->dir);
  if (kf) fprintf(f, "  frames       every %.4g s (%llu steps): %llu frames\n", os->frame_interval,
                  (unsigned long long)kf, (unsigned long long)nframes);
  else fprintf(f, "  frames       off\n");
  if (kc) fprintf(f, "  CSV rows     every %.4g s (%llu steps): %llu rows\n", os->csv_interval,
                  (unsigned long long)kc, (unsigned long long)nrows);
  else fprintf(f, "  CSV rows     off\n");
  if (kk) fprintf(f, "  checkpoints  every %.4g s (%llu steps), on Ctrl-C and at the end\n",
                  os->checkpoint_interval, (unsigned long long)kk);
  else fprintf(f, "  checkpoints  on Ctrl-C and at the end\n");
  fprintf(f, "  energy plot  %s\n", os->plot ? "yes (gnuplot)" : "no");

  /* The estimate the loader checked against limits.max_memory (adem_world_memory_estimate). */
  const adem_memory_estimate *me = &c->memory;
  double per_pair = (double)adem_world_bytes_per_pair(w);
  double frame = 1500.0 + (double)p->n * (8 + 8 + 4 + 4 * 24 + 8 + 8 + 1);
  double row = (9.0 + 3.0 * w->walls.nplanes) * 24.0;
  double ckpt = (double)strlen(c->source) + (double)p->n * (6 * 24 + 3 * 8 + 8 + 4) +
                (double)(w->pp.n + w->pw.n) * per_pair;
  fprintf(f, "\nestimates\n");
  char m0[32], m1[32], m2[32], m3[32], m4[32];
  fprintf(f, "  memory       %s at most: %.0f particles%s %s, %.0f candidate pairs %s, grid %s, "
             "neighbour build %s\n",
          mem_text(m0, sizeof m0, me->total), me->particles,
          c->pours ? " (the pours' totals included)" : "", mem_text(m1, sizeof m1, me->particle_bytes),
          me->pairs, mem_text(m2, sizeof m2, me->pair_bytes), mem_text(m3, sizeof m3, me->grid_bytes),
          mem_text(m4, sizeof m4, me->build_bytes));
  if (c->memory_limit > 0.0)
    fprintf(f, "  memory limit %s (%s): the estimate is %.2g of it\n",
            mem_text(m0, sizeof m0, c->memory_limit),
            c->memory_auto ? "available on this machine" : "limits.max_memory",
            me->total / c->memory_limit);
  fprintf(f, "  disk         %.1f MiB: frames %llu x %.2f MiB, CSV %.2f MiB, checkpoint %.2f MiB\n",
          mib((double)nframes * frame + (double)nrows * row + ckpt), (unsigned long long)nframes,
          mib(frame), mib((double)nrows * row), mib(ckpt));
  free(rmin);
  free(rmax);
  free(wallmat);
  return ADEM_OK;
}
