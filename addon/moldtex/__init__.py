# SPDX-License-Identifier: GPL-3.0-or-later
"""Moldtex: grows Physarum slime mold (MoMaS, or the continuous model of Layton et al.)
and reaction-diffusion patterns over a mesh into a texture.

Layout, by feature (docs/ARCHITECTURE.md draws it; tools/check_addon_imports.py keeps it
free of import cycles, the binding free of bpy and the UI free of ctypes):
  engine/     ctypes binding of libmoldtex.so (next to this file); never imports bpy
  data/       Blender data <-> arrays: mesh export, pheromone images, vertex colours
  settings/   per-object settings (Object.moldtex), enums, the pattern unit, and the
              events a setting change raises for the features that answer it
  models/     one module per model (settings, conversion, display, panels, preset
              fields) behind models/base.py's Model; models/__init__.py lists them
  maps/       parameter maps and stimuli, and the surface map tools
  sim/        the live session: simulations by object, settings -> core structures
              (convert.py), load / depsgraph / undo / save handlers
  colour/     Set Up Material and its nodes, Colour Map from Image
  looks/      presets: the menu, saving, how a preset's agent count scales
  brush/      surface brushes and their stroke history; the viewport tool
  bake/       baking image sequences and their playback
  operators/  Start/Pause, Step, Reset, Set Up Material, Bake, Use Baked Sequence
  ui/         the sidebar panels (draw only) and their layout helpers
  cli.py      headless bake (blender -P cli.py --, blender --command moldtex bake)
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

if "_MODULES" in locals():
    # Re-enabling after a reload: free what the old session held, then load every module
    # afresh (the imports below find none of them cached).
    import sys
    live.free_all()
    for _name in [name for name in sys.modules if name.startswith(__name__ + ".")]:
        del sys.modules[_name]

import bpy  # noqa: E402

from . import engine, models  # noqa: E402
from .maps import operators as map_operators, settings as map_settings  # noqa: E402
from .maps import tool_settings as map_tool_settings, tools as map_tools  # noqa: E402
from .settings import properties  # noqa: E402
from .sim import handlers, session as live  # noqa: E402
from .colour import colour_map, material  # noqa: E402
from .looks import presets  # noqa: E402
from .brush import operators as brush_ops, session as brush  # noqa: E402
from .operators import simulation as operators  # noqa: E402
from .ui import panels as ui  # noqa: E402
from . import cli  # noqa: E402

# In the order they register (a PropertyGroup before the groups that point to it).
_MODULES = (models, map_settings, map_operators, map_tool_settings, map_tools, properties,
            live, material, brush, presets, operators, colour_map, brush_ops, ui, handlers)
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
