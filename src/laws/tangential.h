/* Tangential spring-dashpot with history and a Coulomb limit (H14, H16, H17), in two forms:
 *  - incremental (the default): the history is the spring force itself, changed by
 *    dF = -S_t ds each step and scaled down with S_t when the contact shrinks (Mindlin and
 *    Deresiewicz 1953; LAMMPS `tangential mindlin_rescale/force`). A normal load that rises at a
 *    fixed tangential displacement leaves the force as it is, so the law cannot create energy.
 *  - total (H14 as written): F = -S_t(delta) xi on the accumulated displacement xi. When the load
 *    rises at fixed xi the force rises with no work done on the contact: a closed load path can
 *    give energy out (docs/models.md).
 * Both report the energy stored in the spring and the energy they dissipated in the step (slip
 * at the Coulomb limit, and for the incremental law the spring energy released by a change of
 * S_t), so that the run's energy balance can be closed from the laws' own bookkeeping. */
#ifndef ADEM_CONTACT_TANGENTIAL_H
#define ADEM_CONTACT_TANGENTIAL_H

#include "law_inline.h"

#include <stdbool.h>
#include "adem/vec3.h"

/* Keeps the history xi in the tangent plane of the unit normal n, with its length unchanged, so a
 * rotating contact does not lose or gain stored spring energy. */
ADEM_LAW adem_vec3 adem_tangential_project(adem_vec3 xi, adem_vec3 n) {
  double len2 = v3_norm2(xi);
  if (len2 == 0.0) return xi;
  adem_vec3 p = v3_axpy(xi, -v3_dot(xi, n), n);
  double p2 = v3_norm2(p);
  if (p2 == 0.0) return v3_zero();
  return v3_scale(p, sqrt(len2 / p2));
}

/* One step of a tangential law. */
typedef struct adem_tangential_input {
  adem_vec3 n;       /* unit normal from i to j */
  adem_vec3 vt;      /* slip velocity of i's surface relative to j's (tangent plane), at the
                      * half step: the slip of the step is vt dt */
  adem_vec3 vt_damp; /* the same predicted at the full step, for the dashpot */
  double dt;
  double stiffness; /* S_t = 8 G sqrt(R delta) (H14) */
  double damping;   /* c_t of the dashpot, force -c_t vt (H16) */
  double f_limit;   /* Coulomb limit mu |F_N + 2 F_C| (H17) */
  double mobility;  /* the change of the slip velocity per unit tangential force on i over the
                     * closing half kick, (1/m_i + r_i^2/I_i + 1/m_j + r_j^2/I_j) dt/2; 0: the
                     * dashpot takes vt_damp as it is. Else vt_damp leaves out this contact's own
                     * force of the last pass, and the dashpot takes the slip velocity at the full
                     * step implicitly: (vt_damp + mobility F_spring)/(1 + c_t mobility), with
                     * this pass's spring force (adem_tangential_damping_velocity) */
} adem_tangential_input;

/* The velocity the tangential dashpot takes: the slip at the full step with this contact's own
 * spring force of this pass and its own dashpot force -c_t v solved for (implicit). An explicit
 * dashpot on a predicted velocity is a two-step recurrence that is unstable above
 * c_t dt/(2 m_t) ~ 1 (docs/models.md, "Time step"); the implicit one is stable for any c_t. */
ADEM_LAW adem_vec3 adem_tangential_damping_velocity(const adem_tangential_input *in,
                                                    adem_vec3 spring) {
  double m = in->mobility;
  return v3_scale(v3_axpy(in->vt_damp, m, spring), 1.0 / (1.0 + in->damping * m));
}

typedef struct adem_tangential_output {
  adem_vec3 force;   /* on i: spring + dashpot, within the limit */
  adem_vec3 dashpot; /* the dashpot's part of force (0 while sliding: the spring carries the limit) */
  double elastic;    /* energy stored in the spring, J */
  double dissipated; /* energy the law dissipated in this step, J (slip; load changes) */
  bool sliding;
} adem_tangential_output;

/* H14 with the total displacement: xi <- project(xi) + vt dt, F = -S_t xi - c_t vt, limited to
 * f_limit (H17); when sliding xi is reset so that the spring alone carries the limit. The slip's
 * dissipation is the mean spring force times the slip, (1/2) S_t (xi_old + xi_new).(xi_trial -
 * xi_new), the same trapezoid the integrator's work follows. aux: the S_t of the pass (read only
 * when a stage switches the law: F_s = -S_t xi is then exact). */
