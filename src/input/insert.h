/* Particle insertion: size distributions, regions (box, cylinder, closed STL volume), seeded random
 * fills that overlap nothing, and pours that insert particles at a rate while a run goes on.
 *
 * Everything is deterministic in the seed: a fill or a pour batch draws its radii first, then
 * tries positions from its own xoshiro256** stream (rng.h); the overlap tests are exact, so the
 * result does not depend on how the spheres are searched, on threads or on how a run is chunked. */
#ifndef ADEM_INSERT_H
#define ADEM_INSERT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/case.h"
#include "adem/world.h"
#include "mesh.h"
#include "rng.h"

/* More spheres than this in one fill is surely a mistake and would only exhaust memory. */
#define ADEM_INSERT_MAX_SPHERES 100000000.0

/* ---- size distributions ---- */

typedef enum adem_size_kind {
  ADEM_SIZE_CONSTANT = 0,
  ADEM_SIZE_UNIFORM = 1,
  ADEM_SIZE_NORMAL = 2,
  ADEM_SIZE_LOGNORMAL = 3,
  ADEM_SIZE_DISCRETE = 4
} adem_size_kind;

/* A radius distribution. The discrete arrays belong to it (adem_insert_dist_free). */
typedef struct adem_size_dist {
  adem_size_kind kind;
  double value;     /* constant */
  double min, max;  /* uniform */
  double mean, std; /* normal, lognormal: of the radius itself */
  size_t n;         /* discrete: radii and the running sum of their weights */
  double *values, *cumulative;
  double limit; /* normal, lognormal: draws outside (0, limit] are drawn again */
} adem_size_dist;

/* Draws one radius. Normal and lognormal draws outside (0, limit] are drawn again, 1000 times at
 * most (then ADEM_ERR_INPUT). Constant and uniform use only uniform numbers: the same on every
 * platform bit for bit; normal and lognormal also use the C library's log, cos and exp. */
adem_status adem_insert_draw_radius(const adem_size_dist *d, adem_rng *rng, double *r,
                                    adem_error *err);
/* A radius no draw is below (for the time step): the smallest value, or for normal and lognormal
 * the 0.1 % quantile (mean - 3.09 std, not below mean / 10; exp(mu - 3.09 sigma)). */
double adem_insert_dist_smallest(const adem_size_dist *d);
/* A radius no draw is above in practice: the largest value, or the 99.9 % quantile. */
double adem_insert_dist_largest(const adem_size_dist *d);
/* Mean and standard deviation of the distribution as stated (before truncation). */
void adem_insert_dist_moments(const adem_size_dist *d, double *mean, double *std);
void adem_insert_dist_free(adem_size_dist *d);

/* ---- regions ---- */

typedef enum adem_region_kind {
  ADEM_REGION_BOX = 0,
  ADEM_REGION_CYLINDER = 1,
  ADEM_REGION_MESH = 2
} adem_region_kind;

/* A volume to fill. Zero-initialise, make with one of the init functions, free. */
typedef struct adem_region {
  adem_region_kind kind;
  adem_vec3 lo, hi; /* bounding box (the box itself for a box) */
  double volume;    /* m^3 */
  /* cylinder: the axis runs from `start` (centre of one end) along the unit `axis` */
  adem_vec3 start, axis, e1, e2;
  double length, radius;
  /* closed triangle mesh, with its triangles binned into columns along z for the ray test */
  adem_mesh mesh;
  int cols[2];
  double col_size;
  size_t *col_start; /* cols[0] cols[1] + 1 */
  uint32_t *col_tri;
} adem_region;

void adem_insert_region_box(adem_region *r, adem_vec3 lo, adem_vec3 hi);
/* ADEM_ERR_INPUT if the ends coincide or the radius is not > 0. */
adem_status adem_insert_region_cylinder(adem_region *r, adem_vec3 start, adem_vec3 end,
                                        double radius, adem_error *err);
/* Loads a closed STL surface (every edge shared by exactly two triangles). */
adem_status adem_insert_region_mesh(adem_region *r, const char *path,
                                    const adem_mesh_transform *tf, adem_error *err);
void adem_insert_region_free(adem_region *r);
/* Largest radius a sphere inside the region can have (an upper bound for a mesh: half the
 * smallest side of its bounding box); *what names it for messages ("half its smallest side"). */
double adem_insert_region_fit(const adem_region *r, const char **what);
/* True when the whole sphere (x, radius) is inside the region: for a mesh, its centre is inside
 * (ray parity) and no triangle is closer than the radius. */
