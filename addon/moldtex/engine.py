# SPDX-License-Identifier: GPL-3.0-or-later
"""ctypes binding of libmoldtex (native/include/moldtex.h, ABI 1).

This module never imports bpy: it only knows the C API. Every function's signature is
declared once, when the library is loaded at import. If the library is missing or does
not match, LOAD_ERROR holds a plain-language reason and everything else in the add-on
keeps working (the panel shows the reason); calls then raise EngineError(LOAD_ERROR).

Buffers crossing the boundary are array.array objects (or numpy arrays when a caller
has them): native code gets their address, and the same object is handed to Blender's
foreach_set. Never wrap a ctypes array in a memoryview (it crashed Blender 3.4).
"""

import array
import ctypes
import math
import os
import sys

ABI_VERSION = 1

# moldtex_status values (moldtex.h)
OK = 0
ERROR_INVALID_ARGUMENT = 1
ERROR_INVALID_MESH = 2
ERROR_MISSING_UVS = 3
ERROR_TOO_LARGE = 4
ERROR_OUT_OF_MEMORY = 5
ERROR_INTERNAL = 6
ERROR_UNAVAILABLE = 7
ERROR_IO = 8          # a file could not be read or written
ERROR_BUSY = 9        # a bake is running on this simulation
ERROR_CANCELLED = 10  # the caller cancelled the work (a domain build)

STATUS_NAMES = {
    OK: "ok",
    ERROR_INVALID_ARGUMENT: "invalid argument",
    ERROR_INVALID_MESH: "invalid mesh",
    ERROR_MISSING_UVS: "missing UVs",
    ERROR_TOO_LARGE: "too large",
    ERROR_OUT_OF_MEMORY: "out of memory",
    ERROR_INTERNAL: "internal error",
    ERROR_UNAVAILABLE: "unavailable",
    ERROR_IO: "file error",
    ERROR_BUSY: "busy (a bake is running)",
    ERROR_CANCELLED: "cancelled",
}

# moldtex_backend values (moldtex.h)
BACKEND_AUTO = 0    # OpenCL on the first GPU if there is one and it works, else the CPU
BACKEND_CPU = 1
BACKEND_OPENCL = 2  # the device (opencl_platform, opencl_device)

TEXEL_OUTSIDE = 0
TEXEL_INSIDE = 1
TEXEL_GUTTER = 2

# moldtex_image_format values (moldtex.h)
IMAGE_EXR_HALF = 0   # OpenEXR, 16-bit float, one channel "Y" per species
IMAGE_EXR_FLOAT = 1  # OpenEXR, 32-bit float
IMAGE_PNG8 = 2
IMAGE_PNG16 = 3
IMAGE_EXTENSIONS = {IMAGE_EXR_HALF: ".exr", IMAGE_EXR_FLOAT: ".exr", IMAGE_PNG8: ".png",
                    IMAGE_PNG16: ".png"}

# moldtex_bake_state values (moldtex.h)
BAKE_RUNNING = 0
BAKE_FINISHED = 1
BAKE_CANCELLED = 2
BAKE_FAILED = 3
BAKE_STATE_NAMES = {BAKE_RUNNING: "running", BAKE_FINISHED: "finished",
                    BAKE_CANCELLED: "cancelled", BAKE_FAILED: "failed"}


class EngineError(Exception):
    """A failed core call; str(error) is the core's message (moldtex_last_error)."""

    def __init__(self, message, status=None):
        super().__init__(message)
        self.message = message
        self.status = status


# ---- struct mirrors (field order and types exactly as in moldtex.h) -------------------

class MeshDesc(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("positions", ctypes.POINTER(ctypes.c_float)),
        ("vertex_count", ctypes.c_uint32),
        ("triangles", ctypes.POINTER(ctypes.c_uint32)),
        ("triangle_count", ctypes.c_uint32),
        ("uvs", ctypes.POINTER(ctypes.c_float)),
        ("uv_count", ctypes.c_uint32),
        ("triangle_uvs", ctypes.POINTER(ctypes.c_uint32)),
    ]


class SurfaceInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("vertex_count", ctypes.c_uint32),
        ("triangle_count", ctypes.c_uint32),
        ("boundary_edge_count", ctypes.c_uint32),
        ("seam_edge_count", ctypes.c_uint32),
        ("degenerate_triangle_count", ctypes.c_uint32),
        ("area", ctypes.c_double),
        ("uv_area", ctypes.c_double),
        # appended: 1 when the mesh came without UVs (a placeholder atlas stands in)
        ("generated_uvs", ctypes.c_uint32),
    ]


class SurfacePoint(ctypes.Structure):
    _fields_ = [
        ("triangle", ctypes.c_uint32),
        ("bary", ctypes.c_float * 3),
    ]


class SimConfig(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("width", ctypes.c_uint32),
        ("height", ctypes.c_uint32),
        ("agent_count", ctypes.c_uint32),
        ("seed", ctypes.c_uint64),
        # appended after ABI 1's first release
        ("backend", ctypes.c_uint32),
        ("opencl_platform", ctypes.c_uint32),
        ("opencl_device", ctypes.c_uint32),
        # appended for species, fields and starting seeds
        ("species_count", ctypes.c_uint32),
        ("seed_shape", ctypes.c_uint32),
        ("seed_center", SurfacePoint),
        ("seed_radius", ctypes.c_float),
        ("seed_rays", ctypes.c_uint32),
        ("fields_rgba", ctypes.c_void_p),
        # appended for the continuous model (a moldtex_model)
        ("model", ctypes.c_uint32),
        # appended for the intrinsic domain (a moldtex_domain; mesh units, 0 = auto)
        ("domain", ctypes.c_uint32),
        ("intrinsic_bound", ctypes.c_float),
        # appended for a simulation finer than its image (1, 2 or 4)
        ("detail", ctypes.c_uint32),
    ]


class SpeciesParams(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("movement_speed", ctypes.c_float),
        ("turn_speed", ctypes.c_float),
        ("vision_distance", ctypes.c_float),
        ("vision_angle", ctypes.c_float),
        ("deposit", ctypes.c_float),
        ("attraction", ctypes.c_float * 4),
    ]


class SimParams(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("movement_speed", ctypes.c_float),
        ("turn_speed", ctypes.c_float),
        ("vision_distance", ctypes.c_float),
        ("vision_angle", ctypes.c_float),
        ("evaporation_rate", ctypes.c_float),
        ("diffusion_rate", ctypes.c_float),
        ("deposit", ctypes.c_float),
        ("time_step", ctypes.c_float),
        ("substeps", ctypes.c_uint32),
        ("thread_count", ctypes.c_uint32),
        # Food with hunger (sources: Simulation.set_food / get_food).
        ("hunger_rate", ctypes.c_float),
        ("food_radius", ctypes.c_float),
        # Sensing square radius in texels; 0 = one texel (the default).
        ("sensor_size", ctypes.c_uint32),
        # Surface units: 3D length (mesh units) of one pattern texel; 0 = texel units.
        ("length_unit", ctypes.c_float),
    ]


class FoodSource(ctypes.Structure):
    _fields_ = [
        ("position", ctypes.c_float * 3),
        ("strength", ctypes.c_float),
        ("amount", ctypes.c_float),
    ]


MAX_FOOD_SOURCES = 64  # MOLDTEX_MAX_FOOD_SOURCES


class DomainInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("domain", ctypes.c_uint32),
        ("cell_count", ctypes.c_uint32),
        ("face_count", ctypes.c_uint32),
        ("bound", ctypes.c_double),
        ("build_seconds", ctypes.c_double),
        ("insertions", ctypes.c_uint64),
        ("skipped_faces", ctypes.c_uint32),
        ("from_cache", ctypes.c_uint32),
    ]


class SimStats(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("step_count", ctypes.c_uint64),
        ("agent_count", ctypes.c_uint32),
        ("bytes_in_use", ctypes.c_uint64),
        ("coverage", ctypes.c_double),
        ("presence", ctypes.c_double),
        # appended for the continuous model (0 for MoMaS)
        ("u_metric", ctypes.c_double),           # U, layton-intrinsic-slime.md Eq. 5
        ("mean_concentration", ctypes.c_double),  # area-weighted mean u of species 0
        ("time", ctypes.c_double),               # simulated seconds since create/reset
    ]


class ReactionParams(ctypes.Structure):
    """moldtex_reaction_params (Gray-Scott): F, k per second, D_u, D_v in mesh units^2
    per second, time_step in seconds; seed disks (count, radius in mesh units)."""
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("feed", ctypes.c_float),
        ("kill", ctypes.c_float),
        ("diffusion_u", ctypes.c_float),
        ("diffusion_v", ctypes.c_float),
        ("time_step", ctypes.c_float),
        ("seed_count", ctypes.c_uint32),
        ("seed_radius", ctypes.c_float),
    ]


class ContinuousParams(ctypes.Structure):
    """moldtex_continuous_params: rates per simulated second, lengths in mesh units."""
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("move_rate", ctypes.c_float),        # v: mesh units per second
        ("turn_rate", ctypes.c_float),        # omega: radians per second
        ("turn_frequency", ctypes.c_float),   # f_i: turn decisions per second
        ("sensor_distance", ctypes.c_float),  # d: mesh units along the surface
        ("sensor_angle", ctypes.c_float),     # theta: degrees (negative: chemo-repulsion)
        ("deposit_rate", ctypes.c_float),     # r_dep: amount per agent per second
        ("diffusion_rate", ctypes.c_float),   # r_dif: mesh units^2 per second
        ("decay_rate", ctypes.c_float),       # r_dec: per second
        ("mean_lifetime", ctypes.c_float),    # tau: seconds, 0 = no turnover
        ("activation_time", ctypes.c_float),  # t_a: seconds
        ("time_step", ctypes.c_float),        # dt: seconds per step
        ("integrator", ctypes.c_uint32),      # an INTEGRATOR_* value
        # directional bias (layton-intrinsic-slime.md §3.3, Fig. 6), with set_bias' vectors
        ("bias_strength", ctypes.c_float),    # per second, 0 = off
        ("bias_symmetry", ctypes.c_uint32),   # n, 1 .. 6: n-fold symmetric pull
        ("bias_spawn", ctypes.c_uint32),      # 1: turnover respawns face the bias (Fig. 8)
        ("boundary", ctypes.c_uint32),        # BOUNDARY_*: what agents do at open edges
    ]


class BakeDesc(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("directory", ctypes.c_char_p),
        ("file_prefix", ctypes.c_char_p),
        ("first_frame", ctypes.c_int32),
        ("last_frame", ctypes.c_int32),
        ("steps_per_frame", ctypes.c_uint32),
        ("format", ctypes.c_uint32),
        ("write_checkpoints", ctypes.c_uint32),
        ("resume", ctypes.c_uint32),
    ]


