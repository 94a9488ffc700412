# SPDX-License-Identifier: GPL-3.0-or-later
"""The simulation's operators: Start/Pause, Step, Reset, Set Up Material, Bake, Use Baked
Sequence (simulation.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
