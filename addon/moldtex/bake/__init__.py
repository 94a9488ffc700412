# SPDX-License-Identifier: GPL-3.0-or-later
"""Baking image sequences on the core's bake worker, and their playback (sequence.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
