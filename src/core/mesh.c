#include "mesh.h"

#include <errno.h>
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dmath.h"
#include "log.h"
#include "adem/vec3.h"

_Static_assert(sizeof(adem_vec3) == 3 * sizeof(double), "adem_vec3 must be three packed doubles");

/* ---------------------------------------------------------------- transform */

adem_mesh_transform adem_default_mesh_transform(void) {
  adem_mesh_transform tf;
  memset(&tf, 0, sizeof tf);
  tf.scale = 1.0;
  for (int i = 0; i < 3; ++i) tf.rotation[i][i] = 1.0;
  return tf;
}

/* cos and sin of an angle in degrees, exact at multiples of 90 (cos(pi/2) is 6e-17 otherwise). */
static void cos_sin_deg(double deg, double *c, double *s) {
  double q = deg / 90.0;
  if (q == floor(q) && fabs(q) < 1e15) {
    long k = (long)fmod(q, 4.0);
    if (k < 0) k += 4;
    static const double cs[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    *c = cs[k][0];
    *s = cs[k][1];
    return;
  }
  double r = deg * (ADEM_PI / 180.0);
  *c = adem_dmath_cos(r);
  *s = adem_dmath_sin(r);
}

adem_status adem_mesh_transform_rotate(adem_mesh_transform *tf, adem_vec3 axis, double angle_deg,
                                       adem_error *err) {
  double len = v3_norm(axis);
  if (!isfinite(len) || len == 0.0 || !isfinite(angle_deg))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "mesh rotation needs a finite axis of non-zero length and a finite angle");
  /* A coordinate axis stays exact: dividing (0, 0, 5) by 5 gives (0, 0, 1) exactly. */
  double k[3] = {axis.x / len, axis.y / len, axis.z / len};
  double c, s;
  cos_sin_deg(angle_deg, &c, &s);
  /* Rodrigues: R = c I + s [k]x + (1 - c) k k^T */
  double r[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = (1.0 - c) * k[i] * k[j] + (i == j ? c : 0.0);
  r[0][1] -= s * k[2];
  r[0][2] += s * k[1];
  r[1][0] += s * k[2];
  r[1][2] -= s * k[0];
  r[2][0] -= s * k[1];
  r[2][1] += s * k[0];
  double out[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      out[i][j] = r[i][0] * tf->rotation[0][j] + r[i][1] * tf->rotation[1][j] +
                  r[i][2] * tf->rotation[2][j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) tf->rotation[i][j] = out[i][j];
  return ADEM_OK;
}

adem_status adem_mesh_check_transform(const adem_mesh_transform *tf, const char *path,
                                      adem_error *err) {
  if (!(tf->scale > 0.0) || !isfinite(tf->scale))
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: mesh scale must be finite and > 0, not %g",
                          path, tf->scale);
  if (!v3_isfinite(tf->translation))
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: mesh translation must be finite", path);
  if (tf->material < 0)
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: mesh material index %d is negative", path,
                          tf->material);
  const double(*R)[3] = tf->rotation;
  /* A mirror would turn the winding inside out; a non-orthonormal matrix would shear. */
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double d = R[0][i] * R[0][j] + R[1][i] * R[1][j] + R[2][i] * R[2][j];
      if (!(fabs(d - (i == j ? 1.0 : 0.0)) <= 1e-9))
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "%s: mesh rotation matrix is not orthonormal (column %d . column %d = %g)",
                              path, i, j, d);
    }
  double det = R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1]) -
               R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0]) +
               R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]);
  if (!(det > 0.0))
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: mesh rotation matrix has determinant %g: a mirror is not a rotation",
                          path, det);
  return ADEM_OK;
}

static adem_vec3 rotate(const double R[3][3], adem_vec3 x) {
  return v3(R[0][0] * x.x + R[0][1] * x.y + R[0][2] * x.z,
            R[1][0] * x.x + R[1][1] * x.y + R[1][2] * x.z,
            R[2][0] * x.x + R[2][1] * x.y + R[2][2] * x.z);
}

