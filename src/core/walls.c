/* Walls: infinite planes, boxes of planes, triangle-mesh groups, and their prescribed motion. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "adem/vec3.h"
#include "walls.h"
#include "cylinder.h"

static void note_plane(adem_plane *pl, const adem_motion *m);

adem_plane_def adem_default_plane_def(void) {
  adem_plane_def d;
  memset(&d, 0, sizeof d);
  d.normal = v3(0.0, 0.0, 1.0);
  return d;
}

int adem_walls_add_plane(adem_walls *wl, const adem_plane_def *def, int nmaterials,
                         adem_error *err) {
  double len = v3_norm(def->normal);
  if (!(len > 0.0) || !isfinite(len) || !v3_isfinite(def->point)) {
    adem_error_set(err, ADEM_ERR_INPUT, "wall '%s': the normal must be finite and non-zero",
                   def->name);
    return -1;
  }
  if (def->material < 0 || def->material >= nmaterials) {
    adem_error_set(err, ADEM_ERR_INPUT, "wall '%s': material does not exist", def->name);
    return -1;
  }
  if (adem_wall_check_shape(def, err)) return -1; /* a cylinder's or disc's sizes */
  adem_plane *pl = realloc(wl->planes, (size_t)(wl->nplanes + 1) * sizeof *pl);
  if (!pl) {
    adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    return -1;
  }
  wl->planes = pl;
  adem_plane *np = &pl[wl->nplanes];
  memset(np, 0, sizeof *np);
  np->def = *def;
  np->def.normal = v3_scale(def->normal, 1.0 / len);
  np->point0 = np->def.point;
  np->normal0 = np->def.normal;
  /* a constant velocity is the simplest motion: one knot */
  double t0 = 0.0;
  adem_motion_def md = {0};
  if (v3_norm2(def->velocity) > 0.0) {
    md.n = 1;
    md.time = &t0;
    md.velocity = &def->velocity;
  }
  if (adem_motion_init(&np->motion, &md, err)) return -1;
  note_plane(np, &np->motion);
  return wl->nplanes++;
}

int adem_walls_add_box(adem_walls *wl, const char *name, adem_vec3 lo, adem_vec3 hi, int material,
                       int nmaterials, adem_error *err) {
  if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) {
    adem_error_set(err, ADEM_ERR_INPUT, "box '%s': min must be below max on every axis", name);
    return -1;
  }
  static const char *face[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  adem_vec3 points[6] = {lo, hi, lo, hi, lo, hi};
  adem_vec3 normals[6] = {v3(1, 0, 0), v3(-1, 0, 0), v3(0, 1, 0),
                          v3(0, -1, 0), v3(0, 0, 1), v3(0, 0, -1)};
  int first = -1;
  for (int k = 0; k < 6; ++k) {
    adem_plane_def d = adem_default_plane_def();
    snprintf(d.name, sizeof d.name, "%.50s.%s", name, face[k]);
    d.point = points[k];
    d.normal = normals[k];
    d.material = material;
    int idx = adem_walls_add_plane(wl, &d, nmaterials, err);
    if (idx < 0) return -1;
    if (first < 0) first = idx;
  }
  return first;
}

/* Area-weighted centroid of triangles first .. first + count - 1 (the mean vertex if no area). */
static adem_vec3 area_centroid(const adem_mesh *m, uint32_t first, uint32_t count, double *area) {
  adem_vec3 c = v3_zero(), mean = v3_zero();
  double a = 0.0;
  for (uint32_t t = first; t < first + count; ++t) {
    adem_vec3 x0 = m->vert[m->tri[t][0]], x1 = m->vert[m->tri[t][1]], x2 = m->vert[m->tri[t][2]];
    adem_vec3 g = v3_scale(v3_add(x0, v3_add(x1, x2)), 1.0 / 3.0);
    c = v3_axpy(c, m->area[t], g);
    mean = v3_add(mean, g);
    a += m->area[t];
  }
  *area = a;
  if (a > 0.0) return v3_scale(c, 1.0 / a);
  return count > 0 ? v3_scale(mean, 1.0 / count) : v3_zero();
}

/* The file's name without folder and extension (the default prefix of its groups). */
static void path_stem(const char *path, char *buf, size_t n) {
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  const char *dot = strrchr(base, '.');
  size_t len = dot && dot != base ? (size_t)(dot - base) : strlen(base);
  if (len >= n) len = n - 1;
  memcpy(buf, base, len);
  buf[len] = '\0';
}

adem_status adem_walls_check_mesh(int nmaterials, const char *path, const adem_mesh_transform *tf,
                                  adem_vec3 velocity, adem_error *err) {
  if (tf->material < 0 || tf->material >= nmaterials)
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: mesh material index %d is not a material", path,
                          tf->material);
  bool moving = velocity.x != 0.0 || velocity.y != 0.0 || velocity.z != 0.0;
  if (!v3_isfinite(velocity) || (moving && !tf->own_vertices))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: a moving mesh needs a finite velocity and its own vertices", path);
  return ADEM_OK;
}

