/* Coarse-grained continuum fields of a particle system (docs/fields.md): density, solid fraction,
 * velocity, kinetic and contact stress, coordination number, fabric and granular temperature on
 * a regular grid, by the kernel method of Goldhirsch (2010) and Weinhart et al. (2012): every
 * particle spreads its mass, momentum, ... over the grid with a kernel phi centred on it, and every
 * contact spreads f (x) l along its branch line l (the line integral of phi), so that the
 * coarse-grained stress balances the momentum.
 *
 * Plain arrays and status codes: a frame is given as arrays of particles and contacts
 * (adem_fields_add), any number of frames are averaged, and the result is read back as arrays
 * (adem_fields_get) or written as VTK ImageData (.vti) and CSV. adem_fields_run does all of it on
 * a run's output folder (particle frames with their contact frames, output.contacts). */
#ifndef ADEM_FIELDS_H
#define ADEM_FIELDS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adem/base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum adem_fields_kernel {
  ADEM_KERNEL_GAUSSIAN = 0, /* exp(-x^2 / 2w^2) per axis, cut off at |x| = cutoff * w per axis */
  ADEM_KERNEL_LUCY = 1      /* Lucy's polynomial (1 + 3q)(1 - q)^3, q = r / c, support radius
                             * c = sqrt(12) w (the same variance w^2 per axis as the Gaussian) */
} adem_fields_kernel;

/* The grid and the kernel. Nodes are the centres of cells of side `cell`: along axis a there are
 * n[a] = ceil((hi[a] - lo[a]) / cell) of them at lo[a] + (k + 1/2) cell, the last cell ending at
 * or beyond hi[a]. An averaged axis (average[a] = 1) has one node: the fields are means over
 * [lo[a], hi[a]] of the 3-D ones, taken as each particle's and contact's whole kernel weight
 * over that length (the kernel's marginal), so nothing is lost at the ends of the range. */
typedef struct adem_fields_options {
  adem_fields_kernel kernel;
  double width;        /* w, m: the kernel's standard deviation along an axis */
  double cutoff;       /* Gaussian: cut off at cutoff * w along each axis (default 3) */
  double cell;         /* grid spacing, m */
  double lo[3], hi[3]; /* the grid's extent, m */
  bool average[3];     /* true: average over that axis */
} adem_fields_options;
adem_fields_options adem_fields_default_options(void);

/* One frame's particles (n of them; arrays of n or 3n doubles, x y z per particle). */
typedef struct adem_fields_particles {
  size_t n;
  const double *pos;    /* 3n, m */
  const double *vel;    /* 3n, m/s; NULL: at rest */
  const double *mass;   /* n, kg */
  const double *radius; /* n, m (the solid fraction counts 4/3 pi r^3) */
  const int64_t *id;    /* n stable ids: the contacts name particles by them */
} adem_fields_particles;

/* One frame's contacts: each from particle id_a's centre p0 to p1 (particle id_b's centre as a
 * sees it, or a wall's contact point), with the force on a (on b the opposite). */
typedef struct adem_fields_contacts {
  size_t n;
  const double *p0, *p1, *force; /* 3n each */
  const int32_t *kind;           /* 0 particle pair, 1 plane, 2 mesh (walls have no b) */
  const int64_t *id_a, *id_b;
} adem_fields_contacts;

/* The fields, each stored per node (x fastest, then y, then z) with its number of components;
 * tensors as 9 components xx xy xz yx yy yz zx zy zz, T_ab = sum of f_a l_b. Stress is
 * compressive positive: a bed at rest has sigma_zz = the weight per area above. */
typedef enum adem_field {
  ADEM_CG_DENSITY = 0,    /* rho = sum m phi, kg/m^3 */
  ADEM_CG_SOLID_FRACTION, /* nu = sum (4/3 pi r^3) phi */
  ADEM_CG_MOMENTUM,       /* 3: j = sum m v phi, kg/(m^2 s) */
  ADEM_CG_VELOCITY,       /* 3: V = j / rho, m/s (0 where rho = 0) */
  ADEM_CG_KINETIC_STRESS, /* 9: sum m v v phi - rho V V, Pa */
  ADEM_CG_CONTACT_STRESS, /* 9: sum over contacts of f (x) l psi, l = p0 - p1 (a's centre
                           * minus b's, or minus the wall's contact point), psi the line
                           * integral of phi from p0 to p1, Pa */
  ADEM_CG_STRESS,         /* 9: kinetic + contact, Pa */
  ADEM_CG_PRESSURE,       /* trace(stress) / 3, Pa */
  ADEM_CG_COORDINATION,   /* sum c_i phi / sum phi: the kernel-weighted mean number of
                           * contacts (particles and walls) per particle */
  ADEM_CG_FABRIC,         /* 9: sum (4/3 pi r_i^3) phi sum over i's contacts n n, n the
                           * unit vector along the contact's line (trace = nu Z) */
  ADEM_CG_TEMPERATURE,    /* trace(kinetic stress) / (3 rho), m^2/s^2 */
  ADEM_CG_COUNT_
} adem_cg_field;
int adem_cg_field_components(adem_cg_field f);
const char *adem_cg_field_name(adem_cg_field f); /* "density", "contact_stress", ... */

