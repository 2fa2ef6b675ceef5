/* A system split over MPI processes in slabs (docs/parallel.md): each process steps its own
 * particles and copies ("ghosts") of the others' within reach of its slab, and every result is
 * the serial run's bit for bit (docs/architecture.md, "Order independence").
 *
 * Slabs along the longest axis of the domain box, cut at the quantiles of the centres so that
 * the processes own as many particles (a recursive coordinate bisection in one dimension), and
 * cut again at every neighbour build. A particle's owner is the slab that holds its centre at
 * the last build (pos_at_build), so owners change only at builds, the same on every process.
 * Only this layer calls MPI. */
#ifndef ADEM_SPLIT_H
#define ADEM_SPLIT_H

#include <mpi.h>

#include "adem/world.h"
#include "world_internal.h"

typedef struct adem_split adem_split;

/* Why a world cannot be split yet (three periodic axes: no axis to cut along; no particles),
 * as "its ...", or NULL when it can. */
const char *adem_split_refusal(const adem_world *w);

/* Splits a prepared world, whole and the same on every process of comm: *local becomes this
 * process's part (a new world: its slab's particles and the ghosts, the pairs with one of its
 * own), which adem_world_step then steps with the others. The cuts are taken here and kept. */
adem_status adem_split_create(const adem_world *whole, MPI_Comm comm, adem_split **out,
                              adem_world **local, adem_error *err);
/* The whole system on rank 0, or on every process when `everywhere` (into `whole`, a world
 * prepared from the same case, as given to create): every particle, every pair with its
 * history and results, the walls' state and the counters, so that the serial outputs and
 * checkpoints can be written from it, and the serial decisions taken on it (run-until
 * conditions, stage starts, pours). Collective. */
adem_status adem_split_assemble(adem_split *s, const adem_world *local, adem_world *whole,
                                bool everywhere, adem_error *err);
/* A status on every process: the largest (an error somewhere is an error everywhere; the
 * processes without one get "another process failed"). Collective. */
adem_status adem_split_agree(adem_split *s, adem_status st, adem_error *err);
int adem_split_rank(const adem_split *s);
/* The indices in local of this process's own particles, by id (*idx: free it). */
adem_status adem_split_own_by_id(const adem_split *s, const adem_world *local, uint32_t **idx,
                                 size_t *n);
/* Particles this process owns now. */
size_t adem_split_owned(const adem_split *s, const adem_world *local);
void adem_split_free(adem_split *s);

/* What this process's exchanges have cost (bench/mpi, docs/parallel.md): each a sum, so that
 * the splits of one run (a run is split again after a stage or a pour) add up. */
typedef struct adem_split_stats {
  double refreshes;       /* ghost refreshes: one per step */
  double owned, ghosts;   /* own particles and ghosts held, summed over the refreshes */
  double refresh_bytes;   /* bytes sent to other processes by the refreshes */
  double refresh_seconds; /* wall time inside them: packing, the exchange, unpacking */
  double builds;          /* neighbour builds */
  double build_bytes;     /* bytes sent at builds: the cuts' centres, particles and histories
                           * to new owners, copies to the slabs within reach */
  double build_seconds;   /* wall time inside the builds, the neighbour search included */
  double other_bytes;     /* bytes sent otherwise: assembling for outputs and decisions,
                           * plane forces and face loads */
} adem_split_stats;
#define ADEM_SPLIT_STATS_COUNT 9 /* doubles in adem_split_stats (run.c sends them as an array) */
_Static_assert(sizeof(adem_split_stats) == ADEM_SPLIT_STATS_COUNT * sizeof(double),
               "adem_split_stats must be ADEM_SPLIT_STATS_COUNT doubles");
/* Adds this split's figures to *into. */
void adem_split_stats_add(const adem_split *s, adem_split_stats *into);
/* A test's control (tests/mpi/test_split_features.c): true when the environment has
 * ADEM_SPLIT_BREAK=what, which leaves one exchange out ("plane_forces", "face_loads",
 * "mesh_history", "resplit"; "pieces": a frame piece holds the process's ghosts too;
 * "periodic_axis": slabs along a periodic axis, with no images across its faces), so that the
 * test shows it sees the difference. Never set in a real run. */
bool adem_split_break(const char *what);

#endif