adem_status adem_walls_add_mesh_soup(adem_walls *wl, int nmaterials, const adem_mesh_soup *s,
                                     const adem_mesh_transform *tf, const char *path, int ascii,
                                     const char *name, adem_vec3 velocity, adem_error *err) {
  adem_mesh_transform def = adem_default_mesh_transform();
  if (!tf) tf = &def;
  adem_status st = adem_walls_check_mesh(nmaterials, path, tf, velocity, err);
  if (st) return st;
  bool moving = velocity.x != 0.0 || velocity.y != 0.0 || velocity.z != 0.0;
  int before = wl->mesh.ngroups;
  size_t nv_before = wl->mesh.nverts, nt_before = wl->mesh.ntris;
  st = adem_mesh_append_soup(&wl->mesh, s, tf, path, ascii, err);
  if (st) return st;
  size_t ng = (size_t)wl->mesh.ngroups, nv = wl->mesh.nverts, nt = wl->mesh.ntris;
  adem_motion *mo = realloc(wl->mesh_motion, ng * sizeof *mo);
  if (mo) wl->mesh_motion = mo;
  double *reach = realloc(wl->mesh_reach, ng * sizeof *reach);
  if (reach) wl->mesh_reach = reach;
  adem_vec3 *v0 = realloc(wl->mesh_vert0, (nv + 1) * sizeof *v0);
  if (v0) wl->mesh_vert0 = v0;
  adem_vec3 *n0 = realloc(wl->mesh_normal0, (nt + 1) * sizeof *n0);
  if (n0) wl->mesh_normal0 = n0;
  double *ff = realloc(wl->face_force, (3 * nt + 1) * sizeof *ff);
  if (ff) wl->face_force = ff;
  double *ft = realloc(wl->face_torque, (3 * nt + 1) * sizeof *ft);
  if (ft) wl->face_torque = ft;
  adem_vec3 *r0 = realloc(wl->mesh_ref0, ng * sizeof *r0);
  if (r0) wl->mesh_ref0 = r0;
  adem_vec3 *r = realloc(wl->mesh_ref, ng * sizeof *r);
  if (r) wl->mesh_ref = r;
  adem_mesh_wall *mw = realloc(wl->mesh_walls, (size_t)(wl->nmesh_walls + 1) * sizeof *mw);
  if (mw) wl->mesh_walls = mw;
  if (!mo || !reach || !v0 || !n0 || !ff || !ft || !r0 || !r || !mw)
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory adding %s", path);
  /* the walls are where they are at time 0 (meshes are added before stepping) */
  memcpy(wl->mesh_vert0 + nv_before, wl->mesh.vert + nv_before, (nv - nv_before) * sizeof *v0);
  memcpy(wl->mesh_normal0 + nt_before, wl->mesh.normal + nt_before, (nt - nt_before) * sizeof *n0);
  memset(wl->face_force, 0, 3 * nt * sizeof *ff);
  memset(wl->face_torque, 0, 3 * nt * sizeof *ft);
  adem_mesh_wall *wall = &wl->mesh_walls[wl->nmesh_walls];
  memset(wall, 0, sizeof *wall);
  wall->first = before;
  wall->count = wl->mesh.ngroups - before;
  if (wall->count == 1)
    snprintf(wall->name, sizeof wall->name, "%s", wl->mesh.groups[before].name);
  else if (name && *name)
    snprintf(wall->name, sizeof wall->name, "%s", name);
  else
    path_stem(path, wall->name, sizeof wall->name);
  double area = 0.0;
  uint32_t t_first = wall->count > 0 ? wl->mesh.groups[before].first : 0;
  wall->ref0 = area_centroid(&wl->mesh, t_first, (uint32_t)(nt - nt_before), &area);
  wl->nmesh_walls++;
  for (int g = before; g < wl->mesh.ngroups; ++g) {
    memset(&wl->mesh_motion[g], 0, sizeof wl->mesh_motion[g]);
    wl->mesh_reach[g] = 0.0;
    const adem_mesh_group *grp = &wl->mesh.groups[g];
    wl->mesh_ref0[g] = wl->mesh_ref[g] = area_centroid(&wl->mesh, grp->first, grp->count, &area);
    if (moving) {
      double t0 = 0.0;
      adem_motion_def md = {.n = 1, .time = &t0, .velocity = &velocity};
      st = adem_walls_set_mesh_motion(wl, g, &md, err);
      if (st) return st;
    }
  }
  return ADEM_OK;
}

