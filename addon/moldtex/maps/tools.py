# SPDX-License-Identifier: GPL-3.0-or-later
"""Map tool operators (Layton et al. §6, Fig. 14-17) on the active mesh object: geodesic
distance from a vertex group, Laplace blend between two vertex groups, blur of a vertex
group, and gradient of a map as a face vector attribute for the continuous model's
bias. Inputs come from Object.moldtex_map_tools (settings.py); results go to vertex
groups and attributes of the object's mesh, so they can be seen, painted over and
reused. Every failure is reported as a message, never as a traceback."""

import array

import bpy

from .. import engine
from ..data.mesh_export import MeshExportError
from . import mesh_values
from .mesh_values import MapToolError

# A vertex belongs to a region when its weight in the group is above this.
REGION_WEIGHT = 0.5


def _region(weights):
    return array.array("B", (1 if w > REGION_WEIGHT else 0 for w in weights))


class _MapTool:
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'MESH'

    def execute(self, context):
        obj = context.active_object
        if not engine.available():
            self.report({'ERROR'}, engine.status_text())
            return {'CANCELLED'}
        edit_mode = obj is not None and obj.mode == 'EDIT'
        try:
            if edit_mode:  # vertex groups cannot be written in Edit Mode
                bpy.ops.object.mode_set(mode='OBJECT')
            message = self.run(obj, obj.moldtex_map_tools)
        except (MeshExportError, engine.EngineError) as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        finally:
            if edit_mode:
                bpy.ops.object.mode_set(mode='EDIT')
        self.report({'INFO'}, message)
        return {'FINISHED'}


class MOLDTEX_OT_map_distance(_MapTool, bpy.types.Operator):
    """Geodesic distance over the surface from a vertex group (heat method), into a vertex
    group (0..1) and a Vertex float attribute (object units)"""
    bl_idname = "moldtex.map_distance"
    bl_label = "Geodesic Distance"

    def run(self, obj, tools):
        source = _region(mesh_values.vertex_group_weights(obj, tools.distance_source, "Source"))
        if not any(source):
            raise MapToolError(f"Source: no vertex of '{tools.distance_source}' has a weight "
                               f"above {REGION_WEIGHT}: assign some vertices to it.")
        surface, count, _, _ = mesh_values.build_surface(obj)
        try:
            distance = surface.geodesic_distance(array.array("f", source), tools.time_factor)
        finally:
            surface.release()
        reached = [d for d in distance if d >= 0.0]
        far = max(reached, default=0.0)
        unreachable = count - len(reached)
        weights = [d / far if far > 0.0 and d >= 0.0 else (1.0 if d < 0.0 else 0.0)
                   for d in distance]
        mesh_values.write_vertex_group(obj, tools.distance_group, weights)
        if tools.distance_attribute:
            mesh_values.write_attribute(obj, tools.distance_attribute, distance, 'FLOAT', 'POINT')
        note = (f"; {unreachable} vertices cannot be reached (weight 1, distance -1)"
                if unreachable else "")
        return f"Distance: farthest {far:.4g} object units{note}"


class MOLDTEX_OT_map_blend(_MapTool, bpy.types.Operator):
    """Smoothest blend (Laplace interpolation) from 0 on one vertex group to 1 on another,
    into a vertex group"""
    bl_idname = "moldtex.map_blend"
    bl_label = "Laplace Blend"

    def run(self, obj, tools):
        low = _region(mesh_values.vertex_group_weights(obj, tools.blend_low, "Value 0"))
        high = _region(mesh_values.vertex_group_weights(obj, tools.blend_high, "Value 1"))
        both = sum(1 for a, b in zip(low, high) if a and b)
        if both:
            raise MapToolError(f"{both} vertices are in both '{tools.blend_low}' and "
                               f"'{tools.blend_high}': a vertex can be 0 or 1, not both.")
        if not any(low) or not any(high):
            empty = tools.blend_low if not any(low) else tools.blend_high
            raise MapToolError(f"No vertex of '{empty}' has a weight above {REGION_WEIGHT}: "
                               f"assign some vertices to it.")
        fixed = array.array("B", (a | b for a, b in zip(low, high)))
        values = array.array("f", (float(b) for b in high))
        surface, count, _, _ = mesh_values.build_surface(obj)
        try:
            blend = surface.laplace_interpolate(values, fixed)
        finally:
            surface.release()
        mesh_values.write_vertex_group(obj, tools.blend_group, blend)
        return f"Blend written to '{tools.blend_group}'"


class MOLDTEX_OT_map_blur(_MapTool, bpy.types.Operator):
    """Blur a vertex group over the surface (short-time diffusion, across UV seams) into a
    vertex group"""
    bl_idname = "moldtex.map_blur"
    bl_label = "Blur Map"

    def run(self, obj, tools):
        weights = mesh_values.vertex_group_weights(obj, tools.blur_source, "Map")
        surface, count, _, _ = mesh_values.build_surface(obj)
        try:
            radius = float(tools.blur_radius)
            blurred = surface.diffuse_map(weights, radius * radius / 2.0)
        finally:
            surface.release()
        mesh_values.write_vertex_group(obj, tools.blur_group, blurred)
        return f"Blurred '{tools.blur_source}' by {tools.blur_radius:.4g} into '{tools.blur_group}'"


class MOLDTEX_OT_map_gradient_bias(_MapTool, bpy.types.Operator):
    """Gradient of a map (vertex group or Vertex attribute) as a Face vector attribute, for
    the continuous model's bias (Bias ▸ Source: Attribute)"""
    bl_idname = "moldtex.map_gradient_bias"
    bl_label = "Gradient to Bias"

    def run(self, obj, tools):
        values = mesh_values.vertex_values(obj, tools.gradient_source, "Map")
        if max(values, default=0.0) - min(values, default=0.0) <= 1e-6 * max(
                1.0, max(map(abs, values), default=0.0)):
            raise MapToolError(f"'{tools.gradient_source}' is constant: its gradient is zero "
                               f"everywhere, so it gives no bias.")
        if tools.gradient_direction == 'DOWN':
            values = array.array("f", (-v for v in values))
        surface, count, _, polygons = mesh_values.build_surface(obj)
        try:
            gradient = surface.map_gradient(values)
        finally:
            surface.release()
        vectors = mesh_values.face_vectors(obj.data, gradient, polygons, tools.gradient_normalize)
        if not any(vectors):
            raise MapToolError(f"'{tools.gradient_source}' is constant: its gradient is zero "
                               f"everywhere, so it gives no bias.")
        mesh_values.write_attribute(obj, tools.gradient_attribute, vectors, 'FLOAT_VECTOR', 'FACE')
        return (f"Bias vectors written to the face attribute '{tools.gradient_attribute}': "
                f"set Bias ▸ Source to Attribute to use them")


CLASSES = (MOLDTEX_OT_map_distance, MOLDTEX_OT_map_blend, MOLDTEX_OT_map_blur,
           MOLDTEX_OT_map_gradient_bias)
_register_classes, _unregister_classes = bpy.utils.register_classes_factory(CLASSES)


def register():
    _register_classes()


def unregister():
    _unregister_classes()
