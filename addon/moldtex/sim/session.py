# SPDX-License-Identifier: GPL-3.0-or-later
"""Live simulations, one per object, keyed by object name.

They live here (not in bpy data: a simulation cannot be saved in a .blend), and are
freed on file load, on add-on unregister and when their object is deleted. After
undo the objects are new Python wrappers, so entries are looked up by name and marked
dirty: the next step re-reads the evaluated mesh and rebuilds the simulation if the
mesh (or its UV map) is not the one the simulation was built on.

This module talks to the core only through the binding (engine/).
"""

import array
import time
import zlib

from .. import engine, models
from ..data import image_io, vertex_colours
from ..data.mesh_export import (MeshExportError, export_object, length_in_mesh_units,
                                no_uv_map_message, resolve_uv_map_name)
from ..maps import sampling as map_sampling
from ..settings import events
from ..settings.enums import repair_enums
from ..settings.properties import ensure_species
from . import registry
from .convert import (CENTERED_SHAPES, backend_note, check_seed_radius, check_spawn_map,
                      config_from_settings, detail_for, fields_from_settings,
                      food_from_settings, params_from_settings, seed_center, sim_model,
                      sim_model_for, model_for, species_params_from_settings)

# name -> LiveSim (sim/registry.py, where the settings read them)
_registry = registry._entries

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
        self.reset_key = None     # the model's reset_key(settings) at build time
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
        # Bake (bake/sequence.py): the core's bake worker owns self.sim while it runs.
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
        # last given to the continuous model's simulation (models/continuous.push_bias).
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


get = registry.get
names = registry.names


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


def _push_species(entry, settings):
    # Only the species the simulation has: a new Species count waits for Reset (a
    # parameter change meanwhile is no error).
    config = getattr(entry, "config", None)
    count = config.get("species_count", 1) if config else MAX_SPECIES_PUSHED
    for index, params in species_params_from_settings(settings):
        if index < count:
            entry.sim.set_species_params(index, params)


MAX_SPECIES_PUSHED = engine.MAX_SPECIES


def needs_reset(obj):
    """True when config-type settings differ from the ones the live sim was built with."""
    entry = _registry.get(obj.name) if obj is not None else None
    if entry is None or not entry.has_sim:  # (drawn by the panel: never waits)
        return False
    settings = obj.moldtex
    return (entry.config != config_from_settings(settings, entry.surface_info)
            or entry.uv_map_setting != settings.uv_map
            or entry.reset_key != model_for(settings).reset_key(settings))


def _build(entry, obj, mesh, depsgraph=None):
    settings = obj.moldtex
    # unknown enum values -> defaults
    repaired = " ".join(repair_enums(settings) + [
        note for group in models.own_settings(settings) for note in repair_enums(group)])
    config = config_from_settings(settings)
    device_note = backend_note(settings)
    note = " ".join(filter(None, (repaired, device_note)))
    if len(settings.species) < settings.species_count:
        ensure_species(settings)
    if mesh.uvs is None and config.get("domain") != engine.DOMAIN_INTRINSIC:
        raise MeshExportError(no_uv_map_message(obj.name, mesh.flat_uv_map))
    create_config = dict(config)
    create_config["seed_radius"] = length_in_mesh_units(obj, config["seed_radius"])
    create_config["intrinsic_bound"] = length_in_mesh_units(obj, config["intrinsic_bound"])
    check_seed_radius(obj, settings, create_config["seed_radius"], mesh)
    surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs, mesh.triangle_uvs)
    try:
        if settings.seed_shape in CENTERED_SHAPES:
            import bpy
            create_config["seed_center"] = seed_center(obj, surface,
                                                       bpy.context.scene.cursor.location)
        fields = fields_from_settings(settings, config["width"], config["height"], mesh,
                                      surface, depsgraph)
        check_spawn_map(settings, fields)
        surface_info = surface.info()
        area = surface_info.get("area")
        # Detail: Auto follows the surface's texels per pattern unit.
        config["detail"] = create_config["detail"] = detail_for(settings, config["width"],
                                                                surface_info)
        model = models.of_engine_id(config["model"])
        model_arguments = model.create_arguments(settings, area)
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
                                fields, **model_arguments)
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
    try:
        stored = model.after_build(entry, obj, sim, surface_info, depsgraph)
        for kind, values in map_values.items():
            if values is not None:
                sim.set_map(kind, values)
        if model.has_agents:
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
    entry.bias_key = None
    for name, value in stored.items():
        setattr(entry, name, value)
    entry.map_keys = map_keys
    entry.maps_error = ""
    entry.maps_failed = None
    entry.fields_crc = _crc(fields)
    entry.create_config = create_config
    entry.config = config
    entry.uv_map = mesh.uv_map
    entry.uv_map_setting = settings.uv_map
    entry.reset_key = model.reset_key(settings)
    entry.signature = mesh.signature
    entry.surface_info = surface_info
    entry.pixels = sim.new_rgba_buffer()
    # A mesh without UVs shows its pattern per vertex (data/vertex_colours.py).
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
        sim_model_for(entry).same_mesh(entry, obj, depsgraph)
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
    model = sim_model_for(entry)
    entry.sim.set_params(params_from_settings(settings, area, model.engine_id))
    model.push_params(entry.sim, settings, area)
    model.after_push(entry, obj)
    if map_sampling.kinds_for_model(model.engine_id):
        _push_maps(entry, obj, quiet=True)
    if not model.has_agents:
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


# ---- what a settings change asks of the session (settings/events.py) -------------------

def _reported(push):
    # A refusal of the core becomes the panel's notice instead of an exception inside
    # Blender's property update.
    def listener(obj):
        try:
            push(obj)
        except engine.EngineError as error:
            entry = registry.get(obj.name)
            if entry is not None:
                entry.notice = str(error)
            print(f"Moldtex: {error}")
    return listener


_LISTENERS = (("params", _reported(push_params)), ("fields", _reported(push_fields)),
              ("maps", _reported(push_maps)))


def register():
    for topic, listener in _LISTENERS:
        events.listen(topic, listener)


def unregister():
    for topic, listener in _LISTENERS:
        events.forget(topic, listener)