bool adem_insert_region_holds(const adem_region *r, adem_vec3 x, double radius);
/* One trial centre for a sphere of that radius, uniform over the positions that keep it inside
 * the region's box (box: exactly inside; cylinder: inside the slab and the square around the
 * disc). Returns false when the trial already misses the region. */
bool adem_insert_region_sample(const adem_region *r, adem_rng *rng, double radius, adem_vec3 *x);

/* The inside of a closed surface given as ntri triangles (3 corners each, world coordinates),
 * like a mesh region: ADEM_ERR_INPUT when it does not enclose a volume. */
adem_status adem_insert_region_triangles(adem_region *r, const adem_vec3 *corners, size_t ntri,
                                         adem_error *err);
/* True when the point is inside the region, away from its boundary by more than round-off (a
 * wall lying on a region's face is not in it). */
bool adem_insert_region_contains(const adem_region *r, adem_vec3 x);
/* A point well inside the region: a box's or a cylinder's centre; for a mesh, its bounding box's
 * centre when inside, else the first of a few sample points that is. */
adem_vec3 adem_insert_region_centre(const adem_region *r);
/* Where the region lies with respect to the plane through point with unit normal: +1 wholly in
 * front of it (the normal's side), -1 wholly behind, 0 across it. Touching is not crossing. */
int adem_insert_region_plane_side(const adem_region *r, adem_vec3 point, adem_vec3 normal);
/* True when some of triangle abc lies inside the region (adem_insert_region_contains); exact
 * for a box, from points no farther apart than an eighth of the region's smallest extent for a
 * cylinder or a mesh. */
bool adem_insert_region_cuts_triangle(const adem_region *r, adem_vec3 a, adem_vec3 b,
                                      adem_vec3 c);

/* Named regions: the regions output.regions counts particles in, and the regions the case's
 * random sets were filled in (kept for `adem check`). */
typedef struct adem_named_region {
  char name[ADEM_NAME_MAX];
  char where[128]; /* key path, e.g. particles[0].region */
  adem_region region;
} adem_named_region;

struct adem_regions {
  int n;
  adem_named_region *r;
};

/* Appends a region (*region now belongs to the list and is zeroed). */
adem_status adem_regions_add(adem_regions **rs, const char *name, const char *where,
                             adem_region *region, adem_error *err);
void adem_regions_free(adem_regions *rs);
/* Particles whose centre is inside each region (adem_insert_region_contains) and their mass:
 * count[k] and mass[k] for region k, summed in the particles' order. */
void adem_regions_count(const adem_regions *rs, const adem_world *w, double *count, double *mass);

/* ---- overlap queries ---- */

/* Uniform cell grid over spheres given as arrays of centres and radii, for overlap queries in
 * O(1). Queries are spheres of radius <= reach; cells are at least 2 reach wide. A sphere of
 * radius R is filed in every cell its box widened by max(0, R + reach - h) touches, so a sphere
 * that overlaps a query always sits in the query's cell or a neighbouring one. Centres outside
 * the grid are clamped to its border cells, which keeps that true. */
typedef struct adem_sphere_grid {
  adem_vec3 lo;
  double h, inv_h, reach;
  int dims[3];
  int64_t *head; /* per cell: first entry or -1 */
  int64_t *next; /* per entry */
  size_t *sphere;
  size_t n, cap;
} adem_sphere_grid;

adem_status adem_insert_grid_init(adem_sphere_grid *g, adem_vec3 lo, adem_vec3 hi, double h,
                                  double reach, size_t expected);
void adem_insert_grid_free(adem_sphere_grid *g);
adem_status adem_insert_grid_add(adem_sphere_grid *g, const adem_vec3 *pos, const double *rad,
                                 size_t i);
/* Index of a filed sphere overlapping (p, r), or -1. Touching is not overlapping. */
int64_t adem_insert_grid_overlap(const adem_sphere_grid *g, const adem_vec3 *pos,
                                 const double *rad, adem_vec3 p, double r);

/* ---- fills ---- */

typedef struct adem_fill_def {
  const adem_region *region;
  const adem_size_dist *dist;
  uint64_t count;          /* spheres to place; 0: as many as solid_fraction asks */
  double solid_fraction;   /* of the region's volume, when count is 0 */
  uint64_t max_attempts;   /* trial positions in all; 0: max(1000000, 100 spheres) */
  const adem_world *walls; /* active planes and mesh groups to keep clear of; may be NULL */
} adem_fill_def;

