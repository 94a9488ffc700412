"""A mesh without a UV map (issue 11: "the simulation still runs; only the texture write
needs UVs; say so in the panel"). The Intrinsic domain runs on it and shows the pattern
as the colour attribute 'Moldtex', one colour per vertex, through the material's Color
Attribute node; the Texture domain, MoMaS and bakes refuse it with what to do."""

import os
import shutil
import tempfile
import unittest

import bpy

import helpers as h
from test_ui import draw_all, labels


def without_uvs(obj):
    while len(obj.data.uv_layers):
        obj.data.uv_layers.remove(obj.data.uv_layers[0])
    return obj


def intrinsic(obj, resolution="128", agents=20000):
    h.configure(obj, resolution=resolution, agents=agents)
    obj.moldtex.model = 'CONTINUOUS'
    obj.moldtex.domain = 'INTRINSIC'
    return obj


def vertex_colours(obj):
    attribute = obj.data.color_attributes.get("Moldtex")
    if attribute is None:
        return None
    values = [0.0] * (4 * len(attribute.data))
    attribute.data.foreach_get("color", values)
    return attribute, values


class NoUvMapTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_no_uv_")

    def tearDown(self):
        h.clear_scene()
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_intrinsic_domain_colours_the_vertices(self):
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=5)  # 2,562 vertices
        obj = intrinsic(without_uvs(h.activate(bpy.context.active_object)))
        self.assertEqual(len(obj.data.uv_layers), 0)
        text = labels(draw_all(self, obj))
        self.assertIn("Intrinsic domain still runs", text)
        self.assertEqual(bpy.ops.moldtex.step(steps=60), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertTrue(entry.vertex_colours)
        self.assertEqual(entry.vertex_problem, "")
        found = vertex_colours(obj)
        self.assertIsNotNone(found, "Step wrote no colour attribute")
        attribute, values = found
        self.assertEqual((attribute.domain, attribute.data_type), ('POINT', 'FLOAT_COLOR'))
        self.assertEqual(len(attribute.data), len(obj.data.vertices))
        # What the core holds at each vertex (u / U), grey, opaque.
        expected = entry.sim.read_vertex_rgba()
        worst = max(abs(a - b) for a, b in zip(values, expected))
        self.assertLess(worst, 1e-6)
        red = values[0::4]
        self.assertEqual(red, values[1::4])
        self.assertTrue(all(a == 1.0 for a in values[3::4]))
        # A network, not a wash: after 60 steps (3 s) the mean nears U (1) and trails
        # stand well above it while the space between them is far below.
        mean = sum(red) / len(red)
        print(f"    no UVs: {len(red):,} vertices, mean {mean:.3f} U, max {max(red):.2f} U, "
              f"{entry.domain_info['cell_count']:,} intrinsic vertices")
        self.assertGreater(mean, 0.5)
        self.assertLess(mean, 1.5)
        self.assertGreater(max(red), 2.0)
        self.assertLess(sorted(red)[len(red) // 10], 0.5 * mean)
        # The material reads the attribute: Color Attribute node into the Range node.
        self.assertNotIn("has no UV map", text)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        tree = obj.active_material.node_tree
        node = tree.nodes.get("Moldtex Vertex Colours")
        self.assertIsNotNone(node)
        self.assertEqual(node.layer_name, "Moldtex")
        span = tree.nodes["Moldtex Range"]
        self.assertEqual(span.inputs[0].links[0].from_node, node)
        self.assertIsNone(tree.nodes.get("Moldtex Texture"))
        # Writing the colours is not an edit of the mesh: the depsgraph update it causes
        # does not send the next step to export and compare the mesh again; an edit does.
        sim = entry.sim
        self.assertEqual(bpy.ops.moldtex.step(steps=2), {'FINISHED'})
        bpy.context.view_layer.update()
        self.assertFalse(entry.dirty)
        self.assertEqual(bpy.ops.moldtex.step(steps=2), {'FINISHED'})
        self.assertIs(h.live().get(obj.name).sim, sim)
        self.assertEqual(entry.stats["step_count"], 64)
        obj.data.vertices[0].co.z += 0.01
        obj.data.update()
        bpy.context.view_layer.update()
        self.assertTrue(entry.dirty)
        # Bakes write textures: refused, saying why and what to do.
        h.bake_settings(obj, self.folder, 1, 2, 5, "EXR_HALF")
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.bake()
        self.assertIn("has no UV map", str(caught.exception))
        self.assertEqual(os.listdir(self.folder), [])

    def test_subdivision_keeps_the_base_vertices(self):
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)  # 162 vertices
        obj = intrinsic(without_uvs(h.activate(bpy.context.active_object)), agents=5000)
        modifier = obj.modifiers.new("Subdivision", 'SUBSURF')
        modifier.levels = 1
        self.assertEqual(bpy.ops.moldtex.step(steps=20), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertEqual(entry.vertex_problem, "")
        self.assertGreater(entry.sim.vertex_count, len(obj.data.vertices))
        _attribute, values = vertex_colours(obj)
        core = entry.sim.read_vertex_rgba()
        # The base vertices are the first of the subdivided mesh.
        self.assertEqual(len(values), 4 * len(obj.data.vertices))
        self.assertLess(max(abs(a - b) for a, b in zip(values, core)), 1e-6)

        # Remesh renumbers the vertices: said, not silently wrong.
        h.clear_scene()
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)
        obj = intrinsic(without_uvs(h.activate(bpy.context.active_object)), agents=5000)
        remesh = obj.modifiers.new("Remesh", 'REMESH')
        remesh.mode = 'VOXEL'
        remesh.voxel_size = 0.1
        self.assertEqual(bpy.ops.moldtex.step(steps=2), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertIn("renumber", entry.vertex_problem)
        self.assertIn("renumber", labels(draw_all(self, obj)))

    def test_brushes(self):
        """Slime and food brushes work on the surface; the Fields brushes paint an image
        laid out by the UV map, so they refuse, saying why."""
        bpy.ops.mesh.primitive_grid_add(x_subdivisions=40, y_subdivisions=40, size=2.0)
        obj = intrinsic(without_uvs(h.activate(bpy.context.active_object)), agents=2000)
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        before = len(h.agent_positions(obj))
        settings = bpy.context.scene.moldtex_brush
        settings.target, settings.erase, settings.radius = 'SLIME', False, 0.2
        settings.agents_per_dab = 300
        stroke = [{"name": "", "location": (0.3, 0.2, 1.0), "direction": (0.0, 0.0, -1.0)}]
        self.assertEqual(bpy.ops.moldtex.brush_stroke(stroke=stroke), {'FINISHED'})
        self.assertEqual(len(h.agent_positions(obj)), before + 300)
        settings.target = 'OBSTACLE'
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.brush_stroke(stroke=stroke)
        self.assertIn("UV map", str(caught.exception))
        self.assertIsNone(obj.moldtex.fields_image)

    def test_vertex_group_obstacle(self):
        """Fields from a vertex group (what the brush's refusal suggests) work: agents
        stay out of an obstacle group covering x > 0.2 of a 2 x 2 grid."""
        bpy.ops.mesh.primitive_grid_add(x_subdivisions=40, y_subdivisions=40, size=2.0)
        obj = intrinsic(without_uvs(h.activate(bpy.context.active_object)), agents=4000)
        group = obj.vertex_groups.new(name="Wall")
        group.add([v.index for v in obj.data.vertices if v.co.x > 0.2], 1.0, 'REPLACE')
        obj.moldtex.fields_source = 'ATTRIBUTES'
        obj.moldtex.obstacle_attribute = "Wall"
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        self.assertEqual(bpy.ops.moldtex.step(steps=40), {'FINISHED'})
        xs = [p[0] for p in h.agent_positions(obj)]
        inside = sum(1 for x in xs if x > 0.3)  # (a vertex's cell reaches half an edge on)
        print(f"    vertex-group obstacle: {inside} of {len(xs)} agents beyond x = 0.3")
        # Free ground is 60% of the grid: without the wall about 35% would be beyond 0.3.
        self.assertLess(inside, 0.01 * len(xs))

    def test_texture_domain_and_momas_refuse(self):
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2)
        obj = without_uvs(h.activate(bpy.context.active_object))
        h.configure(obj, resolution="128", agents=500)
        for model, domain in (('MOMAS', 'TEXTURE'), ('CONTINUOUS', 'TEXTURE')):
            obj.moldtex.model = model
            obj.moldtex.domain = domain
            with self.assertRaises(RuntimeError) as caught:
                bpy.ops.moldtex.step(steps=1)
            message = str(caught.exception)
            self.assertIn("has no UV map", message)
            self.assertIn("Intrinsic", message)
            self.assertIn("Intrinsic", labels(draw_all(self, obj)))
        self.assertEqual(h.live().names(), [])

    def test_a_uv_map_of_zero_area_counts_as_none(self):
        """A UV map whose UVs have no area (all on one point, or all on one line: a
        careless unwrap, an importer's placeholder) gives no texture to grow in. The
        Intrinsic domain runs as without a UV map, and says which map it set aside; the
        Texture domain and bakes refuse, naming the map."""
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)  # 642 vertices, with UVs
        obj = h.activate(bpy.context.active_object)
        layer = obj.data.uv_layers[0]
        for collapse in ("point", "line"):
            uvs = [0.5] * (2 * len(layer.data))
            if collapse == "line":  # u spread over [0, 1], v fixed: still no area
                uvs[0::2] = [(k % 97) / 96.0 for k in range(len(layer.data))]
            layer.data.foreach_set("uv", uvs)
            obj.data.update()
            intrinsic(obj, agents=5000)
            self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
            self.assertEqual(bpy.ops.moldtex.step(steps=20), {'FINISHED'}, collapse)
            entry = h.live().get(obj.name)
            self.assertTrue(entry.vertex_colours, collapse)
            self.assertEqual(entry.flat_uv_map, layer.name)
            _attribute, values = vertex_colours(obj)
            core = entry.sim.read_vertex_rgba()
            self.assertLess(max(abs(a - b) for a, b in zip(values, core)), 1e-6)
            self.assertGreater(max(values[0::4]), 0.0)  # agents deposited
            self.assertIn("has no area", labels(draw_all(self, obj)))
            self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
            tree = obj.active_material.node_tree
            self.assertIsNotNone(tree.nodes.get("Moldtex Vertex Colours"))
            self.assertIsNone(tree.nodes.get("Moldtex Texture"))
            h.bake_settings(obj, self.folder, 1, 2, 5, "EXR_HALF")
            with self.assertRaises(RuntimeError) as caught:
                bpy.ops.moldtex.bake()
            self.assertIn(f"UV map ('{layer.name}') whose UVs have no area", str(caught.exception))
            self.assertEqual(os.listdir(self.folder), [])
            obj.moldtex.domain = 'TEXTURE'  # (a new domain takes a Reset)
            with self.assertRaises(RuntimeError) as caught:
                bpy.ops.moldtex.reset()
            self.assertIn("whose UVs have no area", str(caught.exception))
            self.assertIn("Intrinsic", str(caught.exception))
        # The same mesh unwrapped (its UVs spread out again) runs on the texture.
        bpy.ops.object.mode_set(mode='EDIT')
        bpy.ops.mesh.select_all(action='SELECT')
        bpy.ops.uv.smart_project()
        bpy.ops.object.mode_set(mode='OBJECT')
        self.assertEqual(bpy.ops.moldtex.step(steps=2), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertFalse(entry.vertex_colours)
        self.assertEqual(entry.flat_uv_map, "")


if __name__ == "__main__":
    unittest.main()
