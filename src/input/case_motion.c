/* Case files: a wall's `motion` (tables, velocities, rotations) and its `servo`. */
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

/* ---- wall motion and mesh walls ---- */

/* A table of rows [t, x, y, z] under key `key` of mo (absent: *n = 0), times strictly
 * increasing; fresh arrays in *time and *xyz. `what` names the three columns in messages. */
static adem_status read_table(case_ctx *ctx, const map_cursor *mo, const char *key,
                              const char *what, double **time, adem_vec3 **xyz, size_t *n,
                              yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *table;
  char path[KEY_PATH_MAX];
  *n = 0;
  adem_status st = adem_yaml_lookup(ctx, mo, key, &e, &table, path);
  *node = table && !adem_yaml_is_null(table) ? table : NULL;
  if (st || !*node) return st;
  if (table->type != YAML_SEQUENCE_NODE) return adem_yaml_wrong_type(ctx, e, table, path);
  size_t rows = (size_t)(table->data.sequence.items.top - table->data.sequence.items.start);
  if (rows == 0) return adem_yaml_fail(ctx, table, path, "needs at least 1 row [t, %s]", what);
  *time = malloc(rows * sizeof **time);
  *xyz = malloc(rows * sizeof **xyz);
  if (!*time || !*xyz) return adem_yaml_nomem(ctx);
  for (size_t k = 0; k < rows; ++k) {
    yaml_node_t *row = adem_yaml_node_at(ctx, table->data.sequence.items.start[k]);
    char rp[KEY_PATH_MAX + 24], t[128];
    snprintf(rp, sizeof rp, "%s[%zu]", path, k);
    double x[4];
    bool ok = row->type == YAML_SEQUENCE_NODE &&
              row->data.sequence.items.top - row->data.sequence.items.start == 4;
    for (int j = 0; ok && j < 4; ++j)
      ok = adem_yaml_parse_number(adem_yaml_node_at(ctx, row->data.sequence.items.start[j]), &x[j]);
    if (!ok) {
      adem_yaml_node_text(row, t, sizeof t);
      return adem_yaml_fail(ctx, row, rp, "expected a row [t, %s] of 4 numbers (%s), got %s", what,
                            e->unit, t);
    }
    if (k > 0 && !(x[0] > (*time)[k - 1]))
      return adem_yaml_fail(ctx, row, rp,
                            "the table is not ordered in time: t = %g s does not come after t = %g s of "
                            "the row before; times must increase strictly",
                            x[0], (*time)[k - 1]);
    (*time)[k] = x[0];
    (*xyz)[k] = v3(x[1], x[2], x[3]);
  }
  *n = rows;
  return ADEM_OK;
}

/* `motion.servo` (absent: def->on = 0). `groups` is read with the mesh (adem_case_servo_groups). */
static adem_status read_servo(case_ctx *ctx, const map_cursor *mo, adem_servo_def *def) {
  map_cursor sv;
  memset(def, 0, sizeof *def);
  adem_status st = adem_yaml_get_map(ctx, mo, "servo", &sv);
  if (st || !sv.node) return st;
  yaml_node_t *axis_node, *travel_node;
  char path[KEY_PATH_MAX];
  def->on = 1;
  if ((st = adem_yaml_get_vec3(ctx, &sv, "axis", &def->axis, &axis_node))) return st;
  if (!(v3_norm(def->axis) > 0.0) || !isfinite(v3_norm(def->axis))) {
    adem_yaml_join(path, sizeof path, sv.path, "axis");
    return adem_yaml_fail(ctx, axis_node, path, "must be a non-zero vector (the direction the servo acts along)");
  }
  if ((st = adem_yaml_get_number(ctx, &sv, "target_force", &def->target_force, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, &sv, "gain", &def->gain, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, &sv, "max_speed", &def->max_speed, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, &sv, "filter", &def->filter, NULL))) return st;
  double *travel = NULL;
  size_t nt = 0;
  if ((st = adem_case_get_numbers(ctx, &sv, "travel", &travel, &nt, &travel_node))) return st;
  if (travel_node) {
    adem_yaml_join(path, sizeof path, sv.path, "travel");
    bool ok = nt == 2 && travel[0] <= 0.0 && travel[1] >= 0.0 && !(travel[0] == 0.0 && travel[1] == 0.0);
    if (ok) {
      def->travel_min = travel[0];
      def->travel_max = travel[1];
    }
    free(travel);
    if (!ok)
      return adem_yaml_fail(ctx, travel_node, path,
                            "expected [min, max] in m with min <= 0 <= max, not both 0 (the servo "
                            "starts at 0)");
  }
  yaml_node_t *groups = adem_yaml_map_get(ctx, sv.node, "groups");
  if (groups && !adem_yaml_is_null(groups) && groups->type != YAML_SCALAR_NODE &&
      groups->type != YAML_SEQUENCE_NODE) {
    adem_yaml_join(path, sizeof path, sv.path, "groups");
    return adem_yaml_fail(ctx, groups, path, "expected a group name or a list of group names");
  }
  ctx->vmax = fmax(ctx->vmax, def->max_speed);
  return ADEM_OK;
}

