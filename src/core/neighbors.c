/* Neighbour search: particles sorted by cell of a uniform grid, a Verlet list with a skin, and
 * contact history carried across rebuilds by the pair's stable ids. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "adem/vec3.h"
#include "parallel.h"
#include "neighbors.h"
#include "cylinder.h"

/* What one build works on (adem_neighbor_scope with the neighbour structure itself). */
typedef struct build_ctx {
  adem_neighbors *nb;
  adem_particles *p;
  adem_pair_list *pp, *pw;
  adem_mesh_pairs *pm;
  const adem_walls *walls;
  int nthreads;
} build_ctx;

/* History of a touching pair, keyed by ids (or id and wall index). */
typedef struct saved_history {
  uint64_t ka, kb;
  adem_contact_history h;
} saved_history;

/* Order of two pairs' keys: by ka, then kb. */
static int compare_ids(uint64_t ka, uint64_t kb, uint64_t la, uint64_t lb) {
  if (ka != la) return ka < la ? -1 : 1;
  if (kb != lb) return kb < lb ? -1 : 1;
  return 0;
}

static int compare_saved(const void *x, const void *y) {
  const saved_history *a = x, *b = y;
  return compare_ids(a->ka, a->kb, b->ka, b->kb);
}

static const saved_history *find_saved(const saved_history *s, size_t n, uint64_t ka, uint64_t kb) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    const saved_history *m = &s[mid];
    if (m->ka < ka || (m->ka == ka && m->kb < kb))
      lo = mid + 1;
    else
      hi = mid;
  }
  return (lo < n && s[lo].ka == ka && s[lo].kb == kb) ? &s[lo] : NULL;
}

/* Copies out the history of every touching pair, sorted by key. */
static saved_history *save_history(const build_ctx *w, const adem_pair_list *l, bool walls,
                                   size_t *count) {
  size_t m = 0;
  for (size_t k = 0; k < l->n; ++k) m += l->touching[k];
  saved_history *s = malloc((m + 1) * sizeof *s);
  if (!s) return NULL;
  size_t j = 0;
  for (size_t k = 0; k < l->n; ++k) {
    if (!l->touching[k]) continue;
    s[j].ka = w->p->id[l->a[k]];
    s[j].kb = walls ? l->b[k] : w->p->id[l->b[k]];
    s[j].h = l->hist[k];
    ++j;
  }
  qsort(s, m, sizeof *s, compare_saved);
  *count = m;
  return s;
}

static void restore_history(const build_ctx *w, adem_pair_list *l, bool walls,
                            const saved_history *s, size_t ns) {
  int nthreads = w->nthreads;
  const uint64_t *id = w->p->id;
  ADEM_PARALLEL_FOR
  for (size_t k = 0; k < l->n; ++k) {
    uint64_t kb = walls ? l->b[k] : id[l->b[k]];
    const saved_history *h = find_saved(s, ns, id[l->a[k]], kb);
    adem_pairs_clear(l, k);
    if (h) {
      l->hist[k] = h->h;
      l->touching[k] = true;
    }
  }
}

/* The particle pairs' histories stay in their array through a build (the largest list: a copy
 * of every touching pair's history with its ids would be the build's largest allocation, ~80 B
 * per touching pair, on top of the lists). Before the build, the ids of the touching pairs and
 * their slots (24 B each); after it, each new pair's old slot by its ids, and the histories
 * moved within the array along those links. */
typedef struct pair_key {
  uint64_t ka, kb; /* ids, ka the lower */
  size_t k;        /* the pair's slot before the build */
} pair_key;

static int compare_key(const void *x, const void *y) {
  const pair_key *a = x, *b = y;
  return compare_ids(a->ka, a->kb, b->ka, b->kb);
}

/* The touching pairs' ids and slots (where their histories are), sorted by ids. */
static pair_key *save_pair_keys(const build_ctx *w, const adem_pair_list *l, size_t *count) {
  size_t m = 0;
  for (size_t k = 0; k < l->n; ++k) m += l->touching[k];
  pair_key *s = malloc((m + 1) * sizeof *s);
  if (!s) return NULL;
  size_t j = 0;
  for (size_t k = 0; k < l->n; ++k)
    if (l->touching[k]) s[j++] = (pair_key){w->p->id[l->a[k]], w->p->id[l->b[k]], adem_pairs_slot(l, k)};
  qsort(s, m, sizeof *s, compare_key);
  *count = m;
  return s;
}

