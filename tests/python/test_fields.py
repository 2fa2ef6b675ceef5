"""adem.Fields: coarse-grained fields of a live World from Python (docs/fields.md).

Claims, on a small bed settled on a floor at z = 0 (gravity g along -z):
- mass: the grid integral of the density is the particles' total mass (the kernel is normalised,
  and the grid reaches past every kernel's cut-off);
- the virial: the grid integral of the contact stress is sum over contacts of f (x) l
  = sum_i F_i (x) x_i - sum over wall contacts of f (x) x_wall, F_i the contact force on
  particle i (its total force less its weight) and x_wall the foot of its centre on the plane
  (compression positive). An identity of the contact lines, to rounding (1e-9): it holds only if
  every contact's line (particle pairs and wall feet) reaches the library, so it checks the
  binding's contact frame. At rest its zz part is about sum_i m_i g z_i (10 %: the side walls'
  friction holds part of the weight).
- the same frame through a run's output folder (Fields.from_run) gives the same fields.
"""
import numpy as np
import pytest

import adem

G = 9.81


def settled_bed():
    w = adem.World()
    glass = w.add_material("glass", density=2500, young=5e6, poisson=0.25, restitution=0.3,
                           friction=0.5)
    w.add_box("box", (0.0, 0.0, 0.0), (0.02, 0.02, 0.06), material=glass)
    r = 1.0e-3
    g = np.mgrid[0:6, 0:6, 0:5].reshape(3, -1).T
    rng = np.random.default_rng(3)
    pos = (g + 0.5) * 2.6 * r + np.array([0.0025, 0.0025, 0.001])
    pos[:, :2] += rng.uniform(-0.2 * r, 0.2 * r, (len(pos), 2))
    w.add_particles(pos, radius=r, material=glass)
    w.gravity = (0.0, 0.0, -G)
    w.dt = w.estimate_step(1.0)["dt"]
    w.prepare()
    for _ in range(60):
        w.step(500)
        if w.diagnostics()["kinetic"] < 1e-12:
            break
    return w


@pytest.fixture(scope="module")
def bed():
    return settled_bed()


def bed_fields(w, **kw):
    f = adem.Fields(width=1.0e-3, cell=0.5e-3, lo=(-0.006, -0.006, -0.006),
                    hi=(0.026, 0.026, 0.04), **kw)
    f.add(w)
    return f


def test_density_integrates_to_the_mass(bed):
    f = bed_fields(bed)
    mass = bed.particles("mass").sum()
    assert f.frames == 1
    rho = f.get("density")
    n, _, _ = f.grid
    assert rho.shape == tuple(n)
    assert f.integral("density") == pytest.approx(mass, rel=1e-6)
    # the array is indexed [x, y, z]: the density's centre of mass is the particles'
    x, y, z = f.coordinates()
    zc = (rho.sum(axis=(0, 1)) * z).sum() / rho.sum()
    zm = (bed.particles("mass") * bed.particles("position")[:, 2]).sum() / mass
    assert zc == pytest.approx(zm, rel=1e-3)


def test_contact_stress_integral_is_the_virial_of_the_contact_forces(bed):
    f = bed_fields(bed)
    x = bed.particles("position")
    fc = bed.particles("force") - bed.particles("mass")[:, None] * np.array([0.0, 0.0, -G])
    # walls: minus sum f (x) x_w over the wall contacts, x_w the foot of a's centre on the plane
    ids = bed.ids()
    row = {int(i): k for k, i in enumerate(ids)}
    wall = np.zeros((3, 3))
    for c in bed.contacts():
        if c["kind"] != 1:
            continue
        pl = adem._lib.lib.adem_world_plane(bed._w, int(c["b"])).contents
        n, p = np.array(pl.normal.tuple()), np.array(pl.point.tuple())
        xa = x[row[int(c["a"])]]
        foot = xa - np.dot(xa - p, n) * n
        wall += np.outer(c["force"], foot)
    expect = np.einsum("ia,ib->ab", fc, x) - wall
    sigma = f.integral("contact_stress")
    assert sigma.shape == (3, 3)
    scale = np.abs(expect).max()
    assert np.abs(sigma - expect).max() <= 1e-9 * scale
    # and the bed at rest carries its weight: zz is sum_i m_i g z_i, less what the side walls'
    # friction holds (a few per cent here), so within 10 %
    weight = (bed.particles("mass") * G * x[:, 2]).sum()
    assert sigma[2, 2] == pytest.approx(weight, rel=0.10)


def test_average_axes_and_errors(bed):
    f = bed_fields(bed, average="xy")
    n, _, _ = f.grid
    assert n[0] == 1 and n[1] == 1 and n[2] > 1
    assert f.get("stress").shape == (1, 1, n[2], 3, 3)
    assert f.get("velocity").shape == (1, 1, n[2], 3)
    with pytest.raises(adem.InputError):
        f.get("no_such_field")
    with pytest.raises(adem.InputError):
        adem.Fields(width=1e-3, lo=(0, 0, 0), hi=(1, 1, 1), average="w")


RUN = """
name: fields_small
seed: 5
materials:
  - {name: glass, density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.25,
     restitution: 0.3, friction: 0.5}
particles:
  - type: random
    material: glass
    count: 120
    radius: {distribution: uniform, min: 0.9e-3, max: 1.1e-3}
    min: [0.001, 0.001, 0.001]
    max: [0.019, 0.019, 0.03]
walls:
  - {type: box, name: box, min: [0, 0, 0], max: [0.02, 0.02, 0.06], material: glass}
time: {end: 0.05, step: auto}
output: {frame_interval: 0.025, contacts: true}
"""


def test_from_run_equals_the_live_world(tmp_path):
    case = adem.Case.from_string(RUN)
    adem.run(case, out=str(tmp_path / "run"))
    live = bed_fields(case.world)
    lo, hi = (-0.006, -0.006, -0.006), (0.026, 0.026, 0.04)
    frames, info = adem.Fields.from_run(str(tmp_path / "run"), width=1.0e-3, cell=0.5e-3,
                                        lo=lo, hi=hi, last_only=True)
    assert info["frames"] == 1 and info["particles"] == 120
    assert info["t_last"] == pytest.approx(case.world.time, abs=1e-12)
    for name in ("density", "contact_stress", "coordination"):
        a, b = live.get(name), frames.get(name)
        scale = np.abs(a).max()
        assert scale > 0.0
        assert np.abs(a - b).max() <= 1e-9 * scale, name
