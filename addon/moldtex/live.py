# SPDX-License-Identifier: GPL-3.0-or-later
"""Live simulations, one per object, keyed by object name.

They live here (not in bpy data: a simulation cannot be saved in a .blend), and are
freed on file load, on add-on unregister and when their object is deleted. After
undo the objects are new Python wrappers, so entries are looked up by name and marked
dirty: the next step re-reads the evaluated mesh and rebuilds the simulation if the
mesh (or its UV map) is not the one the simulation was built on.

This module talks to the core only through engine.py.
"""

import array
import math
import time
import zlib

from . import engine, image_io, vertex_colours
from .maps import mesh_values
from .maps import sampling as map_sampling
from .mesh_export import (MeshExportError, export_object, export_scale,
                          length_in_mesh_units, no_uv_map_message, read_corner_fields,
                          resolve_uv_map_name, world_to_mesh)

# name -> LiveSim
_registry = {}

PARAM_PROPERTIES = ("movement_speed", "turn_speed", "vision_distance", "vision_angle",
                    "evaporation_rate", "diffusion_rate", "deposit", "substeps",
                    "thread_count", "sensor_size")
CONFIG_PROPERTIES = ("resolution", "agent_count", "seed", "uv_map", "backend_type",
                     "opencl_platform", "opencl_device", "opencl_device_name",
                     "opencl_platform_name", "species_count", "seed_shape", "seed_radius",
                     "seed_rays")
SPECIES_PROPERTIES = ("movement_speed", "turn_speed", "vision_distance", "vision_angle",
                      "deposit")
SEED_SHAPES = {"RANDOM": engine.SEED_RANDOM, "SPAWN_MAP": engine.SEED_SPAWN_MAP,
               "CIRCLE": engine.SEED_CIRCLE, "BIG_BANG": engine.SEED_BIG_BANG,
               "STARBURST": engine.SEED_STARBURST}
CENTERED_SHAPES = {"CIRCLE", "BIG_BANG", "STARBURST"}


class LiveSim:
    """One object's simulation and what it was built from."""

    def __init__(self, name):
        self.name = name
        self._stepper = None      # _Stepper: the core steps the sim between live updates
        self.grown_steps = 0      # steps stopped threads ran that no live update counted
        self.food_left = None     # last sim.get_food() (the panel's, while a thread runs)
        self._sim = None
        self.sim = None           # engine.Simulation (see the property below)
        self.config = None        # dict the sim was created with
        self.uv_map = ""          # UV map name the sim was built on
        self.uv_map_setting = ""  # settings.uv_map at build time ("" = render UV map)
        self.reaction_seeds = None  # reaction_seeds(settings) at build time (Gray-Scott)
        self.signature = None     # MeshArrays.signature of the mesh it was built on
        self.surface_info = {}
        self.pixels = None        # persistent array('f') for read_rgba + foreach_set
        self.vertex_colours = False  # a mesh without (usable) UVs: shown as vertex colours
        self.flat_uv_map = ""        # its UV map of zero area, if it has one
        self.vertex_pixels = None    # persistent array('f') for read_vertex_rgba
        self.vertex_problem = ""     # why the vertex colours cannot follow (modifiers)
        self.stats = {}
        self.dirty = False        # mesh may have changed (depsgraph / undo)
        self.running = False      # a moldtex.start modal drives it
        self.stop_requested = False
        self.notice = ""          # last thing worth telling the user (panel)
        self.warning = ""         # same, but reported as a warning
        self.backend_name = ""    # moldtex_sim_get_backend_name of the running sim
        self.domain_info = None   # Simulation.domain_info() of the running sim
        self.backend_note = ""    # why the sim does not run on the chosen backend
        self.create_config = None  # config given to the core (seed centre, radius)
        # Bake (bake.py): the core's bake worker owns self.sim while it runs.
        self.bake = None          # engine.Bake while a bake runs, else None
        self.bake_plan = None     # bake.BakePlan of the running or last bake
        self.bake_progress = {}   # last engine.Bake.progress() (the panel shows it)
        self.bake_cancel_requested = False  # the modal bake cancels on its next tick
        self.bake_summary = ""    # one line about the last bake, for the panel
        self.bake_started = None  # perf_counter() when the running bake started
        self.bake_resumed_frames = 0  # frames a resumed bake found already done
        # Food sources last given to the core (food_from_settings' tuples), so that a
        # step re-sends them only when the Empties or their properties changed.
        self.food_key = None
        self.food_names = []      # name of the Empty behind each core food source
        self.food_dropped = 0     # Empties beyond engine.MAX_FOOD_SOURCES (ignored)
        # Checksum of the fields last given to the core (None = none), and when the
        # Fields image was last compared with them (poll_fields_image).
        self.fields_crc = None
        self.fields_polled = 0.0
        # (direction in mesh coordinates or None, triangle count) of the bias vectors
        # last given to the continuous model's simulation (_push_bias).
        self.bias_key = None
        # Parameter maps (maps/): {engine.MAP_*: maps.sampling key} of the values last
        # given to the continuous model's simulation (_push_maps), and the last error
        # reading them (the Maps panel shows it; "" = none).
        self.map_keys = {}
        self.maps_error = ""
        self.maps_failed = None   # the keys of that error's settings (no retry per step)
        # Live loop pacing (step_for_time): seconds one step took (running mean), the
        # steps per second of wall time while Start runs (what the panel shows), and
        # the time between the end of one update's stepping and the next one's start
        # (upload, redraw, waiting for the timer).
        self.step_seconds = 0.0
        self.steps_per_second = 0.0
        self.update_overhead = 0.0
        self.last_update_end = 0.0
        self.stepping = False     # a modal moldtex.step runs on it
        # State before the last Step (a checkpoint file), so that Adjust Last Operation
        # can run that Step again with another count: (sim, path, step count at its end).
        self.step_snapshot = None

    # While Start runs, the core steps the simulation on its own thread between two live
    # updates (so that it grows while Blender redraws; _Stepper). Anything else that
    # reaches for the simulation through entry.sim first stops that (waiting at most one
    # chunk of steps, about Update Time): the core refuses other calls meanwhile.
    @property
    def sim(self):
        if self._stepper is not None:
            stop_stepper(self)
        return self._sim

    @sim.setter
    def sim(self, value):
        if self._stepper is not None:
            stop_stepper(self)
        self._sim = value

    @property
    def has_sim(self):
        """entry.sim is not None, without waiting for the stepping thread (panels)."""
        return self._sim is not None

    @property
    def baking(self):
        return self.bake is not None

    def release(self):
        try:
            stop_stepper(self)
        except Exception:  # its error no longer matters: the simulation goes
            pass
        drop_step_snapshot(self)
        if self.bake is not None:
            self.bake.release()  # cancels and waits for the current step
        self.bake = None
        if self.sim is not None:
            self.sim.release()
        self.sim = None
        self.pixels = None
        self.stop_requested = True


def get(name):
    return _registry.get(name)


def names():
    return list(_registry)


def free(name):
    _build_exports.pop(name, None)
    entry = _registry.pop(name, None)
    if entry is not None:
        entry.release()


def free_all():
    for name in list(_registry):
        free(name)


def mark_dirty(name=None):
    """Marks one entry (or all, name=None) to be checked against its mesh."""
    for key, entry in _registry.items():
        if name is None or key == name:
            entry.dirty = True
    for key in list(_build_exports):
        if name is None or key == name:
            del _build_exports[key]


def opencl_devices():
    """engine.opencl_devices(): (devices, reason), read once and cached."""
    return engine.opencl_devices()