adem_status adem_walls_set_mesh_torque_point(adem_walls *wl, int wall, adem_vec3 point,
                                             adem_error *err) {
  if (wall < 0 || wall >= wl->nmesh_walls)
    return adem_error_set(err, ADEM_ERR_INPUT, "mesh wall %d does not exist", wall);
  if (!v3_isfinite(point))
    return adem_error_set(err, ADEM_ERR_INPUT, "mesh wall '%s': the torque point must be finite",
                          wl->mesh_walls[wall].name);
  adem_mesh_wall *mw = &wl->mesh_walls[wall];
  mw->ref0 = point;
  for (int g = mw->first; g < mw->first + mw->count; ++g) {
    wl->mesh_ref0[g] = point;
    wl->mesh_ref[g] = adem_motion_place(&wl->mesh_motion[g], wl->time, point);
  }
  return ADEM_OK;
}

void adem_walls_mesh_loads(const adem_walls *wl, adem_vec3 *group_force, adem_vec3 *group_torque,
                           adem_vec3 *wall_force, adem_vec3 *wall_torque) {
  const adem_mesh *m = &wl->mesh;
  for (int g = 0; g < m->ngroups; ++g) {
    const adem_mesh_group *grp = &m->groups[g];
    adem_vec3 f = v3_zero(), t = v3_zero();
    for (size_t k = grp->first; k < (size_t)grp->first + grp->count; ++k) {
      f = v3_add(f, v3(wl->face_force[3 * k], wl->face_force[3 * k + 1], wl->face_force[3 * k + 2]));
      t = v3_add(t, v3(wl->face_torque[3 * k], wl->face_torque[3 * k + 1], wl->face_torque[3 * k + 2]));
    }
    if (group_force) group_force[g] = f;
    if (group_torque) group_torque[g] = t;
  }
  if (!wall_force && !wall_torque) return;
  for (int k = 0; k < wl->nmesh_walls; ++k) {
    const adem_mesh_wall *mw = &wl->mesh_walls[k];
    adem_vec3 f = v3_zero(), t = v3_zero();
    /* the wall's point travels with its first group; each group's torque is moved onto it */
    adem_vec3 ref = mw->count > 0 ? adem_motion_place(&wl->mesh_motion[mw->first], wl->time, mw->ref0)
                                  : mw->ref0;
    for (int g = mw->first; g < mw->first + mw->count; ++g) {
      const adem_mesh_group *grp = &m->groups[g];
      adem_vec3 fg = v3_zero(), tg = v3_zero();
      for (size_t j = grp->first; j < (size_t)grp->first + grp->count; ++j) {
        fg = v3_add(fg, v3(wl->face_force[3 * j], wl->face_force[3 * j + 1], wl->face_force[3 * j + 2]));
        tg = v3_add(tg, v3(wl->face_torque[3 * j], wl->face_torque[3 * j + 1], wl->face_torque[3 * j + 2]));
      }
      f = v3_add(f, fg);
      t = v3_add(t, v3_add(tg, v3_cross(v3_sub(wl->mesh_ref[g], ref), fg)));
    }
    if (wall_force) wall_force[k] = f;
    if (wall_torque) wall_torque[k] = t;
  }
}

static uint8_t csv_flags(const adem_motion *m) {
  return (uint8_t)((m->moving ? ADEM_WALL_CSV_MOVES : 0u) | (m->servo.on ? ADEM_WALL_CSV_SERVO : 0u));
}

static void note_plane(adem_plane *pl, const adem_motion *m) { pl->csv |= csv_flags(m); }

/* The mesh wall (file) group g belongs to, or -1. */
static int wall_of_group(const adem_walls *wl, int g) {
  for (int k = 0; k < wl->nmesh_walls; ++k)
    if (g >= wl->mesh_walls[k].first && g < wl->mesh_walls[k].first + wl->mesh_walls[k].count) return k;
  return -1;
}

static void note_mesh(adem_walls *wl, int g, const adem_motion *m) {
  int k = wall_of_group(wl, g);
  if (k >= 0) wl->mesh_walls[k].csv |= csv_flags(m);
}

void adem_walls_note_settings(adem_walls *wl, const adem_plane_setting *planes,
                              const adem_mesh_setting *meshes) {
  for (int k = 0; k < wl->nplanes; ++k) note_plane(&wl->planes[k], &planes[k].motion);
  for (int g = 0; g < wl->mesh.ngroups; ++g) note_mesh(wl, g, &meshes[g].motion);
}

