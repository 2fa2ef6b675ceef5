/* Case files: `materials`, `interactions` (the law of each pair, its checks and warnings) and
 * `groups`. */
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

/* Index of the material called name (given at node), or an error naming the known ones. */
adem_status adem_case_find_material(case_ctx *ctx, const char *name, const yaml_node_t *node,
                                    const char *path, int *index) {
  char known[600] = "";
  suggestion s = {name, NULL, (size_t)-1};
  for (int k = 0; k < ctx->nmat; ++k) {
    if (!strcmp(ctx->mat_name[k], name)) {
      *index = k;
      return ADEM_OK;
    }
    adem_yaml_list_append(known, sizeof known, ctx->mat_name[k]);
    adem_yaml_suggest_try(&s, ctx->mat_name[k]);
  }
  if (s.best)
    return adem_yaml_fail(ctx, node, path, "unknown material `%s`; did you mean `%s`? Defined: %s", name,
                          s.best, known);
  return adem_yaml_fail(ctx, node, path, "unknown material `%s`; defined: %s", name, known);
}

adem_status adem_case_find_group(case_ctx *ctx, const char *name, const yaml_node_t *node,
                                 const char *path, int *index) {
  *index = adem_world_find_group(ctx->w, name);
  if (*index >= 0) return ADEM_OK;
  char known[600] = "default";
  suggestion s = {name, NULL, (size_t)-1};
  adem_yaml_suggest_try(&s, "default");
  for (int k = 0; k < ctx->ngroup; ++k) {
    adem_yaml_list_append(known, sizeof known, ctx->group_name[k]);
    adem_yaml_suggest_try(&s, ctx->group_name[k]);
  }
  if (s.best)
    return adem_yaml_fail(ctx, node, path, "unknown group `%s`; did you mean `%s`? Defined: %s", name, s.best,
                          known);
  return adem_yaml_fail(ctx, node, path, "unknown group `%s`; defined: %s", name, known);
}

adem_status adem_case_build_materials(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "materials", &l);
  if (st) return st;
  ctx->mat_name = calloc(l.n, sizeof *ctx->mat_name);
  ctx->mat_node = calloc(l.n, sizeof *ctx->mat_node);
  ctx->mat_density = calloc(l.n, sizeof *ctx->mat_density);
  ctx->mat_rigid = calloc(l.n, sizeof *ctx->mat_rigid);
  if (!ctx->mat_name || !ctx->mat_node || !ctx->mat_density || !ctx->mat_rigid) return adem_yaml_nomem(ctx);
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) return st;
    adem_material_def d = adem_default_material_def();
    yaml_node_t *name_node, *density, *young, *poisson;
    bool rigid;
    if ((st = adem_yaml_get_string(ctx, &m, "name", d.name, sizeof d.name, &name_node))) return st;
    for (int k = 0; k < ctx->nmat; ++k)
      if (!strcmp(ctx->mat_name[k], d.name)) {
        char first[LOC_MAX], path[KEY_PATH_MAX];
        adem_yaml_where_short(ctx, ctx->mat_node[k], first, sizeof first);
        adem_yaml_join(path, sizeof path, m.path, "name");
        return adem_yaml_fail(ctx, name_node, path, "duplicate material name `%s` (first defined at %s)",
                              d.name, first);
      }
    if ((st = adem_yaml_get_bool(ctx, &m, "rigid", &rigid))) return st;
    d.rigid = rigid;
    if ((st = adem_yaml_get_number(ctx, &m, "density", &d.density, &density))) return st;
    if ((st = adem_yaml_get_number(ctx, &m, "youngs_modulus", &d.young, &young))) return st;
    if ((st = adem_yaml_get_number(ctx, &m, "poisson_ratio", &d.poisson, &poisson))) return st;
    char path[KEY_PATH_MAX];
    if (!rigid && !young) {
      adem_yaml_join(path, sizeof path, m.path, "youngs_modulus");
      return adem_yaml_missing(ctx, &m, adem_schema_find("materials[]", "youngs_modulus", NULL), path);
    }
    if (!rigid && !poisson) {
      adem_yaml_join(path, sizeof path, m.path, "poisson_ratio");
      return adem_yaml_missing(ctx, &m, adem_schema_find("materials[]", "poisson_ratio", NULL), path);
    }
    if ((st = adem_yaml_get_number(ctx, &m, "restitution", &d.restitution, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, &m, "friction", &d.friction, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, &m, "stiffness_factor", &d.stiffness_factor, NULL))) return st;
    for (int k = 0; k < ADEM_PARAM_COUNT; ++k) /* the contact laws' parameters (adem/laws.h) */
      if ((st = adem_yaml_get_number(ctx, &m, adem_law_param_get((adem_law_param_id)k)->key,
                                     &d.param[k], NULL)))
        return st;
    adem_error werr = {ADEM_OK, ""};
    int index = -1;
    if (adem_world_add_material(ctx->w, &d, &index, &werr)) {
      if (werr.status == ADEM_ERR_NOMEM) return adem_yaml_nomem(ctx);
      return adem_yaml_fail(ctx, m.node, m.path, "%s", werr.message);
    }
    if (index != ctx->nmat)
      return adem_error_set(ctx->err, ADEM_ERR_INPUT, "internal error: material index %d", index);
    snprintf(ctx->mat_name[index], ADEM_NAME_MAX, "%s", d.name);
    ctx->mat_node[index] = m.node;
    ctx->mat_density[index] = density != NULL;
    ctx->mat_rigid[index] = rigid;
    ctx->nmat++;
  }
  return ADEM_OK;
}

