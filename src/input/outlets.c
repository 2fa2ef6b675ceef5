/* Outlets that remove particles, and mass flows through planes and of regions (outlets.h). */
#include "outlets.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "case_yaml.h"
#include "insert.h"
#include "log.h"
#include "schedule.h"
#include "world_internal.h"

enum { OUTLET_DEFAULT_STEPS = 100 };

typedef struct adem_outlet {
  char name[ADEM_NAME_MAX];
  int region;      /* index in the case's output.regions, or -1 */
  int face;        /* 2 axis + (0: at min, 1: at max), or -1 */
  double interval; /* s; 0: OUTLET_DEFAULT_STEPS steps */
  uint64_t count;  /* removed since the start */
  double mass;     /* kg, summed in the order of removal (each check's particles by id) */
} adem_outlet;

typedef struct adem_flow {
  char name[ADEM_NAME_MAX];
  int region; /* index in output.regions, or -1: a plane */
  int plane;  /* index among the planes (side bytes), or -1 */
  adem_vec3 point, normal;
  double window;  /* s; 0: the last CSV interval */
  double through; /* plane: mass crossed along the normal since the start, kg */
  double *t, *q;  /* the CSV rows the window needs: time and through mass / region mass */
  size_t n, cap;
} adem_flow;

struct adem_outlets {
  adem_outlet *o;
  int no;
  adem_flow *f;
  int nf, nplanes;
  /* side of each particle id of each plane at the last look: side[id * nplanes + k], 0 not
   * seen yet, 1 behind the plane, 2 in front of (or on) it */
  uint8_t *side;
  uint64_t nside; /* ids covered */
};

void adem_outlets_free(adem_outlets *o) {
  if (!o) return;
  for (int k = 0; k < o->nf; ++k) {
    free(o->f[k].t);
    free(o->f[k].q);
  }
  free(o->o);
  free(o->f);
  free(o->side);
  free(o);
}

/* ---------------------------------------------------------------- reading */

static int find_region(const adem_case *c, const char *name) {
  for (int k = 0; c->regions && k < c->regions->n; ++k)
    if (!strcmp(c->regions->r[k].name, name)) return k;
  return -1;
}

/* A name not already taken by a region, an outlet or a flow (they share the CSV's columns). */
static adem_status check_name(case_ctx *ctx, const adem_outlets *o, const char *name,
                              yaml_node_t *node, const char *path) {
  bool taken = find_region(ctx->c, name) >= 0;
  for (int k = 0; o && k < o->no; ++k) taken |= !strcmp(o->o[k].name, name);
  for (int k = 0; o && k < o->nf; ++k) taken |= !strcmp(o->f[k].name, name);
  if (taken)
    return adem_yaml_fail(ctx, node, path,
                          "duplicate name `%s`: regions, outlets and mass flows each need their "
                          "own (they name CSV columns)",
                          name);
  return ADEM_OK;
}

static adem_status region_ref(case_ctx *ctx, const map_cursor *m, char *rname, int *region,
                              yaml_node_t **rnode) {
  adem_status st = adem_yaml_get_string(ctx, m, "region", rname, ADEM_NAME_MAX, rnode);
  *region = -1;
  if (st || !*rnode) return st;
  *region = find_region(ctx->c, rname);
  if (*region >= 0) return ADEM_OK;
  char path[KEY_PATH_MAX], known[512] = "";
  for (int k = 0; ctx->c->regions && k < ctx->c->regions->n; ++k)
    adem_yaml_list_append(known, sizeof known, ctx->c->regions->r[k].name);
  adem_yaml_join(path, sizeof path, m->path, "region");
  return adem_yaml_fail(ctx, *rnode, path, "no region named `%s` in output.regions (%s)", rname,
                        known[0] ? known : "there are none: define it there");
}

