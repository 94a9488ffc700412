# SPDX-License-Identifier: GPL-3.0-or-later
"""Maps on the surface (layton-intrinsic-slime.md §3.3 and §6; issue 12).

Parameter maps and stimuli: per-texel multipliers of a model's parameters (a Lifetime
of 0 = a sink, Spawn = where agents are reborn) and the read / write stimuli, painted
as vertex groups, attributes or images. Which maps a model reads is its
Model.map_keys (models/).

  spec.py           the maps: keys, core kinds, labels, defaults (no bpy)
  settings.py       obj.moldtex.maps: one slot PropertyGroup per map (saved in the .blend)
  sampling.py       a slot -> the core's width*height values (the live session pushes them)
  operators.py      Show: the map's group or image on the model (Weight / Texture Paint)

Surface map tools (Fig. 14-17): finite elements on the object's mesh turn vertex groups
into distance, blend, blurred and gradient maps.

  tool_settings.py  Object.moldtex_map_tools: the tools' inputs (drawn by ui/panels.py)
  mesh_values.py    vertex groups / attributes <-> arrays, the engine Surface of a mesh
  tools.py          the operators

This package imports nothing itself: the add-on registers its modules
(moldtex/__init__.py), so that a model can read mesh_values without loading the rest.
"""
