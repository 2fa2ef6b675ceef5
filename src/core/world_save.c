/* A world in checkpoints: its state (particles, contact histories, walls, scalars) and its
 * set-up, written and read back so that a resumed run equals one that never stopped. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fpenv.h"
#include "hertz.h"
#include "history_switch.h"
#include "jkr.h"
#include "log.h"
#include "parallel.h"
#include "rng.h"
#include "step_limit.h"
#include "world_internal.h"
#include "world_parts.h"
#include "cylinder.h"
#include "mesh_periodic.h"

/* ---------------------------------------------------------------- checkpoints */

void adem_world_save(adem_writer *wr, const adem_world *w) {
  adem_put_u8(wr, w->prepared ? 1 : 0);
  adem_put_f64(wr, w->time);
  adem_put_u64(wr, w->step);
  adem_put_f64(wr, w->dt);
  adem_put_u64(wr, w->next_id);
  adem_put_f64(wr, w->energy_initial);
  adem_put_vec(wr, w->gravity);
  adem_put_f64(wr, w->max_overlap_ratio);
  adem_put_u8(wr, w->has_domain ? 1 : 0);
  adem_put_vec(wr, w->domain_lo);
  adem_put_vec(wr, w->domain_hi);
  adem_put_u32(wr, w->periodic.axes);
  for (int d = 0; d < 3; ++d) {
    adem_put_f64(wr, w->periodic.lo[d]);
    adem_put_f64(wr, w->periodic.len[d]);
  }
  adem_put_u32(wr, w->open_faces);
  adem_put_f64(wr, w->nb.skin);
  adem_put_f64(wr, w->nb.skin_fraction);
  adem_put_u8(wr, w->nb.brute_force ? 1 : 0);
  adem_put_u64(wr, w->nb.rebuilds);
  adem_put_f64(wr, w->nb.time_at_build);
  adem_put_u32(wr, (uint32_t)w->mat.n);
  for (int k = 0; k < w->mat.n; ++k) adem_put_str(wr, w->mat.m[k].def.name);
  adem_put_u32(wr, (uint32_t)w->ngroups);
  for (int k = 0; k < w->ngroups; ++k) adem_put_vec(wr, w->groups[k].external_force);
  adem_put_u32(wr, (uint32_t)w->walls.nplanes);
  for (int k = 0; k < w->walls.nplanes; ++k) {
    const adem_plane_def *d = &w->walls.planes[k].def;
    adem_put_str(wr, d->name);
    adem_put_vec(wr, d->point);
    adem_put_vec(wr, d->normal);
    adem_put_vec(wr, d->velocity);
    adem_put_i32(wr, d->material);
  }
  adem_particles_save(wr, &w->p);
  adem_pairs_save(wr, &w->pp);
  adem_pairs_save(wr, &w->pw);
  adem_mesh_pairs_save(wr, &w->pm, w->p.n);
  size_t nf = 3 * w->walls.mesh.ntris;
  adem_put_array(wr, w->walls.face_force, nf, sizeof *w->walls.face_force);
  adem_put_array(wr, w->walls.face_torque, nf, sizeof *w->walls.face_torque);
  adem_walls_save_state(wr, &w->walls);
}

static adem_status damaged(adem_error *err, const char *why);

/* Reads past what adem_world_save writes before the particles: keep the two in step (the state
 * import test, tests/unit/test_state.c, fails when they are not). */
