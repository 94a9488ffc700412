"""The texture domain true to the surface (issue 9) on Blender's own Suzanne, whose UV
layout has many islands: texels along island borders (seams, and the rims of its eyes
and ears) and texels holding a vertex that a seam splits (one 3D point, two or more UV
points) must hold about what the other texels hold. Before surface units the issue
measured 0.18-0.60 of the mean in those classes; its bound is 0.8."""

import unittest

import bpy

import helpers as h


def split_vertex_texels(obj, width, height):
    """Texels that hold the UV point of a vertex with more than one UV (split by a seam),
    from the evaluated mesh and its render UV map."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        layer = next((uv for uv in mesh.uv_layers if uv.active_render), mesh.uv_layers.active)
        points = {}
        for loop in mesh.loops:
            u, v = layer.data[loop.index].uv
            points.setdefault(loop.vertex_index, set()).add((round(u, 5), round(v, 5)))
    finally:
        evaluated.to_mesh_clear()
    texels = set()
    for uvs in points.values():
        if len(uvs) < 2:
            continue
        for u, v in uvs:
            x = min(width - 1, max(0, int(u * width)))
            y = min(height - 1, max(0, int(v * height)))
            texels.add(y * width + x)
    return texels


class SuzanneTexelClassTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def tearDown(self):
        h.clear_scene()

    def test_seam_and_split_vertex_texels_hold_the_mean(self):
        obj = h.add_primitive("monkey")
        obj.modifiers.new("Subdivision", 'SUBSURF').levels = 1
        width = 256
        sums = {"surface": [0.0, 0.0, 0.0], "texels": [0.0, 0.0, 0.0]}
        # The add-on's default units on 12 seeds, texel units (printed for contrast) on 3.
        for units, seeds in (('SURFACE', range(1, 13)), ('TEXELS', (1, 2, 3))):
            for seed in seeds:
                h.configure(obj, resolution=str(width), agents=20000, seed=seed)
                obj.moldtex.pattern_units = units
                entry = h.run(obj, 200)
                classes = entry.sim.read_texel_classes()
                border = {i for i, near in h.near_island_border(classes, width, 1).items() if near}
                split = {i for i in split_vertex_texels(obj, width, width) if classes[i] == 1}
                rest = [i for i, c in enumerate(classes) if c == 1 and i not in border]
                self.assertGreater(len(split), 50, "Suzanne's seams split many vertices")
                for _ in range(5):  # 5 snapshots 20 steps apart
                    self.assertEqual(bpy.ops.moldtex.step(steps=20), {'FINISHED'})
                    pixels = h.image_pixels(obj)
                    mean = sum(pixels[4 * i] for i in rest) / len(rest)
                    row = sums[units.lower()]
                    row[0] += sum(pixels[4 * i] for i in border) / len(border) / mean
                    row[1] += sum(pixels[4 * i] for i in split) / len(split) / mean
                    row[2] += 1
        for units, (border_sum, split_sum, count) in sums.items():
            print(f"    Suzanne, {units} units: island-border texels {border_sum / count:.3f}, "
                  f"split-vertex texels {split_sum / count:.3f} of the other texels' mean")
        # The bound, 0.8, on the add-on's default units, pooled over 12 seeds x 5
        # snapshots. Only 96 texels sit at split vertices, so one seed's 5 snapshots read
        # 0.80-1.43 for them (border texels 0.84-1.17), seeds 1-12 on Blender 3.4
        # (2026-12-05): standard deviations 0.19 and 0.10 per seed. Pooled over 3 seeds,
        # as until then, the split-vertex mean read 1.18 on Blender 3.4 and 0.78 on bpy
        # 4.2 in one CI run: a test that held by luck. Over 12 seeds (standard errors
        # ~0.03 and ~0.055): border 0.94 and split-vertex 1.02 on Blender 3.4, 0.900 and
        # 0.875 on both bpy 4.2 and 5.0 (not checked whether their subdivided Suzanne
        # differs: the split-vertex means are 1.9 standard errors apart). So 0.8 lies 4-5
        # standard errors below on 3.4, but under 2 below the split-vertex texels on 4.2
        # and 5.0 (open in issue #9).
        border_sum, split_sum, count = sums["surface"]
        self.assertGreater(border_sum / count, 0.8)
        self.assertGreater(split_sum / count, 0.8)



class DetailTests(unittest.TestCase):
    """Detail (moldtex_sim_config.detail): at the add-on's defaults a UV sphere's texture
    has about one texel per pattern unit, where its poles come out about 30% thin
    (README, "Units: Surface"); Detail Auto simulates it at twice the resolution and
    writes the texture at its own. The core's tests check that the image is then the
    finer simulation seen smaller; here, that the add-on picks the detail the settings
    ask for, shows it, and keeps the texture at its Resolution."""

    def setUp(self):
        h.clear_scene()

    def tearDown(self):
        h.clear_scene()

    def test_auto_detail_follows_the_texels_per_unit(self):
        from moldtex.sim import session as live
        bpy.ops.mesh.primitive_uv_sphere_add()
        obj = bpy.context.active_object
        obj.moldtex.agent_count = 20000  # otherwise the add-on's defaults
        self.assertEqual(obj.moldtex.detail, 'AUTO')
        self.assertEqual(obj.moldtex.resolution, '512')
        entry = h.run(obj, 3)
        # Its UVs fill the texture but for the poles' teeth: about 0.97 texels per unit,
        # so Auto takes 2 (1.9 or more), and the core runs at 1024².
        per_unit = h.convert().texels_per_unit(entry, obj.moldtex)
        self.assertAlmostEqual(per_unit, 0.97, delta=0.03)
        self.assertEqual(entry.sim.get_config()["detail"], 2)
        self.assertEqual(tuple(obj.moldtex.image.size), (512, 512))
        self.assertEqual(len(entry.sim.read_texel_classes()), 512 * 512)
        pixels = h.image_pixels(obj)
        self.assertGreater(max(pixels[0::4]), 0.0, "the pattern reaches the image")
        from test_ui import draw_all, labels
        self.assertIn("Simulated 1024 × 1024 (2×)", labels(draw_all(self, obj)))
        # Twice the pattern scale: two texels per unit already, so no detail.
        obj.moldtex.pattern_scale = 2.0
        self.assertTrue(live.needs_reset(obj))
        entry = h.run(obj, 1)
        self.assertEqual(entry.sim.get_config()["detail"], 1)
        self.assertNotIn("Simulated", labels(draw_all(self, obj)))
        # Texel units are MoMaS' own texels: never a detail, whatever the setting.
        obj.moldtex.pattern_scale = 1.0
        obj.moldtex.detail = '4'
        obj.moldtex.pattern_units = 'TEXELS'
        entry = h.run(obj, 1)
        self.assertEqual(entry.sim.get_config()["detail"], 1)
        # An explicit detail in surface units is taken as it is.
        obj.moldtex.pattern_units = 'SURFACE'
        obj.moldtex.resolution = '128'
        self.assertTrue(live.needs_reset(obj))
        entry = h.run(obj, 1)
        self.assertEqual(entry.sim.get_config()["detail"], 4)
        self.assertEqual(tuple(obj.moldtex.image.size), (128, 128))
        # Auto takes 4× where that simulates at most 1024² (here 512²: 0.97 texels per
        # unit, as close to two as it gets), and at most 2× above (its cost: PERFORMANCE).
        obj.moldtex.detail = 'AUTO'
        entry = h.run(obj, 1)
        self.assertAlmostEqual(h.convert().texels_per_unit(entry, obj.moldtex), 0.24, delta=0.01)
        self.assertEqual(entry.sim.get_config()["detail"], 4)
        obj.moldtex.resolution = '512'
        obj.moldtex.pattern_scale = 0.5
        entry = h.run(obj, 1)
        self.assertAlmostEqual(h.convert().texels_per_unit(entry, obj.moldtex), 0.48, delta=0.02)
        self.assertEqual(entry.sim.get_config()["detail"], 2)


if __name__ == "__main__":
    unittest.main()
