/* Frozen particles (issue 29 item 4): spheres fixed to a wall move with it and carry its load. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "case_file.h"
#include "plate_stl.h"
#include "tmpdir.h"
#include "world_internal.h"

static int setup(void **state) {
  (void)state;
  return tmpdir_make("adem_frozen");
}

/* The set "walls=[WALL]" with WALL's %s the test's temporary folder (a static buffer). */
static const char *walls_set(const char *wall) {
  static char set[1024];
  char w[800];
  snprintf(w, sizeof w, wall, tmpdir);
  snprintf(set, sizeof set, "walls=[%s]", w);
  return set;
}

/* Claim: frozen spheres attached to a mesh plate that translates and turns stay exactly on the
 * plate: each sphere put on a vertex of the plate is on that vertex, bit for bit, after 3,000
 * steps (both are placed by the same motion, none is integrated), with the velocity and spin of
 * the plate's material there; a free sphere falls meanwhile. */
static void test_frozen_follow_wall(void **state) {
  (void)state;
  char path[600];
  snprintf(path, sizeof path, "%s/plate.stl", tmpdir);
  write_plate(path, 2, 0.0078125); /* vertices at 0, +-0.0078125 */
  char plate[700];
  snprintf(plate, sizeof plate, "walls.plate.file=%s/plate.stl", tmpdir);
  const char *sets[] = {plate};
  adem_case *c = case_file_load("frozen-follow", sets, 1);
  adem_world *w = c->world;
  adem_error err;
  if (adem_world_step(w, 3000, &err)) fail_msg("%s", err.message);
  const adem_mesh *m = &w->walls.mesh;
  const adem_motion *mo = &w->walls.mesh_motion[0];
  int on_vertex = 0;
  double travelled = 0.0;
  for (size_t i = 0; i < w->p.n; ++i) {
    if (!w->p.frozen[i]) {
      assert_true(w->p.pos[i].z < 0.1 - 0.5 * 9.81 * 0.03 * 0.03 * 0.99); /* it fell */
      continue;
    }
    bool found = false;
    for (uint32_t v = 0; v < m->nverts && !found; ++v)
      if (!memcmp(&w->walls.mesh_vert0[v], &w->p.anchor[i], sizeof(adem_vec3))) {
        found = true;
        if (memcmp(&m->vert[v], &w->p.pos[i], sizeof(adem_vec3)))
          fail_msg("frozen particle %zu at (%.17g, %.17g, %.17g), its vertex at (%.17g, %.17g, %.17g)",
                   i, w->p.pos[i].x, w->p.pos[i].y, w->p.pos[i].z, m->vert[v].x, m->vert[v].y,
                   m->vert[v].z);
      }
    assert_true(found);
    on_vertex++;
    travelled = fmax(travelled, v3_norm(v3_sub(w->p.pos[i], w->p.anchor[i])));
    adem_vec3 v = adem_motion_point_velocity(mo, w->time, w->p.pos[i]);
    assert_memory_equal(&v, &w->p.vel[i], sizeof v);
    adem_vec3 o = v3_scale(mo->axis, mo->omega);
    assert_memory_equal(&o, &w->p.omega[i], sizeof o);
  }
  printf("# %d frozen spheres on their vertices after %llu steps (t = %g s), up to %.4g m from "
         "where they began\n",
         on_vertex, (unsigned long long)w->step, w->time, travelled);
  assert_int_equal(on_vertex, 3);
  assert_true(travelled > 0.001);
  adem_case_free(c);
}

/* The rough floor: tests/cases/frozen-rough.yaml (a plane `floor` under the frozen layer). */

/* Claim: a sphere resting on a floor of frozen spheres loads the floor with its weight: after
 * 0.15 s the floor's force along z is -m g to 1e-6 (the bounce damped away: restitution 0.3,
 * a Hertz contact period ~0.3 ms), whether the floor is a plane or a mesh group (group load and
 * mesh wall load); the frozen spheres touch neither the floor nor each other, so that all of it
 * comes through them. */
