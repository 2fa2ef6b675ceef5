/* Analytic cylinder and plate walls (core/cylinder.h): the nearest point is the nearest point of
 * the surface (against a dense sampling of it, rims included), the gap is continuous over rims,
 * a sphere at rest in a drum sits where the Hertz law and the geometry put it and where its STL
 * twin puts it less the tessellation's sag, and the drive torque of a rotating drum on a sphere
 * held by rolling friction balances the sphere's gravity moment. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "cylinder.h"
#include "helpers.h"
#include "world_internal.h"

static const double PI = 3.14159265358979323846;

/* A tiny deterministic generator (the test's own). */
static double rnd(uint64_t *s) {
  *s = *s * 6364136223846793005ull + 1442695040888963407ull;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

/* Distance from x to the nearest of a dense sampling of a circle (centre c, radius r, axis a). */
static double circle_min(adem_vec3 x, adem_vec3 c, double r, adem_vec3 e1, adem_vec3 e2, int n) {
  double best = INFINITY;
  for (int k = 0; k < n; ++k) {
    double t = 2.0 * PI * k / n;
    adem_vec3 q = v3_add(c, v3_add(v3_scale(e1, r * cos(t)), v3_scale(e2, r * sin(t))));
    best = fmin(best, v3_norm(v3_sub(x, q)));
  }
  return best;
}

/* Claim: for 2,000 random points about an open finite cylinder (inside, outside, beyond its ends)
 * and about a holed plate, the gap is the distance to the nearest point of a dense sampling of
 * the surface (1,000 x 400 points, rims included) within the sampling's reach, no sample is
 * nearer than the gap (to 1e-12 m), and q is on the surface at distance gap from x along n. */
static void test_nearest_point(void **state) {
  (void)state;
  adem_plane_def cyl = adem_default_plane_def();
  cyl.shape = ADEM_WALL_CYLINDER;
  cyl.point = v3(0.01, -0.02, 0.005);
  adem_vec3 a = v3_scale(v3(1.0, 0.5, 0.25), 1.0 / v3_norm(v3(1.0, 0.5, 0.25)));
  cyl.normal = a;
  cyl.radius = 0.03;
  cyl.length = 0.08;
  adem_plane_def plate = adem_default_plane_def();
  plate.shape = ADEM_WALL_DISC;
  plate.flags = ADEM_WALL_TWO_SIDED;
  plate.point = cyl.point;
  plate.normal = a;
  plate.radius = 0.06;
  plate.hole_radius = 0.02;
  adem_vec3 e1 = adem_wall_any_normal(a), e2 = v3_cross(a, e1);
  uint64_t s = 12345;
  const int na = 1000, nl = 400;
  double worst = 0.0;
  for (int shape = 0; shape < 2; ++shape)
    for (int k = 0; k < 1000; ++k) {
      const adem_plane_def *d = shape ? &plate : &cyl;
      /* points within 0.02 m of the surface's parts, on either side, beyond the ends */
      double h = shape ? 0.04 * (rnd(&s) - 0.5) : -0.02 + 0.12 * rnd(&s);
      double rho = shape ? 0.07 * rnd(&s) : 0.01 + 0.04 * rnd(&s);
      double t = 2.0 * PI * rnd(&s);
      adem_vec3 x = v3_add(v3_axpy(d->point, h, a),
                           v3_add(v3_scale(e1, rho * cos(t)), v3_scale(e2, rho * sin(t))));
      adem_wall_near c = adem_wall_nearest(d, x);
      assert_true(c.live);
      /* the sampled surface: side and end rims, or the annulus and its two rims */
      double best = INFINITY, step;
      if (!shape) {
        for (int j = 0; j <= nl; ++j) {
          adem_vec3 cc = v3_axpy(d->point, d->length * j / nl, a);
          best = fmin(best, circle_min(x, cc, d->radius, e1, e2, na));
        }
        step = fmax(d->length / nl, 2.0 * PI * d->radius / na);
      } else {
        for (int j = 0; j <= nl; ++j)
          best = fmin(best, circle_min(x, d->point,
                                       d->hole_radius + (d->radius - d->hole_radius) * j / nl,
                                       e1, e2, na));
        step = fmax((d->radius - d->hole_radius) / nl, 2.0 * PI * d->radius / na);
      }
      double dist = fabs(c.gap); /* inside the surface's own side the gap is >= 0 */
      assert_true(best >= dist - 1e-12);
      assert_true(best <= dist + step);
      worst = fmax(worst, best - dist);
      /* q is x + gap n, and on the surface */
      assert_true(v3_norm(v3_sub(c.q, v3_axpy(x, c.gap, c.n))) < 1e-12);
      assert_true(fabs(v3_norm(c.n) - 1.0) < 1e-12);
    }
  printf("# largest sampled - analytic distance %.3g m (sampling steps up to %.3g m)\n", worst,
         2.0 * PI * 0.06 / na);
}

/* Claim: a sphere centre carried in steps of 1e-5 m over a plate's hole rim, around it and back
 * over the plate, and over an open cylinder's end, sees the gap change by at most the step
 * (the distance to a surface is 1-Lipschitz: no jump at a rim) and the normal turn by at most
 * step / (distance to the rim) radians. */
static void test_rim_continuity(void **state) {
  (void)state;
  adem_plane_def plate = adem_default_plane_def();
  plate.shape = ADEM_WALL_DISC;
  plate.flags = ADEM_WALL_TWO_SIDED;
  plate.hole_radius = 0.01;
  adem_plane_def cyl = adem_default_plane_def();
  cyl.shape = ADEM_WALL_CYLINDER;
  cyl.normal = v3(1, 0, 0);
  cyl.radius = 0.02;
  cyl.length = 0.05;
  const double step = 1e-5;
  for (int part = 0; part < 2; ++part) {
    const adem_plane_def *d = part ? &cyl : &plate;
    /* the plate: a sphere of 3 mm rolling over the rim into the hole at 2 mm above the plane;
     * the drum: along its axis out of the open end, 1 mm inside the side */
    adem_vec3 x0 = part ? v3(0.04, 0.0, -0.019) : v3(0.02, 0.0, 0.002);
    adem_vec3 dir = part ? v3(1, 0, 0) : v3(-1, 0, 0);
    adem_wall_near prev = adem_wall_nearest(d, x0);
    double worst_gap = 0.0, worst_turn = 0.0;
    for (int k = 1; k <= 2000; ++k) {
      adem_vec3 x = v3_axpy(x0, step * k, dir);
      adem_wall_near c = adem_wall_nearest(d, x);
      double jump = fabs(c.gap - prev.gap);
      double turn = v3_norm(v3_sub(c.n, prev.n));
      worst_gap = fmax(worst_gap, jump / step);
      worst_turn = fmax(worst_turn, turn * fmin(fabs(c.gap), fabs(prev.gap)) / step);
      prev = c;
    }
    printf("# %s: largest gap change per step %.6f, normal turn x distance / step %.6f\n",
           part ? "open drum end" : "hole rim", worst_gap, worst_turn);
    assert_true(worst_gap <= 1.0 + 1e-9);
    assert_true(worst_turn <= 1.0 + 1e-6);
  }
}

/* ---- a sphere in a horizontal drum, analytic and as its STL twin ---- */

enum { TWIN_FACETS = 90 };
static const double DRUM_R = 0.05, DRUM_L = 0.04, SPHERE_R = 0.005;

/* A drum of n flat facets along x from -L/2 to L/2, corners at angles (k + 1/2) 2 pi / n from the
 * bottom so that a facet is centred there, at R cos(pi/n) from the axis; normals inwards. */
static void add_twin(adem_world *w, int mat, int n) {
  adem_vec3 *c = malloc((size_t)n * 6 * sizeof *c);
  assert_non_null(c);
  for (int k = 0; k < n; ++k) {
    double p0 = (k + 0.5) * 2.0 * PI / n, p1 = (k + 1.5) * 2.0 * PI / n;
    adem_vec3 a0 = v3(-DRUM_L / 2, DRUM_R * sin(p0), -DRUM_R * cos(p0));
    adem_vec3 a1 = v3(-DRUM_L / 2, DRUM_R * sin(p1), -DRUM_R * cos(p1));
    adem_vec3 b0 = v3(DRUM_L / 2, a0.y, a0.z), b1 = v3(DRUM_L / 2, a1.y, a1.z);
    adem_vec3 t[6] = {a0, a1, b1, a0, b1, b0};
    /* inwards: towards the axis from the facet's middle */
    adem_vec3 nrm = v3_cross(v3_sub(t[1], t[0]), v3_sub(t[2], t[0]));
    adem_vec3 mid = v3_scale(v3_add(a0, b1), 0.5);
    if (v3_dot(nrm, v3(0.0, -mid.y, -mid.z)) < 0.0) {
      adem_vec3 tmp = t[1];
      t[1] = t[2];
      t[2] = tmp;
      tmp = t[4];
      t[4] = t[5];
      t[5] = tmp;
    }
    for (int q = 0; q < 6; ++q) c[6 * k + q] = t[q];
  }
  adem_mesh_transform tf = adem_default_mesh_transform();
  tf.material = mat;
  tf.own_vertices = 1;
  adem_error err;
  assert_int_equal(adem_world_add_mesh(w, c, 2 * (size_t)n, "twin", &tf, &err), ADEM_OK);
  free(c);
}

/* A glass sphere dropped 0.5 mm into the bottom of a drum about x (analytic or its twin). */
static adem_world *drum_world(bool twin, double omega, double eta_r, int *wall_mat) {
  adem_world *w = adem_world_create();
  int glass = test_material(w, "glass", 1e7, 0.3, 0.3, 0.5);
  adem_material_def steel = adem_default_material_def();
  snprintf(steel.name, sizeof steel.name, "steel");
  steel.rigid = 1;
  steel.friction = 0.5;
  steel.restitution = 0.3;
  steel.param[ADEM_PARAM_ROLLING_FRICTION] = eta_r;
  adem_error err;
  int st = -1;
  assert_int_equal(adem_world_add_material(w, &steel, &st, &err), ADEM_OK);
  if (eta_r > 0.0) {
    adem_interaction_def it = adem_default_interaction_def();
    it.material_a = glass;
    it.material_b = st;
    it.rolling = ADEM_ROLLING_C;
    it.param[ADEM_PARAM_ROLLING_FRICTION] = eta_r;
    it.param[ADEM_PARAM_ROLLING_DAMPING] = 0.3;
    assert_int_equal(adem_world_set_interaction(w, &it, &err), ADEM_OK);
  }
  adem_motion_def md = {0};
  md.axis = v3(1, 0, 0);
  md.angular_speed = omega;
  if (twin) {
    add_twin(w, st, TWIN_FACETS);
    if (omega != 0.0) assert_int_equal(adem_world_set_mesh_motion(w, 0, &md, &err), ADEM_OK);
  } else {
    adem_plane_def d = adem_default_plane_def();
    snprintf(d.name, sizeof d.name, "drum");
    d.material = st;
    d.shape = ADEM_WALL_CYLINDER;
    d.point = v3(0, 0, 0);
    d.normal = v3(1, 0, 0);
    d.radius = DRUM_R;
    int idx = -1;
    assert_int_equal(adem_world_add_plane(w, &d, &idx, &err), ADEM_OK);
    if (omega != 0.0) assert_int_equal(adem_world_set_plane_motion(w, idx, &md, &err), ADEM_OK);
  }
  test_particle(w, glass, v3(0.0, 0.0, -(DRUM_R - SPHERE_R) + 0.0005), v3_zero(), SPHERE_R);
  adem_world_set_gravity(w, v3(0, 0, -9.81));
  adem_world_set_dt(w, 4e-6);
  assert_int_equal(adem_world_prepare(w, &err), ADEM_OK);
  if (wall_mat) *wall_mat = st;
  return w;
}

/* Claim: a sphere at rest at the bottom of a drum of radius R sits at z = -(R - r + delta), delta
 * the Hertz overlap under its weight, (3 m g / (4 E* sqrt(r)))^(2/3), to 1e-4 delta, and carries
 * its weight onto the drum to 1e-6; its STL twin of 90 facets, whose bottom facet lies at
 * R cos(pi/90) from the axis, puts it higher by exactly that sag, R (1 - cos(pi/90)) = 30.5 um,
 * to 1e-4 of it (the same overlap under the same weight). */
static void test_drum_rest_vs_twin(void **state) {
  (void)state;
  double z[2];
  for (int twin = 0; twin < 2; ++twin) {
    adem_world *w = drum_world(twin, 0.0, 0.0, NULL);
    adem_error err;
    assert_int_equal(adem_world_step(w, 100000, &err), ADEM_OK); /* 0.4 s: at rest */
    z[twin] = w->p.pos[0].z;
    double m = test_sphere_mass(SPHERE_R, 2500.0);
    double fz;
    if (!twin) {
      adem_vec3 f;
      adem_world_plane_forces(w, &f);
      fz = f.z;
    } else {
      adem_vec3 f;
      adem_world_mesh_loads(w, &f, NULL, NULL, NULL);
      fz = f.z;
    }
    printf("# %s: z = %.12f m, load %.9g N (weight %.9g N), speed %.3g m/s\n",
           twin ? "STL twin" : "cylinder", z[twin], fz, m * 9.81, v3_norm(w->p.vel[0]));
    assert_true(fabs(fz + m * 9.81) <= 1e-6 * m * 9.81);
    if (!twin) {
      double Es = 1e7 / (1.0 - 0.3 * 0.3); /* against a rigid wall (H2) */
      double delta = pow(3.0 * m * 9.81 / (4.0 * Es * sqrt(SPHERE_R)), 2.0 / 3.0);
      double want = -(DRUM_R - SPHERE_R + delta);
      printf("# Hertz: delta = %.6g m, z wanted %.12f m, off by %.3g delta\n", delta, want,
             (z[0] - want) / delta);
      assert_true(fabs(z[0] - want) <= 1e-4 * delta);
    }
    adem_world_free(w);
  }
  double sag = DRUM_R * (1.0 - cos(PI / TWIN_FACETS));
  printf("# twin - cylinder: %.6g m, sag R (1 - cos(pi/n)) %.6g m\n", z[1] - z[0], sag);
  assert_true(fabs((z[1] - z[0]) - sag) <= 1e-4 * sag);
}

/* The sphere's angular momentum about the drum's axis (x through the origin). */
static double axial_momentum(const adem_world *w) {
  adem_vec3 x = w->p.pos[0], v = w->p.vel[0];
  double m = 1.0 / w->p.inv_mass[0], I = 1.0 / w->p.inv_inertia[0];
  return m * (x.y * v.z - x.z * v.y) + I * w->p.omega[0].x;
}

/* Claim: a sphere rolling in place in a drum turning at 2 rad/s about x, held by model C rolling
 * friction eta_r = 0.1 on the drum (set in place at the angle atan(eta_r) from the bottom, with
 * the spin of rolling without slip, 20 rad/s), keeps a mean angle of atan(eta_r) = 0.0997 rad to
 * 1e-3 (friction F_t = eta_r F_n balances the limiting couple eta_r r F_n; measured 1e-4, the
 * centripetal part of F_n and a small oscillation), and over 1 s the drum's torque about its axis
 * (the CSV's drum_t_axis_Nm), integrated step by step, equals the sphere's gravity moment -m g y
 * integrated less its change of angular momentum about the axis, to 1e-6 of the integrated
 * moment (measured 2e-9; the sampled sum of a step's loads): every load the drum takes is
 * accounted for, lever arms and the rolling couple included. Its STL twin (90 facets turning with
 * it; torque from the mesh group's load about the facets' centroid, on the axis) gives the mean
 * angle within a facet's half angle pi/90 and closes the same balance to 1e-3 (measured 1.2e-4:
 * the mesh's own accounting, its contacts switching facets). */
static void test_drum_torque_balance(void **state) {
  (void)state;
  double theta[2];
  const double eta = 0.1, th0 = atan(eta);
  for (int twin = 0; twin < 2; ++twin) {
    adem_world *w = drum_world(twin, 2.0, eta, NULL);
    adem_error err;
    double m = test_sphere_mass(SPHERE_R, 2500.0);
    double rc = DRUM_R - SPHERE_R + 5.3e-6 - (twin ? DRUM_R * (1.0 - cos(PI / TWIN_FACETS)) : 0.0);
    w->p.pos[0] = v3(0.0, rc * sin(th0), -rc * cos(th0));
    w->p.omega[0] = v3(2.0 * DRUM_R / SPHERE_R, 0.0, 0.0);
    assert_int_equal(adem_world_step(w, 50000, &err), ADEM_OK); /* 0.2 s */
    double L0 = axial_momentum(w), th = 0.0, tq = 0.0, moment = 0.0, dt = w->dt;
    int ns = 250000; /* 1 s */
    for (int k = 0; k < ns; ++k) {
      assert_int_equal(adem_world_step(w, 1, &err), ADEM_OK);
      adem_vec3 x = w->p.pos[0], t;
      th += atan2(x.y, -x.z) / ns;
      moment += -m * 9.81 * x.y * dt;
      if (!twin) adem_world_plane_torques(w, &t);
      else adem_world_mesh_loads(w, NULL, &t, NULL, NULL);
      tq += t.x * dt;
    }
    double dL = axial_momentum(w) - L0;
    theta[twin] = th;
    printf("# %s: mean theta = %.6f rad (atan %.1f = %.6f), speed %.3g m/s\n",
           twin ? "STL twin" : "cylinder", th, eta, th0, v3_norm(w->p.vel[0]));
    printf("#   integrated drive torque %.9g N m s, gravity moment %.9g, dL %.3g: off by %.3g\n",
           tq, moment, dL, (tq - (moment - dL)) / fabs(moment));
    assert_true(fabs(tq - (moment - dL)) <= (twin ? 1e-3 : 1e-6) * fabs(moment));
    if (!twin) assert_true(fabs(th - th0) <= 1e-3 * th0);
    adem_world_free(w);
  }
  printf("# twin - cylinder mean angle %.3g rad (pi/90 = %.3g)\n", theta[1] - theta[0],
         PI / TWIN_FACETS);
  assert_true(fabs(theta[1] - theta[0]) <= PI / TWIN_FACETS);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_nearest_point),
      cmocka_unit_test(test_rim_continuity),
      cmocka_unit_test(test_drum_rest_vs_twin),
      cmocka_unit_test(test_drum_torque_balance),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
