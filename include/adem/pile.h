/* The angle of repose of a pile of spheres on a horizontal floor, by two methods:
 *
 * (a) surface fit: the particles are binned by radial distance from the pile's axis (rings one
 *     bin width wide) and by angular sector (cells of equal area, `cell_arc` bin widths along
 *     the arc); the highest centre of each cell is a surface particle. A line z = a + b rho is
 *     fitted to the surface particles over the middle band of the pile's height, by orthogonal
 *     least squares (the particles scatter across the slope, not only vertically); the band is
 *     mapped onto the slope by a first fit so that the selection does not trim the scatter;
 *     angle = atan(-b).
 * (b) slices: horizontal planes cut the pile; each plane's footprint is the region inside the
 *     star-shaped envelope of the particles' cross-sections seen from the axis (along each of a
 *     fan of rays, the farthest edge of a cross-section the ray crosses); its equivalent radius
 *     r_eq is the envelope's mean distance from the axis (by default) or sqrt(A / pi), equal
 *     for a circle. A line r_eq = c + k z is fitted over the same band (ordinary least squares:
 *     the heights are exact); angle = atan(-1 / k).
 * (c) the laboratory angle (the primary measure of issue 30, docs/validation.md "The measure"):
 *     rings one mean diameter wide about the axis; a ring's top is the highest sphere top
 *     (centre + radius) among the spheres centred in it. The skirt level h_e = (d_max +
 *     1.8 d_min) / 2 lies between the top of a sphere on the floor (at most d_max) and that of a
 *     sphere resting on others (at least (1 + sqrt(2/3)) d_min). The continuous base: the rings
 *     from the axis out to, not including, the first ring whose top is below h_e, so a skirt of
 *     spheres one layer high that rolled away is never base, however far it reaches. R_base:
 *     the mean over `lab_sectors` sectors of the largest distance from the axis of a base sphere
 *     whose top is at least h_e. Angle = atan((H - h_e) / R_base): height and base are both taken
 *     from the skirt's level, which cancels for spheres whose tops lie on a cone. NaN when fewer
 *     than half the sectors have such a sphere (no pile two layers high: the spheres rolled away).
 * (d) the ring-top line: ordinary least squares of the ring tops against the rings' mid-radius
 *     over the rings of the continuous base whose top lies in [ring_lo, ring_hi] H.
 *
 * Plain C on arrays of centres and radii; it depends on no engine module (only the adem_vec3,
 * adem_status and adem_error types of the public header), so it runs on any frame, synthetic
 * piles included. See the definitions of the band, bins and rays at adem_pile_default_options. */
#ifndef ADEM_PILE_H
#define ADEM_PILE_H

#include <stdbool.h>
#include <stddef.h>

#include "adem/base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The equivalent radius of a slice's footprint (see slice_req in pile.c for the comparison). */
typedef enum adem_pile_slice_radius {
  ADEM_PILE_MEAN_RADIUS = 0, /* mean distance of the footprint's boundary from the axis */
  ADEM_PILE_AREA_RADIUS = 1  /* sqrt(A / pi) */
} adem_pile_slice_radius;

typedef struct adem_pile_options {
  double floor_z;  /* height of the floor, m */
  bool axis_given; /* true: the pile's axis is (axis_x, axis_y); false: derived (see below) */
  double axis_x, axis_y;
  double band_lo, band_hi; /* the fit band, as fractions of the pile's height H */
  double cell_arc;         /* length along the arc of a cell of method (a), in bin widths */
  double bin_width;        /* radial bin width of method (a), m; <= 0: the mean diameter */
  int rays;                /* rays of the slice envelope, method (b) */
  double slice_step;       /* distance between slice planes, m; <= 0: a quarter of the mean diameter */
  adem_pile_slice_radius slice_radius;
  double zmax;             /* centres higher than floor_z + zmax are not the pile (<= 0: no limit),
                              e.g. spheres still in a hopper above it */
  double rmax;             /* centres farther than rmax from the axis are not the pile (<= 0: no
                              limit), e.g. spheres that bounced away */
  double ring_lo, ring_hi; /* band of the ring-top line, fractions of H (0.2, 0.8) */
  int lab_sectors;         /* sectors over which R_base is averaged, method (c) (8) */
  double skirt_level;      /* h_e of method (c), m; <= 0: (d_max + 1.8 d_min) / 2 of the pile */
} adem_pile_options;

