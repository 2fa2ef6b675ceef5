"""adem: a Discrete Element Method engine for adhesive and granular spheres, from Python.

A thin layer over libadem.so (ctypes): every array goes in and out whole, as numpy arrays in
order of particle id, with no Python loop per particle. See docs/python.md.

    import adem
    case = adem.Case.load("cases/pour.yaml", set={"time.end": 0.05})
    adem.run(case, out="out/pour")                 # what `adem run` writes, bit for bit

    w = adem.World()
    glass = w.add_material("glass", density=2500, young=5e6, poisson=0.25,
                           restitution=0.4, friction=0.5)
    w.add_box("box", (0, 0, 0), (0.1, 0.1, 0.2), material=glass)
    w.add_particles(positions, radius=0.002, material=glass)
    w.step(1000)
    x = w.particles("position")                    # (N, 3) float64
"""
from ._world import World, FIELDS, CONTACT_DTYPE
from ._case import Case, run, Progress
from ._results import Results
from ._fields import Fields, FIELD_NAMES
from ._errors import Error, InputError, SimulationError, OutputError

__all__ = ["World", "Case", "run", "Progress", "Results", "Error", "InputError",
           "SimulationError", "OutputError", "FIELDS", "CONTACT_DTYPE", "Fields", "FIELD_NAMES", "__version__",
           "library_path"]

__version__ = "0.1.0"


def library_path():
    """Path of the libadem.so this module uses."""
    from . import _lib
    return _lib.path
