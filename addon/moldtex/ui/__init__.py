# SPDX-License-Identifier: GPL-3.0-or-later
"""The sidebar (panels.py; draws only) and its layout helpers (layout.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
