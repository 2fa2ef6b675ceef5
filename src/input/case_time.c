/* Case files: `time.until` (run-until conditions), `time.step` (the proposal and the checks of a
 * step given) and the load-time warnings about forces that pull contacts apart. */
#include "adem/case.h"
#include "adem/laws.h"
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

/* ---- run-until conditions ---- */

/* `until` of parent (time, or a stage): *given false when absent. Walls must be built. */
adem_status adem_case_read_until(case_ctx *ctx, const map_cursor *parent, adem_until_def *def,
                                 bool *given) {
  map_cursor u, wl;
  memset(def, 0, sizeof *def);
  *given = false;
  adem_status st = adem_yaml_get_map(ctx, parent, "until", &u);
  if (st || !u.node) return st;
  *given = true;
  yaml_node_t *ke_node, *for_node, *interval_node;
  char path[KEY_PATH_MAX];
  if ((st = adem_yaml_get_number(ctx, &u, "kinetic_energy_per_particle", &def->kinetic, &ke_node)))
    return st;
  if (!ke_node) def->kinetic = 0.0;
  yaml_node_t *ratio_node;
  if ((st = adem_yaml_get_number(ctx, &u, "kinetic_energy_ratio", &def->kinetic_ratio, &ratio_node)))
    return st;
  if (!ratio_node) def->kinetic_ratio = 0.0;
  else if (!(v3_norm(ctx->w->gravity) > 0.0)) {
    char rpath[KEY_PATH_MAX];
    adem_yaml_join(rpath, sizeof rpath, u.path, "kinetic_energy_ratio");
    return adem_yaml_fail(ctx, ratio_node, rpath, "is relative to sum m |g| d and gravity is zero: "
                                                  "give `kinetic_energy_per_particle` instead");
  }
  if ((st = adem_yaml_get_map(ctx, &u, "wall_load", &wl))) return st;
  if (wl.node) {
    const adem_world *w = ctx->w;
    yaml_node_t *wall_node, *dir_node;
    def->load = true;
    if ((st = adem_yaml_get_string(ctx, &wl, "wall", def->wall, sizeof def->wall, &wall_node)))
      return st;
    if ((st = adem_yaml_get_vec3(ctx, &wl, "direction", &def->direction, &dir_node))) return st;
    if ((st = adem_yaml_get_number(ctx, &wl, "tolerance", &def->tolerance, NULL))) return st;
    def->wall_index = -1;
    char names[600] = "";
    suggestion sg = {def->wall, NULL, (size_t)-1};
    for (int k = 0; k < w->walls.nplanes; ++k) {
      if (def->wall_index < 0 && !strcmp(w->walls.planes[k].def.name, def->wall)) {
        def->wall_kind = ADEM_UNTIL_PLANE;
        def->wall_index = k;
      }
      adem_yaml_list_append(names, sizeof names, w->walls.planes[k].def.name);
      adem_yaml_suggest_try(&sg, w->walls.planes[k].def.name);
    }
    for (int k = 0; k < w->walls.mesh.ngroups; ++k) {
      if (def->wall_index < 0 && !strcmp(w->walls.mesh.groups[k].name, def->wall)) {
        def->wall_kind = ADEM_UNTIL_MESH_GROUP;
        def->wall_index = k;
      }
      adem_yaml_list_append(names, sizeof names, w->walls.mesh.groups[k].name);
      adem_yaml_suggest_try(&sg, w->walls.mesh.groups[k].name);
    }
    for (int k = 0; k < w->walls.nmesh_walls; ++k) {
      if (w->walls.mesh_walls[k].count < 2) continue;
      if (def->wall_index < 0 && !strcmp(w->walls.mesh_walls[k].name, def->wall)) {
        def->wall_kind = ADEM_UNTIL_MESH_WALL;
        def->wall_index = k;
      }
      adem_yaml_list_append(names, sizeof names, w->walls.mesh_walls[k].name);
      adem_yaml_suggest_try(&sg, w->walls.mesh_walls[k].name);
    }
    adem_yaml_join(path, sizeof path, wl.path, "wall");
    if (def->wall_index < 0) {
      if (sg.best)
        return adem_yaml_fail(ctx, wall_node, path, "no wall is named `%s`; did you mean `%s`? The "
                                                    "walls: %s",
                              def->wall, sg.best, names[0] ? names : "none");
      return adem_yaml_fail(ctx, wall_node, path, "no wall is named `%s`; the walls: %s", def->wall,
                            names[0] ? names : "none");
    }
    if (!dir_node) def->direction = w->gravity; /* along gravity, as the loads plot */
    double len = v3_norm(def->direction);
    if (!(len > 0.0)) {
      adem_yaml_join(path, sizeof path, wl.path, "direction");
      return adem_yaml_fail(ctx, dir_node ? dir_node : wl.node, path,
                            dir_node ? "must be a non-zero vector"
                                     : "gravity is zero: give the direction of the load");
    }
    def->direction = v3_scale(def->direction, 1.0 / len);
  }
  if (!ke_node && !ratio_node && !wl.node)
    return adem_yaml_fail(ctx, u.node, u.path,
                          "give a condition: `kinetic_energy_per_particle`, "
                          "`kinetic_energy_ratio`, `wall_load` or more than one");
  if ((st = adem_yaml_get_number(ctx, &u, "for", &def->hold, &for_node))) return st;
  if ((st = adem_yaml_get_number(ctx, &u, "interval", &def->interval, &interval_node))) return st;
  if (!interval_node) def->interval = def->hold > 0.0 ? def->hold / 10.0 : 0.0; /* 0: every step */
  return ADEM_OK;
}

