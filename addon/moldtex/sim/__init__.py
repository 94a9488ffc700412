# SPDX-License-Identifier: GPL-3.0-or-later
"""The live session: simulations by object (session.py, registry.py), settings as the
core's structures (convert.py), load / depsgraph / undo / save handlers (handlers.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
