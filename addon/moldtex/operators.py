# SPDX-License-Identifier: GPL-3.0-or-later
"""Start/Pause (modal), Step (synchronous), Reset and Set Up Material.

All act on the active object. Problems with the user's object or the core (a
MeshExportError or EngineError) are reported with self.report({'ERROR'}, ...) and the
operator returns {'CANCELLED'}; the modal Start also stops cleanly on anything else.
"""

import time

import bpy
from bpy.props import IntProperty

from . import engine, image_io, live, material
from .mesh_export import MeshExportError, check_object, resolve_uv_map_name

USER_ERRORS = (MeshExportError, engine.EngineError)

_STEP_CHUNK = 25  # steps between two progress updates of a long Step
_TIMER_INTERVAL = 1.0 / 30.0  # seconds between image updates while running


def _active_object(context):
    obj = context.active_object
    check_object(obj)
    return obj


def _show(entry, obj):
    """Copies the pheromone into the object's image."""
    sim = entry.sim
    image = image_io.ensure_image(obj, sim.width, sim.height)
    image_io.upload(image, live.read_pixels(entry))
    return image


def _tag_redraw(context):
    screen = context.screen
    if screen is None:
        return
    for area in screen.areas:
        if area.type in {'VIEW_3D', 'IMAGE_EDITOR', 'NODE_EDITOR', 'PROPERTIES'}:
            area.tag_redraw()


def _report_notice(operator, entry):
    if entry.warning:  # e.g. the chosen OpenCL device is not on this machine
        operator.report({'WARNING'}, entry.warning)
        entry.warning = ""
    if entry.notice:
        operator.report({'INFO'}, entry.notice)
        entry.notice = ""


class MOLDTEX_OT_step(bpy.types.Operator):
    """Advance the simulation by some steps and update the image (works in background)"""
    bl_idname = "moldtex.step"
    bl_label = "Step"
    bl_options = {'REGISTER'}

    steps: IntProperty(name="Steps", default=1, min=1, max=10_000_000,
                       description="Number of simulation steps to run")

    def execute(self, context):
        try:
            obj = _active_object(context)
            entry = live.ensure(obj, context.evaluated_depsgraph_get())
            _report_notice(self, entry)
            remaining = self.steps
            window_manager = context.window_manager
            progress = remaining > _STEP_CHUNK and not bpy.app.background
            if progress:
                window_manager.progress_begin(0, remaining)
            try:
                while remaining > 0:
                    chunk = min(remaining, _STEP_CHUNK) if progress else remaining
                    live.step(entry, obj, chunk)
                    remaining -= chunk
                    if progress:
                        window_manager.progress_update(self.steps - remaining)
            finally:
                if progress:
                    window_manager.progress_end()
            _show(entry, obj)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        _tag_redraw(context)
        return {'FINISHED'}


class MOLDTEX_OT_reset(bpy.types.Operator):
    """Restart the simulation from the current settings (applies resolution, agents, \
seed, backend and UV map)"""
    bl_idname = "moldtex.reset"
    bl_label = "Reset"
    bl_options = {'REGISTER'}

    def execute(self, context):
        try:
            obj = _active_object(context)
            entry = live.ensure(obj, context.evaluated_depsgraph_get(), rebuild=True)
            material.sync_uv_map(obj, entry.uv_map)
            _report_notice(self, entry)
            _show(entry, obj)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        _tag_redraw(context)
        return {'FINISHED'}


