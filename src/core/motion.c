/* Prescribed wall motion as a function of time. */
#include "motion.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dmath.h"
#include "log.h"
#include "adem/vec3.h"

/* Checks a servo's settings; the axis made unit, travel limits of 0 and 0 made none. */
static adem_status servo_init(adem_servo_def *s, const adem_servo_def *def, adem_error *err) {
  memset(s, 0, sizeof *s);
  if (!def->on) return ADEM_OK;
  *s = *def;
  s->on = 1;
  s->unmeasured = def->unmeasured != 0;
  double len = v3_norm(def->axis);
  if (!(len > 0.0) || !isfinite(len))
    return adem_error_set(err, ADEM_ERR_INPUT, "servo: the axis must be finite and non-zero");
  s->axis = v3_scale(def->axis, 1.0 / len);
  if (!isfinite(def->target_force))
    return adem_error_set(err, ADEM_ERR_INPUT, "servo: the target force must be finite");
  if (!(def->gain > 0.0) || !isfinite(def->gain))
    return adem_error_set(err, ADEM_ERR_INPUT, "servo: the gain must be > 0 and finite");
  if (!(def->max_speed > 0.0) || !isfinite(def->max_speed))
    return adem_error_set(err, ADEM_ERR_INPUT, "servo: the maximum speed must be > 0 and finite");
  if (!(def->filter >= 0.0) || !isfinite(def->filter))
    return adem_error_set(err, ADEM_ERR_INPUT, "servo: the filter time must be >= 0 and finite");
  if (def->travel_min == 0.0 && def->travel_max == 0.0) {
    s->travel_min = -INFINITY;
    s->travel_max = INFINITY;
  } else if (!(def->travel_min <= 0.0 && def->travel_max >= 0.0)) {
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "servo: the travel [%g, %g] m must hold 0 (where the servo starts)",
                          def->travel_min, def->travel_max);
  }
  return ADEM_OK;
}

adem_status adem_motion_init(adem_motion *m, const adem_motion_def *def, adem_error *err) {
  memset(m, 0, sizeof *m);
  const adem_vec3 *given = def->position ? def->position : def->velocity;
  if (def->n > 0 && !given)
    return adem_error_set(err, ADEM_ERR_INPUT, "motion table without velocities or positions");
  if (def->n > 0 && def->position && def->velocity)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "a motion table gives velocities or positions, not both");
  for (size_t k = 0; k < def->n; ++k) {
    if (!isfinite(def->time[k]) || !v3_isfinite(given[k]))
      return adem_error_set(err, ADEM_ERR_INPUT, "motion table entry %zu is not finite", k);
    if (k > 0 && !(def->time[k] > def->time[k - 1]))
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "motion table is not ordered in time: entry %zu (t = %g s) does not "
                            "come after entry %zu (t = %g s)",
                            k, def->time[k], k - 1, def->time[k - 1]);
  }
  if (!isfinite(def->angular_speed) || !v3_isfinite(def->axis) || !v3_isfinite(def->center))
    return adem_error_set(err, ADEM_ERR_INPUT, "rotation axis, centre and speed must be finite");
  double axis_len = v3_norm(def->axis);
  if (def->angular_speed != 0.0 && !(axis_len > 0.0))
    return adem_error_set(err, ADEM_ERR_INPUT, "a rotating wall needs a non-zero axis");
  adem_status st = servo_init(&m->servo, &def->servo, err);
  if (st) return st;
  m->n = def->n;
  if (m->n > 0) {
    m->time = malloc(m->n * sizeof *m->time);
    m->velocity = malloc(m->n * sizeof *m->velocity);
    m->displacement = malloc(m->n * sizeof *m->displacement);
    if (!m->time || !m->velocity || !m->displacement) {
      adem_motion_free(m);
      return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    }
    memcpy(m->time, def->time, m->n * sizeof *m->time);
    if (def->position) {
      /* positions: exact at the knots; each segment's constant velocity is its slope */
      m->positions = true;
      memcpy(m->displacement, def->position, m->n * sizeof *m->displacement);
      for (size_t k = 0; k + 1 < m->n; ++k)
        m->velocity[k] = v3_scale(v3_sub(m->displacement[k + 1], m->displacement[k]),
                                  1.0 / (m->time[k + 1] - m->time[k]));
      m->velocity[m->n - 1] = v3_zero();
    } else {
      memcpy(m->velocity, def->velocity, m->n * sizeof *m->velocity);
      /* displacement at the first knot: constant velocity from 0 (or back from a knot < 0) */
      m->displacement[0] = v3_scale(m->velocity[0], m->time[0]);
      for (size_t k = 1; k < m->n; ++k) {
        double h = m->time[k] - m->time[k - 1];
        m->displacement[k] = v3_axpy(m->displacement[k - 1], 0.5 * h,
                                     v3_add(m->velocity[k - 1], m->velocity[k]));
      }
    }
  }
  m->axis = axis_len > 0.0 ? v3_scale(def->axis, 1.0 / axis_len) : v3(0.0, 0.0, 1.0);
  m->omega = def->angular_speed;
  m->center = def->center;
  m->moving = m->omega != 0.0;
  for (size_t k = 0; k < m->n; ++k)
    if (v3_norm2(m->velocity[k]) > 0.0 || (m->positions && v3_norm2(m->displacement[k]) > 0.0))
      m->moving = true;
  if (m->servo.on) m->moving = true;
  return ADEM_OK;
}

