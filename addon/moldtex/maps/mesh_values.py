# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-vertex and per-face values of a mesh object for the map tools: reading vertex
groups and attributes, building the engine Surface of the object's own mesh, writing
vertex groups and attributes back. Never draws; raises MapToolError (a MeshExportError)
with words the user can act on.

Object space: the map tools work on the object's mesh data (obj.data, without
modifiers, in its local coordinates), because that is where the vertex groups and
attributes they write live; distances and radii are in object units.
"""

import array
import math

from .. import engine
from ..data.mesh_export import (MeshExportError, _named_values, _vertex_group_weights,
                           check_object, export_scale)


class MapToolError(MeshExportError):
    """A problem with the user's object or inputs, worded so that they can fix it."""


# moldtex_sim_set_bias accepts vectors up to this length.
MAX_BIAS_LENGTH = 1e6


def mesh_of(obj):
    """obj's mesh data (checked: a mesh with faces)."""
    check_object(obj)
    mesh = obj.data
    if len(mesh.polygons) == 0:
        raise MapToolError(f"Object '{obj.name}' has no faces: the map tools work on faces.")
    return mesh


def build_surface(obj):
    """(engine.Surface, vertex_count, triangles array('I'), loop triangle polygon indices)
    of obj's mesh in object space. The map tools ignore UVs, so every triangle gets the
    same unit UV triangle (the core needs some UV area, not a layout)."""
    mesh = mesh_of(obj)
    mesh.calc_loop_triangles()
    vertex_count, triangle_count = len(mesh.vertices), len(mesh.loop_triangles)
    positions = array.array("f", bytes(4 * 3 * vertex_count))
    mesh.vertices.foreach_get("co", positions)
    triangles = array.array("I", bytes(4 * 3 * triangle_count))
    mesh.loop_triangles.foreach_get("vertices", triangles)
    polygons = array.array("i", bytes(4 * triangle_count))
    mesh.loop_triangles.foreach_get("polygon_index", polygons)
    uvs = array.array("f", (0.0, 0.0, 1.0, 0.0, 0.0, 1.0)) * triangle_count
    try:
        surface = engine.Surface(positions, triangles, uvs)
    except engine.EngineError as error:
        raise MapToolError(f"Object '{obj.name}': {error}") from None
    return surface, vertex_count, triangles, polygons


def vertex_group_weights(obj, name, label):
    """array('f') of the weights of vertex group `name` (0 where unassigned)."""
    if not name:
        raise MapToolError(f"{label}: pick a vertex group.")
    group = obj.vertex_groups.get(name)
    if group is None:
        groups = ", ".join(f"'{g.name}'" for g in obj.vertex_groups) or "none"
        raise MapToolError(f"{label}: '{obj.name}' has no vertex group '{name}' "
                           f"(it has: {groups}).")
    return _vertex_group_weights(obj, obj.data, group, label)


def vertex_values(obj, name, label):
    """array('f') per vertex from a vertex group or a Float/Color attribute on the Vertex
    or Face Corner domain (corners averaged per vertex)."""
    if not name:
        raise MapToolError(f"{label}: pick a vertex group or attribute.")
    mesh = obj.data
    if obj.vertex_groups.get(name) is None and mesh.attributes.get(name) is None:
        groups = ", ".join(f"'{g.name}'" for g in obj.vertex_groups) or "none"
        raise MapToolError(f"{label}: '{name}' is neither a vertex group of '{obj.name}' nor "
                           f"an attribute of its mesh (vertex groups: {groups}).")
    values, domain = _named_values(obj, mesh, name, label)
    if domain == 'POINT':
        return values
    loop_vertices = array.array("i", bytes(4 * len(mesh.loops)))
    mesh.loops.foreach_get("vertex_index", loop_vertices)
    sums = [0.0] * len(mesh.vertices)
    counts = [0] * len(mesh.vertices)
    for vertex, value in zip(loop_vertices, values):
        sums[vertex] += value
        counts[vertex] += 1
    return array.array("f", [s / c if c else 0.0 for s, c in zip(sums, counts)])


def write_vertex_group(obj, name, weights):
    """Sets every vertex's weight in group `name` (created if missing), clamped to
    [0, 1] as vertex groups hold."""
    if not name:
        raise MapToolError("Pick a name for the output vertex group.")
    if obj.data.attributes.get(name) is not None:
        raise MapToolError(f"'{name}' is already an attribute of '{obj.name}': pick another "
                           f"name for the output vertex group.")
    group = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
    for index, weight in enumerate(weights):
        group.add([index], min(1.0, max(0.0, float(weight))), 'REPLACE')
    return group


