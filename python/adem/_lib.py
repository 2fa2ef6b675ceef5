"""Loading libadem.so and the C structs it shares with Python (ctypes, no compiler needed).

Every struct below mirrors one of include/adem/*.h; at load time each size is compared with the
library's own (adem_abi_sizeof), so a library built from other headers is refused with a clear
message instead of read wrong.
"""
import ctypes
import ctypes.util
import os
from ctypes import (POINTER, Structure, c_bool, c_char, c_char_p, c_double, c_int, c_int32,
                    c_int64, c_size_t, c_uint, c_uint64, c_void_p)

SONAME = "libadem.so.0"


def _candidates():
    env = os.environ.get("ADEM_LIBRARY")
    if env:
        yield env
        return
    here = os.path.dirname(os.path.abspath(__file__))
    # installed: PREFIX/lib/python3.X/dist-packages/adem -> PREFIX/lib;
    # a source tree: python/adem -> build/ (scripts/setup.sh builds there)
    d = here
    for _ in range(5):
        d = os.path.dirname(d)
        yield os.path.join(d, SONAME)
        yield os.path.join(d, "build", SONAME)
    found = ctypes.util.find_library("adem")
    if found:
        yield found


def _load():
    tried = []
    for path in _candidates():
        if os.path.sep in path and not os.path.exists(path):
            tried.append(path)
            continue
        try:
            return ctypes.CDLL(path), path
        except OSError as e:
            tried.append("%s (%s)" % (path, e))
    raise ImportError("adem: libadem.so not found; build it (cmake --build build) or install it "
                      "(cmake --install build), or set ADEM_LIBRARY to its path. Tried: "
                      + ", ".join(tried))


lib, path = _load()

NAME_MAX = 64
MSG_MAX = 1024
PATH_MAX = 4096

lib.adem_abi_sizeof.restype = c_size_t
lib.adem_abi_sizeof.argtypes = [c_char_p]


class ParamRow(Structure):
    _fields_ = [("id", c_int), ("key", c_char_p), ("unit", c_char_p), ("def_", c_double),
                ("lo", c_double), ("mixing", c_int), ("doc", c_char_p)]


lib.adem_law_param_get.restype = POINTER(ParamRow)
lib.adem_law_param_get.argtypes = [c_int]
PARAM_KEYS = []
while True:
    row = lib.adem_law_param_get(len(PARAM_KEYS))
    if not row:
        break
    PARAM_KEYS.append(row.contents.key.decode())
PARAM_COUNT = len(PARAM_KEYS)


class Vec3(Structure):
    _fields_ = [("x", c_double), ("y", c_double), ("z", c_double)]

    def tuple(self):
        return (self.x, self.y, self.z)


def vec(v):
    x, y, z = (float(c) for c in v)
    return Vec3(x, y, z)


class Error(Structure):
    _fields_ = [("status", c_int), ("message", c_char * MSG_MAX)]


class MaterialDef(Structure):
    _fields_ = [("name", c_char * NAME_MAX), ("density", c_double), ("young", c_double),
                ("poisson", c_double), ("restitution", c_double), ("friction", c_double),
                ("stiffness_factor", c_double), ("rigid", c_bool),
                ("param", c_double * PARAM_COUNT)]


class InteractionDef(Structure):
    _fields_ = [("material_a", c_int), ("material_b", c_int), ("restitution", c_double),
                ("friction", c_double), ("normal", c_int), ("damping", c_int),
                ("tangential", c_int), ("rolling", c_int), ("param", c_double * PARAM_COUNT),
                ("dtk_rolling_modification", c_bool)]


class ParticleDef(Structure):
    _fields_ = [("position", Vec3), ("velocity", Vec3), ("angular_velocity", Vec3),
                ("radius", c_double), ("material", c_int), ("group", c_int)]


class PlaneDef(Structure):
    _fields_ = [("name", c_char * NAME_MAX), ("point", Vec3), ("normal", Vec3),
                ("velocity", Vec3), ("material", c_int), ("shape", c_int), ("radius", c_double),
                ("length", c_double), ("hole_radius", c_double), ("flags", c_int)]