void adem_motion_free(adem_motion *m) {
  free(m->time);
  free(m->velocity);
  free(m->displacement);
  memset(m, 0, sizeof *m);
}

/* Index k of the segment [time[k], time[k+1]) holding t; -1 before the first knot. */
static long segment(const adem_motion *m, double t) {
  if (m->n == 0 || t < m->time[0]) return -1;
  size_t lo = 0, hi = m->n - 1;
  while (lo < hi) { /* last knot with time <= t */
    size_t mid = (lo + hi + 1) / 2;
    if (m->time[mid] <= t)
      lo = mid;
    else
      hi = mid - 1;
  }
  return (long)lo;
}

/* Velocity at time t counted from t0 (the table's own clock). */
static adem_vec3 velocity_at(const adem_motion *m, double t) {
  long k = segment(m, t);
  if (m->positions) /* held before the first knot and after the last */
    return k < 0 || (size_t)k + 1 >= m->n ? v3_zero() : m->velocity[k];
  if (k < 0) return m->velocity[0];
  if ((size_t)k + 1 >= m->n) return m->velocity[m->n - 1];
  double s = (t - m->time[k]) / (m->time[k + 1] - m->time[k]);
  return v3_add(v3_scale(m->velocity[k], 1.0 - s), v3_scale(m->velocity[k + 1], s));
}

/* The servo's axis component in place of v's. */
static adem_vec3 servo_replace(const adem_motion *m, adem_vec3 v, double along) {
  if (!m->servo.on) return v;
  adem_vec3 a = m->servo.axis;
  return v3_axpy(v3_axpy(v, -v3_dot(v, a), a), along, a);
}

static adem_vec3 prescribed_velocity(const adem_motion *m, double t) {
  if (m->n == 0) return v3_zero();
  return velocity_at(m, t - m->t0);
}

adem_vec3 adem_motion_velocity(const adem_motion *m, double t) {
  return servo_replace(m, prescribed_velocity(m, t), m->servo_v);
}

static adem_vec3 prescribed_displacement(const adem_motion *m, double t);

adem_vec3 adem_motion_displacement(const adem_motion *m, double t) {
  return servo_replace(m, prescribed_displacement(m, t), m->servo_u);
}

