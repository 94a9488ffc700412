# SPDX-License-Identifier: GPL-3.0-or-later
"""Start/Pause (modal), Step (synchronous), Reset, Set Up Material, Bake (modal, or
synchronous in background mode and from scripts) and Use Baked Sequence.

All act on the active object (Bake and Use Baked Sequence also take object_name).
Problems with the user's object, settings or the core (a MeshExportError, BakeError or
EngineError) are reported with self.report({'ERROR'}, ...) and the operator returns
{'CANCELLED'}; the modal operators also stop cleanly on anything else.
"""

import time

import bpy
from bpy.props import BoolProperty, IntProperty, StringProperty

from ..bake import sequence as bake
from .. import engine
from ..data import image_io, vertex_colours
from ..sim import convert
from ..sim import session as live
from ..colour import material
from ..data.mesh_export import MeshExportError, check_object, no_uv_map_message, resolve_uv_map_name
from ..settings.properties import BAKE_FORMAT_ITEMS

USER_ERRORS = (MeshExportError, bake.BakeError, engine.EngineError)

_STEP_CHUNK = 25  # steps between two progress updates of a long Step
_TIMER_INTERVAL = 1.0 / 30.0  # seconds between image updates while running


def _active_object(context):
    obj = context.active_object
    check_object(obj)
    return obj


def _show(entry, obj):
    """Copies the pheromone into the object's image (a mesh without UVs: into its
    vertex colours, returning None)."""
    if entry.vertex_colours:
        if not entry.vertex_problem:  # (else they would not follow: the panel says so)
            vertex_colours.write(obj, live.read_vertex_pixels(entry))
            live.note_own_geometry_write(obj.name)
        material.sync_display_range(obj)
        return None
    sim = entry.sim
    image = image_io.ensure_image(obj, sim.width, sim.height)
    image_io.upload(image, live.read_pixels(entry))
    material.show_image(obj, image)  # back from a baked sequence to the live image
    material.sync_display_range(obj)  # the ramp spans what this model's image holds
    return image


def _tag_redraw(context):
    screen = context.screen
    if screen is None:
        return
    for area in screen.areas:
        if area.type in {'VIEW_3D', 'IMAGE_EDITOR', 'NODE_EDITOR', 'PROPERTIES'}:
            area.tag_redraw()


def ensure_material(obj, entry):
    """Sets up obj's material (as Set Up Material does) when it has no Moldtex image
    node, so that Start shows the growth even if Set Up Material was not pressed.
    Returns a line for the user, or "" when the material was already set up."""
    if entry.vertex_colours:
        if material.moldtex_node(obj, material.VERTEX_NODE) is not None:
            return ""
        material.setup_material(obj, None, "")
        return (f"Set up the material of '{obj.name}' (its vertex colours '"
                f"{vertex_colours.ATTRIBUTE}' through a colour ramp into Base Color: it has "
                f"no UV map): switch the viewport to Material Preview to watch.")
    if material.moldtex_node(obj, material.TEXTURE_NODE) is not None:
        return ""
    image = image_io.ensure_image(obj, entry.sim.width, entry.sim.height)
    material.setup_material(obj, image, entry.uv_map)
    return (f"Set up the material of '{obj.name}' (the pheromone image through a colour "
            f"ramp into Base Color): switch the viewport to Material Preview to watch.")


def _report_notice(operator, entry):
    if entry.warning:  # e.g. the chosen OpenCL device is not on this machine
        operator.report({'WARNING'}, entry.warning)
        entry.warning = ""
    if entry.notice:
        operator.report({'INFO'}, entry.notice)
        entry.notice = ""


# A Step whose steps would take longer than this runs modally: progress in the status
# bar and the image, Esc stops it, and the interface keeps working in between.
_STEP_MODAL_SECONDS = 0.3
_STEP_TICK_SECONDS = 0.1  # stepping per tick of a modal Step


def _status(context, text, header=False):
    """Shows text in the status bar (and the area's header), or clears it with None."""
    try:
        if context.workspace is not None:
            context.workspace.status_text_set(text)
        if header and context.area is not None:
            context.area.header_text_set(text)
    except (AttributeError, RuntimeError):
        pass