class ServoDef(Structure):
    _fields_ = [("on", c_bool), ("axis", Vec3), ("target_force", c_double), ("gain", c_double),
                ("max_speed", c_double), ("filter", c_double), ("travel_min", c_double),
                ("travel_max", c_double), ("unmeasured", c_bool)]


class MotionDef(Structure):
    _fields_ = [("n", c_size_t), ("time", POINTER(c_double)), ("velocity", POINTER(Vec3)),
                ("axis", Vec3), ("angular_speed", c_double), ("center", Vec3),
                ("position", POINTER(Vec3)), ("servo", ServoDef)]


class MeshTransform(Structure):
    _fields_ = [("scale", c_double), ("rotation", (c_double * 3) * 3), ("translation", Vec3),
                ("material", c_int), ("own_vertices", c_bool)]


class Diagnostics(Structure):
    _fields_ = [("time", c_double), ("kinetic", c_double), ("rotational", c_double),
                ("potential", c_double), ("elastic", c_double), ("dissipated", c_double),
                ("wall_work", c_double), ("initial", c_double), ("balance_error", c_double),
                ("angular_momentum", Vec3), ("brof_impulse", Vec3),
                ("contacts_pp", c_size_t), ("contacts_pw", c_size_t),
                ("max_overlap_ratio", c_double)]


class ContactInfo(Structure):
    _fields_ = [("kind", c_int), ("a", c_uint64), ("b", c_uint64), ("force", Vec3),
                ("overlap_ratio", c_double), ("elastic", c_double),
                ("tangential_history", Vec3), ("rolling_history", Vec3)]


class StepEstimate(Structure):
    _fields_ = [("v_ref", c_double), ("t_collision", c_double), ("t_rayleigh", c_double),
                ("dt", c_double), ("dt_stable", c_double), ("dt_limit", c_double)]


class Progress(Structure):
    _fields_ = [("time", c_double), ("end_time", c_double), ("step", c_uint64),
                ("total_steps", c_uint64), ("wall_seconds", c_double),
                ("eta_seconds", c_double), ("eta_rough", c_int),
                ("steps_per_second", c_double), ("contacts", c_size_t),
                ("particles", c_size_t), ("may_end_early", c_bool), ("final", c_bool),
                ("until", c_char * 160)]


PROGRESS_FN = ctypes.CFUNCTYPE(None, POINTER(Progress), c_void_p)


class RunOptions(Structure):
    _fields_ = [("nthreads", c_int), ("progress", PROGRESS_FN), ("progress_user", c_void_p),
                ("stop_flag", POINTER(c_int))]


class VtuFrame(Structure):
    _fields_ = [("n", c_size_t), ("pos", POINTER(Vec3)), ("radius", POINTER(c_double)),
                ("id", POINTER(c_int64)), ("velocity", POINTER(Vec3)),
                ("mass", POINTER(c_double)), ("time", c_double), ("step", c_int64)]


class FieldsOptions(Structure):
    _fields_ = [("kernel", c_int), ("width", c_double), ("cutoff", c_double), ("cell", c_double),
                ("lo", c_double * 3), ("hi", c_double * 3), ("average", c_bool * 3)]


class FieldsRunOptions(Structure):
    _fields_ = [("grid", FieldsOptions), ("box_given", c_bool), ("width_diameters", c_double),
                ("cell_diameters", c_double), ("t0", c_double), ("t1", c_double),
                ("last_only", c_bool)]


class FieldsRunInfo(Structure):
    _fields_ = [("frames", c_size_t), ("t_first", c_double), ("t_last", c_double),
                ("particles", c_size_t), ("contacts", c_size_t), ("width", c_double),
                ("mean_diameter", c_double), ("mass", c_double)]


_MIRRORS = {"adem_error": Error, "adem_vec3": Vec3, "adem_material_def": MaterialDef,
            "adem_interaction_def": InteractionDef, "adem_particle_def": ParticleDef,
            "adem_plane_def": PlaneDef, "adem_servo_def": ServoDef,
            "adem_motion_def": MotionDef, "adem_mesh_transform": MeshTransform,
            "adem_diagnostics": Diagnostics, "adem_contact_info": ContactInfo,
            "adem_step_estimate": StepEstimate, "adem_progress": Progress,
            "adem_run_options": RunOptions, "adem_vtu_frame": VtuFrame,
            "adem_particle_field": c_int}