class BakeProgress(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("state", ctypes.c_uint32),
        ("first_frame", ctypes.c_int32),
        ("last_frame", ctypes.c_int32),
        ("last_frame_written", ctypes.c_int32),
        ("frames_done", ctypes.c_uint32),
        ("step_count", ctypes.c_uint64),
        ("coverage", ctypes.c_double),
        ("presence", ctypes.c_double),
        ("message", ctypes.c_char * 512),
    ]


# moldtex_build_stage values: what a domain build does now.
BUILD_TEXTURE, BUILD_REFINING, BUILD_OPERATORS, BUILD_TEXEL_MAP, BUILD_DONE = range(5)
BUILD_STAGE_NAMES = {BUILD_TEXTURE: "texels", BUILD_REFINING: "refining",
                     BUILD_OPERATORS: "operators", BUILD_TEXEL_MAP: "texel map",
                     BUILD_DONE: "done"}


class DomainBuildProgress(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("state", ctypes.c_uint32),
        ("stage", ctypes.c_uint32),
        ("vertex_count", ctypes.c_uint32),
        ("fraction", ctypes.c_double),
        ("seconds", ctypes.c_double),
        ("from_cache", ctypes.c_uint32),
        ("message", ctypes.c_char * 512),
    ]


class RunProgress(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("running", ctypes.c_uint32),
        ("steps", ctypes.c_uint64),
        ("step_seconds", ctypes.c_double),
    ]


class OpenCLDeviceInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("platform_index", ctypes.c_uint32),
        ("device_index", ctypes.c_uint32),
        ("is_gpu", ctypes.c_uint32),
        ("global_memory_bytes", ctypes.c_uint64),
        ("name", ctypes.c_char * 256),
        ("platform_name", ctypes.c_char * 256),
    ]


class RayHit(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("hit", ctypes.c_uint32),
        ("point", SurfacePoint),
        ("distance", ctypes.c_float),
        ("position", ctypes.c_float * 3),
        ("uv", ctypes.c_float * 2),
        ("normal", ctypes.c_float * 3),
    ]


class Brush(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("center", SurfacePoint),
        ("radius", ctypes.c_float),
        ("strength", ctypes.c_float),
        ("falloff", ctypes.c_float),
        ("mode", ctypes.c_uint32),
        ("channel", ctypes.c_uint32),
        ("value", ctypes.c_float),
    ]


class ColourRampDesc(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("channels", ctypes.c_uint32),
        ("srgb_encoded", ctypes.c_uint32),
        ("sample_count", ctypes.c_uint32),
        ("neighbour_count", ctypes.c_uint32),
        ("max_stops", ctypes.c_uint32),
        ("tolerance", ctypes.c_float),
        ("reverse", ctypes.c_uint32),
        ("peak_position", ctypes.c_float),
        ("seed", ctypes.c_uint64),
    ]


class ColourStop(ctypes.Structure):
    _fields_ = [
        ("position", ctypes.c_float),
        ("color", ctypes.c_float * 4),
    ]


class ColourRampInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("stop_count", ctypes.c_uint32),
        ("sample_count", ctypes.c_uint32),
        ("component_count", ctypes.c_uint32),
        ("explained", ctypes.c_float),
        ("variance_explained", ctypes.c_float),
        ("eigen_energy", ctypes.c_float),
        ("mean_error", ctypes.c_float),
        ("ramp_error", ctypes.c_float),
        ("continuity", ctypes.c_float),
    ]


class IntrinsicParams(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("max_circumradius", ctypes.c_float),
        ("max_insertions", ctypes.c_uint32),
    ]


class IntrinsicInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("vertex_count", ctypes.c_uint32),
        ("triangle_count", ctypes.c_uint32),
        ("edge_count", ctypes.c_uint32),
        ("input_vertex_count", ctypes.c_uint32),
        ("input_triangle_count", ctypes.c_uint32),
        ("dropped_triangle_count", ctypes.c_uint32),
        ("stop_reason", ctypes.c_uint32),
        ("flips", ctypes.c_uint64),
        ("insertions", ctypes.c_uint64),
        ("boundary_splits", ctypes.c_uint64),
        ("given_up", ctypes.c_uint64),
        ("faces_over_bound_sharp", ctypes.c_uint32),
        ("faces_over_bound_other", ctypes.c_uint32),
        ("max_circumradius", ctypes.c_double),
        ("largest_circumradius", ctypes.c_double),
        ("area", ctypes.c_double),
        ("mollify_epsilon", ctypes.c_double),
        ("build_seconds", ctypes.c_double),
        ("message", ctypes.c_char * 256),
    ]


# moldtex_intrinsic_stop values (moldtex.h)
INTRINSIC_STOP_CONVERGED = 0
INTRINSIC_STOP_INSERTION_CAP = 1
INTRINSIC_STOP_FLIP_CAP = 2
INTRINSIC_NO_TRIANGLE = 0xFFFFFFFF  # vertex_points() of an unused input vertex
MAX_INTRINSIC_POINTS = 1 << 24      # points per locate / to_input call


MAX_RAMP_STOPS = 32  # Blender's ColorRamp holds at most 32 elements


# moldtex_brush_mode values (moldtex.h)
BRUSH_PAINT = 0
BRUSH_ERASE = 1   # paint: target 0
MAX_BRUSH_BATCH = 65535  # batch numbers of moldtex_sim_add_agents are 1 .. this


# moldtex_model values (moldtex.h): chosen at create (a config field)
MODEL_MOMAS = 0       # momas-paper.md Algorithm 1 (SimParams)
MODEL_CONTINUOUS = 1  # layton-intrinsic-slime.md §3.2 (ContinuousParams)
MODEL_GRAY_SCOTT = 2  # Gray-Scott reaction-diffusion (ReactionParams); no agents

# moldtex_domain values (moldtex.h): where concentrations live (a config field)
DOMAIN_TEXTURE = 0    # the texels of the UV layout
DOMAIN_INTRINSIC = 1  # vertices of an intrinsic Delaunay triangulation (continuous, Gray-Scott)

# moldtex_integrator values (moldtex.h): how the continuous model's PDE is stepped
INTEGRATOR_AUTO = 0      # forward Euler while 64 sub-steps suffice, else backward
INTEGRATOR_FORWARD = 1   # forward Euler (Eq. 2), sub-stepped for stability
INTEGRATOR_BACKWARD = 2  # backward Euler (Eq. 3)


CONFIG_FIELDS = tuple(name for name, _ in SimConfig._fields_ if name != "struct_size")
SPECIES_FIELDS = tuple(name for name, _ in SpeciesParams._fields_ if name != "struct_size")
PARAM_FIELDS = tuple(name for name, _ in SimParams._fields_ if name != "struct_size")
STATS_FIELDS = tuple(name for name, _ in SimStats._fields_ if name != "struct_size")
DOMAIN_INFO_FIELDS = tuple(name for name, _ in DomainInfo._fields_ if name != "struct_size")
CONTINUOUS_FIELDS = tuple(name for name, _ in ContinuousParams._fields_
                          if name != "struct_size")
REACTION_FIELDS = tuple(name for name, _ in ReactionParams._fields_ if name != "struct_size")
SURFACE_INFO_FIELDS = tuple(name for name, _ in SurfaceInfo._fields_ if name != "struct_size")
INTRINSIC_INFO_FIELDS = tuple(name for name, _ in IntrinsicInfo._fields_
                              if name not in ("struct_size", "message"))
BAKE_PROGRESS_FIELDS = tuple(name for name, _ in BakeProgress._fields_
                             if name not in ("struct_size", "message"))

_Surface = ctypes.c_void_p  # opaque moldtex_surface
_Sim = ctypes.c_void_p      # opaque moldtex_sim
_Bake = ctypes.c_void_p     # opaque moldtex_bake
_DomainBuild = ctypes.c_void_p  # opaque moldtex_domain_build
_Intrinsic = ctypes.c_void_p  # opaque moldtex_intrinsic
_status = ctypes.c_int      # moldtex_status (a C enum is an int)
_P = ctypes.POINTER

