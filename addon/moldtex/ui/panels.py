# SPDX-License-Identifier: GPL-3.0-or-later
"""The "Moldtex" tab of the 3D Viewport sidebar. Draws only; never calls the engine's
C functions (it reads cached stats from sim/session.py).

Settings use Blender's property-split layout (label column, value column, no animate
dots) with the short labels of LABELS, which fit the label column at the sidebar's
default width (blender_tests/panel_fit.py checks it); the long names start each
property's tooltip (its description)."""

import bpy

from ..bake import sequence as bake
from ..brush import session as brush
from .. import engine
from .. import models
from ..sim import convert
from ..sim import session as live
from ..looks import presets
from ..data.mesh_export import MeshExportError, check_transform, resolve_uv_map_name
from ..settings.enums import invalid_enum_notes
from ..maps.settings import slots as map_slots

from .layout import (COARSE_TEXELS_PER_UNIT, SubPanel as _SubPanel, mesh_object as _mesh_object,
                     split as _split, wrapped as _wrapped)
from . import layout as _layout

# Every short label: the panels' own and each model's (test_ui checks them all).
LABELS = dict(_layout.LABELS)
for _model in models.MODELS:
    LABELS.update(_model.labels)


def _prop(layout, data, name, **kwargs):
    _layout.prop(layout, data, name, labels=LABELS, **kwargs)


def _model(obj):
    """The models.base.Model obj's settings ask for."""
    return convert.model_for(obj.moldtex)