static void test_frozen_carry_load(void **state) {
  (void)state;
  char path[600];
  snprintf(path, sizeof path, "%s/floor.stl", tmpdir);
  write_plate(path, 4, 0.0078125);
  const char *walls[2][2] = {
      {"{type: plane, name: floor, point: [0, 0, 0], normal: [0, 0, 1], material: steel}", "floor"},
      {"{type: mesh, name: floor, file: %s/floor.stl, material: steel}", "floor"}};
  for (int k = 0; k < 2; ++k) {
    const char *sets[] = {walls_set(walls[k][0])};
    adem_case *c = case_file_load("frozen-rough", sets, 1);
    adem_world *w = c->world;
    adem_error err;
    if (adem_world_step(w, 15000, &err)) fail_msg("%s", err.message);
    double weight = 0.0;
    size_t nfree = 0, moved = 0;
    for (size_t i = 0; i < w->p.n; ++i) {
      if (!w->p.frozen[i]) {
        weight += 9.81 / w->p.inv_mass[i];
        nfree++;
      } else { /* a static wall's spheres stay where they were, bit for bit */
        moved += memcmp(&w->p.pos[i], &w->p.anchor[i], sizeof(adem_vec3)) != 0;
      }
    }
    assert_int_equal(moved, 0);
    adem_vec3 f;
    const char *what = k == 0 ? "plane" : "mesh group";
    if (k == 0) {
      adem_world_plane_forces(w, &f);
    } else {
      adem_vec3 g, wf;
      adem_world_mesh_loads(w, &g, NULL, &wf, NULL);
      assert_memory_equal(&g, &wf, sizeof g); /* one group: the wall's load is the group's */
      f = g;
    }
    size_t own = 0; /* the floor's own contacts: none */
    for (size_t j = 0; j < w->pw.n; ++j) own += w->pw.touching[j];
    for (size_t j = 0; j < w->pm.l.n; ++j) own += w->pm.l.touching[j];
    printf("# %s floor: load (%.3g, %.3g, %.9g) N, weight of the free sphere %.9g N (rel. error "
           "%.2g); %zu contacts of the floor itself\n",
           what, f.x, f.y, f.z, weight, fabs(f.z + weight) / weight, own);
    /* reported, not asserted: the energy balance with frozen spheres is not analysed yet */
    adem_diagnostics d = adem_world_diagnostics(w);
    printf("# balance error %.3g J against m g h = %.3g J\n", d.balance_error, weight * 0.00067);
    assert_int_equal(nfree, 1);
    assert_int_equal(own, 0);
    assert_true(fabs(f.z + weight) <= 1e-6 * weight);
    assert_true(fabs(f.x) <= 1e-6 * weight && fabs(f.y) <= 1e-6 * weight);
    adem_case_free(c);
  }
}

/* Claim: the slip measure tells a smooth moving floor from a rough one. A sphere resting on a
 * smooth plane that starts moving along x at 0.1 m/s slips at the plane's speed at first (to
 * 1e-3 m/s: friction has had one step), and once friction has made it roll without slipping its
 * centre lags the plane by 5/7 of its speed (m v = F t, (2/5) m r^2 w = F r t, v + w r = 0.1:
 * v = 0.1 / 3.5), to 1e-3 of that; on a frozen layer attached to the plane the sphere sits in a
 * hollow and is carried along: its slip is below 1e-3 m/s after 0.3 s. */
static void test_slip(void **state) {
  (void)state;
  const char *moving = "walls.floor.motion={velocity: [0.1, 0, 0]}";
  /* smooth: the frozen layer and the sphere on it replaced by one sphere on the plane */
  const char *smooth_sets[] = {
      moving, "particles=[{type: list, material: glass, spheres: [{position: [0, 0, 0.002], radius: 0.002}]}]"};
  adem_case *c = case_file_load("frozen-rough", smooth_sets, 2);
  adem_error err;
  if (adem_world_step(c->world, 1, &err)) fail_msg("%s", err.message);
  double smooth0, smooth, rough[3];
  adem_world_wall_slip(c->world, &smooth0, NULL);
  if (adem_world_step(c->world, 9999, &err)) fail_msg("%s", err.message);
  adem_world_wall_slip(c->world, &smooth, NULL);
  adem_case_free(c);
  c = case_file_load("frozen-rough", &moving, 1);
  for (int k = 0; k < 3; ++k) {
    if (adem_world_step(c->world, 10000, &err)) fail_msg("%s", err.message);
    adem_world_wall_slip(c->world, &rough[k], NULL);
  }
  printf("# slip on a floor moving at 0.1 m/s: smooth %.6g m/s (first step), %.6g m/s (0.1 s; "
         "rolling without slipping: 5/7 x 0.1 = %.6g), rough %.3g, %.3g, %.3g m/s (0.1, 0.2, 0.3 s)\n",
         smooth0, smooth, 0.5 / 7.0, rough[0], rough[1], rough[2]);
  assert_true(fabs(smooth0 - 0.1) < 1e-3);
  assert_true(fabs(smooth - 0.5 / 7.0) < 1e-3 * 0.5 / 7.0);
  assert_true(rough[2] < 1e-3);
  adem_case_free(c);
}

/* Claim: frozen spheres are refused where they cannot work, naming the key. */
static void test_frozen_refusals(void **state) {
  (void)state;
  const char *sets[] = {"particles.0.attach=nowhere"};
  adem_case *c = NULL;
  adem_error err;
  assert_int_equal(adem_case_load_file(case_file_path("frozen-rough"), sets, 1, &c, &err),
                   ADEM_ERR_INPUT);
  printf("# %s\n", err.message);
  assert_non_null(strstr(err.message, "particles[0].attach"));
  assert_non_null(strstr(err.message, "no plane or mesh group named `nowhere`"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_frozen_follow_wall),
      cmocka_unit_test(test_frozen_carry_load),
      cmocka_unit_test(test_slip),
      cmocka_unit_test(test_frozen_refusals),
  };
  return cmocka_run_group_tests(tests, setup, tmpdir_teardown);
}