static adem_status read_flows(case_ctx *ctx, adem_outlets *o, const map_cursor *out) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, out, "mass_flow", &l);
  if (st || l.n == 0) return st;
  o->f = calloc(l.n, sizeof *o->f);
  if (!o->f) return adem_yaml_nomem(ctx);
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    char path[KEY_PATH_MAX], rname[ADEM_NAME_MAX];
    yaml_node_t *name_node, *rnode, *pnode, *nnode;
    adem_flow *f = &o->f[o->nf];
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) return st;
    if ((st = adem_yaml_get_string(ctx, &m, "name", f->name, sizeof f->name, &name_node))) return st;
    adem_yaml_join(path, sizeof path, m.path, "name");
    if ((st = check_name(ctx, o, f->name, name_node, path))) return st;
    if ((st = region_ref(ctx, &m, rname, &f->region, &rnode))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &m, "point", &f->point, &pnode))) return st;
    if ((st = adem_yaml_get_vec3(ctx, &m, "normal", &f->normal, &nnode))) return st;
    if ((st = adem_yaml_get_number(ctx, &m, "window", &f->window, NULL))) return st;
    if (rnode && (pnode || nnode)) {
      adem_yaml_join(path, sizeof path, m.path, pnode ? "point" : "normal");
      return adem_yaml_fail(ctx, pnode ? pnode : nnode, path,
                            "give either `region` (its mass's rate of change) or `point` and "
                            "`normal` (a plane), not both");
    }
    if (!rnode && !(pnode && nnode)) {
      const char *key = !pnode && !nnode ? "region" : !pnode ? "point"
                                                             : "normal";
      adem_yaml_join(path, sizeof path, m.path, key);
      return adem_yaml_missing(ctx, &m, adem_schema_find("output.mass_flow[]", key, NULL), path);
    }
    f->plane = -1;
    if (!rnode) {
      double len = v3_norm(f->normal);
      if (!(len > 0.0)) {
        adem_yaml_join(path, sizeof path, m.path, "normal");
        return adem_yaml_fail(ctx, nnode, path, "the normal is zero: give a direction");
      }
      f->normal = v3_scale(f->normal, 1.0 / len);
      f->plane = o->nplanes++;
    }
    o->nf++;
  }
  return ADEM_OK;
}

static const char *const FACES[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};

static adem_status read_outlet_list(case_ctx *ctx, adem_outlets *o, const map_cursor *root) {
  list_cursor l;
  adem_status st = adem_yaml_get_list(ctx, root, "outlets", &l);
  if (st || l.n == 0) return st;
  o->o = calloc(l.n, sizeof *o->o);
  if (!o->o) return adem_yaml_nomem(ctx);
  adem_world *w = ctx->w;
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    char path[KEY_PATH_MAX], rname[ADEM_NAME_MAX];
    yaml_node_t *name_node, *rnode, *inode;
    adem_outlet *t = &o->o[o->no];
    if ((st = adem_yaml_list_item(ctx, &l, i, &m))) return st;
    if ((st = adem_yaml_get_string(ctx, &m, "name", t->name, sizeof t->name, &name_node))) return st;
    adem_yaml_join(path, sizeof path, m.path, "name");
    if ((st = check_name(ctx, o, t->name, name_node, path))) return st;
    if ((st = region_ref(ctx, &m, rname, &t->region, &rnode))) return st;
    if ((st = adem_yaml_get_enum(ctx, &m, "face", &t->face))) return st;
    if ((st = adem_yaml_get_number(ctx, &m, "interval", &t->interval, &inode))) return st;
    if (!inode) t->interval = 0.0;
    yaml_node_t *fnode = adem_yaml_map_get(ctx, m.node, "face");
    if (rnode && t->face >= 0) {
      adem_yaml_join(path, sizeof path, m.path, "face");
      return adem_yaml_fail(ctx, fnode, path, "give either `region` or `face`, not both (make two outlets)");
    }
    if (!rnode && t->face < 0) {
      adem_yaml_join(path, sizeof path, m.path, "region");
      return adem_yaml_missing(ctx, &m, adem_schema_find("outlets[]", "region", NULL), path);
    }
    if (t->face >= 0) {
      adem_yaml_join(path, sizeof path, m.path, "face");
      yaml_node_t *dom = adem_yaml_map_get(ctx, root->node, "domain");
      if (!dom)
        return adem_yaml_fail(ctx, fnode, path,
                              "an outlet face is a face of the domain box: give `domain` (min, "
                              "max) too");
      int axis = t->face / 2;
      if ((w->periodic.axes >> axis) & 1u)
        return adem_yaml_fail(ctx, fnode, path,
                              "%s is a face of a periodic axis (domain.periodic): particles that "
                              "cross it come back through the other face",
                              FACES[t->face]);
      w->open_faces |= 1u << t->face;
    }
    o->no++;
  }
  return ADEM_OK;
}

