# SPDX-License-Identifier: GPL-3.0-or-later
"""An object's settings as the core's structures: config, parameters, backend, species,
food, fields and Detail, each model's own parameters through its models/ module. Reads
bpy data; keeps no state (the live session, sim/session.py, holds the simulations).
"""

import array
import math

from .. import engine, models
from ..data import image_io
from ..data.mesh_export import (MeshExportError, export_object, length_in_mesh_units,
                                read_corner_fields, world_to_mesh)
from ..settings.enums import enum_value
from ..settings.units import enum_or, length_unit, per_unit

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


def model_of(settings):
    """engine.MODEL_* the settings ask for (a value this version does not know reads as
    MoMaS, the default)."""
    return models.of_key(enum_value(settings, "model")).engine_id


def model_for(settings):
    """The models.base.Model the settings ask for."""
    return models.of_key(enum_value(settings, "model"))


def sim_model(entry):
    """engine.MODEL_* of entry's simulation (the settings may ask for another one until
    Reset), or None without a simulation."""
    if entry is None or entry.config is None:
        return None
    return entry.config.get("model", models.DEFAULT.engine_id)


def sim_model_for(entry):
    """The models.base.Model of entry's simulation, or None without one."""
    model = sim_model(entry)
    return None if model is None else models.of_engine_id(model)


DOMAINS = {"TEXTURE": engine.DOMAIN_TEXTURE, "INTRINSIC": engine.DOMAIN_INTRINSIC}


def domain_of(settings):
    """engine.DOMAIN_* the settings ask for: Intrinsic only for the models that run on
    it (MoMaS works in texels, so a MoMaS simulation keeps the texture whatever the
    setting says)."""
    domain = DOMAINS.get(enum_value(settings, "domain"), engine.DOMAIN_TEXTURE)
    return domain if domain in model_for(settings).domains else engine.DOMAIN_TEXTURE


def config_from_settings(settings, surface_info=None):
    """The core's config for settings; `surface_info` (the surface's area and UV area,
    engine.Surface.info) decides Detail: Auto, which is 1 where it is not given."""
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
    if not model_for(settings).pattern_lengths or \
            enum_or(settings, "pattern_units", 'SURFACE') != 'SURFACE':
        return 1
    choice = enum_or(settings, "detail", 'AUTO')
    if choice != 'AUTO':
        return int(choice)
    texels = per_unit(settings, surface_info or {}, size, size)
    if texels is None:
        return 1
    detail = 1
    while (detail < 4 and texels * detail < AUTO_DETAIL_TEXELS_PER_UNIT
           and 2 * detail * size <= AUTO_DETAIL_MAX_SIZE[2 * detail]):
        detail *= 2
    return detail


def texels_per_unit(entry, settings):
    """How many texels of entry's texture span one pattern unit (MoMaS in surface units):
    the unit over the side of the mean texel, √(3D area / (UV area × width × height)).
    Under about two, detail finer than a unit and a UV sphere's poles come out thin
    (README, "Units: Surface"). None where it does not apply or is not known yet."""
    model = sim_model_for(entry)
    if model is None or not model.pattern_lengths or not entry.has_sim:
        return None
    if enum_or(settings, "pattern_units", 'SURFACE') != 'SURFACE':
        return None
    return per_unit(settings, entry.surface_info,
                     entry.config.get("width", 0), entry.config.get("height", 0))


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
    params["length_unit"] = (length_unit(settings, area)
                             if models.of_engine_id(model).pattern_lengths else 0.0)
    params["hunger_rate"] = settings.hunger_rate
    obj = settings.id_data
    params["food_radius"] = (length_in_mesh_units(obj, settings.food_radius)
                             if obj is not None else settings.food_radius)
    return params


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
        fields = resample_nearest(source, source_width, source_height, channels,
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
resample_nearest = image_io.resample_nearest


def check_spawn_map(settings, fields):
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


def check_seed_radius(obj, settings, radius, mesh):
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
