/* What the world's files (world*.c) share and no other module needs. */
#ifndef ADEM_WORLD_PARTS_H
#define ADEM_WORLD_PARTS_H

#include "world_internal.h"

/* ---- checks (world_checks.c) ---- */
/* Periodic boxes the run cannot use: a length below 2 (largest diameter + skin), where a pair
 * could touch through two images at once, a plane cutting a periodic axis, a cylinder or plate
 * or a mesh within reach of a periodic face unless it is the same all along the axis. */
adem_status adem_world_check_periodic(const adem_world *w, adem_error *err);
/* Rejects overlapping particles and particles behind a wall or cutting a mesh, naming them. */
adem_status adem_world_check_initial_state(const adem_world *w, adem_error *err);
/* Escape check box: the case's domain, or the initial extent of particles and wall points
 * widened generously on each side. */
void adem_world_default_domain(adem_world *w);
/* After a step: the first particle (lowest index) with a non-finite state, an overlap above the
 * limit, or a position outside the domain. Returns ADEM_OK when all is well. */
adem_status adem_world_check_state(const adem_world *w, adem_error *err);
/* Logs particles that moved more than their radius in a step next to a mesh wall. */
void adem_world_note_tunnelling(adem_world *w, double dt);

/* ---- servos (world_servo.c) ---- */
/* The servos move by their laws from the last force pass's loads, before the walls are placed. */
adem_status adem_world_servo_step(adem_world *w, double dt, adem_error *err);

/* ---- diagnostics (world_diag.c) ---- */
double adem_world_total_energy(const adem_diagnostics *d);

#endif