class MOLDTEX_PT_main(bpy.types.Panel):
    bl_label = "Moldtex"
    bl_idname = "MOLDTEX_PT_main"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Moldtex"

    def draw(self, context):
        layout = self.layout
        if engine.available():
            layout.label(text=engine.status_text())  # (with an icon it would be cut)
        else:
            box = layout.box()
            _wrapped(box, engine.status_text(), icon='ERROR')

        obj = _mesh_object(context)
        if obj is None:
            layout.label(text="Select a mesh object", icon='INFO')
            return
        settings = obj.moldtex
        entry = live.get(obj.name)

        layout.label(text=obj.name, icon='OBJECT_DATA')
        # The model comes first: every setting below depends on it.
        row = layout.row(align=True)
        row.prop(settings, "model", expand=True)
        if len(_model(obj).domains) > 1:  # (MoMaS works in texels)
            row = layout.row(align=True)
            row.prop(settings, "domain", expand=True)
        row = layout.row(align=True)
        # The look last applied to this object (not the last one picked anywhere).
        row.menu(presets.MENU_IDNAME, text=presets.menu_label(obj), icon='PRESET')
        row.operator("moldtex.preset_add", text="", icon='ADD')
        props = row.operator("moldtex.preset_add", text="", icon='REMOVE')
        props.remove_active = True
        try:
            check_transform(obj)
        except MeshExportError as error:
            _wrapped(layout.box(), str(error), icon='ERROR')
        notes = invalid_enum_notes(settings) + [
            note for group in models.own_settings(settings)
            for note in invalid_enum_notes(group)]
        for note in notes:
            _wrapped(layout, note + " Reset fixes it.", icon='ERROR')
        column = _split(layout)
        if len(obj.data.uv_layers) == 0:
            if convert.domain_of(settings) == engine.DOMAIN_INTRINSIC:
                # It runs: only the texture needs UVs (the pattern goes to the vertices).
                box = layout.box()
                _wrapped(box, "No UV map: the Intrinsic domain still runs, and shows the "
                              "pattern as the vertex colours 'Moldtex' (one colour per "
                              "vertex: subdivide for detail). Bakes and the Fields image "
                              "need a UV map (UV ▸ Smart UV Project).", icon='INFO')
                problem = entry.vertex_problem if entry is not None and entry.has_sim else ""
                if problem:
                    _wrapped(box, problem, icon='ERROR')
            else:
                _wrapped(layout.box(), "No UV map: add one (UV ▸ Smart UV Project in Edit "
                                       "Mode), or choose the Continuous model on the "
                                       "Intrinsic domain (it colours the vertices).",
                         icon='ERROR')
        else:
            column.prop_search(settings, "uv_map", obj.data, "uv_layers", text="UV Map",
                               icon='GROUP_UVS')
            if entry is not None and entry.has_sim and entry.vertex_colours:
                _wrapped(layout.box(), f"UV map '{entry.flat_uv_map}' has no area (all its "
                                       f"UVs on one point or line): the Intrinsic domain "
                                       f"runs without it and shows the pattern as the vertex "
                                       f"colours 'Moldtex'. Bakes need an unwrapped map (UV "
                                       f"▸ Smart UV Project).", icon='INFO')
            if not settings.uv_map:
                _wrapped(layout, f"Empty: the render UV map "
                                 f"('{resolve_uv_map_name(obj, '')}').", icon='BLANK1')
        # The controls used every minute (the rest is in the sub-panels below).
        column = _split(layout)
        _prop(column, settings, "resolution")
        if _model(obj).has_agents:
            _prop(column, settings, "agent_count")
        _prop(column, settings, "steps_per_update")
        if settings.steps_per_update == 0:
            _prop(column, settings, "update_time")

        column = layout.column(align=True)
        running = entry is not None and entry.running
        # In the order of the work: material (Start also sets it up), grow, adjust.
        column.operator("moldtex.setup_material", icon='MATERIAL')
        column.operator("moldtex.colour_map_from_image", icon='COLOR')
        row = column.row(align=True)
        row.scale_y = 1.4
        row.operator("moldtex.start", text="Pause" if running else "Start",
                     icon='PAUSE' if running else 'PLAY')
        row = column.row(align=True)
        row.operator("moldtex.step", icon='FRAME_NEXT')
        row.operator("moldtex.reset", icon='FILE_REFRESH')

        if live.needs_reset(obj):
            _wrapped(layout, "Model, domain, resolution, detail, agents, seed, backend, UV map, "
                             "species or start changed: press Reset (or Start) to apply.",
                     icon='INFO')
        if entry is not None and entry.notice:
            _wrapped(layout, entry.notice, icon='INFO')
        if entry is not None and entry.baking:
            _wrapped(layout, "Baking: " + _bake_progress_text(entry.bake_progress,
                                                              entry.bake_plan) +
                     " (the live simulation waits)", icon='RENDER_ANIMATION')

        building = live.domain_build_status(obj)
        if building is not None and building["state"] == engine.BAKE_RUNNING:
            _wrapped(layout, live.domain_build_text(building) +
                     " (press Start or Reset again, or Esc, to cancel)", icon='MESH_DATA')
        box = layout.box()
        stats = entry.stats if entry is not None and entry.has_sim else None
        if not stats:
            box.label(text="Not running yet", icon='TIME')
        else:
            # row_major: label, value, label, value... (the default fills columns first,
            # which put "Steps" next to the coverage value).
            grid = box.grid_flow(row_major=True, columns=2, even_columns=True,
                                 align=True)
            grid.label(text="Steps")
            if entry.baking:  # the bake's worker steps it; entry.stats are from before
                grid.label(text=f"{(entry.bake_progress or {}).get('step_count', 0):,} "
                                f"(bake)")
            else:
                grid.label(text=f"{stats['step_count']:,}")
            if running and entry.steps_per_second > 0.0:
                grid.label(text="Speed")
                grid.label(text=f"{entry.steps_per_second:,.0f} steps/s")
            model = convert.sim_model_for(entry)
            if model.simulated_time and not entry.baking:
                grid.label(text="Time")
                grid.label(text=f"{stats.get('time', 0.0):,.2f} s")
            if model.has_agents:
                grid.label(text="Agents")
                grid.label(text=f"{stats['agent_count']:,}")
            for label, text in model.stats_rows(stats):
                grid.label(text=label)
                grid.label(text=text)
            per_unit = convert.texels_per_unit(entry, obj.moldtex)
            detail = int(entry.config.get("detail", 1) or 1) if entry.config else 1
            if per_unit is not None:
                grid.label(text="Texels / Unit")
                grid.label(text=f"{per_unit:.1f}")
            if detail > 1:
                grid.label(text="Simulated")
                grid.label(text=f"{entry.config.get('width', 0) * detail} × "
                                f"{entry.config.get('height', 0) * detail} ({detail}×)")
            grid.label(text="Memory")
            grid.label(text=f"{stats['bytes_in_use'] / 2**20:.1f} MiB")
            if per_unit is not None and per_unit * detail < COARSE_TEXELS_PER_UNIT:
                _wrapped(box, "Under one simulated texel per pattern unit: Detail Auto or a "
                              "higher Resolution computes the same pattern more finely (two "
                              "or more texels per unit keep a UV sphere's poles full)",
                         icon='INFO')
            # e.g. "OpenCL: <device> (<platform>)", or for Auto "CPU (2 threads);
            # OpenCL not used: <why>".
            text = _domain_text(entry.domain_info)
            if text:
                _wrapped(box, text, icon='MESH_DATA')
            _wrapped(box, f"Backend: {entry.backend_name}", icon='SETTINGS')
            if entry.backend_note:
                _wrapped(box, entry.backend_note, icon='ERROR')


