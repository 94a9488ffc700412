# SPDX-License-Identifier: GPL-3.0-or-later
"""The models the add-on offers, one module each (models/<name>.py: its settings, their
conversion to the core's parameters, what its image shows), behind models/base.py's
Model. This is the one list of them: the Model menu, the command line's --model, the
settings' groups and the session all read it.

Adding a model: a module here with MODEL = a Model subclass, and its line in MODELS
(README "Adding a model" in docs/ARCHITECTURE.md lists the native side).
"""

import bpy

from . import continuous, gray_scott, momas

MODELS = (momas.MODEL, continuous.MODEL, gray_scott.MODEL)  # the Model menu's order
DEFAULT = momas.MODEL
BY_KEY = {model.key: model for model in MODELS}
BY_ENGINE_ID = {model.engine_id: model for model in MODELS}


def enum_items():
    """The Model menu's items: (identifier, label, description, number)."""
    return [(m.key, m.label, m.description, m.number) for m in MODELS]


def of_key(key):
    """The model of a Model menu identifier (an unknown one reads as the default)."""
    return BY_KEY.get(key, DEFAULT)


def of_engine_id(engine_id):
    return BY_ENGINE_ID.get(engine_id, DEFAULT)


def on_domain(domain):
    """Labels of the models that run on engine.DOMAIN_* domain."""
    return [m.label for m in MODELS if domain in m.domains]


def settings_groups():
    """{obj.moldtex attribute: PropertyGroup class} of the models' own settings."""
    return {m.settings_name: m.settings_class for m in MODELS if m.settings_class}


def own_settings(settings):
    """The models' own settings groups on an object's settings (obj.moldtex)."""
    return [getattr(settings, m.settings_name) for m in MODELS if m.settings_name]


def register():
    for cls in settings_groups().values():
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(list(settings_groups().values())):
        bpy.utils.unregister_class(cls)


