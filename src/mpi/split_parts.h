/* What the files of the MPI split share (split.h): the split's state, the slabs, byte buffers and
 * the records they carry, the collectives. split.c cuts, builds and steps; split_records.c packs
 * particles and pairs; split_loads.c sums the walls' loads; split_assemble.c gathers the whole. */
#ifndef ADEM_SPLIT_PARTS_H
#define ADEM_SPLIT_PARTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/vec3.h"
#include "split.h"

struct adem_split {
  MPI_Comm comm;
  int rank, size;
  int axis;         /* slabs along x, y or z */
  bool wraps;       /* that axis is periodic: slab 0 and the last are neighbours across its faces */
  double plo, plen; /* the periodic box along it */
  double *cut;      /* size - 1 cuts, ascending: slab r is [cut[r-1], cut[r]) */
  double rmax;      /* the whole system's largest radius */
  adem_world_split hooks;
  /* ghost refresh, each by id within each rank: the own particles whose copies rank q holds
   * (send_idx[sdispl[q] ..]), and the copies here of rank r's (recv_idx[rdispl[r] ..]) */
  int *scount, *sdispl, *rcount, *rdispl;
  uint32_t *send_idx, *recv_idx;
  unsigned char *sbuf, *rbuf;
  size_t sbuf_cap, rbuf_cap;
  int *bytes_a, *bytes_b, *bytes_c, *bytes_d; /* byte counts and offsets of an exchange */
  adem_split_stats stats;                     /* what the exchanges cost (split.h) */
  double sent;                                /* bytes this process has sent to others, every exchange */
};

/* Bytes sent to the other processes by a collective in which this process sends `bytes` to
 * each of `to` others. */
static inline void tally(adem_split *s, double bytes) { s->sent += bytes; }

typedef struct bytes {
  unsigned char *d;
  size_t n, cap;
} bytes;

static inline double along(adem_vec3 v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y
                                                                                       : v.z; }

/* A centre's coordinate along the slabs' axis; along a periodic axis wrapped into the box as the
 * neighbour build wraps it (periodic.h), so that the slab a build sends a particle to is the
 * slab of its position after the build (pos_at_build). */
static inline double coord(const adem_split *s, adem_vec3 v) {
  double x = along(v, s->axis);
  int32_t image = 0;
  return s->wraps ? adem_periodic_wrap_component(x, s->plo, s->plen, &image) : x;
}

/* The slab holding coordinate x: the number of cuts at or below it. */
static inline int slab_in(const double *cut, int size, double x) {
  int lo = 0, hi = size - 1;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (cut[mid] <= x) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

static inline int slab_of(const adem_split *s, double x) { return slab_in(s->cut, s->size, x); }

/* Owner of local particle i: by its centre at the last build, so that owners change at builds
 * only, the same on every process. */
static inline int owner(const adem_split *s, const adem_particles *p, size_t i) {
  return slab_of(s, coord(s, p->pos_at_build[i]));
}

/* Index of id in ids sorted ascending (by[] the indices in that order), or SIZE_MAX. */
typedef struct id_index {
  uint64_t id;
  uint32_t i;
} id_index;

/* ---- byte buffers, the records they carry, the collectives (split_records.c) ---- */
bool adem_split_bytes_put(bytes *b, const void *x, size_t n);
void adem_split_bytes_free_all(bytes *b, int n);
int adem_split_mem_sink(void *ctx, const void *data, size_t n);
size_t adem_split_particle_bytes(void);
bool adem_split_put_particle(bytes *b, const adem_particles *p, size_t i);
/* Particle i from a record; false when out of memory for a kind of field it carries (nonzero)
 * that this process did not keep (particles.h). */
bool adem_split_get_particle(adem_particles *p, size_t i, const unsigned char *src);
size_t adem_split_pair_bytes(bool bal);
bool adem_split_put_pair(bytes *b, const adem_pair_list *l, size_t k, uint64_t ka, uint64_t kb,
                         bool bal);
void adem_split_get_pair(adem_pair_list *l, size_t k, const unsigned char *src, uint64_t *ka,
                         uint64_t *kb, bool bal);
int adem_split_compare_id_index(const void *x, const void *y);
/* The bytes of every rank gathered to every rank (allgather) or to rank 0 (gather), in rank
 * order, into *in. Collective. */
adem_status adem_split_allgather(adem_split *s, const bytes *mine, bytes *in, adem_error *err);
adem_status adem_split_gather(adem_split *s, const bytes *mine, bytes *in, adem_error *err);
size_t adem_split_find_id(const id_index *m, size_t n, uint64_t id);

/* ---- the walls' loads of the whole system, summed in the serial order (split_loads.c) ---- */
adem_status adem_split_plane_forces_hook(void *ctx, const adem_world *w, adem_vec3 *out,
                                         adem_error *err);
adem_status adem_split_face_loads(adem_split *s, const adem_world *w, adem_walls *into,
                                  bool everywhere, adem_error *err);
adem_status adem_split_mesh_loads_hook(void *ctx, adem_world *w, adem_error *err);
adem_status adem_split_sum_terms_hook(void *ctx, const adem_world *w, const adem_id_term *t,
                                      size_t n, double *out, int nout, adem_error *err);

/* ---- exchanges (split.c) ---- */
adem_status adem_split_too_big(adem_error *err);

#endif