_FIELDS_MIRRORS = {"adem_fields_options": FieldsOptions,
                   "adem_fields_run_options": FieldsRunOptions,
                   "adem_fields_run_info": FieldsRunInfo}
lib.adem_fields_abi_sizeof.restype = c_size_t
lib.adem_fields_abi_sizeof.argtypes = [c_char_p]
for _name, _t in list(_MIRRORS.items()) + list(_FIELDS_MIRRORS.items()):
    _c = (lib.adem_fields_abi_sizeof if _name in _FIELDS_MIRRORS else lib.adem_abi_sizeof)(
        _name.encode())
    if _c != ctypes.sizeof(_t):
        raise ImportError("adem: %s (%s) is %d bytes in the library but %d in this module: the "
                          "module and the library come from different versions"
                          % (_name, path, _c, ctypes.sizeof(_t)))

W = c_void_p  # adem_world *
C = c_void_p  # adem_case *
ST = c_int    # adem_status
E = POINTER(Error)


def _sig(name, restype, *argtypes):
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)


_sig("adem_world_create", W)
_sig("adem_world_free", None, W)
_sig("adem_default_material_def", MaterialDef)
_sig("adem_default_interaction_def", InteractionDef)
_sig("adem_default_particle_def", ParticleDef)
_sig("adem_default_plane_def", PlaneDef)
_sig("adem_default_mesh_transform", MeshTransform)
_sig("adem_mesh_transform_rotate", ST, POINTER(MeshTransform), Vec3, c_double, E)
_sig("adem_world_add_material", ST, W, POINTER(MaterialDef), POINTER(c_int), E)
_sig("adem_world_find_material", c_int, W, c_char_p)
_sig("adem_world_material_count", c_int, W)
_sig("adem_world_material", POINTER(MaterialDef), W, c_int)
_sig("adem_world_set_interaction", ST, W, POINTER(InteractionDef), E)
_sig("adem_world_add_group", ST, W, c_char_p, Vec3, POINTER(c_int), E)
_sig("adem_world_find_group", c_int, W, c_char_p)
_sig("adem_world_add_particle", ST, W, POINTER(ParticleDef), POINTER(c_uint64), E)
_sig("adem_world_add_particles", ST, W, c_size_t, c_void_p, c_void_p, c_void_p, c_void_p,
     c_void_p, c_void_p, c_void_p, E)