adem_status adem_world_read_particles(adem_reader *rd, adem_particles *p,
                                      char (**names)[ADEM_NAME_MAX], int *nmat, adem_error *err) {
  const char *cut = "its contents are cut short or damaged";
  *names = NULL;
  *nmat = 0;
  if (!adem_get_u8(rd) || rd->failed)
    return damaged(err, "it was written before the first step (its particles are its case's)");
  (void)adem_get_f64(rd);                             /* time */
  (void)adem_get_u64(rd);                             /* step */
  for (int k = 0; k < 3; ++k) (void)adem_get_f64(rd); /* dt, next id, initial energy */
  (void)adem_get_vec(rd);                             /* gravity */
  (void)adem_get_f64(rd);                             /* overlap limit */
  (void)adem_get_u8(rd);                              /* domain */
  (void)adem_get_vec(rd);
  (void)adem_get_vec(rd);
  (void)adem_get_u32(rd); /* periodic axes, then lo and length per axis */
  for (int d = 0; d < 6; ++d) (void)adem_get_f64(rd);
  (void)adem_get_u32(rd); /* open faces */
  (void)adem_get_f64(rd); /* skin */
  (void)adem_get_f64(rd);
  (void)adem_get_u8(rd);
  (void)adem_get_u64(rd);
  (void)adem_get_f64(rd);
  uint32_t nm = adem_get_u32(rd);
  if (rd->failed || nm > 65535) return damaged(err, cut);
  *names = calloc((size_t)nm + 1, sizeof **names);
  if (!*names) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  *nmat = (int)nm;
  for (uint32_t k = 0; k < nm; ++k) adem_get_str_into(rd, (*names)[k], sizeof **names);
  uint32_t ng = adem_get_u32(rd);
  for (uint32_t k = 0; k < ng && !rd->failed; ++k) (void)adem_get_vec(rd);
  uint32_t np = adem_get_u32(rd);
  for (uint32_t k = 0; k < np && !rd->failed; ++k) {
    char name[ADEM_NAME_MAX];
    adem_get_str_into(rd, name, sizeof name);
    for (int j = 0; j < 3; ++j) (void)adem_get_vec(rd);
    (void)adem_get_i32(rd);
  }
  adem_status st = rd->failed ? ADEM_OK : adem_particles_load(rd, p, err);
  if (!st && rd->failed) st = damaged(err, cut);
  for (size_t i = 0; !st && i < p->n; ++i)
    if (p->material[i] >= nm || !(p->radius[i] > 0.0) || !isfinite(p->radius[i]) ||
        !v3_isfinite(p->pos[i]) || !v3_isfinite(p->vel[i]) || !v3_isfinite(p->omega[i]))
      st = damaged(err, "its particles' materials, radii or positions are out of range");
  if (st) {
    free(*names);
    *names = NULL;
    *nmat = 0;
  }
  return st;
}

static adem_status damaged(adem_error *err, const char *why) {
  return adem_error_set(err, ADEM_ERR_INPUT, "%s", why);
}

adem_status adem_world_load_prepared(adem_reader *rd, bool *prepared,
                                     adem_error *err) {
  *prepared = adem_get_u8(rd) != 0;
  if (rd->failed) return damaged(err, "its contents are cut short or damaged");
  return ADEM_OK;
}