# name: (restype, argtypes) -- every function of moldtex.h, declared once.
_SIGNATURES = {
    "moldtex_abi_version": (ctypes.c_uint32, []),
    "moldtex_version_string": (ctypes.c_char_p, []),
    "moldtex_last_error": (ctypes.c_char_p, []),
    "moldtex_mesh_desc_init": (None, [_P(MeshDesc)]),
    "moldtex_surface_create": (_status, [_P(MeshDesc), _P(_Surface)]),
    "moldtex_surface_release": (None, [_Surface]),
    "moldtex_surface_info_init": (None, [_P(SurfaceInfo)]),
    "moldtex_surface_get_info": (_status, [_Surface, _P(SurfaceInfo)]),
    "moldtex_surface_get_metric": (_status, [_Surface, ctypes.c_uint32, _P(ctypes.c_float)]),
    "moldtex_surface_evaluate": (_status, [_Surface, _P(SurfacePoint), _P(ctypes.c_float),
                                           _P(ctypes.c_float)]),
    "moldtex_surface_trace": (_status, [_Surface, _P(SurfacePoint), _P(ctypes.c_float),
                                        ctypes.c_float, _P(SurfacePoint), _P(ctypes.c_float),
                                        ctypes.c_uint32, _P(ctypes.c_uint32)]),
    "moldtex_surface_rasterize_corners": (_status, [_Surface, ctypes.c_uint32, ctypes.c_uint32,
                                                    ctypes.c_void_p, ctypes.c_size_t,
                                                    ctypes.c_void_p, ctypes.c_size_t]),
    "moldtex_sim_config_init": (None, [_P(SimConfig)]),
    "moldtex_sim_params_init": (None, [_P(SimParams)]),
    "moldtex_sim_create": (_status, [_Surface, _P(SimConfig), _P(SimParams), _P(_Sim)]),
    "moldtex_sim_release": (None, [_Sim]),
    "moldtex_continuous_params_init": (None, [_P(ContinuousParams)]),
    "moldtex_sim_set_continuous_params": (_status, [_Sim, _P(ContinuousParams)]),
    "moldtex_sim_get_continuous_params": (_status, [_Sim, _P(ContinuousParams)]),
    "moldtex_reaction_params_init": (None, [_P(ReactionParams)]),
    "moldtex_sim_set_reaction_params": (_status, [_Sim, _P(ReactionParams)]),
    "moldtex_sim_get_reaction_params": (_status, [_Sim, _P(ReactionParams)]),
    "moldtex_sim_set_params": (_status, [_Sim, _P(SimParams)]),
    "moldtex_sim_get_params": (_status, [_Sim, _P(SimParams)]),
    "moldtex_sim_get_config": (_status, [_Sim, _P(SimConfig)]),
    "moldtex_species_params_init": (None, [_P(SpeciesParams), ctypes.c_uint32]),
    "moldtex_sim_set_species_params": (_status, [_Sim, ctypes.c_uint32, _P(SpeciesParams)]),
    "moldtex_sim_get_species_params": (_status, [_Sim, ctypes.c_uint32, _P(SpeciesParams)]),
    "moldtex_sim_set_fields": (_status, [_Sim, ctypes.c_void_p, ctypes.c_size_t]),
    "moldtex_sim_set_bias": (_status, [_Sim, ctypes.c_void_p, ctypes.c_size_t]),
    "moldtex_sim_set_map": (_status, [_Sim, ctypes.c_uint32, ctypes.c_void_p,
                                      ctypes.c_size_t]),
    "moldtex_sim_get_map": (_status, [_Sim, ctypes.c_uint32, ctypes.c_void_p,
                                      ctypes.c_size_t, _P(ctypes.c_uint32)]),
    "moldtex_sim_set_food": (_status, [_Sim, _P(FoodSource), ctypes.c_uint32]),
    "moldtex_sim_get_food": (_status, [_Sim, _P(FoodSource), ctypes.c_uint32,
                                       _P(ctypes.c_uint32)]),
    "moldtex_sim_reset": (_status, [_Sim]),
    "moldtex_sim_step": (_status, [_Sim, ctypes.c_uint32]),
    "moldtex_sim_read_rgba": (_status, [_Sim, ctypes.c_void_p, ctypes.c_size_t]),
    "moldtex_sim_read_vertex_rgba": (_status, [_Sim, ctypes.c_void_p, ctypes.c_size_t]),
    "moldtex_sim_read_texel_classes": (_status, [_Sim, ctypes.c_void_p, ctypes.c_size_t]),
    "moldtex_sim_read_agents": (_status, [_Sim, _P(SurfacePoint), ctypes.c_uint32]),
    "moldtex_sim_stats_init": (None, [_P(SimStats)]),
    "moldtex_sim_get_stats": (_status, [_Sim, _P(SimStats)]),
    "moldtex_domain_info_init": (None, [_P(DomainInfo)]),
    "moldtex_sim_get_domain_info": (_status, [_Sim, _P(DomainInfo)]),
    "moldtex_sim_get_backend_name": (_status, [_Sim, _P(ctypes.c_char), ctypes.c_size_t]),
    "moldtex_sim_write_image": (_status, [_Sim, ctypes.c_char_p, ctypes.c_uint32]),
    "moldtex_sim_save_checkpoint": (_status, [_Sim, ctypes.c_char_p]),
    "moldtex_sim_load_checkpoint": (_status, [_Sim, ctypes.c_char_p]),
    "moldtex_intrinsic_params_init": (None, [_P(IntrinsicParams)]),
    "moldtex_intrinsic_create": (_status, [_Surface, _P(IntrinsicParams), _P(_Intrinsic)]),
    "moldtex_intrinsic_release": (None, [_Intrinsic]),
    "moldtex_intrinsic_info_init": (None, [_P(IntrinsicInfo)]),
    "moldtex_intrinsic_get_info": (_status, [_Intrinsic, _P(IntrinsicInfo)]),
    "moldtex_intrinsic_locate": (_status, [_Intrinsic, _P(SurfacePoint), ctypes.c_uint32,
                                           _P(SurfacePoint)]),
    "moldtex_intrinsic_to_input": (_status, [_Intrinsic, _P(SurfacePoint), ctypes.c_uint32,
                                             _P(SurfacePoint)]),
    "moldtex_intrinsic_vertex_points": (_status, [_Intrinsic, _P(SurfacePoint),
                                                  ctypes.c_uint32]),
    "moldtex_bake_desc_init": (None, [_P(BakeDesc)]),
    "moldtex_bake_progress_init": (None, [_P(BakeProgress)]),
    "moldtex_bake_start": (_status, [_Sim, _P(BakeDesc), _P(_Bake)]),
    "moldtex_bake_get_progress": (_status, [_Bake, _P(BakeProgress)]),
    "moldtex_bake_cancel": (None, [_Bake]),
    "moldtex_bake_wait": (_status, [_Bake]),
    "moldtex_bake_release": (None, [_Bake]),
    "moldtex_run_progress_init": (None, [_P(RunProgress)]),
    "moldtex_sim_run_start": (_status, [_Sim, ctypes.c_double, ctypes.c_double, ctypes.c_double]),
    "moldtex_sim_run_get_progress": (_status, [_Sim, _P(RunProgress)]),
    "moldtex_sim_run_stop": (_status, [_Sim, _P(RunProgress)]),
    "moldtex_domain_build_progress_init": (None, [_P(DomainBuildProgress)]),
    "moldtex_domain_build_start": (_status, [_Surface, _P(SimConfig), ctypes.c_uint32,
                                             _P(_DomainBuild)]),
    "moldtex_domain_build_get_progress": (_status, [_DomainBuild, _P(DomainBuildProgress)]),
    "moldtex_domain_build_cancel": (None, [_DomainBuild]),
    "moldtex_domain_build_wait": (_status, [_DomainBuild]),
    "moldtex_domain_build_release": (None, [_DomainBuild]),
    "moldtex_opencl_device_info_init": (None, [_P(OpenCLDeviceInfo)]),
    "moldtex_opencl_device_count": (_status, [_P(ctypes.c_uint32)]),
    "moldtex_opencl_get_device": (_status, [ctypes.c_uint32, _P(OpenCLDeviceInfo)]),
    "moldtex_ray_hit_init": (None, [_P(RayHit)]),
    "moldtex_surface_ray_cast": (_status, [_Surface, _P(ctypes.c_float), _P(ctypes.c_float),
                                           ctypes.c_float, _P(RayHit)]),
    "moldtex_surface_closest_point": (_status, [_Surface, _P(ctypes.c_float), _P(SurfacePoint),
                                                _P(ctypes.c_float)]),
    "moldtex_brush_init": (None, [_P(Brush)]),
    "moldtex_surface_paint": (_status, [_Surface, ctypes.c_uint32, ctypes.c_uint32,
                                        ctypes.c_void_p, ctypes.c_size_t, _P(Brush),
                                        _P(ctypes.c_uint32)]),
    "moldtex_sim_add_agents": (_status, [_Sim, _P(Brush), ctypes.c_uint32, ctypes.c_uint32]),
    "moldtex_sim_erase_agents": (_status, [_Sim, _P(Brush), ctypes.c_uint32,
                                           _P(ctypes.c_uint32)]),
    "moldtex_sim_undo_agents": (_status, [_Sim, ctypes.c_uint32]),
    # surface map tools (Layton et al. §6)
    "moldtex_surface_geodesic_distance": (_status, [_Surface, ctypes.c_void_p, ctypes.c_size_t,
                                                    ctypes.c_float, ctypes.c_void_p,
                                                    ctypes.c_size_t]),
    "moldtex_surface_laplace_interpolate": (_status, [_Surface, ctypes.c_void_p, ctypes.c_void_p,
                                                      ctypes.c_size_t, ctypes.c_void_p,
                                                      ctypes.c_size_t]),
    "moldtex_surface_diffuse_map": (_status, [_Surface, ctypes.c_void_p, ctypes.c_size_t,
                                              ctypes.c_float, ctypes.c_void_p, ctypes.c_size_t]),
    "moldtex_surface_map_gradient": (_status, [_Surface, ctypes.c_void_p, ctypes.c_size_t,
                                               ctypes.c_void_p, ctypes.c_size_t]),
    # colour map from an image (Layton et al. §3.4)
    "moldtex_colour_ramp_desc_init": (None, [_P(ColourRampDesc)]),
    "moldtex_colour_ramp_info_init": (None, [_P(ColourRampInfo)]),
    "moldtex_colour_ramp_from_pixels": (_status, [ctypes.c_void_p, ctypes.c_size_t,
                                                  _P(ColourRampDesc), _P(ColourStop),
                                                  ctypes.c_uint32, _P(ColourRampInfo)]),
}

# moldtex_map values (moldtex.h): parameter maps and stimuli of the continuous model,
# Simulation.set_map / get_map. MAP_MOVE_RATE .. MAP_SPAWN multiply their parameter
# where an agent stands (0 .. MAP_MULTIPLIER_MAX; MEAN_LIFETIME 0 = a sink, SPAWN =
# where turnover re-spawns agents); the two stimuli are signed, in units of U.
# moldtex_boundary: what an agent of the continuous model does at the mesh's open edges.
BOUNDARY_REFLECT = 0  # turns back into the surface
BOUNDARY_ABSORB = 1   # dies there and is reborn (a sink along the edges, Fig. 18)

MAP_MOVE_RATE = 0
MAP_TURN_RATE = 1
MAP_SENSOR_DISTANCE = 2
MAP_SENSOR_ANGLE = 3
MAP_DEPOSIT_RATE = 4
MAP_MEAN_LIFETIME = 5
MAP_ACTIVATION_TIME = 6
MAP_SPAWN = 7
MAP_READ_STIMULUS = 8
MAP_WRITE_STIMULUS = 9
MAP_DIFFUSION_RATE = 10
MAP_DECAY_RATE = 11
MAP_FEED = 12  # Gray-Scott: multiplies F there (the product capped at 1)
MAP_KILL = 13  # Gray-Scott: multiplies k there (the product capped at 1)
MAP_COUNT = 14
MAP_MULTIPLIER_MAX = 1000.0  # multipliers are in [0, 1000]
MAP_STIMULUS_MAX = 1e6       # stimuli are within +-1e6

SEED_RANDOM = 0     # moldtex_seed_shape
SEED_SPAWN_MAP = 1
SEED_CIRCLE = 2
SEED_BIG_BANG = 3
SEED_STARBURST = 4
MAX_SPECIES = 4
MAX_STEPS_PER_CALL = 100_000  # MOLDTEX_MAX_STEPS_PER_CALL

# Structs whose *_init function must report the same struct_size as our mirror.
_STRUCT_INITS = (
    ("moldtex_mesh_desc_init", MeshDesc),
    ("moldtex_surface_info_init", SurfaceInfo),
    ("moldtex_sim_config_init", SimConfig),
    ("moldtex_sim_params_init", SimParams),
    ("moldtex_sim_stats_init", SimStats),
    ("moldtex_continuous_params_init", ContinuousParams),
    ("moldtex_reaction_params_init", ReactionParams),
    ("moldtex_bake_desc_init", BakeDesc),
    ("moldtex_bake_progress_init", BakeProgress),
    ("moldtex_opencl_device_info_init", OpenCLDeviceInfo),
    ("moldtex_ray_hit_init", RayHit),
    ("moldtex_brush_init", Brush),
    ("moldtex_colour_ramp_desc_init", ColourRampDesc),
    ("moldtex_colour_ramp_info_init", ColourRampInfo),
    ("moldtex_intrinsic_params_init", IntrinsicParams),
    ("moldtex_intrinsic_info_init", IntrinsicInfo),
)