adem_status adem_walls_set_mesh_motion(adem_walls *wl, int group, const adem_motion_def *def,
                                       adem_error *err) {
  if (group < 0 || group >= wl->mesh.ngroups)
    return adem_error_set(err, ADEM_ERR_INPUT, "mesh group %d does not exist", group);
  const adem_mesh_group *g = &wl->mesh.groups[group];
  adem_motion m;
  adem_status st = adem_motion_init(&m, def, err);
  if (st) return st;
  if (m.moving && !g->own_vertices) {
    adem_motion_free(&m);
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "mesh group '%s' shares vertices with other groups and cannot move: "
                          "load it with its own vertices",
                          g->name);
  }
  adem_motion_free(&wl->mesh_motion[group]);
  wl->mesh_motion[group] = m;
  note_mesh(wl, group, &m);
  double reach = 0.0;
  for (uint32_t v = g->vert_first; v < g->vert_first + g->vert_count; ++v)
    reach = fmax(reach, v3_norm(v3_sub(wl->mesh_vert0[v], m.center)));
  wl->mesh_reach[group] = reach;
  wl->mesh_ref[group] = adem_motion_place(&m, wl->time, wl->mesh_ref0[group]);
  return ADEM_OK;
}

adem_status adem_walls_set_plane_motion(adem_walls *wl, int plane, const adem_motion_def *def,
                                        adem_error *err) {
  if (plane < 0 || plane >= wl->nplanes)
    return adem_error_set(err, ADEM_ERR_INPUT, "plane %d does not exist", plane);
  adem_motion m;
  adem_status st = adem_motion_init(&m, def, err);
  if (st) return st;
  adem_motion_free(&wl->planes[plane].motion);
  wl->planes[plane].motion = m;
  note_plane(&wl->planes[plane], &m);
  return ADEM_OK;
}

void adem_walls_place(adem_walls *wl, double t) {
  wl->time = t;
  for (int k = 0; k < wl->nplanes; ++k) {
    adem_plane *pl = &wl->planes[k];
    if (!pl->motion.moving) continue;
    pl->def.point = adem_motion_place(&pl->motion, t, pl->point0);
    pl->def.normal = adem_motion_turn(&pl->motion, t, pl->normal0);
    pl->def.velocity = adem_motion_velocity(&pl->motion, t);
  }
  adem_mesh *m = &wl->mesh;
  for (int g = 0; g < m->ngroups; ++g) {
    const adem_motion *mo = &wl->mesh_motion[g];
    if (!mo->moving) continue;
    const adem_mesh_group *grp = &m->groups[g];
    for (uint32_t v = grp->vert_first; v < grp->vert_first + grp->vert_count; ++v)
      m->vert[v] = adem_motion_place(mo, t, wl->mesh_vert0[v]);
    for (uint32_t k = grp->first; k < grp->first + grp->count; ++k)
      m->normal[k] = adem_motion_turn(mo, t, wl->mesh_normal0[k]);
    wl->mesh_ref[g] = adem_motion_place(mo, t, wl->mesh_ref0[g]);
  }
}

double adem_walls_shift(const adem_walls *wl, double t0, bool has_box, adem_vec3 lo, adem_vec3 hi) {
  double t1 = wl->time, shift = 0.0;
  /* a rotating plane sweeps the whole domain: bound by its extent from the centre */
  double extent = has_box ? v3_norm(v3_sub(hi, lo)) : 0.0;
  for (int k = 0; k < wl->nplanes; ++k) {
    const adem_motion *mo = &wl->planes[k].motion;
    if (!mo->moving) continue;
    /* a cylinder or disc turning about its own axis sweeps nothing (cylinder.h) */
    double reach = mo->omega != 0.0 && !adem_wall_plane_turns_in_place(&wl->planes[k])
                       ? extent + v3_norm(v3_sub(mo->center, lo))
                       : 0.0;
    shift = fmax(shift, adem_motion_max_shift(mo, t0, t1, reach));
  }
  for (int g = 0; g < wl->mesh.ngroups; ++g) {
    const adem_motion *mo = &wl->mesh_motion[g];
    if (mo->moving) shift = fmax(shift, adem_motion_max_shift(mo, t0, t1, wl->mesh_reach[g]));
  }
  return shift;
}

void adem_walls_clear_face_loads(adem_walls *wl) {
  memset(wl->face_force, 0, 3 * wl->mesh.ntris * sizeof *wl->face_force);
  memset(wl->face_torque, 0, 3 * wl->mesh.ntris * sizeof *wl->face_torque);
}

adem_status adem_walls_get_settings(const adem_walls *wl, adem_plane_setting *planes,
                                    adem_mesh_setting *meshes, adem_error *err) {
  adem_status st = ADEM_OK;
  for (int k = 0; k < wl->nplanes && !st; ++k) {
    const adem_plane *pl = &wl->planes[k];
    planes[k].def = pl->def;
    planes[k].point0 = pl->point0;
    planes[k].normal0 = pl->normal0;
    planes[k].inactive = pl->inactive;
    st = adem_motion_copy(&planes[k].motion, &pl->motion, err);
  }
  for (int k = 0; k < wl->mesh.ngroups && !st; ++k) {
    meshes[k].material = wl->mesh.groups[k].material;
    meshes[k].inactive = !adem_walls_mesh_active(wl, (uint32_t)k);
    st = adem_motion_copy(&meshes[k].motion, &wl->mesh_motion[k], err);
  }
  return st;
}

