"""Changing a parameter while a simulation is live reaches the core at once."""

import unittest

import bpy

import helpers as h


class LiveParameterTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_property_change_pushes_params(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=5000)
        h.run(obj, 10)
        sim = h.live().get(obj.name).sim
        changes = {"movement_speed": 1.5, "turn_speed": 37.5, "vision_distance": 0.7,
                   "vision_angle": 42.0, "evaporation_rate": 0.8, "diffusion_rate": 33.0,
                   "deposit": 0.9, "substeps": 3, "thread_count": 1, "sensor_size": 2}
        for key, value in changes.items():
            setattr(obj.moldtex, key, value)
            # No step in between: the update callback alone must have sent it.
            # float32 storage in the core: compare to 1e-5 relative.
            self.assertAlmostEqual(sim.get_params()[key], value, delta=1e-5 * value,
                                   msg=key)
        self.assertEqual(bpy.ops.moldtex.step(steps=5), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertIs(entry.sim, sim)  # parameters never need a rebuild
        self.assertEqual(entry.stats["step_count"], 15)

    def test_config_change_waits_for_reset(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=5000)
        h.run(obj, 2)
        live = h.live()
        obj.moldtex.resolution = "512"
        obj.moldtex.agent_count = 6000
        self.assertTrue(live.needs_reset(obj))
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        self.assertEqual(live.get(obj.name).sim.get_config()["width"], 256)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        config = live.get(obj.name).sim.get_config()
        self.assertEqual((config["width"], config["height"], config["agent_count"]),
                         (512, 512, 6000))
        self.assertFalse(live.needs_reset(obj))
        self.assertEqual(tuple(obj.moldtex.image.size), (512, 512))


if __name__ == "__main__":
    unittest.main()


class UvMapChoiceTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_second_uv_map_is_used_after_reset(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        h.run(obj, 1)
        first_inside = sum(1 for c in h.texel_classes(obj) if c == 1)
        second = obj.data.uv_layers.new(name="Half")
        source = obj.data.uv_layers["UVMap"].data
        for index, loop in enumerate(second.data):
            u, v = source[index].uv
            loop.uv = (0.5 * u, 0.5 * v)  # the same layout in a quarter of the image
        obj.moldtex.uv_map = "Half"
        self.assertTrue(h.live().needs_reset(obj))
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertEqual(entry.uv_map, "Half")
        half_inside = sum(1 for c in h.texel_classes(obj) if c == 1)
        # A quarter of the UV area: about a quarter of the inside texels (the island
        # border pixels make it a little more than 0.25).
        self.assertAlmostEqual(half_inside / first_inside, 0.25, delta=0.05)
        node = obj.active_material.node_tree.nodes["Moldtex UV"]
        self.assertEqual(node.uv_map, "Half")
