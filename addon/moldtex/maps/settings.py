# SPDX-License-Identifier: GPL-3.0-or-later
"""Settings of the parameter maps (obj.moldtex.maps), saved in the .blend.

One slot per map of maps/spec.py (a PropertyGroup class each, so that each has its own
defaults and tooltips): whether it is on, where its values come from (a vertex group
or mesh attribute by name, or an image in the object's UV space), and how a value v
in [0, 1] becomes what the core takes (At 0 / At 1 for the multipliers, Strength for
the stimuli). A change is sent to the live simulation at once (settings/events.py: the live session pushes it); the
values of a painted group or image are read again on Reset.
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, PointerProperty, StringProperty

from .. import engine
from ..settings import events
from .spec import MAPS, MULTIPLIER

# The numbers are what a .blend stores.
SOURCE_ITEMS = [
    ("ATTRIBUTE", "Attribute", "A vertex group, or a Float or Color attribute (per vertex "
                               "or face corner; a colour counts by its brightness) of the "
                               "mesh after its modifiers", 'GROUP_VERTEX', 0),
    ("IMAGE", "Image", "An image painted in the object's UV space (its brightness)",
     'IMAGE_DATA', 1),
]


def _maps_changed(self, context):
    obj = self.id_data
    if not isinstance(obj, bpy.types.Object):
        return
    events.changed(obj, "maps")


def _slot_class(spec):
    """The PropertyGroup of one map (its own class: its own defaults and tooltips)."""
    long = f"{spec.name} map"
    annotations = {
        "enabled": BoolProperty(
            name=spec.label, default=False,
            description=f"{long}: {spec.meaning}. Applied when changed and on Reset",
            update=_maps_changed),
        "source": EnumProperty(
            name="Source", items=SOURCE_ITEMS, default='ATTRIBUTE',
            description=f"{long} source: where its values (0 to 1) come from",
            update=_maps_changed),
        "attribute": StringProperty(
            name="Group", default="",
            description=f"{long} group: the vertex group, or Float or Color attribute, "
                        f"whose value (0 to 1, clamped) is the map. Read after modifiers; "
                        f"after painting it, press Reset",
            update=_maps_changed),
        "image": PointerProperty(
            name="Image", type=bpy.types.Image,
            description=f"{long} image: an image in the object's UV space whose "
                        f"brightness (0 to 1, clamped) is the map. After painting it, "
                        f"press Reset",
            update=_maps_changed),
    }
    if spec.role == MULTIPLIER:
        limit = engine.MAP_MULTIPLIER_MAX
        annotations["at0"] = FloatProperty(
            name="At 0", default=spec.at0, min=0.0, max=limit, soft_max=10.0,
            description=f"{long} at 0: the factor on {spec.name} where the map is 0 "
                        f"(1 = unchanged; 0 to 1000). Between 0 and 1 the factor blends "
                        f"to At 1",
            update=_maps_changed)
        annotations["at1"] = FloatProperty(
            name="At 1", default=spec.at1, min=0.0, max=limit, soft_max=10.0,
            description=f"{long} at 1: the factor on {spec.name} where the map is 1 "
                        f"(1 = unchanged, 2 = double; 0 to 1000)",
            update=_maps_changed)
    else:
        limit = engine.MAP_STIMULUS_MAX
        annotations["strength"] = FloatProperty(
            name="Strength", default=spec.strength, min=-limit, max=limit,
            soft_min=-10.0, soft_max=10.0,
            description=f"{long} strength: the stimulus where the map is 1, in units of "
                        f"U (1 = the uniform steady state); negative repels. Where the "
                        f"map is v it is Strength × v",
            update=_maps_changed)
    name = "MoldtexMap" + "".join(part.title() for part in spec.key.split("_"))
    return type(name, (bpy.types.PropertyGroup,), {
        "__annotations__": annotations, "__doc__": f"{long} of the continuous model"})


SLOT_CLASSES = tuple(_slot_class(spec) for spec in MAPS)


class MoldtexMaps(bpy.types.PropertyGroup):
    """Parameter maps and stimuli of the continuous model (layton-intrinsic-slime.md
    §3.3): one slot per map of maps/spec.py, under its key."""
    __annotations__ = {spec.key: PointerProperty(type=cls)
                       for spec, cls in zip(MAPS, SLOT_CLASSES)}


def slots(settings):
    """[(spec, slot)] of obj.moldtex's maps, in MAPS' order."""
    maps = settings.maps
    return [(spec, getattr(maps, spec.key)) for spec in MAPS]


CLASSES = SLOT_CLASSES + (MoldtexMaps,)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
