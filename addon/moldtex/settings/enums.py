# SPDX-License-Identifier: GPL-3.0-or-later
"""Enum values this version does not know, read and repaired (bpy data only; imports
nothing of the add-on).

A file from another version (or a script writing the raw number, e.g.
obj.moldtex["resolution"] = 99) can leave an enum holding a number none of its items
has. Blender then reads it as "" (and prints a warning at each read).
"""

def invalid_enums(data):
    """[(name, stored number)] of data's static enum properties that hold a value
    matching none of their items."""
    found = []
    for prop in data.bl_rna.properties:
        if prop.type != 'ENUM' or prop.is_enum_flag or prop.is_readonly:
            continue
        raw = data.get(prop.identifier) if hasattr(data, "get") else None
        if not isinstance(raw, int):  # unset (= the default), or a dynamic enum
            continue
        items = prop.enum_items
        if len(items) and raw not in {item.value for item in items}:
            found.append((prop.identifier, raw))
    return found


def enum_value(data, name):
    """The identifier of enum `name` of data, or the property's default when the stored
    value matches none of its items."""
    raw = data.get(name) if hasattr(data, "get") else None
    prop = data.bl_rna.properties[name]
    if isinstance(raw, int) and raw not in {item.value for item in prop.enum_items}:
        return prop.default
    return getattr(data, name) or prop.default


def _enum_label(data, name, identifier):
    items = data.bl_rna.properties[name].enum_items
    return items[identifier].name if identifier in items else identifier


def invalid_enum_notes(data):
    """A sentence per unknown enum value of data, saying what is used instead."""
    notes = []
    for name, raw in invalid_enums(data):
        prop = data.bl_rna.properties[name]
        notes.append(f"{prop.name} held a value this version of Moldtex does not know "
                     f"({raw}, from another version?): {_enum_label(data, name, prop.default)}"
                     f" is used instead.")
    return notes


def repair_enums(data):
    """Sets every enum of data holding an unknown value back to its default; returns
    the notes (invalid_enum_notes) for the user."""
    notes = invalid_enum_notes(data)
    for name, _raw in invalid_enums(data):
        data.property_unset(name)
    return notes
