# SPDX-License-Identifier: GPL-3.0-or-later
"""Looks: the preset menu and saving presets (presets.py), how a preset's agent count
scales to an object (scaling.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
