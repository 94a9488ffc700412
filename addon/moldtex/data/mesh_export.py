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
import math

import bpy
from mathutils import Matrix


class MeshExportError(Exception):
    """A problem with the user's object, worded so that they can fix it."""


class MeshArrays:
    """The evaluated mesh as the core takes it. A mesh without a usable UV map has uvs
    and triangle_uvs None and uv_map "" (it runs on the Intrinsic domain only);
    flat_uv_map names its UV map when it has one whose area is zero (every UV on one
    point or line), which counts as none. loops (the loop index of each triangle
    corner) and loop_count are there either way."""
    __slots__ = ("positions", "triangles", "uvs", "triangle_uvs", "uv_map", "loops",
                 "loop_count", "signature", "vertex_count", "triangle_count", "flat_uv_map")

    def __init__(self, positions, triangles, uvs, triangle_uvs, uv_map, loops=None,
                 loop_count=None, flat_uv_map=""):
        self.flat_uv_map = flat_uv_map
        self.positions = positions
        self.triangles = triangles
        self.uvs = uvs
        self.triangle_uvs = triangle_uvs
        self.uv_map = uv_map
        self.loops = triangle_uvs if loops is None else loops
        self.loop_count = len(uvs) // 2 if loop_count is None else loop_count
        self.vertex_count = len(positions) // 3
        self.triangle_count = len(triangles) // 3
        digest = hashlib.blake2b(digest_size=16)
        for part in (positions, triangles, uvs, triangle_uvs):
            digest.update(b"-" if part is None else part.tobytes())
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


# What the core's float arithmetic handles: each scale axis within SCALE_LIMITS, and a
# mesh (after the export's scale) spanning EXTENT_LIMITS units. Outside them lengths and
# areas underflow or overflow float32 (a 1e-18 scale, a mesh 1e-30 units across) and
# the world-to-mesh transform has no inverse (a scale of 0).
SCALE_LIMITS = (1e-6, 1e6)
EXTENT_LIMITS = (1e-6, 1e9)


def _axes_text(values):
    return ", ".join(f"{v:.6g}" for v in values)


def check_transform(obj):
    """Raises MeshExportError if obj's world transform cannot be simulated: a scale of 0
    (or nearly 0, or huge) on some axis, or values that are not numbers."""
    matrix = obj.matrix_world
    if not all(math.isfinite(v) for row in matrix for v in row):
        raise MeshExportError(
            f"Object '{obj.name}' has a transform that is not a number (NaN or infinite): "
            f"reset its location, rotation and scale (Object ▸ Clear).")
    # The length of each axis in Python's doubles (Matrix.to_scale works in floats,
    # which turns 1e-18 into 0 and 1e30 into inf).
    scale = [math.hypot(matrix[0][i], matrix[1][i], matrix[2][i]) for i in range(3)]
    if obj.matrix_world.is_negative:
        scale[0] = -scale[0]
    if obj.parent is None:
        scale = [math.copysign(length, axis) for length, axis in zip(scale, obj.scale)]
    low, high = SCALE_LIMITS
    for axis, value in zip("XYZ", scale):
        if value == 0.0:
            raise MeshExportError(
                f"Object '{obj.name}' has a scale of 0 on {axis} (scale {_axes_text(scale)}): "
                f"that flattens it, so there is no surface to grow on. Give {axis} a "
                f"non-zero scale (Object Properties ▸ Transform ▸ Scale).")
        if not low <= abs(value) <= high:
            raise MeshExportError(
                f"Object '{obj.name}' has a scale of {value:.3g} on {axis} (scale "
                f"{_axes_text(scale)}): Moldtex works with scales between {low:g} and "
                f"{high:g} on each axis. Set the scale nearer to 1 (resize the mesh in Edit "
                f"Mode instead).")
    if abs(matrix.to_3x3().determinant()) == 0.0:  # e.g. a zero scale hidden by a parent
        raise MeshExportError(
            f"Object '{obj.name}' is flattened by its transform (or its parent's): set "
            f"a non-zero scale on every axis.")


