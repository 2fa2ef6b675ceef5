"""Coarse-grained fields (docs/fields.md) from Python: of a live World, or of a run's frames.

    f = adem.Fields(width=0.004, cell=0.002, lo=(0, 0, 0), hi=(0.1, 0.1, 0.1), average="xy")
    for _ in range(10):
        w.step(100)
        f.add(w)                         # one frame: particles and the last force pass's contacts
    rho = f.get("density")               # (nx, ny, nz) numpy array, time-averaged over the frames
    sigma = f.get("stress")              # (nx, ny, nz, 3, 3), Pa
    f.write_vti("out/fields.vti")        # for ParaView

    f, info = adem.Fields.from_run("out/pile", width_diameters=2, last_only=True)
"""
import ctypes
import os
from ctypes import byref, c_double, c_size_t

import numpy as np

from . import _lib
from ._errors import InputError, raise_for
from ._lib import lib

KERNELS = {"gaussian": 0, "lucy": 1}


def _field_names():
    out, k = {}, 0
    while True:
        name = lib.adem_cg_field_name(k)
        if not name or lib.adem_cg_field_components(k) <= 0:
            return out
        out[name.decode()] = k
        k += 1


FIELD_NAMES = _field_names()


def _axes(average):
    avg = [0, 0, 0]
    for ch in average or "":
        if ch not in "xyz":
            raise InputError("average: %r is not an axis (x, y or z)" % ch)
        avg["xyz".index(ch)] = 1
    return avg


def _grid_options(kernel, width, cutoff, cell, lo, hi, average):
    o = lib.adem_fields_default_options()
    if kernel not in KERNELS:
        raise InputError("kernel: %r is not one of %s" % (kernel, ", ".join(KERNELS)))
    o.kernel = KERNELS[kernel]
    if width is not None:
        o.width = float(width)
    if cutoff is not None:
        o.cutoff = float(cutoff)
    if cell is not None:
        o.cell = float(cell)
    for name, v, dst in (("lo", lo, o.lo), ("hi", hi, o.hi)):
        if v is None:
            continue
        v = np.asarray(v, dtype=float).reshape(-1)
        if v.shape != (3,):
            raise InputError("%s: three numbers (x, y, z) expected, got %d" % (name, v.size))
        for a in range(3):
            dst[a] = v[a]
    avg = _axes(average)
    for a in range(3):
        o.average[a] = avg[a]
    return o


