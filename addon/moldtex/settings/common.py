# SPDX-License-Identifier: GPL-3.0-or-later
"""What every settings group shares: the Reset note of a description, path options
that each Blender accepts, angles shown in degrees. bpy only; registers nothing."""

import math

import bpy
from bpy.props import FloatProperty, StringProperty

RESET_NOTE = " Takes effect on Reset (or Start)"


# ---- path options -----------------------------------------------------------------
# Blender 5.0 warns about a path property holding a blend-relative "//" path unless it
# declares PATH_SUPPORTS_BLEND_RELATIVE; Blender 4.2 and 3.4 reject that option. Which
# one runs is only known when the add-on registers (this module is imported then).

def supports_blend_relative_paths():
    if bpy.app.version >= (5, 0, 0):
        return True
    if bpy.app.version < (4, 5, 0):
        return False
    # 4.5.x: try it on a throwaway class (an unknown option fails its registration).
    probe = type("MOLDTEX_PG_path_option_probe", (bpy.types.PropertyGroup,), {
        "__annotations__": {"path": StringProperty(
            subtype='DIR_PATH', options={'PATH_SUPPORTS_BLEND_RELATIVE'})}})
    try:
        bpy.utils.register_class(probe)
    except (TypeError, ValueError, RuntimeError):
        return False
    bpy.utils.unregister_class(probe)
    return True


PATH_OPTIONS = ({'PATH_SUPPORTS_BLEND_RELATIVE'} if supports_blend_relative_paths()
                else set())


# ---- angles -----------------------------------------------------------------------
# The vision angles are stored in degrees (what the core, presets, scripts and saved
# files use). The panel shows them through *_ui twins of subtype ANGLE, which Blender
# keeps in radians and displays in degrees: this is the one place that converts.

def degrees_as_radians(name):
    def getter(self):
        return math.radians(getattr(self, name))

    def setter(self, value):
        setattr(self, name, math.degrees(value))
    return getter, setter


def angle_ui(name, description, soft_min=10.0, soft_max=50.0):
    getter, setter = degrees_as_radians(name)
    return FloatProperty(
        name="Vision Angle", subtype='ANGLE', min=0.0, max=math.pi,
        soft_min=math.radians(soft_min), soft_max=math.radians(soft_max), precision=1,
        step=100, get=getter, set=setter, options=set(),
        description=description)