static adem_vec3 prescribed_displacement(const adem_motion *m, double t) {
  if (m->n == 0) return v3_zero();
  t -= m->t0;
  long k = segment(m, t);
  if (m->positions) { /* exact at the knots: nothing added at t = time[k] */
    if (k < 0) return m->displacement[0];
    if ((size_t)k + 1 >= m->n) return m->displacement[m->n - 1];
    return v3_axpy(m->displacement[k], t - m->time[k], m->velocity[k]);
  }
  if (k < 0) return v3_scale(m->velocity[0], t);
  double h = t - m->time[k];
  /* trapezoid over [time[k], t] is exact for a linear velocity */
  return v3_axpy(m->displacement[k], 0.5 * h, v3_add(m->velocity[k], velocity_at(m, t)));
}

/* Rodrigues' rotation of v by angle about the unit axis. */
static adem_vec3 rotate(adem_vec3 v, adem_vec3 axis, double angle) {
  /* adem_dmath's cos and sin (the same bits on every host) cost about 50 times libm's: once per
   * angle (bit for bit, so -0 is not 0), not once per vertex of a turning mesh */
  static _Thread_local double last = NAN, c, s;
  if (memcmp(&angle, &last, sizeof angle) != 0) {
    c = adem_dmath_cos(angle);
    s = adem_dmath_sin(angle);
    last = angle;
  }
  adem_vec3 r = v3_scale(v, c);
  r = v3_axpy(r, s, v3_cross(axis, v));
  return v3_axpy(r, v3_dot(axis, v) * (1.0 - c), axis);
}

adem_vec3 adem_motion_place(const adem_motion *m, double t, adem_vec3 x0) {
  adem_vec3 x = x0;
  if (m->omega != 0.0)
    x = v3_add(m->center, rotate(v3_sub(x0, m->center), m->axis, m->omega * (t - m->t0)));
  return v3_add(x, adem_motion_displacement(m, t));
}

adem_vec3 adem_motion_turn(const adem_motion *m, double t, adem_vec3 v0) {
  return m->omega != 0.0 ? rotate(v0, m->axis, m->omega * (t - m->t0)) : v0;
}

adem_vec3 adem_motion_point_velocity(const adem_motion *m, double t, adem_vec3 x) {
  adem_vec3 v = adem_motion_velocity(m, t);
  if (m->omega == 0.0) return v;
  adem_vec3 c = v3_add(m->center, adem_motion_displacement(m, t));
  return v3_add(v, v3_cross(v3_scale(m->axis, m->omega), v3_sub(x, c)));
}

double adem_motion_max_shift(const adem_motion *m, double t0, double t1, double reach) {
  adem_vec3 dd = v3_sub(prescribed_displacement(m, t1), prescribed_displacement(m, t0));
  double d = v3_norm(servo_replace(m, dd, 0.0));
  /* the servo's past positions are not kept: bounded by its largest speed */
  if (m->servo.on) d += m->servo.max_speed * fabs(t1 - t0);
  return d + fabs(m->omega * (t1 - t0)) * reach;
}

adem_status adem_motion_copy(adem_motion *dst, const adem_motion *src, adem_error *err) {
  adem_motion_def d = {src->n, src->time, src->positions ? NULL : src->velocity,
                       src->axis, src->omega, src->center,
                       src->positions ? src->displacement : NULL, src->servo};
  if (d.servo.on && isinf(d.servo.travel_min) && isinf(d.servo.travel_max))
    d.servo.travel_min = d.servo.travel_max = 0.0; /* none, as servo_init reads it */
  adem_status st = adem_motion_init(dst, &d, err);
  if (!st) dst->t0 = src->t0;
  return st;
}

/* The same motion table, axis and centre (t0 aside). */
bool adem_motion_same(const adem_motion *a, const adem_motion *b) {
  if (a->n != b->n || a->omega != b->omega || a->positions != b->positions) return false;
  if (memcmp(&a->axis, &b->axis, sizeof a->axis) || memcmp(&a->center, &b->center, sizeof a->center))
    return false;
  const adem_servo_def *sa = &a->servo, *sb = &b->servo;
  if (sa->on != sb->on) return false;
  if (sa->on && (memcmp(&sa->axis, &sb->axis, sizeof sa->axis) || sa->target_force != sb->target_force ||
                 sa->gain != sb->gain || sa->max_speed != sb->max_speed || sa->filter != sb->filter ||
                 sa->travel_min != sb->travel_min || sa->travel_max != sb->travel_max ||
                 sa->unmeasured != sb->unmeasured))
    return false;
  return a->n == 0 || (!memcmp(a->time, b->time, a->n * sizeof *a->time) &&
                       !memcmp(a->velocity, b->velocity, a->n * sizeof *a->velocity) &&
                       !memcmp(a->displacement, b->displacement, a->n * sizeof *a->displacement));
}


