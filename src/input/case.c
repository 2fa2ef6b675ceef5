/* Case files: YAML read with libyaml, --set overrides grafted onto the document, every key checked
 * against the schema table (schema.c), then the world built from it. */
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

#include "adem/files.h"
#include "stl.h"
#include "log.h"
#include "rng.h"
#include "schedule.h"
#include "insert.h"
#include "outlets.h"
#include "case_yaml.h"
#include "case_walls.h"
#include "schema.h"
#include "stages.h"
#include "adem/vec3.h"
#include "world_internal.h"

/* Sets larger than this are surely a typo and would only exhaust memory. */
#define MAX_SET_SPHERES 100000000.0


static void box_include(case_ctx *ctx, adem_vec3 lo, adem_vec3 hi) {
  if (!ctx->has_box) {
    ctx->box_lo = lo;
    ctx->box_hi = hi;
    ctx->has_box = true;
    return;
  }
  ctx->box_lo = v3(fmin(ctx->box_lo.x, lo.x), fmin(ctx->box_lo.y, lo.y), fmin(ctx->box_lo.z, lo.z));
  ctx->box_hi = v3(fmax(ctx->box_hi.x, hi.x), fmax(ctx->box_hi.y, hi.y), fmax(ctx->box_hi.z, hi.z));
}

static adem_status push_sphere(case_ctx *ctx, adem_vec3 x, double r, adem_vec3 v, adem_vec3 w) {
  if (ctx->n == ctx->cap) {
    size_t cap = ctx->cap ? 2 * ctx->cap : 256;
    adem_vec3 *pos = realloc(ctx->pos, cap * sizeof *pos);
    if (pos) ctx->pos = pos;
    adem_vec3 *vel = realloc(ctx->vel, cap * sizeof *vel);
    if (vel) ctx->vel = vel;
    adem_vec3 *omega = realloc(ctx->omega, cap * sizeof *omega);
    if (omega) ctx->omega = omega;
    double *rad = realloc(ctx->rad, cap * sizeof *rad);
    if (rad) ctx->rad = rad;
    if (!pos || !vel || !omega || !rad) return adem_yaml_nomem(ctx);
    ctx->cap = cap;
  }
  ctx->pos[ctx->n] = x;
  ctx->rad[ctx->n] = r;
  ctx->vel[ctx->n] = v;
  ctx->omega[ctx->n] = w;
  ctx->n++;
  return ADEM_OK;
}

/* Adds spheres [first, ctx->n) to the world. */
static adem_status flush_spheres(case_ctx *ctx, size_t first, int material, int group,
                                 const yaml_node_t *at, const char *path) {
  for (size_t i = first; i < ctx->n; ++i) {
    adem_particle_def d = adem_default_particle_def();
    d.position = ctx->pos[i];
    d.velocity = ctx->vel[i];
    d.angular_velocity = ctx->omega[i];
    d.radius = ctx->rad[i];
    d.material = material;
    d.group = group;
    adem_error werr = {ADEM_OK, ""};
    if (adem_world_add_particle(ctx->w, &d, NULL, &werr)) {
      if (werr.status == ADEM_ERR_NOMEM) return adem_yaml_nomem(ctx);
      return adem_yaml_fail(ctx, at, path, "%s", werr.message);
    }
    double r = ctx->rad[i];
    box_include(ctx, v3_sub(d.position, v3(r, r, r)), v3_add(d.position, v3(r, r, r)));
    ctx->rmax = fmax(ctx->rmax, r);
    ctx->vmax = fmax(ctx->vmax, v3_norm(d.velocity));
  }
  return ADEM_OK;
}

/* ---- sections ---- */

static adem_status check_box(case_ctx *ctx, adem_vec3 lo, adem_vec3 hi, const yaml_node_t *hi_node,
                             const map_cursor *m) {
  const double a[3] = {lo.x, lo.y, lo.z}, b[3] = {hi.x, hi.y, hi.z};
  for (int k = 0; k < 3; ++k)
    if (!(a[k] < b[k])) {
      char path[KEY_PATH_MAX];
      adem_yaml_join(path, sizeof path, m->path, "max");
      return adem_yaml_fail(ctx, hi_node ? hi_node : m->at, path,
                  "must be greater than `min` in every component (%c: max %g <= min %g)", "xyz"[k],
                  b[k], a[k]);
    }
  return ADEM_OK;
}

/* Index of the material called name (given at node), or an error naming the known ones. */
static adem_status find_material(case_ctx *ctx, const char *name, const yaml_node_t *node,
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

static adem_status find_group(case_ctx *ctx, const char *name, const yaml_node_t *node,
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

static adem_status build_materials(case_ctx *ctx, const map_cursor *root) {
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

/* JKR adhesion needs a surface energy on both sides: the pair's is the geometric mean of the two
 * (materials.c), so a side without one (typically a wall material) silently makes it Hertz. */
static adem_status check_jkr_pair(case_ctx *ctx, const map_cursor *m, const adem_interaction_def *d,
                                  char names[2][ADEM_NAME_MAX]) {
  const int mats[2] = {d->material_a, d->material_b};
  for (int s = 0; s < 2; ++s) {
    if (ctx->w->mat.m[mats[s]].def.param[ADEM_PARAM_SURFACE_ENERGY] > 0.0) continue;
    char path[KEY_PATH_MAX], at[LOC_MAX];
    adem_yaml_join(path, sizeof path, m->path, "normal");
    adem_yaml_where_short(ctx, ctx->mat_node[mats[s]], at, sizeof at);
    yaml_node_t *node = adem_yaml_map_get(ctx, m->node, "normal");
    return adem_yaml_fail(ctx, node ? node : m->node, path,
                "`jkr` between `%s` and `%s` needs a surface energy on both materials, but `%s` "
                "(at %s) has surface_energy 0; give it a `surface_energy` > 0 (for a wall, the "
                "wall material's) or use `normal: hertz`",
                names[0], names[1], ctx->mat_name[mats[s]], at);
  }
  return ADEM_OK;
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
static void warn_unused_law_params(case_ctx *ctx, const char *where, const adem_materials *mt,
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
               "parameters)", loc, mt->m[a].def.name, prm->key, v, mt->m[a].def.name,
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
 * material that has BROF with some material of the particles (any material: a pour may bring it). */
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
      if (pair_rolling(defs, ndefs, mat, b) == ADEM_ROLLING_BROF) return true;
  }
  return false;
}

/* BROF (I9-I10) resists each particle's spin relative to its contacts' capacity-weighted target:
 * the particle contacts' share targets zero, so a bed turning with a drum is braked and part of
 * the drive torque goes into BROF, not into the wall. Say so where it happens. */
static void warn_brof_turning(const char *where, const adem_world *w, const adem_stages *stages) {
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
             "brof_impulse_*_Nms columns give the angular impulse it adds (docs/models.md)", where);
}

static adem_status build_interactions(case_ctx *ctx, const map_cursor *root) {
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
    if ((st = find_material(ctx, names[0], name_nodes[0], paths[0], &d.material_a))) break;
    if ((st = find_material(ctx, names[1], name_nodes[1], paths[1], &d.material_b))) break;
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
    /* (an interaction's own surface energy is the pair's, whatever the materials') */
    if (d.normal == ADEM_NORMAL_JKR && isnan(d.param[ADEM_PARAM_SURFACE_ENERGY]) &&
        (st = check_jkr_pair(ctx, &m, &d, names)))
      break;
    adem_error werr = {ADEM_OK, ""};
    if (adem_world_set_interaction(ctx->w, &d, &werr))
      st = werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, m.node, m.path, "%s", werr.message);
  }
  free(pairs);
  free(nodes);
  return st;
}

