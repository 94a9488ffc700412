"""Bad inputs an artist or an old file can produce: each gives a clear message (or is
handled), never a Python traceback, and the message says the real reason."""

import os
import shutil
import tempfile
import unittest

import bpy

import helpers as h
from test_ui import draw_all, labels


def call(operator, **kwargs):
    """(result, message): the operator's result, or the message it reported as an
    error (Blender raises RuntimeError for those when called from Python)."""
    try:
        return operator(**kwargs), ""
    except RuntimeError as error:
        return {'CANCELLED'}, str(error)


class TransformTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.obj = h.add_primitive("torus")
        h.configure(self.obj, agents=2000)
        self.folder = tempfile.mkdtemp(prefix="moldtex_bad_inputs_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)
        bpy.context.scene.cursor.location = (0.0, 0.0, 0.0)

    def assert_clear(self, message, *fragments):
        self.assertNotIn("Traceback", message)
        self.assertNotIn("ValueError", message)
        self.assertNotIn("Matrix", message)
        for fragment in fragments:
            self.assertIn(fragment, message)

    def everything_refuses(self, *fragments):
        """Reset with each seed shape, Reset with food, a brush stroke, a bake and the
        panel: a clear message each time."""
        obj = self.obj
        for shape in ('RANDOM', 'CIRCLE', 'BIG_BANG', 'STARBURST'):
            obj.moldtex.seed_shape = shape
            result, message = call(bpy.ops.moldtex.reset)
            self.assertEqual(result, {'CANCELLED'}, shape)
            self.assert_clear(message, *fragments)
        obj.moldtex.seed_shape = 'RANDOM'
        food = bpy.data.collections.new("Food")
        bpy.context.scene.collection.children.link(food)
        empty = bpy.data.objects.new("Crumb", None)
        food.objects.link(empty)
        obj.moldtex.food_collection = food
        h.activate(obj)
        result, message = call(bpy.ops.moldtex.reset)
        self.assert_clear(message, *fragments)
        result, message = call(bpy.ops.moldtex.brush_stroke, stroke=[
            {"name": "", "location": (0.0, 0.0, 3.0), "direction": (0.0, 0.0, -1.0)}])
        self.assertEqual(result, {'CANCELLED'})
        self.assert_clear(message, *fragments)
        h.bake_settings(obj, self.folder, 1, 2, 1)
        result, message = call(bpy.ops.moldtex.bake)
        self.assertEqual(result, {'CANCELLED'})
        self.assert_clear(message, *fragments)
        text = labels(draw_all(self, obj))  # the panel draws and says it
        for fragment in fragments:
            self.assertIn(fragment.split(" ")[0], text)

    def test_zero_scale_axis(self):
        self.obj.scale = (1.0, 0.0, 1.0)
        bpy.context.view_layer.update()
        self.everything_refuses("scale of 0 on Y", "non-zero scale")

    def test_nearly_zero_scale_axis(self):
        self.obj.scale = (1e-18, 1.0, 1.0)
        bpy.context.view_layer.update()
        self.everything_refuses("scale of 1e-18 on X", "between 1e-06 and 1e+06")

    def test_huge_non_uniform_scale(self):
        self.obj.scale = (1e30, 1.0, 1.0)
        bpy.context.view_layer.update()
        self.everything_refuses("scale of 1e+30 on X")

    def test_zero_scale_on_the_first_axis(self):
        self.obj.scale = (0.0, 1.0, 1.0)  # was silently taken as uniform
        bpy.context.view_layer.update()
        self.everything_refuses("scale of 0 on X")

    def test_uniform_small_scale_still_works(self):
        self.obj.scale = (0.01, 0.01, 0.01)  # e.g. an import in centimetres
        bpy.context.view_layer.update()
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})

    def test_mesh_far_too_small_says_so(self):
        # Mesh data scaled to 1e-30 (the object's scale is 1): the core would only say
        # "nowhere to spawn agents: paint a spawn region", with no fields set.
        self.obj.data.transform(__import__("mathutils").Matrix.Scale(1e-30, 4))
        result, message = call(bpy.ops.moldtex.reset)
        self.assertEqual(result, {'CANCELLED'})
        self.assertIn("too small", message)
        self.assertNotIn("spawn", message)


