/* Frozen particles: spheres fixed to a wall (a plane or a mesh group) or to space, to make a rough
 * wall or floor. They are not integrated (particles.c skips them): their centre is where their
 * wall's prescribed motion takes their anchor, their velocity and spin those of the wall's
 * material there. Two frozen particles never touch (one rigid body), nor do they touch walls
 * (neighbors.c). The forces the free particles put on them are the wall's: the loads of a plane
 * or a mesh group (and its mesh wall) include them, summed over the frozen particles by id after
 * the wall's own contacts. */
#include <math.h>
#include <stdlib.h>

#include "world_internal.h"

/* The motion of the wall particle i moves with, or NULL (fixed in space). */
static const adem_motion *motion_of(const adem_world *w, size_t i) {
  int32_t a = adem_particles_attach(&w->p, i);
  if (a > 0 && a - 1 < w->walls.mesh.ngroups) return &w->walls.mesh_motion[a - 1];
  if (a < 0 && -a - 1 < w->walls.nplanes) return &w->walls.planes[-a - 1].motion;
  return NULL;
}

adem_status adem_world_freeze_particle(adem_world *w, uint64_t id, int32_t attach,
                                       adem_error *err) {
  adem_particles *p = &w->p;
  if (attach > 0 && attach - 1 >= w->walls.mesh.ngroups)
    return adem_error_set(err, ADEM_ERR_INPUT, "no mesh group %d to attach to", attach - 1);
  if (attach < 0 && -attach - 1 >= w->walls.nplanes)
    return adem_error_set(err, ADEM_ERR_INPUT, "no plane %d to attach to", -attach - 1);
  size_t i = 0;
  while (i < p->n && p->id[i] != id) ++i;
  if (i == p->n)
    return adem_error_set(err, ADEM_ERR_INPUT, "no particle has id %llu", (unsigned long long)id);
  if (adem_particles_keep(p, ADEM_PART_FROZEN))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory freezing particle id %llu",
                          (unsigned long long)id);
  p->frozen[i] = 1;
  p->attach[i] = attach;
  w->frozen_any = true;
  const adem_motion *m = motion_of(w, i);
  if (m && m->servo.on)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "particle id %llu cannot be attached to a servo wall (its travel is not "
                          "a function of time)",
                          (unsigned long long)id);
  /* the anchor is where the motion, counted from its t0, starts the centre */
  p->anchor[i] = p->pos[i];
  p->vel[i] = p->omega[i] = v3_zero();
  return ADEM_OK;
}

void adem_world_place_frozen(adem_world *w, double t) {
  adem_particles *p = &w->p;
  if (!w->frozen_any) return; /* a run without them pays nothing per step */
  for (size_t i = 0; i < p->n; ++i) {
    if (!p->frozen[i]) continue;
    const adem_motion *m = motion_of(w, i);
    if (!m || !m->moving) {
      p->vel[i] = p->omega[i] = v3_zero();
      continue;
    }
    p->pos[i] = adem_motion_place(m, t, p->anchor[i]); /* attached: its kind is present */
    p->vel[i] = adem_motion_point_velocity(m, t, p->pos[i]);
    p->omega[i] = v3_scale(m->axis, m->omega);
  }
}

void adem_world_restart_anchors(adem_world *w, double t_s) {
  adem_particles *p = &w->p;
  if (!w->frozen_any) return;
  for (size_t i = 0; i < p->n; ++i) {
    if (!p->frozen[i]) continue;
    const adem_motion *m = motion_of(w, i);
    /* a motion a stage has just begun counts from where the particle is now */
    if (m && m->t0 == t_s) p->anchor[i] = p->pos[i]; /* attached: its kind is present */
  }
}

/* The contact force on frozen particle i (its force less its body forces, H3). */
static adem_vec3 contact_force(const adem_world *w, size_t i) {
  const adem_particles *p = &w->p;
  adem_vec3 body = v3_add(v3_scale(w->gravity, 1.0 / p->inv_mass[i]),
                          w->groups[p->group[i]].external_force);
  return v3_sub(p->force[i], body);
}

void adem_world_frozen_plane_forces(const adem_world *w, adem_vec3 *out) {
  const adem_particles *p = &w->p;
  uint32_t *order = NULL;
  if (!w->frozen_any) return;
  for (size_t i = 0; i < p->n && !order; ++i)
    if (p->frozen[i] && adem_particles_attach(p, i) < 0) order = adem_world_id_order(w);
  if (!order) return; /* none (or out of memory: the walls' own contacts only) */
  for (size_t r = 0; r < p->n; ++r) {
    size_t i = order[r];
    int32_t a = adem_particles_attach(p, i);
    if (!p->frozen[i] || a >= 0 || -a - 1 >= w->walls.nplanes) continue;
    int k = -a - 1;
    out[k] = v3_add(out[k], contact_force(w, i));
  }
  free(order);
}

void adem_world_frozen_mesh_loads(const adem_world *w, adem_vec3 *group_force,
                                  adem_vec3 *group_torque, adem_vec3 *wall_force,
                                  adem_vec3 *wall_torque) {
  const adem_particles *p = &w->p;
  const adem_walls *wl = &w->walls;
  int ng = wl->mesh.ngroups;
  uint32_t *order = NULL;
  if (!w->frozen_any) return;
  for (size_t i = 0; i < p->n && !order; ++i)
    if (p->frozen[i] && adem_particles_attach(p, i) > 0) order = adem_world_id_order(w);
  if (!order || ng == 0) {
    free(order);
    return;
  }
  adem_vec3 *f = calloc((size_t)ng, sizeof *f), *t = calloc((size_t)ng, sizeof *t);
  if (!f || !t) {
    free(f);
    free(t);
    free(order);
    return;
  }
  for (size_t r = 0; r < p->n; ++r) {
    size_t i = order[r];
    int32_t a = adem_particles_attach(p, i);
    if (!p->frozen[i] || a <= 0 || a - 1 >= ng) continue;
    int g = a - 1;
    adem_vec3 fc = contact_force(w, i);
    f[g] = v3_add(f[g], fc);
    /* about the group's point: the force at the centre and the contacts' torque about it */
    t[g] = v3_add(t[g], v3_add(v3_cross(v3_sub(p->pos[i], wl->mesh_ref[g]), fc), p->torque[i]));
  }
  for (int g = 0; g < ng; ++g) {
    if (group_force) group_force[g] = v3_add(group_force[g], f[g]);
    if (group_torque) group_torque[g] = v3_add(group_torque[g], t[g]);
  }
  for (int k = 0; k < wl->nmesh_walls && (wall_force || wall_torque); ++k) {
    const adem_mesh_wall *mw = &wl->mesh_walls[k];
    adem_vec3 ref = mw->count > 0 ? adem_motion_place(&wl->mesh_motion[mw->first], wl->time, mw->ref0)
                                  : mw->ref0;
    for (int g = mw->first; g < mw->first + mw->count; ++g) {
      if (wall_force) wall_force[k] = v3_add(wall_force[k], f[g]);
      if (wall_torque)
        wall_torque[k] = v3_add(wall_torque[k],
                                v3_add(t[g], v3_cross(v3_sub(wl->mesh_ref[g], ref), f[g])));
    }
  }
  free(f);
  free(t);
  free(order);
}

bool adem_world_has_frozen(const adem_world *w) {
  for (size_t i = 0; i < w->p.n; ++i)
    if (w->p.frozen[i]) return true;
  return false;
}
