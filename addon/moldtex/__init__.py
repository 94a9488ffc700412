# SPDX-License-Identifier: GPL-3.0-or-later
"""Moldtex: grows Physarum slime mold (MoMaS) over a mesh's UV layout into a texture.

Layout (engine never imports bpy; UI never calls ctypes):
  engine.py       ctypes binding of libmoldtex.so (next to this file)
  mesh_export.py  evaluated mesh -> flat arrays
  live.py         live simulations keyed by object name
  properties.py   per-object settings (Object.moldtex)
  operators.py    Start/Pause, Step, Reset, Set Up Material
  image_io.py     pheromone image and fast pixel upload
  material.py     node setup
  handlers.py     load / depsgraph / undo / save handlers
  ui.py           sidebar panel
"""

bl_info = {
    "name": "Moldtex",
    "author": "Moldtex developers",
    "version": (0, 1, 0),
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
    for _module in (engine, mesh_export, live, properties, image_io, material,
                    operators, handlers, ui):
        importlib.reload(_module)

from . import engine, mesh_export, live, properties, image_io, material  # noqa: E402
from . import operators, handlers, ui  # noqa: E402

_MODULES = (properties, operators, ui, handlers)


def register():
    for module in _MODULES:
        module.register()
    if not engine.available():
        print(f"Moldtex: {engine.status_text()}")


def unregister():
    live.free_all()
    for module in reversed(_MODULES):
        module.unregister()