ADDON_DIR = os.path.dirname(os.path.abspath(__file__))

if sys.platform == "win32":
    LIBRARY_NAME = "moldtex.dll"
elif sys.platform == "darwin":
    LIBRARY_NAME = "libmoldtex.dylib"
else:
    LIBRARY_NAME = "libmoldtex.so"

_REBUILD_HINT = ("build it with the README's command (cmake -S . -B build && "
                 "cmake --build build) or reinstall the add-on zip")

_lib = None
_opencl_cache = None  # (devices, reason) from the first opencl_devices() call
LOAD_ERROR = None     # plain-language reason when the core is unusable, else None
LIBRARY_PATH = None   # the file that was loaded (or tried)
VERSION = None        # moldtex_version_string() of the loaded core


def _load():
    """Loads the core next to this file (or $MOLDTEX_LIBRARY) and checks it fits."""
    global _lib, LOAD_ERROR, LIBRARY_PATH, VERSION, _opencl_cache
    _lib, LOAD_ERROR, VERSION = None, None, None
    _opencl_cache = None
    override = os.environ.get("MOLDTEX_LIBRARY")
    path = override or os.path.join(ADDON_DIR, LIBRARY_NAME)
    LIBRARY_PATH = path
    if not os.path.isfile(path):
        if override:
            LOAD_ERROR = (f"MOLDTEX_LIBRARY is set to {override}, which does not exist; "
                          f"unset it to use the library next to the add-on.")
        else:
            LOAD_ERROR = (f"{LIBRARY_NAME} was not found next to the add-on in "
                          f"{ADDON_DIR}; {_REBUILD_HINT}.")
        return
    try:
        lib = ctypes.CDLL(path)
    except OSError as error:
        LOAD_ERROR = (f"{path} could not be loaded ({error}); it may be built for another "
                      f"system or be missing a dependency: {_REBUILD_HINT}.")
        return
    for name, (restype, argtypes) in _SIGNATURES.items():
        try:
            function = getattr(lib, name)
        except AttributeError:
            LOAD_ERROR = (f"{path} has no function {name}: it is from another version "
                          f"of Moldtex; {_REBUILD_HINT}.")
            return
        function.restype = restype
        function.argtypes = argtypes
    abi = lib.moldtex_abi_version()
    if abi != ABI_VERSION:
        LOAD_ERROR = (f"{path} speaks ABI version {abi} but this add-on needs version "
                      f"{ABI_VERSION}: install the add-on zip and the library from the "
                      f"same build.")
        return
    for init_name, struct in _STRUCT_INITS:
        probe = struct()
        getattr(lib, init_name)(ctypes.byref(probe))
        if probe.struct_size != ctypes.sizeof(struct):
            LOAD_ERROR = (f"{path} reports {struct.__name__} as {probe.struct_size} bytes "
                          f"but the add-on expects {ctypes.sizeof(struct)}: the library and "
                          f"the add-on come from different builds; {_REBUILD_HINT}.")
            return
    raw_version = lib.moldtex_version_string()
    VERSION = raw_version.decode("utf-8", "replace") if raw_version else "?"
    _lib = lib


_load()


def available():
    return _lib is not None


def status_text():
    """One line for the panel: which core is loaded, or why none is."""
    if _lib is None:
        return "Engine unavailable: " + (LOAD_ERROR or "unknown reason")
    return f"Moldtex core {VERSION} (ABI {ABI_VERSION})"


def _require():
    if _lib is None:
        raise EngineError(LOAD_ERROR or "The Moldtex core is not loaded.")
    return _lib


def _last_error():
    message = _lib.moldtex_last_error() if _lib is not None else None
    return message.decode("utf-8", "replace") if message else ""


def _check(status, what):
    if status != OK:
        message = _last_error() or f"{what} failed ({STATUS_NAMES.get(status, status)})."
        raise EngineError(message, status)


def _buffer_address(buffer, typecodes, writable):
    """Address and element count of an array.array (or C-contiguous numpy array)."""
    if isinstance(buffer, array.array):
        expected_size = 1 if buffer.typecode == "B" else 4
        if buffer.typecode not in typecodes or buffer.itemsize != expected_size:
            raise TypeError(f"expected array.array of type {'/'.join(typecodes)}, "
                            f"got '{buffer.typecode}'")
        address, count = buffer.buffer_info()
        return address, count
    interface = getattr(buffer, "__array_interface__", None)
    if interface is not None:
        typestr = interface["typestr"]
        kinds = {"f": ("<f4",), "i": ("<i4",), "I": ("<u4",), "B": ("|u1", "<u1")}
        accepted = sum((kinds.get(code, ()) for code in typecodes), ())
        if typestr not in accepted:
            raise TypeError(f"expected a numpy array of {accepted}, got {typestr}")
        if interface.get("strides") is not None:
            raise TypeError("the numpy array must be C-contiguous")
        address, readonly = interface["data"]
        if writable and readonly:
            raise TypeError("the numpy array is read-only")
        count = 1
        for extent in interface["shape"]:
            count *= extent
        return address, count
    raise TypeError(f"expected array.array or a numpy array, got {type(buffer).__name__}")


def _float_ptr(buffer):
    address, count = _buffer_address(buffer, ("f",), writable=False)
    return ctypes.cast(ctypes.c_void_p(address), _P(ctypes.c_float)), count


def _uint_ptr(buffer):
    # Blender's foreach_get fills 'i' (int32); the bits are the same for valid indices.
    address, count = _buffer_address(buffer, ("I", "i"), writable=False)
    return ctypes.cast(ctypes.c_void_p(address), _P(ctypes.c_uint32)), count


def _struct_to_dict(struct, fields):
    result = {name: getattr(struct, name) for name in fields}
    for name, value in result.items():
        if isinstance(value, SurfacePoint):
            result[name] = (value.triangle, tuple(value.bary))
    return result


def default_params():
    """The core's default parameters (moldtex_sim_params_init) as a dict."""
    params = SimParams()
    _require().moldtex_sim_params_init(ctypes.byref(params))
    return _struct_to_dict(params, PARAM_FIELDS)


def default_reaction_params():
    """The core's defaults of the Gray-Scott model (moldtex_reaction_params_init) as a
    dict of REACTION_FIELDS."""
    params = ReactionParams()
    _require().moldtex_reaction_params_init(ctypes.byref(params))
    return _struct_to_dict(params, REACTION_FIELDS)


def default_continuous_params():
    """The core's defaults of the continuous model (moldtex_continuous_params_init) as
    a dict of CONTINUOUS_FIELDS (lengths in mesh units, sensor_angle in degrees)."""
    params = ContinuousParams()
    _require().moldtex_continuous_params_init(ctypes.byref(params))
    return _struct_to_dict(params, CONTINUOUS_FIELDS)


def u_metric(agent_count, deposit_rate, decay_rate, area, activation_time=0.0,
             mean_lifetime=0.0):
    """U of layton-intrinsic-slime.md Eq. 5, the uniform steady-state concentration:
    N r_dep / (r_dec A) exp(-t_a / tau), the factor 1 when tau = 0 (no turnover).
    +inf when r_dec or A is 0 (nothing decays, or no surface), as the core reports it.
    Pure Python (no core call), in the units of its arguments."""
    if decay_rate <= 0.0 or area <= 0.0:
        return math.inf
    value = agent_count * deposit_rate / (decay_rate * area)
    if mean_lifetime > 0.0:
        value *= math.exp(-activation_time / mean_lifetime)
    return value


def deposit_rate_for_u(target_u, agent_count, decay_rate, area, activation_time=0.0,
                       mean_lifetime=0.0):
    """The r_dep that makes u_metric(...) equal target_u (Eq. 5 solved for r_dep), or
    None when no deposit rate can (no agents, nothing decays, no surface, or every
    agent dies before it may deposit)."""
    if (agent_count <= 0 or decay_rate <= 0.0 or area <= 0.0
            or not math.isfinite(target_u) or target_u < 0.0):
        return None
    survive = math.exp(-activation_time / mean_lifetime) if mean_lifetime > 0.0 else 1.0
    if survive <= 0.0:
        return None
    return target_u * decay_rate * area / (agent_count * survive)


def default_config():
    config = SimConfig()
    _require().moldtex_sim_config_init(ctypes.byref(config))
    return _struct_to_dict(config, CONFIG_FIELDS)


BRUSH_FIELDS = ("triangle", "bary", "radius", "strength", "falloff", "mode", "channel", "value")


def default_brush():
    """The core's brush defaults (moldtex_brush_init) as a dict with BRUSH_FIELDS:
    triangle and bary (3 floats) place the centre; radius (mesh units, measured on the
    surface), strength, falloff, mode (BRUSH_PAINT / BRUSH_ERASE), channel (RGBA channel
    for paint, species for agents), value (paint target)."""
    brush = Brush()
    _require().moldtex_brush_init(ctypes.byref(brush))
    return {"triangle": brush.center.triangle, "bary": tuple(brush.center.bary),
            "radius": brush.radius, "strength": brush.strength, "falloff": brush.falloff,
            "mode": brush.mode, "channel": brush.channel, "value": brush.value}


def _brush(values):
    """A Brush from a dict of BRUSH_FIELDS; missing keys keep the core's defaults."""
    brush = Brush()
    _require().moldtex_brush_init(ctypes.byref(brush))
    for name, value in values.items():
        if name not in BRUSH_FIELDS:
            raise KeyError(f"unknown brush field '{name}'")
        if name == "triangle":
            brush.center.triangle = int(value)
        elif name == "bary":
            bary = tuple(value)
            if len(bary) != 3:
                raise EngineError("A brush's bary needs 3 weights.", ERROR_INVALID_ARGUMENT)
            for k in range(3):
                brush.center.bary[k] = float(bary[k])
        elif name in ("mode", "channel"):
            setattr(brush, name, int(value))
        else:
            setattr(brush, name, float(value))
    return brush


def _decode(raw):
    return raw.decode("utf-8", "replace")