def _domain_text(info):
    """The intrinsic triangulation's size and build, e.g. "Intrinsic: 61,204 vertices,
    121,980 triangles (1.3 s)", or "" on the texture domain."""
    if not info or info.get("domain") != engine.DOMAIN_INTRINSIC:
        return ""
    built = ("reused" if info.get("from_cache")
             else f"built in {info.get('build_seconds', 0.0):.1f} s")
    text = (f"Intrinsic: {info.get('cell_count', 0):,} vertices, "
            f"{info.get('face_count', 0):,} triangles ({built})")
    if info.get("skipped_faces"):
        text += f"; {info['skipped_faces']:,} left above the size at sharp corners"
    return text


class MOLDTEX_PT_map_tools(_SubPanel, bpy.types.Panel):
    """Surface map tools (maps/tools.py): inputs from Object.moldtex_map_tools."""
    bl_label = "Map Tools"
    bl_idname = "MOLDTEX_PT_map_tools"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        obj = context.active_object
        tools = getattr(obj, "moldtex_map_tools", None)
        if tools is None:
            return
        layout = self.layout
        groups, attributes = (obj, "vertex_groups"), (obj.data, "attributes")

        def section(title, operator, rows):
            box = layout.box()
            box.label(text=title)
            column = _split(box)
            for name, search in rows:
                if search is None:
                    _prop(column, tools, name)
                else:
                    column.prop_search(tools, name, search[0], search[1])
            box.operator(operator)

        section("Distance from a group", "moldtex.map_distance",
                (("distance_source", groups), ("time_factor", None),
                 ("distance_group", None), ("distance_attribute", None)))
        section("Blend between groups", "moldtex.map_blend",
                (("blend_low", groups), ("blend_high", groups), ("blend_group", None)))
        section("Blur a group", "moldtex.map_blur",
                (("blur_source", groups), ("blur_radius", None), ("blur_group", None)))
        section("Gradient as bias", "moldtex.map_gradient_bias",
                (("gradient_source", groups), ("gradient_direction", None),
                 ("gradient_normalize", None), ("gradient_attribute", None)))


class MOLDTEX_PT_continuous_maps(_SubPanel, bpy.types.Panel):
    """Parameter maps and stimuli (maps/): one line per map the model reads, its source
    and factors when it is on."""
    bl_label = "Maps"
    bl_idname = "MOLDTEX_PT_continuous_maps"
    bl_options = {'DEFAULT_CLOSED'}

    @classmethod
    def poll(cls, context):
        obj = _mesh_object(context)
        return obj is not None and bool(_model(obj).map_keys)

    def draw(self, context):
        obj = context.active_object
        layout = self.layout
        entry = live.get(obj.name)
        if entry is not None and entry.maps_error:
            _wrapped(layout, entry.maps_error, icon='ERROR')
        enabled = 0
        read = _model(obj).map_keys
        for spec, slot in map_slots(obj.moldtex):
            if spec.key not in read:
                continue
            enabled += bool(slot.enabled)
            _draw_map(layout, obj, spec, slot)
        if enabled:
            _wrapped(layout, "Map values 0 to 1; after painting, press Reset.",
                     icon='INFO')
        else:
            _wrapped(layout, "Tick a setting to vary it over the surface by a vertex "
                             "group, attribute or image.", icon='INFO')


