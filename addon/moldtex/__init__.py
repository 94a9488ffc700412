# SPDX-License-Identifier: GPL-3.0-or-later
"""Moldtex: grows Physarum slime mold (MoMaS, or the continuous model of Layton et al.)
over a mesh's UV layout into a texture.

Layout (engine never imports bpy; UI never calls ctypes):
  engine.py       ctypes binding of libmoldtex.so (next to this file)
  mesh_export.py  evaluated mesh -> flat arrays
  live.py         live simulations keyed by object name
  properties.py   per-object settings (Object.moldtex)
  operators.py    Start/Pause, Step, Reset, Set Up Material, Bake, Use Baked Sequence
  brush.py        surface brushes (fields, slime, food) and their stroke history
  brush_ops.py    the viewport brush tool, scripted strokes, Undo/Redo Stroke
  bake.py         baking image sequences (core bake worker) and their playback
  presets.py      looks: preset menu, saving presets, ramp helpers
  cli.py          headless bake (blender -P cli.py --, blender --command moldtex bake)
  image_io.py     pheromone image and fast pixel upload
  material.py     node setup
  colour_map.py   Colour Map from Image (the ramp from an exemplar image, Isomap in the core)
  handlers.py     load / depsgraph / undo / save handlers
  ui.py           sidebar panel
  maps/           parameter maps and stimuli of the continuous model (settings, sampling,
                  Show operator; registered before properties) and the surface map
                  tools (geodesic distance, Laplace blend, blur, gradient)
"""

bl_info = {
    "name": "Moldtex",
    "author": "Moldtex developers",
    "version": (0, 1, 0),  # staged from native/include/moldtex.h (addon/stage_version.cmake)
    "blender": (3, 4, 0),
    "location": "3D Viewport ▸ Sidebar ▸ Moldtex",
    "description": "Grow slime-mold (Physarum, MoMaS) patterns over a mesh's UV layout "
                   "into an image texture",
    "category": "Material",
}

if "live" in locals():
    import importlib
    # Re-enabling after a reload: free what the old module held, then reload all.
    live.free_all()
    for _module in (engine, mesh_export, maps.spec, maps.settings, maps.sampling, maps.operators,
                    maps.tool_settings, maps.mesh_values, maps.tools, maps):
        importlib.reload(_module)
    for _module in (live, properties, image_io, material, colour_map, bake, presets,
                    operators, brush, brush_ops, handlers, ui, cli):
        importlib.reload(_module)

import bpy  # noqa: E402

from . import maps  # noqa: E402  (before live and properties, which use it)
from . import engine, mesh_export, live, properties, image_io, material  # noqa: E402
from . import colour_map  # noqa: E402
from . import bake, presets, operators, brush, brush_ops, handlers, ui, cli  # noqa: E402

_MODULES = (maps, properties, brush, presets, operators, colour_map, brush_ops, ui,
            handlers)
_cli_commands = []  # handles of bpy.utils.register_cli_command (Blender 4.2+)


def register():
    for module in _MODULES:
        module.register()
    # `blender --command moldtex bake ...`: only Blender 4.2+ has command-line commands.
    if hasattr(bpy.utils, "register_cli_command"):
        _cli_commands.append(bpy.utils.register_cli_command("moldtex", cli.command))
    if not engine.available():
        print(f"Moldtex: {engine.status_text()}")


def unregister():
    live.free_all()
    while _cli_commands:
        bpy.utils.unregister_cli_command(_cli_commands.pop())
    for module in reversed(_MODULES):
        module.unregister()
