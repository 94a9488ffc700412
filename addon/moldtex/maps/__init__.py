# SPDX-License-Identifier: GPL-3.0-or-later
"""Surface map tools (Layton et al. §6, Fig. 14-17; issue 12): finite elements on the
object's mesh turn vertex groups into distance, blend, blurred and gradient maps.

  settings.py     Object.moldtex_map_tools: the operators' inputs (drawn by ui.py)
  mesh_values.py  vertex groups / attributes <-> arrays, the engine Surface of a mesh
  tools.py        the operators
"""

from . import settings, mesh_values, tools  # noqa: F401


def register():
    settings.register()
    tools.register()


def unregister():
    tools.unregister()
    settings.unregister()