def find_opencl_device(settings):
    """The engine's device (dict) that the settings' stored OpenCL choice means, or
    None, and a note for the user when the choice cannot be honoured here ("" if it
    can, or if the stored indices are to be used as they are)."""
    devices, reason = engine.opencl_devices()
    name = settings.opencl_device_name
    platform, index = settings.opencl_platform, settings.opencl_device
    if not name:
        # Set by a script through the indices: use them as they are (the core reports
        # a device that does not exist when the simulation is created).
        for device in devices:
            if (device["platform_index"], device["device_index"]) == (platform, index):
                return device, ""
        return None, ""
    # Chosen in the panel: find the device by name, so that a file still finds its
    # device when the platforms are listed in another order.
    same_name = [d for d in devices if d["name"] == name and (
        not settings.opencl_platform_name
        or d["platform_name"] == settings.opencl_platform_name)]
    for device in same_name:
        if (device["platform_index"], device["device_index"]) == (platform, index):
            return device, ""
    if same_name:
        return same_name[0], ""
    where = (f"OpenCL is unavailable here ({reason.rstrip('.')})" if not devices
             else "this machine does not have it")
    return None, (f"The OpenCL device '{name}' chosen in this file cannot be used: "
                  f"{where}. Auto is used instead. Pick a Backend to change it.")


def backend_from_settings(settings):
    """(config fields for the backend, note): note says why the choice is not used."""
    fields = {"backend": engine.BACKEND_AUTO, "opencl_platform": 0, "opencl_device": 0}
    if settings.backend_type == 'CPU':
        fields["backend"] = engine.BACKEND_CPU
    elif settings.backend_type == 'OPENCL':
        device, note = find_opencl_device(settings)
        if device is not None:
            fields.update(backend=engine.BACKEND_OPENCL,
                          opencl_platform=device["platform_index"],
                          opencl_device=device["device_index"])
        elif not note:
            fields.update(backend=engine.BACKEND_OPENCL,
                          opencl_platform=int(settings.opencl_platform),
                          opencl_device=int(settings.opencl_device))
        else:
            return fields, note
    return fields, ""


def backend_note(settings):
    """Why the settings' backend choice cannot be used on this machine, or ""."""
    if settings.backend_type != 'OPENCL':
        return ""
    return find_opencl_device(settings)[1]


MODELS = {"MOMAS": engine.MODEL_MOMAS, "CONTINUOUS": engine.MODEL_CONTINUOUS,
          "GRAY_SCOTT": engine.MODEL_GRAY_SCOTT}
INTEGRATORS = {"AUTO": engine.INTEGRATOR_AUTO, "FORWARD": engine.INTEGRATOR_FORWARD,
               "BACKWARD": engine.INTEGRATOR_BACKWARD}


def model_of(settings):
    """engine.MODEL_* the settings ask for (a value this version does not know reads as
    MoMaS, the default)."""
    from .properties import enum_value  # (properties imports this module)
    return MODELS.get(enum_value(settings, "model"), engine.MODEL_MOMAS)


def sim_model(entry):
    """engine.MODEL_* of entry's simulation (the settings may ask for another one until
    Reset), or None without a simulation."""
    if entry is None or entry.config is None:
        return None
    return entry.config.get("model", engine.MODEL_MOMAS)


DOMAINS = {"TEXTURE": engine.DOMAIN_TEXTURE, "INTRINSIC": engine.DOMAIN_INTRINSIC}


def domain_of(settings):
    """engine.DOMAIN_* the settings ask for: Intrinsic only for the models that run on
    it (MoMaS works in texels, so a MoMaS simulation keeps the texture whatever the
    setting says)."""
    from .properties import enum_value  # (properties imports this module)
    if model_of(settings) == engine.MODEL_MOMAS:
        return engine.DOMAIN_TEXTURE
    return DOMAINS.get(enum_value(settings, "domain"), engine.DOMAIN_TEXTURE)


def config_from_settings(settings, surface_info=None):
    """The core's config for settings; `surface_info` (the surface's area and UV area,
    engine.Surface.info) decides Detail: Auto, which is 1 where it is not given."""
    from .properties import enum_value  # (properties imports this module)
    size = int(enum_value(settings, "resolution"))
    domain = domain_of(settings)
    config = {"model": model_of(settings), "domain": domain,
              "intrinsic_bound": (float(settings.intrinsic_size)
                                  if domain == engine.DOMAIN_INTRINSIC else 0.0),
              "width": size, "height": size, "agent_count": int(settings.agent_count),
              "seed": int(settings.seed), "species_count": int(settings.species_count),
              "seed_shape": SEED_SHAPES[enum_value(settings, "seed_shape")],
              "seed_radius": float(settings.seed_radius),
              "seed_rays": int(settings.seed_rays),
              "detail": detail_for(settings, size, surface_info)}
    config.update(backend_from_settings(settings)[0])
    return config


# Detail: Auto doubles the detail while the simulation has fewer texels per pattern unit
# than this (a UV sphere's poles need two: README, "Units: Surface") and its size stays
# within AUTO_DETAIL_MAX_SIZE[detail] texels per side: 4x only up to 1024^2 simulated,
# since on Suzanne (Subdivision 2, 512^2, the defaults) a step takes 4.8 ms at 1x, 11 ms
# at 2x (1024^2) and 32-41 ms at 4x (2048^2; PERFORMANCE).
AUTO_DETAIL_TEXELS_PER_UNIT = 1.9
AUTO_DETAIL_MAX_SIZE = {2: 4096, 4: 1024}


def detail_for(settings, size, surface_info=None):
    """Simulated texels per image texel and axis (the core's config.detail): 1 except for
    MoMaS in surface units; there the Detail setting, or for Auto the smallest of 1, 2
    and 4 that gives AUTO_DETAIL_TEXELS_PER_UNIT simulated texels per pattern unit, as
    far as AUTO_DETAIL_MAX_SIZE allows (1 where the surface is not known)."""
    if model_of(settings) != engine.MODEL_MOMAS or \
            _enum(settings, "pattern_units", 'SURFACE') != 'SURFACE':
        return 1
    choice = _enum(settings, "detail", 'AUTO')
    if choice != 'AUTO':
        return int(choice)
    per_unit = _per_unit(settings, surface_info or {}, size, size)
    if per_unit is None:
        return 1
    detail = 1
    while (detail < 4 and per_unit * detail < AUTO_DETAIL_TEXELS_PER_UNIT
           and 2 * detail * size <= AUTO_DETAIL_MAX_SIZE[2 * detail]):
        detail *= 2
    return detail


# Surface units: a pattern scale of 1 makes one pattern "texel" the side of a square of
# 1/512² of the object's area (the texel of a 512² texture on a UV layout that fills it),
# so at the default resolution the look is MoMaS' and higher resolutions sharpen it.
REFERENCE_RESOLUTION = 512


def pattern_unit(settings, area):
    """The pattern unit in mesh units: the length every pattern length of both models is
    a multiple of (MoMaS' surface-unit "texel", the continuous model's lengths).
    Pattern Scale Mode 'OBJECT': Pattern Scale × √(area) / 512, area being the surface's
    3D area in mesh units² (0 where it is not known yet); 'LENGTH': the Pattern Length,
    a length in the scene, in the mesh's units (object scale applied)."""
    if _enum(settings, "pattern_scale_mode", 'OBJECT') == 'LENGTH':
        obj = settings.id_data
        length = float(settings.pattern_length)
        return length_in_mesh_units(obj, length) if obj is not None else length
    if not area or area <= 0:
        return 0.0
    return math.sqrt(area) / REFERENCE_RESOLUTION * float(settings.pattern_scale)


def length_unit(settings, area):
    """The core's length_unit (mesh units) for settings on a surface of 3D area `area`:
    0 in texel units, or where the area is not known yet."""
    if _enum(settings, "pattern_units", 'SURFACE') != 'SURFACE':
        return 0.0
    return pattern_unit(settings, area)


