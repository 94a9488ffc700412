"""The demo scenes of tools/demo_scenes.py (issue 12), built small: the map tools, the
Maps panel and the bias from an attribute together give the looks they promise, and
each scene survives a save and reload.

Anisotropy is measured on the texture with central differences: the mean |d/du| over
the mean |d/dv| (the limb's UVs put its length along v), or on the disc the mean
tangential over the mean radial slope. Each is compared with the same scene without
the bias (same seed), whose trails have no preferred direction."""

import importlib.util
import math
import os
import shutil
import tempfile
import unittest

import bpy

import helpers as h

SIZE = "128"
AGENTS = 6000
SECONDS = 3.0


def demo_module():
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "demo_scenes.py")
    spec = importlib.util.spec_from_file_location("demo_scenes", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def grown(build, bias):
    demos = demo_module()
    obj = build(SIZE, AGENTS, bias=bias)
    return obj, demos.grow(obj, SECONDS).sim.read_rgba()


def red(pixels, size, x, y):
    return pixels[4 * (y * size + x)]


class DemoSceneTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_demo_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_stripes_run_along_the_limb(self):
        demos = demo_module()
        size = int(SIZE)

        def anisotropy(pixels):
            across = along = 0.0
            for y in range(1, size - 1):
                for x in range(1, size - 1):
                    across += abs(red(pixels, size, x + 1, y) - red(pixels, size, x - 1, y))
                    along += abs(red(pixels, size, x, y + 1) - red(pixels, size, x, y - 1))
            return across / along

        obj, biased = grown(demos.stripes_along_a_limb, True)
        bias = obj.data.attributes.get("moldtex_bias")
        self.assertIsNotNone(bias)
        self.assertEqual(bias.domain, 'FACE')
        self.saved_and_reloaded(obj)
        free = grown(demos.stripes_along_a_limb, False)[1]
        a_biased, a_free = anisotropy(biased), anisotropy(free)
        print(f"  limb: |d/du| / |d/dv| = {a_biased:.2f} with the bias, {a_free:.2f} without")
        # Trails along the limb (v) change little along v and much across it. Measured
        # 2.45 with the bias against 1.08 without (the free run has no preferred
        # direction); required: 1.5 times the free ratio.
        self.assertGreater(a_biased, 1.5 * a_free, (a_biased, a_free))

    def test_veins_run_toward_the_sink(self):
        demos = demo_module()
        size = int(SIZE)

        def slopes(pixels):
            """(mean tangential / mean radial slope over 0.3 < r < 0.8, mean u / U at
            the sink, mean u / U on the rim band)"""
            tangential = radial = 0.0
            sink = rim = 0.0
            n_sink = n_rim = 0
            for y in range(1, size - 1):
                for x in range(1, size - 1):
                    px, py = 2.0 * (x + 0.5) / size - 1.0, 2.0 * (y + 0.5) / size - 1.0
                    r = math.hypot(px, py)
                    if r < 0.04:
                        sink += red(pixels, size, x, y)
                        n_sink += 1
                    if 0.65 < r < 0.9:
                        rim += red(pixels, size, x, y)
                        n_rim += 1
                    if not 0.3 < r < 0.8:
                        continue
                    gx = red(pixels, size, x + 1, y) - red(pixels, size, x - 1, y)
                    gy = red(pixels, size, x, y + 1) - red(pixels, size, x, y - 1)
                    radial += abs(gx * px + gy * py) / r
                    tangential += abs(-gx * py + gy * px) / r
            return tangential / radial, sink / n_sink, rim / n_rim

        obj, biased = grown(demos.veins_toward_a_sink, True)
        self.saved_and_reloaded(obj)
        free = grown(demos.veins_toward_a_sink, False)[1]
        (t_biased, sink, rim), (t_free, _, _) = slopes(biased), slopes(free)
        print(f"  disc: tangential / radial slope {t_biased:.2f} with the bias, {t_free:.2f} "
              f"without; u / U at the sink {sink:.3f}, on the rim {rim:.3f}")
        # Veins run radially: the pattern changes around the centre, not along the radius
        # (measured 3.6 against 0.55 without the bias, whose agents stay on the rim band
        # in rings); the sink stays nearly empty (agents die on reaching it: 0.05 U)
        # while the rim band, where they are born, carries trails (1.6 U).
        self.assertGreater(t_biased, 1.5 * t_free, (t_biased, t_free))
        self.assertLess(sink, 0.5 * rim, (sink, rim))

    def saved_and_reloaded(self, obj):
        name = obj.name
        maps = {key: (slot.enabled, slot.attribute)
                for key, slot in ((k, getattr(obj.moldtex.maps, k))
                                  for k in ("mean_lifetime", "spawn"))}
        cont = obj.moldtex.continuous
        kept = (cont.bias_source, cont.bias_attribute, cont.bias_strength, cont.bias_symmetry)
        path = os.path.join(self.folder, name + ".blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        obj = bpy.data.objects[name]
        cont = obj.moldtex.continuous
        self.assertEqual((cont.bias_source, cont.bias_attribute, cont.bias_strength,
                          cont.bias_symmetry), kept)
        for key, value in maps.items():
            slot = getattr(obj.moldtex.maps, key)
            self.assertEqual((slot.enabled, slot.attribute), value)
        self.assertIsNotNone(obj.data.attributes.get("moldtex_bias"))


if __name__ == "__main__":
    unittest.main()