ADEM_LAW void adem_tangential_total(const adem_tangential_input *in, adem_vec3 *xi,
                                    double *aux, adem_tangential_output *out) {
  double S = in->stiffness;
  adem_vec3 x0 = adem_tangential_project(*xi, in->n);
  adem_vec3 x = v3_axpy(x0, in->dt, in->vt);
  adem_vec3 dash = v3_scale(adem_tangential_damping_velocity(in, v3_scale(x, -S)), -in->damping);
  adem_vec3 f = v3_add(v3_scale(x, -S), dash);
  double fmag2 = v3_norm2(f);
  out->sliding = false;
  out->dissipated = 0.0;
  if (fmag2 > in->f_limit * in->f_limit) {
    f = v3_scale(f, in->f_limit / sqrt(fmag2));
    adem_vec3 xn = S > 0.0 ? v3_scale(f, -1.0 / S) : v3_zero();
    out->dissipated = 0.5 * S * v3_dot(v3_add(x0, xn), v3_sub(x, xn));
    x = xn;
    dash = v3_zero();
    out->sliding = true;
  }
  *xi = x;
  *aux = S;
  out->force = f;
  out->dashpot = dash;
  out->elastic = 0.5 * S * v3_norm2(x);
}

/* Incremental (Mindlin-Deresiewicz): fs is the spring force on i, aux the S_t it was stored
 * with. fs is turned into the tangent plane, scaled by S_t/S_t,old when the contact shrinks
 * (unloading), kept when it grows (loading: the new annulus sticks without traction), then
 * fs <- fs - S_t vt dt (dF = -S_t ds). Coulomb (H17): the spring is limited to f_limit (slip),
 * then spring + dashpot -c_t vt is limited to f_limit by shortening the dashpot's part, so the
 * spring never stores more than the displacement put in. Stored energy |fs|^2/(2 S_t).
 * Dissipated: the work the relative motion did on the spring in the step, -(fs_old + fs_new)/2 .
 * vt dt (the trapezoid the integrator's kicks follow, with the force as it was applied), less
 * the change of the stored energy: the slip, the energy a change of S_t releases (both ways it
 * lowers |fs|^2/(2 S_t)), and nothing while it sticks (dF = -S_t ds is linear: the trapezoid is
 * exact). The dashpot's share is the integrator's (it is reported apart). */
ADEM_LAW void adem_tangential_incremental(const adem_tangential_input *in, adem_vec3 *fs,
                                          double *aux, adem_tangential_output *out) {
  double S = in->stiffness, S_old = *aux, L = in->f_limit;
  adem_vec3 f_prev = *fs;
  double u_prev = S_old > 0.0 ? 0.5 * v3_norm2(f_prev) / S_old : 0.0;
  adem_vec3 f0 = adem_tangential_project(f_prev, in->n);
  if (S_old > S) f0 = v3_scale(f0, S / S_old);         /* unloading: LAMMPS mindlin_rescale */
  adem_vec3 spring = v3_axpy(f0, -S * in->dt, in->vt); /* dF = -S_t ds */
  double s2 = v3_norm2(spring);
  out->sliding = false;
  if (s2 > L * L) { /* slip */
    spring = v3_scale(spring, L / sqrt(s2));
    out->sliding = true;
  }
  adem_vec3 dash = v3_scale(adem_tangential_damping_velocity(in, spring), -in->damping);
  adem_vec3 f = v3_add(spring, dash);
  double f2 = v3_norm2(f);
  if (f2 > L * L) { /* the dashpot gives up what exceeds the limit */
    f = v3_scale(f, L / sqrt(f2));
    dash = v3_sub(f, spring);
    out->sliding = true;
  }
  *fs = spring;
  *aux = S;
  out->force = f;
  out->dashpot = dash;
  out->elastic = S > 0.0 ? 0.5 * v3_norm2(spring) / S : 0.0;
  double work = -0.5 * in->dt * v3_dot(v3_add(f_prev, spring), in->vt);
  out->dissipated = work - (out->elastic - u_prev);
}

#endif