static adem_status build_groups(case_ctx *ctx, const map_cursor *root) {
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

static adem_status get_numbers(case_ctx *ctx, const map_cursor *m, const char *key, double **out,
                               size_t *n, yaml_node_t **node);

/* `motion.servo` (absent: def->on = 0). `groups` is read with the mesh (servo_groups). */
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
  if ((st = get_numbers(ctx, &sv, "travel", &travel, &nt, &travel_node))) return st;
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
static adem_status servo_groups(case_ctx *ctx, const map_cursor *m, int first, bool *unmeasured) {
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
static adem_status read_motion(case_ctx *ctx, const map_cursor *wall, adem_motion_def *def,
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
static char *mesh_path(const case_ctx *ctx, const char *file) {
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
  st = read_motion(ctx, m, &md, &times, &vels, &moves, &motion_node);
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
  resolved = mesh_path(ctx, file);
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
  st = md.servo.on ? servo_groups(ctx, m, first, unmeasured) : ADEM_OK;
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
        box_include(ctx, x, x);
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
  adem_status st = read_motion(ctx, m, &md, &times, &vels, &moves, &at);
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

static adem_status build_walls(case_ctx *ctx, const map_cursor *root) {
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
    if ((st = find_material(ctx, material, mat_node, path, &mat))) break;
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
      box_include(ctx, d.point, d.point);
      ctx->vmax = fmax(ctx->vmax, v3_norm(d.velocity));
      if ((st = plane_motion(ctx, &m, ctx->w->walls.nplanes - 1, velocity_node))) break;
    } else if (!strcmp(m.variant, "mesh")) {
      if ((st = build_mesh_wall(ctx, &m, mat, name_node ? names[i] : NULL))) break;
    } else if (!strcmp(m.variant, "cylinder") || !strcmp(m.variant, "plate")) {
      double reach = 0.0; /* case_walls.c; every part moves with the wall's `motion` */
      bool cyl = !strcmp(m.variant, "cylinder");
      if ((st = adem_case_curved_wall(ctx, &m, names[i], mat, cyl, &reach))) break;
      adem_vec3 pt = ctx->w->walls.planes[planes_before].def.point, e = v3(reach, reach, reach);
      box_include(ctx, v3_sub(pt, e), v3_add(pt, e));
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
      if ((st = check_box(ctx, lo, hi, hi_node, &m))) break;
      if (adem_world_add_box(ctx->w, names[i], lo, hi, mat, NULL, &werr)) {
        st = werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, m.node, m.path, "%s", werr.message);
        break;
      }
      box_include(ctx, lo, hi);
    }
    st = check_wall_names(ctx, &m);
    if (!st) st = wall_active(ctx, &m, planes_before, meshes_before);
  }
  free(names);
  free(nodes);
  return st;
}

/* limits.max_memory: refuses a case whose particles (those made so far, `extra` about to be
 * made and the pours' totals) would need more memory than the run may use, before they are
 * allocated. The message points at node, the set or pour asking for them. */
static adem_status check_memory(case_ctx *ctx, double extra, const yaml_node_t *node,
                                const char *path) {
  adem_case *c = ctx->c;
  double n = (double)ctx->n + extra + ctx->poured;
  c->memory = adem_world_memory_estimate(ctx->w, n);
  c->memory_auto = ctx->memory_auto;
  c->memory_limit = ctx->memory_auto ? adem_memory_available() : ctx->max_memory;
  const adem_memory_estimate *e = &c->memory;
  if (!(c->memory_limit > 0.0) || e->total <= c->memory_limit) return ADEM_OK;
  const double mib = 1024.0 * 1024.0;
  return adem_yaml_fail(ctx, node, path,
              "the run would need about %.4g MiB for %.4g particles (%.0f B each with their "
              "%.3g candidate pairs, the neighbour grid and build included), more than the "
              "%.4g MiB %s; make fewer particles, or set limits.max_memory (bytes, or auto)",
              e->total / mib, n, e->total / fmax(n, 1.0), e->pairs / fmax(n, 1.0),
              c->memory_limit / mib,
              ctx->memory_auto ? "the machine has available (MemAvailable)"
                               : "limits.max_memory allows");
}

/* Spheres a solid fraction of a volume takes, with the distribution's mean r^3 (normal: mean^3
 * + 3 mean std^2; the others near it). */
static double spheres_for_volume(const adem_size_dist *d, double volume) {
  double mean, std;
  adem_insert_dist_moments(d, &mean, &std);
  double r3 = mean * mean * mean + 3.0 * mean * std * std;
  return r3 > 0.0 ? volume / ((4.0 / 3.0) * ADEM_PI * r3) : 0.0;
}

/* An explicit list of spheres; none of them may overlap another of the list unless
 * limits.initial_overlap accepts some overlap (then the world checks the depth at prepare). */
static adem_status build_list(case_ctx *ctx, const map_cursor *set, int mat, int group) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, set, "spheres", &l);
  if (st) return st;
  if ((st = check_memory(ctx, (double)l.n, set->node, set->path))) return st;
  size_t first = ctx->n;
  double rmax = 0;
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    adem_vec3 x, v, w;
    double r = 0.0;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &m, "position", &x, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, &m, "radius", &r, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &m, "velocity", &v, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &m, "angular_velocity", &w, NULL))) return st;
    if ((st = push_sphere(ctx, x, r, v, w))) return st;
    rmax = fmax(rmax, r);
  }
  if (l.n > 1 && ctx->initial_overlap <= 0.0) {
    adem_vec3 lo = ctx->pos[first], hi = lo;
    for (size_t i = first; i < ctx->n; ++i) {
      adem_vec3 p = ctx->pos[i];
      lo = v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
      hi = v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    adem_sphere_grid g;
    if (adem_insert_grid_init(&g, lo, hi, 2.0 * rmax, rmax, l.n)) return adem_yaml_nomem(ctx);
    for (size_t i = first; i < ctx->n && !st; ++i) {
      int64_t j = adem_insert_grid_overlap(&g, ctx->pos, ctx->rad, ctx->pos[i], ctx->rad[i]);
      if (j >= 0) {
        size_t a = (size_t)j - first, b = i - first;
        yaml_node_t *na = adem_yaml_node_at(ctx, l.node->data.sequence.items.start[a]);
        yaml_node_t *nb = adem_yaml_node_at(ctx, l.node->data.sequence.items.start[b]);
        char pa[KEY_PATH_MAX], pb[KEY_PATH_MAX], first_at[LOC_MAX];
        snprintf(pa, sizeof pa, "%.240s[%zu]", l.path, a);
        snprintf(pb, sizeof pb, "%.240s[%zu]", l.path, b);
        adem_yaml_where_short(ctx, na, first_at, sizeof first_at);
        st = adem_yaml_fail(ctx, nb, pb,
                  "overlaps %s (at %s): centre distance %g m < sum of radii %g m (a settled "
                  "bed may overlap: set limits.initial_overlap)", pa, first_at,
                  v3_norm(v3_sub(ctx->pos[i], ctx->pos[j])), ctx->rad[i] + ctx->rad[j]);
      } else if (adem_insert_grid_add(&g, ctx->pos, ctx->rad, i)) {
        st = adem_yaml_nomem(ctx);
      }
    }
    adem_insert_grid_free(&g);
    if (st) return st;
  }
  return flush_spheres(ctx, first, mat, group, set->node, set->path);
}

/* Number of lattice sites along one axis: centres at lo + r + k s up to hi - r. */
static double lattice_sites(double lo, double hi, double r, double s) {
  double room = hi - lo - 2.0 * r;
  if (room < -1e-12 * fabs(hi - lo)) return 0;
  return floor(fmax(room, 0.0) / s * (1.0 + 1e-12)) + 1.0; /* round-off must not lose a layer */
}

static adem_status build_lattice(case_ctx *ctx, const map_cursor *m, int mat, int group) {
  double r = 0.0, s = 0.0;
  adem_vec3 lo, hi, v, w;
  uint64_t count;
  yaml_node_t *s_node, *hi_node, *count_node;
  adem_status st;
  char path[KEY_PATH_MAX];
  if ((st = adem_yaml_get_number(ctx, m, "radius", &r, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, m, "spacing", &s, &s_node))) return st;
  if (s < 2.0 * r) {
    adem_yaml_join(path, sizeof path, m->path, "spacing");
    return adem_yaml_fail(ctx, s_node, path,
                "spacing %g m is less than the diameter 2 radius = %g m; neighbours would overlap", s,
                2.0 * r);
  }
  if ((st = adem_yaml_get_vec3(ctx, m, "min", &lo, NULL))) return st;
  if ((st = adem_yaml_get_vec3(ctx, m, "max", &hi, &hi_node))) return st;
  if ((st = check_box(ctx, lo, hi, hi_node, m))) return st;
  if ((st = adem_yaml_get_uint(ctx, m, "count", &count, &count_node))) return st;
  if ((st = adem_yaml_get_vec3(ctx, m, "velocity", &v, NULL))) return st;
  if ((st = adem_yaml_get_vec3(ctx, m, "angular_velocity", &w, NULL))) return st;
  double nx = lattice_sites(lo.x, hi.x, r, s), ny = lattice_sites(lo.y, hi.y, r, s),
         nz = lattice_sites(lo.z, hi.z, r, s);
  if (nx < 1 || ny < 1 || nz < 1) {
    adem_yaml_join(path, sizeof path, m->path, "max");
    return adem_yaml_fail(ctx, hi_node, path, "the box is narrower than one sphere (diameter %g m) along %c",
                2.0 * r, nx < 1 ? 'x' : ny < 1 ? 'y' : 'z');
  }
  double capacity = nx * ny * nz;
  double n = count > 0 ? fmin((double)count, capacity) : capacity;
  if (n > MAX_SET_SPHERES)
    return adem_yaml_fail(ctx, m->node, m->path, "would create %.3g spheres (at most %.0g per set)", n,
                MAX_SET_SPHERES);
  if ((double)count > capacity)
    adem_log(ADEM_LOG_WARN, "%s: the lattice box holds %.0f spheres; count asks for %llu", m->path,
             capacity, (unsigned long long)count);
  if ((st = check_memory(ctx, n, m->node, m->path))) return st;
  size_t first = ctx->n, total = (size_t)n, nxy = (size_t)nx * (size_t)ny;
  for (size_t k = 0; k < total; ++k) {
    size_t ix = k % (size_t)nx, iy = (k / (size_t)nx) % (size_t)ny, iz = k / nxy;
    adem_vec3 x = v3(lo.x + r + (double)ix * s, lo.y + r + (double)iy * s, lo.z + r + (double)iz * s);
    if ((st = push_sphere(ctx, x, r, v, w))) return st;
  }
  return flush_spheres(ctx, first, mat, group, m->node, m->path);
}

/* ---- insertion: size distributions, regions, random fills ---- */

/* A list [a, b, ...] of numbers under key (absent: *n = 0, *node NULL), each in the entry's
 * range; a fresh array in *out. */
static adem_status get_numbers(case_ctx *ctx, const map_cursor *m, const char *key, double **out,
                               size_t *n, yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  *out = NULL;
  *n = 0;
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st || !v) return st;
  if (v->type != YAML_SEQUENCE_NODE) return adem_yaml_wrong_type(ctx, e, v, path);
  size_t count = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
  if (count == 0) return adem_yaml_fail(ctx, v, path, "needs at least one number");
  *out = malloc(count * sizeof **out);
  if (!*out) return adem_yaml_nomem(ctx);
  for (size_t k = 0; k < count; ++k) {
    yaml_node_t *item = adem_yaml_node_at(ctx, v->data.sequence.items.start[k]);
    char p[KEY_PATH_MAX + 24];
    snprintf(p, sizeof p, "%s[%zu]", path, k);
    if ((st = adem_yaml_read_number(ctx, e, item, p, &(*out)[k]))) {
      free(*out);
      *out = NULL;
      return st;
    }
  }
  *n = count;
  return ADEM_OK;
}

/* `radius` of a random set or a pour: the distribution, checked against the largest radius the
 * region holds (fit, called `fit_what` of the `region_word` in messages). */
static adem_status read_dist(case_ctx *ctx, const map_cursor *m, double fit, const char *fit_what,
                             const char *region_word, adem_size_dist *d, map_cursor *dm) {
  memset(d, 0, sizeof *d);
  adem_status st = adem_yaml_get_map(ctx, m, "radius", dm);
  if (st) return st;
  char path[KEY_PATH_MAX];
  yaml_node_t *node;
  d->limit = fit;
  if (!strcmp(dm->variant, "constant")) {
    d->kind = ADEM_SIZE_CONSTANT;
    if ((st = adem_yaml_get_number(ctx, dm, "value", &d->value, &node))) return st;
    adem_yaml_join(path, sizeof path, dm->path, "value");
    if (d->value > fit)
      return adem_yaml_fail(ctx, node, path, "radius %g m does not fit the %s (%s is %g m)", d->value,
                  region_word, fit_what, fit);
  } else if (!strcmp(dm->variant, "uniform")) {
    d->kind = ADEM_SIZE_UNIFORM;
    if ((st = adem_yaml_get_number(ctx, dm, "min", &d->min, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, dm, "max", &d->max, &node))) return st;
    adem_yaml_join(path, sizeof path, dm->path, "max");
    if (!(d->max > d->min)) return adem_yaml_fail(ctx, node, path, "must be greater than `min` (%g m)", d->min);
    if (d->max > fit)
      return adem_yaml_fail(ctx, node, path, "radius %g m does not fit the %s (%s is %g m)", d->max,
                  region_word, fit_what, fit);
  } else if (!strcmp(dm->variant, "discrete")) {
    d->kind = ADEM_SIZE_DISCRETE;
    double *weights = NULL;
    size_t nw = 0;
    yaml_node_t *wnode;
    if ((st = get_numbers(ctx, dm, "values", &d->values, &d->n, &node))) return st;
    if ((st = get_numbers(ctx, dm, "weights", &weights, &nw, &wnode))) return st;
    d->cumulative = malloc(d->n * sizeof *d->cumulative);
    if (!d->cumulative) {
      free(weights);
      return adem_yaml_nomem(ctx);
    }
    double sum = 0.0;
    for (size_t k = 0; k < d->n; ++k) {
      sum += wnode ? (k < nw ? weights[k] : 0.0) : 1.0;
      d->cumulative[k] = sum;
    }
    free(weights);
    adem_yaml_join(path, sizeof path, dm->path, "weights");
    if (wnode && nw != d->n)
      return adem_yaml_fail(ctx, wnode, path, "has %zu weights for %zu values; give one weight per value", nw,
                  d->n);
    if (!(sum > 0.0)) return adem_yaml_fail(ctx, wnode, path, "the weights are all 0");
    adem_yaml_join(path, sizeof path, dm->path, "values");
    for (size_t k = 0; k < d->n; ++k)
      if (d->values[k] > fit)
        return adem_yaml_fail(ctx, node, path, "radius %g m does not fit the %s (%s is %g m)", d->values[k],
                    region_word, fit_what, fit);
  } else {
    d->kind = !strcmp(dm->variant, "lognormal") ? ADEM_SIZE_LOGNORMAL : ADEM_SIZE_NORMAL;
    if ((st = adem_yaml_get_number(ctx, dm, "mean", &d->mean, NULL))) return st;
    if ((st = adem_yaml_get_number(ctx, dm, "std", &d->std, NULL))) return st;
  }
  return ADEM_OK;
}