/* What the pair's laws need of its values (their check hooks, law_hooks.h: `jkr` a surface
 * energy on both materials unless the interaction gives one), at load time: the message points
 * at the key of the law that complains and names where the material it blames is defined. */
static adem_status check_laws(case_ctx *ctx, const map_cursor *m, const adem_interaction_def *d,
                              char names[2][ADEM_NAME_MAX]) {
  const int mats[2] = {d->material_a, d->material_b};
  char at[2][LOC_MAX];
  for (int s = 0; s < 2; ++s) adem_yaml_where_short(ctx, ctx->mat_node[mats[s]], at[s], sizeof at[s]);
  adem_law_check c = {ctx->w->mat.m[mats[0]].def.param, ctx->w->mat.m[mats[1]].def.param, d->param, {names[0], names[1]}, {at[0], at[1]}, NULL};
  adem_law_set laws = {(int)d->normal, (int)d->damping, (int)d->tangential, (int)d->rolling};
  char why[1024], path[KEY_PATH_MAX];
  adem_law_slot slot;
  int side;
  if (!adem_laws_check(laws, &c, &slot, &side, why, sizeof why)) return ADEM_OK;
  const char *key = adem_law_slot_name(slot); /* the slots are the interaction's keys */
  adem_yaml_join(path, sizeof path, m->path, key);
  yaml_node_t *node = adem_yaml_map_get(ctx, m->node, key);
  return adem_yaml_fail(ctx, node ? node : m->node, path, "%s", why);
}

/* An interaction's optional `name` (so that `--set interactions.NAME.friction=0.3` and a stage's
 * `set` find it however the list is ordered): unique among the interactions. */
static adem_status interaction_name(case_ctx *ctx, const list_cursor *l, size_t i,
                                    const map_cursor *m) {
  char name[ADEM_NAME_MAX], other[ADEM_NAME_MAX], path[KEY_PATH_MAX];
  yaml_node_t *node, *other_node;
  adem_status st = adem_yaml_get_string(ctx, m, "name", name, sizeof name, &node);
  if (st || !node) return st;
  for (size_t k = 0; k < i; ++k) {
    map_cursor e;
    if ((st = adem_yaml_list_item(ctx, l, k, &e))) return st;
    if ((st = adem_yaml_get_string(ctx, &e, "name", other, sizeof other, &other_node))) return st;
    if (other_node && !strcmp(other, name)) {
      char first[LOC_MAX];
      adem_yaml_where_short(ctx, other_node, first, sizeof first);
      adem_yaml_join(path, sizeof path, m->path, "name");
      return adem_yaml_fail(ctx, node, path, "duplicate interaction name `%s` (first at %s)", name,
                            first);
    }
  }
  return ADEM_OK;
}

