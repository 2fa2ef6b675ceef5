"""adem.World: a world built, stepped and read from Python (adem/world.h)."""
import ctypes
import math
import os
from ctypes import byref, c_double, c_int, c_int32, c_uint64

import numpy as np

from . import _lib
from ._errors import InputError, raise_for
from ._lib import lib, vec

# Particle fields: name -> (adem_particle_field, components, numpy dtype of the result).
FIELDS = {
    "position": (0, 3), "velocity": (1, 3), "angular_velocity": (2, 3), "force": (3, 3),
    "torque": (4, 3), "rolling_torque": (5, 3), "radius": (6, 1), "mass": (7, 1),
    "material": (8, 1), "contacts": (9, 1), "path_length": (10, 1), "inverse_mass": (11, 1),
    "inverse_inertia": (12, 1), "external_force": (13, 3),
}
_ALIASES = {"spin": "angular_velocity", "omega": "angular_velocity", "pos": "position",
            "vel": "velocity"}
_SETTABLE = ("position", "velocity", "angular_velocity", "external_force")
_INT_FIELDS = ("material", "contacts")

# A contact of the last force pass (adem_contact_info): kind 0 particle pair (b a particle id),
# 1 plane (b a plane index), 2 mesh (b a mesh group).
CONTACT_DTYPE = np.dtype([("kind", np.int32), ("a", np.uint64), ("b", np.uint64),
                          ("force", np.float64, (3,)), ("overlap_ratio", np.float64),
                          ("elastic", np.float64), ("tangential_history", np.float64, (3,)),
                          ("rolling_history", np.float64, (3,))], align=True)
assert CONTACT_DTYPE.itemsize == ctypes.sizeof(_lib.ContactInfo)

_SLOTS = {"normal": 0, "damping": 1, "tangential": 2, "rolling": 3}
_AXES = {"x": 1, "y": 2, "z": 4}


def _field(name):
    key = _ALIASES.get(name, name)
    if key not in FIELDS:
        raise InputError("unknown particle field %r: the fields are %s" %
                         (name, ", ".join(sorted(FIELDS))))
    return key


def _rows(a, n, what, width=3):
    """a as a C-contiguous float64 array of n rows of width (a single row is repeated)."""
    arr = np.asarray(a, dtype=np.float64)
    if (width > 1 and arr.shape == (width,)) or (width == 1 and arr.ndim == 0):
        arr = np.broadcast_to(arr, (n, width) if width > 1 else (n,))
    want = (n, width) if width > 1 else (n,)
    if arr.shape != want:
        raise InputError("%s: expected an array of shape %s, got %s" % (what, want, arr.shape))
    return np.ascontiguousarray(arr)


def _law(slot, name):
    row = lib.adem_law_find(_SLOTS[slot], name.encode())
    if not row:
        raise InputError("unknown %s law %r: the choices are %s" %
                         (slot, name, lib.adem_law_choices(_SLOTS[slot]).decode()))
    return row.contents.id


def _param_index(key):
    if key not in _lib.PARAM_KEYS:
        return None
    return _lib.PARAM_KEYS.index(key)