/* A mapping with a `shape` (its variant) and that shape's keys: a box, a cylinder or the inside
 * of a closed STL surface. *word names its kind for messages. */
static adem_status read_region_map(case_ctx *ctx, const map_cursor *rm, adem_region *r,
                                   const char **word) {
  adem_error werr = {ADEM_OK, ""};
  char path[KEY_PATH_MAX];
  adem_vec3 lo, hi;
  yaml_node_t *hi_node;
  adem_status st;
  if (!strcmp(rm->variant, "box")) {
    *word = "box";
    if ((st = adem_yaml_get_vec3(ctx, rm, "min", &lo, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, rm, "max", &hi, &hi_node))) return st;
    if ((st = check_box(ctx, lo, hi, hi_node, rm))) return st;
    adem_insert_region_box(r, lo, hi);
  } else if (!strcmp(rm->variant, "cylinder")) {
    *word = "cylinder";
    adem_vec3 a, b;
    double radius = 0.0;
    yaml_node_t *end_node;
    if ((st = adem_yaml_get_vec3(ctx, rm, "start", &a, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, rm, "end", &b, &end_node))) return st;
    if ((st = adem_yaml_get_number(ctx, rm, "radius", &radius, NULL))) return st;
    if (adem_insert_region_cylinder(r, a, b, radius, &werr)) {
      adem_yaml_join(path, sizeof path, rm->path, "end");
      return adem_yaml_fail(ctx, end_node, path, "%s", werr.message);
    }
  } else {
    *word = "mesh region";
    char file[ADEM_PATH_MAX];
    yaml_node_t *file_node;
    adem_mesh_transform tf = adem_default_mesh_transform();
    if ((st = adem_yaml_get_string(ctx, rm, "file", file, sizeof file, &file_node))) return st;
    if ((st = adem_yaml_get_number(ctx, rm, "scale", &tf.scale, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, rm, "translate", &tf.translation, NULL))) return st;
    char *resolved = mesh_path(ctx, file);
    if (!resolved) return adem_yaml_nomem(ctx);
    st = adem_insert_region_mesh(r, resolved, &tf, &werr);
    free(resolved);
    adem_yaml_join(path, sizeof path, rm->path, "file");
    if (st) return werr.status == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, file_node, path, "%s", werr.message);
  }
  return ADEM_OK;
}

/* The region of a random set (`region`, or the box `min`/`max`: box_keys) or of a pour. *word
 * names its kind for messages. */
static adem_status read_region(case_ctx *ctx, const map_cursor *m, bool box_keys, adem_region *r,
                               const char **word) {
  map_cursor rm;
  memset(&rm, 0, sizeof rm);
  adem_status st = ADEM_OK;
  /* absent from a random set: the box keys are used (an absent mapping with a `shape` to
   * choose would be reported missing) */
  if (!box_keys || adem_yaml_map_get(ctx, m->node, "region")) st = adem_yaml_get_map(ctx, m, "region", &rm);
  if (st) return st;
  char path[KEY_PATH_MAX];
  adem_vec3 lo, hi;
  yaml_node_t *lo_node = NULL, *hi_node = NULL;
  if (box_keys) {
    if ((st = adem_yaml_get_vec3(ctx, m, "min", &lo, &lo_node))) return st;
    if ((st = adem_yaml_get_vec3(ctx, m, "max", &hi, &hi_node))) return st;
    if (rm.node && (lo_node || hi_node)) {
      adem_yaml_join(path, sizeof path, m->path, lo_node ? "min" : "max");
      return adem_yaml_fail(ctx, lo_node ? lo_node : hi_node, path,
                  "give either the box `min`/`max` or a `region`, not both");
    }
    if (!rm.node) {
      *word = "box";
      if (!lo_node || !hi_node) {
        const char *key = lo_node ? "max" : "min";
        adem_yaml_join(path, sizeof path, m->path, key);
        return adem_yaml_missing(ctx, m, adem_schema_find(m->schema, key, m->variant), path);
      }
      if ((st = check_box(ctx, lo, hi, hi_node, m))) return st;
      adem_insert_region_box(r, lo, hi);
      return ADEM_OK;
    }
  }
  return read_region_map(ctx, &rm, r, word);
}

/* A random non-overlapping fill of a box, cylinder or closed mesh, up to a count or a solid
 * fraction; keeps clear of the walls built so far and of every earlier sphere. */
static adem_status build_random(case_ctx *ctx, const map_cursor *m, size_t set_index, int mat,
                                int group) {
  adem_region reg;
  adem_size_dist dist;
  memset(&reg, 0, sizeof reg);
  memset(&dist, 0, sizeof dist);
  const char *word = "box", *fit_what = "";
  uint64_t count = 0, max_attempts = 0;
  double fraction = 0.0;
  yaml_node_t *count_node, *fraction_node, *attempts_node;
  adem_vec3 v, w;
  map_cursor dm;
  char path[KEY_PATH_MAX];
  adem_fill_result res;
  memset(&res, 0, sizeof res);
  adem_status st = read_region(ctx, m, true, &reg, &word);
  if (!st) st = adem_yaml_get_uint(ctx, m, "count", &count, &count_node);
  if (!st) st = adem_yaml_get_number(ctx, m, "solid_fraction", &fraction, &fraction_node);
  map_cursor fl; /* fill_level: the solid fraction of a bed to a level (case_walls.c) */
  if (!st) st = adem_yaml_get_map(ctx, m, "fill_level", &fl);
  if (!st && fl.node && (count_node || fraction_node))
    st = adem_yaml_fail(ctx, fl.node, fl.path, "give one of `count`, `solid_fraction`, `fill_level`");
  if (!st && fl.node && !(st = adem_case_fill_level(ctx, &fl, &reg, &fraction)))
    fraction_node = fl.node;
  if (!st && count_node && fraction_node) {
    adem_yaml_join(path, sizeof path, m->path, "solid_fraction");
    st = adem_yaml_fail(ctx, fraction_node, path, "give either `count` or `solid_fraction`, not both");
  }
  if (!st && !count_node && !fraction_node) {
    adem_yaml_join(path, sizeof path, m->path, "count");
    st = adem_yaml_missing(ctx, m, adem_schema_find(m->schema, "count", m->variant), path);
  }
  if (!st && (double)count > MAX_SET_SPHERES)
    st = adem_yaml_fail(ctx, m->node, m->path, "count %llu is more than %.0g spheres per set",
              (unsigned long long)count, MAX_SET_SPHERES);
  if (!st) st = adem_yaml_get_uint(ctx, m, "max_attempts", &max_attempts, &attempts_node);
  if (!st && !attempts_node) max_attempts = 0;
  if (!st) st = adem_yaml_get_vec3(ctx, m, "velocity", &v, NULL);
  if (!st) st = adem_yaml_get_vec3(ctx, m, "angular_velocity", &w, NULL);
  double fit = adem_insert_region_fit(&reg, &fit_what);
  if (!st) st = read_dist(ctx, m, fit, fit_what, word, &dist, &dm);
  if (!st)
    st = check_memory(ctx, count_node ? (double)count : spheres_for_volume(&dist, fraction * reg.volume),
                      m->node, m->path);
  if (!st) {
    /* Each set draws from its own stream, so editing one set leaves the others' spheres alone. */
    adem_rng rng = adem_rng_seed(ctx->c->seed ^ (0x9e3779b97f4a7c15ULL * (uint64_t)(set_index + 1)));
    adem_fill_def def = {&reg, &dist, count, fraction, max_attempts, ctx->w};
    adem_error werr = {ADEM_OK, ""};
    st = adem_insert_fill(&def, &rng, ctx->pos, ctx->rad, ctx->n, &res, &werr);
    if (st == ADEM_ERR_NOMEM) st = adem_yaml_nomem(ctx);
    else if (st) st = adem_yaml_fail(ctx, dm.node, dm.path, "%s the %s (%s is %g m)", werr.message, word,
                           fit_what, fit);
  }
  size_t first = ctx->n;
  for (size_t k = 0; k < res.n && !st; ++k) st = push_sphere(ctx, res.pos[k], res.radius[k], v, w);
  if (!st && res.n < res.wanted) {
    char loc[LOC_MAX], frac[160] = "";
    adem_yaml_where(ctx, m->node, loc, sizeof loc);
    if (fraction_node)
      snprintf(frac, sizeof frac, " (solid fraction %.4g of the %.4g asked)",
               res.volume / reg.volume, fraction);
    adem_log(ADEM_LOG_WARN,
             "%s: %s: random fill placed %zu of %zu spheres before max_attempts (%llu) ran out%s; "
             "the %s may be too full",
             loc, m->path, res.n, res.wanted, (unsigned long long)res.attempts, frac, word);
  }
  adem_insert_fill_result_free(&res);
  adem_insert_dist_free(&dist);
  if (!st) { /* kept for `adem check`'s look at it against the walls */
    char where[KEY_PATH_MAX + 16];
    snprintf(where, sizeof where, "%s%s", m->path,
             adem_yaml_map_get(ctx, m->node, "region") ? ".region" : " (min, max)");
    adem_error werr = {ADEM_OK, ""};
    if (adem_regions_add(&ctx->c->fills, word, where, &reg, &werr)) st = adem_yaml_nomem(ctx);
  }
  adem_insert_region_free(&reg);
  if (st) return st;
  return flush_spheres(ctx, first, mat, group, m->node, m->path);
}

/* ---- pours ---- */

