# SPDX-License-Identifier: GPL-3.0-or-later
"""Surface brushes: the stroke logic and its history (session.py), the viewport tool and
scripted strokes (operators.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