/* ---------------------------------------------------------------- triangle adem_mesh_soup */


void adem_mesh_soup_free(adem_mesh_soup *s) {
  free(s->corner);
  free(s->normal);
  free(s->where);
  free(s->blocks);
  memset(s, 0, sizeof *s);
}

int adem_mesh_soup_push(adem_mesh_soup *s, const adem_vec3 c[3], adem_vec3 normal, size_t where) {
  if (s->n == s->cap) {
    size_t cap = s->cap ? 2 * s->cap : 256;
    adem_vec3 *c2 = realloc(s->corner, 3 * cap * sizeof *c2);
    if (c2) s->corner = c2;
    adem_vec3 *n2 = realloc(s->normal, cap * sizeof *n2);
    if (n2) s->normal = n2;
    size_t *w2 = realloc(s->where, cap * sizeof *w2);
    if (w2) s->where = w2;
    if (!c2 || !n2 || !w2) return 0;
    s->cap = cap;
  }
  memcpy(&s->corner[3 * s->n], c, 3 * sizeof *c);
  s->normal[s->n] = normal;
  s->where[s->n] = where;
  s->n++;
  return 1;
}

adem_mesh_soup_block *adem_mesh_soup_block_open(adem_mesh_soup *s, const char *name, size_t line) {
  if (s->nblocks == s->block_cap) {
    size_t cap = s->block_cap ? 2 * s->block_cap : 4;
    adem_mesh_soup_block *b = realloc(s->blocks, cap * sizeof *b);
    if (!b) return NULL;
    s->blocks = b;
    s->block_cap = cap;
  }
  adem_mesh_soup_block *b = &s->blocks[s->nblocks++];
  memset(b, 0, sizeof *b);
  snprintf(b->name, sizeof b->name, "%s", name);
  b->line = line;
  b->first = s->n;
  return b;
}

static adem_status oom(adem_error *err, const char *path) {
  return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory reading %s", path);
}

/* ---------------------------------------------------------------- building the mesh */


typedef struct corner_key {
  double x, y, z;
  size_t seq; /* old vertices first (their index), then the new corners */
} corner_key;

static int compare_corner(const void *pa, const void *pb) {
  const corner_key *a = pa, *b = pb;
  if (a->x != b->x) return a->x < b->x ? -1 : 1;
  if (a->y != b->y) return a->y < b->y ? -1 : 1;
  if (a->z != b->z) return a->z < b->z ? -1 : 1;
  return a->seq < b->seq ? -1 : a->seq > b->seq;
}

typedef struct edge_rec {
  uint32_t lo, hi, t, k;
} edge_rec;

static int compare_edge(const void *pa, const void *pb) {
  const edge_rec *a = pa, *b = pb;
  if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
  if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
  if (a->t != b->t) return a->t < b->t ? -1 : 1;
  return a->k < b->k ? -1 : a->k > b->k;
}

