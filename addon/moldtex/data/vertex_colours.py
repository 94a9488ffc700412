# SPDX-License-Identifier: GPL-3.0-or-later
"""The pheromone of a mesh without UVs, as a colour per vertex.

The Intrinsic domain runs on the surface itself and needs UVs only to write a texture.
On a mesh without a UV map the core reads its result at the mesh's vertices
(moldtex_sim_read_vertex_rgba, the values the image would hold) and this module stores
them in the colour attribute ATTRIBUTE of the object's mesh (Vertex domain, float
colour), which the material reads through a Color Attribute node (colour/material.py).

The simulation runs on the evaluated mesh (after modifiers); the attribute lives on the
object's own mesh. They match vertex for vertex when no modifier changes the topology.
Generating modifiers such as Subdivision Surface, Mirror or Array keep the original
vertices first, in order, so those get the values of their evaluated selves and the
modifier interpolates the rest. A modifier that renumbers the vertices (Remesh) breaks
that: `correspondence_problem` notices it (the original vertices are not where their
evaluated namesakes are), and the panel says so.
"""

import array
import math

ATTRIBUTE = "Moldtex"

# Original vertex i and evaluated vertex i count as the same vertex when they lie within
# this many mean edge lengths of each other (Subdivision moves a vertex to its limit
# position: well under one edge of the base mesh).
_MATCH_EDGES = 0.5


def correspondence_problem(obj, evaluated_positions):
    """"" when obj's own mesh vertices are the first vertices of the evaluated mesh
    (evaluated_positions: array('f'), x y z per vertex, mesh units as exported), else a
    sentence for the user."""
    data = obj.data
    count = len(data.vertices)
    if count == 0:
        return ""
    if count * 3 > len(evaluated_positions):
        return (f"The modifiers of '{obj.name}' remove vertices, so its vertex colours "
                f"cannot follow the simulation: apply them, or add a UV map.")
    own = array.array("f", bytes(12 * count))
    data.vertices.foreach_get("co", own)
    from .mesh_export import export_scale  # (the exported coordinates carry it)
    scale = export_scale(obj)
    if scale is not None:
        for axis in range(3):
            own[axis::3] = array.array("f", (v * scale[axis] for v in own[axis::3]))
    if count * 3 == len(evaluated_positions) and own == evaluated_positions[:3 * count]:
        return ""
    edge_sum, edges = 0.0, 0
    for edge in data.edges[:2000]:
        a, b = edge.vertices
        edge_sum += math.dist(own[3 * a:3 * a + 3], own[3 * b:3 * b + 3])
        edges += 1
    mean_edge = edge_sum / edges if edges else 0.0
    step = max(1, count // 2000)
    far = sum(math.dist(own[3 * i:3 * i + 3], evaluated_positions[3 * i:3 * i + 3])
              > _MATCH_EDGES * mean_edge for i in range(0, count, step))
    if far > 0.05 * len(range(0, count, step)):
        return (f"The modifiers of '{obj.name}' renumber its vertices (as Remesh does), "
                f"so its vertex colours do not follow the simulation: apply them, or add "
                f"a UV map.")
    return ""


def write(obj, rgba):
    """Stores rgba (array('f'), 4 floats per evaluated vertex) in obj's colour attribute
    ATTRIBUTE, creating it; obj's own vertices take the first values (see the module
    text). Returns the attribute."""
    mesh = obj.data
    attribute = mesh.color_attributes.get(ATTRIBUTE)
    if attribute is not None and (attribute.domain != 'POINT' or attribute.data_type != 'FLOAT_COLOR'):
        mesh.color_attributes.remove(attribute)
        attribute = None
    if attribute is None:
        attribute = mesh.color_attributes.new(ATTRIBUTE, 'FLOAT_COLOR', 'POINT')
    count = len(mesh.vertices)
    values = rgba if len(rgba) == 4 * count else rgba[:4 * count]
    attribute.data.foreach_set("color", values)
    mesh.update()
    return attribute