typedef struct adem_fill_result {
  adem_vec3 *pos;
  double *radius;
  size_t n;      /* placed */
  size_t wanted; /* asked for (count, or the number the fraction takes) */
  double volume; /* of the spheres placed, m^3 */
  uint64_t attempts;
} adem_fill_result;

/* Random fill: draws the radii (count of them, or until their volume is closest to
 * solid_fraction x region volume: a sphere is kept while the running volume plus half of its
 * own stays within the target, so the result is within half the largest sphere's volume),
 * sorts them largest first and tries each at uniform random positions until it is inside the
 * region, clear of the walls and overlaps no sphere already placed nor any of the `nold` given
 * ones. Stops early when max_attempts run out (out->n < out->wanted). */
adem_status adem_insert_fill(const adem_fill_def *def, adem_rng *rng, const adem_vec3 *old_pos,
                             const double *old_rad, size_t nold, adem_fill_result *out,
                             adem_error *err);
void adem_insert_fill_result_free(adem_fill_result *res);

/* True when the sphere clears every active plane (centre at least its radius in front) and every
 * triangle of an active mesh group. */
bool adem_insert_walls_clear(const adem_world *w, adem_vec3 x, double radius);

/* ---- placing, shared by fills and pours (insert_fill.c) ---- */

/* Places the radii (largest first) in the region; old spheres near it are obstacles. The placed
 * spheres are appended to pos/rad after the old ones copied there. Returns ADEM_ERR_NOMEM or OK;
 * *placed and *attempts say how it went. keep[k] (if not NULL) marks the radii placed. */
typedef struct adem_placer {
  const adem_region *region;
  const adem_world *walls;
  uint64_t max_attempts; /* in all (per_particle false) or per particle */
  bool per_particle;
} adem_placer;
adem_status adem_insert_place(const adem_placer *pl, adem_rng *rng, const double *radii,
                              size_t count, const adem_vec3 *old_pos, const double *old_rad, size_t nold,
                              adem_vec3 **pos_out, double **rad_out, bool *keep, size_t *placed,
                              uint64_t *attempts_out);
/* Appends r to a growing array. */
adem_status adem_insert_push_radius(double **a, size_t *n, size_t *cap, double r);
/* qsort's comparison for radii largest first. */
int adem_insert_compare_descending(const void *a, const void *b);

/* ---- pours ---- */

/* A pour: particles inserted into a region at a rate during a time window, in batches every
 * `interval`, at fixed steps. Each batch brings the total up to rate x elapsed time (for a mass
 * rate: the mass, to within half a particle), measured at the end of the batch's interval. */
typedef struct adem_pour_def {
  char name[ADEM_NAME_MAX];
  adem_region region;  /* moved into the pour by adem_pours_add */
  adem_size_dist dist; /* moved too */
  int material, group;
  adem_vec3 velocity, angular_velocity;
  double rate;           /* particles/s, or 0 */
  double mass_rate;      /* kg/s, or 0 */
  double start, end;     /* s */
  double interval;       /* s between batches */
  uint64_t max_attempts; /* trial positions per particle */
  uint64_t seed;         /* stream of this pour */
} adem_pour_def;

typedef struct adem_pour {
  adem_pour_def def;
  double density; /* of the material, for masses */
  adem_rng rng;
  uint64_t inserted;   /* particles so far */
  double mass;         /* kg so far */
  uint64_t next_batch; /* index of the next batch */
  int short_batches;   /* batches that could not place every particle */
} adem_pour;

struct adem_pours {
  int n;
  adem_pour *p;
};

/* Appends a pour (the def's region and distribution now belong to it). */
adem_status adem_pours_add(adem_pours **ps, adem_pour_def *def, double density, adem_error *err);
void adem_pours_free(adem_pours *ps);
/* Particles (or kg) a pour inserts in all: round(rate x window), or mass_rate x window. */
double adem_pour_total(const adem_pour *p);
/* Smallest step > step at which a batch is due (UINT64_MAX: none). */
uint64_t adem_pours_next_step(const adem_pours *ps, double dt, uint64_t step);
/* Inserts every batch due at the world's current step (and any overdue one). Leaves the world
 * prepared: neighbour lists rebuilt (history kept), the new particles' forces set to their body
 * forces, and the energy balance extended by their energy. */
adem_status adem_pours_run(adem_pours *ps, adem_world *w, adem_error *err);
/* The pours' state (streams, counts) for checkpoints: a fresh buffer of *len bytes. */
unsigned char *adem_pours_pack(const adem_pours *ps, size_t *len);
adem_status adem_pours_unpack(adem_pours *ps, const unsigned char *buf, size_t len,
                              adem_error *err);

#endif