def _draw_map(layout, obj, spec, slot):
    column = layout.column(align=True)
    row = column.row(align=True)
    row.prop(slot, "enabled", text=spec.label)
    if not slot.enabled:
        return
    row.prop(slot, "source", text="", icon_only=True, expand=True)
    row.operator("moldtex.map_show", text="", icon='HIDE_OFF').map = spec.key
    box = column.box()
    source = _split(box)
    if slot.source == 'IMAGE':
        source.prop(slot, "image", text="Image")
        missing = slot.image is None
    else:
        source.prop_search(slot, "attribute", obj, "vertex_groups", text="Group",
                           icon='GROUP_VERTEX', **_SUGGESTIONS)
        missing = not slot.attribute
    if missing:
        _wrapped(box, "Off until one is picked; Reset refuses it.", icon='ERROR')
    if spec.role == 'MULTIPLIER':
        row = box.row(align=True)
        row.prop(slot, "at0")
        row.prop(slot, "at1")
    else:
        _split(box).prop(slot, "strength")


class MOLDTEX_PT_setup(_SubPanel, bpy.types.Panel):
    bl_label = "Simulation"
    bl_idname = "MOLDTEX_PT_setup"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        settings = context.active_object.moldtex
        layout = self.layout
        model = _model(context.active_object)
        column = _split(layout)
        model.draw_setup(column, settings)
        column = _split(layout)
        column.label(text="Applied on Reset", icon='FILE_REFRESH')
        _prop(column, settings, "seed")
        if model.pattern_lengths and settings.pattern_units == 'SURFACE':
            _prop(column, settings, "detail")  # (MoMaS' surface units only)
        if engine.DOMAIN_INTRINSIC in model.domains and settings.domain == 'INTRINSIC':
            _prop(column, settings, "intrinsic_size")
        _prop(column, settings, "backend")
        note = live.backend_note(settings)
        if note:  # e.g. a file saved on a machine with another GPU
            _wrapped(layout, note, icon='ERROR')
        devices, reason = convert.opencl_devices()
        if not devices:
            _wrapped(layout, f"OpenCL unavailable: {reason}", icon='INFO')
        column = _split(layout)
        _prop(column, settings, "thread_count")
        _prop(column, settings, "image")


class MOLDTEX_PT_species(_SubPanel, bpy.types.Panel):
    bl_label = "Species & Start"
    bl_idname = "MOLDTEX_PT_species"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        settings = context.active_object.moldtex
        layout = self.layout
        column = _split(layout)
        column.label(text="Applied on Reset", icon='FILE_REFRESH')
        model = _model(context.active_object)
        if model.has_agents:
            _prop(column, settings, "species_count")
        _prop(column, settings, "seed_shape")
        if settings.seed_shape in {'CIRCLE', 'STARBURST'}:
            _prop(column, settings, "seed_radius")
        if settings.seed_shape == 'STARBURST':
            _prop(column, settings, "seed_rays")
        if settings.seed_shape in live.CENTERED_SHAPES:
            _wrapped(layout, "Centre: the surface point nearest the 3D cursor.",
                     icon='PIVOT_CURSOR')
        _draw_fields(layout, context.active_object)
        if not model.has_agents:
            _wrapped(layout, model.start_note, icon='INFO')
            return
        _draw_food(layout, context.active_object)
        count = settings.species_count
        if count < 2:
            return
        if model.species_note:
            _wrapped(layout, model.species_note, icon='INFO')
        for index in range(min(count, len(settings.species))):
            item = settings.species[index]
            box = layout.box()
            row = box.row()
            row.label(text=f"Species {index + 1}")
            row.prop(item, "color", text="")
            if model.species_params:
                column = _split(box)
                for name in ("movement_speed", "turn_speed", "vision_distance",
                             "vision_angle_ui", "deposit"):
                    _prop(column, item, name)
            column = box.column(align=True)
            column.label(text="Attraction to species:")
            row = column.row(align=True)
            for other in range(count):
                row.prop(item, "attraction", index=other, text=f"{other + 1}")


# prop_search that accepts any typed name (an attribute is not a vertex group) without
# marking it red; Blender before 3.3 lacks the option.
_SUGGESTIONS = ({"results_are_suggestions": True}
                if "results_are_suggestions"
                in bpy.types.UILayout.bl_rna.functions["prop_search"].parameters.keys()
                else {})


