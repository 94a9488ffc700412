"""Material setup, object deletion, mesh edits, undo, and add-on re-enabling."""

import unittest

import addon_utils
import bpy

import helpers as h


class MaterialTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_setup_material_is_idempotent_and_keeps_user_nodes(self):
        obj = h.add_primitive("monkey")
        h.configure(obj)
        material = bpy.data.materials.new("Mine")
        material.use_nodes = True
        user_node = material.node_tree.nodes.new("ShaderNodeTexNoise")
        user_node.name = "My Noise"
        obj.data.materials.append(material)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        nodes = material.node_tree.nodes
        count = len(nodes)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        self.assertEqual(len(nodes), count)  # nothing duplicated
        self.assertIn("My Noise", nodes)
        self.assertIs(obj.active_material, material)
        principled = next(n for n in nodes if n.type == 'BSDF_PRINCIPLED')
        link = principled.inputs["Base Color"].links[0]
        self.assertEqual(link.from_node.name, "Moldtex Fields Overlay")
        # The pheromone colour enters the overlay as its base (Show Fields adds to it).
        self.assertEqual(link.from_node.inputs[2].links[0].from_node.name, "Moldtex Ramp")
        uv_node = nodes["Moldtex UV"]
        self.assertEqual(uv_node.uv_map, "UVMap")
        self.assertEqual(nodes["Moldtex Texture"].inputs["Vector"].links[0].from_node,
                         uv_node)
        image = obj.moldtex.image
        self.assertEqual(image.name, f"Moldtex {obj.name}")
        self.assertEqual(tuple(image.size), (256, 256))
        self.assertTrue(image.is_float)
        self.assertEqual(image.colorspace_settings.name, 'Non-Color')
        ramp = nodes["Moldtex Ramp"].color_ramp.elements
        self.assertLess(sum(ramp[0].color[:3]), 0.1)   # dark at 0
        self.assertGreater(ramp[-1].color[0], 0.9)      # bright yellow at 1
        self.assertGreater(ramp[-1].color[1], 0.7)
        self.assertLess(ramp[-1].color[2], 0.3)

    def test_new_material_when_none(self):
        obj = h.add_primitive("sphere")
        h.configure(obj)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        self.assertIsNotNone(obj.active_material)
        self.assertIn("Moldtex Texture", obj.active_material.node_tree.nodes)


class LifecycleTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_deleting_the_object_frees_its_simulation(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        h.run(obj, 2)
        name = obj.name
        self.assertIn(name, h.live().names())
        bpy.data.objects.remove(obj, do_unlink=True)
        bpy.context.view_layer.update()  # runs depsgraph_update_post
        self.assertNotIn(name, h.live().names())

    def test_mesh_edit_rebuilds_on_next_step(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        h.run(obj, 4)
        triangles = h.live().get(obj.name).surface_info["triangle_count"]
        obj.modifiers.new("Subdivision", 'SUBSURF').levels = 1
        bpy.context.view_layer.update()
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertEqual(entry.surface_info["triangle_count"], 4 * triangles)
        self.assertEqual(entry.stats["step_count"], 1)  # restarted on the new mesh

    def test_moving_the_object_keeps_the_simulation(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        h.run(obj, 4)
        obj.location.x += 3.0
        obj.rotation_euler.z += 1.0
        obj.scale = (2.0, 2.0, 2.0)  # uniform: lengths in texels do not change
        bpy.context.view_layer.update()
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        self.assertEqual(h.live().get(obj.name).stats["step_count"], 5)

    def test_a_long_step_runs_in_chunks_the_core_accepts(self):
        # The core refuses more than MOLDTEX_MAX_STEPS_PER_CALL steps in one call; the
        # engine splits a longer run. With the chunk made tiny, 7 steps take 3 calls and
        # all 7 are run; the core itself refuses a count over its bound.
        from moldtex import engine
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        h.run(obj, 1)
        entry = h.live().get(obj.name)
        saved = engine.structs.MAX_STEPS_PER_CALL
        engine.structs.MAX_STEPS_PER_CALL = 3
        try:
            entry.sim.step(7)
        finally:
            engine.structs.MAX_STEPS_PER_CALL = saved
        self.assertEqual(entry.sim.get_stats()["step_count"], 8)
        with self.assertRaises(engine.EngineError) as caught:
            engine._check(engine.library._lib.moldtex_sim_step(entry.sim.handle, saved + 1), "Stepping")
        self.assertIn("chunks", str(caught.exception))
        self.assertEqual(entry.sim.get_stats()["step_count"], 8)

    def test_undo_does_not_crash(self):
        obj = h.add_primitive("torus")
        name = obj.name
        h.configure(obj, agents=2000)
        h.run(obj, 3)
        bpy.ops.ed.undo_push(message="before subdivision")
        obj.modifiers.new("Subdivision", 'SUBSURF').levels = 1
        bpy.ops.ed.undo_push(message="subdivision")
        h.activate(bpy.data.objects[name])
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        bpy.ops.ed.undo()
        obj = h.activate(bpy.data.objects[name])  # a new wrapper after undo
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        entry = h.live().get(name)
        self.assertEqual(len(obj.modifiers), 0)
        self.assertEqual(entry.surface_info["triangle_count"],
                         len(obj.data.polygons) * 2)  # the torus' quads again

    def test_start_refuses_in_background(self):
        if not bpy.app.background:
            self.skipTest("interactive session")
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.start()
        self.assertIn("moldtex.step", str(caught.exception))


class RegistrationTests(unittest.TestCase):
    def test_disable_and_enable_again(self):
        h.clear_scene()
        obj = h.add_primitive("sphere")
        name = obj.name
        h.configure(obj, agents=2000, seed=4242)
        h.run(obj, 2)
        try:
            addon_utils.disable("moldtex", default_set=True)
            self.assertFalse(hasattr(bpy.types.Object, "moldtex"))
            self.assertFalse(hasattr(bpy.types, "MOLDTEX_OT_step"))
            self.assertFalse(hasattr(bpy.types, "MOLDTEX_PT_main"))
        finally:
            module = addon_utils.enable("moldtex", default_set=True)
        self.assertIsNotNone(module)
        self.assertEqual(h.live().names(), [])  # unregister freed the simulation
        obj = h.activate(bpy.data.objects[name])
        self.assertEqual(obj.moldtex.seed, 4242)  # stored data came back
        self.assertEqual(bpy.ops.moldtex.step(steps=2), {'FINISHED'})


if __name__ == "__main__":
    unittest.main()