/* time.step: the proposal at v_ref (rule in the reference doc), or the user's step checked
 * against it. */
adem_status adem_case_choose_step(case_ctx *ctx, const map_cursor *time, adem_vec3 g) {
  adem_case *c = ctx->c;
  bool step_auto, speed_auto;
  double step = 0, v_ref = 0;
  yaml_node_t *step_node;
  adem_status st;
  if ((st = adem_yaml_get_auto(ctx, time, "step", &step_auto, &step, &step_node))) return st;
  if ((st = adem_yaml_get_auto(ctx, time, "reference_speed", &speed_auto, &v_ref, NULL))) return st;
  if (speed_auto) {
    double gn = v3_norm(g), height = 0;
    if (gn > 0 && ctx->has_box) {
      adem_vec3 ext = v3_sub(ctx->box_hi, ctx->box_lo);
      height = (fabs(g.x) * ext.x + fabs(g.y) * ext.y + fabs(g.z) * ext.z) / gn;
    }
    v_ref = fmax(fmax(ctx->vmax, sqrt(2.0 * gn * height)), 0.1);
  }
  c->estimate = adem_world_estimate_step(ctx->w, v_ref);
  /* t_collision/5 (accuracy) or the contacts' stability limit (damping and the tangential-
   * rotational and rolling modes), whichever is shorter */
  double limit = c->estimate.dt_limit;
  bool stab = c->estimate.dt_stable < c->estimate.t_collision / ADEM_STEP_LIMIT_DIVISOR;
  char limit_name[128];
  if (stab) snprintf(limit_name, sizeof limit_name, "stability limit of the contacts' modes t_collision/%.3g", c->estimate.t_collision / limit);
  else snprintf(limit_name, sizeof limit_name, "limit t_collision/%g (accuracy; the contacts are stable to t_collision/%.3g)", ADEM_STEP_LIMIT_DIVISOR, c->estimate.t_collision / c->estimate.dt_stable);
  bool proposal = c->estimate.dt > 0 && isfinite(c->estimate.dt);
  if (step_auto) {
    if (!proposal)
      return adem_yaml_fail(ctx, time->at, "time.step",
                            "`auto` cannot propose a step (no particles were created); give a number");
    adem_world_set_dt(ctx->w, c->estimate.dt);
    c->dt_auto = 1;
    c->dt_user_ratio = 1.0;
  } else {
    adem_world_set_dt(ctx->w, step);
    c->dt_auto = 0;
    c->dt_user_ratio = proposal ? step / c->estimate.dt : 0.0;
    if (proposal && isfinite(limit) && step > limit && !ctx->allow_large_step)
      return adem_yaml_fail(ctx, step_node ? step_node : time->at, "time.step",
                            "%g s is %.2fx the %s = %g s of the stiffest pair "
                            "(t_collision %g s at v_ref %g m/s): the explicit integration gains or loses "
                            "energy beyond it. Allowed: `auto` (%g s) or a step up to %g s; or set "
                            "limits.allow_large_step: true",
                            step, step / limit, limit_name,
                            limit, c->estimate.t_collision, v_ref, c->estimate.dt, limit);
    if (c->dt_user_ratio > 1.0) {
      bool collision = c->estimate.t_collision / 50.0 <= 0.2 * c->estimate.t_rayleigh;
      char loc[LOC_MAX];
      adem_yaml_where(ctx, step_node, loc, sizeof loc);
      adem_log(ADEM_LOG_WARN,
               "%s: time.step %g s is %.1fx the proposed %g s (%s); the %s = %g s is %.1fx "
               "the proposal%s",
               loc, step, c->dt_user_ratio,
               c->estimate.dt,
               c->estimate.dt < fmin(c->estimate.t_collision / 50.0, 0.2 * c->estimate.t_rayleigh)
                   ? "a fifth of the stability limit"
               : collision ? "t_collision/50"
                           : "0.2 t_Rayleigh",
               limit_name, limit, limit / c->estimate.dt,
               step > limit ? " and the step is above it (limits.allow_large_step)" : "");
    }
  }
  return ADEM_OK;
}