static uint32_t uf_find(uint32_t *parent, uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

/* Kind of edge k of triangle t towards the neighbour whose far vertex is w, seen from t's normal
 * side: w's height above t's plane (y) against its distance beyond the edge (x). */
static adem_mesh_edge_kind classify_edge(const adem_mesh *m, uint32_t t, int k, uint32_t w,
                                         double tan_flat, int *flat_decided) {
  adem_vec3 a = m->vert[m->tri[t][k]], b = m->vert[m->tri[t][(k + 1) % 3]];
  adem_vec3 n = m->normal[t];
  adem_vec3 inward = v3_cross(n, v3_sub(b, a)); /* into t: the interior is left of a->b */
  double len = v3_norm(inward);
  adem_vec3 d = v3_sub(m->vert[w], a);
  double x = v3_dot(d, inward) / len, y = v3_dot(d, n);
  if (flat_decided) *flat_decided = x < 0.0 && fabs(y) <= tan_flat * -x;
  if (y < 0.0) return ADEM_MESH_EDGE_CONVEX;
  return ADEM_MESH_EDGE_CONCAVE; /* y == 0 with x >= 0 is a fin folded onto t: not flat */
}

static uint32_t far_vertex(const adem_mesh *m, uint32_t u, uint32_t va, uint32_t vb) {
  for (int j = 0; j < 3; ++j)
    if (m->tri[u][j] != va && m->tri[u][j] != vb) return m->tri[u][j];
  return m->tri[u][0];
}

/* Vertex-triangle incidence, edge adjacency and kinds, flat regions and flat vertices, all from
 * vert and tri. Replaces the topology arrays of m; returns 0 when out of memory. */
static int build_topology(adem_mesh *m, size_t *nonmanifold) {
  size_t nv = m->nverts, nt = m->ntris;
  size_t *vt_start = calloc(nv + 1, sizeof *vt_start);
  uint32_t *vt_tri = malloc((3 * nt + 1) * sizeof *vt_tri);
  int32_t(*adj)[3] = malloc((nt + 1) * sizeof *adj);
  uint8_t(*kind)[3] = malloc((nt + 1) * sizeof *kind);
  uint32_t(*edge_id)[3] = malloc((nt + 1) * sizeof *edge_id);
  uint32_t *region = malloc((nt + 1) * sizeof *region);
  uint8_t *vert_flat = malloc(nv + 1);
  edge_rec *e = malloc((3 * nt + 1) * sizeof *e);
  int ok = vt_start && vt_tri && adj && kind && edge_id && region && vert_flat && e;
  if (!ok) goto fail;

  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) vt_start[m->tri[t][k] + 1]++;
  for (size_t v = 0; v < nv; ++v) vt_start[v + 1] += vt_start[v];
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) vt_tri[vt_start[m->tri[t][k]]++] = (uint32_t)t;
  for (size_t v = nv; v > 0; --v) vt_start[v] = vt_start[v - 1];
  vt_start[0] = 0;

  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = m->tri[t][k], b = m->tri[t][(k + 1) % 3];
      e[3 * t + (size_t)k] = (edge_rec){a < b ? a : b, a < b ? b : a, (uint32_t)t, (uint32_t)k};
    }
  qsort(e, 3 * nt, sizeof *e, compare_edge);

  double flat = m->flat_angle > 0.0 ? m->flat_angle : ADEM_MESH_FLAT_ANGLE;
  double tan_flat = adem_dmath_tan(flat);
  size_t nedges = 0, nonman = 0;
  for (size_t i = 0; i < 3 * nt;) {
    size_t j = i + 1;
    while (j < 3 * nt && e[j].lo == e[i].lo && e[j].hi == e[i].hi) ++j;
    for (size_t r = i; r < j; ++r) {
      edge_id[e[r].t][e[r].k] = (uint32_t)nedges;
      adj[e[r].t][e[r].k] = -1;
      kind[e[r].t][e[r].k] = j - i == 1 ? ADEM_MESH_EDGE_BORDER : ADEM_MESH_EDGE_NONMANIFOLD;
    }
    if (j - i == 2) {
      uint32_t t = e[i].t, u = e[i + 1].t;
      int kt = (int)e[i].k, ku = (int)e[i + 1].k;
      adj[t][kt] = (int32_t)u;
      adj[u][ku] = (int32_t)t;
      /* Flatness is decided once, from the lower triangle, so both sides agree. */
      int is_flat = 0;
      adem_mesh_edge_kind ct = classify_edge(m, t, kt, far_vertex(m, u, e[i].lo, e[i].hi),
                                             tan_flat, &is_flat);
      adem_mesh_edge_kind cu = classify_edge(m, u, ku, far_vertex(m, t, e[i].lo, e[i].hi),
                                             tan_flat, NULL);
      kind[t][kt] = (uint8_t)(is_flat ? ADEM_MESH_EDGE_FLAT : ct);
      kind[u][ku] = (uint8_t)(is_flat ? ADEM_MESH_EDGE_FLAT : cu);
    } else if (j - i > 2) {
      nonman++;
    }
    nedges++;
    i = j;
  }

  /* Flat regions: union of triangles across flat edges, rooted at the smallest index. */
  for (size_t t = 0; t < nt; ++t) region[t] = (uint32_t)t;
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      if (kind[t][k] != ADEM_MESH_EDGE_FLAT) continue;
      uint32_t a = uf_find(region, (uint32_t)t), b = uf_find(region, (uint32_t)adj[t][k]);
      if (a < b) region[b] = a;
      else if (b < a) region[a] = b;
    }
  for (size_t t = 0; t < nt; ++t) region[t] = uf_find(region, (uint32_t)t);

  memset(vert_flat, 1, nv + 1);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if (kind[t][k] != ADEM_MESH_EDGE_FLAT) {
        vert_flat[m->tri[t][k]] = 0;
        vert_flat[m->tri[t][(k + 1) % 3]] = 0;
      }

  free(e);
  free(m->vt_start);
  free(m->vt_tri);
  free(m->adj);
  free(m->edge_kind);
  free(m->edge_id);
  free(m->region);
  free(m->vert_flat);
  m->vt_start = vt_start;
  m->vt_tri = vt_tri;
  m->adj = adj;
  m->edge_kind = kind;
  m->edge_id = edge_id;
  m->region = region;
  m->vert_flat = vert_flat;
  m->nedges = nedges;
  *nonmanifold = nonman;
  return 1;