class World:
    """A world of spheres, walls and contact laws (adem/world.h). Made empty (World()), read from
    a world checkpoint (World.load), or the world of a loaded case (Case.world)."""

    def __init__(self, _handle=None, _owner=None):
        if _handle is None:
            _handle = lib.adem_world_create()
            if not _handle:
                raise MemoryError("adem: out of memory making a world")
            self._owned = True
        else:
            self._owned = _owner is None
        self._w = ctypes.c_void_p(_handle)
        self._owner = _owner  # a Case that owns the world keeps it alive
        self._err = _lib.Error()

    def __del__(self):
        if getattr(self, "_owned", False) and self._w:
            lib.adem_world_free(self._w)
            self._w = ctypes.c_void_p()

    def _check(self, status):
        raise_for(status, self._err)

    # ------------------------------------------------------------------ set-up
    def add_material(self, name, density=2500.0, young=1e7, poisson=0.3, restitution=0.5,
                     friction=0.5, stiffness_factor=1.0, rigid=False, **params):
        """Adds a material; returns its index. params: the contact laws' parameters by key
        (surface_energy, adhesion_hysteresis, rolling_friction, rolling_damping)."""
        d = lib.adem_default_material_def()
        d.name = name.encode()
        d.density, d.young, d.poisson = density, young, poisson
        d.restitution, d.friction, d.stiffness_factor = restitution, friction, stiffness_factor
        d.rigid = bool(rigid)
        for k, v in params.items():
            i = _param_index(k)
            if i is None:
                raise InputError("material %r: unknown parameter %r: the parameters are %s, "
                                 "density, young, poisson, restitution, friction, "
                                 "stiffness_factor, rigid" % (name, k, ", ".join(_lib.PARAM_KEYS)))
            d.param[i] = v
        index = c_int(-1)
        self._check(lib.adem_world_add_material(self._w, byref(d), byref(index), self._err))
        return index.value

    def material(self, name_or_index):
        """The index of a material given by name (or an index, checked)."""
        if isinstance(name_or_index, str):
            k = lib.adem_world_find_material(self._w, name_or_index.encode())
            if k < 0:
                raise InputError("no material named %r" % name_or_index)
            return k
        k = int(name_or_index)
        if not 0 <= k < lib.adem_world_material_count(self._w):
            raise InputError("no material %d" % k)
        return k

    def set_interaction(self, a, b, restitution=None, friction=None, normal=None, damping=None,
                        tangential=None, rolling=None, dtk_rolling_modification=True, **params):
        """How materials a and b interact: laws by name (normal "hertz"|"jkr", rolling "none"|
        "dtk"|"model_a"|"model_c"|"model_c_capped"|"brof", ...) and values that replace the
        materials' mixed ones (None: derived from the materials)."""
        d = lib.adem_default_interaction_def()
        d.material_a, d.material_b = self.material(a), self.material(b)
        if restitution is not None:
            d.restitution = restitution
        if friction is not None:
            d.friction = friction
        for slot, name in (("normal", normal), ("damping", damping), ("tangential", tangential),
                           ("rolling", rolling)):
            if name is not None:
                setattr(d, slot, _law(slot, name))
        d.dtk_rolling_modification = bool(dtk_rolling_modification)
        for k, v in params.items():
            i = _param_index(k)
            if i is None:
                raise InputError("interaction: unknown parameter %r: the parameters are %s"
                                 % (k, ", ".join(_lib.PARAM_KEYS)))
            d.param[i] = v
        self._check(lib.adem_world_set_interaction(self._w, byref(d), self._err))

    def add_group(self, name, force=(0.0, 0.0, 0.0)):
        """A group of particles with a constant external force each (N); returns its index."""
        index = c_int(-1)
        self._check(lib.adem_world_add_group(self._w, name.encode(), vec(force), byref(index),
                                             self._err))
        return index.value

    def add_particles(self, positions, radius, material=0, velocity=None,
                      angular_velocity=None, group=0):
        """Adds n particles from arrays in one call: positions (n, 3), radius scalar or (n,),
        velocity and angular_velocity (n, 3) or one row for all, material a name or index or
        (n,) indices, group a name or index; returns their ids (n,) uint64. A bad row adds
        none."""
        pos = np.ascontiguousarray(positions, dtype=np.float64)
        if pos.ndim == 1 and pos.shape == (3,):
            pos = pos.reshape(1, 3)
        if pos.ndim != 2 or pos.shape[1] != 3:
            raise InputError("positions: expected an array of shape (n, 3), got %s" % (pos.shape,))
        n = pos.shape[0]
        rad = _rows(radius, n, "radius", 1)
        vel = _rows((0.0, 0.0, 0.0) if velocity is None else velocity, n, "velocity")
        om = _rows((0.0, 0.0, 0.0) if angular_velocity is None else angular_velocity, n,
                   "angular_velocity")
        if np.ndim(material) == 1:  # one material index per particle
            mats = np.ascontiguousarray(material, dtype=np.intc)
            if mats.shape != (n,):
                raise InputError("material: expected %d indices, got %s" % (n, mats.shape))
        else:
            mats = np.full(n, self.material(material), dtype=np.intc)
        grp = group if isinstance(group, int) else lib.adem_world_find_group(self._w,
                                                                            group.encode())
        if grp < 0:
            raise InputError("no group named %r" % group)
        grps = np.full(n, grp, dtype=np.intc)
        ids = np.empty(n, dtype=np.uint64)
        self._check(lib.adem_world_add_particles(self._w, n, pos.ctypes.data, vel.ctypes.data,
                                                 om.ctypes.data, rad.ctypes.data,
                                                 mats.ctypes.data, grps.ctypes.data,
                                                 ids.ctypes.data, self._err))
        return ids

    def add_plane(self, point, normal, material=0, name="plane", velocity=(0.0, 0.0, 0.0)):
        """An infinite plane; particles live on the side its normal points to. Returns its
        index."""
        d = lib.adem_default_plane_def()
        d.name = name.encode()
        d.point, d.normal, d.velocity = vec(point), vec(normal), vec(velocity)
        d.material = self.material(material)
        index = c_int(-1)
        self._check(lib.adem_world_add_plane(self._w, byref(d), byref(index), self._err))
        return index.value

    def add_box(self, name, lo, hi, material=0):
        """Six planes facing inwards (NAME.xmin, NAME.xmax, ...); returns the first's index."""
        first = c_int(-1)
        self._check(lib.adem_world_add_box(self._w, name.encode(), vec(lo), vec(hi),
                                           self.material(material), byref(first), self._err))
        return first.value

    def _transform(self, material, scale, rotation, translation, own_vertices):
        tf = lib.adem_default_mesh_transform()
        tf.scale = scale
        tf.translation = vec(translation)
        tf.material = self.material(material)
        tf.own_vertices = bool(own_vertices)
        if rotation is not None:
            r = np.asarray(rotation, dtype=np.float64)
            if r.shape == (3, 3):
                for i in range(3):
                    for j in range(3):
                        tf.rotation[i][j] = r[i, j]
            else:  # (axis, angle in degrees)
                axis, angle = rotation
                self._check(lib.adem_mesh_transform_rotate(byref(tf), vec(axis), float(angle),
                                                           self._err))
        return tf

    def add_mesh(self, triangles, name, material=0, scale=1.0, rotation=None,
                 translation=(0.0, 0.0, 0.0), own_vertices=False):
        """A mesh wall from an array of triangles (n, 3, 3): corners in metres before the
        transform x' = R (scale x) + translation; rotation a 3x3 matrix or (axis, degrees).
        One group named name; returns the group's index."""
        t = np.ascontiguousarray(np.asarray(triangles, dtype=np.float64))
        if t.ndim != 3 or t.shape[1:] != (3, 3):
            raise InputError("triangles: expected an array of shape (n, 3, 3), got %s" % (t.shape,))
        tf = self._transform(material, scale, rotation, translation, own_vertices)
        self._check(lib.adem_world_add_mesh(self._w, t.ctypes.data, t.shape[0], name.encode(),
                                            byref(tf), self._err))
        return self.mesh_group(name)

    def add_stl(self, path, name, material=0, scale=1.0, rotation=None,
                translation=(0.0, 0.0, 0.0), own_vertices=False):
        """A mesh wall from an ASCII or binary STL file (one group per solid)."""
        tf = self._transform(material, scale, rotation, translation, own_vertices)
        self._check(lib.adem_world_add_stl(self._w, os.fsencode(path), byref(tf), name.encode(),
                                           _lib.Vec3(0, 0, 0), self._err))

    def mesh_group(self, name):
        """Index of the mesh group named name."""
        g = lib.adem_world_find_mesh_group(self._w, name.encode())
        if g < 0:
            names = [lib.adem_world_mesh_group_name(self._w, k).decode()
                     for k in range(lib.adem_world_mesh_group_count(self._w))]
            raise InputError("no mesh group named %r: the groups are %s" % (name, names))
        return g

    @property
    def mesh_groups(self):
        return [lib.adem_world_mesh_group_name(self._w, k).decode()
                for k in range(lib.adem_world_mesh_group_count(self._w))]

    def plane(self, name):
        """Index of the plane named name."""
        for k in range(lib.adem_world_plane_count(self._w)):
            if lib.adem_world_plane(self._w, k).contents.name.decode() == name:
                return k
        raise InputError("no plane named %r" % name)

    def _motion(self, times, velocities, positions, axis, angular_speed, center):
        m = _lib.MotionDef()
        keep = []
        if times is not None:
            t = np.ascontiguousarray(times, dtype=np.float64)
            if t.ndim != 1:
                raise InputError("motion times: expected a 1-d array, got shape %s" % (t.shape,))
            if (velocities is None) == (positions is None):
                raise InputError("motion: give either velocities or positions at the times")
            table = _rows(velocities if velocities is not None else positions, len(t),
                          "motion velocities" if velocities is not None else "motion positions")
            m.n = len(t)
            m.time = t.ctypes.data_as(ctypes.POINTER(c_double))
            ptr = table.ctypes.data_as(ctypes.POINTER(_lib.Vec3))
            if velocities is not None:
                m.velocity = ptr
            else:
                m.position = ptr
            keep += [t, table]
        m.axis = vec(axis)
        m.angular_speed = angular_speed
        m.center = vec(center)
        return m, keep

    def set_plane_motion(self, plane, times=None, velocities=None, positions=None,
                         axis=(0.0, 0.0, 1.0), angular_speed=0.0, center=(0.0, 0.0, 0.0)):
        """Prescribed motion of a plane (index or name): a piecewise-linear velocity or position
        table in time, and a rotation about axis through center."""
        k = self.plane(plane) if isinstance(plane, str) else plane
        m, keep = self._motion(times, velocities, positions, axis, angular_speed, center)
        self._check(lib.adem_world_set_plane_motion(self._w, k, byref(m), self._err))
        del keep

    def set_mesh_motion(self, group, times=None, velocities=None, positions=None,
                        axis=(0.0, 0.0, 1.0), angular_speed=0.0, center=(0.0, 0.0, 0.0)):
        """Prescribed motion of a mesh group (index or name; loaded with own_vertices=True)."""
        g = self.mesh_group(group) if isinstance(group, str) else group
        m, keep = self._motion(times, velocities, positions, axis, angular_speed, center)
        self._check(lib.adem_world_set_mesh_motion(self._w, g, byref(m), self._err))
        del keep

    def set_wall_active(self, name, active):
        """Switches a plane or mesh group (by name) on or off."""
        g = lib.adem_world_find_mesh_group(self._w, name.encode())
        if g >= 0:
            self._check(lib.adem_world_set_mesh_active(self._w, g, int(bool(active)), self._err))
        else:
            self._check(lib.adem_world_set_plane_active(self._w, self.plane(name),
                                                        int(bool(active)), self._err))

    @property
    def gravity(self):
        raise AttributeError("gravity is write-only")

    @gravity.setter
    def gravity(self, g):
        lib.adem_world_set_gravity(self._w, vec(g))

    @property
    def threads(self):
        raise AttributeError("threads is write-only")

    @threads.setter
    def threads(self, n):
        """Threads of the step loops (results do not depend on it)."""
        lib.adem_world_set_threads(self._w, int(n))

    def set_skin(self, fraction):
        lib.adem_world_set_skin(self._w, fraction)

    def set_max_overlap_ratio(self, ratio):
        lib.adem_world_set_max_overlap_ratio(self._w, ratio)

    def set_initial_overlap(self, ratio):
        lib.adem_world_set_initial_overlap(self._w, ratio)

    def set_energy_balance(self, on):
        lib.adem_world_set_energy_balance(self._w, bool(on))

    def set_domain(self, lo, hi):
        """The box outside of which a particle has escaped (a run error)."""
        lib.adem_world_set_domain(self._w, vec(lo), vec(hi))

    def set_periodic(self, lo, hi, axes="xyz"):
        """Periodic box lo..hi along the axes named in axes ("x", "xy", ...; "" turns it off)."""
        bits = 0
        for a in axes:
            if a not in _AXES:
                raise InputError("periodic axes: %r is not x, y or z" % a)
            bits |= _AXES[a]
        self._check(lib.adem_world_set_periodic(self._w, vec(lo), vec(hi), bits, self._err))

    def estimate_step(self, v_ref=1.0):
        """The proposed time step from the Hertz collision and Rayleigh times: a dict of v_ref,
        t_collision, t_rayleigh and dt."""
        e = lib.adem_world_estimate_step(self._w, v_ref)
        return {k: getattr(e, k) for k, _ in e._fields_}

    @property
    def dt(self):
        return lib.adem_world_dt(self._w)

    @dt.setter
    def dt(self, value):
        lib.adem_world_set_dt(self._w, float(value))

    # ------------------------------------------------------------------ stepping
    def prepare(self):
        """Validates the set-up and computes the first forces (step does it if needed)."""
        self._check(lib.adem_world_prepare(self._w, self._err))

    def step(self, n=1):
        """Advances n steps."""
        if self.dt <= 0.0:
            raise InputError("the time step is not set: set World.dt (estimate_step() proposes "
                             "one)")
        self._check(lib.adem_world_step(self._w, int(n), self._err))

    def run_to(self, t):
        """Steps to the first step at or after time t (s)."""
        dt = self.dt
        if dt <= 0.0:
            raise InputError("the time step is not set: set World.dt")
        n = int(math.ceil(t / dt - 1e-9)) - self.step_count
        if n > 0:
            self.step(n)

    def compute_forces(self):
        """One force pass at the current state, moving nothing."""
        lib.adem_world_compute_forces(self._w)

    @property
    def time(self):
        return lib.adem_world_time(self._w)

    @property
    def step_count(self):
        return lib.adem_world_step_count(self._w)

    def __len__(self):
        return lib.adem_world_particle_count(self._w)

    @property
    def particle_count(self):
        return lib.adem_world_particle_count(self._w)

    # ------------------------------------------------------------------ reading and setting
    def ids(self):
        """The particle ids in increasing order (row k of every array is particle ids()[k])."""
        n = len(self)
        out = np.empty(n, dtype=np.uint64)
        self._check(lib.adem_world_get_ids(self._w, out.ctypes.data, n, self._err))
        return out

    def particles(self, field):
        """A particle field in id order: (N, 3) float64 for vectors, (N,) for scalars (int64 for
        material and contacts). Fields: adem.FIELDS."""
        key = _field(field)
        code, nc = FIELDS[key]
        n = len(self)
        out = np.empty((n, 3) if nc == 3 else n, dtype=np.float64)
        self._check(lib.adem_world_get_particles(self._w, code, out.ctypes.data, n * nc,
                                                 self._err))
        return out.astype(np.int64) if key in _INT_FIELDS else out

    def set_particles(self, field, values):
        """Sets position, velocity, angular_velocity or external_force of every particle from
        an (N, 3) array in id order (one row of 3: the same for all)."""
        key = _field(field)
        if key not in _SETTABLE:
            raise InputError("particle field %r cannot be set: %s can" % (key, ", ".join(_SETTABLE)))
        n = len(self)
        a = _rows(values, n, key)
        self._check(lib.adem_world_set_particles(self._w, FIELDS[key][0], a.ctypes.data, n,
                                                 self._err))

    def set_positions(self, x):
        self.set_particles("position", x)

    def set_velocities(self, v):
        self.set_particles("velocity", v)

    def set_spins(self, omega):
        self.set_particles("angular_velocity", omega)

    def set_external_force(self, force, id=None):
        """The external force (N) of every particle ((N, 3) in id order, or one row for all), or
        of particle id alone: it acts in every step until changed, and is saved in checkpoints."""
        if id is None:
            self.set_particles("external_force", force)
        else:
            self._check(lib.adem_world_set_external_force(self._w, int(id), vec(force),
                                                          self._err))

    def set_particle(self, id, position=None, velocity=None, angular_velocity=None):
        """Places one particle or sets its velocity or spin (None: keep)."""
        p = byref(vec(position)) if position is not None else None
        v = byref(vec(velocity)) if velocity is not None else None
        o = byref(vec(angular_velocity)) if angular_velocity is not None else None
        self._check(lib.adem_world_set_particle(self._w, int(id), p, v, o, self._err))

    def image(self, id):
        """Periodic faces particle id has crossed along x, y, z."""
        out = (c_int32 * 3)()
        self._check(lib.adem_world_particle_image(self._w, int(id), out, self._err))
        return tuple(out)

    def contacts(self):
        """The touching contacts of the last force pass as a structured array (CONTACT_DTYPE):
        kind (0 particle, 1 plane, 2 mesh), a (particle id), b (particle id, plane index or mesh
        group), force on a (N), overlap_ratio, elastic (J), tangential_history,
        rolling_history."""
        n = lib.adem_world_contacts(self._w, None, 0)
        out = np.zeros(n, dtype=CONTACT_DTYPE)
        if n:
            got = lib.adem_world_contacts(self._w, out.ctypes.data, n)
            assert got == n
        return out

    def clear_history(self):
        lib.adem_world_clear_history(self._w)

    def diagnostics(self):
        """Summed state (energies in J, contact counts, largest overlap ratio) as a dict."""
        d = lib.adem_world_diagnostics(self._w)
        out = {}
        for k, _ in d._fields_:
            v = getattr(d, k)
            out[k] = v.tuple() if isinstance(v, _lib.Vec3) else v
        return out

    def plane_forces(self):
        """Force of the particles on each plane, (planes, 3)."""
        n = lib.adem_world_plane_count(self._w)
        out = np.zeros((n, 3))
        if n:
            lib.adem_world_plane_forces(self._w, out.ctypes.data)
        return out

    def mesh_loads(self):
        """Force and torque on each mesh group: two (groups, 3) arrays."""
        n = lib.adem_world_mesh_group_count(self._w)
        f, t = np.zeros((n, 3)), np.zeros((n, 3))
        if n:
            lib.adem_world_mesh_loads(self._w, f.ctypes.data, t.ctypes.data, None, None)
        return f, t

    # ------------------------------------------------------------------ checkpoints
    def save(self, path):
        """Writes the world (set-up and state) atomically; World.load continues it bit for bit."""
        self._check(lib.adem_world_checkpoint_write(self._w, os.fsencode(path), self._err))

    @classmethod
    def load(cls, path):
        err = _lib.Error()
        h = ctypes.c_void_p()
        raise_for(lib.adem_world_checkpoint_read(os.fsencode(path), byref(h), byref(err)), err)
        return cls(h.value)