def opencl_devices(refresh=False):
    """The OpenCL devices the core can run on, and why there are none.

    Returns (devices, reason). devices is a list of dicts (index: position in the
    core's list; platform_index, device_index: for the config; name, platform_name,
    is_gpu, global_memory_bytes); reason is "" when there are devices, else a
    plain-language sentence (no OpenCL runtime, no platform, a build without OpenCL,
    or the core not loaded). Never raises. The list is read once (the first call
    starts the OpenCL runtime) and cached; refresh=True reads it again.
    """
    global _opencl_cache
    if _opencl_cache is not None and not refresh:
        return list(_opencl_cache[0]), _opencl_cache[1]
    if _lib is None:
        return [], LOAD_ERROR or "The Moldtex core is not loaded."
    devices, reason = [], ""
    count = ctypes.c_uint32(0)
    status = _lib.moldtex_opencl_device_count(ctypes.byref(count))
    if status != OK:
        reason = _last_error() or f"OpenCL is {STATUS_NAMES.get(status, status)}."
    else:
        for index in range(count.value):
            info = OpenCLDeviceInfo()
            _lib.moldtex_opencl_device_info_init(ctypes.byref(info))
            status = _lib.moldtex_opencl_get_device(index, ctypes.byref(info))
            if status != OK:
                reason = _last_error() or f"Reading OpenCL device {index} failed."
                continue
            devices.append({
                "index": index,
                "platform_index": info.platform_index,
                "device_index": info.device_index,
                "is_gpu": bool(info.is_gpu),
                "global_memory_bytes": info.global_memory_bytes,
                "name": _decode(info.name).strip() or f"OpenCL device {index}",
                "platform_name": _decode(info.platform_name).strip(),
            })
        if not devices and not reason:
            reason = "The OpenCL runtime lists no devices."
    if devices:
        reason = ""
    _opencl_cache = (devices, reason)
    return list(devices), reason


def _fill(struct, values, fields, what):
    for name, value in values.items():
        if name not in fields:
            raise KeyError(f"unknown {what} field '{name}'")
        setattr(struct, name, value)


class Surface:
    """A triangle mesh with a UV layout (moldtex_surface)."""

    def __init__(self, positions, triangles, uvs, triangle_uvs=None):
        """positions: array('f') of x,y,z; triangles: array('I'/'i') of vertex indices,
        3 per triangle; uvs: array('f') of u,v, or None for a mesh without UVs (it runs
        on the intrinsic domain only); triangle_uvs: array('I'/'i') of 3 uv indices per
        triangle (Blender loop indices), or None for per-corner uvs."""
        lib = _require()
        self._handle = None
        desc = MeshDesc()
        lib.moldtex_mesh_desc_init(ctypes.byref(desc))
        desc.positions, n_pos = _float_ptr(positions)
        desc.triangles, n_tri = _uint_ptr(triangles)
        if uvs is None:
            if triangle_uvs is not None:
                raise EngineError("triangle_uvs without uvs.", ERROR_INVALID_ARGUMENT)
            n_uv = 0
        else:
            desc.uvs, n_uv = _float_ptr(uvs)
        if n_pos % 3 or n_tri % 3 or n_uv % 2:
            raise EngineError("Mesh arrays have the wrong length (positions need 3 floats "
                              "a vertex, triangles 3 indices, uvs 2 floats).",
                              ERROR_INVALID_ARGUMENT)
        desc.vertex_count = n_pos // 3
        desc.triangle_count = n_tri // 3
        desc.uv_count = n_uv // 2
        if triangle_uvs is not None:
            desc.triangle_uvs, n_tuv = _uint_ptr(triangle_uvs)
            if n_tuv != n_tri:
                raise EngineError("triangle_uvs needs 3 indices per triangle.",
                                  ERROR_INVALID_ARGUMENT)
        handle = _Surface()
        # The arrays stay referenced by the caller for the duration of this call.
        _check(lib.moldtex_surface_create(ctypes.byref(desc), ctypes.byref(handle)),
               "Building the surface")
        self._handle = handle

    @property
    def handle(self):
        if self._handle is None:
            raise EngineError("This surface was released.", ERROR_INVALID_ARGUMENT)
        return self._handle

    def info(self):
        info = SurfaceInfo()
        _lib.moldtex_surface_info_init(ctypes.byref(info))
        _check(_lib.moldtex_surface_get_info(self.handle, ctypes.byref(info)),
               "Reading surface info")
        return _struct_to_dict(info, SURFACE_INFO_FIELDS)

    def metric(self, triangle):
        g = (ctypes.c_float * 4)()
        _check(_lib.moldtex_surface_get_metric(self.handle, triangle, g), "Reading metric")
        return tuple(g)

    def evaluate(self, triangle, bary):
        point = SurfacePoint(triangle, (ctypes.c_float * 3)(*bary))
        position = (ctypes.c_float * 3)()
        uv = (ctypes.c_float * 2)()
        _check(_lib.moldtex_surface_evaluate(self.handle, ctypes.byref(point), position, uv),
               "Evaluating a surface point")
        return tuple(position), tuple(uv)

    def trace(self, triangle, bary, direction, length, path_capacity=0):
        start = SurfacePoint(triangle, (ctypes.c_float * 3)(*bary))
        end = SurfacePoint()
        path = (ctypes.c_float * (3 * path_capacity))() if path_capacity else None
        count = ctypes.c_uint32(0)
        _check(_lib.moldtex_surface_trace(self.handle, ctypes.byref(start),
                                          (ctypes.c_float * 3)(*direction), length,
                                          ctypes.byref(end), path, path_capacity,
                                          ctypes.byref(count)),
               "Tracing a path")
        points = []
        if path is not None:
            n = min(count.value, path_capacity)
            points = [tuple(path[3 * i:3 * i + 3]) for i in range(n)]
        return (end.triangle, tuple(end.bary)), points, count.value

    def rasterize_corners(self, width, height, corner_rgba):
        """Bakes per-corner values into a width × height RGBA float image over the UV
        layout (Blender's pixel order, the layout a simulation of that size uses):
        corner_rgba holds 4 floats for each corner of each triangle (array('f') or numpy
        float32 of triangle_count*12, corners in the order of `triangles`). Island texels
        interpolate their triangle's corners, gutter texels copy the texel across the
        seam, the rest is 0. Returns a new array('f') of width*height*4 floats."""
        address, count = _buffer_address(corner_rgba, ("f",), writable=False)
        width, height = int(width), int(height)
        # Sizes the core refuses get no buffer (so no 4 GiB allocation before the refusal).
        fits = 8 <= width <= 16384 and 8 <= height <= 16384
        out = array.array("f", bytes(4 * 4 * width * height if fits else 4))
        out_address, out_count = _buffer_address(out, ("f",), writable=True)
        _check(_lib.moldtex_surface_rasterize_corners(self.handle, width, height,
                                                      ctypes.c_void_p(address), count,
                                                      ctypes.c_void_p(out_address),
                                                      out_count),
               "Rasterizing corner values")
        return out

    def ray_cast(self, origin, direction, max_distance=float("inf")):
        """Nearest hit of origin + s * direction (0 <= s <= max_distance, both faces):
        None on a miss, else a dict with triangle, bary, distance (s), position, uv and
        normal (unit, by winding). The first call builds the surface's BVH."""
        hit = RayHit()
        _lib.moldtex_ray_hit_init(ctypes.byref(hit))
        _check(_lib.moldtex_surface_ray_cast(self.handle, (ctypes.c_float * 3)(*origin),
                                             (ctypes.c_float * 3)(*direction),
                                             float(max_distance), ctypes.byref(hit)),
               "Casting a ray")
        if not hit.hit:
            return None
        return {"triangle": hit.point.triangle, "bary": tuple(hit.point.bary),
                "distance": hit.distance, "position": tuple(hit.position),
                "uv": tuple(hit.uv), "normal": tuple(hit.normal)}

    def closest_point(self, position):
        """Nearest surface point to a 3D position: (triangle, (b0, b1, b2), distance)."""
        point = SurfacePoint()
        distance = ctypes.c_float(0.0)
        _check(_lib.moldtex_surface_closest_point(self.handle, (ctypes.c_float * 3)(*position),
                                                  ctypes.byref(point), ctypes.byref(distance)),
               "Finding the closest point")
        return point.triangle, tuple(point.bary), distance.value

    def paint(self, width, height, rgba, brush):
        """One brush dab into an RGBA float image of width x height over the UV layout
        (array('f') or numpy float32, >= width*height*4 floats, Blender's pixel order),
        changed in place. brush: dict of BRUSH_FIELDS (see default_brush). Returns the
        number of texels that changed."""
        b = _brush(brush)
        address, count = _buffer_address(rgba, ("f",), writable=True)
        changed = ctypes.c_uint32(0)
        _check(_lib.moldtex_surface_paint(self.handle, int(width), int(height),
                                          ctypes.c_void_p(address), count, ctypes.byref(b),
                                          ctypes.byref(changed)),
               "Painting")
        return changed.value

    # ---- surface map tools (Layton et al. §6): per-vertex maps over the FE mesh ----

    def _vertex_map_call(self, values, extra_count):
        """(input address, input count, output array('f'), output address, count)."""
        address, count = _buffer_address(values, ("f",), writable=False)
        out = array.array("f", bytes(4 * max(count, extra_count, 1)))
        out_address, out_count = _buffer_address(out, ("f",), writable=True)
        return address, count, out, out_address, out_count

    def geodesic_distance(self, source_weights, time_factor=1.0):
        """Heat-method geodesic distance (mesh units) from the vertices whose weight is
        > 0.5 (source_weights: array('f')/numpy float32, one per vertex). Returns
        array('f') per vertex: 0 at the sources, -1 where no source is reachable."""
        address, count, out, out_address, out_count = self._vertex_map_call(source_weights, 0)
        _check(_lib.moldtex_surface_geodesic_distance(self.handle, ctypes.c_void_p(address),
                                                      count, float(time_factor),
                                                      ctypes.c_void_p(out_address), out_count),
               "Measuring geodesic distance")
        return out

    def laplace_interpolate(self, values, fixed):
        """Harmonic blend: values where fixed (array('B')/numpy uint8, one per vertex,
        nonzero = fixed) is set, Laplacian 0 elsewhere. Returns array('f') per vertex."""
        address, count, out, out_address, out_count = self._vertex_map_call(values, 0)
        fixed_address, fixed_count = _buffer_address(fixed, ("B",), writable=False)
        if fixed_count != count:
            raise EngineError(f"The fixed mask needs one entry per value ({count}), got "
                              f"{fixed_count}.", ERROR_INVALID_ARGUMENT)
        _check(_lib.moldtex_surface_laplace_interpolate(self.handle, ctypes.c_void_p(address),
                                                        ctypes.c_void_p(fixed_address), count,
                                                        ctypes.c_void_p(out_address), out_count),
               "Laplace interpolation")
        return out

    def diffuse_map(self, values, time):
        """Short-time diffusion (M + time L) x = M values, time in mesh units² (a blur of
        radius r, the Gaussian's standard deviation, is time = r² / 2). array('f')."""
        address, count, out, out_address, out_count = self._vertex_map_call(values, 0)
        _check(_lib.moldtex_surface_diffuse_map(self.handle, ctypes.c_void_p(address), count,
                                                float(time), ctypes.c_void_p(out_address),
                                                out_count),
               "Diffusing a map")
        return out

    def map_gradient(self, values):
        """Per-triangle gradient of the per-vertex map: array('f') of triangle_count * 3
        (set_bias' layout)."""
        triangles = self.info()["triangle_count"]
        address, count, out, out_address, out_count = self._vertex_map_call(values, 3 * triangles)
        del out[3 * triangles:]
        out_address, out_count = _buffer_address(out, ("f",), writable=True)
        _check(_lib.moldtex_surface_map_gradient(self.handle, ctypes.c_void_p(address), count,
                                                 ctypes.c_void_p(out_address), out_count),
               "Taking a map's gradient")
        return out

    def release(self):
        if self._handle is not None and _lib is not None:
            _lib.moldtex_surface_release(self._handle)
        self._handle = None

    def __del__(self):
        try:
            self.release()
        except Exception:
            pass