def check_extent(obj, positions):
    """Raises MeshExportError if the exported mesh is too small or too large for the
    core's float arithmetic (a mesh scaled to 1e-30 has areas of 0)."""
    if not positions:
        return
    extent = max(max(positions[axis::3]) - min(positions[axis::3]) for axis in range(3))
    low, high = EXTENT_LIMITS
    if not math.isfinite(extent) or extent > high:
        raise MeshExportError(
            f"Object '{obj.name}' is too large for Moldtex: its mesh spans "
            f"{extent:.3g} units (with its scale); at most {high:g} works. Scale the mesh "
            f"down in Edit Mode.")
    if extent < low:
        raise MeshExportError(
            f"Object '{obj.name}' is too small for Moldtex: its mesh spans only "
            f"{extent:.3g} units (without its object scale); at least {low:g} works. "
            f"Scale the mesh up in Edit Mode (the object's own scale can stay small).")


def export_scale(obj):
    """The object scale applied to the exported coordinates: its world scale when that
    is not uniform, else None (a uniform scale is left out, see the module's note)."""
    scale = obj.matrix_world.to_scale()
    low, high = min(abs(v) for v in scale), max(abs(v) for v in scale)
    if low > 0.0 and high - low > 1e-6 * high:
        return scale
    return None


def world_to_mesh(obj):
    """4x4 matrix from world space to the exported mesh's coordinates. Raises
    MeshExportError for a transform without an inverse (check_transform)."""
    check_transform(obj)
    try:
        matrix = obj.matrix_world.inverted()
    except ValueError:
        raise MeshExportError(
            f"Object '{obj.name}' is flattened by its transform: set a non-zero scale on "
            f"every axis.") from None
    scale = export_scale(obj)
    if scale is not None:
        matrix = Matrix.Diagonal((scale[0], scale[1], scale[2], 1.0)) @ matrix
    return matrix


def length_in_mesh_units(obj, length):
    """A length in scene units, measured on obj's surface, in the exported mesh's units
    (rotations keep lengths; a uniform scale is not in the exported mesh)."""
    if export_scale(obj) is not None:
        return length  # the exported mesh carries the scale
    scale = abs(obj.matrix_world.to_scale()[0])
    return length / scale if scale > 0.0 else length


def length_in_scene_units(obj, length):
    """A length in the exported mesh's units, in scene units (length_in_mesh_units'
    inverse)."""
    if export_scale(obj) is not None:
        return length
    return length * abs(obj.matrix_world.to_scale()[0])


def export_object(obj, depsgraph, uv_map_name=""):
    """MeshArrays of the evaluated `obj`. uv_map_name "" means the render UV map."""
    check_object(obj)
    check_transform(obj)
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
    layer = None
    if len(layers) == 0:
        pass  # the Intrinsic domain runs without (see no_uv_map_message)
    elif uv_map_name:
        layer = layers.get(uv_map_name)
        if layer is None:
            names = ", ".join(f"'{layer.name}'" for layer in layers)
            raise MeshExportError(
                f"Object '{name}' has no UV map named '{uv_map_name}' (it has {names}): "
                f"pick one in the Moldtex panel.")
    else:
        layer = layers.get(default_uv_map_name(layers))

    scale = export_scale(obj)
    if scale is not None:
        mesh.transform(Matrix.Diagonal((scale[0], scale[1], scale[2], 1.0)))

    mesh.calc_loop_triangles()
    vertex_count = len(mesh.vertices)
    triangle_count = len(mesh.loop_triangles)
    loop_count = len(mesh.loops)

    positions = array.array("f", bytes(4 * 3 * vertex_count))
    mesh.vertices.foreach_get("co", positions)
    check_extent(obj, positions)
    triangles = array.array("I", bytes(4 * 3 * triangle_count))
    mesh.loop_triangles.foreach_get("vertices", triangles)
    loops = array.array("I", bytes(4 * 3 * triangle_count))
    mesh.loop_triangles.foreach_get("loops", loops)
    if layer is None:
        return MeshArrays(positions, triangles, None, None, "", loops, loop_count)
    uvs = array.array("f", bytes(4 * 2 * loop_count))
    layer.data.foreach_get("uv", uvs)
    if uv_area_is_zero(uvs, loops):  # no texture to grow in: as if there were no UV map
        return MeshArrays(positions, triangles, None, None, "", loops, loop_count,
                          flat_uv_map=layer.name)
    return MeshArrays(positions, triangles, uvs, loops, layer.name, loops, loop_count)


