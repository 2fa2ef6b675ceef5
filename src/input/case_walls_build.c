/* Case files: `walls` (planes, boxes, mesh walls from STL files; cylinders and plates in
 * case_walls.c). */
#include "adem/case.h"
#include "adem/world.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "stl.h"
#include "log.h"
#include "rng.h"
#include "schedule.h"
#include "insert.h"
#include "outlets.h"
#include "case_yaml.h"
#include "case_build.h"
#include "case_walls.h"
#include "schema.h"
#include "stages.h"
#include "adem/vec3.h"
#include "world_internal.h"

static adem_status check_wall_names(case_ctx *ctx, const map_cursor *m) {
  const adem_world *w = ctx->w;
  int ng = w->walls.mesh.ngroups, nw = w->walls.nmesh_walls;
  for (int a = 0; a < ng + nw; ++a) {
    const char *an = a < ng ? w->walls.mesh.groups[a].name : w->walls.mesh_walls[a - ng].name;
    if (a >= ng && w->walls.mesh_walls[a - ng].count < 2) continue;
    for (int k = 0; k < w->walls.nplanes; ++k)
      if (!strcmp(an, w->walls.planes[k].def.name))
        return adem_yaml_fail(ctx, m->node, m->path,
                              "the name `%s` is used by a plane and by a mesh; give one of them another "
                              "`name`",
                              an);
    for (int b = ng; b < a; ++b)
      if (w->walls.mesh_walls[b - ng].count >= 2 && !strcmp(an, w->walls.mesh_walls[b - ng].name))
        return adem_yaml_fail(ctx, m->node, m->path,
                              "the name `%s` is used by two meshes; give one of them another `name`", an);
    for (int g = 0; a >= ng && g < ng; ++g)
      if (!strcmp(an, w->walls.mesh.groups[g].name))
        return adem_yaml_fail(ctx, m->node, m->path,
                              "the name `%s` is used by a mesh file and by a mesh group; give one of them "
                              "another `name`",
                              an);
  }
  return ADEM_OK;
}

/* `rotate`: one {axis, angle} mapping or a list of them, composed in order onto tf. */
static adem_status read_rotations(case_ctx *ctx, const map_cursor *wall, adem_mesh_transform *tf) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, wall, "rotate", &e, &v, path);
  if (st || !v || adem_yaml_is_null(v)) return st;
  size_t n = 1;
  if (v->type == YAML_SEQUENCE_NODE)
    n = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
  else if (v->type != YAML_MAPPING_NODE)
    return adem_yaml_fail(ctx, v, path, "expected `{axis: [x, y, z], angle: degrees}` or a list of them");
  for (size_t k = 0; k < n; ++k) {
    map_cursor r;
    char rp[KEY_PATH_MAX];
    yaml_node_t *item = v;
    if (v->type == YAML_SEQUENCE_NODE) {
      snprintf(rp, sizeof rp, "%.200s[%zu]", path, k);
      item = adem_yaml_node_at(ctx, v->data.sequence.items.start[k]);
    } else {
      snprintf(rp, sizeof rp, "%s", path);
    }
    if ((st = adem_yaml_map_open(ctx, item, v, rp, "walls[].rotate[]", NULL, &r))) return st;
    if (!r.node) return adem_yaml_fail(ctx, item, rp, "expected `{axis: [x, y, z], angle: degrees}`");
    adem_vec3 axis;
    double angle = 0.0;
    yaml_node_t *axis_node;
    if ((st = adem_yaml_get_vec3(ctx, &r, "axis", &axis, &axis_node))) return st;
    if ((st = adem_yaml_get_number(ctx, &r, "angle", &angle, NULL))) return st;
    adem_error werr = {ADEM_OK, ""};
    if (adem_mesh_transform_rotate(tf, axis, angle, &werr)) {
      char ap[KEY_PATH_MAX];
      adem_yaml_join(ap, sizeof ap, rp, "axis");
      return adem_yaml_fail(ctx, axis_node, ap, "%s", werr.message);
    }
  }
  return ADEM_OK;
}

