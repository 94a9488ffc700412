# SPDX-License-Identifier: GPL-3.0-or-later
"""A simulation of the core (Simulation): create, step, parameters of every model, maps,
fields, food, brushes, pixels, checkpoints."""

import array
import ctypes

from . import library, structs
from .library import (Handle, _Sim, _brush, _buffer_address, _check, _decode, _fill, _path_bytes, _require,
                      _struct_to_dict)
from .structs import *  # noqa: F401,F403  (the header's constants and structs)


class Simulation(Handle):
    """A simulation on a surface's UV layout (moldtex_sim): MoMaS, or the continuous
    model when config["model"] is MODEL_CONTINUOUS."""
    _release = "moldtex_sim_release"
    _what = "simulation"

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
        reaction: dict with any of REACTION_FIELDS for a reaction-diffusion simulation
        (moldtex_reaction_params), set right after create, then reset (seeds from them).
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

    def set_params(self, params):
        """Changes parameters between steps; fields not given keep their current value."""
        p = SimParams()
        library._lib.moldtex_sim_params_init(ctypes.byref(p))
        _check(library._lib.moldtex_sim_get_params(self.handle, ctypes.byref(p)), "Reading parameters")
        _fill(p, params, PARAM_FIELDS, "params")
        _check(library._lib.moldtex_sim_set_params(self.handle, ctypes.byref(p)), "Setting parameters")

    def set_continuous_params(self, params):
        """Continuous model: changes its parameters between steps (a dict with any of
        CONTINUOUS_FIELDS; lengths in mesh units, sensor_angle in degrees); fields not
        given keep their current value."""
        p = ContinuousParams()
        library._lib.moldtex_continuous_params_init(ctypes.byref(p))
        _check(library._lib.moldtex_sim_get_continuous_params(self.handle, ctypes.byref(p)),
               "Reading the continuous model's parameters")
        _fill(p, params, CONTINUOUS_FIELDS, "continuous params")
        _check(library._lib.moldtex_sim_set_continuous_params(self.handle, ctypes.byref(p)),
               "Setting the continuous model's parameters")

    def set_reaction_params(self, params):
        """The reaction-diffusion model: a dict with any of REACTION_FIELDS (diffusion in mesh
        units^2 per second); fields not given keep their current value. The seed fields
        apply at the next reset."""
        p = ReactionParams()
        library._lib.moldtex_reaction_params_init(ctypes.byref(p))
        _check(library._lib.moldtex_sim_get_reaction_params(self.handle, ctypes.byref(p)),
               "Reading the reaction-diffusion parameters")
        _fill(p, params, REACTION_FIELDS, "reaction params")
        _check(library._lib.moldtex_sim_set_reaction_params(self.handle, ctypes.byref(p)),
               "Setting the reaction-diffusion parameters")

    def get_reaction_params(self):
        p = ReactionParams()
        library._lib.moldtex_reaction_params_init(ctypes.byref(p))
        _check(library._lib.moldtex_sim_get_reaction_params(self.handle, ctypes.byref(p)),
               "Reading the reaction-diffusion parameters")
        return _struct_to_dict(p, REACTION_FIELDS)

    def get_continuous_params(self):
        p = ContinuousParams()
        library._lib.moldtex_continuous_params_init(ctypes.byref(p))
        _check(library._lib.moldtex_sim_get_continuous_params(self.handle, ctypes.byref(p)),
               "Reading the continuous model's parameters")
        return _struct_to_dict(p, CONTINUOUS_FIELDS)

    def get_params(self):
        p = SimParams()
        library._lib.moldtex_sim_params_init(ctypes.byref(p))
        _check(library._lib.moldtex_sim_get_params(self.handle, ctypes.byref(p)), "Reading parameters")
        return _struct_to_dict(p, PARAM_FIELDS)

    def set_species_params(self, index, params):
        """Behaviour of species `index`: a dict with any of SPECIES_FIELDS (attraction
        as up to 4 floats); fields not given keep their current value."""
        p = SpeciesParams()
        library._lib.moldtex_species_params_init(ctypes.byref(p), int(index))
        _check(library._lib.moldtex_sim_get_species_params(self.handle, int(index), ctypes.byref(p)),
               "Reading species parameters")
        params = dict(params)
        attraction = params.pop("attraction", None)
        _fill(p, params, SPECIES_FIELDS, "species")
        if attraction is not None:
            for k, value in enumerate(list(attraction)[:4]):
                p.attraction[k] = float(value)
        _check(library._lib.moldtex_sim_set_species_params(self.handle, int(index), ctypes.byref(p)),
               "Setting species parameters")

    def get_species_params(self, index):
        p = SpeciesParams()
        library._lib.moldtex_species_params_init(ctypes.byref(p), int(index))
        _check(library._lib.moldtex_sim_get_species_params(self.handle, int(index), ctypes.byref(p)),
               "Reading species parameters")
        result = _struct_to_dict(p, SPECIES_FIELDS)
        result["attraction"] = tuple(p.attraction)
        return result

    def set_fields(self, rgba):
        """Static fields: width*height*4 floats (array('f') or numpy float32) in
        read_rgba's order, R spawn weight, G obstacle (> 0.5), B attractor; None clears."""
        if rgba is None:
            _check(library._lib.moldtex_sim_set_fields(self.handle, None, 0), "Setting the fields")
            return
        address, count = _buffer_address(rgba, ("f",), writable=False)
        _check(library._lib.moldtex_sim_set_fields(self.handle, ctypes.c_void_p(address), count),
               "Setting the fields")

    def set_bias(self, vectors):
        """Continuous model's directional bias field: triangle_count*3 floats
        (array('f') or numpy float32), one 3D vector per triangle in the mesh's own
        coordinates and triangle order, projected onto its triangle; its length weights
        bias_strength there (1 = full). None clears it (no bias)."""
        if vectors is None:
            _check(library._lib.moldtex_sim_set_bias(self.handle, None, 0), "Setting the bias")
            return
        address, count = _buffer_address(vectors, ("f",), writable=False)
        expected = 3 * self.triangle_count
        if count != expected:
            raise EngineError(f"The bias needs 3 floats per triangle ({expected} for "
                              f"{self.triangle_count} triangles), got {count}.",
                              ERROR_INVALID_ARGUMENT)
        _check(library._lib.moldtex_sim_set_bias(self.handle, ctypes.c_void_p(address), count),
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
            _check(library._lib.moldtex_sim_set_map(self.handle, kind, None, 0), "Setting a map")
            return
        address, count = _buffer_address(values, ("f",), writable=False)
        expected = self.width * self.height
        if count != expected:
            raise EngineError(f"A map needs one float per texel ({expected} for "
                              f"{self.width} x {self.height}), got {count}.",
                              ERROR_INVALID_ARGUMENT)
        _check(library._lib.moldtex_sim_set_map(self.handle, kind, ctypes.c_void_p(address), count),
               "Setting a map")

    def get_map(self, kind):
        """Map `kind` (MAP_*) as array('f') of width*height floats, or None when unset."""
        values = array.array("f", bytes(4 * self.width * self.height))
        address, count = _buffer_address(values, ("f",), writable=True)
        is_set = ctypes.c_uint32(0)
        _check(library._lib.moldtex_sim_get_map(self.handle, int(kind), ctypes.c_void_p(address),
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
        _check(library._lib.moldtex_sim_set_food(self.handle, items, count), "Setting food sources")

    def get_food(self):
        """Current food sources as (position, strength, remaining amount) tuples."""
        items = (FoodSource * MAX_FOOD_SOURCES)()
        count = ctypes.c_uint32(0)
        _check(library._lib.moldtex_sim_get_food(self.handle, items, MAX_FOOD_SOURCES,
                                         ctypes.byref(count)), "Reading food sources")
        return [(tuple(item.position), item.strength, item.amount)
                for item in items[:min(count.value, MAX_FOOD_SOURCES)]]

    def get_config(self):
        c = SimConfig()
        library._lib.moldtex_sim_config_init(ctypes.byref(c))
        _check(library._lib.moldtex_sim_get_config(self.handle, ctypes.byref(c)), "Reading config")
        return _struct_to_dict(c, CONFIG_FIELDS)

    def backend_name(self):
        """What the simulation runs on, e.g. "CPU (2 threads)" or "OpenCL: <device>
        (<platform>)"; for Auto followed by why OpenCL was not used."""
        capacity = 1024
        while True:
            buffer = ctypes.create_string_buffer(capacity)
            _check(library._lib.moldtex_sim_get_backend_name(self.handle, buffer, capacity),
                   "Reading the backend name")
            if len(buffer.value) < capacity - 1 or capacity >= 1 << 16:
                return _decode(buffer.value)
            capacity *= 4

    def reset(self):
        _check(library._lib.moldtex_sim_reset(self.handle), "Resetting the simulation")

    def step(self, steps=1):
        # One core call runs at most structs.MAX_STEPS_PER_CALL steps: longer runs go in chunks.
        steps = int(steps)
        if steps < 0:
            raise ValueError(f"Steps must be 0 or more (got {steps})")
        while True:
            chunk = min(steps, structs.MAX_STEPS_PER_CALL)
            _check(library._lib.moldtex_sim_step(self.handle, chunk), "Stepping the simulation")
            steps -= chunk
            if steps <= 0:
                return

    def run_start(self, chunk_seconds, limit_seconds=5.0, step_seconds_hint=0.0):
        """Steps on the core's own thread (moldtex_sim_run_start) in chunks of about
        chunk_seconds until run_stop, or by itself after limit_seconds; meanwhile every
        other call raises EngineError (ERROR_BUSY). No Python runs on that thread."""
        _check(library._lib.moldtex_sim_run_start(self.handle, float(chunk_seconds),
                                          float(limit_seconds), float(step_seconds_hint)),
               "Starting the live stepping")

    def run_progress(self):
        """dict: running (bool), steps (since run_start), step_seconds (mean cost of a
        step). Never blocks."""
        p = RunProgress()
        library._lib.moldtex_run_progress_init(ctypes.byref(p))
        _check(library._lib.moldtex_sim_run_get_progress(self.handle, ctypes.byref(p)),
               "Reading the live stepping's progress")
        return {"running": bool(p.running), "steps": p.steps, "step_seconds": p.step_seconds}

    def run_stop(self):
        """Stops the live stepping after its current chunk and waits (without holding
        Python's lock); returns its last run_progress() (steps 0 if none ran). Raises
        EngineError with the error a step raised, if one did."""
        p = RunProgress()
        library._lib.moldtex_run_progress_init(ctypes.byref(p))
        _check(library._lib.moldtex_sim_run_stop(self.handle, ctypes.byref(p)), "The live stepping")
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
        _check(library._lib.moldtex_sim_read_rgba(self.handle, ctypes.c_void_p(address), count),
               "Reading the pheromone")
        return buffer

    def read_vertex_rgba(self, buffer=None):
        """The pheromone at each mesh vertex, encoded as read_rgba encodes a texel
        (4 floats a vertex; intrinsic domain only), into `buffer` (array('f'), >=
        vertex_count*4 floats), which it returns."""
        if buffer is None:
            buffer = array.array("f", bytes(16 * self.vertex_count))
        address, count = _buffer_address(buffer, ("f",), writable=True)
        _check(library._lib.moldtex_sim_read_vertex_rgba(self.handle, ctypes.c_void_p(address), count),
               "Reading the pheromone at the mesh vertices")
        return buffer

    def read_texel_classes(self, buffer=None):
        """Texel classes (TEXEL_OUTSIDE/INSIDE/GUTTER) as array('B'), pheromone order."""
        if buffer is None:
            buffer = array.array("B", bytes(self.width * self.height))
        address, count = _buffer_address(buffer, ("B",), writable=True)
        _check(library._lib.moldtex_sim_read_texel_classes(self.handle, ctypes.c_void_p(address),
                                                   count),
               "Reading texel classes")
        return buffer

    def read_agents(self, capacity):
        """Up to `capacity` agent positions as (triangle, (b0, b1, b2)) tuples."""
        points = (SurfacePoint * capacity)()
        _check(library._lib.moldtex_sim_read_agents(self.handle, points, capacity), "Reading agents")
        return [(pt.triangle, tuple(pt.bary)) for pt in points]

    def get_stats(self):
        s = SimStats()
        library._lib.moldtex_sim_stats_init(ctypes.byref(s))
        _check(library._lib.moldtex_sim_get_stats(self.handle, ctypes.byref(s)), "Reading statistics")
        return _struct_to_dict(s, STATS_FIELDS)

    def domain_info(self):
        """The domain (DOMAIN_*) and its size: cell_count (island texels or intrinsic
        vertices), face_count, bound (mesh units), build_seconds, insertions,
        skipped_faces, from_cache (1: a recent build of the same mesh was reused)."""
        info = DomainInfo()
        library._lib.moldtex_domain_info_init(ctypes.byref(info))
        _check(library._lib.moldtex_sim_get_domain_info(self.handle, ctypes.byref(info)),
               "Reading the domain")
        return _struct_to_dict(info, DOMAIN_INFO_FIELDS)

    def write_image(self, path, image_format=IMAGE_EXR_HALF):
        """Writes the pheromone to `path` (IMAGE_* format; one channel "Y" per species,
        written as path.partial and renamed when whole)."""
        _check(library._lib.moldtex_sim_write_image(self.handle, _path_bytes(path), int(image_format)),
               "Writing the image")

    def save_checkpoint(self, path):
        """Saves the whole state (agents, pheromone, step count, parameters) atomically."""
        _check(library._lib.moldtex_sim_save_checkpoint(self.handle, _path_bytes(path)),
               "Saving the checkpoint")

    def load_checkpoint(self, path):
        """Restores a checkpoint made by a simulation of the same mesh and config."""
        _check(library._lib.moldtex_sim_load_checkpoint(self.handle, _path_bytes(path)),
               "Loading the checkpoint")

    def add_agents(self, brush, count, batch):
        """Slime brush: adds `count` agents of species brush["channel"] uniformly over the
        brush's geodesic disk, tagged `batch` (1..65535, e.g. one per stroke) for
        undo_agents. Deterministic in (seed, batch, agents of the batch so far)."""
        b = _brush(brush)
        _check(library._lib.moldtex_sim_add_agents(self.handle, ctypes.byref(b), int(count), int(batch)),
               "Adding agents")

    def erase_agents(self, brush, batch):
        """Erase-slime brush: removes the agents in the disk (each with probability
        strength * falloff weight) and keeps them under `batch`; returns how many."""
        b = _brush(brush)
        removed = ctypes.c_uint32(0)
        _check(library._lib.moldtex_sim_erase_agents(self.handle, ctypes.byref(b), int(batch),
                                             ctypes.byref(removed)),
               "Erasing agents")
        return removed.value

    def undo_agents(self, batch):
        """Undoes a stroke: removes the agents added with `batch`, restores those erased
        with it."""
        _check(library._lib.moldtex_sim_undo_agents(self.handle, int(batch)), "Undoing a brush stroke")