/* Material of a set or pour that makes particles: exists, not rigid, has a density. */
static adem_status particle_material(case_ctx *ctx, const map_cursor *m, int *mat) {
  char material[ADEM_NAME_MAX], path[KEY_PATH_MAX];
  yaml_node_t *mat_node;
  adem_status st = adem_yaml_get_string(ctx, m, "material", material, sizeof material, &mat_node);
  if (st) return st;
  adem_yaml_join(path, sizeof path, m->path, "material");
  if ((st = find_material(ctx, material, mat_node, path, mat))) return st;
  if (ctx->mat_rigid[*mat])
    return adem_yaml_fail(ctx, mat_node, path, "material `%s` is rigid; rigid materials are for walls only",
                material);
  if (!ctx->mat_density[*mat]) {
    char at[LOC_MAX];
    adem_yaml_where_short(ctx, ctx->mat_node[*mat], at, sizeof at);
    return adem_yaml_fail(ctx, mat_node, path,
                "material `%s` (at %s) has no `density`; materials of particles need one", material,
                at);
  }
  return ADEM_OK;
}

static adem_status build_pours(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "pours", &l);
  if (st || l.n == 0) return st;
  adem_world *w = ctx->w;
  if (!w->insert_rmin) {
    w->insert_rmin = malloc((size_t)(w->mat.n > 0 ? w->mat.n : 1) * sizeof *w->insert_rmin);
    if (!w->insert_rmin) return adem_yaml_nomem(ctx);
    for (int k = 0; k < w->mat.n; ++k) w->insert_rmin[k] = INFINITY;
  }
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m, dm;
    adem_pour_def d;
    memset(&d, 0, sizeof d);
    char path[KEY_PATH_MAX], group_name[ADEM_NAME_MAX];
    yaml_node_t *name_node, *group_node, *rate_node, *mass_node, *end_node, *interval_node;
    const char *word = "", *fit_what = "";
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    if ((st = adem_yaml_get_string(ctx, &m, "name", d.name, sizeof d.name, &name_node))) break;
    if (!name_node) snprintf(d.name, sizeof d.name, "pour%zu", i);
    for (int k = 0; ctx->c->pours && k < ctx->c->pours->n && !st; ++k)
      if (!strcmp(ctx->c->pours->p[k].def.name, d.name)) {
        adem_yaml_join(path, sizeof path, m.path, "name");
        st = adem_yaml_fail(ctx, name_node ? name_node : m.node, path, "duplicate pour name `%s`", d.name);
      }
    if (st) break;
    if ((st = particle_material(ctx, &m, &d.material))) break;
    if ((st = adem_yaml_get_string(ctx, &m, "group", group_name, sizeof group_name, &group_node))) break;
    adem_yaml_join(path, sizeof path, m.path, "group");
    if ((st = find_group(ctx, group_name, group_node ? group_node : m.node, path, &d.group))) break;
    if ((st = adem_yaml_get_number(ctx, &m, "rate", &d.rate, &rate_node))) break;
    if ((st = adem_yaml_get_number(ctx, &m, "mass_rate", &d.mass_rate, &mass_node))) break;
    if (rate_node && mass_node) {
      adem_yaml_join(path, sizeof path, m.path, "mass_rate");
      st = adem_yaml_fail(ctx, mass_node, path, "give either `rate` (particles/s) or `mass_rate` (kg/s), not both");
      break;
    }
    if (!rate_node && !mass_node) {
      adem_yaml_join(path, sizeof path, m.path, "rate");
      st = adem_yaml_missing(ctx, &m, adem_schema_find("pours[]", "rate", NULL), path);
      break;
    }
    if ((st = adem_yaml_get_number(ctx, &m, "start", &d.start, NULL))) break;
    if ((st = adem_yaml_get_number(ctx, &m, "end", &d.end, &end_node))) break;
    if (!(d.end > d.start)) {
      adem_yaml_join(path, sizeof path, m.path, "end");
      st = adem_yaml_fail(ctx, end_node, path, "the window ends (%g s) before it starts (`start`: %g s)",
                d.end, d.start);
      break;
    }
    if (d.end > ctx->c->end_time) {
      char loc[LOC_MAX];
      adem_yaml_where(ctx, end_node, loc, sizeof loc);
      adem_log(ADEM_LOG_WARN, "%s: %s.end: the pour ends at t = %g s, after time.end = %g s: the "
               "run stops before it is complete", loc, m.path, d.end, ctx->c->end_time);
    }
    d.interval = (d.end - d.start) / 20.0;
    if ((st = adem_yaml_get_number(ctx, &m, "interval", &d.interval, &interval_node))) break;
    if ((st = adem_yaml_get_vec3(ctx, &m, "velocity", &d.velocity, NULL))) break;
    if ((st = adem_yaml_get_vec3(ctx, &m, "angular_velocity", &d.angular_velocity, NULL))) break;
    if ((st = adem_yaml_get_uint(ctx, &m, "max_attempts", &d.max_attempts, NULL))) break;
    if ((st = read_region(ctx, &m, false, &d.region, &word))) break;
    double fit = adem_insert_region_fit(&d.region, &fit_what);
    if ((st = read_dist(ctx, &m, fit, fit_what, word, &d.dist, &dm))) {
      adem_insert_region_free(&d.region);
      adem_insert_dist_free(&d.dist);
      break;
    }
    double window = d.end - d.start;
    ctx->poured += d.rate > 0.0 ? d.rate * window
                                : spheres_for_volume(&d.dist, d.mass_rate * window /
                                                                 w->mat.m[d.material].def.density);
    if ((st = check_memory(ctx, 0.0, m.node, m.path))) {
      adem_insert_region_free(&d.region);
      adem_insert_dist_free(&d.dist);
      break;
    }
    d.seed = ctx->c->seed ^ (0xd1b54a32d192ed03ULL * (uint64_t)(i + 1));
    w->insert_rmin[d.material] = fmin(w->insert_rmin[d.material], adem_insert_dist_smallest(&d.dist));
    box_include(ctx, d.region.lo, d.region.hi);
    ctx->vmax = fmax(ctx->vmax, v3_norm(d.velocity));
    ctx->rmax = fmax(ctx->rmax, adem_insert_dist_largest(&d.dist));
    adem_error werr = {ADEM_OK, ""};
    if (adem_pours_add(&ctx->c->pours, &d, w->mat.m[d.material].def.density, &werr)) {
      adem_insert_region_free(&d.region);
      adem_insert_dist_free(&d.dist);
      st = adem_yaml_nomem(ctx);
    }
  }
  return st;
}

/* ---- run-until conditions ---- */

/* `until` of parent (time, or a stage): *given false when absent. Walls must be built. */
static adem_status read_until(case_ctx *ctx, const map_cursor *parent, adem_until_def *def,
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
                              "walls: %s", def->wall, sg.best, names[0] ? names : "none");
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

/* ---- stages ---- */

/* Appends text to a growing string. */
static bool emit_text(char **buf, size_t *len, size_t *cap, const char *s, size_t n) {
  if (*len + n + 1 > *cap) {
    size_t c = 2 * (*len + n + 1);
    char *b = realloc(*buf, c);
    if (!b) return false;
    *buf = b;
    *cap = c;
  }
  memcpy(*buf + *len, s, n);
  *len += n;
  (*buf)[*len] = '\0';
  return true;
}

/* A YAML value written back as flow-style text that --set's parser reads as the same value:
 * plain scalars stay plain (numbers, booleans, `auto`), others are double-quoted. */
static bool emit_node(case_ctx *ctx, yaml_node_t *v, char **buf, size_t *len, size_t *cap,
                      int depth) {
  if (depth > 64) return false;
  if (v->type == YAML_SCALAR_NODE) {
    const char *s = adem_yaml_sval(v);
    size_t n = v->data.scalar.length;
    if (adem_yaml_is_null(v)) return emit_text(buf, len, cap, "~", 1);
    if (adem_yaml_is_plain(v) && !strpbrk(s, ",[]{}#:\"'\n") && s[0] != ' ' && s[0] != '&' && s[0] != '*' &&
        s[0] != '!' && s[0] != '|' && s[0] != '>' && s[0] != '%' && s[0] != '@' && s[0] != '`')
      return emit_text(buf, len, cap, s, n);
    if (!emit_text(buf, len, cap, "\"", 1)) return false;
    for (size_t k = 0; k < n; ++k) {
      char esc[8];
      unsigned char ch = (unsigned char)s[k];
      if (ch == '"' || ch == '\\') snprintf(esc, sizeof esc, "\\%c", ch);
      else if (ch < 0x20) snprintf(esc, sizeof esc, "\\x%02x", ch);
      else snprintf(esc, sizeof esc, "%c", ch);
      if (!emit_text(buf, len, cap, esc, strlen(esc))) return false;
    }
    return emit_text(buf, len, cap, "\"", 1);
  }
  bool seq = v->type == YAML_SEQUENCE_NODE;
  if (!emit_text(buf, len, cap, seq ? "[" : "{", 1)) return false;
  if (seq) {
    for (yaml_node_item_t *it = v->data.sequence.items.start; it < v->data.sequence.items.top; ++it)
      if ((it > v->data.sequence.items.start && !emit_text(buf, len, cap, ", ", 2)) ||
          !emit_node(ctx, adem_yaml_node_at(ctx, *it), buf, len, cap, depth + 1))
        return false;
  } else {
    for (yaml_node_pair_t *p = v->data.mapping.pairs.start; p < v->data.mapping.pairs.top; ++p)
      if ((p > v->data.mapping.pairs.start && !emit_text(buf, len, cap, ", ", 2)) ||
          !emit_node(ctx, adem_yaml_node_at(ctx, p->key), buf, len, cap, depth + 1) ||
          !emit_text(buf, len, cap, ": ", 2) ||
          !emit_node(ctx, adem_yaml_node_at(ctx, p->value), buf, len, cap, depth + 1))
        return false;
  }
  return emit_text(buf, len, cap, seq ? "]" : "}", 1);
}