typedef struct adem_fields adem_fields;

/* A grid for the options (checked: width, cell > 0, lo < hi, at most 2 averaged axes and at most
 * ADEM_FIELDS_MAX_NODES nodes). */
#define ADEM_FIELDS_MAX_NODES ((size_t)1 << 25) /* 33.5 million: 7.5 GB of accumulators */
adem_status adem_fields_create(const adem_fields_options *opt, adem_fields **out, adem_error *err);
void adem_fields_free(adem_fields *f);
/* Adds one frame (a time average over the frames added). Contacts naming a particle id that is
 * not in the frame are refused. */
adem_status adem_fields_add(adem_fields *f, const adem_fields_particles *p,
                            const adem_fields_contacts *c, adem_error *err);
size_t adem_fields_frames(const adem_fields *f);
/* Node counts along x, y, z (1 along an averaged axis), the first node's centre and the spacing. */
void adem_fields_grid(const adem_fields *f, size_t n[3], double origin[3], double *cell);
/* The field averaged over the frames added, n[0] n[1] n[2] x components doubles into out
 * (capacity doubles). ADEM_ERR_INPUT when nothing was added or out is too small. */
adem_status adem_fields_get(const adem_fields *f, adem_cg_field field, double *out, size_t capacity,
                            adem_error *err);
/* The grid integral of a field: sum over nodes of value x cell volume (an averaged axis counts
 * its length lo..hi), per component (out: components doubles). */
adem_status adem_fields_integral(const adem_fields *f, adem_cg_field field, double *out,
                                 adem_error *err);

/* Adds the world's present state as one frame: its particles (adem_world_get_particles) and the
 * contacts of its last force pass (adem_world_contact_frame), as adem_fields_add takes them. */
typedef struct adem_world adem_world;
adem_status adem_fields_add_world(adem_fields *f, const adem_world *w, adem_error *err);
/* sizeof the named struct of this header (adem_fields_options, adem_fields_run_options,
 * adem_fields_run_info), 0 for another name: bindings compare it with their mirrors, as
 * adem_abi_sizeof (adem/binding.h) does for the layers below. */
size_t adem_fields_abi_sizeof(const char *type);

/* Every field as VTK ImageData (.vti, appended raw, point data on the nodes); atomic. */
adem_status adem_fields_write_vti(const adem_fields *f, const char *path, adem_error *err);
/* Every field as CSV, one row per node: x_m,y_m,z_m (the averaged axes left out), then the
 * fields' components (density_kg_m3, ..., contact_stress_zz_Pa, ...); atomic. */
adem_status adem_fields_write_csv(const adem_fields *f, const char *path, adem_error *err);

/* ---- on a run's output folder ---- */

typedef struct adem_fields_run_options {
  adem_fields_options grid; /* lo/hi ignored unless box_given */
  bool box_given;           /* false: the grid spans the particles' centres (over the frames
                             * used) and reaches cutoff widths (Lucy: its support) beyond them,
                             * so that no kernel is cut by the grid's edge; an averaged axis
                             * spans the particles' extent (centre +- radius) */
  double width_diameters;   /* > 0: the width is this many mean diameters (of the first frame
                             * used), grid.width ignored */
  double cell_diameters;    /* > 0: the cell is this many mean diameters; else grid.cell, and
                             * grid.cell <= 0 is half the width */
  double t0, t1;            /* the frames with t0 <= time <= t1 (t1 < t0: every frame) */
  bool last_only;           /* true: only the last frame in the window */
} adem_fields_run_options;
adem_fields_run_options adem_fields_default_run_options(void);

/* What adem_fields_run used. */
typedef struct adem_fields_run_info {
  size_t frames;               /* frames averaged */
  double t_first, t_last;      /* their times */
  size_t particles, contacts;  /* of the last one */
  double width, mean_diameter; /* m */
  double mass;                 /* total particle mass of the last frame, kg */
} adem_fields_run_info;

/* Reads the particle frames of DIR (particles.pvd) in the window and the contact frame of each
 * (contacts.pvd: a frame without one is refused: switch output.contacts on), and averages their
 * fields. Frames need the mass array (adem writes it; ADEM_ERR_INPUT otherwise). */
adem_status adem_fields_run(const char *dir, const adem_fields_run_options *opt,
                            adem_fields **out, adem_fields_run_info *info, adem_error *err);

#ifdef __cplusplus
}
#endif
#endif