static inline bool pair_close(const adem_neighbors *nb, const adem_particles *p, size_t i, size_t j,
                              double skin) {
  adem_vec3 d = adem_periodic_min_image(&nb->periodic, v3_sub(p->pos[j], p->pos[i]));
  double cut = p->radius[i] + p->radius[j] + skin;
  return v3_norm2(d) < cut * cut;
}

/* After the build (l holds the new pairs; its slots still the old pairs' histories): each new
 * pair takes the history its ids had (adem_pairs_pack_slots), every other record cleared, as
 * restore_history does for the other lists. */
static adem_status carry_pair_history(const build_ctx *w, adem_pair_list *l, const pair_key *s,
                                      size_t ns) {
  int nthreads = w->nthreads;
  size_t n = l->n;
  uint32_t *src = malloc((n + 1) * sizeof *src);
  if (!src) return ADEM_ERR_NOMEM;
  const uint64_t *id = w->p->id;
  ADEM_PARALLEL_FOR
  for (size_t k = 0; k < n; ++k) {
    pair_key key = {id[l->a[k]], id[l->b[k]], 0};
    size_t lo = 0, hi = ns;
    while (lo < hi) {
      size_t mid = lo + (hi - lo) / 2;
      if (compare_key(&s[mid], &key) < 0) lo = mid + 1;
      else hi = mid;
    }
    src[k] = lo < ns && compare_key(&s[lo], &key) == 0 ? (uint32_t)s[lo].k : 0u;
    /* a pair that overlaps now but kept no history (a new contact, or the first build of a run)
     * will touch at the next pass: its slot now, in the list's order, rather than in the order
     * the threads come to it (where two threads' slots would share cache lines) */
    if (src[k] == 0 && pair_close(w->nb, w->p, l->a[k], l->b[k], 0.0)) src[k] = ADEM_PAIR_FRESH_SLOT;
  }
  adem_status st = adem_pairs_pack_slots(l, src);
  free(src);
  return st;
}

static adem_status grow_size_t(size_t **p, size_t *cap, size_t need) {
  if (need <= *cap) return ADEM_OK;
  size_t c = need + need / 4 + 16;
  size_t *q = realloc(*p, c * sizeof *q);
  if (!q) return ADEM_ERR_NOMEM;
  *p = q;
  *cap = c;
  return ADEM_OK;
}

static adem_status grow_u32(uint32_t **p, size_t *cap, size_t need) {
  if (need <= *cap) return ADEM_OK;
  size_t c = need + need / 4 + 16;
  uint32_t *q = realloc(*p, c * sizeof *q);
  if (!q) return ADEM_ERR_NOMEM;
  *p = q;
  *cap = c;
  return ADEM_OK;
}

/* One cell coordinate, clamped to 0 .. dim - 1 before the conversion to int: a position far
 * outside the grid (or NaN, which the step then reports) must not overflow the int. */
static inline int cell_clamp(double u, int dim) {
  if (!(u >= 0.0)) return 0;
  if (u >= (double)(dim - 1)) return dim - 1;
  return (int)u;
}

/* Cell coordinates of a point, clamped to the grid. */
static inline void cell_coords(const adem_neighbors *nb, adem_vec3 x, int c[3]) {
  double inv = 1.0 / nb->cell_size;
  c[0] = cell_clamp((x.x - nb->origin.x) * inv, nb->dims[0]);
  c[1] = cell_clamp((x.y - nb->origin.y) * inv, nb->dims[1]);
  c[2] = cell_clamp((x.z - nb->origin.z) * inv, nb->dims[2]);
}

/* The cell at integer coordinates (x, y, z). */
static inline size_t cell_index(const adem_neighbors *nb, int x, int y, int z) {
  return (size_t)x * nb->stride[0] + (size_t)y * nb->stride[1] + (size_t)z * nb->stride[2];
}

/* Strides of the cell index: the axis with the fewest cells fastest, the one with the most
 * slowest. Particles are stored in cell order, so a particle's neighbours along the fast axes
 * are close in memory; in a flat bed (71 x 71 x 20 cells for the 100,000-sphere benchmark) its
 * neighbours above and below are then a few cells away instead of a whole layer (~7,000
 * particles, several MB, beyond the core's cache). Results do not depend on the storage order
 * (docs/architecture.md, "Order independence"); only the time does. */