/* Whether law row `params` (space separated keys) reads key. */
static bool params_name(const char *params, const char *key) {
  size_t klen = strlen(key);
  for (const char *f = strstr(params, key); f; f = strstr(f + 1, key))
    if ((f == params || f[-1] == ' ') && (f[klen] == '\0' || f[klen] == ' ')) return true;
  return false;
}

/* Whether every pair of material a (with any of the nmat materials, given the interaction
 * entries defs; a pair without one takes the default laws) leaves law parameter k unread with
 * the default law in each slot where some law would read it: a value set for a law nobody
 * chose. A pair that chose another law of that slot (BROF without model C's rolling_damping)
 * is a choice, not an oversight, and silences it. */
static bool law_param_forgotten(const adem_interaction_def *defs, int ndefs, int nmat, int a, int k) {
  const char *key = adem_law_param_get((adem_law_param_id)k)->key;
  for (int b = 0; b < nmat; ++b) {
    adem_interaction_def d = adem_default_interaction_def();
    for (int j = 0; j < ndefs; ++j)
      if ((defs[j].material_a == a && defs[j].material_b == b) ||
          (defs[j].material_a == b && defs[j].material_b == a))
        d = defs[j];
    const int law[4] = {(int)d.normal, (int)d.damping, (int)d.tangential, (int)d.rolling};
    for (int sl = 0; sl < 4; ++sl) {
      bool slot_reads = false;
      for (size_t r = 0; r < adem_law_count((adem_law_slot)sl) && !slot_reads; ++r)
        slot_reads = params_name(adem_law_get((adem_law_slot)sl, (int)r)->params, key);
      if (slot_reads && law[sl] != 0) return false; /* chosen: read, or deliberately not */
    }
  }
  return true;
}

/* A material's law parameter that no pair of it can read, in the case or in any stage, because
 * every pair keeps the default law of that slot: say so, as users of other codes expect a
 * rolling friction to act once it is set (the default rolling law is `none`). where: the
 * parameter's location or the case file; stages: their configurations (NULL: none). */
void adem_case_warn_unused_law_params(case_ctx *ctx, const char *where, const adem_materials *mt,
                                      const adem_stages *stages) {
  for (int a = 0; a < mt->n; ++a)
    for (int k = 0; k < ADEM_PARAM_COUNT; ++k) {
      const adem_law_param *prm = adem_law_param_get((adem_law_param_id)k);
      double v = mt->m[a].def.param[k];
      if (v == prm->def || !law_param_forgotten(mt->defs, mt->ndefs, mt->n, a, k)) continue;
      bool later = false;
      for (int j = 0; stages && j < stages->n && !later; ++j) {
        const adem_stage_config *g = &stages->s[j].config;
        later = !law_param_forgotten(g->interactions, g->ninteractions, g->nmaterials, a, k);
      }
      if (later) continue;
      char loc[LOC_MAX];
      snprintf(loc, sizeof loc, "%s", where);
      yaml_node_t *node = ctx ? adem_yaml_map_get(ctx, ctx->mat_node[a], prm->key) : NULL;
      if (node) adem_yaml_where(ctx, node, loc, sizeof loc);
      adem_log(ADEM_LOG_WARN, "%s: materials.%s.%s = %g has no effect: every pair of `%s` has the "
                              "default law that does not read it (rolling: none, normal: hertz)%s; choose a law "
                              "that does in an interaction entry (`adem reference` lists the laws and their "
                              "parameters)",
               loc, mt->m[a].def.name, prm->key, v, mt->m[a].def.name,
               stages ? ", in every stage" : "");
    }
}

/* The rolling law of materials a and b under the interaction entries defs. */
static adem_rolling_model pair_rolling(const adem_interaction_def *defs, int ndefs, int a, int b) {
  for (int j = 0; j < ndefs; ++j)
    if ((defs[j].material_a == a && defs[j].material_b == b) ||
        (defs[j].material_a == b && defs[j].material_b == a))
      return defs[j].rolling;
  return adem_default_interaction_def().rolling;
}

/* Whether a configuration lets BROF meet a turning wall: a wall whose motion turns, of a
 * material that has BROF (a rolling law that resists absolute spin, its row's .absolute_spin)
 * with some material of the particles (any material: a pour may bring it). */