/* A wall that starts a new motion at t_s starts it from where it is: its reference placement
 * becomes the current one and the motion's clock starts at t_s. */
adem_status adem_walls_change(adem_walls *wl, const adem_plane_setting *prev_planes,
                              const adem_plane_setting *next_planes,
                              const adem_mesh_setting *prev_meshes,
                              const adem_mesh_setting *next_meshes, double t_s, adem_error *err) {
  /* A plane at rest is at its reference place (a checkpoint has put where it is now). */
  for (int k = 0; k < wl->nplanes; ++k)
    if (!wl->planes[k].motion.moving) {
      wl->planes[k].def.point = wl->planes[k].point0;
      wl->planes[k].def.normal = wl->planes[k].normal0;
    }
  adem_walls_place(wl, t_s);
  adem_status st = ADEM_OK;
  for (int k = 0; k < wl->nplanes && !st; ++k) {
    adem_plane *pl = &wl->planes[k];
    const adem_plane_setting *a = &prev_planes[k], *b = &next_planes[k];
    bool moved = memcmp(&a->point0, &b->point0, sizeof a->point0) ||
                 memcmp(&a->normal0, &b->normal0, sizeof a->normal0);
    bool new_motion = !adem_motion_same(&a->motion, &b->motion);
    if (moved) { /* the stage puts the plane somewhere else */
      pl->point0 = b->point0;
      pl->normal0 = b->normal0;
      pl->def.point = b->point0;
      pl->def.normal = b->normal0;
    } else if (new_motion) {
      pl->point0 = pl->def.point;
      pl->normal0 = pl->def.normal;
    }
    if (moved || new_motion) {
      adem_motion m;
      if ((st = adem_motion_copy(&m, &b->motion, err))) break;
      m.t0 = t_s;
      adem_motion_free(&pl->motion);
      pl->motion = m;
      note_plane(pl, &m);
      pl->def.velocity = adem_motion_velocity(&pl->motion, t_s);
    }
    pl->def.material = b->def.material;
    pl->inactive = b->inactive;
  }
  adem_mesh *m = &wl->mesh;
  for (int g = 0; g < m->ngroups && !st; ++g) {
    const adem_mesh_setting *a = &prev_meshes[g], *b = &next_meshes[g];
    m->groups[g].material = b->material;
    if ((st = adem_walls_set_mesh_active(wl, g, !b->inactive, err))) break;
    if (adem_motion_same(&a->motion, &b->motion)) continue;
    const adem_mesh_group *grp = &m->groups[g];
    for (uint32_t v = grp->vert_first; v < grp->vert_first + grp->vert_count; ++v)
      wl->mesh_vert0[v] = m->vert[v];
    for (uint32_t t = grp->first; t < grp->first + grp->count; ++t) wl->mesh_normal0[t] = m->normal[t];
    for (int k = 0; k < wl->nmesh_walls; ++k) /* a wall's torque point travels with its first group */
      if (wl->mesh_walls[k].first == g)
        wl->mesh_walls[k].ref0 = adem_motion_place(&wl->mesh_motion[g], t_s, wl->mesh_walls[k].ref0);
    wl->mesh_ref0[g] = wl->mesh_ref[g];
    adem_motion mo;
    if ((st = adem_motion_copy(&mo, &b->motion, err))) break;
    mo.t0 = t_s;
    adem_motion_free(&wl->mesh_motion[g]);
    wl->mesh_motion[g] = mo;
    note_mesh(wl, g, &mo);
    double reach = 0.0;
    for (uint32_t v = grp->vert_first; v < grp->vert_first + grp->vert_count; ++v)
      reach = fmax(reach, v3_norm(v3_sub(wl->mesh_vert0[v], mo.center)));
    wl->mesh_reach[g] = reach;
  }
  if (!st) adem_walls_place(wl, t_s);
  return st;
}

void adem_walls_free(adem_walls *wl) {
  for (int k = 0; k < wl->nplanes; ++k) adem_motion_free(&wl->planes[k].motion);
  for (int g = 0; g < wl->mesh.ngroups; ++g)
    if (wl->mesh_motion) adem_motion_free(&wl->mesh_motion[g]);
  free(wl->planes);
  free(wl->mesh_motion);
  free(wl->mesh_reach);
  free(wl->mesh_vert0);
  free(wl->mesh_normal0);
  free(wl->face_force);
  free(wl->face_torque);
  free(wl->mesh_inactive);
  free(wl->mesh_ref0);
  free(wl->mesh_ref);
  free(wl->mesh_walls);
  adem_mesh_free(&wl->mesh);
  memset(wl, 0, sizeof *wl);
}

