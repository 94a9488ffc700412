# SPDX-License-Identifier: GPL-3.0-or-later
"""Colour Map from Image (Layton et al. §3.4): the Moldtex Ramp from an exemplar image.

The core (moldtex_colour_ramp_from_pixels) subsamples the pixels, finds one coordinate
that orders their colours (Isomap in CIELAB), fits a curve per channel over it and
places at most 32 ColorRamp stops where the curve bends. This module reads the image's
pixels (Image.pixels.foreach_get into an array('f'), no numpy) and writes the stops into
the active object's Moldtex Ramp; without a Moldtex material yet, the stops are kept on
the object and Set Up Material uses them.
"""

import bpy
from bpy.props import BoolProperty, FloatProperty, IntProperty, StringProperty

from .. import engine
from ..data import image_io
from . import material

# Below this, one variable does not explain the image's colours well (e.g. two unrelated
# colour groups): the ramp is still written, with a warning.
EXPLAINED_WARNING = 0.7

last_report = None  # (level, message) of the last run (for scripts and tests)


def quality_report(image_name, info, stop_count, where):
    """(report level, message) after a colour map: a WARNING when one variable does not
    explain the image's colours well (info["explained"] < EXPLAINED_WARNING)."""
    explained = info["explained"]
    if explained < EXPLAINED_WARNING:
        why = ("the colors jump between separate groups"
               if info["continuity"] < 0.8 else "the colors spread far from one curve")
        return ('WARNING',
                f"One variable does not explain the colors of '{image_name}' well "
                f"(explained {explained:.2f}: {why}); the {stop_count} stops in {where} "
                f"join them: crop the image to one pattern, or edit the ramp.")
    return ('INFO', f"{stop_count} stops from '{image_name}' in {where} (explained "
                    f"{explained:.2f}, mean error {info['mean_error']:.1f} ΔE).")


def image_colours(image):
    """(pixels array('f'), channels, srgb_encoded) of a Blender image, or raises
    ValueError with a message a user can act on."""
    if image is None:
        raise ValueError("Pick an image to take the colours from.")
    try:
        width, height = image.size
    except (AttributeError, RuntimeError):
        width = height = 0
    if width * height == 0:
        raise ValueError(f"Image '{image.name}' has no pixels (is its file missing?): "
                         f"open or reload it first.")
    channels = int(image.channels)
    if channels < 3:
        raise ValueError(f"Image '{image.name}' has {channels} channel(s): a colour map "
                         f"needs an RGB or RGBA image.")
    pixels = image_io.read_pixels(image)
    # Byte images give their stored (sRGB-encoded) values; float images are linear.
    srgb = (not image.is_float) and image.colorspace_settings.name in ("sRGB", "")
    return pixels, channels, srgb


def colour_ramp_from_image(image, reverse=False, sample_count=1500, peak_position=-1.0):
    """(stops, info) of moldtex_colour_ramp_from_pixels for a Blender image."""
    pixels, channels, srgb = image_colours(image)
    if channels > 4:
        raise ValueError(f"Image '{image.name}' has {channels} channels; 3 or 4 are supported.")
    return engine.colour_ramp_from_pixels(pixels, channels=channels, srgb_encoded=srgb,
                                          sample_count=sample_count, reverse=reverse,
                                          peak_position=peak_position)


class MOLDTEX_OT_colour_map_from_image(bpy.types.Operator):
    """Set the Moldtex color ramp from an image's colors: orders the colors along one \
variable (Isomap) and places up to 32 stops where their curve bends"""
    bl_idname = "moldtex.colour_map_from_image"
    bl_label = "Colour Map from Image"
    bl_options = {'REGISTER', 'UNDO'}

    image: StringProperty(name="Image", description="The image whose colors make the ramp")
    reverse: BoolProperty(name="Reverse", default=False,
                          description="Lighter end of the colors at 0 (default: darker end at 0)")
    sample_count: IntProperty(name="Samples", default=1500, min=16, max=4096,
                              description="Pixels used (evenly spread over the image; more "
                                          "is slower, about quadratic: 1500 take ~0.5 s, "
                                          "4096 ~5 s)")
    use_peak: BoolProperty(name="Peak At", default=False,
                           description="Move the ramp so its most saturated color sits at "
                                       "Position (e.g. rings around spot peaks)")
    peak_position: FloatProperty(name="Position", default=0.5, min=0.0, max=1.0,
                                 description="Where the most saturated color sits on the ramp")

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def invoke(self, context, event):
        if not self.image:
            node = material.moldtex_node(context.active_object, material.TEXTURE_NODE)
            own = {node.image.name} if node is not None and node.image is not None else set()
            for image in bpy.data.images:
                if image.name not in own and not image.name.startswith("Moldtex "):
                    self.image = image.name
                    break
        return context.window_manager.invoke_props_dialog(self)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop_search(self, "image", bpy.data, "images")
        layout.prop(self, "reverse")
        layout.prop(self, "sample_count")
        row = layout.row(heading="Peak At")
        row.prop(self, "use_peak", text="")
        sub = row.row()
        sub.active = self.use_peak
        sub.prop(self, "peak_position", text="")

    def execute(self, context):
        obj = context.active_object
        if obj is None:
            self.report({'ERROR'}, "Select the object whose Moldtex material gets the colors.")
            return {'CANCELLED'}
        if not engine.available():
            self.report({'ERROR'}, engine.LOAD_ERROR or "The Moldtex core is not loaded.")
            return {'CANCELLED'}
        image = bpy.data.images.get(self.image) if self.image else None
        if image is None:
            self.report({'ERROR'}, f"There is no image named '{self.image}': pick one."
                        if self.image else "Pick an image to take the colors from.")
            return {'CANCELLED'}
        try:
            stops, info = colour_ramp_from_image(
                image, reverse=self.reverse, sample_count=self.sample_count,
                peak_position=self.peak_position if self.use_peak else -1.0)
        except (ValueError, engine.EngineError) as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        ramp = material.moldtex_node(obj, material.RAMP_NODE)
        material.store_preset_ramp(obj, stops, 'LINEAR')
        if ramp is not None:
            material.set_ramp(ramp, stops, 'LINEAR')
            where = f"the Moldtex Ramp of '{obj.active_material.name}'"
        else:
            where = (f"'{obj.name}' (no Moldtex material yet: Set Up Material will use "
                     f"them)")
        global last_report
        last_report = quality_report(image.name, info, len(stops), where)
        self.report({last_report[0]}, last_report[1])
        return {'FINISHED'}


CLASSES = (MOLDTEX_OT_colour_map_from_image,)

register, unregister = bpy.utils.register_classes_factory(CLASSES)