fail:
  free(vt_start);
  free(vt_tri);
  free(adj);
  free(kind);
  free(edge_id);
  free(region);
  free(vert_flat);
  free(e);
  return 0;
}

static void mesh_free_arrays(adem_mesh *m) {
  free(m->vert);
  free(m->vert_flat);
  free(m->vt_start);
  free(m->vt_tri);
  free(m->tri);
  free(m->normal);
  free(m->area);
  free(m->group);
  free(m->region);
  free(m->adj);
  free(m->edge_kind);
  free(m->edge_id);
  free(m->groups);
}

void adem_mesh_free(adem_mesh *mesh) {
  if (!mesh) return;
  mesh_free_arrays(mesh);
  memset(mesh, 0, sizeof *mesh);
}

int adem_mesh_find_group(const adem_mesh *mesh, const char *name) {
  for (int g = 0; g < mesh->ngroups; ++g)
    if (strcmp(mesh->groups[g].name, name) == 0) return g;
  return -1;
}

/* Appends the soup's blocks as groups. Builds a new mesh beside the old one and swaps it in, so
 * that a failure leaves mesh untouched. Messages name the facet's line (ascii) or the triangle. */
adem_status adem_mesh_append_soup(adem_mesh *mesh, const adem_mesh_soup *s, const adem_mesh_transform *tf,
                                  const char *path, int ascii, adem_error *err) {
  size_t nold_v = mesh->nverts, nold_t = mesh->ntris, n = s->n;
  if (nold_t + n >= INT32_MAX || nold_v + 3 * n >= UINT32_MAX)
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: too many triangles for 32-bit indices", path);

  /* Transformed corners, checked: a huge scale could overflow. */
  adem_vec3 *x = malloc((3 * n + 1) * sizeof *x);
  corner_key *keys = malloc((nold_v + 3 * n + 1) * sizeof *keys);
  size_t *rep = malloc((nold_v + 3 * n + 1) * sizeof *rep);
  uint32_t *id = malloc((nold_v + 3 * n + 1) * sizeof *id);
  unsigned char *keep = malloc(n + 1);
  adem_mesh nm;
  memset(&nm, 0, sizeof nm);
  adem_status st = ADEM_OK;
  if (!x || !keys || !rep || !id || !keep) goto nomem;

  for (size_t c = 0; c < 3 * n; ++c) {
    x[c] = v3_add(rotate(tf->rotation, v3_scale(s->corner[c], tf->scale)), tf->translation);
    if (!v3_isfinite(x[c])) {
      if (ascii)
        st = adem_error_set(err, ADEM_ERR_INPUT,
                            "%s:%zu: a vertex is not finite after the transform (scale %g)", path,
                            s->where[c / 3], tf->scale);
      else
        st = adem_error_set(err, ADEM_ERR_INPUT,
                            "%s: triangle %zu (byte offset %zu): a vertex is not finite after the transform (scale %g)",
                            path, s->where[c / 3], 84 + 50 * s->where[c / 3], tf->scale);
      goto done;
    }
  }

  /* Exactly equal points become one vertex; an equal old vertex keeps its index. Vertices of
   * own_vertices groups are joined by nobody else, and such a group joins nobody. */
  unsigned char *excluded = calloc(nold_v + 1, 1);
  if (!excluded) goto nomem;
  for (int g = 0; g < mesh->ngroups; ++g) {
    const adem_mesh_group *gr = &mesh->groups[g];
    if (!gr->own_vertices) continue;
    for (uint32_t v = gr->vert_first; v < gr->vert_first + gr->vert_count; ++v) excluded[v] = 1;
  }
  for (size_t v = 0; v < nold_v; ++v)
    keys[v] = (corner_key){mesh->vert[v].x, mesh->vert[v].y, mesh->vert[v].z, v};
  for (size_t c = 0; c < 3 * n; ++c) keys[nold_v + c] = (corner_key){x[c].x, x[c].y, x[c].z, nold_v + c};
  qsort(keys, nold_v + 3 * n, sizeof *keys, compare_corner);
  for (size_t i = 0; i < nold_v + 3 * n;) {
    size_t j = i + 1;
    while (j < nold_v + 3 * n && keys[j].x == keys[i].x && keys[j].y == keys[i].y &&
           keys[j].z == keys[i].z)
      ++j;
    /* runs are sorted by seq: old vertices first, then the new corners */
    size_t shared = SIZE_MAX, first_new = SIZE_MAX;
    for (size_t r = i; r < j; ++r) {
      size_t q = keys[r].seq;
      if (q < nold_v && !excluded[q] && !tf->own_vertices && shared == SIZE_MAX) shared = q;
      if (q >= nold_v && first_new == SIZE_MAX) first_new = q;
    }
    for (size_t r = i; r < j; ++r) {
      size_t q = keys[r].seq;
      rep[q] = q < nold_v ? q : shared != SIZE_MAX ? shared
                                                   : first_new;
    }
    i = j;
  }
  free(excluded);

  /* Degenerate: a repeated vertex, or an area at the rounding level of its longest edge. */
  size_t kept = 0, dropped = 0, disagreed = 0;
  for (size_t t = 0; t < n; ++t) {
    size_t r0 = rep[nold_v + 3 * t], r1 = rep[nold_v + 3 * t + 1], r2 = rep[nold_v + 3 * t + 2];
    adem_vec3 a = x[3 * t], b = x[3 * t + 1], c = x[3 * t + 2];
    double cr = v3_norm(v3_cross(v3_sub(b, a), v3_sub(c, a)));
    double l2 = fmax(v3_norm2(v3_sub(b, a)), fmax(v3_norm2(v3_sub(c, b)), v3_norm2(v3_sub(a, c))));
    keep[t] = !(r0 == r1 || r1 == r2 || r0 == r2 || !(cr > 64.0 * DBL_EPSILON * l2));
    kept += keep[t];
    dropped += !keep[t];
  }

  size_t nv = nold_v, nt = nold_t + kept;
  nm.vert = malloc((nold_v + 3 * kept + 1) * sizeof *nm.vert);
  nm.tri = malloc((nt + 1) * sizeof *nm.tri);
  nm.normal = malloc((nt + 1) * sizeof *nm.normal);
  nm.area = malloc((nt + 1) * sizeof *nm.area);
  nm.group = malloc((nt + 1) * sizeof *nm.group);
  nm.groups = malloc(((size_t)mesh->ngroups + s->nblocks + 1) * sizeof *nm.groups);
  if (!nm.vert || !nm.tri || !nm.normal || !nm.area || !nm.group || !nm.groups) goto nomem;
  if (nold_v) memcpy(nm.vert, mesh->vert, nold_v * sizeof *nm.vert);
  if (nold_t) {
    memcpy(nm.tri, mesh->tri, nold_t * sizeof *nm.tri);
    memcpy(nm.normal, mesh->normal, nold_t * sizeof *nm.normal);
    memcpy(nm.area, mesh->area, nold_t * sizeof *nm.area);
    memcpy(nm.group, mesh->group, nold_t * sizeof *nm.group);
  }
  if (mesh->ngroups) memcpy(nm.groups, mesh->groups, (size_t)mesh->ngroups * sizeof *nm.groups);
  nm.ngroups = mesh->ngroups;

  for (size_t v = 0; v < nold_v; ++v) id[v] = (uint32_t)v;
  for (size_t c = 0; c < 3 * n; ++c) id[nold_v + c] = UINT32_MAX;
  size_t at = nold_t;
  for (size_t bi = 0; bi < s->nblocks; ++bi) {
    const adem_mesh_soup_block *b = &s->blocks[bi];
    adem_mesh_group *g = &nm.groups[nm.ngroups];
    memcpy(g->name, b->name, sizeof g->name);
    g->material = tf->material;
    g->own_vertices = tf->own_vertices != 0;
    g->first = (uint32_t)at;
    g->vert_first = (uint32_t)nv;
    for (size_t t = b->first; t < b->first + b->count; ++t) {
      if (!keep[t]) continue;
      for (int k = 0; k < 3; ++k) {
        size_t r = rep[nold_v + 3 * t + (size_t)k];
        if (id[r] == UINT32_MAX) {
          id[r] = (uint32_t)nv;
          nm.vert[nv++] = x[r - nold_v]; /* r is a new corner: an old vertex has its id */
        }
        nm.tri[at][k] = id[r];
      }
      adem_vec3 p0 = nm.vert[nm.tri[at][0]], p1 = nm.vert[nm.tri[at][1]], p2 = nm.vert[nm.tri[at][2]];
      adem_vec3 cr = v3_cross(v3_sub(p1, p0), v3_sub(p2, p0));
      double len = v3_norm(cr);
      nm.normal[at] = v3_scale(cr, 1.0 / len);
      nm.area[at] = 0.5 * len;
      nm.group[at] = (uint32_t)nm.ngroups;
      /* The stored normal only turns with the rotation; zero means "not given". */
      adem_vec3 sn = rotate(tf->rotation, s->normal[t]);
      if (v3_dot(sn, nm.normal[at]) < 0.0) disagreed++;
      at++;
    }
    g->count = (uint32_t)(at - g->first);
    g->vert_count = (uint32_t)(nv - g->vert_first);
    nm.ngroups++;
    if (g->count == 0)
      adem_log(ADEM_LOG_WARN, "%s: mesh group '%s' has no triangles", path, g->name);
  }
  nm.nverts = nv;
  nm.ntris = nt;
  nm.flat_angle = mesh->flat_angle;
  size_t nonman = 0;
  if (!build_topology(&nm, &nonman)) goto nomem;
  nm.normals_disagreed = mesh->normals_disagreed + disagreed;
  nm.degenerate_dropped = mesh->degenerate_dropped + dropped;
  nm.nonmanifold_edges = nonman;

  if (dropped)
    adem_log(ADEM_LOG_WARN, "%s: dropped %zu degenerate triangles (zero area or a repeated vertex) of %zu",
             path, dropped, n);
  if (disagreed)
    adem_log(ADEM_LOG_WARN,
             "%s: %zu of %zu stored normals point against the vertex order; the vertex order "
             "(right-hand rule) is used",
             path, disagreed, kept);
  if (nonman > mesh->nonmanifold_edges)
    adem_log(ADEM_LOG_WARN, "%s: %zu edges are shared by three or more triangles", path,
             nonman - mesh->nonmanifold_edges);
  mesh_free_arrays(mesh);
  *mesh = nm;
  memset(&nm, 0, sizeof nm);
  goto done;
nomem:
  st = oom(err, path);
done:
  mesh_free_arrays(&nm);
  free(x);
  free(keys);
  free(rep);
  free(id);
  free(keep);
  return st;
}


