# SPDX-License-Identifier: GPL-3.0-or-later
"""Loading libmoldtex and the calls' plumbing: every function's signature (declared once,
when the library is loaded at import), the error of the last call, buffers crossing the
boundary, the core's defaults, OpenCL devices. LOAD_ERROR holds a plain-language reason
when the library is missing or does not match; calls then raise EngineError."""

import array
import ctypes
import math
import os
import sys

from .structs import *  # noqa: F401,F403  (the header's constants and structs)

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

ADDON_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # moldtex/

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
    """The core's defaults of the reaction-diffusion model (moldtex_reaction_params_init)
    as a dict of REACTION_FIELDS."""
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


def _path_bytes(path):
    """A file path as the bytes the core's const char* expects."""
    if not path:
        raise EngineError("The file path is empty.", ERROR_INVALID_ARGUMENT)
    return os.fsencode(os.fspath(path))


class Handle:
    """An object of the core owned by one Python object (a subclass sets _release, the
    name of its moldtex_*_release function, and _what, its name in messages): freed once,
    by release() or when the Python object is collected."""
    _release = ""
    _what = "object"
    _handle = None

    @property
    def handle(self):
        if self._handle is None:
            raise EngineError(f"This {self._what} was released.", ERROR_INVALID_ARGUMENT)
        return self._handle

    def release(self):
        """Frees the core's object (a running bake or build is cancelled and waited for)."""
        if self._handle is not None and _lib is not None:
            getattr(_lib, self._release)(self._handle)
        self._handle = None

    def __del__(self):
        try:
            self.release()
        except Exception:
            pass