static void order_axes(adem_neighbors *nb) {
  int ax[3] = {0, 1, 2};
  for (int a = 0; a < 3; ++a) /* stable: ties keep x before y before z */
    for (int b = 2; b > a; --b)
      if (nb->dims[ax[b]] < nb->dims[ax[b - 1]]) {
        int t = ax[b];
        ax[b] = ax[b - 1];
        ax[b - 1] = t;
      }
  nb->stride[ax[0]] = 1;
  nb->stride[ax[1]] = (size_t)nb->dims[ax[0]];
  nb->stride[ax[2]] = (size_t)nb->dims[ax[0]] * (size_t)nb->dims[ax[1]];
}

/* Lays the grid over the particles' bounding box and sorts particles by cell. */
static adem_status sort_by_cell(build_ctx *w, double cell) {
  adem_particles *p = w->p;
  adem_neighbors *nb = w->nb;
  size_t n = p->n;
  adem_vec3 lo = p->pos[0], hi = p->pos[0];
  for (size_t i = 1; i < n; ++i) {
    adem_vec3 x = p->pos[i];
    lo = v3(fmin(lo.x, x.x), fmin(lo.y, x.y), fmin(lo.z, x.z));
    hi = v3(fmax(hi.x, x.x), fmax(hi.y, x.y), fmax(hi.z, x.z));
  }
  /* A periodic axis: the grid spans the box, floor(len / cell) cells, the last one taking the
   * remainder (cells at least `cell` long, so the 3 x 3 x 3 stencil, wrapped, still covers the
   * cut-off). */
  const adem_periodic *pb = &nb->periodic;
  if (pb->axes & 1u) lo.x = pb->lo[0];
  if (pb->axes & 2u) lo.y = pb->lo[1];
  if (pb->axes & 4u) lo.z = pb->lo[2];
  /* Few cells per particle at most: a sparse or spread-out system gets coarser cells. */
  size_t max_cells = 8 * n + 1024;
  for (;;) {
    double ext[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
    size_t total = 1;
    bool fits = true;
    for (int d = 0; d < 3; ++d) {
      double c = floor(ext[d] / cell) + 1.0;
      if (pb->axes & (1u << d)) c = fmax(1.0, floor(pb->len[d] / cell));
      if (c > (double)max_cells) {
        fits = false;
        break;
      }
      nb->dims[d] = (int)c;
      total *= (size_t)c;
      if (total > max_cells) {
        fits = false;
        break;
      }
    }
    if (fits) {
      nb->ncells = total;
      break;
    }
    cell *= 1.5;
  }
  nb->origin = lo;
  nb->cell_size = cell;
  order_axes(nb);

  if (grow_size_t(&nb->cell_start, &nb->cell_cap, nb->ncells + 1)) return ADEM_ERR_NOMEM;
  size_t *cell_of = malloc(n * sizeof *cell_of);
  size_t *perm = malloc(n * sizeof *perm);
  if (!cell_of || !perm) {
    free(cell_of);
    free(perm);
    return ADEM_ERR_NOMEM;
  }
  int nthreads = w->nthreads;
  ADEM_PARALLEL_FOR
  for (size_t i = 0; i < n; ++i) {
    int c[3];
    cell_coords(nb, p->pos[i], c);
    cell_of[i] = cell_index(nb, c[0], c[1], c[2]);
  }
  /* Counting sort, stable: the order inside a cell keeps the previous order. */
  size_t *start = nb->cell_start;
  memset(start, 0, (nb->ncells + 1) * sizeof *start);
  for (size_t i = 0; i < n; ++i) start[cell_of[i] + 1]++;
  for (size_t c = 0; c < nb->ncells; ++c) start[c + 1] += start[c];
  for (size_t i = 0; i < n; ++i) perm[start[cell_of[i]]++] = i;
  /* start[c] now holds the end of cell c; shift back to starts. */
  for (size_t c = nb->ncells; c > 0; --c) start[c] = start[c - 1];
  start[0] = 0;
  free(cell_of);
  adem_status st = adem_particles_permute(p, perm);
  free(perm);
  return st;
}

/* The cells next to cell c along one axis (itself included), each once, ascending from c - 1 for
 * a bounded axis; a periodic one wraps, and with fewer than 4 cells takes each of them once. */
static inline int stencil(int c, int dim, unsigned periodic, int out[3]) {
  int n = 0;
  if (!periodic) {
    for (int k = c - 1; k <= c + 1; ++k)
      if (k >= 0 && k < dim) out[n++] = k;
  } else if (dim <= 3) {
    for (int k = 0; k < dim; ++k) out[n++] = k;
  } else {
    out[n++] = c == 0 ? dim - 1 : c - 1;
    out[n++] = c;
    out[n++] = c == dim - 1 ? 0 : c + 1;
  }
  return n;
}

/* Counts (pass 0) or writes (pass 1) the particle pairs of particle i. */
static size_t particle_pairs_of(const build_ctx *w, size_t i, adem_pair_list *out, size_t at) {
  const adem_particles *p = w->p;
  const adem_neighbors *nb = w->nb;
  size_t count = 0;
  double skin = nb->skin;
  if (nb->brute_force) {
    for (size_t j = i + 1; j < p->n; ++j) {
      if ((p->frozen[i] && p->frozen[j]) || !pair_close(nb, p, i, j, skin)) continue;
      if (out) {
        bool lower = p->id[i] < p->id[j];
        out->a[at + count] = (uint32_t)(lower ? i : j);
        out->b[at + count] = (uint32_t)(lower ? j : i);
      }
      ++count;
    }
    return count;
  }
  int c0[3], near[3][3], nnear[3];
  cell_coords(nb, p->pos[i], c0);
  for (int d = 0; d < 3; ++d) nnear[d] = stencil(c0[d], nb->dims[d], (nb->periodic.axes >> d) & 1u, near[d]);
  for (int sz = 0; sz < nnear[2]; ++sz) {
    int cz = near[2][sz];
    for (int sy = 0; sy < nnear[1]; ++sy) {
      int cy = near[1][sy];
      for (int sx = 0; sx < nnear[0]; ++sx) {
        int cx = near[0][sx];
        size_t cell = cell_index(nb, cx, cy, cz);
        size_t jb = nb->cell_start[cell], je = nb->cell_start[cell + 1];
        if (jb < i + 1) jb = i + 1; /* each pair once, from its lower index */
        for (size_t j = jb; j < je; ++j) {
          /* two frozen particles are one rigid wall: no contact */
          if ((p->frozen[i] && p->frozen[j]) || !pair_close(nb, p, i, j, skin)) continue;
          if (out) {
            bool lower = p->id[i] < p->id[j];
            out->a[at + count] = (uint32_t)(lower ? i : j);
            out->b[at + count] = (uint32_t)(lower ? j : i);
          }
          ++count;
        }
      }
    }
  }
  return count;
}

static size_t wall_pairs_of(const build_ctx *w, size_t i, adem_pair_list *out, size_t at) {
  size_t count = 0;
  if (w->p->frozen[i]) return 0; /* part of a wall: no wall contacts */
  adem_vec3 x = w->p->pos[i];
  double reach = w->p->radius[i] + w->nb->skin;
  for (int k = 0; k < w->walls->nplanes; ++k) {
    const adem_plane_def *pl = &w->walls->planes[k].def;
    if (w->walls->planes[k].inactive) continue;
    double d = adem_wall_nearest(pl, x).gap; /* a plane: (x - p).n */
    if (d < reach) {
      if (out) {
        out->a[at + count] = (uint32_t)i;
        out->b[at + count] = (uint32_t)k;
      }
      ++count;
    }
  }
  return count;
}

/* Cells of the grid that a box overlaps, clamped; 0 if it misses the grid. */
static int box_cells(const adem_neighbors *nb, adem_vec3 lo, adem_vec3 hi, int c0[3], int c1[3]) {
  double l[3] = {lo.x - nb->origin.x, lo.y - nb->origin.y, lo.z - nb->origin.z};
  double h[3] = {hi.x - nb->origin.x, hi.y - nb->origin.y, hi.z - nb->origin.z};
  for (int d = 0; d < 3; ++d) {
    /* a periodic axis's last cell reaches the box's face */
    double top = (nb->periodic.axes >> d) & 1u ? nb->periodic.len[d] : nb->dims[d] * nb->cell_size;
    if (h[d] < 0.0 || l[d] > top) return 0;
    double a = floor(l[d] / nb->cell_size), b = floor(h[d] / nb->cell_size);
    c0[d] = a < 0.0 ? 0 : (int)a;
    c1[d] = b >= nb->dims[d] ? nb->dims[d] - 1 : (int)b;
  }
  return 1;
}

/* Bins each triangle into every cell that its box grown by reach overlaps and that lies within
 * reach of its plane: a particle's candidates are then in its own cell. Counting sort by cell,
 * triangles ascending within a cell. */
static adem_status bin_triangles(build_ctx *w, double reach) {
  adem_neighbors *nb = w->nb;
  const adem_mesh *m = &w->walls->mesh;
  if (grow_size_t(&nb->tri_cell_start, &nb->tri_cell_start_cap, nb->ncells + 1)) return ADEM_ERR_NOMEM;
  size_t *start = nb->tri_cell_start;
  memset(start, 0, (nb->ncells + 1) * sizeof *start);
  /* a periodic axis's last cell is up to twice as long: its farthest point is 1.5 cells from
   * the centre taken here */
  double half_diag = (nb->periodic.axes ? 1.5 : 0.5) * sqrt(3.0) * nb->cell_size;
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t t = 0; t < m->ntris; ++t) {
      adem_vec3 a = m->vert[m->tri[t][0]], b = m->vert[m->tri[t][1]], c = m->vert[m->tri[t][2]];
      adem_vec3 lo = v3(fmin(a.x, fmin(b.x, c.x)) - reach, fmin(a.y, fmin(b.y, c.y)) - reach,
                        fmin(a.z, fmin(b.z, c.z)) - reach);
      adem_vec3 hi = v3(fmax(a.x, fmax(b.x, c.x)) + reach, fmax(a.y, fmax(b.y, c.y)) + reach,
                        fmax(a.z, fmax(b.z, c.z)) + reach);
      int c0[3], c1[3];
      if (!box_cells(nb, lo, hi, c0, c1)) continue;
      for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
          for (int x = c0[0]; x <= c1[0]; ++x) {
            adem_vec3 centre = v3(nb->origin.x + (x + 0.5) * nb->cell_size,
                                  nb->origin.y + (y + 0.5) * nb->cell_size,
                                  nb->origin.z + (z + 0.5) * nb->cell_size);
            if (fabs(v3_dot(v3_sub(centre, a), m->normal[t])) > half_diag + reach) continue;
            size_t cell = cell_index(nb, x, y, z);
            if (pass == 0) start[cell + 1]++;
            else nb->tri_cell[start[cell]++] = (uint32_t)t;
          }
    }
    if (pass == 0) {
      for (size_t c = 0; c < nb->ncells; ++c) start[c + 1] += start[c];
      if (grow_u32(&nb->tri_cell, &nb->tri_cell_cap, start[nb->ncells] + 1)) return ADEM_ERR_NOMEM;
    }
  }
  for (size_t c = nb->ncells; c > 0; --c) start[c] = start[c - 1];
  start[0] = 0;
  return ADEM_OK;
}