adem_status adem_mesh_add_triangles(adem_mesh *mesh, const adem_vec3 *corners,
                                    const adem_vec3 *stored_normals, size_t ntri,
                                    const char *group_name, int material, int own_vertices,
                                    adem_error *err) {
  const char *name = group_name && *group_name ? group_name : "mesh";
  if (adem_mesh_find_group(mesh, name) >= 0)
    return adem_error_set(err, ADEM_ERR_INPUT, "mesh group name '%s' is already used", name);
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.material = material;
  tf.own_vertices = own_vertices;
  adem_status st = adem_mesh_check_transform(&tf, name, err);
  if (st) return st;
  adem_mesh_soup s;
  memset(&s, 0, sizeof s);
  adem_mesh_soup_block *b = adem_mesh_soup_block_open(&s, name, 0);
  if (!b) return oom(err, name);
  for (size_t t = 0; t < ntri && !st; ++t) {
    for (int k = 0; k < 3; ++k)
      if (!v3_isfinite(corners[3 * t + (size_t)k]))
        st = adem_error_set(err, ADEM_ERR_INPUT, "mesh group '%s': triangle %zu has a non-finite vertex",
                            name, t);
    adem_vec3 sn = stored_normals && v3_isfinite(stored_normals[t]) ? stored_normals[t] : v3_zero();
    if (!st && !adem_mesh_soup_push(&s, &corners[3 * t], sn, t)) st = oom(err, name);
    if (!st) s.blocks[0].count++;
  }
  if (!st) st = adem_mesh_append_soup(mesh, &s, &tf, name, 0, err);
  adem_mesh_soup_free(&s);
  return st;
}