def _points_array(points, what):
    """A ctypes array of SurfacePoint from (triangle, (b0, b1, b2)) pairs."""
    points = list(points)
    if not points:
        raise EngineError(f"{what}: pass at least one point.", ERROR_INVALID_ARGUMENT)
    if len(points) > MAX_INTRINSIC_POINTS:
        raise EngineError(f"{what}: at most {MAX_INTRINSIC_POINTS} points per call, got "
                          f"{len(points)}.", ERROR_TOO_LARGE)
    array_type = SurfacePoint * len(points)
    out = array_type()
    for i, (triangle, bary) in enumerate(points):
        if len(bary) != 3:
            raise EngineError(f"{what}: point {i} needs 3 barycentric weights.",
                              ERROR_INVALID_ARGUMENT)
        out[i].triangle = int(triangle)
        out[i].bary[:] = [float(b) for b in bary]
    return out


def _points_list(points):
    return [(p.triangle, tuple(p.bary)) for p in points]


class Intrinsic:
    """Intrinsic Delaunay triangulation of a surface (moldtex_intrinsic, issue 11).

    max_circumradius: bound on the triangles' circumradius in mesh units (0: only
    Delaunay edge flips, no refinement); max_insertions: cap on inserted vertices.
    Points are (triangle, (b0, b1, b2)) pairs: triangles of the surface for input
    points, of the intrinsic triangulation for intrinsic ones. Keeps the surface alive."""

    def __init__(self, surface, max_circumradius=0.0, max_insertions=None):
        lib = _require()
        self._handle = None
        params = IntrinsicParams()
        lib.moldtex_intrinsic_params_init(ctypes.byref(params))
        params.max_circumradius = float(max_circumradius)
        if max_insertions is not None:
            params.max_insertions = int(max_insertions)
        handle = _Intrinsic()
        _check(lib.moldtex_intrinsic_create(surface.handle, ctypes.byref(params),
                                            ctypes.byref(handle)),
               "Building the intrinsic triangulation")
        self._handle = handle

    @property
    def handle(self):
        if self._handle is None:
            raise EngineError("This intrinsic triangulation was released.",
                              ERROR_INVALID_ARGUMENT)
        return self._handle

    def info(self):
        info = IntrinsicInfo()
        _lib.moldtex_intrinsic_info_init(ctypes.byref(info))
        _check(_lib.moldtex_intrinsic_get_info(self.handle, ctypes.byref(info)),
               "Reading the intrinsic triangulation's info")
        result = _struct_to_dict(info, INTRINSIC_INFO_FIELDS)
        result["message"] = _decode(info.message)
        return result

    def locate(self, points):
        """Input surface points -> intrinsic points."""
        src = _points_array(points, "Locating points")
        out = (SurfacePoint * len(src))()
        _check(_lib.moldtex_intrinsic_locate(self.handle, src, len(src), out),
               "Locating points on the intrinsic triangulation")
        return _points_list(out)

    def to_input(self, points):
        """Intrinsic points -> input surface points."""
        src = _points_array(points, "Mapping intrinsic points")
        out = (SurfacePoint * len(src))()
        _check(_lib.moldtex_intrinsic_to_input(self.handle, src, len(src), out),
               "Mapping intrinsic points to the surface")
        return _points_list(out)

    def vertex_points(self):
        """Each intrinsic vertex's point on the input surface (triangle
        INTRINSIC_NO_TRIANGLE for an input vertex that no triangle uses)."""
        count = self.info()["vertex_count"]
        out = (SurfacePoint * count)()
        _check(_lib.moldtex_intrinsic_vertex_points(self.handle, out, count),
               "Reading the intrinsic vertices' points")
        return _points_list(out)

    def release(self):
        if self._handle is not None and _lib is not None:
            _lib.moldtex_intrinsic_release(self._handle)
        self._handle = None

    def __del__(self):
        try:
            self.release()
        except Exception:
            pass