def _end_modal_progress(operator, context, header=False):
    """Removes a modal operator's timer and progress bar and clears its texts."""
    if operator._timer is not None:
        context.window_manager.event_timer_remove(operator._timer)
        operator._timer = None
        context.window_manager.progress_end()
    _status(context, None, header)


class MOLDTEX_OT_step(bpy.types.Operator):
    """Advance the simulation by some steps and update the image (change the count in \
Adjust Last Operation; long runs show their progress, Esc stops them; works in \
background)"""
    bl_idname = "moldtex.step"
    bl_label = "Step"
    bl_options = {'REGISTER', 'UNDO'}

    steps: IntProperty(name="Steps", default=1, min=1, max=10_000_000, soft_max=10_000,
                       description="Number of simulation steps to run")

    _timer = None
    _name = ""
    _done = 0

    def _prepare(self, context):
        obj = _active_object(context)
        entry = live.ensure(obj, context.evaluated_depsgraph_get())
        _report_notice(self, entry)
        # Adjust Last Operation runs the operator again (options.is_repeat; not
        # is_repeat(), which is also true for a second Step in a row): start from where
        # the Step being adjusted started, so that "Steps" means that many in all.
        if self.options.is_repeat:
            live.restore_step_snapshot(entry)
        live.save_step_snapshot(entry)
        return obj, entry

    # ---- synchronous: scripts, background mode, Adjust Last Operation ----
    def execute(self, context):
        try:
            obj, entry = self._prepare(context)
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
            live.note_step_end(entry)
            _show(entry, obj)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        _tag_redraw(context)
        return {'FINISHED'}

    # ---- the Step button: short runs at once, long ones modally ----
    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        try:
            obj, entry = self._prepare(context)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        if entry.running:
            self.report({'ERROR'}, "The simulation is running: pause it (Start) to step.")
            return {'CANCELLED'}
        estimate = entry.step_seconds * self.steps
        if self.steps <= 2 or (entry.step_seconds > 0.0
                               and estimate < _STEP_MODAL_SECONDS):
            try:
                live.step(entry, obj, self.steps)
                live.note_step_end(entry)
                _show(entry, obj)
            except USER_ERRORS as error:
                self.report({'ERROR'}, str(error))
                return {'CANCELLED'}
            _tag_redraw(context)
            return {'FINISHED'}
        self._name = obj.name
        self._done = 0
        window_manager = context.window_manager
        window_manager.progress_begin(0, self.steps)
        self._timer = window_manager.event_timer_add(0.02, window=context.window)
        window_manager.modal_handler_add(self)
        entry.stepping = True
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if event.type == 'ESC' and event.value == 'PRESS':
            self.report({'WARNING'}, f"Stopped after {self._done:,} of {self.steps:,} "
                                     f"steps.")
            self.steps = max(1, self._done)  # what Adjust Last Operation then shows
            return self._end(context, {'FINISHED'})
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        entry = live.get(self._name)
        obj = bpy.data.objects.get(self._name)
        if entry is None or obj is None or entry.sim is None:
            return self._end(context, {'CANCELLED'})
        try:
            self._done += live.step_for_time(entry, obj, _STEP_TICK_SECONDS,
                                             max_steps=self.steps - self._done)
            _show(entry, obj)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return self._end(context, {'CANCELLED'})
        context.window_manager.progress_update(self._done)
        _status(context, f"Moldtex: step {self._done:,}/{self.steps:,} — Esc to stop")
        _tag_redraw(context)
        if self._done >= self.steps:
            return self._end(context, {'FINISHED'})
        return {'RUNNING_MODAL'}

    def cancel(self, context):
        self._end(context, {'CANCELLED'})

    def _end(self, context, result):
        _end_modal_progress(self, context)
        entry = live.get(self._name)
        if entry is not None:
            entry.stepping = False
            live.note_step_end(entry)
        _tag_redraw(context)
        return result