class EnumTests(unittest.TestCase):
    """Enum settings holding a number none of their items has (a file from another
    version, or a script writing the raw value) are treated as the default, with a
    warning, instead of raising in the panel, Reset and Bake."""

    def setUp(self):
        h.clear_scene()
        self.obj = h.add_primitive("torus")
        h.configure(self.obj, agents=2000, resolution="128")
        self.folder = tempfile.mkdtemp(prefix="moldtex_bad_enum_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_unknown_resolution(self):
        obj = self.obj
        obj.moldtex["resolution"] = 99
        text = labels(draw_all(self, obj))  # no exception
        self.assertIn("Resolution held a value", text)
        self.assertIn("512 × 512 is used", text)
        result, message = call(bpy.ops.moldtex.reset)
        self.assertEqual(result, {'FINISHED'}, message)
        self.assertEqual(obj.moldtex.resolution, "512")  # repaired to the default
        self.assertEqual(h.live().get(obj.name).sim.width, 512)
        self.assertNotIn("Resolution held a value", labels(draw_all(self, obj)))

    def test_unknown_seed_shape_and_bake_format(self):
        obj = self.obj
        obj.moldtex["seed_shape"] = 42
        obj.moldtex["bake_format"] = 77
        labels(draw_all(self, obj))
        h.bake_settings(obj, self.folder, 1, 2, 1)
        obj.moldtex["bake_format"] = 77  # (bake_settings set it)
        result, message = call(bpy.ops.moldtex.bake)
        self.assertEqual(result, {'FINISHED'}, message)
        self.assertEqual(obj.moldtex.seed_shape, 'RANDOM')
        self.assertEqual(obj.moldtex.bake_format, 'EXR_HALF')
        self.assertTrue(any(name.endswith(".exr") for name in os.listdir(self.folder)))


class BrushEnumTests(unittest.TestCase):
    def tearDown(self):
        from moldtex.brush import session as brush
        brush.forget()  # leave no stroke history behind for other tests' objects
        h.clear_scene()
    def test_unknown_brush_target_paints_the_default_with_a_note(self):
        h.clear_scene()
        obj = h.subdivided_plane()
        h.configure(obj, agents=2000, resolution="128")
        scene = bpy.context.scene
        scene.moldtex_brush["target"] = 99  # e.g. a target a newer version added
        self.assertIn("Paint held a value", labels(draw_all(self, obj)))
        food = bpy.data.collections.get("Food")
        before = len(food.objects) if food is not None else 0
        self.assertEqual(bpy.ops.moldtex.brush_stroke(stroke=[
            {"name": "", "location": (0.0, 0.0, 1.0), "direction": (0.0, 0.0, -1.0)}]),
            {'FINISHED'})
        self.assertEqual(scene.moldtex_brush.target, 'OBSTACLE')  # the default
        food = bpy.data.collections.get("Food")
        self.assertEqual(len(food.objects) if food is not None else 0, before,
                         "an unknown target must not place food")
        image = obj.moldtex.fields_image
        self.assertIsNotNone(image)  # it painted an obstacle into the Fields image


class LimitTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.obj = h.add_primitive("torus")
        h.configure(self.obj, agents=2000, resolution="128")

    def test_threads_stop_at_the_cores_limit(self):
        settings = self.obj.moldtex
        self.assertEqual(settings.bl_rna.properties["thread_count"].hard_max, 256)
        settings.thread_count = 1024
        self.assertEqual(settings.thread_count, 256)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        self.assertEqual(bpy.ops.moldtex.step(), {'FINISHED'})

    def test_long_prefix_says_it_is_too_long(self):
        folder = tempfile.mkdtemp(prefix="moldtex_prefix_")
        try:
            h.bake_settings(self.obj, folder, 1, 2, 1, prefix="p" * 300)
            result, message = call(bpy.ops.moldtex.bake)
            self.assertEqual(result, {'CANCELLED'})
            self.assertIn("300 characters long", message)
            self.assertNotIn("without '/'", message)
            self.assertIn("characters long", labels(draw_all(self, self.obj)))
        finally:
            shutil.rmtree(folder, ignore_errors=True)

    def test_huge_seed_radius_says_why(self):
        settings = self.obj.moldtex
        settings.seed_shape = 'CIRCLE'
        settings.seed_radius = 1e30
        result, message = call(bpy.ops.moldtex.reset)
        self.assertEqual(result, {'CANCELLED'})
        self.assertIn("far larger than 'Torus'", message)
        self.assertNotIn("finite number", message)


if __name__ == "__main__":
    unittest.main()