def texels_per_unit(entry, settings):
    """How many texels of entry's texture span one pattern unit (MoMaS in surface units):
    the unit over the side of the mean texel, √(3D area / (UV area × width × height)).
    Under about two, detail finer than a unit and a UV sphere's poles come out thin
    (README, "Units: Surface"). None where it does not apply or is not known yet."""
    if sim_model(entry) != engine.MODEL_MOMAS or not entry.has_sim:
        return None
    if _enum(settings, "pattern_units", 'SURFACE') != 'SURFACE':
        return None
    return _per_unit(settings, entry.surface_info,
                     entry.config.get("width", 0), entry.config.get("height", 0))


def _per_unit(settings, surface_info, width, height):
    """Texels of a width × height texture per pattern unit on a surface of
    surface_info's area and UV area: the unit over the side of the mean texel,
    √(3D area / (UV area × width × height)); None where any of them is unknown."""
    area = surface_info.get("area") or 0.0
    uv_area = surface_info.get("uv_area") or 0.0
    unit = pattern_unit(settings, area)
    if not (area > 0.0 and uv_area > 0.0 and width > 0 and height > 0 and unit > 0.0):
        return None
    return unit / math.sqrt(area / (uv_area * width * height))


def _enum(settings, name, default):
    try:
        return getattr(settings, name) or default  # "" for a value it does not know
    except (AttributeError, TypeError, ValueError):
        return default


def params_from_settings(settings, area=None, model=None):
    """The core's moldtex_sim_params for settings on a surface of `area` mesh units²;
    model (engine.MODEL_*, default: what the settings ask for) decides whether the
    MoMaS pattern lengths apply (the continuous model ignores them and gets
    length_unit 0, which the core always accepts)."""
    if model is None:
        model = model_of(settings)
    params = {name: getattr(settings, name) for name in PARAM_PROPERTIES}
    params["thread_count"] = min(int(params["thread_count"]), 256)  # the core's limit
    params["time_step"] = float(settings.time_step)
    params["length_unit"] = (length_unit(settings, area) if model == engine.MODEL_MOMAS
                             else 0.0)
    params["hunger_rate"] = settings.hunger_rate
    obj = settings.id_data
    params["food_radius"] = (length_in_mesh_units(obj, settings.food_radius)
                             if obj is not None else settings.food_radius)
    return params


def known_pattern_unit(settings, area):
    """pattern_unit(settings, area), or engine.EngineError when it is not known (no
    area yet in Pattern Scale Mode Object)."""
    unit = pattern_unit(settings, area)
    if not unit > 0.0 or not math.isfinite(unit):
        raise engine.EngineError(
            "The pattern unit is not known yet (the surface's area is needed for Pattern "
            "Scale Mode Object): press Reset.", engine.ERROR_INVALID_ARGUMENT)
    return unit


def reaction_params_from_settings(settings, area):
    """The core's moldtex_reaction_params (Gray-Scott) for settings on a surface of
    `area` mesh units²: diffusion rates from pattern units² to mesh units², the seed
    radius from pattern units. Raises engine.EngineError when the pattern unit is not
    known."""
    reaction = settings.reaction
    unit = known_pattern_unit(settings, area)
    return {
        "feed": float(reaction.feed),
        "kill": float(reaction.kill),
        "diffusion_u": float(reaction.diffusion_u) * unit * unit,
        "diffusion_v": float(reaction.diffusion_v) * unit * unit,
        "time_step": float(reaction.time_step),
        "seed_count": int(reaction.seed_count),
        "seed_radius": float(reaction.seed_radius) * unit,
    }


def reaction_seeds(settings):
    """What a Gray-Scott simulation takes only at Reset: the seeds' count and radius,
    and what turns the radius into mesh units (the pattern scale settings); None for
    the other models."""
    if model_of(settings) != engine.MODEL_GRAY_SCOTT:
        return None
    return (int(settings.reaction.seed_count), float(settings.reaction.seed_radius),
            float(settings.pattern_scale), _enum(settings, "pattern_scale_mode", 'OBJECT'),
            float(settings.pattern_length))


def continuous_params_from_settings(settings, area):
    """The core's moldtex_continuous_params for settings on a surface of `area` mesh
    units²: lengths from pattern units to mesh units (pattern_unit), the sensor angle
    in degrees. Raises engine.EngineError when the pattern unit is not known (no
    area in Object mode)."""
    from .properties import enum_value  # (properties imports this module)
    cont = settings.continuous
    unit = known_pattern_unit(settings, area)
    return {
        "move_rate": float(cont.move_rate) * unit,
        "turn_rate": float(cont.turn_rate),
        "turn_frequency": float(cont.turn_frequency),
        "sensor_distance": float(cont.sensor_distance) * unit,
        "sensor_angle": math.degrees(float(cont.sensor_angle)),
        "deposit_rate": float(cont.deposit_rate),
        "diffusion_rate": float(cont.diffusion_rate) * unit * unit,
        "decay_rate": float(cont.decay_rate),
        "mean_lifetime": float(cont.mean_lifetime),
        "activation_time": float(cont.activation_time),
        "time_step": float(settings.time_step),
        "integrator": INTEGRATORS.get(enum_value(cont, "integrator"),
                                      engine.INTEGRATOR_AUTO),
        "bias_strength": float(cont.bias_strength),
        "bias_symmetry": int(cont.bias_symmetry),
        "bias_spawn": 1 if cont.bias_spawn else 0,
        "boundary": (engine.BOUNDARY_ABSORB if enum_value(cont, "boundary") == 'ABSORB'
                     else engine.BOUNDARY_REFLECT),
    }


def bias_direction_in_mesh(obj):
    """The continuous model's Bias Direction (object axes) in the exported mesh's
    coordinates (mesh_export: a non-uniform object scale is applied to them, so a
    direction along the surface scales with it), normalised; None when it is zero or
    the bias is off (Bias Strength 0)."""
    cont = obj.moldtex.continuous
    if not (cont.bias_strength > 0.0 or cont.bias_spawn):
        return None
    direction = [float(v) for v in cont.bias_direction]
    scale = export_scale(obj)
    if scale is not None:
        direction = [d * float(k) for d, k in zip(direction, scale)]
    length = math.sqrt(sum(d * d for d in direction))
    if not (length > 0.0 and math.isfinite(length)):
        return None
    return tuple(d / length for d in direction)


def bias_vectors(direction, triangle_count):
    """moldtex_sim_set_bias' vectors: `direction` for each of the triangles (array('f')
    of triangle_count * 3), or None for None (no bias)."""
    if direction is None:
        return None
    return array.array("f", direction) * int(triangle_count)


def bias_from_settings(obj, triangle_count, depsgraph=None):
    """(key, vectors) of the bias obj's settings ask for: the Bias Direction on every
    triangle, or with Bias Source Attribute each face's vector of that Face attribute
    (maps/mesh_values.py); vectors None = no bias. Raises engine.EngineError."""
    cont = obj.moldtex.continuous
    if getattr(cont, "bias_source", 'DIRECTION') == 'ATTRIBUTE':
        if not (cont.bias_strength > 0.0 or cont.bias_spawn):
            return (None, triangle_count), None
        try:
            vectors = mesh_values.bias_vectors_from_attribute(obj, depsgraph, cont.bias_attribute,
                                                              triangle_count)
        except MeshExportError as error:
            raise engine.EngineError(str(error), engine.ERROR_INVALID_ARGUMENT) from None
        return (("ATTRIBUTE", zlib.crc32(vectors.tobytes())), triangle_count), vectors
    direction = bias_direction_in_mesh(obj)
    return (direction, triangle_count), bias_vectors(direction, triangle_count)