adem_status adem_outlets_read(case_ctx *ctx, const map_cursor *root, const map_cursor *out) {
  adem_outlets *o = calloc(1, sizeof *o);
  if (!o) return adem_yaml_nomem(ctx);
  adem_status st = read_flows(ctx, o, out);
  if (!st) st = read_outlet_list(ctx, o, root);
  if (st || (o->no == 0 && o->nf == 0)) {
    adem_outlets_free(o);
    return st;
  }
  ctx->c->outlets = o;
  return ADEM_OK;
}

/* ---------------------------------------------------------------- running */

static uint64_t period_of(const adem_outlet *t, double dt) {
  if (!(t->interval > 0.0)) return OUTLET_DEFAULT_STEPS;
  uint64_t k = adem_schedule_period(t->interval, dt);
  return k > 0 ? k : 1;
}

uint64_t adem_outlets_next_step(const adem_outlets *o, double dt, uint64_t step) {
  uint64_t next = UINT64_MAX;
  for (int k = 0; o && k < o->no; ++k) {
    uint64_t p = period_of(&o->o[k], dt), e = (step / p + 1) * p;
    if (e < next) next = e;
  }
  return next;
}

/* Brings the planes' through masses up to date: each particle (by id) whose side changed since
 * it was last seen adds its mass, + along the normal. */
static adem_status update_planes(adem_outlets *o, const adem_world *w) {
  if (o->nplanes == 0) return ADEM_OK;
  const adem_particles *p = &w->p;
  if (w->next_id > o->nside) {
    size_t bytes = (size_t)w->next_id * (size_t)o->nplanes;
    uint8_t *s = realloc(o->side, bytes + 1);
    if (!s) return ADEM_ERR_NOMEM;
    memset(s + o->nside * (size_t)o->nplanes, 0, bytes - (size_t)o->nside * (size_t)o->nplanes);
    o->side = s;
    o->nside = w->next_id;
  }
  uint32_t *order = adem_world_id_order(w);
  if (!order) return ADEM_ERR_NOMEM;
  for (int k = 0; k < o->nf; ++k) {
    adem_flow *f = &o->f[k];
    if (f->plane < 0) continue;
    for (size_t r = 0; r < p->n; ++r) {
      size_t i = order[r];
      if (p->id[i] >= o->nside) continue; /* cannot happen: ids are below next_id */
      uint8_t now = v3_dot(v3_sub(p->pos[i], f->point), f->normal) >= 0.0 ? 2 : 1;
      uint8_t *was = &o->side[p->id[i] * (uint64_t)o->nplanes + (uint64_t)f->plane];
      if (*was && *was != now) f->through += (now == 2 ? 1.0 : -1.0) / p->inv_mass[i];
      *was = now;
    }
  }
  free(order);
  return ADEM_OK;
}

static bool removes(const adem_outlet *t, const adem_case *c, const adem_world *w, adem_vec3 x) {
  if (t->region >= 0) return adem_insert_region_contains(&c->regions->r[t->region].region, x);
  const double v[3] = {x.x, x.y, x.z};
  const double lo[3] = {w->domain_lo.x, w->domain_lo.y, w->domain_lo.z};
  const double hi[3] = {w->domain_hi.x, w->domain_hi.y, w->domain_hi.z};
  int d = t->face / 2;
  return t->face % 2 ? v[d] > hi[d] : v[d] < lo[d];
}

