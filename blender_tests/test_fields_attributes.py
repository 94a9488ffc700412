"""Static fields from vertex groups and painted attributes (Fields Source = Attributes)."""

import array
import unittest

import bpy

import helpers as h

RESOLUTION = 128
CELL = 2.0 / 16      # the plane's quad size (3D units)
TEXEL = 2.0 / RESOLUTION  # one texel's 3D length: the UVs fill [0, 1]² on a 2 × 2 plane


def _plane():
    obj = h.subdivided_plane()
    h.configure(obj, resolution=str(RESOLUTION), agents=3000)
    return obj


def _reset(obj):
    h.activate(obj)
    assert bpy.ops.moldtex.reset() == {'FINISHED'}
    return h.live().get(obj.name)


def _fields(obj):
    return h.convert().fields_from_settings(obj.moldtex, RESOLUTION, RESOLUTION)


class FieldAttributeTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_vertex_group_obstacle_keeps_agents_out(self):
        # Weight 1 on the vertices left of x = 0 (0 elsewhere), read after a Simple
        # Subdivision modifier (the evaluated mesh interpolates the weights: 0.5 at
        # x = -CELL/2). The wall is where the interpolated weight is above 0.5, i.e. the
        # texels whose centre lies left of x = -CELL/2; an agent in the first texel to
        # the right may stand up to half a texel left of that texel's centre, so every
        # agent must be right of x = -CELL/2 - 1 texel (margin: that half texel plus
        # rounding). Checked after spawning (Random avoids walls), after 5 and after
        # 150 steps.
        obj = _plane()
        group = obj.vertex_groups.new(name="Wall")
        group.add([v.index for v in obj.data.vertices if v.co.x < -1e-6], 1.0, 'REPLACE')
        modifier = obj.modifiers.new("Subdivision", 'SUBSURF')
        modifier.subdivision_type = 'SIMPLE'
        modifier.levels = 1
        obj.moldtex.fields_source = 'ATTRIBUTES'
        obj.moldtex.obstacle_attribute = "Wall"
        fields = _fields(obj)
        # Wall share of the texels: x in [-1, -CELL/2) of [-1, 1] = 0.5 - CELL/4 (0.469).
        walls = sum(1 for g in fields[1::4] if g > 0.5) / (RESOLUTION * RESOLUTION)
        print(f"\n  vertex group wall: {walls:.3f} of the texels")
        self.assertAlmostEqual(walls, 0.5 - CELL / 4, delta=2.0 / RESOLUTION)
        self.assertEqual(max(fields[0::4]), 0.0)  # no spawn or attractor channel
        self.assertEqual(max(fields[2::4]), 0.0)
        limit = -CELL / 2 - TEXEL
        entry = _reset(obj)
        start = min(p[0] for p in h.agent_positions(obj))
        print(f"  spawned: leftmost agent at x = {start:.4f}")
        self.assertGreater(start, limit)
        # After 5 steps agents still crowd the wall (they spawned up to it); by step
        # 150 they have turned away from it (they sense -1e9 there).
        self.assertEqual(bpy.ops.moldtex.step(steps=5), {'FINISHED'})
        early = min(p[0] for p in h.agent_positions(obj))
        print(f"  after 5 steps: leftmost agent at x = {early:.4f}")
        self.assertGreater(early, limit)
        self.assertEqual(bpy.ops.moldtex.step(steps=145), {'FINISHED'})
        self.assertEqual(entry.stats["step_count"], 150)
        xs = [p[0] for p in h.agent_positions(obj)]
        print(f"  after 150 steps: leftmost agent at x = {min(xs):.4f} (wall edge "
              f"{-CELL / 2:.4f}, limit {limit:.4f}), {len(xs)} agents, "
              f"{sum(1 for x in xs if x < 0.0)} left of 0, "
              f"{sum(1 for x in xs if x < 0.5)} left of 0.5")
        self.assertGreater(min(xs), limit)

    def test_spawn_float_attribute_places_every_agent(self):
        # A FLOAT POINT attribute, 1 on the vertices with x > 0.5 and y > 0.5 (the
        # first such column and row lie at 0.625), 0 elsewhere: the spawn weight is
        # above 0 only in triangles touching those vertices, i.e. x, y > 0.5; agents
        # spawn at a uniform point of a texel with weight, so each is within
        # x, y > 0.5 - 1 texel (a texel whose centre is right of 0.5 reaches half a
        # texel left of it).
        obj = _plane()
        mesh = obj.data
        attribute = mesh.attributes.new("spawn", 'FLOAT', 'POINT')
        co = array.array("f", bytes(4 * 3 * len(mesh.vertices)))
        mesh.vertices.foreach_get("co", co)
        attribute.data.foreach_set("value", array.array("f", [
            1.0 if x > 0.5 + 1e-6 and y > 0.5 + 1e-6 else 0.0
            for x, y in zip(co[0::3], co[1::3])]))
        obj.moldtex.fields_source = 'ATTRIBUTES'
        obj.moldtex.spawn_attribute = "spawn"
        obj.moldtex.seed_shape = 'SPAWN_MAP'
        _reset(obj)
        positions = h.agent_positions(obj)
        low = 0.5 - TEXEL
        worst = min(min(p[0], p[1]) for p in positions)
        print(f"\n  spawn attribute: {len(positions)} agents, lowest x or y {worst:.4f} "
              f"(limit {low:.4f})")
        self.assertEqual(len(positions), 3000)
        self.assertGreater(worst, low)

    def test_colour_attributes_count_by_luminance(self):
        # Colours count by the luminance of their sRGB values (Rec. 709 weights): pure
        # red spawns with 0.2126, pure green attracts with 0.7152, on both domains.
        obj = _plane()
        mesh = obj.data
        red = mesh.color_attributes.new("Red", 'FLOAT_COLOR', 'CORNER')
        red.data.foreach_set("color_srgb", [1.0, 0.0, 0.0, 1.0] * len(mesh.loops))
        green = mesh.color_attributes.new("Green", 'BYTE_COLOR', 'POINT')
        green.data.foreach_set("color_srgb", [0.0, 1.0, 0.0, 1.0] * len(mesh.vertices))
        obj.moldtex.fields_source = 'ATTRIBUTES'
        obj.moldtex.spawn_attribute = "Red"
        obj.moldtex.attractor_attribute = "Green"
        fields = _fields(obj)
        middle = 4 * ((RESOLUTION // 2) * RESOLUTION + RESOLUTION // 3)
        self.assertAlmostEqual(fields[middle], 0.2126, places=4)
        self.assertEqual(fields[middle + 1], 0.0)
        self.assertAlmostEqual(fields[middle + 2], 0.7152, places=4)

    def test_bad_names_give_clear_errors(self):
        obj = _plane()
        mesh = obj.data
        mesh.attributes.new("Count", 'INT', 'POINT')
        mesh.attributes.new("Per Face", 'FLOAT', 'FACE')
        obj.moldtex.fields_source = 'ATTRIBUTES'
        cases = [("Nope", "'Nope' is neither a vertex group of 'Plane' nor an attribute"),
                 ("Count", "holds int values"),
                 ("Per Face", "stored per Face")]
        for name, words in cases:
            obj.moldtex.obstacle_attribute = name
            # Background mode turns the operator's error report into a RuntimeError.
            with self.assertRaises(RuntimeError) as caught:
                bpy.ops.moldtex.reset()
            self.assertIn(words, str(caught.exception))
            self.assertIn("Obstacle:", str(caught.exception))
        self.assertIsNone(h.live().get(obj.name))
        # A vertex group that the modifiers drop says so. (Remesh drops it, but also
        # the UVs, which is reported first: so the weights are read here from a mesh
        # that has none, as the evaluated mesh would be.)
        group = obj.vertex_groups.new(name="Wall")
        group.add([0, 1, 2], 1.0, 'REPLACE')
        from moldtex.data import mesh_export
        bare = bpy.data.meshes.new("Bare")
        bare.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
        with self.assertRaises(mesh_export.MeshExportError) as caught:
            mesh_export._vertex_group_weights(obj, bare, group, "Obstacle")
        self.assertIn("drop the vertex group 'Wall'", str(caught.exception))
        bpy.data.meshes.remove(bare)
        # Spawn Map without a spawn source.
        obj.moldtex.obstacle_attribute = ""
        obj.moldtex.seed_shape = 'SPAWN_MAP'
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.reset()
        self.assertIn("no Spawn vertex group or attribute is set", str(caught.exception))
        everywhere = obj.vertex_groups.new(name="Everywhere")
        everywhere.add(list(range(len(mesh.vertices))), 1.0, 'REPLACE')
        obj.moldtex.spawn_attribute = "Wall"
        obj.moldtex.obstacle_attribute = "Everywhere"  # spawn only inside the walls
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.reset()
        self.assertIn("is 0 everywhere outside the obstacles", str(caught.exception))
        # On a running simulation a bad name (set in the panel) becomes the panel's
        # notice, not an exception out of the property update.
        obj.moldtex.seed_shape = 'RANDOM'
        obj.moldtex.spawn_attribute = ""
        obj.moldtex.obstacle_attribute = ""
        entry = h.run(obj, 1)
        obj.moldtex.obstacle_attribute = "Nope"
        self.assertIn("'Nope' is neither", entry.notice)
        entry.notice = ""
        obj.moldtex.obstacle_attribute = "Wall"  # a good name is applied at once
        self.assertEqual(entry.notice, "")
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})

    def test_image_stays_the_default_and_the_panel_shows_the_names(self):
        from test_ui import draw_all
        obj = _plane()
        self.assertEqual(obj.moldtex.fields_source, 'IMAGE')
        shown = [entry for entry in draw_all(self, obj)]
        self.assertIn(("prop", "fields_image"), shown)
        self.assertNotIn(("prop_search", "spawn_attribute"), shown)
        obj.moldtex.fields_source = 'ATTRIBUTES'
        shown = draw_all(self, obj)
        for name in ("spawn_attribute", "obstacle_attribute", "attractor_attribute"):
            self.assertIn(("prop_search", name), shown)
        self.assertNotIn(("prop", "fields_image"), shown)
        self.assertIn(("prop", "fields_source"), shown)


if __name__ == "__main__":
    unittest.main()