/* `stages`: names, durations and the `set` of each, as "path=value" strings for the loader. */
static adem_status build_stages(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "stages", &l);
  if (st || l.n == 0) return st;
  adem_case *c = ctx->c;
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    char name[ADEM_NAME_MAX], path[KEY_PATH_MAX], loc[LOC_MAX];
    yaml_node_t *name_node, *duration_node, *v;
    const adem_schema_entry *e;
    double duration = -1.0;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    if ((st = adem_yaml_get_string(ctx, &m, "name", name, sizeof name, &name_node))) break;
    if (!name_node) snprintf(name, sizeof name, "stage%zu", i);
    for (int k = 0; c->stages && k < c->stages->n && !st; ++k)
      if (!strcmp(c->stages->s[k].name, name)) {
        adem_yaml_join(path, sizeof path, m.path, "name");
        st = adem_yaml_fail(ctx, name_node ? name_node : m.node, path, "duplicate stage name `%s`", name);
      }
    if (st) break;
    if ((st = adem_yaml_get_number(ctx, &m, "duration", &duration, &duration_node))) break;
    if (!duration_node) duration = -1.0;
    adem_yaml_where(ctx, m.node, loc, sizeof loc);
    adem_error werr = {ADEM_OK, ""};
    if (adem_stages_add(&c->stages, name, duration, loc, &werr)) {
      st = adem_yaml_nomem(ctx);
      break;
    }
    adem_until_def ud;
    bool has_until = false;
    if ((st = read_until(ctx, &m, &ud, &has_until))) break;
    if (has_until && adem_stages_set_until(c->stages, &ud, &werr)) {
      st = adem_yaml_nomem(ctx);
      break;
    }
    if ((st = adem_yaml_lookup(ctx, &m, "set", &e, &v, path))) break;
    if (!v || adem_yaml_is_null(v)) continue;
    if (v->type != YAML_MAPPING_NODE) {
      st = adem_yaml_wrong_type(ctx, e, v, path);
      break;
    }
    for (yaml_node_pair_t *p = v->data.mapping.pairs.start; p < v->data.mapping.pairs.top && !st; ++p) {
      yaml_node_t *k = adem_yaml_node_at(ctx, p->key);
      char kp[KEY_PATH_MAX];
      if (k->type != YAML_SCALAR_NODE || adem_yaml_is_null(k)) {
        st = adem_yaml_fail(ctx, k, path, "a key must be a key path such as materials.glass.friction");
        break;
      }
      adem_yaml_join(kp, sizeof kp, path, adem_yaml_sval(k));
      const char *why = adem_stages_check_path(adem_yaml_sval(k));
      if (why) {
        st = adem_yaml_fail(ctx, k, kp, "cannot change in a stage: %s", why);
        break;
      }
      char *text = NULL;
      size_t len = 0, cap = 0;
      bool ok = emit_text(&text, &len, &cap, adem_yaml_sval(k), strlen(adem_yaml_sval(k))) &&
                emit_text(&text, &len, &cap, "=", 1) &&
                emit_node(ctx, adem_yaml_node_at(ctx, p->value), &text, &len, &cap, 0);
      if (!ok || adem_stages_add_set(c->stages, text, &werr)) st = adem_yaml_nomem(ctx);
      free(text);
    }
  }
  return st;
}

/* `type: state`: the particles of a checkpoint, in the order of their ids, with this case's
 * materials of the same names. */
static adem_status build_state(case_ctx *ctx, const map_cursor *m, int group) {
  char file[ADEM_PATH_MAX], path[KEY_PATH_MAX];
  yaml_node_t *file_node;
  adem_status st = adem_yaml_get_string(ctx, m, "file", file, sizeof file, &file_node);
  if (st) return st;
  adem_yaml_join(path, sizeof path, m->path, "file");
  char *resolved = mesh_path(ctx, file);
  if (!resolved) return adem_yaml_nomem(ctx);
  char *data = NULL;
  size_t len = 0;
  adem_error werr = {ADEM_OK, ""};
  adem_particles p;
  memset(&p, 0, sizeof p);
  char(*names)[ADEM_NAME_MAX] = NULL;
  int nmat = 0;
  size_t *order = NULL;
  adem_reader rd;
  st = adem_file_read_all(resolved, &data, &len, &werr);
  if (!st) st = adem_checkpoint_header_check(data, len, resolved, ADEM_CKPT_MAGIC,
                                              sizeof(adem_contact_history), &rd, &werr);
  if (!st) { /* the case section, skipped by its length */
    uint64_t skip = adem_get_u64(&rd);
    if (rd.failed || skip > (uint64_t)(rd.end - rd.at))
      st = adem_error_set(&werr, ADEM_ERR_INPUT, "%s is not a usable adem checkpoint: it is cut short", resolved);
    else
      rd.at += skip;
  }
  if (!st) {
    st = adem_world_read_particles(&rd, &p, &names, &nmat, &werr);
    if (st && st != ADEM_ERR_NOMEM) {
      char why[ADEM_MSG_MAX];
      snprintf(why, sizeof why, "%s", werr.message);
      adem_error_set(&werr, st, "%s is not a usable adem checkpoint: %s", resolved, why);
    }
  }
  if (st) {
    st = st == ADEM_ERR_NOMEM ? adem_yaml_nomem(ctx) : adem_yaml_fail(ctx, file_node, path, "%s", werr.message);
    goto done;
  }
  /* keep_inside: trim to the centres inside a box (a levelled bed) */
  bool trim = adem_yaml_map_get(ctx, m->node, "keep_inside") != NULL;
  adem_vec3 keep_lo = {0, 0, 0}, keep_hi = {0, 0, 0};
  if (trim) {
    map_cursor km;
    yaml_node_t *hi_node;
    if ((st = adem_yaml_get_map(ctx, m, "keep_inside", &km))) goto done;
    if ((st = adem_yaml_get_vec3(ctx, &km, "min", &keep_lo, NULL))) goto done;
    if ((st = adem_yaml_get_vec3(ctx, &km, "max", &keep_hi, &hi_node))) goto done;
    if ((st = check_box(ctx, keep_lo, keep_hi, hi_node, &km))) goto done;
  }
  if ((st = check_memory(ctx, (double)p.n, m->node, m->path))) goto done;
  /* by id (an outlet may have removed some: not always 0 .. n-1) */
  order = malloc((p.n + 1) * sizeof *order);
  uint32_t *by_id = malloc((p.n + 1) * sizeof *by_id);
  if (!order || !by_id || adem_particles_id_order(&p, by_id)) {
    free(by_id);
    st = adem_yaml_nomem(ctx);
    goto done;
  }
  for (size_t k = 0; k < p.n; ++k) order[k] = by_id[k];
  for (size_t k = 1; k < p.n && !st; ++k)
    if (p.id[order[k]] == p.id[order[k - 1]])
      st = adem_yaml_fail(ctx, file_node, path, "%s is not a usable adem checkpoint: particle id %llu is there twice", resolved, (unsigned long long)p.id[order[k]]);
  free(by_id);
  for (size_t k = 0; k < p.n && !st; ++k) {
    size_t i = order[k];
    adem_vec3 x = p.pos[i];
    if (trim && !(x.x >= keep_lo.x && x.x <= keep_hi.x && x.y >= keep_lo.y && x.y <= keep_hi.y &&
                  x.z >= keep_lo.z && x.z <= keep_hi.z))
      continue;
    const char *name = names[p.material[i]];
    int mat = -1;
    for (int j = 0; j < ctx->nmat && mat < 0; ++j)
      if (!strcmp(ctx->mat_name[j], name)) mat = j;
    if (mat < 0) {
      st = adem_yaml_fail(ctx, file_node, path,
                          "the particles of %s are made of material `%s`, which this case does not "
                          "have; add a material of that name", resolved, name);
      break;
    }
    if (ctx->mat_rigid[mat] || !ctx->mat_density[mat]) {
      st = adem_yaml_fail(ctx, file_node, path,
                          "material `%s` of the particles of %s needs a `density` and must not be "
                          "rigid here", name, resolved);
      break;
    }
    if ((st = push_sphere(ctx, p.pos[i], p.radius[i], p.vel[i], p.omega[i]))) break;
    st = flush_spheres(ctx, ctx->n - 1, mat, group, file_node, path);
  }
done:
  free(order);
  free(names);
  adem_particles_free(&p);
  free(data);
  free(resolved);
  return st;
}

/* particles[].frozen / attach: the set's spheres (from index n0) become part of a wall
 * (src/core/frozen.c), a plane or a mesh group by name, or are fixed in space. */
static adem_status freeze_set(case_ctx *ctx, const map_cursor *m, size_t n0) {
  bool frozen = false;
  char name[ADEM_NAME_MAX] = "", path[KEY_PATH_MAX];
  yaml_node_t *node;
  adem_status st = adem_yaml_get_bool(ctx, m, "frozen", &frozen);
  if (!st) st = adem_yaml_get_string(ctx, m, "attach", name, sizeof name, &node);
  if (st || (!frozen && !node)) return st;
  int32_t attach = 0;
  if (node) {
    adem_yaml_join(path, sizeof path, m->path, "attach");
    int g = adem_world_find_mesh_group(ctx->w, name);
    for (int k = 0; g < 0 && k < adem_world_plane_count(ctx->w) && !attach; ++k)
      if (!strcmp(adem_world_plane(ctx->w, k)->name, name)) attach = -(k + 1);
    if (g >= 0) attach = g + 1;
    if (!attach)
      return adem_yaml_fail(ctx, node, path, "no plane or mesh group named `%s` to attach to "
                            "(a box's planes are NAME.xmin ...)", name);
  }
  for (size_t i = n0; i < ctx->w->p.n; ++i) {
    adem_error werr = {ADEM_OK, ""};
    if (adem_world_freeze_particle(ctx->w, ctx->w->p.id[i], attach, &werr))
      return adem_yaml_fail(ctx, node ? node : m->node, node ? path : m->path, "%s", werr.message);
  }
  return ADEM_OK;
}

static adem_status build_particles(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "particles", &l);
  if (st) return st;
  if (l.n == 0 && !adem_yaml_map_get(ctx, root->node, "pours")) { /* a case needs something to move */
    if (!l.node) return adem_yaml_missing(ctx, root, l.e, l.path);
    return adem_yaml_fail(ctx, l.node, l.path, "needs at least 1 item (or give `pours`)");
  }
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    char material[ADEM_NAME_MAX], group_name[ADEM_NAME_MAX], path[KEY_PATH_MAX];
    yaml_node_t *mat_node, *group_node;
    int mat, group;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) return st;
    if (!strcmp(m.variant, "state")) {
      if ((st = adem_yaml_get_string(ctx, &m, "group", group_name, sizeof group_name, &group_node))) return st;
      adem_yaml_join(path, sizeof path, m.path, "group");
      if ((st = find_group(ctx, group_name, group_node ? group_node : m.node, path, &group))) return st;
      if ((st = build_state(ctx, &m, group))) return st;
      continue;
    }
    if ((st = adem_yaml_get_string(ctx, &m, "material", material, sizeof material, &mat_node))) return st;
    adem_yaml_join(path, sizeof path, m.path, "material");
    if ((st = find_material(ctx, material, mat_node, path, &mat))) return st;
    if (ctx->mat_rigid[mat])
      return adem_yaml_fail(ctx, mat_node, path, "material `%s` is rigid; rigid materials are for walls only",
                  material);
    if (!ctx->mat_density[mat]) {
      char at[LOC_MAX];
      adem_yaml_where_short(ctx, ctx->mat_node[mat], at, sizeof at);
      return adem_yaml_fail(ctx, mat_node, path,
                  "material `%s` (at %s) has no `density`; materials of particles need one", material,
                  at);
    }
    if ((st = adem_yaml_get_string(ctx, &m, "group", group_name, sizeof group_name, &group_node))) return st;
    adem_yaml_join(path, sizeof path, m.path, "group");
    if ((st = find_group(ctx, group_name, group_node ? group_node : m.node, path, &group))) return st;
    size_t n0 = ctx->w->p.n;
    if (!strcmp(m.variant, "list"))
      st = build_list(ctx, &m, mat, group);
    else if (!strcmp(m.variant, "lattice"))
      st = build_lattice(ctx, &m, mat, group);
    else
      st = build_random(ctx, &m, i, mat, group);
    if (!st) st = freeze_set(ctx, &m, n0);
    if (st) return st;
  }
  return ADEM_OK;
}