static bool brof_meets_turning_wall(const adem_interaction_def *defs, int ndefs, int nmat,
                                    const adem_walls *wl, const adem_plane_setting *planes,
                                    const adem_mesh_setting *meshes) {
  for (int k = 0; k < wl->nplanes + wl->mesh.ngroups; ++k) {
    bool plane = k < wl->nplanes;
    int g = k - wl->nplanes;
    double omega = plane ? (planes ? planes[k].motion.omega : wl->planes[k].motion.omega)
                         : (meshes ? meshes[g].motion.omega : wl->mesh_motion[g].omega);
    int mat = plane ? (planes ? planes[k].def.material : wl->planes[k].def.material)
                    : (meshes ? meshes[g].material : wl->mesh.groups[g].material);
    if (omega == 0.0) continue;
    for (int b = 0; b < nmat; ++b)
      if (adem_laws_absolute_spin((int)pair_rolling(defs, ndefs, mat, b))) return true;
  }
  return false;
}

/* BROF (I9-I10) resists each particle's spin relative to its contacts' capacity-weighted target:
 * the particle contacts' share targets zero, so a bed turning with a drum is braked and part of
 * the drive torque goes into BROF, not into the wall. Say so where it happens. */
void adem_case_warn_brof_turning(const char *where, const adem_world *w, const adem_stages *stages) {
  const adem_materials *mt = &w->mat;
  bool meets = brof_meets_turning_wall(mt->defs, mt->ndefs, mt->n, &w->walls, NULL, NULL);
  for (int j = 0; stages && j < stages->n && !meets; ++j) {
    const adem_stage_config *g = &stages->s[j].config;
    meets = brof_meets_turning_wall(g->interactions, g->ninteractions, g->nmaterials, &w->walls,
                                    g->planes, g->meshes);
  }
  if (meets)
    adem_log(ADEM_LOG_WARN, "%s: BROF meets a turning wall: between particles it resists their "
                            "absolute spin (I9-I10 act per particle), so a bed turning with the wall is braked "
                            "and part of the drive torque goes into BROF, not into the wall's load; the CSV's "
                            "brof_impulse_*_Nms columns give the angular impulse it adds (docs/models.md)",
             where);
}

