# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-object settings (properties.py: Object.moldtex), what every group shares
(common.py), enums from other versions (enums.py), the pattern unit (units.py) and the
events a change raises for the features that answer it (events.py).

Imports nothing itself (the add-on's __init__.py registers the modules), so that any
feature can use one module of it without loading the others."""