/* Case name from a file name: no directory, no extension. */
static void file_stem(const char *file, char *buf, size_t n) {
  const char *base = strrchr(file, '/');
  base = base ? base + 1 : file;
  const char *dot = strrchr(base, '.');
  size_t len = dot && dot != base ? (size_t)(dot - base) : strlen(base);
  if (len >= n) len = n - 1;
  if (len == 0) {
    snprintf(buf, n, "case");
    return;
  }
  memcpy(buf, base, len);
  buf[len] = '\0';
}

/* time.step: the proposal at v_ref (rule in the reference doc), or the user's step checked
 * against it. */
static adem_status choose_step(case_ctx *ctx, const map_cursor *time, adem_vec3 g) {
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
                  "limits.allow_large_step: true", step, step / limit, limit_name,
                  limit, c->estimate.t_collision, v_ref, c->estimate.dt, limit);
    if (c->dt_user_ratio > 1.0) {
      bool collision = c->estimate.t_collision / 50.0 <= 0.2 * c->estimate.t_rayleigh;
      char loc[LOC_MAX];
      adem_yaml_where(ctx, step_node, loc, sizeof loc);
      adem_log(ADEM_LOG_WARN,
               "%s: time.step %g s is %.1fx the proposed %g s (%s); the %s = %g s is %.1fx "
               "the proposal%s", loc, step, c->dt_user_ratio,
               c->estimate.dt,
               c->estimate.dt < fmin(c->estimate.t_collision / 50.0, 0.2 * c->estimate.t_rayleigh)
                   ? "a fifth of the stability limit"
                   : collision ? "t_collision/50" : "0.2 t_Rayleigh",
               limit_name, limit, limit / c->estimate.dt,
               step > limit ? " and the step is above it (limits.allow_large_step)" : "");
    }
  }
  return ADEM_OK;
}

/* H section 6.2: with a reduced stiffness the force that breaks a JKR contact drops to
 * (8/9) 3 pi gamma_mod R. The group forces are constant, so one look at load time finds every
 * group whose force pulls hard enough, against any JKR pair its spheres can touch, to break
 * contacts the real material would keep. One warning per group, for its weakest pair. */
static adem_status warn_pulling_forces(case_ctx *ctx) {
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
        if (it->normal != ADEM_NORMAL_JKR || !(it->pp.gamma > 0.0)) continue;
        double rb = rmin[ng * nm + b];
        for (int side = 0; side < 2; ++side) { /* 0: a sphere of b, 1: a wall of b */
          if (side == 0 && !isfinite(rb)) continue;
          if (side == 1 && !wall[b]) continue;
          double R = side ? ra : ra * rb / (ra + rb);
          double pull = 8.0 / 9.0 * adem_jkr_pair_summarize(it->pp.E_real, it->pp.E, it->pp.gamma_real,
                                                            it->pp.gamma, R, 1.0, 1.0).f_c_mod;
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
             "`%s`-`%s`%s JKR contact, (8/9) 3 pi gamma_mod R = %.3g N (R = %.3g m, gamma_mod = "
             "%.3g J/m^2%s); such forces can tear apart contacts the real material keeps. Keep "
             "them below %.0f%% of it (%.3g N)%s (Haervig et al. section 6.2)",
             loc, w->groups[g].name, force, 100.0 * worst, w->mat.m[wa].def.name,
             w->mat.m[wb].def.name, worst_wall ? " (wall)" : "", worst_pull, worst_R,
             it->pp.gamma, it->pp.E < it->pp.E_real ? ", reduced with the stiffness by H24" : "",
             100.0 * ADEM_PULLOFF_SAFETY, ADEM_PULLOFF_SAFETY * worst_pull,
             it->pp.E < it->pp.E_real ? " or reduce the stiffness less" : "");
  }
  free(rmin);
  free(wall);
  return ADEM_OK;
}

/* output.track: ids of particles already created (ids count from 0 in order of creation, so
 * particle id k was made from ctx->pos[k]), without repeats. */
static adem_status read_track(case_ctx *ctx, const map_cursor *out) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_output_settings *o = &ctx->c->output;
  o->ntrack = 0;
  adem_status st = adem_yaml_lookup(ctx, out, "track", &e, &v, path);
  if (st || !v || adem_yaml_is_null(v)) return st;
  if (v->type != YAML_SEQUENCE_NODE) return adem_yaml_wrong_type(ctx, e, v, path);
  size_t n = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
  if ((double)n > e->hi)
    return adem_yaml_fail(ctx, v, path, "lists %zu particles; at most %g can be tracked", n, e->hi);
  for (size_t k = 0; k < n; ++k) {
    yaml_node_t *item = adem_yaml_node_at(ctx, v->data.sequence.items.start[k]);
    char p[KEY_PATH_MAX + 24], t[128];
    snprintf(p, sizeof p, "%s[%zu]", path, k);
    uint64_t id;
    if (!adem_yaml_parse_uint(item, &id)) {
      adem_yaml_node_text(item, t, sizeof t);
      return adem_yaml_fail(ctx, item, p, "expected a particle id (an integer >= 0), got %s", t);
    }
    if (id >= ctx->n)
      return adem_yaml_fail(ctx, item, p, "there is no particle %llu: the case creates %zu (ids 0 to %zu)",
                  (unsigned long long)id, ctx->n, ctx->n ? ctx->n - 1 : 0);
    for (int j = 0; j < o->ntrack; ++j)
      if (o->track[j] == id)
        return adem_yaml_fail(ctx, item, p, "particle %llu is listed twice", (unsigned long long)id);
    o->track[o->ntrack] = id;
    o->ntrack++;
  }
  return ADEM_OK;
}

/* output.regions: named regions whose particles each CSV row counts. */
static adem_status read_output_regions(case_ctx *ctx, const map_cursor *out) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, out, "regions", &l);
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    char name[ADEM_NAME_MAX], path[KEY_PATH_MAX];
    yaml_node_t *name_node;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    if ((st = adem_yaml_get_string(ctx, &m, "name", name, sizeof name, &name_node))) break;
    for (int k = 0; ctx->c->regions && k < ctx->c->regions->n; ++k)
      if (!strcmp(ctx->c->regions->r[k].name, name)) {
        adem_yaml_join(path, sizeof path, m.path, "name");
        return adem_yaml_fail(ctx, name_node, path, "duplicate region name `%s` (also %s)", name,
                              ctx->c->regions->r[k].where);
      }
    adem_region reg;
    memset(&reg, 0, sizeof reg);
    const char *word = "";
    if ((st = read_region_map(ctx, &m, &reg, &word))) break;
    adem_error werr = {ADEM_OK, ""};
    if (adem_regions_add(&ctx->c->regions, name, m.path, &reg, &werr)) st = adem_yaml_nomem(ctx);
    adem_insert_region_free(&reg);
  }
  return st;
}

/* domain.periodic: each periodic length at least 2 (largest diameter + skin), so that a pair
 * touches through one image at most; no plane wall with a component of its normal along a
 * periodic axis and no box wall (its faces cut every axis). */
static adem_status check_periodic(case_ctx *ctx, const map_cursor *root, adem_vec3 lo, adem_vec3 hi,
                                  const bool per[3], yaml_node_t *const per_items[3],
                                  double skin_fraction) {
  const double a[3] = {lo.x, lo.y, lo.z}, b[3] = {hi.x, hi.y, hi.z};
  double dmax = 2.0 * ctx->rmax, skin = skin_fraction * dmax, need = 2.0 * (dmax + skin);
  char path[KEY_PATH_MAX], where[LOC_MAX];
  for (int d = 0; d < 3; ++d) {
    if (!per[d] || b[d] - a[d] >= need) continue;
    snprintf(path, sizeof path, "domain.periodic[%d]", d);
    return adem_yaml_fail(ctx, per_items[d], path,
                          "the domain is %g m long along %c; a periodic axis needs at least 2 "
                          "(largest diameter + skin) = 2 (%g + %g) = %g m for the minimum image: "
                          "lengthen the domain along %c or make it non-periodic",
                          b[d] - a[d], "xyz"[d], dmax, skin, need, "xyz"[d]);
  }
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "walls", &l);
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) break;
    int d = per[0] ? 0 : per[1] ? 1 : 2;
    if (!strcmp(m.variant, "box")) {
      adem_yaml_where_short(ctx, per_items[d], where, sizeof where);
      adem_yaml_join(path, sizeof path, m.path, "type");
      return adem_yaml_fail(ctx, adem_yaml_map_get(ctx, m.node, "type"), path,
                            "a box wall has faces across every axis, and %c is periodic "
                            "(domain.periodic at %s); use plane walls parallel to the periodic "
                            "axes", "xyz"[d], where);
    }
    if (strcmp(m.variant, "plane")) continue;
    adem_vec3 n;
    yaml_node_t *node;
    if ((st = adem_yaml_get_vec3(ctx, &m, "normal", &n, &node))) break;
    const double c[3] = {n.x, n.y, n.z};
    for (d = 0; d < 3; ++d) {
      if (!per[d] || !(fabs(c[d]) > 1e-12 * v3_norm(n))) continue;
      adem_yaml_where_short(ctx, per_items[d], where, sizeof where);
      adem_yaml_join(path, sizeof path, m.path, "normal");
      return adem_yaml_fail(ctx, node, path,
                            "the plane's normal [%g, %g, %g] has a component along %c, a periodic "
                            "axis (domain.periodic at %s): a plane would cut the periodic box; it "
                            "must be parallel to every periodic axis",
                            c[0], c[1], c[2], "xyz"[d], where);
    }
  }
  return st;
}

