"""Meshes the core refuses give a clear report, and Blender keeps running."""

import unittest

import bpy

import helpers as h

OPERATORS = ("step", "reset", "setup_material")


def call(operator_name):
    """Runs bpy.ops.moldtex.<name>; returns (result set, error text)."""
    operator = getattr(bpy.ops.moldtex, operator_name)
    try:
        return operator(), ""
    except RuntimeError as error:
        # An operator that reports an ERROR and returns CANCELLED raises this when
        # called from Python; the text is the report.
        return {'CANCELLED'}, str(error)


class BadMeshTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def tearDown(self):
        # Blender still works: a good mesh simulates after every failure.
        h.clear_scene()
        obj = h.add_primitive("sphere")
        h.configure(obj, agents=1000)
        self.assertEqual(bpy.ops.moldtex.step(steps=2), {'FINISHED'})

    def assert_refused(self, operators, *fragments):
        for name in operators:
            result, message = call(name)
            self.assertEqual(result, {'CANCELLED'}, name)
            for fragment in fragments:
                self.assertIn(fragment, message, f"{name}: {message!r}")
        self.assertEqual(h.live().names(), [])

    def test_no_uv_map(self):
        h.mesh_object("NoUV", [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)],
                      [(0, 1, 2, 3)], with_uvs=False)
        self.assert_refused(OPERATORS, "'NoUV' has no UV map", "Smart UV Project")

    def test_no_faces(self):
        h.mesh_object("Points", [(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], with_uvs=False)
        self.assert_refused(("step", "reset"), "'Points' has no faces")

    def test_non_manifold_edge(self):
        # Three triangles share the edge 0-1.
        h.mesh_object("Fin", [(0, 0, 0), (1, 0, 0), (0.5, 1, 0), (0.5, -1, 0),
                              (0.5, 0, 1)],
                      [(0, 1, 2), (1, 0, 3), (0, 1, 4)])
        for name in ("step", "reset"):
            result, message = call(name)
            self.assertEqual(result, {'CANCELLED'})
            self.assertIn("manifold", message.lower(), message)
        # The engine says why, with the status for a bad mesh.
        from moldtex.data import mesh_export
        obj = bpy.context.active_object
        arrays = mesh_export.export_object(obj, bpy.context.evaluated_depsgraph_get())
        engine = h.engine()
        with self.assertRaises(engine.EngineError) as caught:
            engine.Surface(arrays.positions, arrays.triangles, arrays.uvs,
                           arrays.triangle_uvs)
        self.assertEqual(caught.exception.status, engine.ERROR_INVALID_MESH)
        self.assertTrue(str(caught.exception))

    def test_zero_uv_area(self):
        obj = h.mesh_object("Flat", [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)],
                            [(0, 1, 2, 3)])
        for loop in obj.data.uv_layers[0].data:
            loop.uv = (0.5, 0.5)
        result, message = call("step")
        self.assertEqual(result, {'CANCELLED'})
        self.assertTrue(message)

    def test_not_a_mesh(self):
        empty = bpy.data.objects.new("Nothing", None)
        bpy.context.scene.collection.objects.link(empty)
        h.activate(empty)
        self.assert_refused(OPERATORS, "'Nothing'", "not a mesh")

    def test_no_active_object(self):
        bpy.context.view_layer.objects.active = None
        self.assert_refused(OPERATORS, "No active object")

    def test_missing_uv_map_name(self):
        obj = h.add_primitive("torus")
        obj.moldtex.uv_map = "DoesNotExist"
        self.assert_refused(("step", "reset", "setup_material"), "DoesNotExist")


if __name__ == "__main__":
    unittest.main()