class _DomainBuildPhase:
    """Start and Reset, pressed in the interface, first build an Intrinsic domain on the
    core's thread: its progress shows in the status bar, the cursor and the panel, the
    interface keeps working, and Esc cancels it (nothing is kept, the simulation stays as
    it was). Without a build to make (the Texture domain, or a recent build of the same
    mesh and size) the operator goes on at once."""

    _domain_build = None

    def begin_domain_build(self, context, obj, rebuild):
        """True when a build runs (the caller returns RUNNING_MODAL; on_domain_built is
        called when it is done)."""
        build = live.start_domain_build(obj, context.evaluated_depsgraph_get(), rebuild)
        if build is None:
            return False
        if not build.running() and build.progress()["state"] == engine.BAKE_FINISHED:
            live.end_domain_build(obj.name, finished=True)  # (the cache had it)
            return False
        self._domain_build = build
        self._name = obj.name
        window_manager = context.window_manager
        self._timer = window_manager.event_timer_add(0.1, window=context.window)
        window_manager.progress_begin(0, 100)
        window_manager.modal_handler_add(self)
        _status(context, live.domain_build_text(build.progress()) + " — Esc cancels")
        return True

    def domain_build_modal(self, context, event):
        """The modal step while the build runs: 'RUNNING', 'DONE', or 'STOPPED' (cancelled
        or failed: reported, and the operator should end with CANCELLED)."""
        build = self._domain_build
        if event.type == 'ESC' and event.value == 'PRESS':
            build.cancel()
        if event.type not in {'TIMER', 'ESC'}:
            return 'RUNNING'
        progress = build.progress()
        if progress["state"] == engine.BAKE_RUNNING:
            context.window_manager.progress_update(int(100 * progress["fraction"]))
            _status(context, live.domain_build_text(progress) + " — Esc cancels")
            _tag_redraw(context)
            return 'RUNNING'
        _end_modal_progress(self, context)
        self._domain_build = None
        live.end_domain_build(self._name, finished=progress["state"] == engine.BAKE_FINISHED)
        _tag_redraw(context)
        if progress["state"] == engine.BAKE_FINISHED:
            return 'DONE'
        if progress["state"] == engine.BAKE_CANCELLED:
            self.report({'INFO'}, "Building the intrinsic triangulation was cancelled.")
        else:
            self.report({'ERROR'}, progress["message"] or "Building the intrinsic triangulation failed.")
        return 'STOPPED'

    def domain_build_then(self, context, event, then):
        """The modal step of an operator whose build runs: waits for it, ends with
        CANCELLED when it was cancelled or failed, else returns then(context, obj)."""
        outcome = self.domain_build_modal(context, event)
        if outcome == 'RUNNING':
            return {'PASS_THROUGH'} if event.type != 'ESC' else {'RUNNING_MODAL'}
        obj = bpy.data.objects.get(self._name)
        if outcome == 'STOPPED' or obj is None:
            return {'CANCELLED'}
        return then(context, obj)

    def cancel_domain_build(self, context):
        if self._domain_build is not None:
            _end_modal_progress(self, context)
            self._domain_build = None
            live.end_domain_build(self._name)


class MOLDTEX_OT_reset(_DomainBuildPhase, bpy.types.Operator):
    """Restart the simulation from the current settings (applies resolution, agents, \
seed, backend and UV map)"""
    bl_idname = "moldtex.reset"
    bl_label = "Reset"
    bl_options = {'REGISTER'}

    _timer = None
    _name = ""

    def invoke(self, context, event):
        if live.cancel_domain_build(context.active_object):  # pressed again: cancel
            return {'FINISHED'}
        if context.window is not None and not bpy.app.background:
            try:
                obj = _active_object(context)
                if self.begin_domain_build(context, obj, rebuild=True):
                    return {'RUNNING_MODAL'}
            except USER_ERRORS as error:
                self.report({'ERROR'}, str(error))
                return {'CANCELLED'}
        return self.execute(context)

    def modal(self, context, event):
        return self.domain_build_then(context, event, lambda context, _obj: self.execute(context))

    def cancel(self, context):
        self.cancel_domain_build(context)

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