/* ---------------------------------------------------------------- queries */

adem_status adem_mesh_translate_group(adem_mesh *mesh, int group, adem_vec3 d, adem_error *err) {
  if (group < 0 || group >= mesh->ngroups)
    return adem_error_set(err, ADEM_ERR_INPUT, "no mesh group %d", group);
  const adem_mesh_group *g = &mesh->groups[group];
  if (!g->own_vertices)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "mesh group '%s' shares vertices with other groups: load it with "
                          "own_vertices to move it",
                          g->name);
  for (uint32_t v = g->vert_first; v < g->vert_first + g->vert_count; ++v)
    mesh->vert[v] = v3_add(mesh->vert[v], d);
  return ADEM_OK;
}

void adem_mesh_bounds(const adem_mesh *mesh, adem_vec3 *lo, adem_vec3 *hi) {
  if (mesh->nverts == 0) {
    *lo = *hi = v3_zero();
    return;
  }
  adem_vec3 l = mesh->vert[0], h = mesh->vert[0];
  for (size_t v = 1; v < mesh->nverts; ++v) {
    adem_vec3 x = mesh->vert[v];
    l = v3(fmin(l.x, x.x), fmin(l.y, x.y), fmin(l.z, x.z));
    h = v3(fmax(h.x, x.x), fmax(h.y, x.y), fmax(h.z, x.z));
  }
  *lo = l;
  *hi = h;
}

double adem_mesh_area(const adem_mesh *mesh, int group) {
  double a = 0.0;
  for (size_t t = 0; t < mesh->ntris; ++t)
    if (group < 0 || mesh->group[t] == (uint32_t)group) a += mesh->area[t];
  return a;
}
