# SPDX-License-Identifier: GPL-3.0-or-later
"""Set Up Material: wires the pheromone image into the object's material.

UV Map ▸ Image Texture ▸ Map Range ▸ Color Ramp ▸ Principled BSDF Base Color; for a mesh
without UVs (the Intrinsic domain runs on it), Color Attribute "Moldtex" (one colour per
vertex, vertex_colours.py) in place of the UV Map and Image Texture. The Map
Range node spans what the image holds: MoMaS pheromone 0..1, the continuous model's
u / U 0..Display Range (1 = the uniform steady state), a model's one channel where its
image holds several (Model.display_channel, through a Separate Color node) 0..its
Display Range, so one ramp fits all and the
live image and a baked sequence (the same values) look alike. The user's nodes are
kept; our nodes are found again by name, so running it twice adds nothing. On the way
to Base Color the Fields image can be laid over the pheromone (Show Fields: walls
green, attractors blue, spawn regions red), so that what the brush paints is seen.
"""

import json

import bpy

from ..settings import events
from ..sim import convert, registry

from .nodes import (CHANNEL_NODE, FIELDS_NODE, OVERLAY_NODE, RAMP_NODE, RANGE_NODE,  # noqa: F401
                    SPECIES_NODE_PREFIX, TEXTURE_NODE, UV_NODE, VERTEX_NODE, moldtex_node)

OVERLAY_STRENGTH = 0.6

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

    vertex_colours = not uv_map_name  # no UV map: the pheromone per mesh vertex
    if vertex_colours:
        from ..data.vertex_colours import ATTRIBUTE  # (imports nothing of ours but bpy)
        for name in (UV_NODE, TEXTURE_NODE, FIELDS_NODE):
            if nodes.get(name) is not None:
                nodes.remove(nodes[name])
        texture, _ = _node(nodes, VERTEX_NODE, "ShaderNodeVertexColor", "Moldtex Vertex Colours")
        texture.layer_name = ATTRIBUTE
    else:
        if nodes.get(VERTEX_NODE) is not None:
            nodes.remove(nodes[VERTEX_NODE])
        uv, _ = _node(nodes, UV_NODE, "ShaderNodeUVMap", "Moldtex UV Map")
        texture, _ = _node(nodes, TEXTURE_NODE, "ShaderNodeTexImage", "Moldtex Pheromone")
        uv.uv_map = uv_map_name
        texture.image = image
        texture.interpolation = 'Linear'
    ramp, ramp_created = _node(nodes, RAMP_NODE, "ShaderNodeValToRGB", "Moldtex Ramp")
    span, span_created = _node(nodes, RANGE_NODE, "ShaderNodeMapRange", "Moldtex Range")
    x, y = principled.location.x, principled.location.y
    if ramp_created:
        stops, interpolation = preset_ramp(obj)
        set_ramp(ramp, stops or DEFAULT_RAMP, interpolation)
        ramp.location = (x - 320.0, y)
    texture.location = (x - 820.0, y)
    if not vertex_colours:
        uv.location = (x - 1040.0, y - 60.0)
    if span_created:
        span.data_type = 'FLOAT'
        span.interpolation_type = 'LINEAR'
        span.clamp = True
        span.location = (ramp.location.x - 200.0, ramp.location.y)

    links = tree.links
    if not vertex_colours:
        links.new(uv.outputs["UV"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], span.inputs[0])
    links.new(span.outputs[0], ramp.inputs["Fac"])
    for node in [n for n in nodes if n.name.startswith(SPECIES_NODE_PREFIX)]:
        nodes.remove(node)
    count = _species_shown(obj)
    if count >= 2:
        base = _species_mix(tree, obj.moldtex, texture, count, ramp.location).outputs["Vector"]
    else:
        base = ramp.outputs["Color"]
    sync_display_range(obj)
    overlay, overlay_created = _node(nodes, OVERLAY_NODE, "ShaderNodeVectorMath",
                                     "Moldtex Fields Overlay")
    overlay.operation = 'MULTIPLY_ADD'
    if overlay_created:
        overlay.location = (principled.location.x - 180.0, principled.location.y + 260.0)
    if not vertex_colours:  # (the Fields image lies in the UV layout)
        fields, fields_created = _node(nodes, FIELDS_NODE, "ShaderNodeTexImage",
                                       "Moldtex Fields")
        if fields_created:
            fields.interpolation = 'Closest'
            fields.location = (texture.location.x, texture.location.y + 300.0)
        links.new(uv.outputs["UV"], fields.inputs["Vector"])
        links.new(fields.outputs["Color"], overlay.inputs[0])
    links.new(base, overlay.inputs[2])
    links.new(overlay.outputs["Vector"], principled.inputs["Base Color"])
    show_fields(obj, obj.moldtex.show_fields)
    return material