def _push_bias(entry, obj, sim=None, depsgraph=None):
    """Gives the simulation the bias vectors of obj's settings when they differ from
    the last ones it got (entry.bias_key). sim: a new simulation, not yet entry's,
    which always gets them; its key is returned for the caller to store."""
    fresh = sim is not None
    sim = sim if fresh else entry.sim
    key, vectors = bias_from_settings(obj, sim.triangle_count, depsgraph)
    if not fresh and key == entry.bias_key:
        return key
    sim.set_bias(vectors)
    if not fresh:
        entry.bias_key = key
    return key


# ---- U (layton-intrinsic-slime.md Eq. 5) --------------------------------------------

def agents_per_species(settings):
    """Agents of species 0 at the configured count (agent i belongs to species i %
    species_count): the N of Eq. 5 as the core counts it."""
    count = max(1, int(settings.species_count))
    return -(-int(settings.agent_count) // count)


def surface_area(obj, compute=True):
    """3D area (mesh units²) of obj's surface as the core measures it: the area stored
    at the last build, else the live simulation's, else (compute=True, not while
    drawing) measured from the evaluated mesh now and stored. None if unknown (no core,
    a mesh that cannot be exported)."""
    settings = obj.moldtex
    stored = float(settings.continuous.surface_area)
    if stored > 0.0:
        return stored
    entry = _registry.get(obj.name)
    if entry is not None and entry.surface_info.get("area"):
        return float(entry.surface_info["area"])
    if not compute or not engine.available():
        return None
    try:
        import bpy
        mesh = export_object(obj, bpy.context.evaluated_depsgraph_get(), settings.uv_map)
        surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs,
                                 mesh.triangle_uvs)
        try:
            area = float(surface.info()["area"])
        finally:
            surface.release()
    except (MeshExportError, engine.EngineError):
        return None
    if area > 0.0:
        settings.continuous.surface_area = area
        return area
    return None


def u_from_settings(settings, area=None, compute=True):
    """U (Eq. 5) that the settings give on obj's surface (area: mesh units², default
    surface_area(obj, compute)); None when the area is not known. +inf without decay."""
    obj = settings.id_data
    if area is None:
        area = surface_area(obj, compute) if obj is not None else None
    if not area:
        return None
    cont = settings.continuous
    return engine.u_metric(agents_per_species(settings), float(cont.deposit_rate),
                           float(cont.decay_rate), area, float(cont.activation_time),
                           float(cont.mean_lifetime))


def deposit_rate_for_target(settings, area=None):
    """The deposit rate giving the stored target U (Keep U) with the current agent
    count, area, decay rate, mean lifetime and activation time; None if none can."""
    obj = settings.id_data
    if area is None:
        area = surface_area(obj) if obj is not None else None
    if not area:
        return None
    cont = settings.continuous
    return engine.deposit_rate_for_u(float(cont.target_u), agents_per_species(settings),
                                     float(cont.decay_rate), area,
                                     float(cont.activation_time), float(cont.mean_lifetime))


FOOD_STRENGTH_PROPERTY = "moldtex_strength"
FOOD_AMOUNT_PROPERTY = "moldtex_amount"


def _number(value, default):
    try:
        value = float(value)
    except (TypeError, ValueError):
        return default
    return value if math.isfinite(value) else default


def food_from_settings(obj):
    """(sources, dropped): sources = [(name, position, strength, amount)] for the Empties
    in the object's Food collection (sorted by name, at most engine.MAX_FOOD_SOURCES),
    positions in the exported mesh's coordinates, strength converted from scene units²;
    dropped = how many Empties were left out."""
    collection = obj.moldtex.food_collection
    if collection is None:
        return [], 0
    empties = sorted((o for o in collection.all_objects if o is not None
                      and o.type == 'EMPTY'), key=lambda o: o.name)
    dropped = max(0, len(empties) - engine.MAX_FOOD_SOURCES)
    empties = empties[:engine.MAX_FOOD_SOURCES]
    to_mesh = world_to_mesh(obj)
    factor = length_in_mesh_units(obj, 1.0)
    sources = []
    for empty in empties:
        point = to_mesh @ empty.matrix_world.translation
        strength = max(0.0, _number(empty.get(FOOD_STRENGTH_PROPERTY, 1.0), 1.0))
        amount = _number(empty.get(FOOD_AMOUNT_PROPERTY, -1.0), -1.0)
        if amount < 0.0:
            amount = -1.0
        sources.append((empty.name, tuple(round(float(v), 6) for v in point),
                        strength * factor * factor, amount))
    return sources, dropped


def _push_food(entry, obj, fresh):
    """Sends the Food collection's sources to the core when they changed (fresh: a new
    simulation). A source whose Empty keeps its name and amount property keeps what is
    left of its food (moving it or changing its strength does not refill it)."""
    sources, dropped = food_from_settings(obj)
    key = tuple(sources)
    entry.food_dropped = dropped
    if not fresh and key == entry.food_key:
        return
    remaining = {}
    if not fresh and entry.food_key:
        current = entry.sim.get_food()
        for old, now in zip(entry.food_key, current):
            remaining[(old[0], old[3])] = now[2]
    entry.sim.set_food([(position, strength, remaining.get((name, amount), amount))
                        for name, position, strength, amount in sources])
    entry.food_key = key
    entry.food_names = [source[0] for source in sources]


def food_status(obj):
    """[(name, remaining amount)] of the live simulation's food (amount < 0 =
    inexhaustible), or None without a simulation."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is None or not entry.has_sim or entry.baking:
        return None
    if entry._stepper is None or entry.food_left is None:
        entry.food_left = entry.sim.get_food()
    # else: what the last live update read (the panel does not stop the stepping thread)
    current = entry.food_left
    return [(entry.food_names[i] if i < len(entry.food_names) else f"Source {i + 1}",
             source[2]) for i, source in enumerate(current)]


def species_params_from_settings(settings):
    """[(index, dict)] for every species when there are 2 or more, else [] (one species
    takes the object's own agent settings through set_params)."""
    count = int(settings.species_count)
    if count < 2:
        return []
    result = []
    for index in range(min(count, len(settings.species))):
        item = settings.species[index]
        params = {name: getattr(item, name) for name in SPECIES_PROPERTIES}
        params["attraction"] = tuple(item.attraction)
        result.append((index, params))
    return result


def _push_species(entry, settings):
    # Only the species the simulation has: a new Species count waits for Reset (a
    # parameter change meanwhile is no error).
    config = getattr(entry, "config", None)
    count = config.get("species_count", 1) if config else MAX_SPECIES_PUSHED
    for index, params in species_params_from_settings(settings):
        if index < count:
            entry.sim.set_species_params(index, params)


MAX_SPECIES_PUSHED = engine.MAX_SPECIES


# Settings naming the vertex group or attribute of each field channel (R, G, B).
FIELD_ATTRIBUTES = ("spawn_attribute", "obstacle_attribute", "attractor_attribute")
FIELD_LABELS = ("Spawn", "Obstacle", "Attractor")


def fields_from_settings(settings, width, height, mesh=None, surface=None, depsgraph=None):
    """The static fields as width*height*4 floats, or None without any. Raises
    engine.EngineError with plain words.

    Fields Source 'IMAGE': the Fields image (nearest resampling when its size differs).
    'ATTRIBUTES': the named vertex groups / attributes of the evaluated mesh, baked over
    the UV layout by the core; mesh (export_object's MeshArrays), surface (an
    engine.Surface of that mesh) and depsgraph are made here when not given."""
    if settings.fields_source == 'ATTRIBUTES':
        return _fields_from_attributes(settings, width, height, mesh, surface, depsgraph)
    image = settings.fields_image
    if image is None:
        return None
    source_width, source_height = image.size
    channels = image.channels
    if source_width == 0 or source_height == 0 or channels == 0:
        raise engine.EngineError(
            f"The Fields image '{image.name}' has no pixels (is its file missing?): pick "
            f"another image or clear Fields (Moldtex ▸ Species & Start).")
    source = image_io.read_pixels(image)
    if channels == 4 and (source_width, source_height) == (width, height):
        fields = source
    else:
        fields = _resample_nearest(source, source_width, source_height, channels,
                                   width, height)
    if not all(math.isfinite(value) for value in fields):
        raise engine.EngineError(f"The Fields image '{image.name}' holds values that are "
                                 f"not numbers: repaint it or pick another image.")
    return fields


def _fields_from_attributes(settings, width, height, mesh, surface, depsgraph):
    names = tuple(getattr(settings, name) for name in FIELD_ATTRIBUTES)
    if not any(names):
        return None
    obj = settings.id_data
    try:
        if depsgraph is None:
            import bpy
            depsgraph = bpy.context.evaluated_depsgraph_get()
        if mesh is None:
            mesh = export_object(obj, depsgraph, settings.uv_map)
        corners = read_corner_fields(obj, depsgraph, mesh, names, FIELD_LABELS)
    except MeshExportError as error:
        raise engine.EngineError(str(error), engine.ERROR_INVALID_ARGUMENT) from None
    # The core's ranges: spawn weight >= 0, attractor 0 .. 1 (the obstacle is a
    # threshold, any value goes). Interpolation keeps texels within the corners' range.
    spawn, attractor = corners[0::4], corners[2::4]
    if min(spawn, default=0.0) < 0.0:
        corners[0::4] = array.array("f", [value if value > 0.0 else 0.0 for value in spawn])
    if min(attractor, default=0.0) < 0.0 or max(attractor, default=0.0) > 1.0:
        corners[2::4] = array.array("f", [min(1.0, max(0.0, value)) for value in attractor])
    own_surface = surface is None
    if own_surface:
        surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs, mesh.triangle_uvs)
    try:
        return surface.rasterize_corners(width, height, corners)
    finally:
        if own_surface:
            surface.release()