adem_status adem_world_load(adem_reader *rd, adem_world *w, adem_error *err) {
  const char *cut = "its contents are cut short or damaged";
  w->time = adem_get_f64(rd);
  w->step = adem_get_u64(rd);
  w->dt = adem_get_f64(rd);
  w->next_id = adem_get_u64(rd);
  w->energy_initial = adem_get_f64(rd);
  w->gravity = adem_get_vec(rd);
  w->max_overlap_ratio = adem_get_f64(rd);
  w->has_domain = adem_get_u8(rd) != 0;
  w->domain_lo = adem_get_vec(rd);
  w->domain_hi = adem_get_vec(rd);
  w->periodic.axes = adem_get_u32(rd);
  for (int d = 0; d < 3; ++d) {
    w->periodic.lo[d] = adem_get_f64(rd);
    w->periodic.len[d] = adem_get_f64(rd);
  }
  w->open_faces = adem_get_u32(rd);
  w->nb.skin = adem_get_f64(rd);
  w->nb.skin_fraction = adem_get_f64(rd);
  w->nb.brute_force = adem_get_u8(rd) != 0;
  w->nb.rebuilds = adem_get_u64(rd);
  w->nb.time_at_build = adem_get_f64(rd);
  uint32_t nmat = adem_get_u32(rd);
  if (rd->failed) return damaged(err, cut);
  if (nmat != (uint32_t)w->mat.n) return damaged(err, "its materials do not match its own case text");
  for (int k = 0; k < w->mat.n; ++k) {
    char name[ADEM_NAME_MAX];
    adem_get_str_into(rd, name, sizeof name);
    if (!rd->failed && strcmp(name, w->mat.m[k].def.name))
      return damaged(err, "its materials do not match its own case text");
  }
  uint32_t ngroups = adem_get_u32(rd);
  if (rd->failed) return damaged(err, cut);
  if (ngroups != (uint32_t)w->ngroups)
    return damaged(err, "its materials or groups do not match its own case text");
  for (int k = 0; k < w->ngroups; ++k) w->groups[k].external_force = adem_get_vec(rd);
  uint32_t nplanes = adem_get_u32(rd);
  if (rd->failed) return damaged(err, cut);
  if (nplanes != (uint32_t)w->walls.nplanes) return damaged(err, "its walls do not match its own case text");
  for (int k = 0; k < w->walls.nplanes; ++k) {
    adem_plane_def *d = &w->walls.planes[k].def;
    adem_get_str_into(rd, d->name, sizeof d->name);
    d->point = adem_get_vec(rd);
    d->normal = adem_get_vec(rd);
    d->velocity = adem_get_vec(rd);
    d->material = adem_get_i32(rd);
  }
  adem_status st = adem_particles_load(rd, &w->p, err);
  if (!st) w->frozen_any = adem_world_has_frozen(w);
  if (!st) st = adem_pairs_load(rd, &w->pp, err);
  if (!st) st = adem_pairs_load(rd, &w->pw, err);
  if (!st && !rd->failed) {
    adem_pairs_clear_apart(&w->pp);
    adem_pairs_clear_apart(&w->pw);
  }
  if (!st) st = adem_mesh_pairs_load(rd, &w->pm, w->p.n, err);
  if (st) return st;
  size_t nf = 3 * w->walls.mesh.ntris;
  adem_get_array(rd, w->walls.face_force, nf, sizeof *w->walls.face_force);
  adem_get_array(rd, w->walls.face_torque, nf, sizeof *w->walls.face_torque);
  adem_walls_load_state(rd, &w->walls);
  if (rd->failed) return damaged(err, cut);
  /* Indices must be in range before the gather lists and the stepper use them. */
  const char *bad = "its particle, pair or wall indices are out of range";
  const adem_particles *p = &w->p;
  for (size_t k = 0; k < w->pp.n; ++k)
    if (w->pp.a[k] >= p->n || w->pp.b[k] >= p->n) return damaged(err, bad);
  for (size_t k = 0; k < w->pw.n; ++k)
    if (w->pw.a[k] >= p->n || w->pw.b[k] >= (uint32_t)w->walls.nplanes) return damaged(err, bad);
  if (!adem_mesh_pairs_consistent(&w->pm, p->n, w->walls.mesh.ntris)) return damaged(err, bad);
  for (size_t i = 0; i < p->n; ++i)
    if (p->material[i] >= w->mat.n || (w->ngroups > 0 && p->group[i] >= w->ngroups))
      return damaged(err, bad);
  for (int k = 0; k < w->walls.nplanes; ++k)
    if (w->walls.planes[k].def.material < 0 || w->walls.planes[k].def.material >= w->mat.n)
      return damaged(err, "its particle, pair or wall indices are out of range");
  /* What sizes the cell grid and the step must be finite and positive (a zero cell size would
   * never fit the grid), as the case loader requires of them. */
  const char *nonfinite = "its time step, skin, radii or positions are not finite and positive";
  if (!(w->dt > 0.0) || !isfinite(w->dt) || !(w->nb.skin_fraction > 0.0) ||
      !isfinite(w->nb.skin_fraction) || !(w->nb.skin >= 0.0) || !isfinite(w->nb.skin))
    return damaged(err, nonfinite);
  for (size_t i = 0; i < p->n; ++i)
    if (!(p->radius[i] > 0.0) || !isfinite(p->radius[i]) || !v3_isfinite(p->pos[i]))
      return damaged(err, nonfinite);
  if (w->periodic.axes > 7u) return damaged(err, "its periodic axes are not valid");
  for (int d = 0; d < 3; ++d)
    if ((w->periodic.axes >> d) & 1u && !(w->periodic.len[d] > 0.0 && isfinite(w->periodic.len[d])))
      return damaged(err, nonfinite);
  return ADEM_OK;
}