def _model(obj):
    """The models.base.Model of the image shown: that of the live simulation (whose image
    or bake is shown), else the one the settings ask for."""
    entry = registry.get(obj.name)
    model = convert.sim_model_for(entry) if entry is not None and entry.has_sim else None
    return convert.model_for(obj.moldtex) if model is None else model


def _species_shown(obj):
    """How many species the image's colours stand for (1 for a model without agents)."""
    return int(obj.moldtex.species_count) if _model(obj).has_agents else 1


def display_maximum(obj):
    """The image value shown at the top of the ramp: 1 for MoMaS (pheromone in [0, 1]),
    the model's Display Range for the others (Model.display_maximum)."""
    return _model(obj).display_maximum(obj.moldtex)


def _sync_channel(obj, tree):
    """A model whose image holds several quantities (Model.display_channel) has the
    Range node read that channel alone (through a Separate Color node); the other
    models' single-species images are grey, read whole. Changes nothing that already
    matches."""
    nodes, links = tree.nodes, tree.links
    texture, span = nodes.get(VERTEX_NODE) or nodes.get(TEXTURE_NODE), nodes.get(RANGE_NODE)
    if texture is None or span is None:
        return
    channel = nodes.get(CHANNEL_NODE)
    model = _model(obj)
    shown = model.display_channel
    if shown is not None:
        if channel is None:
            channel = nodes.new("ShaderNodeSeparateColor")
            channel.name = CHANNEL_NODE
            channel.location = (span.location.x - 180.0, span.location.y - 160.0)
        label = f"Moldtex {model.label} ({shown})"
        if channel.label != label:
            channel.label = label
        if not channel.inputs[0].is_linked:
            links.new(texture.outputs["Color"], channel.inputs[0])
        wanted = channel.outputs["RGB".index(shown)]
    else:
        if channel is not None:
            nodes.remove(channel)
        wanted = texture.outputs["Color"]
    source = span.inputs[0].links[0].from_socket if span.inputs[0].is_linked else None
    if source != wanted:
        links.new(wanted, span.inputs[0])


def sync_display_range(obj):
    """Points the Range node (and the species' colour weights) at display_maximum(obj);
    changes nothing that already matches (a change recompiles the material). False if
    the material has no Moldtex nodes."""
    span = moldtex_node(obj, RANGE_NODE)
    if span is None:
        return False
    maximum = display_maximum(obj)
    _sync_channel(obj, obj.active_material.node_tree)
    inputs = span.inputs  # Value, From Min, From Max, To Min, To Max (float sockets)
    for index, value in ((1, 0.0), (2, maximum), (3, 0.0), (4, 1.0)):
        if abs(inputs[index].default_value - value) > 1e-9 * max(1.0, value):
            inputs[index].default_value = value
    settings = obj.moldtex
    tree = obj.active_material.node_tree
    for index in range(_species_shown(obj)):
        node = tree.nodes.get(f"{SPECIES_NODE_PREFIX}{index + 1}")
        if node is None:
            continue
        color = (tuple(settings.species[index].color) if index < len(settings.species)
                 else (1.0, 1.0, 1.0))
        weighted = tuple(c / maximum for c in color)
        if any(abs(a - b) > 1e-7 for a, b in zip(node.inputs[0].default_value, weighted)):
            node.inputs[0].default_value = weighted
    return True


def show_fields(obj, show):
    """Lays the object's Fields image over the pheromone in its Moldtex material, or
    takes it off (strength 0 gives the pheromone colour unchanged). False if the
    material has no Moldtex nodes (Set Up Material makes them)."""
    fields, overlay = moldtex_node(obj, FIELDS_NODE), moldtex_node(obj, OVERLAY_NODE)
    if overlay is not None and fields is None and moldtex_node(obj, VERTEX_NODE) is not None:
        overlay.inputs[1].default_value = (0.0, 0.0, 0.0)  # no UVs: no Fields image shown
        return True
    if fields is None or overlay is None:
        return False
    image = obj.moldtex.fields_image
    if fields.image != image:
        fields.image = image
    if image is not None and image.colorspace_settings.name != 'Non-Color':
        image.colorspace_settings.name = 'Non-Color'
    strength = OVERLAY_STRENGTH if show and image is not None else 0.0
    overlay.inputs[1].default_value = (strength, strength, strength)
    return True