# The core refuses a UV map whose triangles' UV areas sum to no more than this
# (native/src/surface/surface.cpp): the same limit here.
ZERO_UV_AREA = 1e-12


def uv_area_is_zero(uvs, loops):
    """Whether the UV triangles (corner loops `loops`, 3 per triangle, into `uvs`, 2
    floats per loop) have a total area of at most ZERO_UV_AREA. Stops at the first
    triangles that add up to more, so an unwrapped mesh costs a few triangles."""
    total = 0.0
    for k in range(0, len(loops) - 2, 3):
        a, b, c = 2 * loops[k], 2 * loops[k + 1], 2 * loops[k + 2]
        total += 0.5 * abs((uvs[b] - uvs[a]) * (uvs[c + 1] - uvs[a + 1])
                           - (uvs[c] - uvs[a]) * (uvs[b + 1] - uvs[a + 1]))
        if total > ZERO_UV_AREA:
            return False
    return True


def no_uv_map_message(name, flat_uv_map=""):
    """What to do about an object without a UV map where a texture is needed (or with
    one of zero area, flat_uv_map)."""
    problem = (f"has a UV map ('{flat_uv_map}') whose UVs have no area (all on one point "
               f"or line): unwrap it" if flat_uv_map else "has no UV map: add one")
    return (f"Object '{name}' {problem} (UV ▸ Smart UV Project in Edit Mode) so the mold "
            f"has a texture to grow in, or choose the Continuous model on the Intrinsic "
            f"domain, which runs on the surface and colours the mesh's vertices.")


# ---- static fields from vertex groups and attributes ----------------------------------

# Colour attributes count by the luminance of the colour as shown (sRGB values, Rec. 709
# weights): black 0, white 1, a 50 % grey 0.5.
LUMINANCE = (0.2126, 0.7152, 0.0722)
_DOMAIN_WORDS = {'POINT': "Vertex", 'CORNER': "Face Corner", 'EDGE': "Edge", 'FACE': "Face",
                 'CURVE': "Spline", 'INSTANCE': "Instance"}


FIELDS_WHERE = "Moldtex ▸ Species & Start ▸ Fields"


def read_corner_fields(obj, depsgraph, mesh, names, labels=("Spawn", "Obstacle", "Attractor"),
                       where=FIELDS_WHERE):
    """Per-corner RGBA (array('f'), 4 floats for each corner of each triangle of `mesh`,
    the MeshArrays export_object made of the same evaluated object): channel k holds the
    values of names[k] ("" = 0), a vertex group (weights, 0 where unassigned) or else a
    mesh attribute (FLOAT, FLOAT_COLOR or BYTE_COLOR on the Vertex or Face Corner domain;
    colours by LUMINANCE), read from the evaluated mesh (after modifiers). Raises
    MeshExportError with words the user can act on (`where`: the panel that names them)."""
    check_object(obj)
    evaluated = obj.evaluated_get(depsgraph)
    data = evaluated.to_mesh()
    try:
        if len(data.vertices) != mesh.vertex_count or len(data.loops) != mesh.loop_count:
            raise MeshExportError(
                f"The mesh of '{obj.name}' changed while its fields were read: press Reset.")
        corners = array.array("f", bytes(4 * 12 * mesh.triangle_count))
        for channel, (label, name) in enumerate(zip(labels, names)):
            if not name:
                continue
            values, domain = _named_values(obj, data, name, label, where)
            # Corner -> vertex (triangles) or corner -> loop (triangle_uvs: loop indices).
            index = mesh.triangles if domain == 'POINT' else mesh.loops
            corners[channel::4] = array.array("f", map(values.__getitem__, index))
        return corners
    finally:
        evaluated.to_mesh_clear()


