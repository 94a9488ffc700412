# SPDX-License-Identifier: GPL-3.0-or-later
"""The pheromone's colour: Set Up Material (material.py) and its node names (nodes.py),
Colour Map from Image (colour_map.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