class Fields:
    """Kernel-averaged fields on a grid (density, solid fraction, momentum, velocity, kinetic,
    contact and total stress, pressure, coordination, fabric, granular temperature), averaged
    over the frames added. Names: adem.FIELD_NAMES."""

    def __init__(self, width, lo, hi, cell=None, kernel="gaussian", cutoff=None, average="",
                 _handle=None):
        self._err = _lib.Error()
        if _handle is not None:
            self._f = _handle
            return
        if lo is None or hi is None:
            raise InputError("lo and hi: the grid's extent (m) is needed")
        o = _grid_options(kernel, width, cutoff, cell, lo, hi, average)
        h = ctypes.c_void_p()
        raise_for(lib.adem_fields_create(byref(o), byref(h), byref(self._err)), self._err)
        self._f = h.value

    def __del__(self):
        f = getattr(self, "_f", None)
        if f:
            lib.adem_fields_free(f)
            self._f = None

    @classmethod
    def from_run(cls, directory, width=None, width_diameters=None, cell=None, cell_diameters=None,
                 kernel="gaussian", cutoff=None, lo=None, hi=None, average="", t0=None, t1=None,
                 last_only=False):
        """The fields of a run's output folder (particle frames with the contact frames:
        output.contacts on), as `adem fields` computes them. Returns (Fields, info dict).
        Without lo/hi the grid spans the particles plus the kernel's reach."""
        o = lib.adem_fields_default_run_options()
        g = _grid_options(kernel, width, cutoff, cell, lo, hi, average)
        o.grid = g
        o.box_given = int(lo is not None and hi is not None)
        if (lo is None) != (hi is None):
            raise InputError("lo and hi: give both or neither")
        if (width is None) == (width_diameters is None):
            raise InputError("give one of width (m) and width_diameters")
        o.width_diameters = float(width_diameters) if width_diameters is not None else 0.0
        if cell is not None and cell_diameters is not None:
            raise InputError("give at most one of cell (m) and cell_diameters")
        o.cell_diameters = float(cell_diameters) if cell_diameters is not None else 0.0
        if t0 is not None:
            o.t0 = float(t0)
        if t1 is not None:
            o.t1 = float(t1)
        o.last_only = int(bool(last_only))
        err = _lib.Error()
        h = ctypes.c_void_p()
        info = _lib.FieldsRunInfo()
        raise_for(lib.adem_fields_run(os.fsencode(directory), byref(o), byref(h), byref(info),
                                      byref(err)), err)
        out = cls(None, None, None, _handle=h.value)
        return out, {k: getattr(info, k) for k, _ in info._fields_}

    def _check(self, status):
        raise_for(status, self._err)

    def add(self, world):
        """Adds the world's present state as one frame (call after a step: the contacts are
        those of the last force pass)."""
        self._check(lib.adem_fields_add_world(self._f, world._w, byref(self._err)))

    @property
    def frames(self):
        return lib.adem_fields_frames(self._f)

    @property
    def grid(self):
        """(n, origin, cell): node counts along x, y, z (1 on an averaged axis), the first node's
        centre (m) and the spacing (m)."""
        n, o, c = (c_size_t * 3)(), (c_double * 3)(), c_double()
        lib.adem_fields_grid(self._f, byref(n), byref(o), byref(c))
        return tuple(n), tuple(o), c.value

    def coordinates(self):
        """The node centres along x, y and z: three 1-d arrays."""
        n, o, c = self.grid
        return tuple(o[a] + c * np.arange(n[a]) for a in range(3))

    @staticmethod
    def _index(name):
        if name not in FIELD_NAMES:
            raise InputError("no field %r; fields: %s" % (name, ", ".join(FIELD_NAMES)))
        return FIELD_NAMES[name]

    def get(self, name):
        """The field averaged over the frames: shape (nx, ny, nz) for a scalar, (..., 3) for a
        vector, (..., 3, 3) for a tensor (row-major: [..., i, j] is the ij component)."""
        k = self._index(name)
        nc = lib.adem_cg_field_components(k)
        n, _, _ = self.grid
        flat = np.empty(n[0] * n[1] * n[2] * nc)
        self._check(lib.adem_fields_get(self._f, k, flat.ctypes.data, flat.size,
                                        byref(self._err)))
        a = flat.reshape(n[2], n[1], n[0], nc)        # the library's order: x fastest
        a = np.ascontiguousarray(a.transpose(2, 1, 0, 3))
        if nc == 1:
            return a[..., 0]
        if nc == 9:
            return a.reshape(n[0], n[1], n[2], 3, 3)
        return a

    def integral(self, name):
        """Sum over nodes of value x cell volume (m^3; an averaged axis counts its length)."""
        k = self._index(name)
        nc = lib.adem_cg_field_components(k)
        out = np.empty(nc)
        self._check(lib.adem_fields_integral(self._f, k, out.ctypes.data, byref(self._err)))
        return out[0] if nc == 1 else (out.reshape(3, 3) if nc == 9 else out)

    def write_vti(self, path):
        """Every field as a VTK ImageData file (ParaView), written atomically."""
        self._check(lib.adem_fields_write_vti(self._f, os.fsencode(path), byref(self._err)))

    def write_csv(self, path):
        self._check(lib.adem_fields_write_csv(self._f, os.fsencode(path), byref(self._err)))