def _species_mix(tree, settings, texture, count, location):
    """Species k's channel (R, G, B, A) times its colour, summed; returns the last node."""
    nodes, links = tree.nodes, tree.links
    separate = nodes.new("ShaderNodeSeparateColor")
    separate.name = SPECIES_NODE_PREFIX + "Channels"
    separate.label = "Moldtex Species Channels"
    separate.location = (location.x, location.y - 300.0)
    links.new(texture.outputs["Color"], separate.inputs[0])
    channels = [separate.outputs[0], separate.outputs[1], separate.outputs[2],
                texture.outputs["Alpha"]]
    total = None
    for index in range(count):
        color = (tuple(settings.species[index].color) if index < len(settings.species)
                 else (1.0, 1.0, 1.0))
        scale = nodes.new("ShaderNodeVectorMath")
        scale.operation = 'SCALE'
        scale.name = f"{SPECIES_NODE_PREFIX}{index + 1}"
        scale.label = f"Moldtex Species {index + 1}"
        scale.location = (location.x + 180.0, location.y - 300.0 - 160.0 * index)
        scale.inputs[0].default_value = color
        links.new(channels[index], scale.inputs["Scale"])
        if total is None:
            total = scale
            continue
        add = nodes.new("ShaderNodeVectorMath")
        add.operation = 'ADD'
        add.name = f"{SPECIES_NODE_PREFIX}Sum {index + 1}"
        add.label = "Moldtex Species Sum"
        add.location = (location.x + 360.0, location.y - 300.0 - 160.0 * index)
        links.new(total.outputs["Vector"], add.inputs[0])
        links.new(scale.outputs["Vector"], add.inputs[1])
        total = add
    return total


def sync_uv_map(obj, uv_map_name):
    """Points an existing Moldtex UV Map node at the UV map the simulation uses."""
    material = obj.active_material
    if material is None or material.node_tree is None:
        return
    node = material.node_tree.nodes.get(UV_NODE)
    if node is not None and node.uv_map != uv_map_name:
        node.uv_map = uv_map_name


def set_ramp(ramp_node, stops, interpolation='LINEAR'):
    """Replaces the elements of a ColorRamp node: stops = [(position, (r, g, b, a))]."""
    stops = sorted(((float(p), tuple(float(c) for c in color)) for p, color in stops),
                   key=lambda stop: stop[0])
    if not stops:
        raise ValueError("a colour ramp needs at least one stop")
    color_ramp = ramp_node.color_ramp
    elements = color_ramp.elements
    while len(elements) > 1:  # a ramp keeps at least one element
        elements.remove(elements[-1])
    first_position, first_color = stops[0]
    elements[0].position = first_position
    elements[0].color = _rgba(first_color)
    for position, color in stops[1:]:
        element = elements.new(position)
        element.color = _rgba(color)
    color_ramp.interpolation = interpolation


def _rgba(color):
    return tuple(color) + (1.0,) * (4 - len(color)) if len(color) < 4 else tuple(color[:4])


def store_preset_ramp(obj, stops, interpolation):
    """Remembers a preset's ramp on the object, for a Set Up Material still to come."""
    obj.moldtex.ramp_stops = json.dumps(
        {"stops": [[float(p), list(_rgba(c))] for p, c in stops],
         "interpolation": interpolation})


def preset_ramp(obj):
    """(stops, interpolation) remembered by store_preset_ramp, or (None, 'LINEAR')."""
    text = obj.moldtex.ramp_stops
    if not text:
        return None, 'LINEAR'
    try:
        data = json.loads(text)
        stops = [(float(p), tuple(float(c) for c in color)) for p, color in data["stops"]]
        return stops or None, str(data.get("interpolation", 'LINEAR'))
    except (ValueError, KeyError, TypeError):
        return None, 'LINEAR'


def show_image(obj, image):
    """Points an existing Moldtex Image Texture node at `image` (e.g. back at the live
    pheromone after a baked sequence was shown)."""
    node = moldtex_node(obj, TEXTURE_NODE)
    if node is not None and node.image != image:
        node.image = image


def apply_ramp(obj, stops, interpolation='LINEAR'):
    """Sets the Moldtex Ramp node of obj's material to `stops` ([(position, (r, g, b,
    a)), ...]) if it exists, and remembers them so that a later Set Up Material (or a
    bake's playback setup) uses them too."""
    store_preset_ramp(obj, stops, interpolation)
    node = moldtex_node(obj, RAMP_NODE)
    if node is not None:
        set_ramp(node, stops, interpolation)


# ---- what a settings change asks of the material (settings/events.py) -----------------

def _show_fields_changed(obj):
    show_fields(obj, obj.moldtex.show_fields)


def register():
    events.listen("show_fields", _show_fields_changed)
    events.listen("display_range", sync_display_range)


def unregister():
    events.forget("display_range", sync_display_range)
    events.forget("show_fields", _show_fields_changed)