/* The file of a mesh wall: relative paths start from the case file's folder. */
char *adem_case_mesh_path(const case_ctx *ctx, const char *file) {
  bool as_is = file[0] == '/' || !ctx->base_dir || !*ctx->base_dir || !strcmp(ctx->base_dir, ".");
  size_t n = (as_is ? 0 : strlen(ctx->base_dir) + 1) + strlen(file) + 1;
  char *p = malloc(n);
  if (p) snprintf(p, n, "%s%s%s", as_is ? "" : ctx->base_dir, as_is ? "" : "/", file);
  return p;
}

static adem_status build_mesh_wall(case_ctx *ctx, const map_cursor *m, int mat, const char *name) {
  adem_world *w = ctx->w;
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.material = mat;
  char file[ADEM_PATH_MAX], path[KEY_PATH_MAX];
  yaml_node_t *file_node, *own_node, *about_node, *motion_node = NULL;
  adem_error werr = {ADEM_OK, ""};
  char *resolved = NULL;
  int first = w->walls.mesh.ngroups;
  adem_status st;
  if ((st = adem_yaml_get_string(ctx, m, "file", file, sizeof file, &file_node))) return st;
  if ((st = adem_yaml_get_number(ctx, m, "scale", &tf.scale, NULL))) return st;
  if ((st = read_rotations(ctx, m, &tf))) return st;
  if ((st = adem_yaml_get_vec3(ctx, m, "translate", &tf.translation, NULL))) return st;
  adem_vec3 about;
  if ((st = adem_yaml_get_vec3(ctx, m, "torque_about", &about, &about_node))) return st;
  adem_motion_def md;
  double *times = NULL;
  adem_vec3 *vels = NULL;
  bool moves = false, own = false;
  st = adem_case_read_motion(ctx, m, &md, &times, &vels, &moves, &motion_node);
  if (!st) st = adem_yaml_get_bool(ctx, m, "own_vertices", &own);
  if (st) goto done;
  own_node = adem_yaml_map_get(ctx, m->node, "own_vertices");
  if (!own_node) own = moves;
  if (moves && !own) {
    adem_yaml_join(path, sizeof path, m->path, "own_vertices");
    st = adem_yaml_fail(ctx, own_node, path,
                        "a mesh with a `motion` needs its own vertices: set `own_vertices: true`");
    goto done;
  }
  tf.own_vertices = own;
  resolved = adem_case_mesh_path(ctx, file);
  if (!resolved) {
    st = adem_yaml_nomem(ctx);
    goto done;
  }
  st = adem_world_add_stl(w, resolved, &tf, name, v3_zero(), &werr);
  adem_yaml_join(path, sizeof path, m->path, "file");
  if (st) {
    st = werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, file_node, path, "%s", werr.message);
    goto done;
  }
  bool *unmeasured = calloc((size_t)(w->walls.mesh.ngroups - first) + 1, sizeof *unmeasured);
  if (!unmeasured) {
    st = adem_yaml_nomem(ctx);
    goto done;
  }
  st = md.servo.on ? adem_case_servo_groups(ctx, m, first, unmeasured) : ADEM_OK;
  for (int g = first; !st && g < w->walls.mesh.ngroups && moves; ++g) {
    md.servo.unmeasured = unmeasured[g - first];
    if (adem_world_set_mesh_motion(w, g, &md, &werr)) {
      adem_yaml_join(path, sizeof path, m->path, "motion");
      st = werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, motion_node, path, "%s", werr.message);
      break;
    }
    /* a rotating mesh's points move at up to omega times their distance from the axis */
    ctx->vmax = fmax(ctx->vmax, fabs(md.angular_speed) * w->walls.mesh_reach[g]);
  }
  free(unmeasured);
  if (st) goto done;
  if (about_node && adem_world_set_mesh_torque_point(w, w->walls.nmesh_walls - 1, about, &werr)) {
    adem_yaml_join(path, sizeof path, m->path, "torque_about");
    st = adem_yaml_fail(ctx, about_node, path, "%s", werr.message);
    goto done;
  }
  if (first < w->walls.mesh.ngroups) { /* the file's bounding box */
    const adem_mesh *mesh = &w->walls.mesh;
    for (size_t t = mesh->groups[first].first; t < mesh->ntris; ++t)
      for (int k = 0; k < 3; ++k) {
        adem_vec3 x = mesh->vert[mesh->tri[t][k]];
        adem_case_box_include(ctx, x, x);
      }
  }
