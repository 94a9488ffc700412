# SPDX-License-Identifier: GPL-3.0-or-later
"""Turns the map slots of an object's settings into the core's per-texel values.

A slot's values come the way the Fields read theirs: a vertex group or attribute is
read per triangle corner from the evaluated mesh (mesh_export.read_corner_fields, four
maps in one pass) and baked over the UV layout by the core (Surface.rasterize_corners);
an image is resampled to the texture's size (image_io.resample_nearest) and its
brightness taken. A value v, clamped to [0, 1], then becomes At 0 + (At 1 - At 0) × v
(multipliers) or Strength × v (stimuli). Errors are engine.EngineError in words the
user can act on."""

import array
import math

from .. import engine, models
from ..data import image_io
from ..data.mesh_export import LUMINANCE, MeshExportError, export_object, read_corner_fields
from .spec import BY_KEY, MAPS, MULTIPLIER

WHERE = "Moldtex ▸ Maps"


def _image_key(image):
    if image is None:
        return None
    try:
        size = tuple(image.size)
    except ReferenceError:
        return None
    return (image.name_full, size, image.channels, image.filepath)


def slot_key(spec, slot):
    """What the values of one slot depend on (hashable); None for a map that is off, or
    on but with no group or image chosen yet (a live simulation runs without it while
    the user picks one; Reset, a bake and the command line refuse it: sample())."""
    if not slot.enabled:
        return None
    source = slot.source or 'ATTRIBUTE'  # "" for a value this version does not know
    where = slot.attribute if source == 'ATTRIBUTE' else _image_key(slot.image)
    if not where:
        return None
    if spec.role == MULTIPLIER:
        transform = (float(slot.at0), float(slot.at1))
    else:
        transform = (float(slot.strength),)
    return (source, where, transform)


def keys(settings, width, height, signature, kinds=None):
    """{engine.MAP_*: key} of every map (None = off), or of those in `kinds`, for a
    simulation of width × height texels on the mesh of `signature` (a new mesh or size
    needs new values)."""
    from .settings import slots
    return {spec.kind: (None if key is None else (width, height, signature, key))
            for spec, slot in slots(settings) if kinds is None or spec.kind in kinds
            for key in (slot_key(spec, slot),)}


def _describe(spec):
    return f"The {spec.label} map ({spec.name})"


def _clamped(values, low, high, scale=1.0, offset=0.0):
    """array('f') of offset + scale * clamp(v, low, high) (numpy when Blender has it: a
    4096² map takes seconds in plain Python)."""
    try:
        import numpy
    except ImportError:
        return array.array("f", [offset + scale * min(high, max(low, v)) for v in values])
    data = numpy.frombuffer(values, dtype=numpy.float32)
    result = (offset + scale * numpy.clip(data, low, high)).astype(numpy.float32)
    return array.array("f", result.tobytes())


def _transform(spec, slot, values):
    """Map values (clamped to [0, 1]) -> the core's values."""
    if spec.role == MULTIPLIER:
        at0 = min(engine.MAP_MULTIPLIER_MAX, max(0.0, float(slot.at0)))
        at1 = min(engine.MAP_MULTIPLIER_MAX, max(0.0, float(slot.at1)))
        result = _clamped(values, 0.0, 1.0, at1 - at0, at0)
        # (float32 rounding of at0 + (at1 - at0) * v stays within the core's range)
        return _clamped(result, 0.0, engine.MAP_MULTIPLIER_MAX)
    strength = min(engine.MAP_STIMULUS_MAX,
                   max(-engine.MAP_STIMULUS_MAX, float(slot.strength)))
    return _clamped(values, 0.0, 1.0, strength)


def _image_values(spec, slot, width, height):
    image = slot.image
    if image is None:
        raise engine.EngineError(
            f"{_describe(spec)} is on but has no image: pick one, or choose Attribute "
            f"as its source, or turn it off ({WHERE}).", engine.ERROR_INVALID_ARGUMENT)
    source_width, source_height = image.size
    channels = image.channels
    if source_width == 0 or source_height == 0 or channels == 0:
        raise engine.EngineError(
            f"{_describe(spec)}: the image '{image.name}' has no pixels (is its file "
            f"missing?): pick another image, or turn the map off ({WHERE}).",
            engine.ERROR_INVALID_ARGUMENT)
    pixels = image_io.read_pixels(image)
    if channels != 4 or (source_width, source_height) != (width, height):
        pixels = image_io.resample_nearest(pixels, source_width, source_height, channels,
                                           width, height)
    if channels >= 3:
        r, g, b = LUMINANCE
        values = array.array("f", [r * cr + g * cg + b * cb for cr, cg, cb
                                   in zip(pixels[0::4], pixels[1::4], pixels[2::4])])
    else:
        values = pixels[0::4]
    if not all(map(math.isfinite, values)):
        raise engine.EngineError(
            f"{_describe(spec)}: the image '{image.name}' holds values that are not "
            f"numbers: repaint it or pick another image ({WHERE}).",
            engine.ERROR_INVALID_ARGUMENT)
    return values


