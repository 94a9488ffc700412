# SPDX-License-Identifier: GPL-3.0-or-later
"""Set Up Material: wires the pheromone image into the object's material.

UV Map ▸ Image Texture ▸ Color Ramp ▸ Principled BSDF Base Color. The user's nodes are
kept; our nodes are found again by name, so running it twice adds nothing.
"""

import bpy

UV_NODE = "Moldtex UV"
TEXTURE_NODE = "Moldtex Texture"
RAMP_NODE = "Moldtex Ramp"

# Dark violet-black through amber to bright yellow.
DEFAULT_RAMP = (
    (0.0, (0.004, 0.003, 0.010, 1.0)),
    (0.35, (0.30, 0.10, 0.005, 1.0)),
    (1.0, (1.0, 0.85, 0.08, 1.0)),
)


def _node(nodes, name, type_name, label):
    node = nodes.get(name)
    created = node is None
    if created:
        node = nodes.new(type_name)
        node.name = name
        node.label = label
    return node, created


def _principled(tree):
    """The Principled BSDF feeding the material output, creating both if needed."""
    nodes = tree.nodes
    output = None
    for node in nodes:
        if node.type == 'OUTPUT_MATERIAL' and (output is None or node.is_active_output):
            output = node
    if output is not None and output.inputs["Surface"].is_linked:
        source = output.inputs["Surface"].links[0].from_node
        if source.type == 'BSDF_PRINCIPLED':
            return source
    for node in nodes:
        if node.type == 'BSDF_PRINCIPLED':
            principled = node
            break
    else:
        principled = nodes.new("ShaderNodeBsdfPrincipled")
        principled.location = (10.0, 300.0)
    if output is None:
        output = nodes.new("ShaderNodeOutputMaterial")
        output.location = (principled.location.x + 400.0, principled.location.y)
    if not output.inputs["Surface"].is_linked:
        tree.links.new(principled.outputs["BSDF"], output.inputs["Surface"])
    return principled


def setup_material(obj, image, uv_map_name):
    """Adds (or updates) the Moldtex nodes in obj's active material; returns it."""
    material = obj.active_material
    if material is None:
        material = bpy.data.materials.new(f"Moldtex {obj.name}")
        if len(obj.material_slots) and obj.material_slots[obj.active_material_index].link:
            obj.active_material = material
        else:
            obj.data.materials.append(material)
            obj.active_material_index = len(obj.material_slots) - 1
    material.use_nodes = True
    tree = material.node_tree
    nodes = tree.nodes
    principled = _principled(tree)

    uv, _ = _node(nodes, UV_NODE, "ShaderNodeUVMap", "Moldtex UV Map")
    texture, _ = _node(nodes, TEXTURE_NODE, "ShaderNodeTexImage", "Moldtex Pheromone")
    ramp, ramp_created = _node(nodes, RAMP_NODE, "ShaderNodeValToRGB", "Moldtex Ramp")

    uv.uv_map = uv_map_name
    texture.image = image
    texture.interpolation = 'Linear'
    if ramp_created:
        elements = ramp.color_ramp.elements
        while len(elements) < len(DEFAULT_RAMP):
            elements.new(0.5)
        for element, (position, color) in zip(elements, DEFAULT_RAMP):
            element.position = position
            element.color = color
        x, y = principled.location.x, principled.location.y
        ramp.location = (x - 320.0, y)
        texture.location = (x - 640.0, y)
        uv.location = (x - 860.0, y - 60.0)

    links = tree.links
    links.new(uv.outputs["UV"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], principled.inputs["Base Color"])
    return material


def sync_uv_map(obj, uv_map_name):
    """Points an existing Moldtex UV Map node at the UV map the simulation uses."""
    material = obj.active_material
    if material is None or material.node_tree is None:
        return
    node = material.node_tree.nodes.get(UV_NODE)
    if node is not None and node.uv_map != uv_map_name:
        node.uv_map = uv_map_name
