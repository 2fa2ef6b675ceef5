"""The Python module (python/adem) against the C library and the `adem` command.

Run by ctest (label python) with PYTHONPATH=python, ADEM_LIBRARY=build/libadem.so.0,
ADEM_BINARY=build/adem and ADEM_TWIN=build/tests/twin_world."""
import filecmp
import os
import shutil
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

import adem

SRC = os.environ.get("ADEM_SOURCE_DIR",
                     os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
BINARY = os.environ.get("ADEM_BINARY", os.path.join(SRC, "build", "adem"))
TWIN = os.environ.get("ADEM_TWIN", os.path.join(SRC, "build", "tests", "twin_world"))

# A small case: 300 spheres poured into a box, 0.03 s (about 1 s of work).
SMALL = """
name: small
seed: 5
materials:
  - {name: glass, density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.25,
     restitution: 0.4, friction: 0.5, rolling_friction: 0.05}
  - {name: wall, density: 7800, youngs_modulus: 5.0e6, poisson_ratio: 0.25,
     restitution: 0.4, friction: 0.5}
interactions:
  - {materials: [glass, glass], rolling: model_c}
particles:
  - type: random
    material: glass
    count: 300
    radius: {distribution: uniform, min: 1.5e-3, max: 2.0e-3}
    min: [0.0, 0.0, 0.005]
    max: [0.04, 0.04, 0.06]
    velocity: [0, 0, -0.3]
walls:
  - {type: box, name: box, min: [0, 0, 0], max: [0.04, 0.04, 0.1], material: wall}
time: {end: 0.03, step: auto}
output: {frame_interval: 0.01, csv_interval: 0.002, checkpoint_interval: 0.01}
"""


@pytest.fixture
def small_case(tmp_path):
    path = tmp_path / "small.yaml"
    path.write_text(SMALL)
    return path


def _tree_equal(a, b):
    """Every file under a equals (bytes) the file of the same name under b, and the names match."""
    fa = sorted(os.path.relpath(os.path.join(d, f), a) for d, _, fs in os.walk(a) for f in fs)
    fb = sorted(os.path.relpath(os.path.join(d, f), b) for d, _, fs in os.walk(b) for f in fs)
    assert fa == fb
    for f in fa:
        assert filecmp.cmp(os.path.join(a, f), os.path.join(b, f), shallow=False), f
    return fa


def test_run_equals_adem_run(small_case, tmp_path, monkeypatch):
    """adem.run writes the files `adem run` writes, bit for bit (same case, sets, out string)."""
    monkeypatch.chdir(tmp_path)
    sets = ["--set", "time.end=0.02", "--set", "materials.glass.friction=0.3"]
    subprocess.run([BINARY, "run", "small.yaml", "--out", "out", "--quiet", "--threads", "2"]
                   + sets, check=True)
    os.rename("out", "out_cli")
    seen = []
    case = adem.Case.load("small.yaml", set={"time.end": 0.02, "materials.glass.friction": 0.3})
    adem.run(case, out="out", threads=1, progress=seen.append)
    files = _tree_equal("out_cli", "out")
    assert "checkpoint" in files and "timeseries.csv" in files
    assert len([f for f in files if f.startswith("frames")]) == 3
    assert seen and seen[-1].final and seen[-1].step == case.total_steps


def test_world_built_in_python_equals_c(tmp_path):
    """The world of tests/python/twin_world.c built through the module: same checkpoint bytes."""
    c_out, py_out = tmp_path / "c.world", tmp_path / "py.world"
    subprocess.run([TWIN, str(c_out)], check=True)
    w = adem.World()
    w.threads = 1
    glass = w.add_material("glass", density=2500.0, young=1e7, poisson=0.3, restitution=0.5,
                           friction=0.4, rolling_friction=0.1)
    steel = w.add_material("steel", density=7800.0, young=1e7, poisson=0.3, restitution=0.6,
                           friction=0.3)
    w.set_interaction(glass, glass, rolling="model_c", rolling_damping=0.3)
    w.add_box("box", (0, 0, 0), (0.04, 0.04, 0.08), material=steel)
    w.set_plane_motion("box.zmax", times=[0.0, 1.0], velocities=[[0, 0, -0.05]] * 2)
    ramp = np.array([[[0, 0, 0.002], [0.04, 0, 0.012], [0.04, 0.04, 0.012]],
                     [[0, 0, 0.002], [0.04, 0.04, 0.012], [0, 0.04, 0.002]]])
    w.add_mesh(ramp, "ramp", material=steel)
    k = np.arange(64)
    pos = np.stack([0.004 + 0.009 * (k % 4), 0.004 + 0.009 * ((k // 4) % 4),
                    0.02 + 0.008 * (k // 16)], axis=1)
    vel = np.stack([0.01 * (k % 3), -0.01 * (k % 5), np.full(64, -0.2)], axis=1)
    ids = w.add_particles(pos, radius=0.0015 + 0.0001 * (k % 4), material=glass, velocity=vel)
    assert (ids == k).all()
    w.dt = 2e-5
    w.prepare()
    w.set_external_force(np.stack([1e-4 * (k % 3), -2e-4 * (k % 2), np.zeros(64)], axis=1))
    w.step(1500)
    assert len(w.contacts()) > 0
    w.save(py_out)
    assert c_out.read_bytes() == py_out.read_bytes()
    # and the world read back continues as the one that wrote it
    back = adem.World.load(py_out)
    w.step(100)
    back.step(100)
    assert (back.particles("position") == w.particles("position")).all()
    assert (back.particles("external_force") == w.particles("external_force")).all()


def test_fields_and_bulk_setters():
    w = adem.World()
    g = w.add_material("glass")
    w.gravity = (0, 0, 0)
    n = 50
    x = np.stack([np.arange(n) * 0.01, np.zeros(n), np.zeros(n)], axis=1)
    w.add_particles(x, radius=0.002, material=g)
    w.dt = 1e-5
    for name, (code, nc) in adem.FIELDS.items():
        a = w.particles(name)
        assert a.shape == ((n, 3) if nc == 3 else (n,)), name
    assert (w.particles("position") == x).all()
    assert (w.ids() == np.arange(n)).all()
    v = np.random.default_rng(1).normal(size=(n, 3))
    w.set_velocities(v)
    w.set_spins(2 * v)
    assert (w.particles("velocity") == v).all()
    assert (w.particles("spin") == 2 * v).all()
    x2 = x + 1.0
    w.set_positions(x2)
    assert (w.particles("position") == x2).all()
    w.set_particle(7, velocity=(1, 2, 3))
    assert tuple(w.particles("velocity")[7]) == (1, 2, 3)
    assert w.particles("material").dtype == np.int64


def test_external_force_acts_and_stays():
    """F = m a: a lone sphere without gravity under a set external force; exact for velocity
    Verlet with a constant force (1e-12); it stays over steps until changed."""
    w = adem.World()
    g = w.add_material("glass", density=2000.0)
    w.gravity = (0, 0, 0)
    w.add_particles([[0, 0, 0]], radius=0.001, material=g)
    w.dt = 1e-5
    m = w.particles("mass")[0]
    w.set_external_force((3e-6, 0, 0), id=0)
    w.step(500)
    w.step(500)
    assert w.particles("velocity")[0, 0] == pytest.approx(3e-6 / m * w.time, rel=1e-12)
    w.set_external_force(np.zeros((1, 3)))
    v = w.particles("velocity").copy()
    w.step(100)
    assert (w.particles("velocity") == v).all()


def test_errors_are_exceptions(small_case, tmp_path):
    """A bad case, a bad array shape and an unknown field raise clear exceptions; the process
    survives and what was written stays."""
    bad = tmp_path / "bad.yaml"
    bad.write_text(SMALL.replace("restitution: 0.4, friction: 0.5, rolling",
                                 "restitution: 1.4, friction: 0.5, rolling"))
    with pytest.raises(adem.InputError) as e:
        adem.Case.load(bad)
    assert e.value.file == str(bad) and e.value.line == 6 and e.value.column > 0
    assert "restitution" in e.value.reason
    w = adem.World()
    w.add_material("glass")
    w.add_particles(np.zeros((4, 3)) + np.arange(4)[:, None] * 0.01, radius=0.001)
    with pytest.raises(adem.InputError, match=r"shape \(4, 3\), got \(3, 3\)"):
        w.set_positions(np.zeros((3, 3)))
    with pytest.raises(adem.InputError, match="unknown particle field 'colour'"):
        w.particles("colour")
    with pytest.raises(adem.InputError, match="cannot be set"):
        w.set_particles("radius", np.zeros((4, 3)))
    with pytest.raises(adem.InputError, match="not finite"):
        w.set_positions(np.full((4, 3), np.nan))
    with pytest.raises(adem.InputError, match="unknown rolling law 'modle_c'"):
        w.set_interaction(0, 0, rolling="modle_c")
    with pytest.raises(ValueError):  # InputError is a ValueError
        w.add_particles(np.zeros((2, 2)), radius=0.001)
    # a run that goes wrong: SimulationError, what it wrote is kept
    case = adem.Case.load(small_case, set={"limits.max_overlap_ratio": 1e-6})
    with pytest.raises(adem.SimulationError, match="overlap"):
        adem.run(case, out=tmp_path / "failed")
    assert (tmp_path / "failed" / "timeseries.csv").exists()
    assert len(w.particles("position")) == 4  # still alive


def test_results_and_resume(small_case, tmp_path, monkeypatch):
    """A results folder read back; its checkpoint continues bit for bit (a run stopped from the
    progress callback and resumed equals one that never stopped)."""
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    monkeypatch.chdir(tmp_path / "a")  # the same output folder name: checkpoints record it
    whole = tmp_path / "a" / "out"
    adem.run(adem.Case.load(small_case), out="out")
    r = adem.Results(whole)
    ts = r.timeseries
    assert "time_s" in ts and len(ts["time_s"]) == 16
    assert ts["time_s"][-1] == pytest.approx(0.03, rel=1e-3)
    f = r.frame(-1)
    assert f["position"].shape == (300, 3) and (f["id"] == np.arange(300)).all()
    case = r.case()
    assert (f["position"] == case.world.particles("position")).all()

    class Stop(Exception):
        pass

    def stop_at_once(p):
        raise Stop()

    monkeypatch.chdir(tmp_path / "b")
    parts = tmp_path / "b" / "out"
    with pytest.raises(Stop):
        adem.run(adem.Case.load(small_case), out="out", progress=stop_at_once)
    resumed = adem.Case.resume("out")
    assert resumed.world.time < 0.03
    adem.run(resumed)
    assert (whole / "checkpoint").read_bytes() == (parts / "checkpoint").read_bytes()


def test_ctrl_c_raises_keyboard_interrupt_after_a_checkpoint(small_case, tmp_path):
    """SIGINT during adem.run: the run stops at the next progress check with a checkpoint
    written, and KeyboardInterrupt is raised."""
    case = adem.Case.load(small_case, set={"time.end": 5.0, "output.checkpoint_interval": 0})
    timer = threading.Timer(1.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt, match="checkpoint written"):
        adem.run(case, out=tmp_path / "int")
    timer.cancel()
    resumed = adem.Case.resume(tmp_path / "int")
    assert 0.0 < resumed.world.time < 5.0
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_installed_module_imports(tmp_path):
    """cmake --install puts the package where Debian's python3 finds a prefix's packages, and
    it loads the installed libadem.so.0 with no environment."""
    build = os.path.dirname(os.environ.get("ADEM_LIBRARY", os.path.join(SRC, "build", "x")))
    subprocess.run(["cmake", "--install", build, "--prefix", str(tmp_path)], check=True,
                   stdout=subprocess.DEVNULL)
    site = [d for d in (tmp_path / "lib").glob("python3*/dist-packages")]
    assert len(site) == 1 and (site[0] / "adem" / "__init__.py").exists()
    env = {k: v for k, v in os.environ.items() if k not in ("ADEM_LIBRARY", "PYTHONPATH")}
    env["PYTHONPATH"] = str(site[0])
    out = subprocess.run([sys.executable, "-c", "import adem; print(adem.library_path())"],
                         env=env, check=True, capture_output=True, text=True, cwd=tmp_path)
    assert out.stdout.strip() == str(tmp_path / "lib" / "libadem.so.0")
