# SPDX-License-Identifier: GPL-3.0-or-later
"""The names of the Moldtex nodes in a material, and finding one (bpy data only; imports
nothing of the add-on). Set Up Material (material.py) makes them."""

UV_NODE = "Moldtex UV"
TEXTURE_NODE = "Moldtex Texture"
VERTEX_NODE = "Moldtex Vertex Colours"  # a mesh without UVs: the colour attribute
RAMP_NODE = "Moldtex Ramp"
RANGE_NODE = "Moldtex Range"  # image value 0..display_maximum -> ramp 0..1
SPECIES_NODE_PREFIX = "Moldtex Species "  # colour by species (2 or more)
CHANNEL_NODE = "Moldtex V"  # one channel (Model.display_channel) into the Range node
# (the name saved files have: kept, so that they find it again)
FIELDS_NODE = "Moldtex Fields"
OVERLAY_NODE = "Moldtex Fields Overlay"  # base colour + fields colour * strength


def moldtex_node(obj, name):
    """One of our nodes (UV_NODE, TEXTURE_NODE, RANGE_NODE, RAMP_NODE, FIELDS_NODE,
    OVERLAY_NODE) in obj's active material."""
    material = obj.active_material if obj is not None else None
    if material is None or material.node_tree is None:
        return None
    return material.node_tree.nodes.get(name)
