# SPDX-License-Identifier: GPL-3.0-or-later
"""Live simulations, one per object, keyed by object name.

They live here (not in bpy data: a simulation cannot be saved in a .blend), and are
freed on file load, on add-on unregister and when their object is deleted. After
undo the objects are new Python wrappers, so entries are looked up by name and marked
dirty: the next step re-reads the evaluated mesh and rebuilds the simulation if the
mesh (or its UV map) is not the one the simulation was built on.

This module talks to the core only through engine.py.
"""

from . import engine
from .mesh_export import export_object, resolve_uv_map_name

# name -> LiveSim
_registry = {}

PARAM_PROPERTIES = ("movement_speed", "turn_speed", "vision_distance", "vision_angle",
                    "evaporation_rate", "diffusion_rate", "deposit", "substeps",
                    "thread_count")
CONFIG_PROPERTIES = ("resolution", "agent_count", "seed", "uv_map")


class LiveSim:
    """One object's simulation and what it was built from."""

    def __init__(self, name):
        self.name = name
        self.sim = None           # engine.Simulation
        self.config = None        # dict the sim was created with
        self.uv_map = ""          # UV map name the sim was built on
        self.uv_map_setting = ""  # settings.uv_map at build time ("" = render UV map)
        self.signature = None     # MeshArrays.signature of the mesh it was built on
        self.surface_info = {}
        self.pixels = None        # persistent array('f') for read_rgba + foreach_set
        self.stats = {}
        self.dirty = False        # mesh may have changed (depsgraph / undo)
        self.running = False      # a moldtex.start modal drives it
        self.stop_requested = False
        self.notice = ""          # last thing worth telling the user (panel)

    def release(self):
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


def config_from_settings(settings):
    size = int(settings.resolution)
    return {"width": size, "height": size, "agent_count": int(settings.agent_count),
            "seed": int(settings.seed)}


def params_from_settings(settings):
    return {name: getattr(settings, name) for name in PARAM_PROPERTIES}


def needs_reset(obj):
    """True when config-type settings differ from the ones the live sim was built with."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is None or entry.sim is None:
        return False
    settings = obj.moldtex
    return (entry.config != config_from_settings(settings)
            or entry.uv_map_setting != settings.uv_map)


def _build(entry, obj, mesh):
    settings = obj.moldtex
    config = config_from_settings(settings)
    surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs, mesh.triangle_uvs)
    try:
        surface_info = surface.info()
        sim = engine.Simulation(surface, config, params_from_settings(settings))
    finally:
        surface.release()  # the simulation holds its own reference
    if entry.sim is not None:
        entry.sim.release()
    entry.sim = sim
    entry.config = config
    entry.uv_map = mesh.uv_map
    entry.uv_map_setting = settings.uv_map
    entry.signature = mesh.signature
    entry.surface_info = surface_info
    entry.pixels = sim.new_rgba_buffer()
    entry.dirty = False
    entry.stats = sim.get_stats()


def ensure(obj, depsgraph, rebuild=False):
    """The object's LiveSim with a simulation matching its current mesh.

    rebuild=True makes a fresh simulation from the current settings (Reset, or Start
    after a config change). A dirty entry is rebuilt only if its mesh really changed.
    Raises MeshExportError or engine.EngineError with a message for the user.
    """
    entry = _registry.get(obj.name)
    if entry is not None and entry.sim is not None and not rebuild and not entry.dirty:
        return entry
    if not engine.available():
        raise engine.EngineError(engine.status_text())
    settings = obj.moldtex
    uv_map = entry.uv_map_setting if (entry is not None and entry.sim is not None
                                      and not rebuild) else settings.uv_map
    mesh = export_object(obj, depsgraph, uv_map)
    if entry is None:
        entry = LiveSim(obj.name)
    if entry.sim is not None and not rebuild and mesh.signature == entry.signature:
        entry.dirty = False
        return entry
    restarted = entry.sim is not None and not rebuild
    if uv_map != settings.uv_map:
        # The mesh changed anyway: restart on the UV map the settings ask for now.
        mesh = export_object(obj, depsgraph, settings.uv_map)
    _build(entry, obj, mesh)
    _registry[obj.name] = entry
    entry.notice = ("The mesh changed, so the simulation restarted on the new mesh."
                    if restarted else "")
    return entry


def push_params(obj):
    """Sends the object's current parameters to its live simulation, if any."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is None or entry.sim is None:
        return
    entry.sim.set_params(params_from_settings(obj.moldtex))


def step(entry, obj, steps):
    """Advances the simulation (with the object's current parameters) and caches stats."""
    entry.sim.set_params(params_from_settings(obj.moldtex))
    entry.sim.step(steps)
    entry.stats = entry.sim.get_stats()


def read_pixels(entry):
    """Fills the entry's persistent pixel buffer with the pheromone (RGBA floats)."""
    if entry.pixels is None:
        entry.pixels = entry.sim.new_rgba_buffer()
    return entry.sim.read_rgba(entry.pixels)


def uv_map_in_use(obj):
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is not None and entry.sim is not None:
        return entry.uv_map
    return resolve_uv_map_name(obj, obj.moldtex.uv_map) if obj is not None else ""