class MOLDTEX_OT_start(_DomainBuildPhase, bpy.types.Operator):
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
        if live.cancel_domain_build(obj):  # pressed again while building: cancel
            return {'FINISHED'}
        entry = live.get(obj.name) if obj is not None else None
        if entry is not None and entry.running:
            entry.stop_requested = True  # the running modal pauses on its next tick
            return {'FINISHED'}
        if entry is not None and entry.baking:
            self.report({'ERROR'}, live.bake_running_message(entry, "Cannot start"))
            return {'CANCELLED'}
        if entry is not None and entry.stepping:
            self.report({'ERROR'}, "A Step is running: wait for it, or press Esc.")
            return {'CANCELLED'}
        if bpy.app.background or context.window is None:
            self.report({'ERROR'}, "Start needs Blender's interface (timers do not run "
                                   "in background mode): use moldtex.step instead.")
            return {'CANCELLED'}
        try:
            check_object(obj)
            if self.begin_domain_build(context, obj, rebuild=live.needs_reset(obj)):
                return {'RUNNING_MODAL'}  # then begin_running
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        return self.begin_running(context, obj)

    def begin_running(self, context, obj, modal_added=False):
        try:
            entry = live.ensure(obj, context.evaluated_depsgraph_get(),
                                rebuild=live.needs_reset(obj))
            material.sync_uv_map(obj, entry.uv_map)
            _report_notice(self, entry)
            note = ensure_material(obj, entry)
            if note:
                self.report({'INFO'}, note)
            _show(entry, obj)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        entry.running = True
        entry.stop_requested = False
        self._name = obj.name
        window_manager = context.window_manager
        self._timer = window_manager.event_timer_add(_TIMER_INTERVAL, window=context.window)
        if not modal_added:
            window_manager.modal_handler_add(self)
        _tag_redraw(context)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if self._domain_build is not None:  # (begin_running: RUNNING_MODAL or CANCELLED)
            return self.domain_build_then(
                context, event, lambda context, obj: self.begin_running(context, obj, modal_added=True))
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
        entry = live.get(self._name)
        obj = bpy.data.objects.get(self._name)
        if entry is None or obj is None or not entry.has_sim or entry.stop_requested:
            self._finish(context)
            return {'FINISHED'}
        settings = obj.moldtex
        threaded = settings.steps_per_update == 0
        if threaded and live.stepper_waiting(entry):
            return {'PASS_THROUGH'}  # nothing new grown yet: no upload, no redraw
        self._last_update = now
        try:
            # Time-paced (Steps per Update 0): a thread grew the mold since the last
            # update, while Blender redrew; collect its steps, update, let it go on.
            steps = live.take_grown_steps(entry)
            entry = live.ensure(obj, context.evaluated_depsgraph_get())
            _report_notice(self, entry)
            live.poll_fields_image(entry, obj)
            if threaded:
                live.prepare_step(entry, obj)
                entry.food_left = entry.sim.get_food()  # for the panel (food_status)
            else:
                live.step(entry, obj, settings.steps_per_update)
                steps += settings.steps_per_update
            now = time.perf_counter()
            live.note_update(entry, steps, now, now)
            _show(entry, obj)
            if threaded:
                live.start_stepper(entry, settings.update_time / 1000.0)
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
        if self._domain_build is not None:
            self.cancel_domain_build(context)
            return
        self._finish(context)

    def _finish(self, context):
        if self._timer is not None:
            context.window_manager.event_timer_remove(self._timer)
            self._timer = None
        entry = live.get(self._name)
        if entry is not None:
            try:
                live.stop_stepper(entry)
            except Exception as error:  # noqa: BLE001 (it is reported, then dropped)
                self.report({'ERROR'}, f"Moldtex stopped: {error}")
            if entry.has_sim:
                try:  # show the steps grown since the last update
                    obj = bpy.data.objects.get(self._name)
                    if obj is not None and not entry.baking:
                        entry.stats = entry.sim.get_stats()
                        _show(entry, obj)
                except USER_ERRORS:
                    pass
            entry.running = False
            entry.stop_requested = False
            live.stop_pacing(entry)
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
        entry = live.get(obj.name)
        on_vertices = entry is not None and entry.has_sim and entry.vertex_colours
        if ((len(obj.data.uv_layers) == 0 or on_vertices)
                and convert.domain_of(settings) == engine.DOMAIN_INTRINSIC):
            material.setup_material(obj, None, "")  # the vertex colours (no usable UV map)
            if on_vertices and not entry.baking:
                _show(entry, obj)
            return {'FINISHED'}
        if not uv_map or uv_map not in obj.data.uv_layers:
            if len(obj.data.uv_layers) == 0:
                self.report({'ERROR'}, no_uv_map_message(obj.name))
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
        if entry is not None and entry.sim is not None and not entry.baking:
            try:
                image_io.upload(image, live.read_pixels(entry))
            except engine.EngineError as error:
                self.report({'WARNING'}, str(error))
        material.setup_material(obj, image, uv_map)
        return {'FINISHED'}


