# SPDX-License-Identifier: GPL-3.0-or-later
"""Parameter maps and stimuli of the continuous model (layton-intrinsic-slime.md §3.3,
issue 12): per-texel multipliers of its parameters (a Lifetime of 0 = a sink, Spawn =
where agents are reborn) and the read / write stimuli, painted as vertex groups,
attributes or images.

  spec.py      the maps: keys, core kinds, labels, defaults (no bpy)
  settings.py  obj.moldtex.maps: one slot PropertyGroup per map (saved in the .blend)
  sampling.py  a slot -> the core's width*height values (live.py pushes them)
  operators.py Show: the map's group or image on the model (Weight / Texture Paint)

The panel (ui.py) only draws; the engine never sees bpy.
"""

from . import operators, sampling, settings, spec  # noqa: F401


def register():
    settings.register()
    operators.register()


def unregister():
    operators.unregister()
    settings.unregister()