def _attribute_values(obj, chosen, width, height, mesh, surface, depsgraph):
    """{kind: values} of the (spec, slot) pairs with an attribute source."""
    for spec, slot in chosen:
        if not slot.attribute:
            raise engine.EngineError(
                f"{_describe(spec)} is on but names no vertex group or attribute: pick "
                f"one, or turn the map off ({WHERE}).", engine.ERROR_INVALID_ARGUMENT)
    if depsgraph is None:
        import bpy
        depsgraph = bpy.context.evaluated_depsgraph_get()
    result = {}
    own_surface = False
    try:
        if mesh is None:
            mesh = export_object(obj, depsgraph, obj.moldtex.uv_map)
        if surface is None:
            surface = engine.Surface(mesh.positions, mesh.triangles, mesh.uvs,
                                     mesh.triangle_uvs)
            own_surface = True
        for start in range(0, len(chosen), 4):  # four maps per pass (R, G, B, A)
            group = chosen[start:start + 4]
            names = [slot.attribute for _spec, slot in group]
            labels = [f"{spec.label} map" for spec, _slot in group]
            names += [""] * (4 - len(group))
            labels += [""] * (4 - len(group))
            corners = read_corner_fields(obj, depsgraph, mesh, names, labels, where=WHERE)
            rgba = surface.rasterize_corners(width, height, corners)
            for channel, (spec, _slot) in enumerate(group):
                result[spec.kind] = rgba[channel::4]
    except MeshExportError as error:
        raise engine.EngineError(str(error), engine.ERROR_INVALID_ARGUMENT) from None
    finally:
        if own_surface:
            surface.release()
    return result


def _check_spawn(spec, slot, values, classes):
    """The core refuses a spawn map that is 0 on every texel: say why in plain words."""
    inside = (values if classes is None else
              [v for v, c in zip(values, classes) if c == engine.TEXEL_INSIDE])
    if any(v > 0.0 for v in inside):
        return
    if slot.source == 'IMAGE' and slot.image is not None:
        what = f"the image '{slot.image.name}' is black on the model"
    elif slot.source != 'IMAGE':
        what = f"'{slot.attribute}' is 0 everywhere"
    else:
        what = "it is 0 everywhere"
    raise engine.EngineError(
        f"{_describe(spec)} is 0 everywhere, so agents could be reborn nowhere: {what} "
        f"and At 0 is 0. Paint some weight into it, raise At 0, or turn the map off "
        f"({WHERE}).", engine.ERROR_INVALID_ARGUMENT)


def sample(obj, kinds, width, height, mesh=None, surface=None, depsgraph=None,
           classes=None, unchosen_off=False):
    """{kind: array('f') of width*height core values, or None (off)} for the maps
    `kinds` (engine.MAP_*) of obj's settings. mesh / surface / depsgraph: as
    live.fields_from_settings takes them (made here when needed). classes: the
    simulation's texel classes, if known (the spawn check then looks inside only).
    A map that is on with no group or image chosen raises, or with unchosen_off (a
    live simulation while the user picks one) counts as off."""
    from .settings import slots
    chosen = [(spec, slot) for spec, slot in slots(obj.moldtex) if spec.kind in kinds]
    result = {spec.kind: None for spec, _slot in chosen}
    on = [(spec, slot) for spec, slot in chosen if slot.enabled
          and not (unchosen_off and slot_key(spec, slot) is None)]
    attribute = [(spec, slot) for spec, slot in on if slot.source != 'IMAGE']
    raw = {}
    if attribute:
        raw.update(_attribute_values(obj, attribute, width, height, mesh, surface,
                                     depsgraph))
    for spec, slot in on:
        if slot.source == 'IMAGE':
            raw[spec.kind] = _image_values(spec, slot, width, height)
    for spec, slot in on:
        values = _transform(spec, slot, raw[spec.kind])
        if spec.kind == engine.MAP_SPAWN:
            _check_spawn(spec, slot, values, classes)
        result[spec.kind] = values
    return result


def all_kinds():
    return [spec.kind for spec in MAPS]


def kinds_for_model(model):
    """engine.MAP_* of the maps a simulation of engine.MODEL_* `model` reads (its
    Model.map_keys; none for MoMaS)."""
    return [BY_KEY[key].kind for key in models.of_engine_id(model).map_keys]