/* Candidate triangles of particle i: closer than radius + skin. */
static size_t mesh_pairs_of(const build_ctx *w, size_t i, adem_pair_list *out, size_t at) {
  const adem_mesh *m = &w->walls->mesh;
  const adem_neighbors *nb = w->nb;
  if (m->ntris == 0 || w->p->frozen[i]) return 0;
  adem_vec3 x = w->p->pos[i];
  double reach = w->p->radius[i] + nb->skin;
  size_t count = 0, tb = 0, te = m->ntris;
  const uint32_t *list = NULL;
  if (!nb->brute_force && nb->ncells > 0) {
    int c[3];
    cell_coords(nb, x, c);
    size_t cell = cell_index(nb, c[0], c[1], c[2]);
    list = nb->tri_cell;
    tb = nb->tri_cell_start[cell];
    te = nb->tri_cell_start[cell + 1];
  }
  for (size_t e = tb; e < te; ++e) {
    uint32_t t = list ? list[e] : (uint32_t)e;
    if (!adem_walls_mesh_active(w->walls, m->group[t])) continue;
    adem_vec3 q;
    adem_triangle_feature f;
    if (adem_triangle_distance2(m, t, x, &q, &f) >= reach * reach) continue;
    if (out) {
      out->a[at + count] = (uint32_t)i;
      out->b[at + count] = t;
    }
    ++count;
  }
  return count;
}

