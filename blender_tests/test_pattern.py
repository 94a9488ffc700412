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
        self.assertEqual(entry.stats["step_count"], STEPS)
        self.assertEqual(entry.stats["agent_count"], h.AGENTS)
        pixels = h.image_pixels(obj)
        classes = h.texel_classes(obj)
        width = int(h.RESOLUTION)
        self.assertEqual(len(classes), width * width)
        self.assertEqual(len(pixels), 4 * width * width)

        # Coverage (momas Eq. 1): agents have laid trails (not empty) but a network
        # leaves dark cells between them (not saturated). Seen: 0.35 .. 0.50 here.
        coverage = entry.stats["coverage"]
        self.assertGreater(coverage, 0.15, f"{kind}: almost no pheromone")
        self.assertLess(coverage, 0.85, f"{kind}: pheromone everywhere, no pattern")

        m = h.pattern_metrics(pixels, classes, width)
        detail = f"{kind}: coverage {coverage:.3f}, metrics {m}"
        # Clearly non-uniform: a trail network is bright lines on a dark background.
        # Seen: std/mean 0.9 .. 1.3, dark 35 .. 55 %, bright 31 .. 48 %; a uniform
        # haze would have std/mean near 0 and neither dark nor bright texels.
        self.assertGreater(m["cv"], 0.5, detail)
        self.assertGreater(m["dark"], 0.15, detail)
        self.assertGreater(m["bright"], 0.15, detail)
        # Structured, not salt-and-pepper: trails are continuous, so neighbouring
        # texels agree (seen 0.90 .. 0.97; independent dots would give about 0).
        self.assertGreater(m["neighbour_corr"], 0.8, detail)

        # Texels outside every UV island (and its gutter) stay exactly black.
        leaks = [i for i, c in enumerate(classes)
                 if c == 0 and (pixels[4 * i] or pixels[4 * i + 1] or pixels[4 * i + 2])]
        self.assertEqual(leaks, [], f"{kind}: {len(leaks)} outside texels are not 0")
        # Sanity of the layout itself: most of these UV layouts are islands.
        self.assertGreater(m["inside"], 0.4 * width * width, detail)

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
