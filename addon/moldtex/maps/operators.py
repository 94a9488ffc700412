# SPDX-License-Identifier: GPL-3.0-or-later
"""Show: a map's source on the model, in the paint mode that shows (and edits) it."""

import bpy
from bpy.props import StringProperty

from .spec import BY_KEY


def _set_mode(operator, context, obj, mode):
    if obj.mode == mode:
        return True
    view_layer = context.view_layer
    if view_layer.objects.active != obj:
        view_layer.objects.active = obj
    try:
        bpy.ops.object.mode_set(mode=mode)
    except RuntimeError as error:  # hidden, linked, in another mode's edit, ...
        operator.report({'ERROR'}, f"Cannot show the map on '{obj.name}': "
                                   f"{str(error).replace('Error: ', '', 1).strip()}")
        return False
    return True


class MOLDTEX_OT_map_show(bpy.types.Operator):
    """Show this map on the model: a vertex group in Weight Paint, a colour attribute \
in Vertex Paint, an image in Texture Paint (where you can also paint it; Ctrl Tab or \
the mode menu goes back to Object Mode, then press Reset)"""
    bl_idname = "moldtex.map_show"
    bl_label = "Show Map"
    bl_options = {'REGISTER', 'UNDO'}

    map: StringProperty(name="Map", default="", options={'SKIP_SAVE', 'HIDDEN'},
                        description="Key of the map to show (maps/spec.py)")

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'MESH'

    def execute(self, context):
        obj = context.active_object
        spec = BY_KEY.get(self.map)
        if spec is None:
            self.report({'ERROR'}, f"There is no map '{self.map}'.")
            return {'CANCELLED'}
        slot = getattr(obj.moldtex.maps, spec.key)
        if slot.source == 'IMAGE':
            return self._show_image(context, obj, spec, slot)
        return self._show_attribute(context, obj, spec, slot)

    def _show_image(self, context, obj, spec, slot):
        image = slot.image
        if image is None or image.size[0] == 0 or image.size[1] == 0:
            self.report({'ERROR'}, f"The {spec.label} map has no image with pixels to "
                                   f"show: pick one (Moldtex ▸ Maps).")
            return {'CANCELLED'}
        paint = context.scene.tool_settings.image_paint
        paint.mode = 'IMAGE'
        paint.canvas = image
        if not _set_mode(self, context, obj, 'TEXTURE_PAINT'):
            return {'CANCELLED'}
        self.report({'INFO'}, f"Showing the image '{image.name}' in Texture Paint.")
        return {'FINISHED'}

    def _show_attribute(self, context, obj, spec, slot):
        name = slot.attribute
        if not name:
            self.report({'ERROR'}, f"The {spec.label} map names no vertex group or "
                                   f"attribute: pick one (Moldtex ▸ Maps).")
            return {'CANCELLED'}
        group = obj.vertex_groups.get(name)
        if group is not None:
            obj.vertex_groups.active_index = group.index
            if not _set_mode(self, context, obj, 'WEIGHT_PAINT'):
                return {'CANCELLED'}
            self.report({'INFO'}, f"Showing the vertex group '{name}' in Weight Paint.")
            return {'FINISHED'}
        mesh = obj.data
        attribute = mesh.attributes.get(name)
        if attribute is None:
            self.report({'ERROR'}, f"'{name}' is neither a vertex group of '{obj.name}' "
                                   f"nor an attribute of its mesh: fix the name "
                                   f"(Moldtex ▸ Maps).")
            return {'CANCELLED'}
        colors = getattr(mesh, "color_attributes", None)
        if (attribute.data_type in {'FLOAT_COLOR', 'BYTE_COLOR'} and colors is not None
                and attribute.domain in {'POINT', 'CORNER'}):
            colors.active_color = attribute
            if not _set_mode(self, context, obj, 'VERTEX_PAINT'):
                return {'CANCELLED'}
            self.report({'INFO'}, f"Showing the colour attribute '{name}' in Vertex "
                                  f"Paint.")
            return {'FINISHED'}
        self.report({'WARNING'}, f"'{name}' is a {attribute.data_type.title()} attribute, "
                                 f"which no paint mode shows: see its values in the "
                                 f"Spreadsheet, or use a vertex group.")
        return {'CANCELLED'}


CLASSES = (MOLDTEX_OT_map_show,)
register, unregister = bpy.utils.register_classes_factory(CLASSES)
