/* Prescribed motion of a wall: a piecewise-linear translation velocity in time and a constant
 * rotation about an axis through a centre that travels with the translation. Positions are a
 * function of time alone (no integration), so a restarted run places the walls exactly. */
#ifndef ADEM_MOTION_H
#define ADEM_MOTION_H

#include <stdbool.h>
#include <stddef.h>
#include "adem/world.h"
#include "stream.h"

typedef struct adem_motion {
  size_t n;
  double *time;
  /* a velocity table: the velocity at each knot; positions: the velocity of the segment that
   * starts at each knot (0 for the last) */
  adem_vec3 *velocity;
  adem_vec3 *displacement; /* integral of the velocity from 0 to each knot (positions: given) */
  bool positions;          /* the table gives positions (a piecewise-linear displacement) */
  adem_vec3 axis;          /* unit */
  double omega;
  adem_vec3 center;
  bool moving;
  /* Time the motion starts from (0 unless a stage changed the motion): the table's times, the
   * rotation angle and the placement of x0 all count from t0. */
  double t0;
  /* Servo along servo.axis (servo.on): its definition, and its state, integrated by the walls
   * (walls.c) rather than a function of time, hence saved in checkpoints. */
  adem_servo_def servo;
  double servo_u;     /* displacement along the axis since the motion began, m */
  double servo_v;     /* velocity along the axis over the last step, m/s */
  double servo_force; /* measured force along the axis (filtered), N */
  bool servo_started; /* servo_force holds a measurement */
  bool servo_warned;  /* its gain has been found too high (a message, not state) */
} adem_motion;

/* Checks the table (finite, times strictly increasing) and copies it; a table of positions
 * (def->position) is turned into its segments' velocities. */
adem_status adem_motion_init(adem_motion *m, const adem_motion_def *def, adem_error *err);
void adem_motion_free(adem_motion *m);

adem_vec3 adem_motion_velocity(const adem_motion *m, double t);
/* Translation from time 0 to t: the exact integral of the piecewise-linear velocity. */
adem_vec3 adem_motion_displacement(const adem_motion *m, double t);
/* Where a point of the wall that was at x0 at time 0 is at time t. */
adem_vec3 adem_motion_place(const adem_motion *m, double t, adem_vec3 x0);
/* A direction of the wall (a normal) at time t. */
adem_vec3 adem_motion_turn(const adem_motion *m, double t, adem_vec3 v0);
/* Velocity of the wall's material at the point x at time t: v + omega axis x (x - centre(t)). */
adem_vec3 adem_motion_point_velocity(const adem_motion *m, double t, adem_vec3 x);
/* An upper bound on how far any point within `reach` of the centre moves between t0 and t1. */
double adem_motion_max_shift(const adem_motion *m, double t0, double t1, double reach);

/* A copy of src (its table duplicated), t0 included. */
adem_status adem_motion_copy(adem_motion *dst, const adem_motion *src, adem_error *err);
/* The same motion table (of the same kind), axis and centre (t0 aside). */
bool adem_motion_same(const adem_motion *a, const adem_motion *b);

/* The servo's state (not its definition), exactly. */
void adem_motion_save_servo(adem_writer *wr, const adem_motion *m);
void adem_motion_load_servo(adem_reader *rd, adem_motion *m);

/* Every field, exactly (a restart places the wall bit for bit). */
void adem_motion_save(adem_writer *wr, const adem_motion *m);
adem_status adem_motion_load(adem_reader *rd, adem_motion *m, adem_error *err);

#endif