def _draw_fields(layout, obj):
    settings = obj.moldtex
    box = layout.box()
    box.label(text="Fields", icon='MOD_MASK')
    box.row().prop(settings, "fields_source", expand=True)
    if settings.fields_source == 'IMAGE':
        _prop(_split(box), settings, "fields_image")
        if settings.seed_shape == 'SPAWN_MAP' and settings.fields_image is None:
            _wrapped(box, "Spawn Map needs a Fields image whose red channel marks "
                          "where agents start.", icon='ERROR')
        return
    column = _split(box)
    for name in convert.FIELD_ATTRIBUTES:
        column.prop_search(settings, name, obj, "vertex_groups", icon='GROUP_VERTEX',
                           **_SUGGESTIONS)
    if settings.seed_shape == 'SPAWN_MAP' and not settings.spawn_attribute:
        _wrapped(box, "Spawn Map needs a Spawn vertex group or attribute.", icon='ERROR')
    _wrapped(box, "A vertex group, or a Float or Color attribute per vertex or face "
                  "corner (colours by brightness). Obstacle: walls where above 0.5; "
                  "Attractor: 0 to 1. Read after modifiers; ones that rebuild the mesh "
                  "(Remesh) drop vertex groups. After painting, press Reset.",
             icon='INFO')


def _draw_food(layout, obj):
    settings = obj.moldtex
    box = layout.box()
    box.label(text="Food", icon='FORCE_FORCE')
    column = _split(box)
    _prop(column, settings, "food_collection")
    box.operator("moldtex.food_at_cursor", icon='PIVOT_CURSOR')
    column = _split(box)
    _prop(column, settings, "hunger_rate")
    _prop(column, settings, "food_radius")
    if settings.food_collection is None:
        _wrapped(box, "Pick a collection of Empties: each is a food source "
                      "(custom properties moldtex_strength, moldtex_amount).", icon='INFO')
        return
    status = live.food_status(obj)
    if status is None:
        try:
            sources, dropped = live.food_from_settings(obj)
        except MeshExportError as error:  # e.g. a scale of 0: no world-to-mesh map
            _wrapped(box, str(error), icon='ERROR')
            return
        status = [(name, amount) for name, _position, _strength, amount in sources]
    else:
        entry = live.get(obj.name)
        dropped = entry.food_dropped if entry is not None else 0
    if not status:
        _wrapped(box, f"No Empties in '{settings.food_collection.name}'.", icon='ERROR')
    column = box.column(align=True)
    for name, amount in status:
        row = column.row()
        row.label(text=name, icon='EMPTY_AXIS')
        row.label(text="∞" if amount < 0 else f"{amount:.0f} left")
    if dropped:
        _wrapped(box, f"{dropped} more Empties ignored (at most 64 food sources).",
                 icon='ERROR')
    if settings.hunger_rate <= 0.0:
        _wrapped(box, "Hunger Rate is 0: the agents ignore the food.", icon='INFO')


def _bake_progress_text(progress, plan=None):
    if not progress:
        return "starting"
    continuous = plan is not None and plan.continuous
    text = bake.progress_line(progress, continuous)
    if progress["frames_done"] and continuous:
        text = f"{text.split(' (')[0]}, mean u / U {progress['coverage']:.3f}"
    elif progress["frames_done"]:
        text = (f"{text.split(' (')[0]}, coverage {100.0 * progress['coverage']:.1f} %, "
                f"presence {100.0 * progress['presence']:.1f} %")
    return text


