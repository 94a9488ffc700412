# SPDX-License-Identifier: GPL-3.0-or-later
"""The header's constants, status codes and structs, mirrored for ctypes (field order and
types exactly as in native/include/moldtex.h; tools/check_ctypes_mirrors.py compares
each struct's size and offsets with the C compiler's). No bpy, no library."""

import ctypes

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