def write_attribute(obj, name, values, data_type, domain):
    """Writes a FLOAT (values per element) or FLOAT_VECTOR (3 per element) attribute,
    replacing one of the same name with another type or domain."""
    if not name:
        raise MapToolError("Pick a name for the output attribute.")
    if obj.vertex_groups.get(name) is not None:
        raise MapToolError(f"'{name}' is a vertex group of '{obj.name}': pick another name "
                           f"for the output attribute.")
    if name.startswith("."):
        raise MapToolError(f"Attribute names starting with '.' are Blender's own: pick "
                           f"another name than '{name}'.")
    mesh = obj.data
    attribute = mesh.attributes.get(name)
    if attribute is not None and (attribute.data_type != data_type or attribute.domain != domain):
        mesh.attributes.remove(attribute)
        attribute = None
    if attribute is None:
        try:
            attribute = mesh.attributes.new(name, data_type, domain)
        except RuntimeError as error:
            raise MapToolError(f"Cannot create the attribute '{name}': {error}") from None
    attribute.data.foreach_set("vector" if data_type == 'FLOAT_VECTOR' else "value", values)
    mesh.update()
    return attribute


def face_vectors(mesh, triangle_vectors, polygons, normalize):
    """Per-polygon vectors (array('f'), 3 per face) from per-loop-triangle ones: the
    area-weighted mean over each face's triangles. normalize: unit vectors (0 stays 0);
    else scaled so that the longest is 1."""
    count = len(mesh.polygons)
    areas = array.array("f", bytes(4 * len(polygons)))
    mesh.loop_triangles.foreach_get("area", areas)
    sums = [0.0] * (3 * count)
    for t, (polygon, area) in enumerate(zip(polygons, areas)):
        for k in range(3):
            sums[3 * polygon + k] += area * triangle_vectors[3 * t + k]
    lengths = [math.sqrt(sums[3 * f] ** 2 + sums[3 * f + 1] ** 2 + sums[3 * f + 2] ** 2)
               for f in range(count)]
    # Faces where the map is flat (rounding leaves ~1e-16 of the longest) stay 0.
    floor = 1e-9 * max(lengths, default=0.0)
    lengths = [length if length > floor else 0.0 for length in lengths]
    if normalize:
        scales = [1.0 / length if length > 0.0 else 0.0 for length in lengths]
    else:
        total = [0.0] * count
        for polygon, area in zip(polygons, areas):
            total[polygon] += area
        means = [length / a if a > 0.0 else 0.0 for length, a in zip(lengths, total)]
        longest = max(means, default=0.0)
        scales = [1.0 / (a * longest) if a > 0.0 and longest > 0.0 else 0.0 for a in total]
    out = array.array("f", bytes(4 * 3 * count))
    for f in range(count):
        for k in range(3):
            out[3 * f + k] = sums[3 * f + k] * scales[f]
    return out


def bias_vectors_from_attribute(obj, depsgraph, name, triangle_count):
    """moldtex_sim_set_bias' vectors (array('f'), 3 per triangle of the evaluated mesh the
    simulation was made from) from the Face-domain vector attribute `name`: each loop
    triangle takes its face's vector, in the exported mesh's coordinates (a non-uniform
    object scale applied, as for the Bias Direction); lengths above 1e6 are cut."""
    if not name:
        raise MapToolError("Bias: pick the face attribute that holds the bias vectors "
                           "(Map Tools ▸ Gradient to Bias writes one).")
    if depsgraph is None:
        import bpy
        depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    data = evaluated.to_mesh()
    try:
        attribute = data.attributes.get(name)
        if attribute is None:
            raise MapToolError(
                f"Bias: '{obj.name}' has no attribute '{name}' (after modifiers): run Map "
                f"Tools ▸ Gradient to Bias, or pick another attribute.")
        if attribute.domain != 'FACE' or attribute.data_type != 'FLOAT_VECTOR':
            raise MapToolError(
                f"Bias: attribute '{name}' must hold vectors per Face (it is "
                f"{attribute.data_type.replace('_', ' ').lower()} per "
                f"{attribute.domain.lower()}).")
        data.calc_loop_triangles()
        if len(data.loop_triangles) != triangle_count:
            raise MapToolError(f"Bias: the mesh of '{obj.name}' changed: press Reset.")
        vectors = array.array("f", bytes(4 * 3 * len(data.polygons)))
        attribute.data.foreach_get("vector", vectors)
        polygons = array.array("i", bytes(4 * triangle_count))
        data.loop_triangles.foreach_get("polygon_index", polygons)
    finally:
        evaluated.to_mesh_clear()
    if not all(map(math.isfinite, vectors)):
        raise MapToolError(f"Bias: attribute '{name}' holds values that are not numbers.")
    scale = export_scale(obj)
    out = array.array("f", bytes(4 * 3 * triangle_count))
    for t, polygon in enumerate(polygons):
        v = [vectors[3 * polygon + k] for k in range(3)]
        if scale is not None:
            v = [v[k] * float(scale[k]) for k in range(3)]
        length = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        if length > MAX_BIAS_LENGTH:
            v = [c * (MAX_BIAS_LENGTH / length) for c in v]
        out[3 * t:3 * t + 3] = array.array("f", v)
    return out
