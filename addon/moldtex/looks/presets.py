# SPDX-License-Identifier: GPL-3.0-or-later
"""Looks (presets): parameter sets plus a colour ramp, in Blender's preset format.

A preset is a .py file that Blender's script.execute_preset runs with the object to
change as context.object:

    import bpy
    obj = bpy.context.object
    s = obj.moldtex
    s.movement_speed = 1.0
    ...
    s.agent_count = s.scaled_agent_count(60000)  # agents on 512 x 512 pattern units
    s.apply_ramp([(0.0, (0.9, 0.9, 0.85, 1.0)), (1.0, (0.3, 0.3, 0.32, 1.0))])

A look for the continuous model sets s.model = 'CONTINUOUS' and the parameters of
s.continuous (lengths in pattern units, angles in radians, times in seconds), turns
Keep U off first and sets it last, and gives a fixed agent count: that model's look
does not depend on the texture resolution. Its ramp spans u / U from 0 to
s.continuous.display_range.

Another model's look sets s.model and that model's own settings group (its
models/<name>.py lists the fields a preset writes); its ramp spans 0 to that group's
display_range.

Presets neither store nor change the parameter maps (s.maps, maps/): a look is about
the parameters, while a map names one object's vertex groups and images, which another
object would not have (applying a look keeps the object's maps as they are).

scaled_agent_count and apply_ramp are methods of the settings (settings/properties.py),
so a preset never imports this add-on, whose module name differs between installs
("moldtex" as a legacy add-on, "bl_ext.<repository>.moldtex" as a 4.2 extension).

Where presets are found (the same on Blender 3.4 and 4.2+):
  - the presets shipped with the add-on: <add-on>/presets/*.py (staged there from the
    repository's presets/ folder; in a source checkout addon/moldtex/../../presets);
  - the user's own: Blender's preset folders for "moldtex"
    (bpy.utils.preset_paths("moldtex"), e.g. ~/.config/blender/<version>/scripts/
    presets/moldtex/), where moldtex.preset_add saves them.
MOLDTEX_MT_presets lists both (its draw passes both folders to Menu.path_menu), so
nothing is copied into the user's folders and the shipped presets are updated with
the add-on. bpy.utils.register_preset_path would do this on 4.2+ only.

Each entry runs moldtex.preset_apply (Blender's script.execute_preset, then the name
is stored on the object: the menu shows the look of the active object, not the last
one picked anywhere); its tooltip is the preset's "# Look: ..." comment line.
"""

import os

import bpy
from bl_operators.presets import AddPresetBase

from .. import engine, models
from ..colour import material
from ..settings.enums import enum_value
from . import scaling

SUBDIR = "moldtex"
MENU_IDNAME = "MOLDTEX_MT_presets"
AGENT_COUNT_COMMENT = "agents on 512 x 512 pattern units"

# Settings a preset sets (besides the model, the agent count and the ramp): MoMaS'...
PRESET_PROPERTIES = ("movement_speed", "turn_speed", "vision_distance", "vision_angle",
                     "evaporation_rate", "diffusion_rate", "deposit", "substeps")
# ... and each model's own (models/: Model.preset_alias and preset_fields).


def shipped_directory():
    """The folder of the presets that come with the add-on, or "" if missing."""
    for candidate in (os.path.join(engine.ADDON_DIR, "presets"),
                      os.path.join(engine.ADDON_DIR, os.pardir, os.pardir, "presets")):
        if os.path.isdir(candidate):
            return os.path.normpath(candidate)
    return ""


def user_directories():
    """Blender's preset folders for Moldtex that exist (the user's saved presets)."""
    shipped = shipped_directory()
    found = []
    for path in bpy.utils.preset_paths(SUBDIR):
        path = os.path.normpath(path)
        if path != shipped and path not in found:
            found.append(path)
    return found


def search_directories():
    shipped = shipped_directory()
    return ([shipped] if shipped else []) + user_directories()


def _is_preset_file(name):
    return name.endswith(".py") and not name.startswith((".", "_"))


def available():
    """{name: path} of every preset, shipped first; a user's preset of the same name
    comes later and wins."""
    presets = {}
    for directory in search_directories():
        try:
            names = sorted(os.listdir(directory))
        except OSError:
            continue
        for name in names:
            if _is_preset_file(name):
                presets[name[:-3]] = os.path.join(directory, name)
    return presets