/* floor 0, axis derived, band 0.25..0.75 of H (clear of the rounded top and of the toe), cells
 * of one mean diameter by two, 720 rays, slices every quarter diameter with the mean radius, no
 * limits; ring-top band 0.2..0.8 of H, 8 sectors for R_base, skirt level derived. */
adem_pile_options adem_pile_default_options(void);

/* A fitted line over n points: for the surface fit z = intercept + slope rho (orthogonal least
 * squares), for the slices r_eq = intercept + slope z (ordinary least squares); r2 is the
 * squared correlation coefficient of the points (R^2 of the ordinary fit). */
typedef struct adem_pile_fit {
  size_t n;
  double slope, intercept, r2;
} adem_pile_fit;

/* A point of a profile: rho (radial distance from the axis, or r_eq) and z (height above the
 * floor), both m; used is true when the point is inside the fit band and entered the fit. */
typedef struct adem_pile_point {
  double rho, z;
  bool used;
} adem_pile_point;

typedef struct adem_pile_result {
  size_t n_pile;               /* particles counted as the pile */
  double axis_x, axis_y;       /* axis used */
  double height;               /* H: top of the highest sphere above the floor, m */
  double base_radius;          /* the slice fit's r_eq at the floor: the fitted cone's base, m */
  double footprint_radius;     /* r_eq of the slice half a mean diameter above the floor, m,
                                  spheres that rolled away included */
  double mean_diameter;        /* of the pile's particles, m */
  double band_zmin, band_zmax; /* the fit band above the floor, m */
  /* (a) surface fit: z = intercept + slope rho */
  double angle_surface_deg;
  adem_pile_fit surface;
  adem_pile_point *surface_pts; /* every surface particle (one per occupied bin) */
  size_t n_surface_pts;
  /* (b) slices: r_eq = intercept + slope z */
  double angle_slices_deg;
  adem_pile_fit slices;
  adem_pile_point *slice_pts; /* (r_eq, z) of every slice plane */
  size_t n_slice_pts;
  /* (c) laboratory angle: atan((height - skirt_level) / lab_base_radius) */
  double angle_lab_deg;
  double angle_lab_plain_deg; /* atan(height / lab_base_radius), for comparison */
  double skirt_level;         /* h_e, m */
  double lab_base_radius;     /* R_base, m */
  double lab_base_sd;         /* standard deviation of R_base over the sectors, m */
  size_t base_rings;          /* rings in the continuous base */
  /* (d) ring-top line: top = intercept + slope rho */
  double angle_ringtop_deg;
  adem_pile_fit ringtop;
  adem_pile_point *ring_pts; /* (mid-radius, top) of every ring out to the last occupied one;
                                used = 1: in the line's fit */
  size_t n_ring_pts;
  /* (e) height over footprint: atan(height / footprint_radius), the crude figure of old */
  double angle_footprint_deg;
} adem_pile_result;

/* Measures the pile formed by the n spheres (centres pos, radii radius). The axis, when not
 * given, is the volume-weighted centroid (x, y) of the pile's particles. Fails with
 * ADEM_ERR_INPUT when the input is unusable (no particle above the floor, non-finite values,
 * bad options, fewer than 3 points in a band) and ADEM_ERR_NOMEM; *res is then zeroed. Free the
 * result with adem_pile_result_free. */
adem_status adem_pile_measure(const adem_vec3 *pos, const double *radius, size_t n,
                              const adem_pile_options *opt, adem_pile_result *res,
                              adem_error *err);

void adem_pile_result_free(adem_pile_result *res);

/* The last particle frame of a run's output folder (OUTDIR/frames/particles_NNNNNN.vtu); *path a
 * fresh string. */
adem_status adem_frames_last(const char *outdir, char **path, adem_error *err);

/* `adem analyze repose OUTDIR`: the pile in the last frame of a run, measured with opt, and its
 * profile written beside the run's files as OUTDIR/repose_profile.csv and .png, and every
 * measure as one row of OUTDIR/repose_measures.csv (header: quantity_unit). */
typedef struct adem_repose_report {
  char frame[4096]; /* the frame measured */
  double time;      /* its time, s */
  size_t particles; /* in the frame */
  adem_pile_result pile;
  char profile_csv[4096], profile_png[4096], measures_csv[4096];
} adem_repose_report;
adem_status adem_repose_analyze(const char *outdir, const adem_pile_options *opt,
                                adem_repose_report *rep, adem_error *err);
void adem_repose_report_free(adem_repose_report *rep);

#ifdef __cplusplus
}
#endif

#endif
