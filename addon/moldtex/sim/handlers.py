# SPDX-License-Identifier: GPL-3.0-or-later
"""Application handlers that keep the live simulations in step with Blender's data."""

import bpy
from bpy.app.handlers import persistent

from ..brush import session as brush
from ..data import image_io
from . import session as live


@persistent
def on_load_pre(*_args):
    # Another file replaces every object: nothing live survives.
    live.free_all()
    brush.forget()


@persistent
def on_depsgraph_update_post(scene, depsgraph=None):
    changed = [] if depsgraph is None else [
        update.id.name for update in depsgraph.updates
        if update.is_updated_geometry and isinstance(update.id, bpy.types.Object)]
    for name in changed:
        brush.mesh_changed(name)  # the brush reads the mesh again before its next dab
    objects = bpy.data.objects
    for name in live.names():
        if objects.get(name) is None:  # deleted (or renamed)
            live.free(name)
            brush.forget(name)
    for name in changed:
        if not live.take_own_geometry_write(name):  # (not the vertex colours we wrote)
            live.mark_dirty(name)


@persistent
def on_undo_redo_post(*_args):
    # Undo makes new object wrappers and may restore another mesh: check before the
    # next step (live.ensure compares the mesh and rebuilds only if it differs).
    for name in live.names():
        if bpy.data.objects.get(name) is None:
            live.free(name)
    live.mark_dirty()
    brush.mesh_changed()


@persistent
def on_save_pre(*_args):
    # Generated images (the pheromone, and Fields painted with the brush) lose their
    # pixels on reload unless packed.
    for obj in bpy.data.objects:
        settings = getattr(obj, "moldtex", None)
        if settings is None:
            continue
        for image in (settings.image, settings.fields_image):
            if image is None:
                continue
            try:
                image_io.pack_for_save(image)
            except RuntimeError as error:
                print(f"Moldtex: could not pack '{image.name}': {error}")


_HANDLERS = (
    ("load_pre", on_load_pre),
    ("depsgraph_update_post", on_depsgraph_update_post),
    ("undo_post", on_undo_redo_post),
    ("redo_post", on_undo_redo_post),
    ("save_pre", on_save_pre),
)


def register():
    for attribute, function in _HANDLERS:
        handlers = getattr(bpy.app.handlers, attribute)
        if function not in handlers:
            handlers.append(function)


def unregister():
    for attribute, function in _HANDLERS:
        handlers = getattr(bpy.app.handlers, attribute)
        # Compare by name too: a reloaded module has new function objects.
        for existing in list(handlers):
            if existing is function or (getattr(existing, "__module__", None) == __name__
                                        and existing.__name__ == function.__name__):
                handlers.remove(existing)
