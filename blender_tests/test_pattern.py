"""A structured slime-mold pattern grows on ordinary meshes, through the operators."""

import unittest

import bpy

import helpers as h

STEPS = 300  # 5 s of the paper's 60 Hz clock: past the initial peak (momas Fig. 8a)


class PatternTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_engine_loaded(self):
        self.assertTrue(h.engine().available(), h.engine().status_text())

    def _grow(self, kind):
        obj = h.add_primitive(kind)
        h.configure(obj)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        entry = h.run(obj, STEPS)
        h.check_pattern(self, obj, entry, kind, STEPS)

        # The image the material shows is this one.
        image = obj.moldtex.image
        node = obj.active_material.node_tree.nodes.get("Moldtex Texture")
        self.assertIsNotNone(node)
        self.assertEqual(node.image, image)
        self.assertTrue(image.is_float)
        self.assertEqual(image.colorspace_settings.name, 'Non-Color')

    def test_suzanne(self):
        self._grow("monkey")

    def test_uv_sphere(self):
        self._grow("sphere")

    def test_torus(self):
        self._grow("torus")

    def test_quads_and_modifiers(self):
        """The evaluated mesh is used: a Subdivision modifier changes the triangles."""
        obj = h.add_primitive("monkey")
        h.configure(obj)
        base = h.run(obj, 1).surface_info["triangle_count"]
        obj.modifiers.new("Subdivision", 'SUBSURF').levels = 1
        # A Catmull-Clark level turns every n-gon into n quads = 2n triangles.
        entry = h.run(obj, 1)
        self.assertEqual(entry.surface_info["triangle_count"],
                         2 * sum(len(p.vertices) for p in obj.data.polygons))
        self.assertGreater(entry.surface_info["triangle_count"], base)


if __name__ == "__main__":
    unittest.main()