# (image_io.resample_nearest; the parameter maps resample their images with it too)
_resample_nearest = image_io.resample_nearest


def _check_spawn_map(settings, fields):
    if settings.seed_shape != 'SPAWN_MAP':
        return
    if settings.fields_source == 'ATTRIBUTES':
        name = settings.spawn_attribute
        if not name:
            raise engine.EngineError(
                "Start is Spawn Map, but no Spawn vertex group or attribute is set: name "
                "one whose weights mark where agents start (Moldtex ▸ Species & Start ▸ "
                "Fields), or choose another Start.")
        if fields is None or not any(red > 0.0 and green <= 0.5
                                     for red, green in zip(fields[0::4], fields[1::4])):
            raise engine.EngineError(
                f"Start is Spawn Map, but the Spawn source '{name}' is 0 everywhere "
                f"outside the obstacles: paint some weight into it, or choose another "
                f"Start.")
        return
    if fields is None:
        raise engine.EngineError(
            "Start is Spawn Map, but no Fields image is set: pick one whose red channel "
            "marks where agents start (Moldtex ▸ Species & Start), or choose another Start.")
    if not any(red > 0.0 and green <= 0.5
               for red, green in zip(fields[0::4], fields[1::4])):
        raise engine.EngineError(
            f"Start is Spawn Map, but the Fields image '{settings.fields_image.name}' has "
            f"no spawn region (red) outside the walls (green): paint some red, or choose "
            f"another Start.")


def _check_seed_radius(obj, settings, radius, mesh):
    """Refuses a Circle or Starburst radius the core cannot use, saying why (the core
    only knows that its number is out of range)."""
    if settings.seed_shape not in {'CIRCLE', 'STARBURST'}:
        return
    positions = mesh.positions
    extent = max((max(positions[a::3]) - min(positions[a::3]) for a in range(3)),
                 default=0.0)
    if not (math.isfinite(radius) and 0.0 < radius <= 1e6 * max(extent, 1e-30)):
        shape = settings.bl_rna.properties["seed_shape"].enum_items[settings.seed_shape].name
        raise engine.EngineError(
            f"The {shape} Radius ({settings.seed_radius:.3g}) is far larger than "
            f"'{obj.name}' itself (about {extent:.3g} across in its own units"
            f"{'' if radius == settings.seed_radius else f', where the radius is {radius:.3g}'}"
            f"): use a radius the size of the object or smaller (Moldtex ▸ Species & "
            f"Start).", engine.ERROR_INVALID_ARGUMENT)


def seed_center(obj, surface, location):
    """(triangle, barycentrics) of the surface point nearest `location` (world space),
    in mesh_export's triangle order (the core's exact closest-point query)."""
    triangle, bary, _distance = surface.closest_point(tuple(world_to_mesh(obj) @ location))
    return (triangle, tuple(bary))


