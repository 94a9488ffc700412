"""Intrinsic Delaunay triangulation (issue 11) through the binding (engine/): Suzanne and a UV
sphere, refined and not; counts near area / bound^2; vertex points map to intrinsic
vertices and back to the same 3D positions; an absurd bound is a clear EngineError."""

import math
import unittest

import bpy

import helpers as h


def surface_of(obj):
    from moldtex.data import mesh_export
    arrays = mesh_export.export_object(obj, bpy.context.evaluated_depsgraph_get())
    engine = h.engine()
    return engine.Surface(arrays.positions, arrays.triangles, arrays.uvs, arrays.triangle_uvs)


class IntrinsicTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.engine = h.engine()

    def tearDown(self):
        h.clear_scene()

    def check(self, kind):
        obj = h.add_primitive(kind)
        surface = surface_of(obj)
        area = surface.info()["area"]
        # Flips only: the input vertices, no insertions.
        flat = self.engine.Intrinsic(surface, 0.0)
        info = flat.info()
        self.assertEqual(info["vertex_count"], info["input_vertex_count"])
        self.assertEqual(info["insertions"] + info["boundary_splits"], 0)
        self.assertEqual(info["stop_reason"], self.engine.INTRINSIC_STOP_CONVERGED)
        self.assertIn("edge flips", info["message"])
        flat.release()
        # Refined to about 3000 vertices.
        bound = math.sqrt(area / 3000.0)
        intrinsic = self.engine.Intrinsic(surface, bound)
        info = intrinsic.info()
        self.assertEqual(info["stop_reason"], self.engine.INTRINSIC_STOP_CONVERGED,
                         info["message"])
        expected = area / bound ** 2
        self.assertGreater(info["vertex_count"], 0.3 * expected, info)
        self.assertLess(info["vertex_count"], 2.0 * expected, info)
        self.assertEqual(info["vertex_count"], info["input_vertex_count"] + info["insertions"]
                         + info["boundary_splits"])
        self.assertAlmostEqual(info["area"], area, delta=1e-3 * area)
        # Round trip: each vertex's input point -> intrinsic point (a corner) -> input.
        points = intrinsic.vertex_points()
        self.assertEqual(len(points), info["vertex_count"])
        used = [p for p in points if p[0] != self.engine.INTRINSIC_NO_TRIANGLE]
        located = intrinsic.locate(used)
        for triangle, bary in located:
            self.assertLess(triangle, info["triangle_count"])
            self.assertAlmostEqual(sum(bary), 1.0, delta=1e-5)
            self.assertGreater(max(bary), 1 - 1e-3)
        back = intrinsic.to_input(located)
        size = math.sqrt(area)
        worst = 0.0
        for a, b in zip(used, back):
            pa, _ = surface.evaluate(*a)
            pb, _ = surface.evaluate(*b)
            worst = max(worst, math.dist(pa, pb))
        self.assertLess(worst, 1e-4 * size)
        print(f"    {kind}: {info['input_vertex_count']} -> {info['vertex_count']} vertices "
              f"(area/bound^2 {expected:.0f}), {info['build_seconds']:.3f} s, round trip "
              f"{worst:.2g}")
        intrinsic.release()
        surface.release()

    def test_suzanne(self):
        self.check("monkey")

    def test_uv_sphere(self):
        self.check("sphere")

    def test_bad_bounds(self):
        surface = surface_of(h.add_primitive("sphere"))
        with self.assertRaises(self.engine.EngineError) as caught:
            self.engine.Intrinsic(surface, 1e-5)
        self.assertEqual(caught.exception.status, self.engine.ERROR_TOO_LARGE)
        self.assertIn("max_insertions", str(caught.exception))
        self.assertIn("use a bound of at least", str(caught.exception))
        for bad in (-1.0, float("nan")):
            with self.assertRaises(self.engine.EngineError) as caught:
                self.engine.Intrinsic(surface, bad)
            self.assertEqual(caught.exception.status, self.engine.ERROR_INVALID_ARGUMENT)
            self.assertIn("max_circumradius", str(caught.exception))
        intrinsic = self.engine.Intrinsic(surface, 0.0)
        with self.assertRaises(self.engine.EngineError):
            intrinsic.locate([(10 ** 6, (1.0, 0.0, 0.0))])
        intrinsic.release()
        with self.assertRaises(self.engine.EngineError):
            intrinsic.info()


if __name__ == "__main__":
    unittest.main()