def find(name):
    """Path of the preset called `name` ("marble", "Wood Grain", or a .py path)."""
    if name.endswith(".py") and os.path.isfile(name):
        return os.path.abspath(name)
    presets = available()
    if name in presets:
        return presets[name]
    wanted = bpy.path.display_name_to_filepath(name.strip()).replace(" ", "_").lower()
    for key, path in presets.items():
        if key.lower() == wanted:
            return path
    return ""


LOOK_PREFIX = "# Look:"


def display_name(path):
    """ "Wood Grain" for .../wood_grain.py."""
    return bpy.path.display_name(os.path.basename(path))


def describe(path):
    """The look a preset file describes (its "# Look: ..." line), for its tooltip."""
    try:
        with open(path, encoding="utf-8") as file:
            for _index, line in zip(range(40), file):
                if line.startswith(LOOK_PREFIX):
                    return line[len(LOOK_PREFIX):].strip()
    except OSError:
        return ""
    return ""


def menu_label(obj):
    """What the preset menu shows for obj: the look last applied to it, else
    "Presets"."""
    name = obj.moldtex.preset_name if obj is not None else ""
    return name or "Presets"


agents_per_preset_agent = scaling.agents_per_preset_agent
scaled_agent_count = scaling.scaled_agent_count
apply_ramp = material.apply_ramp


def current_ramp(obj):
    """(stops, interpolation) of obj's Moldtex Ramp node, else the remembered ones."""
    node = material.moldtex_node(obj, material.RAMP_NODE)
    if node is not None:
        ramp = node.color_ramp
        return ([(element.position, tuple(element.color)) for element in ramp.elements],
                ramp.interpolation)
    return material.preset_ramp(obj)


def _literal(value):
    return repr(round(value, 7) if isinstance(value, float) else value)


def preset_text(obj, title=""):
    """The preset file for obj's current look, in the shipped presets' format."""
    settings = obj.moldtex
    cont = settings.continuous
    model = enum_value(settings, "model")
    lines = [f"# Moldtex preset{': ' + title if title else ''}",
             f"{LOOK_PREFIX} Your look{' ' + repr(title) if title else ''}, saved from "
             f"'{obj.name}'.", "import bpy", "obj = bpy.context.object", "s = obj.moldtex",
             "c = s.continuous", f"s.model = {model!r}", "c.keep_u = False"]
    for name in PRESET_PROPERTIES:
        lines.append(f"s.{name} = {_literal(getattr(settings, name))}")
    lines.append(f"s.time_step = {_literal(settings.time_step)}")
    for own in models.MODELS:
        if not own.preset_fields:
            continue
        group = getattr(settings, own.settings_name)
        if own.preset_alias != "c":  # (c = s.continuous is written above, for Keep U)
            lines.append(f"{own.preset_alias} = s.{own.settings_name}")
        for name in own.preset_fields:
            value = (enum_value(group, name)
                     if group.bl_rna.properties[name].type == 'ENUM' else getattr(group, name))
            lines.append(f"{own.preset_alias}.{name} = {_literal(value)}")
    if not models.of_key(model).scaled_presets:
        # These models' looks do not depend on the resolution.
        lines.append(f"s.agent_count = {int(settings.agent_count)}")
    else:
        at_512 = round(settings.agent_count / agents_per_preset_agent(settings))
        lines.append(f"s.agent_count = s.scaled_agent_count({max(1, at_512)})  "
                     f"# {AGENT_COUNT_COMMENT}")
    lines.append(f"c.keep_u = {bool(cont.keep_u)!r}")
    stops, interpolation = current_ramp(obj)
    if stops:
        lines.append("s.apply_ramp([")
        for position, color in stops:
            rgba = ", ".join(f"{c:.4f}" for c in color)
            lines.append(f"    ({position:.4f}, ({rgba})),")
        lines.append(f"], interpolation={interpolation!r})")
    return "\n".join(lines) + "\n"