_sig("adem_world_add_plane", ST, W, POINTER(PlaneDef), POINTER(c_int), E)
_sig("adem_world_add_box", ST, W, c_char_p, Vec3, Vec3, c_int, POINTER(c_int), E)
_sig("adem_world_add_mesh", ST, W, c_void_p, c_size_t, c_char_p, POINTER(MeshTransform), E)
_sig("adem_world_add_stl", ST, W, c_char_p, POINTER(MeshTransform), c_char_p, Vec3, E)
_sig("adem_world_plane_count", c_int, W)
_sig("adem_world_plane", POINTER(PlaneDef), W, c_int)
_sig("adem_world_mesh_group_count", c_int, W)
_sig("adem_world_mesh_group_name", c_char_p, W, c_int)
_sig("adem_world_find_mesh_group", c_int, W, c_char_p)
_sig("adem_world_set_plane_motion", ST, W, c_int, POINTER(MotionDef), E)
_sig("adem_world_set_mesh_motion", ST, W, c_int, POINTER(MotionDef), E)
_sig("adem_world_set_plane_active", ST, W, c_int, c_int, E)
_sig("adem_world_set_mesh_active", ST, W, c_int, c_int, E)
_sig("adem_world_set_gravity", None, W, Vec3)
_sig("adem_world_set_threads", None, W, c_int)
_sig("adem_world_set_skin", None, W, c_double)
_sig("adem_world_set_max_overlap_ratio", None, W, c_double)
_sig("adem_world_set_initial_overlap", None, W, c_double)
_sig("adem_world_set_domain", None, W, Vec3, Vec3)
_sig("adem_world_set_periodic", ST, W, Vec3, Vec3, c_uint, E)
_sig("adem_world_estimate_step", StepEstimate, W, c_double)
_sig("adem_world_set_dt", None, W, c_double)
_sig("adem_world_dt", c_double, W)
_sig("adem_world_set_energy_balance", None, W, ctypes.c_bool)
_sig("adem_world_prepare", ST, W, E)
_sig("adem_world_step", ST, W, c_uint64, E)
_sig("adem_world_compute_forces", None, W)
_sig("adem_world_time", c_double, W)
_sig("adem_world_step_count", c_uint64, W)
_sig("adem_world_particle_count", c_size_t, W)
_sig("adem_world_diagnostics", Diagnostics, W)
_sig("adem_world_get_particles", ST, W, c_int, c_void_p, c_size_t, E)
_sig("adem_world_get_ids", ST, W, c_void_p, c_size_t, E)
_sig("adem_world_set_particles", ST, W, c_int, c_void_p, c_size_t, E)
_sig("adem_world_set_particle", ST, W, c_uint64, POINTER(Vec3), POINTER(Vec3), POINTER(Vec3), E)
_sig("adem_world_set_external_force", ST, W, c_uint64, Vec3, E)
_sig("adem_world_particle_image", ST, W, c_uint64, POINTER(c_int32), E)
_sig("adem_world_contacts", c_size_t, W, c_void_p, c_size_t)
_sig("adem_world_clear_history", None, W)
_sig("adem_world_plane_forces", None, W, c_void_p)
_sig("adem_world_mesh_wall_count", c_int, W)
_sig("adem_world_mesh_loads", None, W, c_void_p, c_void_p, c_void_p, c_void_p)
_sig("adem_world_checkpoint_write", ST, W, c_char_p, E)
_sig("adem_world_checkpoint_read", ST, c_char_p, POINTER(W), E)
_sig("adem_case_load_file", ST, c_char_p, POINTER(c_char_p), c_int, POINTER(C), E)
_sig("adem_case_load_string_at", ST, c_char_p, c_char_p, c_char_p, POINTER(c_char_p), c_int,
     POINTER(C), E)
_sig("adem_case_free", None, C)
_sig("adem_case_world", W, C)
_sig("adem_case_set_output_dir", ST, C, c_char_p, E)
_sig("adem_case_output_dir", c_char_p, C)
_sig("adem_case_end_time", c_double, C)
_sig("adem_case_name", c_char_p, C)
_sig("adem_case_total_steps", c_uint64, C)
_sig("adem_default_run_options", RunOptions)
_sig("adem_run", ST, C, POINTER(RunOptions), E)
_sig("adem_checkpoint_read_with", ST, c_char_p, POINTER(c_char_p), c_int, POINTER(C), E)
_sig("adem_checkpoint_write", ST, C, c_char_p, E)
_sig("adem_vtu_read_file", ST, c_char_p, POINTER(VtuFrame), E)
_sig("adem_vtu_frame_free", None, POINTER(VtuFrame))
_sig("adem_default_thread_count", c_int)
F = c_void_p  # adem_fields *
_sig("adem_fields_default_options", FieldsOptions)
_sig("adem_fields_default_run_options", FieldsRunOptions)
_sig("adem_fields_create", ST, POINTER(FieldsOptions), POINTER(F), E)
_sig("adem_fields_free", None, F)
_sig("adem_fields_add_world", ST, F, W, E)
_sig("adem_fields_frames", c_size_t, F)
_sig("adem_fields_grid", None, F, POINTER(c_size_t * 3), POINTER(c_double * 3), POINTER(c_double))
_sig("adem_fields_get", ST, F, c_int, c_void_p, c_size_t, E)
_sig("adem_fields_integral", ST, F, c_int, c_void_p, E)
_sig("adem_fields_write_vti", ST, F, c_char_p, E)
_sig("adem_fields_write_csv", ST, F, c_char_p, E)
_sig("adem_fields_run", ST, c_char_p, POINTER(FieldsRunOptions), POINTER(F), POINTER(FieldsRunInfo),
     E)
_sig("adem_cg_field_components", c_int, c_int)
_sig("adem_cg_field_name", c_char_p, c_int)


class LawRow(Structure):
    _fields_ = [("slot", c_int), ("id", c_int), ("name", c_char_p)]


_sig("adem_law_find", POINTER(LawRow), c_int, c_char_p)
_sig("adem_law_choices", c_char_p, c_int)