/* Whether mesh group `name` of a file is among the names of `servo.groups` (its solid's name, or
 * the whole group name). */
static bool servo_group_listed(case_ctx *ctx, yaml_node_t *groups, const char *name) {
  const char *dot = strrchr(name, '.');
  size_t n = groups->type == YAML_SEQUENCE_NODE
                 ? (size_t)(groups->data.sequence.items.top - groups->data.sequence.items.start)
                 : 1;
  for (size_t k = 0; k < n; ++k) {
    yaml_node_t *it = groups->type == YAML_SEQUENCE_NODE
                          ? adem_yaml_node_at(ctx, groups->data.sequence.items.start[k])
                          : groups;
    const char *v = it->type == YAML_SCALAR_NODE ? adem_yaml_sval(it) : "";
    if (!strcmp(v, name) || (dot && !strcmp(v, dot + 1))) return true;
  }
  return false;
}

/* `servo.groups` of mesh wall `m`, whose groups are first .. ngroups - 1: every name must be one
 * of them; the others are marked unmeasured in md. Returns the groups not measured via flags. */
adem_status adem_case_servo_groups(case_ctx *ctx, const map_cursor *m, int first, bool *unmeasured) {
  adem_world *w = ctx->w;
  int ng = w->walls.mesh.ngroups;
  yaml_node_t *mo = adem_yaml_map_get(ctx, m->node, "motion");
  yaml_node_t *sv = mo && mo->type == YAML_MAPPING_NODE ? adem_yaml_map_get(ctx, mo, "servo") : NULL;
  yaml_node_t *groups = sv && sv->type == YAML_MAPPING_NODE ? adem_yaml_map_get(ctx, sv, "groups") : NULL;
  for (int g = first; g < ng; ++g) unmeasured[g - first] = false;
  if (!groups || adem_yaml_is_null(groups)) return ADEM_OK;
  char path[KEY_PATH_MAX], gp[KEY_PATH_MAX];
  adem_yaml_join(gp, sizeof gp, m->path, "motion.servo.groups");
  size_t n = groups->type == YAML_SEQUENCE_NODE
                 ? (size_t)(groups->data.sequence.items.top - groups->data.sequence.items.start)
                 : 1;
  if (n == 0) return adem_yaml_fail(ctx, groups, gp, "needs at least one group name");
  for (size_t k = 0; k < n; ++k) {
    yaml_node_t *it = groups->type == YAML_SEQUENCE_NODE
                          ? adem_yaml_node_at(ctx, groups->data.sequence.items.start[k])
                          : groups;
    snprintf(path, sizeof path, "%.200s[%zu]", gp, k);
    const char *v = it->type == YAML_SCALAR_NODE ? adem_yaml_sval(it) : NULL;
    bool found = false;
    for (int g = first; v && g < ng && !found; ++g) {
      const char *name = w->walls.mesh.groups[g].name, *dot = strrchr(name, '.');
      found = !strcmp(v, name) || (dot && !strcmp(v, dot + 1));
    }
    if (!found) {
      char list[512] = "";
      for (int g = first; g < ng; ++g) adem_yaml_list_append(list, sizeof list, w->walls.mesh.groups[g].name);
      char t[128];
      adem_yaml_node_text(it, t, sizeof t);
      return adem_yaml_fail(ctx, it, groups->type == YAML_SEQUENCE_NODE ? path : gp,
                            "%s is not a group of this mesh; its groups are: %s", t, list);
    }
  }
  for (int g = first; g < ng; ++g)
    unmeasured[g - first] = !servo_group_listed(ctx, groups, w->walls.mesh.groups[g].name);
  return ADEM_OK;
}