adem_status adem_case_build_interactions(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "interactions", &l);
  if (st || l.n == 0) return st;
  int *pairs = malloc(2 * l.n * sizeof *pairs);
  yaml_node_t **nodes = malloc(l.n * sizeof *nodes);
  if (!pairs || !nodes) {
    free(pairs);
    free(nodes);
    return adem_yaml_nomem(ctx);
  }
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    char names[2][ADEM_NAME_MAX], paths[2][KEY_PATH_MAX];
    yaml_node_t *name_nodes[2];
    adem_interaction_def d = adem_default_interaction_def();
    int law[4];
    yaml_node_t *e_node, *mu_node;
    double e, mu;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    if ((st = interaction_name(ctx, &l, i, &m))) break;
    if ((st = adem_yaml_get_pair(ctx, &m, "materials", names, name_nodes, paths))) break;
    if ((st = adem_case_find_material(ctx, names[0], name_nodes[0], paths[0], &d.material_a))) break;
    if ((st = adem_case_find_material(ctx, names[1], name_nodes[1], paths[1], &d.material_b))) break;
    nodes[i] = m.node;
    pairs[2 * i] = d.material_a < d.material_b ? d.material_a : d.material_b;
    pairs[2 * i + 1] = d.material_a < d.material_b ? d.material_b : d.material_a;
    for (size_t k = 0; k < i && !st; ++k)
      if (pairs[2 * k] == pairs[2 * i] && pairs[2 * k + 1] == pairs[2 * i + 1]) {
        char first[LOC_MAX];
        adem_yaml_where_short(ctx, nodes[k], first, sizeof first);
        st = adem_yaml_fail(ctx, m.node, m.path, "a second interaction of `%s` and `%s` (first at %s)",
                            names[0], names[1], first);
      }
    if (st) break;
    if ((st = adem_yaml_get_number(ctx, &m, "restitution", &e, &e_node))) break;
    if ((st = adem_yaml_get_number(ctx, &m, "friction", &mu, &mu_node))) break;
    /* The schema's choices are the laws' rows in the order of their ids (adem/laws.h). */
    static const char *const slot_key[4] = {"normal", "damping", "tangential", "rolling"};
    for (int s = 0; s < 4 && !st; ++s) st = adem_yaml_get_enum(ctx, &m, slot_key[s], &law[s]);
    if (st) break;
    for (int k = 0; k < ADEM_PARAM_COUNT && !st; ++k) {
      yaml_node_t *node = NULL;
      double x;
      st = adem_yaml_get_number(ctx, &m, adem_law_param_get((adem_law_param_id)k)->key, &x, &node);
      if (node) d.param[k] = x;
    }
    if (st) break;
    if (e_node) d.restitution = e;
    if (mu_node) d.friction = mu;
    d.normal = (adem_normal_model)law[0];
    d.damping = (adem_damping_model)law[1];
    d.tangential = (adem_tangential_model)law[2];
    d.rolling = (adem_rolling_model)law[3];
    /* A law may need a particular normal law (its row's `requires`): DTK's stiffness and limit
     * come from the JKR pull-off force and contact radius (H18-H22). */
    const adem_law *normal = adem_law_get(ADEM_SLOT_NORMAL, law[0]);
    for (int s = 1; s < 4 && !st; ++s) {
      const adem_law *lw = adem_law_get((adem_law_slot)s, law[s]);
      if (!lw->requires[0] || !strcmp(lw->requires, normal->name)) continue;
      char rpath[KEY_PATH_MAX], others[256] = "";
      adem_yaml_join(rpath, sizeof rpath, m.path, slot_key[s]);
      for (size_t j = 0; j < adem_law_count((adem_law_slot)s); ++j) {
        const adem_law *o = adem_law_get((adem_law_slot)s, (int)j);
        if (!o->requires[0] || !strcmp(o->requires, normal->name)) adem_yaml_list_append(others, sizeof others, o->name);
      }
      st = adem_yaml_fail(ctx, adem_yaml_map_get(ctx, m.node, slot_key[s]), rpath,
                          "`%s` %s needs the `%s` normal law (%s), which `%s` is not; add `normal: "
                          "%s` to this interaction or choose another %s law (%s)",
                          lw->name, slot_key[s], lw->requires, lw->equations, normal->name,
                          lw->requires, slot_key[s], others);
    }
    if (st) break;
    if ((st = check_laws(ctx, &m, &d, names))) break;
    adem_error werr = {ADEM_OK, ""};
    if (adem_world_set_interaction(ctx->w, &d, &werr))
      st = werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, m.node, m.path, "%s", werr.message);
  }
  free(pairs);
  free(nodes);
  return st;
}

adem_status adem_case_build_groups(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "groups", &l);
  if (st || l.n == 0) return st;
  ctx->group_name = calloc(l.n, sizeof *ctx->group_name);
  ctx->group_node = calloc(l.n, sizeof *ctx->group_node);
  if (!ctx->group_name || !ctx->group_node) return adem_yaml_nomem(ctx);
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    char name[ADEM_NAME_MAX];
    yaml_node_t *name_node;
    adem_vec3 force;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) return st;
    if ((st = adem_yaml_get_string(ctx, &m, "name", name, sizeof name, &name_node))) return st;
    for (int k = 0; k < ctx->ngroup; ++k)
      if (!strcmp(ctx->group_name[k], name)) {
        char first[LOC_MAX], path[KEY_PATH_MAX];
        adem_yaml_where_short(ctx, ctx->group_node[k], first, sizeof first);
        adem_yaml_join(path, sizeof path, m.path, "name");
        return adem_yaml_fail(ctx, name_node, path, "duplicate group name `%s` (first defined at %s)", name,
                              first);
      }
    if ((st = adem_yaml_get_vec3(ctx, &m, "external_force", &force, NULL))) return st;
    /* Naming `default` sets the force of the group particles without `group` belong to. */
    if (adem_world_add_group(ctx->w, name, force, NULL, NULL)) return adem_yaml_nomem(ctx);
    snprintf(ctx->group_name[ctx->ngroup], ADEM_NAME_MAX, "%s", name);
    ctx->group_node[ctx->ngroup++] = name_node;
  }
  return ADEM_OK;
}