adem_status adem_walls_set_plane_active(adem_walls *wl, int plane, bool active, adem_error *err) {
  if (plane < 0 || plane >= wl->nplanes)
    return adem_error_set(err, ADEM_ERR_INPUT, "plane %d does not exist", plane);
  wl->planes[plane].inactive = !active;
  return ADEM_OK;
}

adem_status adem_walls_set_mesh_active(adem_walls *wl, int group, bool active, adem_error *err) {
  if (group < 0 || group >= wl->mesh.ngroups)
    return adem_error_set(err, ADEM_ERR_INPUT, "mesh group %d does not exist", group);
  if (group >= wl->mesh_inactive_n) { /* groups beyond the array are active */
    if (active) return ADEM_OK;
    uint8_t *f = realloc(wl->mesh_inactive, (size_t)wl->mesh.ngroups);
    if (!f) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    memset(f + wl->mesh_inactive_n, 0, (size_t)(wl->mesh.ngroups - wl->mesh_inactive_n));
    wl->mesh_inactive = f;
    wl->mesh_inactive_n = wl->mesh.ngroups;
  }
  wl->mesh_inactive[group] = !active;
  return ADEM_OK;
}

/* ---------------------------------------------------------------- set-up in checkpoints */

void adem_walls_save_setup(adem_writer *wr, const adem_walls *wl) {
  adem_put_u32(wr, (uint32_t)wl->nplanes);
  for (int k = 0; k < wl->nplanes; ++k) {
    const adem_plane *pl = &wl->planes[k];
    adem_put(wr, &pl->def, sizeof pl->def);
    adem_put_vec(wr, pl->point0);
    adem_put_vec(wr, pl->normal0);
    adem_put_u8(wr, pl->inactive ? 1 : 0);
    adem_motion_save(wr, &pl->motion);
  }
  const adem_mesh *m = &wl->mesh;
  adem_put_u32(wr, (uint32_t)wl->nmesh_walls);
  for (int k = 0; k < wl->nmesh_walls; ++k) {
    const adem_mesh_wall *mw = &wl->mesh_walls[k];
    adem_put_str(wr, mw->name);
    adem_put_vec(wr, mw->ref0);
    adem_put_u32(wr, (uint32_t)mw->count);
    for (int g = mw->first; g < mw->first + mw->count; ++g) {
      const adem_mesh_group *grp = &m->groups[g];
      adem_put_str(wr, grp->name);
      adem_put_i32(wr, grp->material);
      adem_put_i32(wr, grp->own_vertices);
      adem_put_u64(wr, grp->count);
      for (uint32_t t = grp->first; t < grp->first + grp->count; ++t)
        for (int c = 0; c < 3; ++c) adem_put_vec(wr, wl->mesh_vert0[m->tri[t][c]]);
      adem_motion_save(wr, &wl->mesh_motion[g]);
      adem_put_u8(wr, adem_walls_mesh_active(wl, (uint32_t)g) ? 0 : 1);
      adem_put_vec(wr, wl->mesh_ref0[g]);
    }
  }
}