/* Mesh history: (id, key) of every touching slot, sorted. */
static saved_history *save_mesh_history(const build_ctx *w, size_t *count) {
  const adem_mesh_pairs *pm = w->pm;
  size_t m = 0;
  for (size_t k = 0; k < pm->l.n; ++k) m += pm->l.touching[k];
  saved_history *s = malloc((m + 1) * sizeof *s);
  if (!s) return NULL;
  size_t j = 0;
  for (size_t k = 0; k < pm->l.n; ++k) {
    if (!pm->l.touching[k]) continue;
    s[j++] = (saved_history){w->p->id[pm->l.a[k]], pm->key[k], pm->l.hist[k]};
  }
  qsort(s, m, sizeof *s, compare_saved);
  *count = m;
  return s;
}

/* Puts each particle's saved contacts, sorted by key, in the first slots of its range. */
static void restore_mesh_history(build_ctx *w, const saved_history *s, size_t ns) {
  adem_mesh_pairs *pm = w->pm;
  adem_pair_list *l = &pm->l;
  int nthreads = w->nthreads;
  size_t n = w->p->n;
  ADEM_PARALLEL_FOR
  for (size_t i = 0; i < n; ++i) {
    uint64_t id = w->p->id[i];
    size_t lo = 0, hi = ns;
    while (lo < hi) {
      size_t mid = lo + (hi - lo) / 2;
      if (s[mid].ka < id) lo = mid + 1;
      else hi = mid;
    }
    for (size_t k = pm->start[i]; k < pm->start[i + 1]; ++k) {
      adem_mesh_pairs_clear(pm, k); /* the owner is found again by the next force pass */
      if (lo < ns && s[lo].ka == id) {
        l->touching[k] = true;
        pm->key[k] = s[lo].kb;
        l->hist[k] = s[lo++].h;
      }
    }
  }
}