adem_status adem_outlets_run(adem_case *c, adem_error *err) {
  adem_outlets *o = c->outlets;
  adem_world *w = c->world;
  if (!o || o->no == 0 || w->step == 0 || !w->prepared) return ADEM_OK;
  bool any = false;
  for (int k = 0; k < o->no; ++k) any |= w->step % period_of(&o->o[k], w->dt) == 0;
  if (!any) return ADEM_OK;
  /* the crossings of the particles about to go are counted first */
  if (update_planes(o, w)) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  size_t n = w->p.n;
  uint8_t *gone = calloc(n + 1, 1);
  uint32_t *order = adem_world_id_order(w);
  if (!gone || !order) {
    free(gone);
    free(order);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  /* each particle goes to the first outlet due that holds it; counts and masses by id */
  for (int k = 0; k < o->no; ++k) {
    adem_outlet *t = &o->o[k];
    if (w->step % period_of(t, w->dt) != 0) continue;
    for (size_t r = 0; r < n; ++r) {
      size_t i = order[r];
      if (gone[i] || w->p.frozen[i] || !removes(t, c, w, w->p.pos[i])) continue; /* a wall's */
      gone[i] = 1;
      t->count++;
      t->mass += 1.0 / w->p.inv_mass[i];
    }
  }
  free(order);
  adem_status st = adem_world_remove_particles(w, gone, NULL, err);
  free(gone);
  return st;
}

/* ---------------------------------------------------------------- CSV */

int adem_outlets_columns(const adem_outlets *o) {
  if (!o) return 0;
  int n = 2 * o->no;
  for (int k = 0; k < o->nf; ++k) n += o->f[k].region < 0 ? 2 : 1;
  return n;
}

void adem_outlets_column_name(const adem_outlets *o, int k, char *buf, size_t n) {
  if (k < 2 * o->no) {
    snprintf(buf, n, "%s_%s", o->o[k / 2].name, k % 2 ? "deleted_mass_kg" : "deleted_count");
    return;
  }
  k -= 2 * o->no;
  for (int j = 0; j < o->nf; ++j) {
    const adem_flow *f = &o->f[j];
    int cols = f->region < 0 ? 2 : 1;
    if (k < cols) {
      snprintf(buf, n, "%s_%s", f->name, cols == 2 && k == 0 ? "through_kg" : "flow_kg_s");
      return;
    }
    k -= cols;
  }
  snprintf(buf, n, "unknown");
}

/* Adds the row (t, q) to the flow's window and returns the rate over it (NaN at the first). */
static adem_status flow_rate(adem_flow *f, double t, double q, double *rate) {
  /* rows older than the one at least `window` before t are not needed any more */
  size_t drop = 0;
  while (drop + 1 < f->n && t - f->t[drop + 1] >= f->window && f->window > 0.0) drop++;
  if (f->window <= 0.0 && f->n > 1) drop = f->n - 1;
  if (drop) {
    memmove(f->t, f->t + drop, (f->n - drop) * sizeof *f->t);
    memmove(f->q, f->q + drop, (f->n - drop) * sizeof *f->q);
    f->n -= drop;
  }
  *rate = f->n > 0 && t > f->t[0] ? (q - f->q[0]) / (t - f->t[0]) : NAN;
  if (f->n == f->cap) {
    size_t cap = 2 * f->cap + 4;
    double *a = realloc(f->t, cap * sizeof *a);
    if (!a) return ADEM_ERR_NOMEM;
    f->t = a;
    double *b = realloc(f->q, cap * sizeof *b);
    if (!b) return ADEM_ERR_NOMEM;
    f->q = b;
    f->cap = cap;
  }
  f->t[f->n] = t;
  f->q[f->n] = q;
  f->n++;
  return ADEM_OK;
}

adem_status adem_outlets_sample(adem_case *c, double *values, adem_error *err) {
  adem_outlets *o = c->outlets;
  if (!o) return ADEM_OK;
  const adem_world *w = c->world;
  int v = 0;
  for (int k = 0; k < o->no; ++k) {
    values[v++] = (double)o->o[k].count;
    values[v++] = o->o[k].mass;
  }
  if (o->nf == 0) return ADEM_OK;
  int nr = c->regions ? c->regions->n : 0;
  double *count = calloc((size_t)nr + 1, sizeof *count), *mass = calloc((size_t)nr + 1, sizeof *mass);
  adem_status st = count && mass ? update_planes(o, w) : ADEM_ERR_NOMEM;
  if (!st && nr > 0) adem_regions_count(c->regions, w, count, mass);
  for (int k = 0; k < o->nf && !st; ++k) {
    adem_flow *f = &o->f[k];
    double q = f->region >= 0 ? mass[f->region] : f->through, rate = NAN;
    if (f->region < 0) values[v++] = f->through;
    st = flow_rate(f, w->time, q, &rate);
    values[v++] = rate;
  }
  free(count);
  free(mass);
  if (st) return adem_error_set(err, st, "out of memory");
  return ADEM_OK;
}

void adem_outlets_log(const adem_case *c) {
  const adem_outlets *o = c->outlets;
  for (int k = 0; o && k < o->no; ++k)
    adem_log(ADEM_LOG_INFO, "outlet '%s' removed %llu particles, %.6g kg, by t = %.9g s",
             o->o[k].name, (unsigned long long)o->o[k].count, o->o[k].mass, c->world->time);
}

/* ---------------------------------------------------------------- checkpoints */

void adem_outlets_save(adem_writer *wr, const adem_outlets *o) {
  adem_put_u32(wr, o ? (uint32_t)o->no : 0u);
  adem_put_u32(wr, o ? (uint32_t)o->nf : 0u);
  if (!o) return;
  for (int k = 0; k < o->no; ++k) {
    adem_put_u64(wr, o->o[k].count);
    adem_put_f64(wr, o->o[k].mass);
  }
  for (int k = 0; k < o->nf; ++k) {
    const adem_flow *f = &o->f[k];
    adem_put_f64(wr, f->through);
    adem_put_array(wr, f->t, f->n, sizeof *f->t);
    adem_put_array(wr, f->q, f->n, sizeof *f->q);
  }
  adem_put_u64(wr, o->nside);
  adem_put_array(wr, o->side, (size_t)o->nside * (size_t)o->nplanes, 1);
}

adem_status adem_outlets_load(adem_reader *rd, adem_outlets *o, adem_error *err) {
  uint32_t no = adem_get_u32(rd), nf = adem_get_u32(rd);
  if (rd->failed || no != (uint32_t)(o ? o->no : 0) || nf != (uint32_t)(o ? o->nf : 0))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "its outlets and mass flows do not match those of its own case text");
  if (!o) return ADEM_OK;
  for (int k = 0; k < o->no; ++k) {
    o->o[k].count = adem_get_u64(rd);
    o->o[k].mass = adem_get_f64(rd);
  }
  for (int k = 0; k < o->nf && !rd->failed; ++k) {
    adem_flow *f = &o->f[k];
    f->through = adem_get_f64(rd);
    for (int a = 0; a < 2; ++a) {
      uint64_t n = adem_get_count(rd, sizeof(double));
      if (rd->failed) break;
      double **dst = a == 0 ? &f->t : &f->q;
      double *b = realloc(*dst, ((size_t)n + 1) * sizeof *b);
      if (!b) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      *dst = b;
      adem_get(rd, b, (size_t)n * sizeof *b);
      f->n = (size_t)n;
      f->cap = (size_t)n + 1;
    }
  }
  uint64_t ns = adem_get_u64(rd);
  uint64_t bytes = adem_get_count(rd, 1);
  if (rd->failed || bytes != ns * (uint64_t)o->nplanes)
    return adem_error_set(err, ADEM_ERR_INPUT, "its contents are cut short or damaged");
  free(o->side);
  o->side = malloc((size_t)bytes + 1);
  if (!o->side) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_get(rd, o->side, (size_t)bytes);
  o->nside = ns;
  if (rd->failed) return adem_error_set(err, ADEM_ERR_INPUT, "its contents are cut short or damaged");
  return ADEM_OK;
}
