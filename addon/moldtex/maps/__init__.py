# SPDX-License-Identifier: GPL-3.0-or-later
"""Maps on the surface (layton-intrinsic-slime.md §3.3 and §6; issue 12).

Parameter maps and stimuli of the continuous model: per-texel multipliers of its
parameters (a Lifetime of 0 = a sink, Spawn = where agents are reborn) and the read /
write stimuli, painted as vertex groups, attributes or images.

  spec.py           the maps: keys, core kinds, labels, defaults (no bpy)
  settings.py       obj.moldtex.maps: one slot PropertyGroup per map (saved in the .blend)
  sampling.py       a slot -> the core's width*height values (live.py pushes them)
  operators.py      Show: the map's group or image on the model (Weight / Texture Paint)

Surface map tools (Fig. 14-17): finite elements on the object's mesh turn vertex groups
into distance, blend, blurred and gradient maps.

  tool_settings.py  Object.moldtex_map_tools: the tools' inputs (drawn by ui.py)
  mesh_values.py    vertex groups / attributes <-> arrays, the engine Surface of a mesh
  tools.py          the operators

The panels (ui.py) only draw; the engine never sees bpy.
"""

from . import mesh_values, operators, sampling, settings, spec, tool_settings, tools  # noqa: F401


def register():
    settings.register()
    operators.register()
    tool_settings.register()
    tools.register()


def unregister():
    tools.unregister()
    tool_settings.unregister()
    operators.unregister()
    settings.unregister()
