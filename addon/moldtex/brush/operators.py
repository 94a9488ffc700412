# SPDX-License-Identifier: GPL-3.0-or-later
"""Brush operators: the viewport tool (moldtex.brush_paint, modal), one scripted
stroke (moldtex.brush_stroke, works in background mode) and Undo/Redo Stroke.

The brush settings are the scene's (Scene.moldtex_brush, see brush/session.py); strokes act on
the active object (or object_name).
"""

import math

import bpy
from bpy.props import CollectionProperty, FloatVectorProperty, StringProperty
from mathutils import Vector

from . import session as brush

# Events the viewport tool leaves to Blender: view navigation and the timers that
# drive a running simulation (moldtex.start) and the interface.
_PASS_EVENTS = {
    'MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE', 'WHEELINMOUSE', 'WHEELOUTMOUSE',
    'TRACKPADPAN', 'TRACKPADZOOM', 'MOUSEROTATE', 'MOUSESMARTZOOM',
    'NDOF_MOTION', 'NDOF_BUTTON_MENU', 'NDOF_BUTTON_FIT',
    'NUMPAD_0', 'NUMPAD_1', 'NUMPAD_2', 'NUMPAD_3', 'NUMPAD_4', 'NUMPAD_5', 'NUMPAD_6',
    'NUMPAD_7', 'NUMPAD_8', 'NUMPAD_9', 'NUMPAD_PERIOD', 'NUMPAD_SLASH', 'NUMPAD_PLUS',
    'NUMPAD_MINUS', 'HOME', 'TIMER', 'TIMER0', 'TIMER1', 'TIMER2', 'TIMER_JOBS',
    'TIMER_AUTOSAVE', 'TIMER_REPORT', 'TIMERREGION', 'WINDOW_DEACTIVATE',
}
_RADIUS_STEP = 1.15  # [ and ] scale the radius by this


def _object(context, name):
    obj = bpy.data.objects.get(name) if name else context.active_object
    if obj is None or obj.type != 'MESH':
        raise brush.BrushError("Select the mesh object to paint on (or give object_name).")
    return obj


def _tag_redraw(context):
    screen = context.screen
    if screen is None:
        return
    for area in screen.areas:
        if area.type in {'VIEW_3D', 'IMAGE_EDITOR', 'PROPERTIES'}:
            area.tag_redraw()


class MoldtexStrokePoint(bpy.types.PropertyGroup):
    location: FloatVectorProperty(name="Location", size=3, subtype='XYZ',
                                  description="Ray origin, world space")
    direction: FloatVectorProperty(
        name="Direction", size=3, subtype='XYZ',
        description="Ray direction, world space; (0, 0, 0) = the surface point nearest "
                    "Location")


class MOLDTEX_OT_brush_stroke(bpy.types.Operator):
    """Paint one brush stroke with the scene's Moldtex brush: one dab per point (for \
scripts; works in background mode)"""
    bl_idname = "moldtex.brush_stroke"
    bl_label = "Brush Stroke"
    bl_options = {'REGISTER'}

    stroke: CollectionProperty(type=MoldtexStrokePoint, name="Stroke")
    object_name: StringProperty(name="Object", default="",
                                description="Object to paint on (empty = the active one)")

    def execute(self, context):
        try:
            obj = _object(context, self.object_name)
            stroke = brush.Stroke(context, obj)
            hits = 0
            for point in self.stroke:
                if stroke.dab(tuple(point.location), tuple(point.direction), force=True):
                    hits += 1
            message = stroke.finish()
        except brush.USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        if message:
            self.report({'WARNING'}, message)
        if hits == 0:
            self.report({'WARNING'}, "The stroke missed the surface: nothing was painted.")
            return {'CANCELLED'}
        _tag_redraw(context)
        return {'FINISHED'}


class MOLDTEX_OT_food_at_cursor(bpy.types.Operator):
    """Place a food Empty on the surface point nearest the 3D cursor (one brush stroke: Undo Stroke removes it)"""
    bl_idname = "moldtex.food_at_cursor"
    bl_label = "Food at 3D Cursor"
    bl_options = {'REGISTER'}

    def execute(self, context):
        settings = context.scene.moldtex_brush
        target, erase = settings.target, settings.erase
        settings.target, settings.erase = 'FOOD', False
        try:
            obj = _object(context, "")
            stroke = brush.Stroke(context, obj)
            hit = stroke.dab(tuple(context.scene.cursor.location), (0.0, 0.0, 0.0),
                             force=True)
            message = stroke.finish()
        except brush.USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        finally:
            settings.target, settings.erase = target, erase
        if message or hit is None:
            self.report({'WARNING'}, message or "No surface point found.")
            return {'CANCELLED'}
        _tag_redraw(context)
        return {'FINISHED'}