def needs_reset(obj):
    """True when config-type settings differ from the ones the live sim was built with."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is None or not entry.has_sim:  # (drawn by the panel: never waits)
        return False
    settings = obj.moldtex
    return (entry.config != config_from_settings(settings, entry.surface_info)
            or entry.uv_map_setting != settings.uv_map
            or entry.reaction_seeds != reaction_seeds(settings))


def _build(entry, obj, mesh, depsgraph=None):
    settings = obj.moldtex
    from .properties import repair_enums  # (properties imports this module)
    # unknown enum values -> defaults
    repaired = " ".join(repair_enums(settings) + repair_enums(settings.continuous))
    config = config_from_settings(settings)
    device_note = backend_note(settings)
    note = " ".join(filter(None, (repaired, device_note)))
    if len(settings.species) < settings.species_count:
        from .properties import ensure_species  # (properties imports this module)
        ensure_species(settings)
    if mesh.uvs is None and config.get("domain") != engine.DOMAIN_INTRINSIC:
        raise MeshExportError(no_uv_map_message(obj.name, mesh.flat_uv_map))
    create_config = dict(config)
    create_config["seed_radius"] = length_in_mesh_units(obj, config["seed_radius"])
    create_config["intrinsic_bound"] = length_in_mesh_units(obj, config["intrinsic_bound"])
    _check_seed_radius(obj, settings, create_config["seed_radius"], mesh)
    surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs, mesh.triangle_uvs)
    try:
        if settings.seed_shape in CENTERED_SHAPES:
            import bpy
            create_config["seed_center"] = seed_center(obj, surface,
                                                       bpy.context.scene.cursor.location)
        fields = fields_from_settings(settings, config["width"], config["height"], mesh,
                                      surface, depsgraph)
        _check_spawn_map(settings, fields)
        surface_info = surface.info()
        area = surface_info.get("area")
        # Detail: Auto follows the surface's texels per pattern unit.
        config["detail"] = create_config["detail"] = detail_for(settings, config["width"],
                                                                surface_info)
        continuous = reaction = None
        if config["model"] == engine.MODEL_CONTINUOUS:
            continuous = continuous_params_from_settings(settings, area)
        elif config["model"] == engine.MODEL_GRAY_SCOTT:
            reaction = reaction_params_from_settings(settings, area)
        map_values, map_keys = {}, {}
        kinds = map_sampling.kinds_for_model(config["model"])
        if kinds:
            try:
                map_values = map_sampling.sample(obj, kinds, config["width"],
                                                 config["height"], mesh, surface, depsgraph)
            except engine.EngineError as error:
                entry.maps_error = str(error)  # (the Maps panel shows it too)
                raise
            map_keys = map_sampling.keys(settings, config["width"], config["height"],
                                         mesh.signature, kinds)
        sim = engine.Simulation(surface, create_config,
                                params_from_settings(settings, area, config["model"]),
                                fields, continuous, reaction)
    except engine.EngineError as error:
        # The core's message says what failed (out of memory already suggests what to
        # lower); for an unusable device, say where to choose another one.
        if (config["backend"] == engine.BACKEND_OPENCL
                and error.status == engine.ERROR_UNAVAILABLE):
            raise engine.EngineError(
                f"{str(error).rstrip(' ;.')}. Pick Auto or CPU as Backend (Moldtex ▸ "
                f"Simulation) to run without this device.", error.status) from None
        raise
    finally:
        surface.release()  # the simulation holds its own reference
    bias_key = None
    try:
        if continuous is not None:
            _note_u_area(sim, settings, surface_info.get("area"))
            bias_key = _push_bias(entry, obj, sim, depsgraph)
        for kind, values in map_values.items():
            if values is not None:
                sim.set_map(kind, values)
        if config["model"] != engine.MODEL_GRAY_SCOTT:  # (no agents there)
            _push_species(_Holder(sim), settings)
        holder = LiveSim(entry.name)
        holder.sim = sim
        _push_food(holder, obj, fresh=True)
    except engine.EngineError:
        sim.release()
        raise
    if entry.sim is not None:
        entry.sim.release()
    entry.sim = sim
    entry.bias_key = bias_key
    entry.map_keys = map_keys
    entry.maps_error = ""
    entry.maps_failed = None
    entry.fields_crc = _crc(fields)
    entry.create_config = create_config
    entry.config = config
    entry.uv_map = mesh.uv_map
    entry.uv_map_setting = settings.uv_map
    entry.reaction_seeds = reaction_seeds(settings)
    entry.signature = mesh.signature
    entry.surface_info = surface_info
    entry.pixels = sim.new_rgba_buffer()
    # A mesh without UVs shows its pattern per vertex (vertex_colours.py).
    entry.vertex_colours = mesh.uvs is None
    entry.flat_uv_map = mesh.flat_uv_map  # (a UV map of zero area counts as none)
    entry.vertex_pixels = None
    entry.vertex_problem = (vertex_colours.correspondence_problem(obj, mesh.positions)
                            if entry.vertex_colours else "")
    entry.step_seconds = 0.0  # a new simulation: its steps cost what they cost
    entry.dirty = False
    entry.stats = sim.get_stats()
    entry.backend_name = sim.backend_name()
    entry.domain_info = sim.domain_info()
    entry.backend_note = device_note
    entry.warning = " ".join(filter(None, (note, entry.vertex_problem)))
    entry.food_key, entry.food_names = holder.food_key, holder.food_names
    entry.food_dropped = holder.food_dropped


def _note_u_area(sim, settings, triangle_area):
    """Stores the area U's Eq. 5 uses on this simulation (the core's A: the 3D area of
    the island texels, the PDE's cells, which the triangles' area approaches as the
    resolution grows), read back from the U the core reports; then, with Keep U on,
    sets the deposit rate for the target U on it (a new mesh, resolution or agent
    count) and gives it to the simulation."""
    cont = settings.continuous
    stats = sim.get_stats()
    u_value = stats.get("u_metric", 0.0)
    rate = float(cont.deposit_rate)
    agents = agents_per_species(settings)
    area = triangle_area
    if 0.0 < u_value < math.inf and rate > 0.0 and cont.decay_rate > 0.0:
        # U = N r_dep alive / (r_dec A) with the float32 values the core holds.
        core = sim.get_continuous_params()
        alive = (math.exp(-core["activation_time"] / core["mean_lifetime"])
                 if core["mean_lifetime"] > 0.0 else 1.0)
        area = agents * core["deposit_rate"] * alive / (core["decay_rate"] * u_value)
    if area and area > 0.0 and math.isfinite(area):
        cont.surface_area = area
    from .properties import keep_u  # (properties imports this module)
    if keep_u(settings):
        sim.set_continuous_params({"deposit_rate": float(cont.deposit_rate)})


class _Holder:
    def __init__(self, sim):
        self.sim = sim


def bake_running_message(entry, what=""):
    """Plain words for "the core refuses: a bake owns this simulation"."""
    progress = entry.bake_progress or {}
    where = ""
    if progress:
        total = progress["last_frame"] - progress["first_frame"] + 1
        where = f" (frame {progress['frames_done']}/{total})"
    start = f"{what}: a" if what else "A"
    return (f"{start} bake is running on '{entry.name}'{where}: wait for it to finish, or "
            f"cancel it (Esc, or Cancel Bake in the Moldtex panel).")


def check_not_baking(obj, what=""):
    """Raises engine.EngineError (ERROR_BUSY) if a bake runs on obj's simulation."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is not None and entry.baking:
        raise engine.EngineError(bake_running_message(entry, what), engine.ERROR_BUSY)


def ensure(obj, depsgraph, rebuild=False):
    """The object's LiveSim with a simulation matching its current mesh.

    rebuild=True makes a fresh simulation from the current settings (Reset, or Start
    after a config change). A dirty entry is rebuilt only if its mesh really changed.
    Raises MeshExportError or engine.EngineError with a message for the user (status
    ERROR_BUSY while a bake runs on the object's simulation).
    """
    check_not_baking(obj)
    entry = _registry.get(obj.name)
    if entry is not None and entry.sim is not None and not rebuild and not entry.dirty:
        return entry
    if not engine.available():
        raise engine.EngineError(engine.status_text())
    settings = obj.moldtex
    uv_map = entry.uv_map_setting if (entry is not None and entry.sim is not None
                                      and not rebuild) else settings.uv_map
    mesh = _take_build_export(obj.name, uv_map) or export_object(obj, depsgraph, uv_map)
    if entry is None:
        entry = LiveSim(obj.name)
    if entry.sim is not None and not rebuild and mesh.signature == entry.signature:
        entry.dirty = False
        if (sim_model(entry) == engine.MODEL_CONTINUOUS
                and getattr(settings.continuous, "bias_source", "") == 'ATTRIBUTE'):
            _push_bias(entry, obj, depsgraph=depsgraph)  # the attribute may have changed
        return entry
    restarted = entry.sim is not None and not rebuild
    if uv_map != settings.uv_map:
        # The mesh changed anyway: restart on the UV map the settings ask for now.
        mesh = export_object(obj, depsgraph, settings.uv_map)
    _build(entry, obj, mesh, depsgraph)
    _registry[obj.name] = entry
    entry.notice = ("The mesh changed, so the simulation restarted on the new mesh."
                    if restarted else "")
    return entry


# Intrinsic-domain builds running ahead of a simulation (Start and Reset in the
# interface): {object name: engine.DomainBuild}, read by the panel.
_domain_builds = {}
# The mesh each of those builds was made from, {object name: (UV map, MeshArrays)}:
# the next ensure() of that object creates its simulation from the same arrays instead
# of reading the mesh again (a second export of a big mesh; and the simulation then
# matches the domain the core has cached). Dropped when the build fails or is
# cancelled, and when the object's geometry changes (mark_dirty), so it is never stale.
_build_exports = {}


def _take_build_export(name, uv_map):
    """The arrays a finished domain build of `name` exported with `uv_map`, once."""
    held = _build_exports.pop(name, None)
    return held[1] if held is not None and held[0] == uv_map else None


def start_domain_build(obj, depsgraph, rebuild=False):
    """Starts building, on the core's thread, the intrinsic domain that
    ensure(obj, depsgraph, rebuild) would otherwise build inside its (blocking) create;
    returns the engine.DomainBuild, or None when ensure will build none (the texture
    domain, MoMaS, or a simulation it keeps). A domain the core built recently for the
    same mesh, size and bound finishes at once; the simulation created afterwards finds
    it in the core's cache."""
    check_not_baking(obj)
    entry = _registry.get(obj.name)
    if entry is not None and entry.has_sim and not rebuild and not entry.dirty:
        return None
    settings = obj.moldtex
    config = config_from_settings(settings)
    if config.get("domain") != engine.DOMAIN_INTRINSIC:
        return None
    mesh = export_object(obj, depsgraph, settings.uv_map)
    surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs, mesh.triangle_uvs)
    try:
        create_config = dict(config)
        create_config["intrinsic_bound"] = length_in_mesh_units(obj, config["intrinsic_bound"])
        build = engine.DomainBuild(surface, create_config, settings.thread_count)
    finally:
        surface.release()  # (the build keeps its own reference)
    _domain_builds[obj.name] = build
    _build_exports[obj.name] = (settings.uv_map, mesh)
    return build