/* H section 6.2: with a reduced stiffness the force that breaks an adhesive contact drops (JKR:
 * to (8/9) 3 pi gamma_mod R; the normal law's pull_off hook). The group forces are constant, so
 * one look at load time finds every group whose force pulls hard enough, against any adhesive
 * pair its spheres can touch, to break contacts the real material would keep. One warning per
 * group, for its weakest pair. */
adem_status adem_case_warn_pulling_forces(case_ctx *ctx) {
  adem_world *w = ctx->w;
  size_t nm = (size_t)w->mat.n, ng = (size_t)w->ngroups;
  if (!w->mat.pairs || nm == 0) return ADEM_OK;
  double *rmin = malloc((ng + 1) * nm * sizeof *rmin); /* per group and material; last row: all */
  bool *wall = calloc(nm, sizeof *wall);
  if (!rmin || !wall) {
    free(rmin);
    free(wall);
    return adem_yaml_nomem(ctx);
  }
  for (size_t k = 0; k < (ng + 1) * nm; ++k) rmin[k] = INFINITY;
  for (size_t i = 0; i < w->p.n; ++i) {
    size_t g = w->p.group[i], m = w->p.material[i];
    rmin[g * nm + m] = fmin(rmin[g * nm + m], w->p.radius[i]);
    rmin[ng * nm + m] = fmin(rmin[ng * nm + m], w->p.radius[i]);
  }
  for (int k = 0; k < w->walls.nplanes; ++k) wall[w->walls.planes[k].def.material] = true;
  for (int k = 0; k < w->walls.mesh.ngroups; ++k) wall[w->walls.mesh.groups[k].material] = true;
  for (size_t g = 0; g < ng; ++g) {
    double force = v3_norm(w->groups[g].external_force);
    if (!(force > 0.0)) continue;
    double worst = 0.0, worst_pull = 0.0, worst_R = 0.0;
    size_t wa = 0, wb = 0;
    bool worst_wall = false;
    for (size_t a = 0; a < nm; ++a) {
      double ra = rmin[g * nm + a];
      if (!isfinite(ra)) continue;
      for (size_t b = 0; b < nm; ++b) {
        const adem_interaction *it = adem_world_interaction(w, (int)a, (int)b);
        double rb = rmin[ng * nm + b];
        for (int side = 0; side < 2; ++side) { /* 0: a sphere of b, 1: a wall of b */
          if (side == 0 && !isfinite(rb)) continue;
          if (side == 1 && !wall[b]) continue;
          double R = side ? ra : ra * rb / (ra + rb);
          /* the normal law's pull-off force (its hook; 0 for a law that holds nothing) */
          double pull = adem_laws_pull_off(adem_interaction_laws(it), &it->pp, R);
          if (!(pull > 0.0)) continue;
          if (force / pull > worst) {
            worst = force / pull;
            worst_pull = pull;
            worst_R = R;
            wa = a;
            wb = b;
            worst_wall = side == 1;
          }
        }
      }
    }
    if (worst < ADEM_PULLOFF_SAFETY) continue;
    const adem_interaction *it = adem_world_interaction(w, (int)wa, (int)wb);
    char loc[LOC_MAX] = "";
    for (int k = 0; k < ctx->ngroup; ++k)
      if (!strcmp(ctx->group_name[k], w->groups[g].name)) adem_yaml_where(ctx, ctx->group_node[k], loc, sizeof loc);
    if (!loc[0]) snprintf(loc, sizeof loc, "%.500s", ctx->file);
    adem_log(ADEM_LOG_WARN,
             "%s: group `%s`: its external force of %.3g N is %.0f%% of the force that breaks a "
             "`%s`-`%s`%s `%s` contact, its pull-off force %.3g N (R = %.3g m%s); such forces can "
             "tear apart contacts the real material keeps. Keep them below %.0f%% of it "
             "(%.3g N)%s (Haervig et al. section 6.2)",
             loc, w->groups[g].name, force, 100.0 * worst, w->mat.m[wa].def.name,
             w->mat.m[wb].def.name, worst_wall ? " (wall)" : "",
             adem_law_get(ADEM_SLOT_NORMAL, (int)it->normal)->name, worst_pull, worst_R,
             it->pp.E < it->pp.E_real ? ", reduced with the stiffness by H24" : "",
             100.0 * ADEM_PULLOFF_SAFETY, ADEM_PULLOFF_SAFETY * worst_pull,
             it->pp.E < it->pp.E_real ? " or reduce the stiffness less" : "");
  }
  free(rmin);
  free(wall);
  return ADEM_OK;
}