class _HistoryOperator:
    bl_options = {'REGISTER'}
    object_name: StringProperty(name="Object", default="")

    def execute(self, context):
        try:
            obj = _object(context, self.object_name)
        except brush.BrushError as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        done, message = self.action(obj)
        self.report({'INFO'} if done else {'WARNING'}, message)
        _tag_redraw(context)
        return {'FINISHED'} if done else {'CANCELLED'}


class MOLDTEX_OT_brush_undo(_HistoryOperator, bpy.types.Operator):
    """Undo the last Moldtex brush stroke on this object (fields, slime or food)"""
    bl_idname = "moldtex.brush_undo"
    bl_label = "Undo Stroke"
    action = staticmethod(brush.undo)


class MOLDTEX_OT_brush_redo(_HistoryOperator, bpy.types.Operator):
    """Redo the last undone Moldtex brush stroke on this object"""
    bl_idname = "moldtex.brush_redo"
    bl_label = "Redo Stroke"
    action = staticmethod(brush.redo)


# ---- the viewport tool --------------------------------------------------------------

def _circle_points(centre, normal, radius, segments=48):
    n = Vector(normal).normalized()
    helper = Vector((1.0, 0.0, 0.0)) if abs(n.x) < 0.9 else Vector((0.0, 1.0, 0.0))
    u = n.cross(helper).normalized()
    v = n.cross(u)
    c = Vector(centre) + n * (radius * 0.01)  # just above the surface
    return [tuple(c + radius * (math.cos(a) * u + math.sin(a) * v))
            for a in (2.0 * math.pi * i / segments for i in range(segments))]


def _uniform_shader():
    import gpu
    for name in ('UNIFORM_COLOR', '3D_UNIFORM_COLOR'):  # 4.x / 3.x names
        try:
            return gpu.shader.from_builtin(name)
        except (ValueError, SystemError):
            continue
    return None


def _draw_cursor(operator):
    cursor = operator.cursor
    if cursor is None:
        return
    from gpu_extras.batch import batch_for_shader
    shader = _uniform_shader()
    if shader is None:
        return
    centre, normal, radius, erase = cursor
    points = _circle_points(centre, normal, radius)
    batch = batch_for_shader(shader, 'LINE_LOOP', {"pos": points})
    shader.bind()
    shader.uniform_float("color", (1.0, 0.35, 0.35, 1.0) if erase else (1.0, 1.0, 1.0, 1.0))
    batch.draw(shader)