def cancel_domain_build(obj):
    """Cancels obj's running domain build (Start or Reset pressed again); True if one
    ran. The operator that started it sees it end and reports it."""
    build = _domain_builds.get(obj.name) if obj is not None else None
    if build is None:
        return False
    build.cancel()
    return True


def end_domain_build(obj_name, finished=False):
    """Forgets (and cancels, if it still runs) the domain build of an object; unless it
    `finished`, also the mesh it exported."""
    if not finished:
        _build_exports.pop(obj_name, None)
    build = _domain_builds.pop(obj_name, None)
    if build is not None:
        build.release()


def domain_build_status(obj):
    """What the panel shows while an intrinsic domain builds: the build's progress dict,
    or None."""
    build = _domain_builds.get(obj.name) if obj is not None else None
    if build is None:
        return None
    try:
        return build.progress()
    except engine.EngineError:
        return None


def domain_build_text(progress):
    """One line on a build's progress, e.g. "Building the intrinsic triangulation: 43%
    (refining, 120,000 vertices, 4 s)"."""
    stage = engine.BUILD_STAGE_NAMES.get(progress["stage"], "")
    return (f"Building the intrinsic triangulation: {100 * progress['fraction']:.0f}% "
            f"({stage}, {progress['vertex_count']:,} vertices, {progress['seconds']:.0f} s)")


def _push_settings(entry, obj):
    """Gives entry's simulation obj's current parameters (those of its model, on its
    surface's area) and species."""
    settings = obj.moldtex
    area = entry.surface_info.get("area")
    model = sim_model(entry)
    entry.sim.set_params(params_from_settings(settings, area, model))
    if model == engine.MODEL_CONTINUOUS:
        entry.sim.set_continuous_params(continuous_params_from_settings(settings, area))
        _push_bias(entry, obj)
        _push_maps(entry, obj, quiet=True)
    elif model == engine.MODEL_GRAY_SCOTT:
        # (the seeds' count and radius wait for Reset: needs_reset says so)
        entry.sim.set_reaction_params(reaction_params_from_settings(settings, area))
        _push_maps(entry, obj, quiet=True)
        return  # no agents, so no species
    _push_species(entry, settings)


def push_params(obj):
    """Sends the object's current parameters to its live simulation, if any."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is None or entry.sim is None or entry.baking:
        return  # a running bake keeps the parameters it started with
    _push_settings(entry, obj)


def push_fields(obj):
    """Sends the object's fields (image or attributes) to its live simulation, if any
    (None clears)."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is None or entry.sim is None or entry.baking:
        return
    settings = obj.moldtex
    mesh = depsgraph = None
    if settings.fields_source == 'ATTRIBUTES':
        import bpy
        depsgraph = bpy.context.evaluated_depsgraph_get()
        try:
            mesh = export_object(obj, depsgraph, entry.uv_map)
        except MeshExportError as error:
            raise engine.EngineError(str(error), engine.ERROR_INVALID_ARGUMENT) from None
        if mesh.signature != entry.signature:
            # Not the mesh the simulation runs on: the next step rebuilds on the new
            # mesh, and reads the fields then.
            entry.dirty = True
            return
    fields = fields_from_settings(settings, entry.sim.width, entry.sim.height, mesh, None,
                                  depsgraph)
    entry.sim.set_fields(fields)
    entry.fields_crc = _crc(fields)


def _push_maps(entry, obj, quiet=False):
    """Gives the continuous simulation the maps whose settings changed since it last got
    them (entry.map_keys): a map is read again only when its own slot, the mesh or the
    size changed (setting a Lifetime or Activation map restarts the agents' clocks).
    quiet=True (every step): an error becomes entry.maps_error and the notice, and the
    simulation runs on with the maps it has; else it raises engine.EngineError."""
    sim = entry.sim
    settings = obj.moldtex
    wanted = map_sampling.keys(settings, sim.width, sim.height, entry.signature,
                               map_sampling.kinds_for_model(sim_model(entry)))
    changed = [kind for kind, key in wanted.items() if key != entry.map_keys.get(kind)]
    if not changed or (quiet and wanted == entry.maps_failed):
        return
    try:
        mesh = depsgraph = None
        if any(wanted[kind] is not None and wanted[kind][3][0] != 'IMAGE'
               for kind in changed):
            import bpy
            depsgraph = bpy.context.evaluated_depsgraph_get()
            try:
                mesh = export_object(obj, depsgraph, entry.uv_map)
            except MeshExportError as error:
                raise engine.EngineError(str(error),
                                         engine.ERROR_INVALID_ARGUMENT) from None
            if mesh.signature != entry.signature:
                # Not the mesh the simulation runs on: the next step rebuilds on the new
                # mesh, and reads the maps then.
                entry.dirty = True
                return
        values = map_sampling.sample(obj, changed, sim.width, sim.height, mesh, None,
                                     depsgraph, classes=sim.read_texel_classes(),
                                     unchosen_off=True)
        for kind in changed:
            sim.set_map(kind, values[kind])
            entry.map_keys[kind] = wanted[kind]
        entry.maps_error = ""
        entry.maps_failed = None
    except engine.EngineError as error:
        entry.maps_error = str(error)
        # Not again every step: only when the settings change again.
        entry.maps_failed = wanted
        if not quiet:
            raise
        entry.notice = str(error)


def push_maps(obj):
    """Sends the object's parameter maps to its live continuous simulation, if any (only
    the maps whose settings changed). Raises engine.EngineError in plain words."""
    entry = _registry.get(obj.name) if obj is not None else None
    if (entry is None or entry.sim is None or entry.baking
            or not map_sampling.kinds_for_model(sim_model(entry))):
        return
    _push_maps(entry, obj)


def step(entry, obj, steps):
    """Advances the simulation (with the object's current parameters) and caches stats."""
    _push_settings(entry, obj)
    _push_food(entry, obj, fresh=False)
    entry.sim.step(steps)
    entry.stats = entry.sim.get_stats()


# The live loop (moldtex.start) is paced by time, not by a count of steps: with Steps
# per Update 0 the core's own thread grows the mold between two updates (_Stepper), in
# chunks of about settings.update_time, while Blender uploads and redraws; Step's long
# runs use step_for_time.


def step_for_time(entry, obj, seconds, min_steps=1, max_steps=None):
    """Advances the simulation (with the object's current parameters) by as many steps
    as fit in `seconds` (at least min_steps, at most max_steps), in chunks sized from
    the measured time of a step; caches stats. Returns the number of steps run."""
    _push_settings(entry, obj)
    _push_food(entry, obj, fresh=False)
    began = time.perf_counter()
    done = 0
    while max_steps is None or done < max_steps:
        left = seconds - (time.perf_counter() - began)
        if done >= min_steps and (left <= 0.0 or left < 0.5 * entry.step_seconds):
            break
        if entry.step_seconds > 0.0:
            chunk = max(1, min(1000, int(left / entry.step_seconds)))
        else:
            chunk = 1  # the first step of this simulation measures its cost
        if done < min_steps:
            chunk = max(chunk, min_steps - done)
        if max_steps is not None:
            chunk = min(chunk, max_steps - done)
        start = time.perf_counter()
        entry.sim.step(chunk)
        per_step = (time.perf_counter() - start) / chunk
        entry.step_seconds = (per_step if entry.step_seconds <= 0.0
                              else 0.5 * entry.step_seconds + 0.5 * per_step)
        done += chunk
    entry.stats = entry.sim.get_stats()
    return done


