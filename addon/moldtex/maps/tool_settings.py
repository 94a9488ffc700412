# SPDX-License-Identifier: GPL-3.0-or-later
"""Inputs of the map tools, kept per object (Object.moldtex_map_tools) so the Map Tools
panel can show them and they are saved with the .blend."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, PointerProperty, StringProperty


class MoldtexMapToolSettings(bpy.types.PropertyGroup):
    # Geodesic distance
    distance_source: StringProperty(
        name="Source", default="",
        description="Source: vertex group whose vertices (weight above 0.5) the distance is "
                    "measured from")
    distance_group: StringProperty(
        name="Output", default="Moldtex Distance",
        description="Output: vertex group that receives the distance divided by its "
                    "largest value (0 at the source, 1 farthest; unreachable parts 1)")
    distance_attribute: StringProperty(
        name="Attribute", default="moldtex_distance",
        description="Attribute: Vertex float attribute that receives the distance in object "
                    "units (-1 where no source can be reached over the surface)")
    time_factor: FloatProperty(
        name="Smoothness", default=1.0, min=0.01, max=1000.0, soft_min=0.1, soft_max=20.0,
        description="Smoothness (heat time factor): the heat method's time in squared mean "
                    "edge lengths. 1 is the usual choice; larger values give smoother "
                    "distances and reach farther on very large meshes")
    # Laplace interpolation
    blend_low: StringProperty(
        name="Value 0", default="",
        description="Value 0: vertex group of the region that gets 0 (weight above 0.5)")
    blend_high: StringProperty(
        name="Value 1", default="",
        description="Value 1: vertex group of the region that gets 1 (weight above 0.5)")
    blend_group: StringProperty(
        name="Output", default="Moldtex Blend",
        description="Output: vertex group that receives the smoothest blend (harmonic "
                    "interpolation) from the 0 region to the 1 region")
    # Blur
    blur_source: StringProperty(
        name="Map", default="",
        description="Map: vertex group to blur over the surface (across UV seams)")
    blur_radius: FloatProperty(
        name="Radius", default=0.1, min=0.0, max=1e6, soft_min=0.0, soft_max=2.0,
        subtype='DISTANCE', precision=3,
        description="Radius: blur radius in object units (the Gaussian's standard "
                    "deviation; the heat flows for time radius² / 2)")
    blur_group: StringProperty(
        name="Output", default="Moldtex Blur",
        description="Output: vertex group that receives the blurred map (may be the map "
                    "itself)")
    # Gradient to bias
    gradient_source: StringProperty(
        name="Map", default="",
        description="Map: vertex group or Vertex float attribute whose gradient becomes "
                    "the bias")
    gradient_attribute: StringProperty(
        name="Output", default="moldtex_bias",
        description="Output: Face vector attribute that receives the gradient (the "
                    "continuous model's Bias reads it with Source Attribute)")
    gradient_direction: EnumProperty(
        name="Toward", default='UP',
        items=(('UP', "Higher", "Agents are pulled toward higher values of the map"),
               ('DOWN', "Lower", "Agents are pulled toward lower values of the map")),
        description="Toward: pull agents uphill or downhill on the map")
    gradient_normalize: BoolProperty(
        name="Normalize", default=True,
        description="Normalize: unit vectors on every face (full bias wherever the map "
                    "slopes); off: lengths follow the slope, the steepest face 1")


def register():
    bpy.utils.register_class(MoldtexMapToolSettings)
    bpy.types.Object.moldtex_map_tools = PointerProperty(type=MoldtexMapToolSettings)


def unregister():
    del bpy.types.Object.moldtex_map_tools
    bpy.utils.unregister_class(MoldtexMapToolSettings)