def _named_values(obj, data, name, label, where=FIELDS_WHERE):
    """(array('f') of values, 'POINT' or 'CORNER') of a vertex group or attribute."""
    group = obj.vertex_groups.get(name)
    if group is not None:
        return _vertex_group_weights(obj, data, group, label), 'POINT'
    attribute = data.attributes.get(name)
    if attribute is None:
        original = obj.data.attributes.get(name) if obj.data is not None else None
        if original is not None:
            raise MeshExportError(
                f"{label}: the modifiers of '{obj.name}' remove the attribute '{name}': "
                f"turn off or apply the modifier that drops it, or pick another "
                f"attribute.")
        groups = ", ".join(f"'{g.name}'" for g in obj.vertex_groups) or "none"
        attributes = ", ".join(f"'{a.name}'" for a in data.attributes
                               if not a.name.startswith(".")) or "none"
        raise MeshExportError(
            f"{label}: '{name}' is neither a vertex group of '{obj.name}' nor an attribute "
            f"of its mesh (vertex groups: {groups}; attributes: {attributes}). Fix the name "
            f"in {where}, or clear it.")
    domain, kind = attribute.domain, attribute.data_type
    if domain not in ('POINT', 'CORNER'):
        raise MeshExportError(
            f"{label}: attribute '{name}' is stored per {_DOMAIN_WORDS.get(domain, domain)}; "
            f"Moldtex reads Vertex or Face Corner attributes: store it on one of those "
            f"domains (e.g. Geometry Nodes' Store Named Attribute), or use a vertex group.")
    count = len(attribute.data)
    if kind == 'FLOAT':
        values = array.array("f", bytes(4 * count))
        attribute.data.foreach_get("value", values)
    elif kind in ('FLOAT_COLOR', 'BYTE_COLOR'):
        colors = array.array("f", bytes(4 * 4 * count))
        attribute.data.foreach_get("color_srgb", colors)
        r, g, b = LUMINANCE
        values = array.array("f", [r * cr + g * cg + b * cb for cr, cg, cb
                                   in zip(colors[0::4], colors[1::4], colors[2::4])])
    else:
        raise MeshExportError(
            f"{label}: attribute '{name}' holds {kind.replace('_', ' ').lower()} values; "
            f"Moldtex reads Float and Color attributes (and vertex groups): convert it, "
            f"or pick another.")
    if not all(map(math.isfinite, values)):
        raise MeshExportError(
            f"{label}: attribute '{name}' holds values that are not numbers (NaN or "
            f"infinite): fix them, or pick another attribute.")
    return values, domain


def _vertex_group_weights(obj, data, group, label):
    """Weights of `group` on the evaluated mesh's vertices (0 where unassigned). Blender
    has no bulk read of weights: this loop takes 0.04 to 0.12 s per 100,000 vertices
    (measured on Blender 3.4 and 4.2; more when vertices belong to many groups)."""
    index = group.index
    weights = array.array("f", bytes(4 * len(data.vertices)))
    assigned = 0
    for vertex in data.vertices:
        for element in vertex.groups:
            if element.group == index:
                weights[vertex.index] = element.weight
                assigned += 1
                break
    if assigned == 0 and data.vertices and obj.data is not None and any(
            element.group == index for vertex in obj.data.vertices
            for element in vertex.groups):
        raise MeshExportError(
            f"{label}: the modifiers of '{obj.name}' drop the vertex group '{group.name}' "
            f"(modifiers that rebuild the mesh, such as Remesh, do): turn that modifier "
            f"off, or apply it and paint the group on the result.")
    return weights