/* ---------------------------------------------------------------- set-up in checkpoints */

void adem_world_save_setup(adem_writer *wr, const adem_world *w) {
  adem_put_vec(wr, w->gravity);
  adem_put_f64(wr, w->dt);
  adem_put_f64(wr, w->nb.skin_fraction);
  adem_put_u8(wr, w->nb.brute_force ? 1 : 0);
  adem_put_f64(wr, w->max_overlap_ratio);
  adem_put_u64(wr, w->parallel_min);
  adem_put_u8(wr, w->second_order ? 1 : 0);
  adem_put_u8(wr, w->energy_balance ? 1 : 0);
  adem_put_u32(wr, (uint32_t)w->mat.n);
  for (int k = 0; k < w->mat.n; ++k) adem_put(wr, &w->mat.m[k].def, sizeof w->mat.m[k].def);
  adem_put_u32(wr, (uint32_t)w->mat.ndefs);
  adem_put(wr, w->mat.defs, (size_t)w->mat.ndefs * sizeof *w->mat.defs);
  adem_put_u32(wr, (uint32_t)w->ngroups);
  for (int k = 0; k < w->ngroups; ++k) {
    adem_put_str(wr, w->groups[k].name);
    adem_put_vec(wr, w->groups[k].external_force);
  }
  adem_walls_save_setup(wr, &w->walls);
}

adem_status adem_world_load_setup(adem_reader *rd, adem_world *w, adem_error *err) {
  const char *cut = "its contents are cut short or damaged";
  w->gravity = adem_get_vec(rd);
  w->dt = adem_get_f64(rd);
  w->nb.skin_fraction = adem_get_f64(rd);
  w->nb.brute_force = adem_get_u8(rd) != 0;
  w->max_overlap_ratio = adem_get_f64(rd);
  w->parallel_min = (size_t)adem_get_u64(rd);
  w->second_order = adem_get_u8(rd) != 0;
  w->energy_balance = adem_get_u8(rd) != 0;
  uint32_t nm = adem_get_u32(rd);
  adem_status st = ADEM_OK;
  for (uint32_t k = 0; k < nm && !st && !rd->failed; ++k) {
    adem_material_def d;
    adem_get(rd, &d, sizeof d);
    d.name[ADEM_NAME_MAX - 1] = '\0';
    if (!rd->failed) st = adem_world_add_material(w, &d, NULL, err);
  }
  uint32_t nd = adem_get_u32(rd);
  for (uint32_t k = 0; k < nd && !st && !rd->failed; ++k) {
    adem_interaction_def d;
    adem_get(rd, &d, sizeof d);
    if (!rd->failed) st = adem_world_set_interaction(w, &d, err);
  }
  uint32_t ng = adem_get_u32(rd);
  for (uint32_t k = 0; k < ng && !st && !rd->failed; ++k) {
    char name[ADEM_NAME_MAX];
    adem_get_str_into(rd, name, sizeof name);
    adem_vec3 f = adem_get_vec(rd);
    if (!rd->failed) st = adem_world_add_group(w, name, f, NULL, err);
  }
  if (!st && !rd->failed) st = adem_walls_load_setup(rd, &w->walls, w->mat.n, err);
  if (st) return st == ADEM_ERR_NOMEM ? st : damaged(err, err ? err->message : cut);
  if (rd->failed) return damaged(err, cut);
  w->prepared = false;
  return ADEM_OK;
}