done:
  free(resolved);
  free(times);
  free(vels);
  return st;
}

/* `motion` of plane `plane` (not together with its `velocity`). */
static adem_status plane_motion(case_ctx *ctx, const map_cursor *m, int plane,
                                const yaml_node_t *velocity_node) {
  adem_motion_def md;
  double *times = NULL;
  adem_vec3 *vels = NULL;
  bool moves = false;
  yaml_node_t *at = NULL;
  char path[KEY_PATH_MAX];
  adem_status st = adem_case_read_motion(ctx, m, &md, &times, &vels, &moves, &at);
  adem_yaml_join(path, sizeof path, m->path, "motion");
  yaml_node_t *sv = !st && md.servo.on ? adem_yaml_map_get(ctx, at, "servo") : NULL;
  yaml_node_t *groups = sv ? adem_yaml_map_get(ctx, sv, "groups") : NULL;
  if (groups && !adem_yaml_is_null(groups)) {
    char gp[KEY_PATH_MAX];
    adem_yaml_join(gp, sizeof gp, path, "servo.groups");
    st = adem_yaml_fail(ctx, groups, gp, "is for mesh walls only (a plane is one wall)");
  }
  if (!st && moves && velocity_node)
    st = adem_yaml_fail(ctx, at, path, "give either `velocity` or `motion`, not both");
  adem_error werr = {ADEM_OK, ""};
  if (!st && moves && adem_world_set_plane_motion(ctx->w, plane, &md, &werr))
    st = werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, at, path, "%s", werr.message);
  free(times);
  free(vels);
  return st;
}

/* `active: false`: the planes and mesh groups the wall made are switched off. */
static adem_status wall_active(case_ctx *ctx, const map_cursor *m, int planes_before,
                               int meshes_before) {
  bool active = true;
  adem_status st = adem_yaml_get_bool(ctx, m, "active", &active);
  adem_error werr = {ADEM_OK, ""};
  for (int k = planes_before; !st && !active && k < ctx->w->walls.nplanes; ++k)
    if (adem_world_set_plane_active(ctx->w, k, false, &werr)) st = adem_yaml_nomem(ctx);
  for (int g = meshes_before; !st && !active && g < ctx->w->walls.mesh.ngroups; ++g)
    if (adem_world_set_mesh_active(ctx->w, g, false, &werr)) st = adem_yaml_nomem(ctx);
  return st;
}