adem_status adem_walls_load_setup(adem_reader *rd, adem_walls *wl, int nmaterials,
                                  adem_error *err) {
  adem_status st = ADEM_OK;
  uint32_t np = adem_get_u32(rd);
  for (uint32_t k = 0; k < np && !st && !rd->failed; ++k) {
    adem_plane_def def;
    adem_get(rd, &def, sizeof def);
    def.name[ADEM_NAME_MAX - 1] = '\0';
    int idx = adem_walls_add_plane(wl, &def, nmaterials, err);
    if (idx < 0) return err ? err->status : ADEM_ERR_INPUT;
    adem_plane *pl = &wl->planes[idx];
    pl->def = def;
    pl->point0 = adem_get_vec(rd);
    pl->normal0 = adem_get_vec(rd);
    pl->inactive = adem_get_u8(rd) != 0;
    adem_motion_free(&pl->motion);
    st = adem_motion_load(rd, &pl->motion, err);
  }
  uint32_t nw = adem_get_u32(rd);
  for (uint32_t k = 0; k < nw && !st && !rd->failed; ++k) {
    char name[ADEM_NAME_MAX];
    adem_get_str_into(rd, name, sizeof name);
    adem_vec3 wall_ref0 = adem_get_vec(rd);
    uint32_t ng = adem_get_u32(rd);
    if (rd->failed || ng > 1u << 20) break;
    /* the wall's groups as one soup, one block each, with their time-0 corners */
    adem_mesh_soup s;
    memset(&s, 0, sizeof s);
    adem_mesh_transform tf = adem_default_mesh_transform();
    int first = wl->mesh.ngroups;
    int *material = calloc(ng + 1, sizeof *material);
    uint8_t *inactive = calloc(ng + 1, 1);
    adem_motion *motion = calloc(ng + 1, sizeof *motion);
    adem_vec3 *ref0 = calloc(ng + 1, sizeof *ref0);
    if (!material || !inactive || !motion || !ref0) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    for (uint32_t g = 0; g < ng && !st && !rd->failed; ++g) {
      char gname[ADEM_NAME_MAX];
      adem_get_str_into(rd, gname, sizeof gname);
      material[g] = adem_get_i32(rd);
      tf.material = g == 0 ? material[g] : tf.material;
      tf.own_vertices = adem_get_i32(rd);
      uint64_t nt = adem_get_count(rd, 3 * sizeof(adem_vec3));
      adem_mesh_soup_block *b = adem_mesh_soup_block_open(&s, gname, 0);
      if (!b) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      for (uint64_t t = 0; t < nt && !st && !rd->failed; ++t) {
        adem_vec3 c[3] = {adem_get_vec(rd), adem_get_vec(rd), adem_get_vec(rd)};
        if (!adem_mesh_soup_push(&s, c, v3_zero(), (size_t)t))
          st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
        else
          s.blocks[s.nblocks - 1].count++;
      }
      if (!st) st = adem_motion_load(rd, &motion[g], err);
      inactive[g] = adem_get_u8(rd);
      ref0[g] = adem_get_vec(rd);
    }
    if (!st && !rd->failed)
      st = adem_walls_add_mesh_soup(wl, nmaterials, &s, &tf, name, 0, name, v3_zero(), err);
    adem_mesh_soup_free(&s);
    for (uint32_t g = 0; g < ng && !st && !rd->failed; ++g) {
      int grp = first + (int)g;
      wl->mesh.groups[grp].material = material[g];
      adem_motion_free(&wl->mesh_motion[grp]);
      wl->mesh_motion[grp] = motion[g];
      memset(&motion[g], 0, sizeof motion[g]);
      double reach = 0.0; /* as adem_walls_set_mesh_motion */
      const adem_mesh_group *gr = &wl->mesh.groups[grp];
      for (uint32_t v = gr->vert_first; v < gr->vert_first + gr->vert_count; ++v)
        reach = fmax(reach, v3_norm(v3_sub(wl->mesh_vert0[v], wl->mesh_motion[grp].center)));
      wl->mesh_reach[grp] = reach;
      wl->mesh_ref0[grp] = ref0[g];
      wl->mesh_ref[grp] = adem_motion_place(&wl->mesh_motion[grp], wl->time, ref0[g]);
      if (inactive[g]) st = adem_walls_set_mesh_active(wl, grp, false, err);
    }
    if (!st && !rd->failed) wl->mesh_walls[wl->nmesh_walls - 1].ref0 = wall_ref0;
    for (uint32_t g = 0; motion && g < ng; ++g) adem_motion_free(&motion[g]);
    free(material);
    free(inactive);
    free(motion);
    free(ref0);
  }
  return st;
}

/* ---------------------------------------------------------------- servos */

bool adem_walls_has_servo(const adem_walls *wl) {
  for (int k = 0; k < wl->nplanes; ++k)
    if (wl->planes[k].motion.servo.on) return true;
  for (int g = 0; g < wl->mesh.ngroups; ++g)
    if (wl->mesh_motion[g].servo.on) return true;
  return false;
}

/* One step of the servo law from the measured force F along its axis. */
static void servo_advance(adem_motion *m, double f, double dt) {
  const adem_servo_def *s = &m->servo;
  if (!m->servo_started || !(s->filter > 0.0))
    m->servo_force = f;
  else /* backward-Euler low-pass: stable for any dt */
    m->servo_force += dt / (s->filter + dt) * (f - m->servo_force);
  m->servo_started = true;
  double v = s->gain * (m->servo_force - s->target_force);
  v = fmin(fmax(v, -s->max_speed), s->max_speed);
  double u = m->servo_u + v * dt;
  if (u > s->travel_max || u < s->travel_min) { /* stops at the limit */
    u = fmin(fmax(u, s->travel_min), s->travel_max);
    v = (u - m->servo_u) / dt;
  }
  m->servo_u = u;
  m->servo_v = v;
}

/* First group of mesh wall k with a servo, or -1. */
static int wall_servo_group(const adem_walls *wl, int k) {
  const adem_mesh_wall *mw = &wl->mesh_walls[k];
  for (int g = mw->first; g < mw->first + mw->count; ++g)
    if (wl->mesh_motion[g].servo.on) return g;
  return -1;
}

