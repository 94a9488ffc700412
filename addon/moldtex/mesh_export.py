# SPDX-License-Identifier: GPL-3.0-or-later
"""Reads an object's evaluated mesh (modifiers applied) into flat arrays for the core.

Coordinates: the mesh's local coordinates with the object's world scale applied. A
uniform scale, a rotation or a translation does not change the simulation (the core
measures lengths in texels of this mesh), so only a non-uniform scale is applied; this
also keeps the data identical while the object is merely moved, so the live
simulation is not rebuilt for that.
"""

import array
import hashlib

import bpy
from mathutils import Matrix


class MeshExportError(Exception):
    """A problem with the user's object, worded so that they can fix it."""


class MeshArrays:
    __slots__ = ("positions", "triangles", "uvs", "triangle_uvs", "uv_map",
                 "signature", "vertex_count", "triangle_count")

    def __init__(self, positions, triangles, uvs, triangle_uvs, uv_map):
        self.positions = positions
        self.triangles = triangles
        self.uvs = uvs
        self.triangle_uvs = triangle_uvs
        self.uv_map = uv_map
        self.vertex_count = len(positions) // 3
        self.triangle_count = len(triangles) // 3
        digest = hashlib.blake2b(digest_size=16)
        for part in (positions, triangles, uvs, triangle_uvs):
            digest.update(part.tobytes())
        digest.update(uv_map.encode("utf-8"))
        self.signature = digest.hexdigest()


def default_uv_map_name(uv_layers):
    """The UV map Blender renders with (active render), else the active one."""
    for layer in uv_layers:
        if layer.active_render:
            return layer.name
    active = uv_layers.active
    if active is not None:
        return active.name
    return uv_layers[0].name if len(uv_layers) else ""


def resolve_uv_map_name(obj, requested):
    """The UV map the simulation uses for `obj` (empty request = render UV map)."""
    if requested:
        return requested
    if obj is None or obj.type != 'MESH':
        return ""
    return default_uv_map_name(obj.data.uv_layers)


def check_object(obj):
    """Raises MeshExportError if `obj` cannot be simulated at all (cheap checks)."""
    if obj is None:
        raise MeshExportError("No active object: select a mesh object first.")
    if obj.type != 'MESH':
        raise MeshExportError(
            f"Object '{obj.name}' is not a mesh (it is of type {obj.type.title()}): "
            f"select a mesh object, or convert it with Object ▸ Convert ▸ Mesh.")


def export_object(obj, depsgraph, uv_map_name=""):
    """MeshArrays of the evaluated `obj`. uv_map_name "" means the render UV map."""
    check_object(obj)
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        return _read_mesh(obj, mesh, uv_map_name)
    finally:
        evaluated.to_mesh_clear()


def _read_mesh(obj, mesh, uv_map_name):
    name = obj.name
    if len(mesh.polygons) == 0:
        raise MeshExportError(
            f"Object '{name}' has no faces ({len(mesh.vertices)} vertices, "
            f"{len(mesh.edges)} edges): the mold grows on faces. Fill it "
            f"(Edit Mode ▸ Face ▸ Fill) or pick another object.")
    layers = mesh.uv_layers
    if len(layers) == 0:
        raise MeshExportError(
            f"Object '{name}' has no UV map: add one (UV ▸ Smart UV Project in Edit Mode) "
            f"so the mold has a texture to grow in.")
    if uv_map_name:
        layer = layers.get(uv_map_name)
        if layer is None:
            names = ", ".join(f"'{layer.name}'" for layer in layers)
            raise MeshExportError(
                f"Object '{name}' has no UV map named '{uv_map_name}' (it has {names}): "
                f"pick one in the Moldtex panel.")
    else:
        layer = layers.get(default_uv_map_name(layers))

    scale = obj.matrix_world.to_scale()
    low, high = min(abs(s) for s in scale), max(abs(s) for s in scale)
    if low > 0.0 and high - low > 1e-6 * high:
        mesh.transform(Matrix.Diagonal((scale[0], scale[1], scale[2], 1.0)))

    mesh.calc_loop_triangles()
    vertex_count = len(mesh.vertices)
    triangle_count = len(mesh.loop_triangles)
    loop_count = len(mesh.loops)

    positions = array.array("f", bytes(4 * 3 * vertex_count))
    mesh.vertices.foreach_get("co", positions)
    triangles = array.array("I", bytes(4 * 3 * triangle_count))
    mesh.loop_triangles.foreach_get("vertices", triangles)
    triangle_uvs = array.array("I", bytes(4 * 3 * triangle_count))
    mesh.loop_triangles.foreach_get("loops", triangle_uvs)
    uvs = array.array("f", bytes(4 * 2 * loop_count))
    layer.data.foreach_get("uv", uvs)
    return MeshArrays(positions, triangles, uvs, triangle_uvs, layer.name)
