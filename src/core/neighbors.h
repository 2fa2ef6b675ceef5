/* Neighbour search: particles sorted by cell of a uniform grid, a Verlet list with a skin, mesh
 * triangles binned into the same cells, and contact history carried across rebuilds by the
 * pair's stable ids. */
#ifndef ADEM_NEIGHBORS_H
#define ADEM_NEIGHBORS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/base.h"
#include "pairs.h"
#include "particles.h"
#include "periodic.h"
#include "walls.h"

typedef struct adem_neighbors {
  double skin;          /* absolute skin distance, m */
  double skin_fraction; /* skin as a fraction of the largest diameter */
  bool brute_force;     /* O(N^2) search, for tests */
  double rmax_floor;    /* largest radius of particles held elsewhere (other MPI ranks'), m:
                         * the skin follows the whole system's largest; 0 in a serial run */
  /* cell grid; along a periodic axis it spans the box, its last cell taking the remainder of
   * the length, and the cells wrap */
  adem_periodic periodic; /* of the last build */
  adem_vec3 origin;
  double cell_size;
  int dims[3];
  size_t stride[3]; /* cell index = sum of coordinate x stride: the axis with the fewest cells
                     * varies fastest (neighbours.c, cell_index) */
  size_t ncells;
  size_t *cell_start; /* ncells + 1; particles are sorted by cell */
  size_t cell_cap;
  /* mesh triangles binned into the cells their box, grown by the largest reach, overlaps */
  size_t *tri_cell_start; /* ncells + 1 */
  uint32_t *tri_cell;
  size_t tri_cell_start_cap, tri_cell_cap;
  /* per-particle gather lists: entries (pair index << 1 | side) for pp, by the partner's id;
   * pair index for pw, by plane index: an order the storage order does not change */
  size_t *pp_start, *pw_start;
  uint32_t *pp_entries, *pw_entries;
  size_t pp_start_cap, pw_start_cap, pp_entries_cap, pw_entries_cap;
  /* the particles by id at the last gather (adem_particles_id_order), gathered of them */
  uint32_t *id_order;
  size_t id_order_cap, gathered;
  uint64_t rebuilds;
  double time_at_build; /* moving walls use up the skin from then on */
} adem_neighbors;

/* What a neighbour build reads and writes. */
typedef struct adem_neighbor_scope {
  adem_particles *p;       /* reordered by cell */
  adem_pair_list *pp, *pw; /* particle pairs, particle-plane pairs */
  adem_mesh_pairs *pm;     /* particle-triangle candidates */
  const adem_walls *walls;
  const adem_periodic *periodic; /* positions are wrapped into its box first */
  int nthreads;
} adem_neighbor_scope;

/* Sorts the particles by cell and rebuilds every candidate list, keeping the history of the
 * pairs that touch. */
adem_status adem_neighbors_build(adem_neighbors *nb, const adem_neighbor_scope *s, adem_error *err);
/* True when a particle has moved more than half the skin, less what the walls have used up
 * (wall_shift), since the last build. */
bool adem_neighbors_need_rebuild(const adem_neighbors *nb, const adem_particles *p,
                                 double wall_shift, int nthreads);
/* Rebuilds the per-particle gather lists from the pair lists and the order by id (after a
 * build, a checkpoint load or a change of the storage order). */
adem_status adem_neighbors_gather(adem_neighbors *nb, const adem_particles *p,
                                  const adem_pair_list *pp, const adem_pair_list *pw, int nthreads);
void adem_neighbors_free(adem_neighbors *nb);
/* Bytes of the grid (cells at most 8 n + 1024, as sort_by_cell allows; twice with mesh walls)
 * in *grid, and in *build what a build holds besides the lists for n particles and npairs
 * candidate pairs: the saved history, the sort's arrays and the gather lists. */
void adem_neighbors_estimate_bytes(double n, double npairs, bool mesh, double *grid, double *build);

#endif