class MOLDTEX_OT_brush_paint(bpy.types.Operator):
    """Paint on the surface with the Moldtex brush: left-drag paints, E toggles erase, \
[ ] change the radius, Ctrl+Z / Ctrl+Shift+Z undo and redo strokes, Esc or right-click \
ends"""
    bl_idname = "moldtex.brush_paint"
    bl_label = "Paint"
    bl_options = {'REGISTER'}

    def invoke(self, context, event):
        if context.area is None or context.area.type != 'VIEW_3D':
            self.report({'ERROR'}, "Paint from a 3D Viewport (the Moldtex sidebar tab).")
            return {'CANCELLED'}
        try:
            obj = _object(context, "")
        except brush.BrushError as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        for note in brush.repair_settings(context.scene.moldtex_brush):
            self.report({'WARNING'}, note)
        self.obj_name = obj.name
        self.area = context.area
        self.region = next((r for r in context.area.regions if r.type == 'WINDOW'), None)
        self.rv3d = context.area.spaces.active.region_3d
        if self.region is None or self.rv3d is None:
            self.report({'ERROR'}, "This 3D Viewport has no view to paint in.")
            return {'CANCELLED'}
        self.stroke = None
        self.cursor = None
        # Painting fields: lay them over the pheromone while the tool runs.
        self.shown_before = obj.moldtex.show_fields
        if context.scene.moldtex_brush.target in brush.FIELD_CHANNELS:
            obj.moldtex.show_fields = True
        self.handle = bpy.types.SpaceView3D.draw_handler_add(
            _draw_cursor, (self,), 'WINDOW', 'POST_VIEW')
        context.window_manager.modal_handler_add(self)
        self._status(context)
        return {'RUNNING_MODAL'}

    def _status(self, context):
        settings = context.scene.moldtex_brush
        what = dict((item[0], item[1]) for item in brush.TARGETS)[settings.target]
        mode = "erasing" if settings.erase else "painting"
        done, undone = brush.counts(self.obj_name)
        text = (f"Moldtex: {mode} {what} (radius {settings.radius:.3g}) · LMB drag: paint · "
                f"E: erase · [ ]: radius · Ctrl+Z/Ctrl+Shift+Z: undo/redo ({done}/{undone}) "
                f"· Esc/RMB: done")
        if self.area is not None:
            self.area.header_text_set(text)

    def _ray(self, event):
        from bpy_extras import view3d_utils
        region = self.region
        for other in self.area.regions:  # sidebar, toolbar, headers over the view
            if (other.type != 'WINDOW' and other.width > 1 and other.height > 1
                    and other.x <= event.mouse_x < other.x + other.width
                    and other.y <= event.mouse_y < other.y + other.height):
                return None
        coord = (event.mouse_x - region.x, event.mouse_y - region.y)
        if not (0 <= coord[0] < region.width and 0 <= coord[1] < region.height):
            return None
        origin = view3d_utils.region_2d_to_origin_3d(region, self.rv3d, coord)
        direction = view3d_utils.region_2d_to_vector_3d(region, self.rv3d, coord)
        return tuple(origin), tuple(direction)

    def _update_cursor(self, context, hit):
        settings = context.scene.moldtex_brush
        if hit is None or hit.get("world_normal") is None:
            self.cursor = None
        else:
            self.cursor = (hit["world"], hit["world_normal"], settings.radius,
                           settings.erase)

    def _report(self, message, level='WARNING'):
        if message:
            self.report({level}, message)

    def modal(self, context, event):
        try:
            return self._modal(context, event)
        except brush.USER_ERRORS as error:
            self.report({'ERROR'}, str(error))
            self.stroke = None
            return {'RUNNING_MODAL'}
        except Exception:
            self._finish(context)
            raise

    def _modal(self, context, event):
        if bpy.data.objects.get(self.obj_name) is None:
            self._finish(context)
            return {'CANCELLED'}
        settings = context.scene.moldtex_brush
        if event.type in _PASS_EVENTS:
            return {'PASS_THROUGH'}
        if event.type in {'ESC', 'RIGHTMOUSE', 'RET'} and event.value == 'PRESS':
            self._end_stroke()
            self._finish(context)
            return {'FINISHED'}
        if event.type == 'Z' and event.value == 'PRESS' and (event.ctrl or event.oskey):
            self._end_stroke()
            obj = bpy.data.objects[self.obj_name]
            done, message = (brush.redo if event.shift else brush.undo)(obj)
            self._report(message, 'INFO' if done else 'WARNING')
            self._status(context)
            _tag_redraw(context)
            return {'RUNNING_MODAL'}
        if event.type == 'E' and event.value == 'PRESS':
            settings.erase = not settings.erase
        elif event.type in {'LEFT_BRACKET', 'RIGHT_BRACKET'} and event.value == 'PRESS':
            factor = _RADIUS_STEP if event.type == 'RIGHT_BRACKET' else 1.0 / _RADIUS_STEP
            settings.radius = settings.radius * factor
        elif event.type == 'LEFTMOUSE' and event.value == 'PRESS':
            ray = self._ray(event)
            if ray is None:
                return {'PASS_THROUGH'}  # a click on the header, sidebar or toolbar
            self.stroke = brush.Stroke(context, bpy.data.objects[self.obj_name])
            self._update_cursor(context, self.stroke.dab(*ray, force=True))
        elif event.type == 'LEFTMOUSE' and event.value == 'RELEASE':
            self._end_stroke()
        elif event.type in {'MOUSEMOVE', 'INBETWEEN_MOUSEMOVE'}:
            ray = self._ray(event)
            if ray is None:
                self.cursor = None
            elif self.stroke is not None:
                self._update_cursor(context, self.stroke.dab(*ray))
            else:
                obj = bpy.data.objects[self.obj_name]
                self._update_cursor(context, brush.cast(
                    obj, context.evaluated_depsgraph_get(), *ray))
        else:
            return {'RUNNING_MODAL'}
        self._status(context)
        _tag_redraw(context)
        return {'RUNNING_MODAL'}

    def _end_stroke(self):
        if self.stroke is not None:
            stroke, self.stroke = self.stroke, None
            self._report(stroke.finish())

    def cancel(self, context):
        self._end_stroke()
        self._finish(context)

    def _finish(self, context):
        obj = bpy.data.objects.get(getattr(self, "obj_name", ""))
        if obj is not None and hasattr(self, "shown_before"):
            obj.moldtex.show_fields = self.shown_before
        if getattr(self, "handle", None) is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self.handle, 'WINDOW')
            self.handle = None
        if getattr(self, "area", None) is not None:
            try:
                self.area.header_text_set(None)
            except ReferenceError:
                pass
        _tag_redraw(context)


CLASSES = (MoldtexStrokePoint, MOLDTEX_OT_brush_stroke, MOLDTEX_OT_food_at_cursor,
           MOLDTEX_OT_brush_undo,
           MOLDTEX_OT_brush_redo, MOLDTEX_OT_brush_paint)
register, unregister = bpy.utils.register_classes_factory(CLASSES)
