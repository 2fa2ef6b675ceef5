/* The free surface of a rotating drum (`adem analyze drum OUTDIR`): from a run's particle frames
 * (positions, velocities) and its checkpoint (the drum's cylinder wall, its rotation, the
 * particles' masses, gravity) and CSV (the drum's torque about its axis). Per frame: the dynamic
 * angle of the free surface by a profile fit of the surface particles in the cross-section and
 * by the bed's centre of mass, the flowing layer's thickness along the normal to the surface
 * through the drum's axis, and the wall layer's co-rotation; over the frames: the regime
 * (rolling or slumping) from the angle's time series, and the torque balance. */
#ifndef ADEM_DRUM_H
#define ADEM_DRUM_H

#include <stddef.h>

#include "adem/base.h"
#include "adem/frames.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct adem_drum_options {
  double from;              /* s: frames at or after this time (NaN: the last two thirds of the run) */
  char wall[ADEM_NAME_MAX]; /* the drum's cylinder wall ("": the first cylinder) */
} adem_drum_options;
adem_drum_options adem_drum_default_options(void);

typedef struct adem_drum_frame {
  double time;
  double angle_fit_deg; /* profile fit of the surface particles (middle half of the chord) */
  double fit_r2;
  double angle_cm_deg; /* the bed's centre of mass from the bottom, about the axis */
  double layer_m;      /* flowing layer: depth below the surface where the streamwise
                          velocity changes sign, on the normal through the axis (NaN: none) */
  double corotation;   /* wall layer: mean tangential speed / the drum's at their centres */
  double slip_m_s;     /* wall layer: mean speed of the drum at their centres less theirs */
  double moment_Nm;    /* the bed's gravity moment about the axis, m g x_cm */
  size_t wall_layer;   /* particles in the wall layer */
} adem_drum_frame;

typedef struct adem_drum_report {
  double radius, omega, froude; /* the drum: R (m), rad/s, omega^2 R / g */
  double mass;                  /* of the bed, kg */
  size_t particles, nframes;
  adem_drum_frame *frames;
  /* means over the frames and their standard deviations */
  double angle_fit_deg, angle_fit_sd, angle_cm_deg, angle_cm_sd, layer_m, corotation, slip_m_s;
  double moment_Nm;   /* mean gravity moment m g x_cm */
  double torque_Nm;   /* mean drive torque about the axis over the same times (CSV) */
  size_t torque_rows; /* CSV rows averaged (0: no torque column) */
  /* regime: the angle's excursion (max - min), the skewness of its frame-to-frame changes
   * (a sawtooth: slow rises, sudden drops, strongly negative) and the drops above 1 deg */
  double excursion_deg, skewness;
  size_t drops;
  size_t slipping_frames;    /* frames whose wall layer turns at less than half the drum's rate */
  char regime[16];           /* "rolling", "slumping", or "slipping" (the bed slides back along
                                the wall in a tenth of the frames or more: a smooth wall) */
  char csv[1024], png[1024]; /* written files */
} adem_drum_report;

/* One frame's measures for a drum given explicitly (mass: each particle's, kg): what
 * adem_drum_analyze does with every frame. */
typedef struct adem_drum_geometry {
  adem_vec3 point, axis; /* a point of the axis, its direction */
  double radius, omega;  /* m; rad/s, right-handed about axis */
  adem_vec3 gravity;
} adem_drum_geometry;
adem_status adem_drum_measure(const adem_drum_geometry *geo, const adem_vtu_frame *f,
                              const double *mass, adem_drum_frame *out, adem_error *err);

adem_status adem_drum_analyze(const char *outdir, const adem_drum_options *opt,
                              adem_drum_report *rep, adem_error *err);
void adem_drum_report_free(adem_drum_report *rep);

#ifdef __cplusplus
}
#endif

#endif