class Simulation:
    """A simulation on a surface's UV layout (moldtex_sim): MoMaS, or the continuous
    model when config["model"] is MODEL_CONTINUOUS."""

    def __init__(self, surface, config=None, params=None, fields=None, continuous=None,
                 reaction=None):
        """config: dict with any of CONFIG_FIELDS (width, height, agent_count, seed,
        backend, opencl_platform, opencl_device, species_count, seed_shape, seed_radius,
        seed_rays; seed_center as (triangle, (b0, b1, b2)); missing = core default);
        params: dict with any of PARAM_FIELDS (missing = core default);
        fields: static fields (array('f') or numpy float32 of width*height*4, see
        set_fields) taken at create, or None;
        continuous: dict with any of CONTINUOUS_FIELDS for a continuous simulation,
        given to the core right after it is created, which then resets (the state a
        reset with these parameters gives), or None for the core's defaults.
        reaction: dict with any of REACTION_FIELDS for a Gray-Scott simulation
        (MODEL_GRAY_SCOTT), set right after create, then reset (seeds from them).
        config["model"] chooses the model (MODEL_*)."""
        lib = _require()
        self._handle = None
        c = SimConfig()
        lib.moldtex_sim_config_init(ctypes.byref(c))
        config = dict(config or {})
        center = config.pop("seed_center", None)
        config.pop("fields_rgba", None)
        _fill(c, config, CONFIG_FIELDS, "config")
        if center is not None:
            c.seed_center = SurfacePoint(int(center[0]),
                                         (ctypes.c_float * 3)(*center[1]))
        if fields is not None:
            address, count = _buffer_address(fields, ("f",), writable=False)
            if count < 4 * c.width * c.height:
                raise EngineError("The fields need width × height × 4 floats.",
                                  ERROR_INVALID_ARGUMENT)
            c.fields_rgba = address
        p = SimParams()
        lib.moldtex_sim_params_init(ctypes.byref(p))
        _fill(p, params or {}, PARAM_FIELDS, "params")
        handle = _Sim()
        _check(lib.moldtex_sim_create(surface.handle, ctypes.byref(c), ctypes.byref(p),
                                      ctypes.byref(handle)),
               "Creating the simulation")
        self._handle = handle
        surface_info = surface.info()
        self.triangle_count = int(surface_info["triangle_count"])
        self.vertex_count = int(surface_info["vertex_count"])
        self.width = c.width
        self.height = c.height
        self.model = c.model
        if continuous:
            try:
                self.set_continuous_params(continuous)
                # The agents' clocks (ages, lifetimes, turn timers) started from the
                # defaults at create, and changing the lifetime or decision frequency
                # restarts them on another random stream: respawn, so that this state
                # is exactly what a reset (and so a bake) starts from.
                self.reset()
            except (EngineError, KeyError, TypeError):
                self.release()
                raise
        if reaction:
            try:
                self.set_reaction_params(reaction)
                self.reset()  # the seed disks from these parameters
            except (EngineError, KeyError, TypeError):
                self.release()
                raise

    @property
    def handle(self):
        if self._handle is None:
            raise EngineError("This simulation was released.", ERROR_INVALID_ARGUMENT)
        return self._handle

    def set_params(self, params):
        """Changes parameters between steps; fields not given keep their current value."""
        p = SimParams()
        _lib.moldtex_sim_params_init(ctypes.byref(p))
        _check(_lib.moldtex_sim_get_params(self.handle, ctypes.byref(p)), "Reading parameters")
        _fill(p, params, PARAM_FIELDS, "params")
        _check(_lib.moldtex_sim_set_params(self.handle, ctypes.byref(p)), "Setting parameters")

    def set_continuous_params(self, params):
        """Continuous model: changes its parameters between steps (a dict with any of
        CONTINUOUS_FIELDS; lengths in mesh units, sensor_angle in degrees); fields not
        given keep their current value."""
        p = ContinuousParams()
        _lib.moldtex_continuous_params_init(ctypes.byref(p))
        _check(_lib.moldtex_sim_get_continuous_params(self.handle, ctypes.byref(p)),
               "Reading the continuous model's parameters")
        _fill(p, params, CONTINUOUS_FIELDS, "continuous params")
        _check(_lib.moldtex_sim_set_continuous_params(self.handle, ctypes.byref(p)),
               "Setting the continuous model's parameters")

    def set_reaction_params(self, params):
        """Gray-Scott model: a dict with any of REACTION_FIELDS (diffusion in mesh
        units^2 per second); fields not given keep their current value. The seed fields
        apply at the next reset."""
        p = ReactionParams()
        _lib.moldtex_reaction_params_init(ctypes.byref(p))
        _check(_lib.moldtex_sim_get_reaction_params(self.handle, ctypes.byref(p)),
               "Reading the reaction-diffusion parameters")
        _fill(p, params, REACTION_FIELDS, "reaction params")
        _check(_lib.moldtex_sim_set_reaction_params(self.handle, ctypes.byref(p)),
               "Setting the reaction-diffusion parameters")

    def get_reaction_params(self):
        p = ReactionParams()
        _lib.moldtex_reaction_params_init(ctypes.byref(p))
        _check(_lib.moldtex_sim_get_reaction_params(self.handle, ctypes.byref(p)),
               "Reading the reaction-diffusion parameters")
        return _struct_to_dict(p, REACTION_FIELDS)

    def get_continuous_params(self):
        p = ContinuousParams()
        _lib.moldtex_continuous_params_init(ctypes.byref(p))
        _check(_lib.moldtex_sim_get_continuous_params(self.handle, ctypes.byref(p)),
               "Reading the continuous model's parameters")
        return _struct_to_dict(p, CONTINUOUS_FIELDS)

    def get_params(self):
        p = SimParams()
        _lib.moldtex_sim_params_init(ctypes.byref(p))
        _check(_lib.moldtex_sim_get_params(self.handle, ctypes.byref(p)), "Reading parameters")
        return _struct_to_dict(p, PARAM_FIELDS)

    def set_species_params(self, index, params):
        """Behaviour of species `index`: a dict with any of SPECIES_FIELDS (attraction
        as up to 4 floats); fields not given keep their current value."""
        p = SpeciesParams()
        _lib.moldtex_species_params_init(ctypes.byref(p), int(index))
        _check(_lib.moldtex_sim_get_species_params(self.handle, int(index), ctypes.byref(p)),
               "Reading species parameters")
        params = dict(params)
        attraction = params.pop("attraction", None)
        _fill(p, params, SPECIES_FIELDS, "species")
        if attraction is not None:
            for k, value in enumerate(list(attraction)[:4]):
                p.attraction[k] = float(value)
        _check(_lib.moldtex_sim_set_species_params(self.handle, int(index), ctypes.byref(p)),
               "Setting species parameters")

    def get_species_params(self, index):
        p = SpeciesParams()
        _lib.moldtex_species_params_init(ctypes.byref(p), int(index))
        _check(_lib.moldtex_sim_get_species_params(self.handle, int(index), ctypes.byref(p)),
               "Reading species parameters")
        result = _struct_to_dict(p, SPECIES_FIELDS)
        result["attraction"] = tuple(p.attraction)
        return result

    def set_fields(self, rgba):
        """Static fields: width*height*4 floats (array('f') or numpy float32) in
        read_rgba's order, R spawn weight, G obstacle (> 0.5), B attractor; None clears."""
        if rgba is None:
            _check(_lib.moldtex_sim_set_fields(self.handle, None, 0), "Setting the fields")
            return
        address, count = _buffer_address(rgba, ("f",), writable=False)
        _check(_lib.moldtex_sim_set_fields(self.handle, ctypes.c_void_p(address), count),
               "Setting the fields")

    def set_bias(self, vectors):
        """Continuous model's directional bias field: triangle_count*3 floats
        (array('f') or numpy float32), one 3D vector per triangle in the mesh's own
        coordinates and triangle order, projected onto its triangle; its length weights
        bias_strength there (1 = full). None clears it (no bias)."""
        if vectors is None:
            _check(_lib.moldtex_sim_set_bias(self.handle, None, 0), "Setting the bias")
            return
        address, count = _buffer_address(vectors, ("f",), writable=False)
        expected = 3 * self.triangle_count
        if count != expected:
            raise EngineError(f"The bias needs 3 floats per triangle ({expected} for "
                              f"{self.triangle_count} triangles), got {count}.",
                              ERROR_INVALID_ARGUMENT)
        _check(_lib.moldtex_sim_set_bias(self.handle, ctypes.c_void_p(address), count),
               "Setting the bias")

    def set_map(self, kind, values):
        """Parameter map or stimulus `kind` (MAP_*) of the continuous model: width*height
        floats (array('f') or numpy float32) in read_rgba's texel order (gutter texels
        are ignored), multipliers in [0, 1000], stimuli within +-1e6. None clears it.
        Kept across reset and in checkpoints."""
        kind = int(kind)
        if not 0 <= kind < MAP_COUNT:
            raise EngineError(f"Unknown map {kind} (0 .. {MAP_COUNT - 1}).",
                              ERROR_INVALID_ARGUMENT)
        if values is None:
            _check(_lib.moldtex_sim_set_map(self.handle, kind, None, 0), "Setting a map")
            return
        address, count = _buffer_address(values, ("f",), writable=False)
        expected = self.width * self.height
        if count != expected:
            raise EngineError(f"A map needs one float per texel ({expected} for "
                              f"{self.width} x {self.height}), got {count}.",
                              ERROR_INVALID_ARGUMENT)
        _check(_lib.moldtex_sim_set_map(self.handle, kind, ctypes.c_void_p(address), count),
               "Setting a map")

    def get_map(self, kind):
        """Map `kind` (MAP_*) as array('f') of width*height floats, or None when unset."""
        values = array.array("f", bytes(4 * self.width * self.height))
        address, count = _buffer_address(values, ("f",), writable=True)
        is_set = ctypes.c_uint32(0)
        _check(_lib.moldtex_sim_get_map(self.handle, int(kind), ctypes.c_void_p(address),
                                        count, ctypes.byref(is_set)), "Reading a map")
        return values if is_set.value else None

    def set_food(self, sources):
        """Replaces the food sources: a list of (position (x, y, z), strength, amount)
        in mesh units, amount < 0 = inexhaustible; at most MAX_FOOD_SOURCES; [] clears."""
        sources = list(sources)
        count = len(sources)
        array_type = FoodSource * max(1, count)
        items = array_type()
        for item, (position, strength, amount) in zip(items, sources):
            for k in range(3):
                item.position[k] = float(position[k])
            item.strength = float(strength)
            item.amount = float(amount)
        _check(_lib.moldtex_sim_set_food(self.handle, items, count), "Setting food sources")

    def get_food(self):
        """Current food sources as (position, strength, remaining amount) tuples."""
        items = (FoodSource * MAX_FOOD_SOURCES)()
        count = ctypes.c_uint32(0)
        _check(_lib.moldtex_sim_get_food(self.handle, items, MAX_FOOD_SOURCES,
                                         ctypes.byref(count)), "Reading food sources")
        return [(tuple(item.position), item.strength, item.amount)
                for item in items[:min(count.value, MAX_FOOD_SOURCES)]]

    def get_config(self):
        c = SimConfig()
        _lib.moldtex_sim_config_init(ctypes.byref(c))
        _check(_lib.moldtex_sim_get_config(self.handle, ctypes.byref(c)), "Reading config")
        return _struct_to_dict(c, CONFIG_FIELDS)

    def backend_name(self):
        """What the simulation runs on, e.g. "CPU (2 threads)" or "OpenCL: <device>
        (<platform>)"; for Auto followed by why OpenCL was not used."""
        capacity = 1024
        while True:
            buffer = ctypes.create_string_buffer(capacity)
            _check(_lib.moldtex_sim_get_backend_name(self.handle, buffer, capacity),
                   "Reading the backend name")
            if len(buffer.value) < capacity - 1 or capacity >= 1 << 16:
                return _decode(buffer.value)
            capacity *= 4

    def reset(self):
        _check(_lib.moldtex_sim_reset(self.handle), "Resetting the simulation")

    def step(self, steps=1):
        # One core call runs at most MAX_STEPS_PER_CALL steps: longer runs go in chunks.
        steps = int(steps)
        if steps < 0:
            raise ValueError(f"Steps must be 0 or more (got {steps})")
        while True:
            chunk = min(steps, MAX_STEPS_PER_CALL)
            _check(_lib.moldtex_sim_step(self.handle, chunk), "Stepping the simulation")
            steps -= chunk
            if steps <= 0:
                return

    def run_start(self, chunk_seconds, limit_seconds=5.0, step_seconds_hint=0.0):
        """Steps on the core's own thread (moldtex_sim_run_start) in chunks of about
        chunk_seconds until run_stop, or by itself after limit_seconds; meanwhile every
        other call raises EngineError (ERROR_BUSY). No Python runs on that thread."""
        _check(_lib.moldtex_sim_run_start(self.handle, float(chunk_seconds),
                                          float(limit_seconds), float(step_seconds_hint)),
               "Starting the live stepping")

    def run_progress(self):
        """dict: running (bool), steps (since run_start), step_seconds (mean cost of a
        step). Never blocks."""
        p = RunProgress()
        _lib.moldtex_run_progress_init(ctypes.byref(p))
        _check(_lib.moldtex_sim_run_get_progress(self.handle, ctypes.byref(p)),
               "Reading the live stepping's progress")
        return {"running": bool(p.running), "steps": p.steps, "step_seconds": p.step_seconds}

    def run_stop(self):
        """Stops the live stepping after its current chunk and waits (without holding
        Python's lock); returns its last run_progress() (steps 0 if none ran). Raises
        EngineError with the error a step raised, if one did."""
        p = RunProgress()
        _lib.moldtex_run_progress_init(ctypes.byref(p))
        _check(_lib.moldtex_sim_run_stop(self.handle, ctypes.byref(p)), "The live stepping")
        return {"running": bool(p.running), "steps": p.steps, "step_seconds": p.step_seconds}

    def new_rgba_buffer(self):
        """A zeroed array('f') of width*height*4 floats for read_rgba / foreach_set."""
        return array.array("f", bytes(4 * 4 * self.width * self.height))

    def read_rgba(self, buffer=None):
        """Copies the pheromone as RGBA floats (Blender's pixel order) into `buffer`
        (array('f') or numpy float32, >= width*height*4 floats) and returns it."""
        if buffer is None:
            buffer = self.new_rgba_buffer()
        address, count = _buffer_address(buffer, ("f",), writable=True)
        _check(_lib.moldtex_sim_read_rgba(self.handle, ctypes.c_void_p(address), count),
               "Reading the pheromone")
        return buffer

    def read_vertex_rgba(self, buffer=None):
        """The pheromone at each mesh vertex, encoded as read_rgba encodes a texel
        (4 floats a vertex; intrinsic domain only), into `buffer` (array('f'), >=
        vertex_count*4 floats), which it returns."""
        if buffer is None:
            buffer = array.array("f", bytes(16 * self.vertex_count))
        address, count = _buffer_address(buffer, ("f",), writable=True)
        _check(_lib.moldtex_sim_read_vertex_rgba(self.handle, ctypes.c_void_p(address), count),
               "Reading the pheromone at the mesh vertices")
        return buffer

    def read_texel_classes(self, buffer=None):
        """Texel classes (TEXEL_OUTSIDE/INSIDE/GUTTER) as array('B'), pheromone order."""
        if buffer is None:
            buffer = array.array("B", bytes(self.width * self.height))
        address, count = _buffer_address(buffer, ("B",), writable=True)
        _check(_lib.moldtex_sim_read_texel_classes(self.handle, ctypes.c_void_p(address),
                                                   count),
               "Reading texel classes")
        return buffer

    def read_agents(self, capacity):
        """Up to `capacity` agent positions as (triangle, (b0, b1, b2)) tuples."""
        points = (SurfacePoint * capacity)()
        _check(_lib.moldtex_sim_read_agents(self.handle, points, capacity), "Reading agents")
        return [(pt.triangle, tuple(pt.bary)) for pt in points]

    def get_stats(self):
        s = SimStats()
        _lib.moldtex_sim_stats_init(ctypes.byref(s))
        _check(_lib.moldtex_sim_get_stats(self.handle, ctypes.byref(s)), "Reading statistics")
        return _struct_to_dict(s, STATS_FIELDS)

    def domain_info(self):
        """The domain (DOMAIN_*) and its size: cell_count (island texels or intrinsic
        vertices), face_count, bound (mesh units), build_seconds, insertions,
        skipped_faces, from_cache (1: a recent build of the same mesh was reused)."""
        info = DomainInfo()
        _lib.moldtex_domain_info_init(ctypes.byref(info))
        _check(_lib.moldtex_sim_get_domain_info(self.handle, ctypes.byref(info)),
               "Reading the domain")
        return _struct_to_dict(info, DOMAIN_INFO_FIELDS)

    def write_image(self, path, image_format=IMAGE_EXR_HALF):
        """Writes the pheromone to `path` (IMAGE_* format; one channel "Y" per species,
        written as path.partial and renamed when whole)."""
        _check(_lib.moldtex_sim_write_image(self.handle, _path_bytes(path), int(image_format)),
               "Writing the image")

    def save_checkpoint(self, path):
        """Saves the whole state (agents, pheromone, step count, parameters) atomically."""
        _check(_lib.moldtex_sim_save_checkpoint(self.handle, _path_bytes(path)),
               "Saving the checkpoint")

    def load_checkpoint(self, path):
        """Restores a checkpoint made by a simulation of the same mesh and config."""
        _check(_lib.moldtex_sim_load_checkpoint(self.handle, _path_bytes(path)),
               "Loading the checkpoint")

    def add_agents(self, brush, count, batch):
        """Slime brush: adds `count` agents of species brush["channel"] uniformly over the
        brush's geodesic disk, tagged `batch` (1..65535, e.g. one per stroke) for
        undo_agents. Deterministic in (seed, batch, agents of the batch so far)."""
        b = _brush(brush)
        _check(_lib.moldtex_sim_add_agents(self.handle, ctypes.byref(b), int(count), int(batch)),
               "Adding agents")

    def erase_agents(self, brush, batch):
        """Erase-slime brush: removes the agents in the disk (each with probability
        strength * falloff weight) and keeps them under `batch`; returns how many."""
        b = _brush(brush)
        removed = ctypes.c_uint32(0)
        _check(_lib.moldtex_sim_erase_agents(self.handle, ctypes.byref(b), int(batch),
                                             ctypes.byref(removed)),
               "Erasing agents")
        return removed.value

    def undo_agents(self, batch):
        """Undoes a stroke: removes the agents added with `batch`, restores those erased
        with it."""
        _check(_lib.moldtex_sim_undo_agents(self.handle, int(batch)), "Undoing a brush stroke")

    def release(self):
        if self._handle is not None and _lib is not None:
            _lib.moldtex_sim_release(self._handle)
        self._handle = None

    def __del__(self):
        try:
            self.release()
        except Exception:
            pass