class MOLDTEX_OT_start(bpy.types.Operator):
    """Grow the mold live in the viewport; press again (or Esc) to pause"""
    bl_idname = "moldtex.start"
    bl_label = "Start"
    bl_options = {'REGISTER'}

    _timer = None
    _name = ""
    _last_update = 0.0

    def execute(self, context):
        return self.invoke(context, None)

    def invoke(self, context, event):
        obj = context.active_object
        entry = live.get(obj.name) if obj is not None else None
        if entry is not None and entry.running:
            entry.stop_requested = True  # the running modal pauses on its next tick
            return {'FINISHED'}
        if bpy.app.background or context.window is None:
            self.report({'ERROR'}, "Start needs Blender's interface (timers do not run "
                                   "in background mode): use moldtex.step instead.")
            return {'CANCELLED'}
        try:
            check_object(obj)
            entry = live.ensure(obj, context.evaluated_depsgraph_get(),
                                rebuild=live.needs_reset(obj))
            material.sync_uv_map(obj, entry.uv_map)
            _report_notice(self, entry)
            _show(entry, obj)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        entry.running = True
        entry.stop_requested = False
        self._name = obj.name
        window_manager = context.window_manager
        self._timer = window_manager.event_timer_add(_TIMER_INTERVAL, window=context.window)
        window_manager.modal_handler_add(self)
        _tag_redraw(context)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if event.type == 'ESC' and event.value == 'PRESS':
            self._finish(context)
            return {'FINISHED'}
        # Every timer's events arrive as 'TIMER' (the event does not say whose), so
        # pace the updates by the clock rather than by the count of events.
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        now = time.perf_counter()
        if now - self._last_update < 0.8 * _TIMER_INTERVAL:
            return {'PASS_THROUGH'}
        self._last_update = now
        entry = live.get(self._name)
        obj = bpy.data.objects.get(self._name)
        if entry is None or obj is None or entry.sim is None or entry.stop_requested:
            self._finish(context)
            return {'FINISHED'}
        try:
            entry = live.ensure(obj, context.evaluated_depsgraph_get())
            _report_notice(self, entry)
            live.step(entry, obj, obj.moldtex.steps_per_update)
            _show(entry, obj)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            self._finish(context)
            return {'CANCELLED'}
        except Exception as error:  # never leave a dead modal marked as running
            self.report({'ERROR'}, f"Moldtex stopped: {error}")
            self._finish(context)
            raise
        _tag_redraw(context)
        return {'PASS_THROUGH'}

    def cancel(self, context):
        self._finish(context)

    def _finish(self, context):
        if self._timer is not None:
            context.window_manager.event_timer_remove(self._timer)
            self._timer = None
        entry = live.get(self._name)
        if entry is not None:
            entry.running = False
            entry.stop_requested = False
        _tag_redraw(context)


class MOLDTEX_OT_setup_material(bpy.types.Operator):
    """Create the pheromone image and wire it through a color ramp into the active \
material's Base Color (keeps your nodes; safe to run again)"""
    bl_idname = "moldtex.setup_material"
    bl_label = "Set Up Material"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        try:
            obj = _active_object(context)
        except MeshExportError as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        settings = obj.moldtex
        uv_map = live.uv_map_in_use(obj) or resolve_uv_map_name(obj, settings.uv_map)
        if not uv_map or uv_map not in obj.data.uv_layers:
            if len(obj.data.uv_layers) == 0:
                self.report({'ERROR'}, f"Object '{obj.name}' has no UV map: add one "
                                       f"(UV ▸ Smart UV Project in Edit Mode) first.")
            else:
                self.report({'ERROR'}, f"Object '{obj.name}' has no UV map named "
                                       f"'{uv_map}': pick one in the Moldtex panel.")
            return {'CANCELLED'}
        entry = live.get(obj.name)
        if entry is not None and entry.sim is not None:
            width, height = entry.sim.width, entry.sim.height
        else:
            width = height = int(settings.resolution)
        image = image_io.ensure_image(obj, width, height)
        if entry is not None and entry.sim is not None:
            try:
                image_io.upload(image, live.read_pixels(entry))
            except engine.EngineError as error:
                self.report({'WARNING'}, str(error))
        material.setup_material(obj, image, uv_map)
        return {'FINISHED'}


CLASSES = (MOLDTEX_OT_step, MOLDTEX_OT_reset, MOLDTEX_OT_start, MOLDTEX_OT_setup_material)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