class MOLDTEX_MT_presets(bpy.types.Menu):
    """Looks: parameters and colour ramp (shipped presets, then your own)"""
    bl_label = "Presets"
    bl_idname = MENU_IDNAME
    preset_subdir = SUBDIR
    preset_operator = "moldtex.preset_apply"
    preset_add_operator = "moldtex.preset_add"

    def draw(self, context):
        layout = self.layout

        def is_py(extension):
            return extension.lower() == ".py"

        shipped = shipped_directory()
        if shipped:
            self.path_menu([shipped], self.preset_operator, filter_ext=is_py,
                           display_name=display_name)
        users = user_directories()
        if users:
            layout.separator()
            # With add_operator: a remove button on each (own) preset, then a name
            # field and an add button.
            self.path_menu(users, self.preset_operator, filter_ext=is_py,
                           display_name=display_name, add_operator=self.preset_add_operator)
        else:
            layout.separator()
            row = layout.row()
            window_manager = context.window_manager
            row.prop(window_manager, "preset_name", text="")
            props = row.operator(self.preset_add_operator, text="", icon='ADD')
            props.name = window_manager.preset_name


class MOLDTEX_OT_preset_apply(bpy.types.Operator):
    """Apply this look to the active object"""
    bl_idname = "moldtex.preset_apply"
    bl_label = "Apply Moldtex Preset"
    bl_options = {'REGISTER', 'UNDO'}

    filepath: bpy.props.StringProperty(subtype='FILE_PATH', options={'SKIP_SAVE'})
    menu_idname: bpy.props.StringProperty(options={'SKIP_SAVE', 'HIDDEN'})

    @classmethod
    def description(cls, context, properties):
        look = describe(properties.filepath) if properties.filepath else ""
        return look or cls.__doc__

    @classmethod
    def poll(cls, context):
        obj = context.object
        return obj is not None and obj.type == 'MESH'

    def execute(self, context):
        obj = context.object
        label = MOLDTEX_MT_presets.bl_label
        try:
            result = bpy.ops.script.execute_preset(filepath=self.filepath,
                                                   menu_idname=MENU_IDNAME)
        except RuntimeError as error:  # e.g. the preset raised: reported as an error
            self.report({'ERROR'}, str(error).replace("Error: ", "", 1).strip())
            return {'CANCELLED'}
        finally:
            MOLDTEX_MT_presets.bl_label = label  # the menu's label is per object
        if 'FINISHED' in result and obj is not None:
            obj.moldtex.preset_name = display_name(self.filepath)
        return result


class MOLDTEX_OT_preset_add(AddPresetBase, bpy.types.Operator):
    """Save the active object's look (parameters, agent density and colour ramp) as a \
preset, or remove one of your presets"""
    bl_idname = "moldtex.preset_add"
    bl_label = "Add Moldtex Preset"
    preset_menu = MENU_IDNAME
    preset_subdir = SUBDIR
    preset_defines = (["obj = bpy.context.object", "s = obj.moldtex"]
                      + [f"{m.preset_alias} = s.{m.settings_name}" for m in models.MODELS
                         if m.preset_fields])
    preset_values = (["s.model"] + [f"s.{name}" for name in PRESET_PROPERTIES]
                     + ["s.time_step"]
                     + [f"{m.preset_alias}.{name}" for m in models.MODELS
                        for name in m.preset_fields]
                     + ["s.agent_count", "c.keep_u"])

    @classmethod
    def poll(cls, context):
        obj = context.object
        return obj is not None and obj.type == 'MESH'

    def execute(self, context):
        # Blender removes "the active preset" by the menu class's label; here the
        # active object's look is the active one.
        obj = context.object
        if self.remove_active:
            MOLDTEX_MT_presets.bl_label = menu_label(obj)
        try:
            result = super().execute(context)
        finally:
            MOLDTEX_MT_presets.bl_label = "Presets"
        if obj is not None and 'FINISHED' in result:
            settings = obj.moldtex
            if self.remove_active:
                settings.preset_name = ""
            elif self.remove_name:
                if settings.preset_name == bpy.path.display_name(self.name):
                    settings.preset_name = ""
            else:
                settings.preset_name = bpy.path.display_name(self.as_filename(self.name))
        return result

    def add(self, context, filepath):
        # Our own writer, so a saved preset also keeps the colour ramp and scales the
        # agent count with the resolution like the shipped ones.
        print(f"Writing Moldtex preset: {filepath!r}")
        with open(filepath, "w", encoding="utf-8") as file:
            file.write(preset_text(context.object, self.name.strip()))


CLASSES = (MOLDTEX_MT_presets, MOLDTEX_OT_preset_apply, MOLDTEX_OT_preset_add)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