def _named_or_active_object(context, name):
    if name:
        obj = bpy.data.objects.get(name)
        if obj is None:
            raise MeshExportError(f"There is no object named '{name}' in this file.")
    else:
        obj = context.active_object
    check_object(obj)
    return obj


_FORMAT_NAMES = {identifier: label for identifier, label, _ in BAKE_FORMAT_ITEMS}


class MOLDTEX_OT_bake(_DomainBuildPhase, bpy.types.Operator):
    """Bake the growth into an image sequence, one file per frame, from the current \
settings (restarts the simulation as Reset does). Press again or Esc to cancel"""
    bl_idname = "moldtex.bake"
    bl_label = "Bake Sequence"
    bl_options = {'REGISTER'}

    object_name: StringProperty(
        name="Object", default="", options={'SKIP_SAVE'},
        description="Object to bake (empty = the active object)")
    use_sequence: BoolProperty(
        name="Play Back", default=True, options={'SKIP_SAVE'},
        description="When the bake is done, show the baked sequence in the material")

    _job = None
    _timer = None
    _window = None
    _name = ""

    # ---- synchronous: scripts (EXEC_DEFAULT), background mode, the command line ----
    def execute(self, context):
        try:
            obj = _named_or_active_object(context, self.object_name)
            plan = bake.plan_for(obj, context.scene)
            job = bake.BakeJob(obj, context.evaluated_depsgraph_get(), plan)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        print(f"Moldtex bake: '{obj.name}', {self._describe(plan)}")
        note = bake.clipping_note(obj, plan)
        if note:
            self.report({'WARNING'}, note)
        try:
            progress = bake.run_synchronously(job)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        return self._done(obj.name, plan, progress)

    # ---- modal: the Bake button ----
    def invoke(self, context, event):
        try:
            obj = _named_or_active_object(context, self.object_name)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        entry = live.get(obj.name)
        if entry is not None and entry.baking:
            entry.bake_cancel_requested = True  # the running modal cancels on its tick
            return {'FINISHED'}
        if bpy.app.background or context.window is None:
            return self.execute(context)
        if live.cancel_domain_build(obj):  # pressed again while its domain builds
            return {'FINISHED'}
        try:
            if self.begin_domain_build(context, obj, rebuild=True):
                return {'RUNNING_MODAL'}  # then _start_bake
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        return self._start_bake(context, obj)

    def _start_bake(self, context, obj, modal_added=False):
        try:
            plan = bake.plan_for(obj, context.scene)
            self._job = bake.BakeJob(obj, context.evaluated_depsgraph_get(), plan)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        note = bake.clipping_note(obj, plan)
        if note:
            self.report({'WARNING'}, note)
        window_manager = context.window_manager
        window_manager.progress_begin(0, max(1, plan.frame_count))
        self._window = context.window
        self._timer = window_manager.event_timer_add(0.1, window=context.window)
        if not modal_added:
            window_manager.modal_handler_add(self)
        self._show_progress(context, self._job.progress)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if self._domain_build is not None:
            return self.domain_build_then(
                context, event, lambda context, obj: self._start_bake(context, obj, modal_added=True))
        job = self._job
        if job is None:
            return {'CANCELLED'}
        if event.type == 'ESC' and event.value == 'PRESS':
            job.cancel()
            return self._end(context)
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        try:
            if job.cancel_requested:
                job.cancel()
                return self._end(context)
            progress = job.poll()
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            self._cleanup(context)
            return {'CANCELLED'}
        self._show_progress(context, progress)
        if progress["state"] != engine.BAKE_RUNNING:
            return self._end(context)
        return {'PASS_THROUGH'}

    def cancel(self, context):
        # Blender ends the modal (another file is loaded, Blender quits): stop the bake.
        self.cancel_domain_build(context)
        if self._job is not None:
            self._job.cancel()
            try:
                self._job.finish()
            except USER_ERRORS:
                pass
        self._cleanup(context)

    def _end(self, context):
        job = self._job
        try:
            progress = job.finish()
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            self._cleanup(context)
            return {'CANCELLED'}
        self._cleanup(context)
        return self._done(job.name, job.plan, progress)

    def _done(self, name, plan, progress):
        entry = live.get(name)
        summary = entry.bake_summary if entry is not None else ""
        if progress["state"] == engine.BAKE_CANCELLED:
            self.report({'WARNING'}, summary or "Bake cancelled.")
            return {'CANCELLED'}
        obj = bpy.data.objects.get(name)
        if self.use_sequence and obj is not None:
            try:
                bake.use_sequence(obj, plan)
            except (bake.BakeError, RuntimeError) as error:
                self.report({'WARNING'}, f"Baked, but the sequence could not be shown: "
                                         f"{error}")
                return {'FINISHED'}
        self.report({'INFO'}, summary)
        return {'FINISHED'}

    @staticmethod
    def _describe(plan):
        return (f"frames {plan.first_frame}–{plan.last_frame}, {plan.steps_per_frame} "
                f"steps per frame, {_FORMAT_NAMES.get(plan.format_id, plan.format_id)}"
                f"{', resuming' if plan.resume else ''} into {plan.directory}")

    def _show_progress(self, context, progress):
        window_manager = context.window_manager
        window_manager.progress_update(progress["frames_done"])
        continuous = self._job is not None and self._job.plan.continuous
        line = bake.progress_line(progress, continuous)
        text = f"Moldtex bake: {line} — Esc to cancel"
        entry = live.get(self._job.name) if self._job is not None else None
        timing = bake.timing_text(entry) if entry is not None else ""
        if timing:
            text = f"Moldtex bake: {line}, {timing} — Esc to cancel"
        _status(context, text, header=True)
        _tag_redraw(context)

    def _cleanup(self, context):
        _end_modal_progress(self, context, header=True)
        self._job = None
        _tag_redraw(context)


