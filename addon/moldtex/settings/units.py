# SPDX-License-Identifier: GPL-3.0-or-later
"""The pattern unit: the length every model's pattern lengths are multiples of, from
the Pattern Scale settings and the surface's area (measured once and kept). Imports the
binding, the mesh export and the registry of live simulations, nothing above them."""

import math

import bpy

from .. import engine
from ..data.mesh_export import MeshExportError, export_object, length_in_mesh_units
from ..sim import registry


def enum_or(settings, name, default):
    """settings.<name>, or default for a value this version does not know ("")."""
    try:
        return getattr(settings, name) or default  # "" for a value it does not know
    except (AttributeError, TypeError, ValueError):
        return default


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
    if enum_or(settings, "pattern_scale_mode", 'OBJECT') == 'LENGTH':
        obj = settings.id_data
        length = float(settings.pattern_length)
        return length_in_mesh_units(obj, length) if obj is not None else length
    if not area or area <= 0:
        return 0.0
    return math.sqrt(area) / REFERENCE_RESOLUTION * float(settings.pattern_scale)


def length_unit(settings, area):
    """The core's length_unit (mesh units) for settings on a surface of 3D area `area`:
    0 in texel units, or where the area is not known yet."""
    if enum_or(settings, "pattern_units", 'SURFACE') != 'SURFACE':
        return 0.0
    return pattern_unit(settings, area)


def per_unit(settings, surface_info, width, height):
    """Texels of a width × height texture per pattern unit on a surface of
    surface_info's area and UV area: the unit over the side of the mean texel,
    √(3D area / (UV area × width × height)); None where any of them is unknown."""
    area = surface_info.get("area") or 0.0
    uv_area = surface_info.get("uv_area") or 0.0
    unit = pattern_unit(settings, area)
    if not (area > 0.0 and uv_area > 0.0 and width > 0 and height > 0 and unit > 0.0):
        return None
    return unit / math.sqrt(area / (uv_area * width * height))


def known_pattern_unit(settings, area):
    """pattern_unit(settings, area), or engine.EngineError when it is not known (no
    area yet in Pattern Scale Mode Object)."""
    unit = pattern_unit(settings, area)
    if not unit > 0.0 or not math.isfinite(unit):
        raise engine.EngineError(
            "The pattern unit is not known yet (the surface's area is needed for Pattern "
            "Scale Mode Object): press Reset.", engine.ERROR_INVALID_ARGUMENT)
    return unit


def surface_area(obj, compute=True):
    """3D area (mesh units²) of obj's surface as the core measures it: the area stored
    at the last build, else the live simulation's, else (compute=True, not while
    drawing) measured from the evaluated mesh now and stored. None if unknown (no core,
    a mesh that cannot be exported). (The stored area is settings.continuous.surface_area,
    where files have kept it since the continuous model came: every model reads it.)"""
    settings = obj.moldtex
    stored = float(settings.continuous.surface_area)
    if stored > 0.0:
        return stored
    entry = registry.get(obj.name)
    if entry is not None and entry.surface_info.get("area"):
        return float(entry.surface_info["area"])
    if not compute or not engine.available():
        return None
    try:
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