/* A prescribed motion read from `motion` (absent: *given = false). The table's arrays are
 * allocated into *time and *vel (free them); def points into them. */
adem_status adem_case_read_motion(case_ctx *ctx, const map_cursor *wall, adem_motion_def *def,
                                  double **time, adem_vec3 **vel, bool *given, yaml_node_t **at) {
  map_cursor mo, rot;
  memset(def, 0, sizeof *def);
  *time = NULL;
  *vel = NULL;
  *given = false;
  adem_status st = adem_yaml_get_map(ctx, wall, "motion", &mo);
  if (st || !mo.node) return st;
  *given = true;
  *at = mo.node;
  yaml_node_t *vnode, *table, *positions;
  adem_vec3 v;
  char path[KEY_PATH_MAX];
  if ((st = adem_yaml_get_vec3(ctx, &mo, "velocity", &v, &vnode))) return st;
  size_t n = 0;
  if ((st = read_table(ctx, &mo, "table", "vx, vy, vz", time, vel, &n, &table))) return st;
  if (!table && (st = read_table(ctx, &mo, "positions", "x, y, z", time, vel, &n, &positions)))
    return st;
  if (table) positions = adem_yaml_map_get(ctx, mo.node, "positions");
  int ngiven = (vnode != NULL) + (table != NULL) + (positions != NULL && !adem_yaml_is_null(positions));
  if (ngiven > 1) {
    yaml_node_t *second = table && vnode ? table : positions;
    adem_yaml_join(path, sizeof path, mo.path, second == table ? "table" : "positions");
    return adem_yaml_fail(ctx, second, path,
                          "give one translation: `velocity` (constant), `table` (velocities) or "
                          "`positions` (displacements), not %s",
                          ngiven == 3 ? "all three" : "two of them");
  }
  if (table) {
    def->n = n;
  } else if (positions) {
    def->n = n;
    def->position = *vel; /* displacements */
  } else if (vnode) {
    *time = malloc(sizeof **time);
    *vel = malloc(sizeof **vel);
    if (!*time || !*vel) return adem_yaml_nomem(ctx);
    (*time)[0] = 0.0;
    (*vel)[0] = v;
    def->n = 1;
  }
  def->time = *time;
  if (def->position) {
    for (size_t k = 0; k + 1 < def->n; ++k)
      ctx->vmax = fmax(ctx->vmax, v3_norm(v3_sub((*vel)[k + 1], (*vel)[k])) /
                                      ((*time)[k + 1] - (*time)[k]));
  } else {
    def->velocity = *vel;
    for (size_t k = 0; k < def->n; ++k) ctx->vmax = fmax(ctx->vmax, v3_norm((*vel)[k]));
  }
  if ((st = read_servo(ctx, &mo, &def->servo))) return st;
  if ((st = adem_yaml_get_map(ctx, &mo, "rotation", &rot))) return st;
  if (rot.node) {
    yaml_node_t *axis_node;
    if ((st = adem_yaml_get_vec3(ctx, &rot, "axis", &def->axis, &axis_node))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &rot, "center", &def->center, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, &rot, "speed", &def->angular_speed, NULL))) return st;
    if (!(v3_norm(def->axis) > 0.0)) {
      adem_yaml_join(path, sizeof path, rot.path, "axis");
      return adem_yaml_fail(ctx, axis_node, path, "must be a non-zero vector");
    }
  }
  return ADEM_OK;
}

/* Planes, mesh groups and files of several groups each get CSV columns under their name: no
 * name may be two of them. */