static adem_status build(case_ctx *ctx) {
  adem_case *c = ctx->c;
  map_cursor root, time, nb, limits, out, domain;
  yaml_node_t *node;
  adem_status st;
  if ((st = adem_yaml_map_open(ctx, yaml_document_get_root_node(&ctx->doc), NULL, "", "", NULL, &root)))
    return st;
  if ((st = adem_yaml_get_string(ctx, &root, "name", c->name, sizeof c->name, &node))) return st;
  if (!node) file_stem(ctx->stem_of, c->name, sizeof c->name);
  if ((st = adem_yaml_get_uint(ctx, &root, "seed", &c->seed, NULL))) return st;
  if ((st = adem_yaml_get_map(ctx, &root, "time", &time))) return st; /* required: report it early */
  if ((st = adem_yaml_get_number(ctx, &time, "end", &c->end_time, NULL))) return st;
  if ((st = build_materials(ctx, &root))) return st;
  if ((st = build_interactions(ctx, &root))) return st;
  if (!adem_yaml_map_get(ctx, root.node, "stages")) /* with stages: once they are known */
    warn_unused_law_params(ctx, ctx->file, &ctx->w->mat, NULL);
  if ((st = build_groups(ctx, &root))) return st;
  if ((st = build_walls(ctx, &root))) return st;
  if (!adem_yaml_map_get(ctx, root.node, "stages")) /* with stages: once they are known */
    warn_brof_turning(ctx->file, ctx->w, NULL);
  /* Limits first: an explicit list may overlap by what limits.initial_overlap accepts. */
  double skin, overlap, initial = 0.0;
  if ((st = adem_yaml_get_map(ctx, &root, "limits", &limits))) return st;
  if ((st = adem_yaml_get_number(ctx, &limits, "max_overlap_ratio", &overlap, NULL))) return st;
  adem_world_set_max_overlap_ratio(ctx->w, overlap);
  if ((st = adem_yaml_get_number(ctx, &limits, "initial_overlap", &initial, NULL))) return st;
  adem_world_set_initial_overlap(ctx->w, initial);
  ctx->initial_overlap = initial;
  if ((st = adem_yaml_get_auto(ctx, &limits, "max_memory", &ctx->memory_auto, &ctx->max_memory, NULL)))
    return st;
  if ((st = adem_yaml_get_bool(ctx, &limits, "allow_large_step", &ctx->allow_large_step))) return st;
  /* the skin sets the candidate pairs of the memory estimate */
  if ((st = adem_yaml_get_map(ctx, &root, "neighbor", &nb))) return st;
  if ((st = adem_yaml_get_number(ctx, &nb, "skin", &skin, NULL))) return st;
  adem_world_set_skin(ctx->w, skin);
  if ((st = build_particles(ctx, &root))) return st;
  if ((st = build_pours(ctx, &root))) return st;
  if ((st = check_memory(ctx, 0.0, limits.node ? limits.node : root.at, limits.node ? "limits" : "")))
    return st;

  adem_vec3 g;
  if ((st = adem_yaml_get_vec3(ctx, &root, "gravity", &g, NULL))) return st;
  adem_world_set_gravity(ctx->w, g);
  adem_until_def ud;
  bool has_until = false;
  if ((st = read_until(ctx, &time, &ud, &has_until))) return st; /* walls and gravity known */
  if (has_until) {
    if (!(c->until = malloc(sizeof *c->until))) return adem_yaml_nomem(ctx);
    adem_until_init(c->until, &ud);
  }

  adem_output_settings *o = &c->output;
  if ((st = adem_yaml_get_map(ctx, &root, "output", &out))) return st;
  if ((st = adem_yaml_get_string(ctx, &out, "dir", o->dir, sizeof o->dir, &node))) return st;
  if (!node) snprintf(o->dir, sizeof o->dir, "out/%s", c->name);
  o->frame_interval = c->end_time / 100.0;
  o->csv_interval = c->end_time / 1000.0;
  o->checkpoint_interval = c->end_time / 10.0;
  bool plot;
  if ((st = adem_yaml_get_number(ctx, &out, "frame_interval", &o->frame_interval, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, &out, "csv_interval", &o->csv_interval, NULL))) return st;
  if ((st = adem_yaml_get_number(ctx, &out, "checkpoint_interval", &o->checkpoint_interval, NULL))) return st;
  if ((st = adem_yaml_get_bool(ctx, &out, "plot", &plot))) return st;
  o->plot = plot;
  if ((st = adem_yaml_get_bool(ctx, &out, "plot_loads", &plot))) return st;
  o->plot_loads = plot;
  if ((st = adem_yaml_get_bool(ctx, &out, "pieces", &plot))) return st;
  o->pieces = plot;
  if ((st = adem_yaml_get_bool(ctx, &out, "contacts", &plot))) return st;
  uint64_t every = 1;
  if ((st = adem_yaml_get_uint(ctx, &out, "contacts_every", &every, NULL))) return st;
  o->contacts_every = plot ? (int)(every < INT32_MAX ? every : INT32_MAX) : 0;
  if ((st = adem_yaml_get_bool(ctx, &out, "contacts_csv", &plot))) return st;
  o->contacts_csv = plot;
  bool balance;
  if ((st = adem_yaml_get_bool(ctx, &out, "energy_balance", &balance))) return st;
  adem_world_set_energy_balance(ctx->w, balance);
  if ((st = read_track(ctx, &out))) return st;
  if ((st = read_output_regions(ctx, &out))) return st;
  if ((st = build_stages(ctx, &root))) return st;

  if ((st = adem_yaml_get_map(ctx, &root, "domain", &domain))) return st;
  if (domain.node) {
    adem_vec3 lo, hi;
    yaml_node_t *hi_node;
    if ((st = adem_yaml_get_vec3(ctx, &domain, "min", &lo, NULL))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &domain, "max", &hi, &hi_node))) return st;
    if ((st = check_box(ctx, lo, hi, hi_node, &domain))) return st;
    bool per[3];
    yaml_node_t *per_items[3];
    if ((st = adem_yaml_get_bool3(ctx, &domain, "periodic", per, per_items))) return st;
    unsigned axes = (per[0] ? 1u : 0u) | (per[1] ? 2u : 0u) | (per[2] ? 4u : 0u);
    if (axes) {
      if ((st = check_periodic(ctx, &root, lo, hi, per, per_items, skin))) return st;
      adem_error werr = {ADEM_OK, ""};
      if (adem_world_set_periodic(ctx->w, lo, hi, axes, &werr))
        return adem_yaml_fail(ctx, domain.node, domain.path, "%s", werr.message);
    } else {
      adem_world_set_domain(ctx->w, lo, hi);
    }
  } else if (ctx->has_box) {
    /* Wide enough for free flight over the whole run, so only a blow-up trips it. */
    adem_vec3 ext = v3_sub(ctx->box_hi, ctx->box_lo);
    double t = c->end_time;
    double margin = fmax(fmax(ext.x, fmax(ext.y, ext.z)), 20.0 * ctx->rmax);
    margin = fmax(margin, ctx->vmax * t + 0.5 * v3_norm(g) * t * t);
    adem_world_set_domain(ctx->w, v3_sub(ctx->box_lo, v3(margin, margin, margin)),
                          v3_add(ctx->box_hi, v3(margin, margin, margin)));
  }
  if ((st = adem_outlets_read(ctx, &root, &out))) return st; /* regions and domain known */
  if ((st = choose_step(ctx, &time, g))) return st;
  return warn_pulling_forces(ctx);
}

static void ctx_free(case_ctx *ctx) {
  if (ctx->have_doc) yaml_document_delete(&ctx->doc);
  free(ctx->origin);
  free(ctx->mat_name);
  free(ctx->mat_node);
  free(ctx->mat_density);
  free(ctx->mat_rigid);
  free(ctx->group_name);
  free(ctx->group_node);
  free(ctx->pos);
  free(ctx->vel);
  free(ctx->omega);
  free(ctx->rad);
}

static char *copy_text(const char *s) {
  size_t n = strlen(s) + 1;
  char *t = malloc(n);
  if (t) memcpy(t, s, n);
  return t;
}

/* c->base_dir: dir made absolute, so that a checkpoint finds the case's files from any working
 * folder. */
static bool set_base_dir(adem_case *c, const char *dir) {
  if (dir[0] == '/') {
    snprintf(c->base_dir, sizeof c->base_dir, "%s", dir);
    return strlen(dir) < sizeof c->base_dir;
  }
  char cwd[ADEM_PATH_MAX];
  if (!getcwd(cwd, sizeof cwd)) return false;
  int n = strcmp(dir, ".") == 0 ? snprintf(c->base_dir, sizeof c->base_dir, "%s", cwd)
                                 : snprintf(c->base_dir, sizeof c->base_dir, "%s/%s", cwd, dir);
  return n > 0 && (size_t)n < sizeof c->base_dir;
}

/* Loads a case as adem_case_load_string does; with LOAD_STAGE it is a stage's configuration: its
 * own stages are read but not prepared, and nothing is logged. */
enum { LOAD_STAGE = 1 };
static adem_status load_string_flags(const char *text, const char *name_for_messages,
                                     const char *base_dir, const char *const *sets, int nsets,
                                     unsigned flags, adem_case **out, adem_error *err);

/* ---- stages: each stage's configuration is the case loaded again with the sets of the stages
 * up to it; stages.c carries them into the running world ---- */

static adem_status stage_config_extract(adem_stage_config *g, const adem_case *c, adem_error *err) {
  const adem_world *w = c->world;
  memset(g, 0, sizeof *g);
  g->nmaterials = w->mat.n;
  g->ninteractions = w->mat.ndefs;
  g->ngroups = w->ngroups;
  g->nplanes = w->walls.nplanes;
  g->nmeshes = w->walls.mesh.ngroups;
  g->materials = calloc((size_t)g->nmaterials + 1, sizeof *g->materials);
  g->interactions = calloc((size_t)g->ninteractions + 1, sizeof *g->interactions);
  g->group_force = calloc((size_t)g->ngroups + 1, sizeof *g->group_force);
  g->planes = calloc((size_t)g->nplanes + 1, sizeof *g->planes);
  g->meshes = calloc((size_t)g->nmeshes + 1, sizeof *g->meshes);
  if (!g->materials || !g->interactions || !g->group_force || !g->planes || !g->meshes) {
    adem_stage_config_free(g);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  for (int k = 0; k < g->nmaterials; ++k) g->materials[k] = w->mat.m[k].def;
  for (int k = 0; k < g->ninteractions; ++k) g->interactions[k] = w->mat.defs[k];
  for (int k = 0; k < g->ngroups; ++k) g->group_force[k] = w->groups[k].external_force;
  adem_status st = adem_walls_get_settings(&w->walls, g->planes, g->meshes, err);
  g->gravity = w->gravity;
  g->frame_interval = c->output.frame_interval;
  g->csv_interval = c->output.csv_interval;
  g->checkpoint_interval = c->output.checkpoint_interval;
  g->max_overlap_ratio = w->max_overlap_ratio;
  g->skin_fraction = w->nb.skin_fraction;
  g->dt_proposed = c->estimate.dt;
  if (st) adem_stage_config_free(g);
  return st;
}

/* The stage's configuration describes the same world: same materials, groups and walls. */
static adem_status check_same_world(const adem_case *c, const adem_case *sc, const adem_stage *g,
                                    adem_error *err) {
  const adem_world *w = c->world, *v = sc->world;
  const char *what = NULL;
  if (v->mat.n != w->mat.n) what = "materials";
  for (int k = 0; !what && k < w->mat.n; ++k)
    if (strcmp(v->mat.m[k].def.name, w->mat.m[k].def.name)) what = "materials";
  if (!what && v->ngroups != w->ngroups) what = "groups";
  for (int k = 0; !what && k < w->ngroups; ++k)
    if (strcmp(v->groups[k].name, w->groups[k].name)) what = "groups";
  if (!what && v->walls.nplanes != w->walls.nplanes) what = "walls";
  for (int k = 0; !what && k < w->walls.nplanes; ++k)
    if (strcmp(v->walls.planes[k].def.name, w->walls.planes[k].def.name)) what = "walls";
  if (!what && (v->walls.mesh.ngroups != w->walls.mesh.ngroups || v->walls.mesh.nverts != w->walls.mesh.nverts ||
                v->walls.mesh.ntris != w->walls.mesh.ntris))
    what = "walls";
  if (!what && v->p.n != w->p.n) what = "particles";
  if (what)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: stage `%s` changes which %s there are; a stage may change their "
                          "properties, not add or remove them (switch a wall off with `active: "
                          "false`)",
                          g->where, g->name, what);
  if (w->walls.mesh.nverts > 0 &&
      memcmp(v->walls.mesh_vert0, w->walls.mesh_vert0, w->walls.mesh.nverts * sizeof *w->walls.mesh_vert0) != 0)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: stage `%s` changes the shape or placement of a mesh wall; a stage "
                          "may change a mesh wall's motion, material and `active` only",
                          g->where, g->name);
  for (int k = 0; k < w->walls.mesh.ngroups; ++k)
    if (v->walls.mesh_motion[k].moving && !w->walls.mesh.groups[k].own_vertices)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "%s: stage `%s` sets mesh wall `%s` moving, but it was loaded sharing "
                            "its vertices with other walls; give it a motion (it may be at rest) "
                            "in the case itself",
                            g->where, g->name, w->walls.mesh.groups[k].name);
  return ADEM_OK;
}