adem_status adem_case_build_walls(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "walls", &l);
  if (st || l.n == 0) return st;
  char(*names)[ADEM_NAME_MAX] = calloc(l.n, sizeof *names);
  yaml_node_t **nodes = calloc(l.n, sizeof *nodes);
  if (!names || !nodes) {
    free(names);
    free(nodes);
    return adem_yaml_nomem(ctx);
  }
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    char material[ADEM_NAME_MAX], path[KEY_PATH_MAX];
    yaml_node_t *name_node, *mat_node;
    int mat;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    int planes_before = ctx->w->walls.nplanes, meshes_before = ctx->w->walls.mesh.ngroups;
    if ((st = adem_yaml_get_string(ctx, &m, "name", names[i], sizeof names[i], &name_node))) break;
    if (!name_node) snprintf(names[i], sizeof names[i], "wall%zu", i);
    nodes[i] = name_node ? name_node : m.node;
    for (size_t k = 0; k < i && !st; ++k)
      if (!strcmp(names[k], names[i])) {
        char first[LOC_MAX];
        adem_yaml_where_short(ctx, nodes[k], first, sizeof first);
        adem_yaml_join(path, sizeof path, m.path, "name");
        st = adem_yaml_fail(ctx, nodes[i], path, "duplicate wall name `%s` (first used at %s)", names[i],
                            first);
      }
    if (st) break;
    if ((st = adem_yaml_get_string(ctx, &m, "material", material, sizeof material, &mat_node))) break;
    adem_yaml_join(path, sizeof path, m.path, "material");
    if ((st = adem_case_find_material(ctx, material, mat_node, path, &mat))) break;
    adem_error werr = {ADEM_OK, ""};
    if (!strcmp(m.variant, "plane")) {
      adem_plane_def d = adem_default_plane_def();
      yaml_node_t *normal_node;
      snprintf(d.name, sizeof d.name, "%s", names[i]);
      d.material = mat;
      if ((st = adem_yaml_get_vec3(ctx, &m, "point", &d.point, NULL))) break;
      if ((st = adem_yaml_get_vec3(ctx, &m, "normal", &d.normal, &normal_node))) break;
      yaml_node_t *velocity_node;
      if ((st = adem_yaml_get_vec3(ctx, &m, "velocity", &d.velocity, &velocity_node))) break;
      double len = v3_norm(d.normal);
      if (!(len > 0) || !isfinite(len)) {
        adem_yaml_join(path, sizeof path, m.path, "normal");
        st = adem_yaml_fail(ctx, normal_node, path, "must be a non-zero vector");
        break;
      }
      d.normal = v3_scale(d.normal, 1.0 / len);
      if (adem_world_add_plane(ctx->w, &d, NULL, &werr)) {
        st = werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, m.node, m.path, "%s", werr.message);
        break;
      }
      adem_case_box_include(ctx, d.point, d.point);
      ctx->vmax = fmax(ctx->vmax, v3_norm(d.velocity));
      if ((st = plane_motion(ctx, &m, ctx->w->walls.nplanes - 1, velocity_node))) break;
    } else if (!strcmp(m.variant, "mesh")) {
      if ((st = build_mesh_wall(ctx, &m, mat, name_node ? names[i] : NULL))) break;
    } else if (!strcmp(m.variant, "cylinder") || !strcmp(m.variant, "plate")) {
      double reach = 0.0; /* case_walls.c; every part moves with the wall's `motion` */
      bool cyl = !strcmp(m.variant, "cylinder");
      if ((st = adem_case_curved_wall(ctx, &m, names[i], mat, cyl, &reach))) break;
      adem_vec3 pt = ctx->w->walls.planes[planes_before].def.point, e = v3(reach, reach, reach);
      adem_case_box_include(ctx, v3_sub(pt, e), v3_add(pt, e));
      for (int k = planes_before; !st && k < ctx->w->walls.nplanes; ++k) {
        if ((st = plane_motion(ctx, &m, k, NULL))) break;
        const adem_motion *mo = &ctx->w->walls.planes[k].motion; /* its points' largest speed */
        double arm = reach + v3_norm(v3_sub(mo->center, pt));
        ctx->vmax = fmax(ctx->vmax, fabs(mo->omega) * arm + v3_norm(adem_motion_velocity(mo, 0.0)));
      }
      if (st) break;
    } else {
      adem_vec3 lo, hi;
      yaml_node_t *hi_node;
      if ((st = adem_yaml_get_vec3(ctx, &m, "min", &lo, NULL))) break;
      if ((st = adem_yaml_get_vec3(ctx, &m, "max", &hi, &hi_node))) break;
      if ((st = adem_case_check_box(ctx, lo, hi, hi_node, &m))) break;
      if (adem_world_add_box(ctx->w, names[i], lo, hi, mat, NULL, &werr)) {
        st = werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, m.node, m.path, "%s", werr.message);
        break;
      }
      adem_case_box_include(ctx, lo, hi);
    }
    st = check_wall_names(ctx, &m);
    if (!st) st = wall_active(ctx, &m, planes_before, meshes_before);
  }
  free(names);
  free(nodes);
  return st;
}