void adem_walls_servo_step(adem_walls *wl, const adem_vec3 *plane_force, double dt) {
  for (int k = 0; k < wl->nplanes; ++k) {
    adem_plane *pl = &wl->planes[k];
    if (!pl->motion.servo.on || pl->inactive) continue; /* a switched-off wall stays put */
    servo_advance(&pl->motion, v3_dot(plane_force[k], pl->motion.servo.axis), dt);
  }
  const adem_mesh *m = &wl->mesh;
  for (int k = 0; k < wl->nmesh_walls; ++k) {
    int g0 = wall_servo_group(wl, k);
    if (g0 < 0) continue;
    const adem_mesh_wall *mw = &wl->mesh_walls[k];
    adem_motion *lead = &wl->mesh_motion[g0];
    adem_vec3 f = v3_zero();
    bool measured = false;
    for (int g = g0; g < mw->first + mw->count; ++g) {
      const adem_motion *mo = &wl->mesh_motion[g];
      if (!mo->servo.on || mo->servo.unmeasured || !adem_walls_mesh_active(wl, (uint32_t)g)) continue;
      measured = true;
      const adem_mesh_group *grp = &m->groups[g];
      adem_vec3 fg = v3_zero(); /* as adem_walls_mesh_loads sums it */
      for (size_t j = grp->first; j < (size_t)grp->first + grp->count; ++j)
        fg = v3_add(fg, v3(wl->face_force[3 * j], wl->face_force[3 * j + 1], wl->face_force[3 * j + 2]));
      f = v3_add(f, fg);
    }
    if (!measured) continue;
    servo_advance(lead, v3_dot(f, lead->servo.axis), dt);
    for (int g = g0 + 1; g < mw->first + mw->count; ++g) {
      adem_motion *mo = &wl->mesh_motion[g];
      if (!mo->servo.on) continue;
      mo->servo_u = lead->servo_u;
      mo->servo_v = lead->servo_v;
      mo->servo_force = lead->servo_force;
      mo->servo_started = lead->servo_started;
    }
  }
}

const adem_motion *adem_walls_plane_servo(const adem_walls *wl, int k) {
  return wl->planes[k].motion.servo.on ? &wl->planes[k].motion : NULL;
}

const adem_motion *adem_walls_mesh_wall_servo(const adem_walls *wl, int k) {
  int g = wall_servo_group(wl, k);
  return g >= 0 ? &wl->mesh_motion[g] : NULL;
}

adem_vec3 adem_walls_plane_displacement(const adem_walls *wl, int k) {
  const adem_plane *pl = &wl->planes[k];
  return pl->motion.moving ? v3_sub(pl->def.point, pl->point0) : v3_zero();
}

adem_vec3 adem_walls_mesh_wall_displacement(const adem_walls *wl, int k) {
  const adem_mesh_wall *mw = &wl->mesh_walls[k];
  if (mw->count == 0) return v3_zero();
  /* the wall's point travels with its first group (adem_walls_mesh_loads) */
  return v3_sub(adem_motion_place(&wl->mesh_motion[mw->first], wl->time, mw->ref0), mw->ref0);
}

void adem_walls_save_state(adem_writer *wr, const adem_walls *wl) {
  for (int k = 0; k < wl->nplanes; ++k) {
    adem_put_vec(wr, wl->planes[k].point0);
    adem_put_vec(wr, wl->planes[k].normal0);
    adem_motion_save_servo(wr, &wl->planes[k].motion);
  }
  const adem_mesh *m = &wl->mesh;
  adem_put_array(wr, wl->mesh_vert0, m->nverts, sizeof *wl->mesh_vert0);
  adem_put_array(wr, wl->mesh_normal0, m->ntris, sizeof *wl->mesh_normal0);
  for (int g = 0; g < m->ngroups; ++g) {
    adem_put_vec(wr, wl->mesh_ref0[g]);
    adem_motion_save_servo(wr, &wl->mesh_motion[g]);
  }
  for (int k = 0; k < wl->nmesh_walls; ++k) adem_put_vec(wr, wl->mesh_walls[k].ref0);
}

void adem_walls_load_state(adem_reader *rd, adem_walls *wl) {
  for (int k = 0; k < wl->nplanes; ++k) {
    wl->planes[k].point0 = adem_get_vec(rd);
    wl->planes[k].normal0 = adem_get_vec(rd);
    adem_motion_load_servo(rd, &wl->planes[k].motion);
  }
  const adem_mesh *m = &wl->mesh;
  adem_get_array(rd, wl->mesh_vert0, m->nverts, sizeof *wl->mesh_vert0);
  adem_get_array(rd, wl->mesh_normal0, m->ntris, sizeof *wl->mesh_normal0);
  for (int g = 0; g < m->ngroups; ++g) {
    wl->mesh_ref0[g] = adem_get_vec(rd);
    if (!wl->mesh_motion[g].moving) wl->mesh_ref[g] = wl->mesh_ref0[g]; /* placing skips it */
    adem_motion_load_servo(rd, &wl->mesh_motion[g]);
  }
  for (int k = 0; k < wl->nmesh_walls; ++k) wl->mesh_walls[k].ref0 = adem_get_vec(rd);
}