typedef size_t pairs_of_fn(const build_ctx *w, size_t i, adem_pair_list *out, size_t at);

/* Two passes over particles (count, then fill at prefix offsets): the list order is fixed by
 * particle index alone, whatever the number of threads. */
static adem_status build_list(build_ctx *w, adem_pair_list *l, pairs_of_fn *pairs_of,
                              size_t *offsets) {
  size_t n = w->p->n;
  int nthreads = w->nthreads;
  ADEM_PARALLEL_FOR
  for (size_t i = 0; i < n; ++i) offsets[i + 1] = pairs_of(w, i, NULL, 0);
  offsets[0] = 0;
  for (size_t i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
  if (adem_pairs_reserve(l, offsets[n])) return ADEM_ERR_NOMEM;
  l->n = offsets[n];
  ADEM_PARALLEL_FOR
  for (size_t i = 0; i < n; ++i) pairs_of(w, i, l, offsets[i]);
  return ADEM_OK;
}

/* The partner of a gather entry of pp, by id. */
static inline uint64_t partner_id(const adem_pair_list *pp, const uint64_t *id, uint32_t code) {
  size_t k = code >> 1;
  return id[(code & 1u) ? pp->a[k] : pp->b[k]];
}

/* Sorts one particle's entries by its partners' ids (insertion sort: a particle has few, and
 * the ids are distinct, so the order is total). */
static void sort_pp_entries(uint32_t *e, size_t n, const adem_pair_list *pp, const uint64_t *id) {
  for (size_t i = 1; i < n; ++i) {
    uint32_t x = e[i];
    uint64_t key = partner_id(pp, id, x);
    size_t j = i;
    while (j > 0 && partner_id(pp, id, e[j - 1]) > key) {
      e[j] = e[j - 1];
      --j;
    }
    e[j] = x;
  }
}

/* Sorts one particle's plane entries by plane index (one pair per plane). */
static void sort_pw_entries(uint32_t *e, size_t n, const adem_pair_list *pw) {
  for (size_t i = 1; i < n; ++i) {
    uint32_t x = e[i];
    size_t j = i;
    while (j > 0 && pw->b[e[j - 1]] > pw->b[x]) {
      e[j] = e[j - 1];
      --j;
    }
    e[j] = x;
  }
}

adem_status adem_neighbors_gather(adem_neighbors *nb, const adem_particles *p,
                                  const adem_pair_list *pp, const adem_pair_list *pw, int nthreads) {
  size_t n = p->n;
  nb->gathered = 0;
  if (grow_size_t(&nb->pp_start, &nb->pp_start_cap, n + 1)) return ADEM_ERR_NOMEM;
  if (grow_size_t(&nb->pw_start, &nb->pw_start_cap, n + 1)) return ADEM_ERR_NOMEM;
  if (grow_u32(&nb->pp_entries, &nb->pp_entries_cap, 2 * pp->n)) return ADEM_ERR_NOMEM;
  if (grow_u32(&nb->pw_entries, &nb->pw_entries_cap, pw->n)) return ADEM_ERR_NOMEM;
  if (grow_u32(&nb->id_order, &nb->id_order_cap, n + 1)) return ADEM_ERR_NOMEM;

  size_t *s = nb->pp_start;
  memset(s, 0, (n + 1) * sizeof *s);
  for (size_t k = 0; k < pp->n; ++k) {
    s[pp->a[k] + 1]++;
    s[pp->b[k] + 1]++;
  }
  for (size_t i = 0; i < n; ++i) s[i + 1] += s[i];
  for (size_t k = 0; k < pp->n; ++k) {
    nb->pp_entries[s[pp->a[k]]++] = (uint32_t)(k << 1);
    nb->pp_entries[s[pp->b[k]]++] = (uint32_t)(k << 1 | 1u);
  }
  for (size_t i = n; i > 0; --i) s[i] = s[i - 1];
  s[0] = 0;

  s = nb->pw_start;
  memset(s, 0, (n + 1) * sizeof *s);
  for (size_t k = 0; k < pw->n; ++k) s[pw->a[k] + 1]++;
  for (size_t i = 0; i < n; ++i) s[i + 1] += s[i];
  for (size_t k = 0; k < pw->n; ++k) nb->pw_entries[s[pw->a[k]]++] = (uint32_t)k;
  for (size_t i = n; i > 0; --i) s[i] = s[i - 1];
  s[0] = 0;

  /* The pair lists follow the storage order; a particle's sum must not (force_sums.c). */
  const uint64_t *id = p->id;
  const size_t *ps = nb->pp_start, *ws = nb->pw_start;
  uint32_t *pe = nb->pp_entries, *we = nb->pw_entries;
  ADEM_PARALLEL_FOR
  for (size_t i = 0; i < n; ++i) {
    /* an empty list may be a NULL array: no pointer arithmetic on it */
    if (ps[i + 1] > ps[i]) sort_pp_entries(pe + ps[i], ps[i + 1] - ps[i], pp, id);
    if (ws[i + 1] > ws[i]) sort_pw_entries(we + ws[i], ws[i + 1] - ws[i], pw);
  }
  if (adem_particles_id_order(p, nb->id_order)) return ADEM_ERR_NOMEM;
  nb->gathered = n;
  return ADEM_OK;
}

adem_status adem_neighbors_build(adem_neighbors *nb, const adem_neighbor_scope *scope,
                                 adem_error *err) {
  build_ctx ctx = {nb, scope->p, scope->pp, scope->pw,
                   scope->pm, scope->walls, scope->nthreads};
  build_ctx *w = &ctx;
  adem_particles *p = w->p;
  size_t n = p->n;
  if (2 * w->pp->n + 2 >= UINT32_MAX || n >= UINT32_MAX)
    return adem_error_set(err, ADEM_ERR_NOMEM, "too many particles or pairs for 32-bit indices");
  nb->periodic = scope->periodic ? *scope->periodic : (adem_periodic){0, {0}, {0}};
  if (adem_particles_wrap(p, &nb->periodic, w->nthreads))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for the periodic image counters");

  size_t nsaved_pp = 0, nsaved_pw = 0, nsaved_pm = 0;
  pair_key *saved_pp = save_pair_keys(w, w->pp, &nsaved_pp);
  saved_history *saved_pw = save_history(w, w->pw, true, &nsaved_pw);
  saved_history *saved_pm = save_mesh_history(w, &nsaved_pm);
  size_t *offsets = malloc((n + 1) * sizeof *offsets);
  adem_status st = ADEM_OK;
  if (!saved_pp || !saved_pw || !saved_pm || !offsets) {
    st = ADEM_ERR_NOMEM;
    goto done;
  }

  double rmax = nb->rmax_floor;
  for (size_t i = 0; i < n; ++i) rmax = fmax(rmax, p->radius[i]);
  nb->skin = nb->skin_fraction * 2.0 * rmax;

  if (n > 0 && !nb->brute_force) {
    st = sort_by_cell(w, 2.0 * rmax + nb->skin);
    if (st) goto done;
  }
  if (n > 0 && !nb->brute_force && w->walls->mesh.ntris > 0) {
    st = bin_triangles(w, rmax + nb->skin);
    if (st) goto done;
  }
  st = build_list(w, w->pp, particle_pairs_of, offsets);
  if (!st) st = build_list(w, w->pw, wall_pairs_of, offsets);
  if (!st) st = build_list(w, &w->pm->l, mesh_pairs_of, offsets);
  if (!st) st = adem_mesh_pairs_reserve(w->pm);
  if (!st && grow_size_t(&w->pm->start, &w->pm->start_cap, n + 1)) st = ADEM_ERR_NOMEM;
  if (st) goto done;
  memcpy(w->pm->start, offsets, (n + 1) * sizeof *offsets);
  st = carry_pair_history(w, w->pp, saved_pp, nsaved_pp);
  if (st) goto done;
  restore_history(w, w->pw, true, saved_pw, nsaved_pw);
  restore_mesh_history(w, saved_pm, nsaved_pm);
  nb->time_at_build = w->walls->time;
  st = adem_neighbors_gather(nb, p, w->pp, w->pw, w->nthreads);
  if (st) goto done;
  adem_particles_mark_build(p);
  nb->rebuilds++;
done:
  free(saved_pp);
  free(saved_pw);
  free(saved_pm);
  free(offsets);
  if (st) return adem_error_set(err, st, "out of memory building the neighbour list");
  return ADEM_OK;
}

bool adem_neighbors_need_rebuild(const adem_neighbors *nb, const adem_particles *p,
                                 double wall_shift, int nthreads) {
  /* a moving wall uses up the skin too */
  double half = 0.5 * nb->skin - wall_shift;
  if (half <= 0.0) return true;
  double limit = half * half;
  double worst = 0.0;
  size_t n = p->n;
  if (nthreads > 1) {
    ADEM_PARALLEL_FOR_MAX(worst)
    for (size_t i = 0; i < n; ++i) {
      double d2 = v3_norm2(v3_sub(p->pos[i], p->pos_at_build[i]));
      worst = d2 > worst ? d2 : worst;
    }
    return worst > limit;
  }
  for (size_t i = 0; i < n; ++i)
    if (v3_norm2(v3_sub(p->pos[i], p->pos_at_build[i])) > limit) return true;
  return false;
}

void adem_neighbors_estimate_bytes(double n, double npairs, bool mesh, double *grid, double *build) {
  double cells = 8.0 * n + 1024.0 + 1.0; /* sort_by_cell's cap, + 1 start */
  *grid = cells * (double)sizeof(size_t) * (mesh ? 2.0 : 1.0);
  /* history kept across the build: particle pairs' keys and links (carry_pair_history), the
   * copies of the wall and mesh pairs' (one a particle at most, as the estimate counts them) */
  *build = npairs * (double)(sizeof(pair_key) + sizeof(uint32_t) + 1) + n * (double)sizeof(saved_history) + 3.0 * (n + 1.0) * (double)sizeof(size_t) /* cell_of, perm, offsets */
           + 2.0 * (n + 1.0) * (double)sizeof(size_t)                                                                                                /* pp_start, pw_start */
           + (n + 1.0) * (double)sizeof(uint32_t)                                                                                                    /* id_order */
           + 2.0 * npairs * (double)sizeof(uint32_t);                                                                                                /* gather entries */
}

void adem_neighbors_free(adem_neighbors *nb) {
  free(nb->cell_start);
  free(nb->pp_start);
  free(nb->pw_start);
  free(nb->pp_entries);
  free(nb->pw_entries);
  free(nb->tri_cell_start);
  free(nb->tri_cell);
  free(nb->id_order);
  nb->id_order = NULL;
  nb->id_order_cap = nb->gathered = 0;
  nb->tri_cell_start = NULL;
  nb->tri_cell = NULL;
  nb->tri_cell_start_cap = nb->tri_cell_cap = 0;
  nb->cell_start = nb->pp_start = nb->pw_start = NULL;
  nb->pp_entries = nb->pw_entries = NULL;
  nb->cell_cap = nb->pp_start_cap = nb->pw_start_cap = nb->pp_entries_cap = nb->pw_entries_cap = 0;
}