void adem_motion_save(adem_writer *wr, const adem_motion *m) {
  adem_put_array(wr, m->time, m->n, sizeof *m->time);
  adem_put_array(wr, m->velocity, m->n, sizeof *m->velocity);
  adem_put_array(wr, m->displacement, m->n, sizeof *m->displacement);
  adem_put_vec(wr, m->axis);
  adem_put_f64(wr, m->omega);
  adem_put_vec(wr, m->center);
  adem_put_u8(wr, m->moving ? 1 : 0);
  adem_put_u8(wr, m->positions ? 1 : 0);
  adem_put_f64(wr, m->t0);
  const adem_servo_def *sv = &m->servo;
  adem_put_i32(wr, sv->on);
  adem_put_vec(wr, sv->axis);
  adem_put_f64(wr, sv->target_force);
  adem_put_f64(wr, sv->gain);
  adem_put_f64(wr, sv->max_speed);
  adem_put_f64(wr, sv->filter);
  adem_put_f64(wr, sv->travel_min);
  adem_put_f64(wr, sv->travel_max);
  adem_put_i32(wr, sv->unmeasured);
  adem_motion_save_servo(wr, m);
}

void adem_motion_save_servo(adem_writer *wr, const adem_motion *m) {
  adem_put_f64(wr, m->servo_u);
  adem_put_f64(wr, m->servo_v);
  adem_put_f64(wr, m->servo_force);
  adem_put_u8(wr, m->servo_started ? 1 : 0);
}

void adem_motion_load_servo(adem_reader *rd, adem_motion *m) {
  m->servo_u = adem_get_f64(rd);
  m->servo_v = adem_get_f64(rd);
  m->servo_force = adem_get_f64(rd);
  m->servo_started = adem_get_u8(rd) != 0;
}

adem_status adem_motion_load(adem_reader *rd, adem_motion *m, adem_error *err) {
  memset(m, 0, sizeof *m);
  uint64_t n = adem_get_count(rd, sizeof(double));
  if (rd->failed) return ADEM_OK;
  if (n > 0) {
    m->time = malloc((size_t)n * sizeof *m->time);
    m->velocity = malloc((size_t)n * sizeof *m->velocity);
    m->displacement = malloc((size_t)n * sizeof *m->displacement);
    if (!m->time || !m->velocity || !m->displacement) {
      adem_motion_free(m);
      return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    }
  }
  m->n = (size_t)n;
  adem_get(rd, m->time, m->n * sizeof *m->time);
  adem_get_array(rd, m->velocity, m->n, sizeof *m->velocity);
  adem_get_array(rd, m->displacement, m->n, sizeof *m->displacement);
  m->axis = adem_get_vec(rd);
  m->omega = adem_get_f64(rd);
  m->center = adem_get_vec(rd);
  m->moving = adem_get_u8(rd) != 0;
  m->positions = adem_get_u8(rd) != 0;
  m->t0 = adem_get_f64(rd);
  adem_servo_def *sv = &m->servo;
  sv->on = adem_get_i32(rd);
  sv->axis = adem_get_vec(rd);
  sv->target_force = adem_get_f64(rd);
  sv->gain = adem_get_f64(rd);
  sv->max_speed = adem_get_f64(rd);
  sv->filter = adem_get_f64(rd);
  sv->travel_min = adem_get_f64(rd);
  sv->travel_max = adem_get_f64(rd);
  sv->unmeasured = adem_get_i32(rd);
  adem_motion_load_servo(rd, m);
  return ADEM_OK;
}