/* Re-labels an error of loading stage k's configuration: where the stage (or the set entry
 * that caused it) is written. */
static adem_status stage_error(const adem_stage *g, int k, adem_status st, adem_error *err) {
  char inner[ADEM_MSG_MAX];
  snprintf(inner, sizeof inner, "%s", err ? err->message : "");
  const char *msg = inner;
  if (!strncmp(msg, "--set ", 6)) msg += 6;
  return adem_error_set(err, st, "%s: stages[%d] (`%s`).set: %s", g->where, k, g->name, msg);
}

static adem_status stages_prepare(adem_case *c, adem_error *err) {
  adem_stages *s = c->stages;
  if (!s || s->n == 0) return ADEM_OK;
  adem_status st = stage_config_extract(&s->base, c, err);
  if (st) return st;
  int total = c->nsets;
  for (int k = 0; k < s->n; ++k) total += s->s[k].nsets;
  const char **sets = malloc((size_t)(total + 1) * sizeof *sets);
  if (!sets) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  int nsets = 0;
  for (int j = 0; j < c->nsets; ++j) sets[nsets++] = c->sets[j];
  double proposed = s->base.dt_proposed > 0.0 ? s->base.dt_proposed : INFINITY;
  for (int k = 0; k < s->n && !st; ++k) {
    adem_stage *g = &s->s[k];
    for (int j = 0; j < g->nsets; ++j) sets[nsets++] = g->sets[j];
    adem_case *sc = NULL;
    adem_log_mute(1);
    st = load_string_flags(c->source, c->path, c->base_dir, sets, nsets,
                                     LOAD_STAGE, &sc, err);
    adem_log_mute(0);
    if (st) {
      st = stage_error(g, k, st, err);
      break;
    }
    st = check_same_world(c, sc, g, err);
    if (!st) st = stage_config_extract(&g->config, sc, err);
    /* a wall the stage moves or servos gets its CSV columns from the start */
    if (!st) adem_walls_note_settings(&c->world->walls, g->config.planes, g->config.meshes);
    adem_case_free(sc);
    if (st) break;
    double ratio = adem_world_dt(c->world) / g->config.dt_proposed;
    /* warned once: by the case itself, or by the first stage that proposes a smaller step */
    bool stricter = g->config.dt_proposed < proposed * (1.0 - 1e-12);
    if (g->config.dt_proposed > 0.0 && g->config.dt_proposed < proposed)
      proposed = g->config.dt_proposed;
    if (c->dt_auto && ratio > 1.0 && g->config.dt_proposed > 0.0) { /* the smallest of all */
      adem_world_set_dt(c->world, g->config.dt_proposed);
    } else if (stricter && ratio > 1.0 + 1e-12 && isfinite(ratio))
      adem_log(ADEM_LOG_WARN,
               "%s: stage `%s`: the time step %g s is %.2fx the step its materials propose (%g s)",
               g->where, g->name, adem_world_dt(c->world), ratio, g->config.dt_proposed);
  }
  free(sets);
  if (st) return st;
  warn_unused_law_params(NULL, c->path[0] ? c->path : c->name, &c->world->mat, s);
  warn_brof_turning(c->path[0] ? c->path : c->name, c->world, s);
  /* Durations: every stage but the last needs one; the last may run until time.end. */
  double t = 0.0;
  bool earlier = false; /* a stage before may end early (its `until`) */
  for (int k = 0; k < s->n; ++k) {
    adem_stage *g = &s->s[k];
    if (g->duration < 0.0 && k + 1 < s->n)
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "%s: stages[%d] (`%s`): duration: required value is missing (every "
                            "stage but the last needs one%s)",
                            g->where, k, g->name, g->until ? "; with `until` it is the most the "
                            "stage lasts" : "");
    /* the step it begins on, as adem_stages_start_step plans it, against the run's last step */
    double dt = adem_world_dt(c->world);
    if (k > 0 && !earlier && llround(t / dt) >= (long long)adem_schedule_total_steps(c->end_time, dt))
      adem_log(ADEM_LOG_WARN, "%s: stage `%s` begins at t = %g s, at or after time.end = %g s: it "
               "will not run (unless the run goes on to a later end: adem run --resume DIR --set "
               "time.end=T)", g->where, g->name, t, c->end_time);
    if (g->until) earlier = true;
    if (g->duration >= 0.0) t += g->duration;
  }
  const adem_stage *last = &s->s[s->n - 1];
  if (last->duration >= 0.0 && t < c->end_time * (1.0 - 1e-12))
    adem_log(ADEM_LOG_WARN, "%s: the stages end at t = %g s, before time.end = %g s: the last "
             "stage (`%s`) goes on until time.end", last->where, t, c->end_time, last->name);
  s->current = 0;
  return adem_stages_enter(c, 0, false, err);
}

adem_status adem_case_load_string(const char *text, const char *name_for_messages,
                                  const char *const *sets, int nsets, adem_case **out,
                                  adem_error *err) {
  return adem_case_load_string_at(text, name_for_messages, NULL, sets, nsets, out, err);
}

adem_status adem_case_load_string_at(const char *text, const char *name_for_messages,
                                     const char *base_dir, const char *const *sets, int nsets,
                                     adem_case **out, adem_error *err) {
  return load_string_flags(text, name_for_messages, base_dir, sets, nsets, 0, out, err);
}

static adem_status load_string_flags(const char *text, const char *name_for_messages,
                                        const char *base_dir, const char *const *sets, int nsets,
                                        unsigned flags, adem_case **out, adem_error *err) {
  if (out) *out = NULL;
  if (!text || !out || nsets < 0 || (nsets > 0 && !sets))
    return adem_error_set(err, ADEM_ERR_INPUT, "adem_case_load_string: no case text");
  adem_case *c = calloc(1, sizeof *c);
  if (!c) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory loading a case");
  snprintf(c->path, sizeof c->path, "%s", name_for_messages ? name_for_messages : "<case>");
  case_ctx ctx;
  memset(&ctx, 0, sizeof ctx);
  ctx.file = c->path;
  ctx.stem_of = name_for_messages ? c->path : "case";
  ctx.err = err;
  ctx.c = c;
  adem_status st = ADEM_OK;
  char *dir = base_dir ? copy_text(base_dir) : adem_file_dirname(name_for_messages ? c->path : ".");
  if (!dir) st = adem_yaml_nomem(&ctx);
  else if (!set_base_dir(c, dir))
    st = adem_error_set(err, ADEM_ERR_INPUT, "%s: cannot tell the case's folder (%s): %s", c->path,
                        dir, strerror(errno ? errno : ENAMETOOLONG));
  ctx.base_dir = dir;
  if (!st) c->source = copy_text(text);
  c->sets = calloc((size_t)(nsets > 0 ? nsets : 1), sizeof *c->sets);
  if (!st && (!c->source || !c->sets)) st = adem_yaml_nomem(&ctx);
  for (int k = 0; k < nsets && !st; ++k) {
    if (!sets[k]) {
      st = adem_error_set(err, ADEM_ERR_INPUT, "--set: missing key.path=value");
      break;
    }
    c->sets[k] = copy_text(sets[k]);
    if (!c->sets[k]) st = adem_yaml_nomem(&ctx);
    c->nsets = k + 1;
  }
  ctx.sets = (const char *const *)c->sets;
  if (!st) st = adem_yaml_load_yaml(text, strlen(text), &ctx.doc, c->path, false, err);
  if (!st) {
    ctx.have_doc = true;
    ctx.nbase = (int)(ctx.doc.nodes.top - ctx.doc.nodes.start);
    st = adem_yaml_apply_sets(&ctx, nsets);
  }
  if (!st) {
    c->world = adem_world_create();
    ctx.w = c->world;
    st = c->world ? build(&ctx) : adem_yaml_nomem(&ctx);
  }
  ctx_free(&ctx);
  free(dir);
  /* Stage configurations are whole loads of the case: not for a stage's own load. */
  if (!st && !(flags & LOAD_STAGE)) st = stages_prepare(c, err);
  if (st) {
    adem_case_free(c);
    return st;
  }
  *out = c;
  return ADEM_OK;
}

adem_status adem_case_load_file(const char *path, const char *const *sets, int nsets,
                                adem_case **out, adem_error *err) {
  if (out) *out = NULL;
  if (!path) return adem_error_set(err, ADEM_ERR_INPUT, "no case file given");
  FILE *f = fopen(path, "rb");
  if (!f) return adem_error_set(err, ADEM_ERR_INPUT, "%s: cannot open the case file: %s", path,
                                strerror(errno));
  size_t len = 0, cap = 4096;
  char *text = malloc(cap);
  while (text) {
    len += fread(text + len, 1, cap - 1 - len, f);
    if (len < cap - 1) break;
    char *t = realloc(text, 2 * cap);
    if (!t) {
      free(text);
      text = NULL;
      break;
    }
    text = t;
    cap *= 2;
  }
  int read_errno = errno;
  bool failed = ferror(f);
  fclose(f);
  if (!text) return adem_error_set(err, ADEM_ERR_NOMEM, "%s: out of memory reading the case", path);
  if (failed) {
    free(text);
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: cannot read the case file: %s", path,
                          strerror(read_errno));
  }
  text[len] = '\0';
  if (strlen(text) != len) {
    free(text);
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: the case file holds a NUL byte; is it text?",
                          path);
  }
  adem_status st = adem_case_load_string(text, path, sets, nsets, out, err);
  free(text);
  return st;
}

void adem_case_free(adem_case *c) {
  if (!c) return;
  adem_world_free(c->world);
  adem_pours_free(c->pours);
  adem_stages_free(c->stages);
  adem_regions_free(c->regions);
  adem_regions_free(c->fills);
  adem_outlets_free(c->outlets);
  free(c->until);
  free(c->source);
  if (c->sets)
    for (int k = 0; k < c->nsets; ++k) free(c->sets[k]);
  free(c->sets);
  free(c);
}

void adem_case_write_reference(FILE *f) { adem_schema_write_markdown(f); }
