"""adem.Results: a run's output folder read back (timeseries.csv, frames, checkpoint)."""
import ctypes
import glob
import os
from ctypes import byref

import numpy as np

from . import _lib
from ._errors import InputError, raise_for
from ._lib import lib


class Results:
    """The output folder of a run (adem run --out DIR, or adem.run(case, out=DIR))."""

    def __init__(self, folder):
        self.folder = os.fspath(folder)
        if not os.path.isdir(self.folder):
            raise InputError("%s is not a folder of results" % self.folder)
        self._series = None

    @property
    def timeseries(self):
        """timeseries.csv as a dict: column name -> float64 array (one entry per row)."""
        if self._series is None:
            path = os.path.join(self.folder, "timeseries.csv")
            if not os.path.exists(path):
                raise InputError("%s: no such file (the run wrote no CSV rows)" % path)
            with open(path) as f:
                header = f.readline().strip().split(",")
            data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
            if data.size == 0:
                data = np.zeros((0, len(header)))
            if data.shape[1] != len(header):
                raise InputError("%s: %d columns in the header, %d in the rows"
                                 % (path, len(header), data.shape[1]))
            self._series = {name: np.ascontiguousarray(data[:, k])
                            for k, name in enumerate(header)}
        return self._series

    @property
    def columns(self):
        return list(self.timeseries)

    @property
    def frames(self):
        """Paths of the particle frames, in order."""
        return sorted(glob.glob(os.path.join(self.folder, "frames", "particles_*.vtu")))

    def frame(self, k):
        """Particle frame k (an index into frames, or a path) as a dict: time, step, id (int64),
        position (n, 3), radius (n,), and velocity (n, 3) and mass (n,) when the frame has them,
        rows sorted by id."""
        path = self.frames[k] if isinstance(k, int) else os.fspath(k)
        f = _lib.VtuFrame()
        err = _lib.Error()
        raise_for(lib.adem_vtu_read_file(os.fsencode(path), byref(f), byref(err)), err)
        try:
            n = f.n
            pos = np.ctypeslib.as_array(ctypes.cast(f.pos, ctypes.POINTER(ctypes.c_double)),
                                        shape=(n * 3,)).reshape(n, 3).copy() if n else np.zeros((0, 3))
            rad = np.ctypeslib.as_array(f.radius, shape=(n,)).copy() if n else np.zeros(0)
            ids = (np.ctypeslib.as_array(f.id, shape=(n,)).copy() if n and f.id
                   else np.arange(n, dtype=np.int64))
            out = {"time": f.time, "step": f.step}
            extra = {}
            if n and f.velocity:
                extra["velocity"] = np.ctypeslib.as_array(
                    ctypes.cast(f.velocity, ctypes.POINTER(ctypes.c_double)),
                    shape=(n * 3,)).reshape(n, 3).copy()
            if n and f.mass:
                extra["mass"] = np.ctypeslib.as_array(f.mass, shape=(n,)).copy()
        finally:
            lib.adem_vtu_frame_free(byref(f))
        order = np.argsort(ids, kind="stable")
        out.update(id=ids[order], position=pos[order], radius=rad[order])
        out.update({k: v[order] for k, v in extra.items()})
        return out

    @property
    def checkpoint_path(self):
        return os.path.join(self.folder, "checkpoint")

    def case(self, set=None):
        """The checkpoint as a Case that continues bit for bit (adem.run(results.case()), or
        step its world); set may change time.end and the output intervals."""
        from ._case import Case
        return Case.resume(self.checkpoint_path, set=set)