class MOLDTEX_PT_bake(_SubPanel, bpy.types.Panel):
    bl_label = "Bake Sequence"
    bl_idname = "MOLDTEX_PT_bake"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        obj = context.active_object
        settings = obj.moldtex
        entry = live.get(obj.name)
        baking = entry is not None and entry.baking
        layout = self.layout

        column = layout.column(align=True)
        column.enabled = not baking
        column.prop(settings, "bake_use_scene_range")
        column = _split(column)
        if not settings.bake_use_scene_range:
            _prop(column, settings, "bake_frame_start")
            _prop(column, settings, "bake_frame_end")
        for name in ("bake_steps_per_frame", "bake_directory", "bake_format",
                     "bake_prefix"):
            _prop(column, settings, name)
        row = layout.row()
        row.enabled = not baking
        row.prop(settings, "bake_resume")
        scene = getattr(context, "scene", None)
        if scene is not None:
            try:
                plan = bake.plan_for(obj, scene)
                _wrapped(layout, f"{plan.frame_count} frames: {plan.describe_files()}",
                         icon='FILE_IMAGE')
                note = bake.clipping_note(obj, plan)
                if note:
                    _wrapped(layout, note, icon='ERROR')
                if not baking and not settings.bake_resume:
                    _wrapped(layout, "Bakes from step 0 (restarts the simulation as "
                                     "Reset does): the live state is not kept.",
                             icon='INFO')
            except bake.BakeError as error:
                _wrapped(layout, str(error), icon='ERROR')

        column = layout.column(align=True)
        row = column.row(align=True)
        row.scale_y = 1.4
        if baking:
            row.operator("moldtex.bake", text="Cancel Bake", icon='CANCEL')
        else:
            row.operator("moldtex.bake", text="Bake Sequence", icon='RENDER_ANIMATION')
        column.operator("moldtex.use_baked_sequence", icon='SEQUENCE')

        if entry is None:
            return
        if baking:
            timing = bake.timing_text(entry)
            _wrapped(layout, "Baking: " + _bake_progress_text(entry.bake_progress,
                                                              entry.bake_plan) +
                     (f"; {timing}" if timing else "") + ". Esc cancels.", icon='TIME')
        elif entry.bake_summary:
            _wrapped(layout, entry.bake_summary, icon='INFO')


class MOLDTEX_PT_brush(_SubPanel, bpy.types.Panel):
    bl_label = "Brush"
    bl_idname = "MOLDTEX_PT_brush"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        obj = context.active_object
        settings = context.scene.moldtex_brush
        layout = self.layout
        row = layout.row(align=True)
        row.scale_y = 1.4
        row.operator("moldtex.brush_paint", icon='BRUSH_DATA')
        row.prop(obj.moldtex, "show_fields", text="", icon='HIDE_OFF')
        for note in invalid_enum_notes(settings):
            _wrapped(layout, note, icon='ERROR')
        _prop(_split(layout), settings, "target")
        row = layout.row(align=True)
        row.prop(settings, "erase", toggle=True, icon='REMOVE' if settings.erase else 'ADD',
                 text="Erase" if settings.erase else "Add")
        column = _split(layout)
        _prop(column, settings, "radius")
        if settings.target != 'FOOD':  # an Empty is placed or removed whole
            _prop(column, settings, "strength")
            _prop(column, settings, "falloff")
        if settings.target in brush.FIELD_CHANNELS:
            if obj.moldtex.fields_source != 'IMAGE':
                _wrapped(layout, "Fields come from vertex groups or attributes: the brush "
                                 "paints only a Fields image.", icon='ERROR')
            elif obj.moldtex.fields_image is None:
                _wrapped(layout, "The first stroke makes a Fields image.", icon='INFO')
        elif settings.target == 'SLIME' and not _model(obj).has_agents:
            _wrapped(layout, _model(obj).slime_note, icon='INFO')
        elif settings.target == 'SLIME':
            _prop(column, settings, "agents_per_dab")
            if obj.moldtex.species_count > 1:
                _prop(column, settings, "species")
            _wrapped(layout, "Agents join the live simulation (Reset removes them).",
                     icon='INFO')
        else:
            _prop(column, settings, "food_strength")
            _prop(column, settings, "food_amount")
        done, undone = brush.counts(obj.name)
        row = layout.row(align=True)
        sub = row.row(align=True)
        sub.enabled = done > 0
        sub.operator("moldtex.brush_undo", icon='LOOP_BACK', text=f"Undo ({done})")
        sub = row.row(align=True)
        sub.enabled = undone > 0
        sub.operator("moldtex.brush_redo", icon='LOOP_FORWARDS', text=f"Redo ({undone})")


# The sidebar shows sub-panels in registration order: the models' own (each drawn only
# for its model) after the main panel, then the Maps sub-panel and the shared ones.
CLASSES = ((MOLDTEX_PT_main,) + tuple(panel for model in models.MODELS for panel in model.panels)
           + (MOLDTEX_PT_continuous_maps, MOLDTEX_PT_species, MOLDTEX_PT_brush,
              MOLDTEX_PT_map_tools, MOLDTEX_PT_setup, MOLDTEX_PT_bake))
# (Resolution, Agents and Steps per Update are on the main panel; the Simulation
# sub-panel keeps what is changed rarely: seed, backend, threads, image.)


register, unregister = bpy.utils.register_classes_factory(CLASSES)
