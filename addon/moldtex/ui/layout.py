# SPDX-License-Identifier: GPL-3.0-or-later
"""How the Moldtex panels lay out what they draw: short labels, Blender's property-split
columns, lines wrapped to the sidebar's width, the sub-panel base, the pattern scale.
Registers nothing; the panels (ui/panels.py, and a model's own in models/) use it."""

import bpy

from ..data.mesh_export import MeshExportError, length_in_scene_units
from ..settings import units
from ..settings.enums import enum_value


# Short labels shown in the panel: property identifier -> label (a model's own settings
# add theirs: Model.labels, models/).
LABELS = {
    "resolution": "Texture",
    "intrinsic_size": "Tri. Size",
    "pattern_scale_mode": "Scale",
    "pattern_scale": "Factor",
    "pattern_length": "Length",
    "agent_count": "Agents",
    "steps_per_update": "Steps",
    "update_time": "Update",
    "movement_speed": "Speed",
    "turn_speed": "Turning",
    "vision_distance": "Sight",
    "vision_angle_ui": "Angle",
    "sensor_size": "Sensor",
    "evaporation_rate": "Decay",
    "diffusion_rate": "Diffusion",
    "thread_count": "Threads",
    "species_count": "Species",
    "fields_image": "Image",
    "food_collection": "Empties",
    "hunger_rate": "Hunger",
    "food_radius": "Radius",
    "bake_frame_start": "Start",
    "bake_frame_end": "End",
    "bake_steps_per_frame": "Per Frame",
    "bake_directory": "Folder",
    "bake_prefix": "Prefix",
    # the Map Tools panel (Object.moldtex_map_tools)
    "time_factor": "Smooth",
    "gradient_normalize": "Unit",
    # ("Direction X" is cut at the default width)
    # the Brush panel (scene settings)
    "target": "Paint",
    "agents_per_dab": "Agents",
    "food_strength": "Strength",
    "food_amount": "Amount",
}


def prop(layout, data, name, labels=LABELS, **kwargs):
    """layout.prop with the panel's short label (from `labels`)."""
    if name in labels and "text" not in kwargs:
        kwargs["text"] = labels[name]
    layout.prop(data, name, **kwargs)


def split(layout):
    """A column in Blender's property-split layout (labels left, values right)."""
    column = layout.column(align=True)
    column.use_property_split = True
    column.use_property_decorate = False
    return column


# Characters a line of the sidebar shows at its default width next to an icon, inside
# a box (seen in Blender 3.4; blender_tests/panel_fit.py checks every line drawn);
# longer lines would be cut with an ellipsis.
WIDTH = 21
# Below this many texels per pattern unit the panel suggests a higher Resolution (the
# default, 512² at Pattern Scale 1 on a layout that fills the texture, gives 1).
COARSE_TEXELS_PER_UNIT = 0.95


def char_width(ch):
    """A character's width in WIDTH's units: capitals and m, w are drawn wider than
    the lower-case letters a line's count is measured in."""
    return 1.3 if ch.isupper() or ch in "mw" else 1.0


def wrap(text, width=WIDTH):
    """Lines of at most `width` units (char_width), broken between words; a word
    longer than a line (a driver's CL_PLATFORM_NOT_FOUND_KHR) in pieces. Counting
    characters alone cut such capitals at the sidebar's edge."""
    lines, line, used = [], "", 0.0
    for word in text.split():
        size = sum(char_width(ch) for ch in word)
        if line and used + 1.0 + size <= width:
            line, used = f"{line} {word}", used + 1.0 + size
            continue
        if line:
            lines.append(line)
        line, used = "", 0.0
        for ch in word:  # (most words fit whole)
            if line and used + char_width(ch) > width:
                lines.append(line)
                line, used = "", 0.0
            line, used = line + ch, used + char_width(ch)
    if line:
        lines.append(line)
    return lines


def wrapped(layout, text, icon='NONE', width=WIDTH):
    lines = wrap(text, width) or [""]
    column = layout.column(align=True)
    for index, line in enumerate(lines):
        column.label(text=line, icon=icon if index == 0 else 'BLANK1')


def mesh_object(context):
    obj = context.active_object
    return obj if obj is not None and obj.type == 'MESH' else None


class SubPanel:
    """A sub-panel of the Moldtex tab (MOLDTEX_PT_main), shown for a mesh object."""
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Moldtex"
    bl_parent_id = "MOLDTEX_PT_main"

    @classmethod
    def poll(cls, context):
        return mesh_object(context) is not None


class ModelPanel(SubPanel):
    """A sub-panel shown while the active mesh object's settings ask for the model whose
    Model.key is model_key (a model's own panels, models/<name>.py)."""
    model_key = ""

    @classmethod
    def poll(cls, context):
        obj = mesh_object(context)
        return obj is not None and enum_value(obj.moldtex, "model") == cls.model_key


def scene_length(context, value):
    """A length in scene units as Blender writes it (e.g. "5.86 mm")."""
    scene = getattr(context, "scene", None)
    unit_settings = scene.unit_settings if scene is not None else None
    if unit_settings is None or unit_settings.system == 'NONE':
        return f"{value:.4g}"
    try:
        return bpy.utils.units.to_string(unit_settings.system, 'LENGTH',
                                         value * unit_settings.scale_length, precision=3)
    except (AttributeError, TypeError, ValueError):
        return f"{value:.4g}"


def pattern_unit_text(context, obj):
    """ "Unit: 5.86 mm" (the pattern unit in the scene), or how to learn it."""
    settings = obj.moldtex
    area = units.surface_area(obj, compute=False)
    unit = units.pattern_unit(settings, area)
    if unit <= 0.0:
        return "Unit: known after Reset (it needs the surface's area)"
    try:
        world = length_in_scene_units(obj, unit)
    except MeshExportError:
        return ""
    return f"Unit: {scene_length(context, world)} on the object"


def draw_pattern_scale(layout, settings, active=True):
    column = layout.column(align=True)
    column.active = active
    prop(column.row(align=True), settings, "pattern_scale_mode", expand=True)
    if settings.pattern_scale_mode == 'LENGTH':
        prop(column, settings, "pattern_length")
    else:
        prop(column, settings, "pattern_scale")


def draw_pattern_unit(layout, context, obj, what):
    """The pattern scale settings, then the unit on the object and what is in it."""
    draw_pattern_scale(split(layout), obj.moldtex)
    text = pattern_unit_text(context, obj)
    if text:
        wrapped(layout, f"{text} ({what})", icon='DRIVER_DISTANCE')
