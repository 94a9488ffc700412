# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender data as arrays and back: the evaluated mesh (mesh_export.py), the pheromone
image (image_io.py), vertex colours for a mesh without UVs (vertex_colours.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