def note_update(entry, steps, update_start, stepping_end):
    """Records one live update: `steps` steps stepped from update_start (perf_counter)
    to stepping_end. Keeps the overhead between updates and the steps per second of
    wall time (running means over about a second)."""
    if entry.last_update_end > 0.0:
        overhead = max(0.0, update_start - entry.last_update_end)
        wall = stepping_end - entry.last_update_end
        if wall > 0.0:
            weight = min(1.0, wall)  # about a one-second memory
            rate = steps / wall
            entry.steps_per_second = (rate if entry.steps_per_second <= 0.0 else
                                      (1.0 - weight) * entry.steps_per_second
                                      + weight * rate)
        entry.update_overhead = (overhead if entry.update_overhead <= 0.0
                                 else 0.7 * entry.update_overhead + 0.3 * overhead)
    entry.last_update_end = stepping_end


class _Stepper:
    """The simulation stepping on the core's own thread (Simulation.run_start) between
    two live updates. No Python thread: Blender 3.4 crashed now and then inside its own
    operators (bpy.ops.screen.screenshot) while a Python thread of ours waited in the
    core (docs/ARCHITECTURE.md)."""

    def __init__(self, sim):
        self.sim = sim


def start_stepper(entry, chunk_seconds, limit_seconds=5.0):
    """Lets the core step entry's simulation on its thread, in chunks of about
    chunk_seconds, until stop_stepper (the live loop calls this after each update, so
    the mold grows while Blender redraws), and at most limit_seconds should nobody come
    back for it."""
    stop_stepper(entry)
    if entry._sim is None or entry.bake is not None:
        return
    entry._sim.run_start(chunk_seconds, limit_seconds, entry.step_seconds)
    entry._stepper = _Stepper(entry._sim)


def stop_stepper(entry):
    """Stops entry's stepping and waits for its current chunk; returns the steps it ran
    (0 if none ran) and refreshes entry.stats. Re-raises what went wrong in it."""
    stepper = entry._stepper
    if stepper is None:
        return 0
    entry._stepper = None
    last = stepper.sim.run_stop()
    steps = int(last["steps"])
    entry.grown_steps += steps
    if last["step_seconds"] > 0.0:
        entry.step_seconds = last["step_seconds"]
    if steps and stepper.sim is entry._sim:
        entry.stats = stepper.sim.get_stats()
    return steps


def take_grown_steps(entry):
    """Stops entry's stepping thread; returns the steps grown by threads since the last
    call (also by ones stopped because something else needed the simulation)."""
    try:
        stop_stepper(entry)
    finally:
        steps, entry.grown_steps = entry.grown_steps, 0
    return steps


def stepper_waiting(entry):
    """True while entry's stepping runs and has not finished a chunk yet."""
    stepper = entry._stepper
    if stepper is None:
        return False
    progress = stepper.sim.run_progress()
    return progress["running"] and progress["steps"] == 0


def prepare_step(entry, obj):
    """Gives the simulation the object's current parameters, species and food (what
    step() does before stepping)."""
    _push_settings(entry, obj)
    _push_food(entry, obj, fresh=False)


def stop_pacing(entry):
    """Forgets the live loop's timing when Start pauses (the pause is no overhead)."""
    entry.last_update_end = 0.0
    entry.update_overhead = 0.0
    entry.steps_per_second = 0.0


def _snapshot_path(entry):
    import os
    import tempfile
    safe = "".join(c if c.isalnum() else "_" for c in entry.name)[:40]
    return os.path.join(tempfile.gettempdir(),
                        f"moldtex_step_{os.getpid()}_{id(entry):x}_{safe}.bin")


def save_step_snapshot(entry):
    """Keeps the simulation's state before a Step (see restore_step_snapshot)."""
    drop_step_snapshot(entry)
    path = _snapshot_path(entry)
    entry.sim.save_checkpoint(path)
    entry.step_snapshot = (entry.sim, path, None)


def note_step_end(entry):
    """Marks where the last Step ended (its snapshot is valid only from there)."""
    if entry.step_snapshot is not None and entry.step_snapshot[0] is entry.sim:
        sim, path, _end = entry.step_snapshot
        entry.step_snapshot = (sim, path, entry.sim.get_stats()["step_count"])


def restore_step_snapshot(entry):
    """Puts the simulation back to its state before the last Step, if nothing ran on
    it since (Adjust Last Operation then runs that Step with the new count). Returns
    True if it did."""
    snapshot = entry.step_snapshot
    if snapshot is None or snapshot[0] is not entry.sim or snapshot[2] is None:
        return False
    if entry.sim.get_stats()["step_count"] != snapshot[2]:
        return False
    entry.sim.load_checkpoint(snapshot[1])
    entry.stats = entry.sim.get_stats()
    return True


def drop_step_snapshot(entry):
    import os
    if entry.step_snapshot is not None:
        try:
            os.remove(entry.step_snapshot[1])
        except OSError:
            pass
    entry.step_snapshot = None


def read_pixels(entry):
    """Fills the entry's persistent pixel buffer with the pheromone (RGBA floats)."""
    if entry.pixels is None:
        entry.pixels = entry.sim.new_rgba_buffer()
    return entry.sim.read_rgba(entry.pixels)


def read_vertex_pixels(entry):
    """Fills the entry's persistent buffer with the pheromone per mesh vertex (a mesh
    without UVs, on the Intrinsic domain)."""
    needed = 4 * entry.sim.vertex_count
    if entry.vertex_pixels is None or len(entry.vertex_pixels) != needed:
        entry.vertex_pixels = array.array("f", bytes(4 * needed))
    return entry.sim.read_vertex_rgba(entry.vertex_pixels)


# Objects whose mesh Moldtex itself just changed (the vertex colours): the depsgraph
# update that follows is not an edit, and must not make the next step export the mesh
# again to compare it.
_own_geometry_writes = set()


def note_own_geometry_write(name):
    _own_geometry_writes.add(name)


def take_own_geometry_write(name):
    """True (once) when the last geometry change of `name` was Moldtex's own write."""
    if name in _own_geometry_writes:
        _own_geometry_writes.discard(name)
        return True
    return False


def uv_map_in_use(obj):
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is not None and entry.has_sim:
        return entry.uv_map
    return resolve_uv_map_name(obj, obj.moldtex.uv_map) if obj is not None else ""


def _crc(pixels):
    return None if pixels is None else zlib.crc32(memoryview(pixels).cast("B"))


def note_fields_pushed(obj, pixels):
    """Records fields that were given to obj's simulation (by the brush), so that
    poll_fields_image does not send them again."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is not None:
        entry.fields_crc = _crc(pixels)


FIELDS_POLL_INTERVAL = 1.0  # seconds between two looks at a repainted Fields image


def poll_fields_image(entry, obj):
    """Sends the Fields image to the running simulation when it was repainted (Texture
    Paint, the Image Editor, a script) since the core last got it. Looks at most once a
    FIELDS_POLL_INTERVAL, only at images Blender marks as modified and of the
    simulation's size (others are resampled, which is slow: Reset applies them).
    Returns True if new fields were sent."""
    settings = obj.moldtex
    image = settings.fields_image
    if (image is None or entry.sim is None or entry.baking or not image.is_dirty
            or settings.fields_source != 'IMAGE'
            or tuple(image.size) != (entry.sim.width, entry.sim.height)
            or image.channels != 4):
        return False
    now = time.perf_counter()
    if now - entry.fields_polled < FIELDS_POLL_INTERVAL:
        return False
    entry.fields_polled = now
    fields = image_io.read_pixels(image)
    crc = _crc(fields)
    if crc == entry.fields_crc:
        return False
    entry.sim.set_fields(fields)
    entry.fields_crc = crc
    return True
