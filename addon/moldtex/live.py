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
CONFIG_PROPERTIES = ("resolution", "agent_count", "seed", "uv_map", "backend_type",
                     "opencl_platform", "opencl_device", "opencl_device_name",
                     "opencl_platform_name")


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
        self.warning = ""         # same, but reported as a warning
        self.backend_name = ""    # moldtex_sim_get_backend_name of the running sim
        self.backend_note = ""    # why the sim does not run on the chosen backend
        # Bake (bake.py): the core's bake worker owns self.sim while it runs.
        self.bake = None          # engine.Bake while a bake runs, else None
        self.bake_plan = None     # bake.BakePlan of the running or last bake
        self.bake_progress = {}   # last engine.Bake.progress() (the panel shows it)
        self.bake_cancel_requested = False  # the modal bake cancels on its next tick
        self.bake_summary = ""    # one line about the last bake, for the panel

    @property
    def baking(self):
        return self.bake is not None

    def release(self):
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


def config_from_settings(settings):
    size = int(settings.resolution)
    config = {"width": size, "height": size, "agent_count": int(settings.agent_count),
              "seed": int(settings.seed)}
    config.update(backend_from_settings(settings)[0])
    return config


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
    note = backend_note(settings)
    surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs, mesh.triangle_uvs)
    try:
        surface_info = surface.info()
        sim = engine.Simulation(surface, config, params_from_settings(settings))
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
    entry.backend_name = sim.backend_name()
    entry.backend_note = note
    entry.warning = note


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
    if entry is None or entry.sim is None or entry.baking:
        return  # a running bake keeps the parameters it started with
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