def _path_bytes(path):
    """A file path as the bytes the core's const char* expects."""
    if not path:
        raise EngineError("The file path is empty.", ERROR_INVALID_ARGUMENT)
    return os.fsencode(os.fspath(path))


def frame_file_name(prefix, frame, image_format):
    """The name a bake gives frame `frame`: <prefix><frame, 4 digits>.exr|png."""
    return f"{prefix}{int(frame):04d}{IMAGE_EXTENSIONS[int(image_format)]}"


def metrics_file_name(prefix):
    return f"{prefix}metrics.csv"


def checkpoint_file_name(prefix):
    return f"{prefix}checkpoint.bin"


class Bake:
    """A native bake (moldtex_bake): frames first_frame..last_frame of a simulation
    written into `directory` by the core's own thread.

    It resets the simulation; frame f is the state after (f - first_frame + 1) *
    steps_per_frame steps. Files: frame_file_name(prefix, f, format) for each frame,
    metrics_file_name(prefix) (frame, step, coverage, presence) and, with
    write_checkpoints, checkpoint_file_name(prefix) after every frame; resume=True
    continues from that checkpoint with bit-identical frames. While it runs, every other
    call on the simulation raises EngineError with status ERROR_BUSY.
    progress() never blocks; wait() blocks (without holding Python's GIL).
    """

    def __init__(self, sim, directory, first_frame, last_frame, steps_per_frame,
                 image_format=IMAGE_EXR_HALF, file_prefix="moldtex_", resume=False,
                 write_checkpoints=True):
        lib = _require()
        self._handle = None
        desc = BakeDesc()
        lib.moldtex_bake_desc_init(ctypes.byref(desc))
        # The core copies both strings before moldtex_bake_start returns; they are kept
        # here anyway so that nothing points into freed memory.
        self._directory = _path_bytes(directory)
        self._prefix = os.fsencode(file_prefix)
        desc.directory = self._directory
        desc.file_prefix = self._prefix
        desc.first_frame = int(first_frame)
        desc.last_frame = int(last_frame)
        desc.steps_per_frame = int(steps_per_frame)
        desc.format = int(image_format)
        desc.write_checkpoints = 1 if write_checkpoints else 0
        desc.resume = 1 if resume else 0
        handle = _Bake()
        _check(lib.moldtex_bake_start(sim.handle, ctypes.byref(desc), ctypes.byref(handle)),
               "Starting the bake")
        self._handle = handle
        self.directory = os.fsdecode(self._directory)
        self.file_prefix = file_prefix
        self.first_frame = desc.first_frame
        self.last_frame = desc.last_frame
        self.steps_per_frame = desc.steps_per_frame
        self.image_format = desc.format
        self.resume = bool(resume)

    @property
    def handle(self):
        if self._handle is None:
            raise EngineError("This bake was released.", ERROR_INVALID_ARGUMENT)
        return self._handle

    @property
    def frame_count(self):
        return self.last_frame - self.first_frame + 1

    def frame_path(self, frame):
        return os.path.join(self.directory,
                            frame_file_name(self.file_prefix, frame, self.image_format))

    def progress(self):
        """dict: state (BAKE_*), first_frame, last_frame, last_frame_written, frames_done
        (whole frames on disk, resumed ones included), step_count, coverage, presence
        (of the last frame written) and message (why it failed)."""
        p = BakeProgress()
        _lib.moldtex_bake_progress_init(ctypes.byref(p))
        _check(_lib.moldtex_bake_get_progress(self.handle, ctypes.byref(p)),
               "Reading the bake's progress")
        result = _struct_to_dict(p, BAKE_PROGRESS_FIELDS)
        result["message"] = _decode(p.message)
        return result

    def running(self):
        return self.progress()["state"] == BAKE_RUNNING

    def cancel(self):
        """Asks the bake to stop after the current step (no partial frame is left)."""
        if self._handle is not None:
            _lib.moldtex_bake_cancel(self._handle)

    def wait(self):
        """Blocks until the bake ends; raises EngineError if it failed (a cancelled
        bake is not a failure: see progress()["state"])."""
        _check(_lib.moldtex_bake_wait(self.handle), "The bake")

    def release(self):
        """Cancels and waits if still running, then frees the handle."""
        if self._handle is not None and _lib is not None:
            _lib.moldtex_bake_release(self._handle)
        self._handle = None

    def __del__(self):
        try:
            self.release()
        except Exception:
            pass


class DomainBuild:
    """Builds the intrinsic domain a Simulation(surface, config) would run on, on the
    core's own thread (moldtex_domain_build), so that an interface can show its progress
    and cancel it; the Simulation created next with the same surface, size and bound
    reuses it (domain_info()["from_cache"]). config as for Simulation (domain must be
    DOMAIN_INTRINSIC); thread_count as the params' (0 = all cores).
    progress() never blocks; wait() blocks (without holding Python's GIL)."""

    def __init__(self, surface, config, thread_count=0):
        lib = _require()
        self._handle = None
        c = SimConfig()
        lib.moldtex_sim_config_init(ctypes.byref(c))
        config = dict(config or {})
        config.pop("seed_center", None)   # (where agents start does not shape the domain)
        config.pop("fields_rgba", None)
        _fill(c, config, CONFIG_FIELDS, "config")
        handle = _DomainBuild()
        _check(lib.moldtex_domain_build_start(surface.handle, ctypes.byref(c),
                                              int(thread_count), ctypes.byref(handle)),
               "Building the intrinsic triangulation")
        self._handle = handle

    @property
    def handle(self):
        if self._handle is None:
            raise EngineError("This domain build was released.", ERROR_INVALID_ARGUMENT)
        return self._handle

    def progress(self):
        """dict: state (BAKE_RUNNING / _FINISHED / _CANCELLED / _FAILED), stage (BUILD_*),
        vertex_count, fraction (0..1, an estimate that only grows), seconds, from_cache
        and message (why it failed)."""
        p = DomainBuildProgress()
        _lib.moldtex_domain_build_progress_init(ctypes.byref(p))
        _check(_lib.moldtex_domain_build_get_progress(self.handle, ctypes.byref(p)),
               "Reading the build's progress")
        return {"state": p.state, "stage": p.stage, "vertex_count": p.vertex_count,
                "fraction": p.fraction, "seconds": p.seconds,
                "from_cache": bool(p.from_cache), "message": _decode(p.message)}

    def running(self):
        return self.progress()["state"] == BAKE_RUNNING

    def cancel(self):
        """Asks the build to stop (nothing of it is kept); returns at once."""
        if self._handle is not None:
            _lib.moldtex_domain_build_cancel(self._handle)

    def wait(self):
        """Blocks until the build ends; raises EngineError if it failed or was cancelled
        (status ERROR_CANCELLED)."""
        _check(_lib.moldtex_domain_build_wait(self.handle), "Building the intrinsic triangulation")

    def release(self):
        """Cancels and waits if still running, then frees the handle."""
        if self._handle is not None and _lib is not None:
            _lib.moldtex_domain_build_release(self._handle)
        self._handle = None

    def __del__(self):
        try:
            self.release()
        except Exception:
            pass


# ---- colour map from an image (Layton et al. §3.4) ----------------------------------

def colour_ramp_from_pixels(pixels, channels=4, srgb_encoded=False, sample_count=1500,
                            max_stops=MAX_RAMP_STOPS, reverse=False, peak_position=-1.0,
                            tolerance=1.0, neighbour_count=10):
    """Colour map of an image's pixel colours (moldtex_colour_ramp_from_pixels):
    pixels is an array('f') (or float32 numpy array) of `channels` (3 or 4) floats per
    pixel. Returns (stops, info): stops = [(position, (r, g, b, a))] in linear RGB,
    darker end first unless reverse; info = dict of moldtex_colour_ramp_info (explained:
    0..1, how well one variable describes the image)."""
    _require()
    address, count = _buffer_address(pixels, ("f",), writable=False)
    desc = ColourRampDesc()
    _lib.moldtex_colour_ramp_desc_init(ctypes.byref(desc))
    desc.channels = int(channels)
    desc.srgb_encoded = 1 if srgb_encoded else 0
    desc.sample_count = int(sample_count)
    desc.max_stops = int(max_stops)
    desc.reverse = 1 if reverse else 0
    desc.peak_position = float(peak_position)
    desc.tolerance = float(tolerance)
    desc.neighbour_count = int(neighbour_count)
    stops = (ColourStop * MAX_RAMP_STOPS)()
    info = ColourRampInfo()
    _lib.moldtex_colour_ramp_info_init(ctypes.byref(info))
    pixel_count = count // max(1, int(channels))
    _check(_lib.moldtex_colour_ramp_from_pixels(ctypes.c_void_p(address), pixel_count,
                                                ctypes.byref(desc), stops, MAX_RAMP_STOPS,
                                                ctypes.byref(info)),
           "Extracting a colour map")
    result = [(float(stops[i].position), tuple(float(c) for c in stops[i].color))
              for i in range(info.stop_count)]
    return result, {name: getattr(info, name) for name, _ in ColourRampInfo._fields_
                    if name != "struct_size"}