class MOLDTEX_OT_use_baked_sequence(bpy.types.Operator):
    """Show the baked image sequence in the material: scene frame f shows baked frame \
f (uses the Bake settings to find the files)"""
    bl_idname = "moldtex.use_baked_sequence"
    bl_label = "Use Baked Sequence"
    bl_options = {'REGISTER', 'UNDO'}

    object_name: StringProperty(
        name="Object", default="", options={'SKIP_SAVE'},
        description="Object whose bake to show (empty = the active object)")

    def execute(self, context):
        try:
            obj = _named_or_active_object(context, self.object_name)
            plan = bake.plan_for(obj, context.scene)
            image, count = bake.use_sequence(obj, plan)
        except USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        last = plan.first_frame + count - 1
        if count < plan.frame_count:
            self.report({'WARNING'}, f"Only frames {plan.first_frame}–{last} of "
                                     f"{plan.first_frame}–{plan.last_frame} are baked; "
                                     f"later frames show frame {last}.")
        else:
            self.report({'INFO'}, f"'{image.name}' plays frames {plan.first_frame}–{last}.")
        _tag_redraw(context)
        return {'FINISHED'}


CLASSES = (MOLDTEX_OT_step, MOLDTEX_OT_reset, MOLDTEX_OT_start, MOLDTEX_OT_setup_material,
           MOLDTEX_OT_bake, MOLDTEX_OT_use_baked_sequence)


register, unregister = bpy.utils.register_classes_factory(CLASSES)
