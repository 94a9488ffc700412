"""Colour Map from Image (issue 13, layton-intrinsic-slime.md §3.4): the operator turns a
generated exemplar image into the Moldtex Ramp of the real Moldtex material (at most 32
stops, colours along the image's colour curve, darker end first), warns when two
unrelated colour groups cannot be explained by one variable, refuses missing images
clearly, and a Cycles render of a plane whose pheromone is a gradient shows the ramp's
colours."""

import math
import os
import random
import shutil
import tempfile
import unittest

import bpy

import helpers as h


def colour_map():
    from moldtex.colour import colour_map as module
    return module


def curve(u):
    """Linear RGB along black -> red -> yellow -> white, u in [0, 1]."""
    s = min(max(u, 0.0), 1.0) * 3.0
    return (min(s, 1.0), min(max(s - 1.0, 0.0), 1.0), min(max(s - 2.0, 0.0), 1.0))


def float_image(name, size, colour_of):
    """A float (linear) RGBA image whose pixel (x, y) is colour_of(x, y)."""
    image = bpy.data.images.new(name, size, size, alpha=True, float_buffer=True)
    pixels = [0.0] * (4 * size * size)
    for y in range(size):
        for x in range(size):
            r, g, b = colour_of(x, y)
            pixels[4 * (y * size + x):4 * (y * size + x) + 4] = (r, g, b, 1.0)
    image.pixels.foreach_set(pixels)
    return image


def curve_image(size=64):
    rng = random.Random(3)
    return float_image("Exemplar Curve", size, lambda x, y: tuple(
        min(1.0, max(0.0, c + rng.uniform(-0.01, 0.01)))
        for c in curve((x + 0.5) / size)))


def two_cluster_image(size=64):
    rng = random.Random(5)
    blue, green = (0.05, 0.10, 0.60), (0.10, 0.50, 0.05)
    return float_image("Exemplar Clusters", size, lambda x, y: tuple(
        max(0.0, c + rng.uniform(-0.05, 0.05)) for c in (blue if x < size // 2 else green)))


def distance_to_curve(colour):
    return min(math.dist(colour[:3], curve(j / 600.0)) for j in range(601))


def nearest_u(colour):
    return min(range(601), key=lambda j: math.dist(colour[:3], curve(j / 600.0))) / 600.0


class ColourMapTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.obj = h.plane(resolution="128")
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        self.ramp = self.obj.active_material.node_tree.nodes["Moldtex Ramp"]
        self.folder = tempfile.mkdtemp(prefix="moldtex_colour_map_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_colour_map_writes_the_curve_into_the_moldtex_ramp(self):
        image = curve_image()
        result = bpy.ops.moldtex.colour_map_from_image(image=image.name)
        self.assertEqual(result, {'FINISHED'})
        level, message = colour_map().last_report
        self.assertEqual(level, 'INFO', message)
        elements = self.ramp.color_ramp.elements
        self.assertGreaterEqual(len(elements), 3)
        self.assertLessEqual(len(elements), 32)
        self.assertEqual(self.ramp.color_ramp.interpolation, 'LINEAR')
        positions = [e.position for e in elements]
        self.assertEqual(positions, sorted(positions))
        self.assertAlmostEqual(positions[0], 0.0, places=5)
        self.assertAlmostEqual(positions[-1], 1.0, places=5)
        # Every stop lies on the image's colour curve, in order from black to white.
        for element in elements:
            self.assertLess(distance_to_curve(tuple(element.color)), 0.08,
                            f"stop at {element.position:.3f}: {tuple(element.color)}")
        us = [nearest_u(tuple(e.color)) for e in elements]
        for a, b in zip(us, us[1:]):
            self.assertGreaterEqual(b, a - 0.02, f"stops out of order along the curve: {us}")
        self.assertLess(us[0], 0.08)
        self.assertGreater(us[-1], 0.92)
        # Reverse: white first. Undo-able like any edit (bl_options has UNDO).
        self.assertEqual(bpy.ops.moldtex.colour_map_from_image(image=image.name, reverse=True),
                         {'FINISHED'})
        self.assertGreater(nearest_u(tuple(self.ramp.color_ramp.elements[0].color)), 0.92)
        self.assertIn('UNDO', bpy.types.MOLDTEX_OT_colour_map_from_image.bl_options)
        # Peak At: the most saturated stop (red .. yellow) moves to the chosen position.
        self.assertEqual(bpy.ops.moldtex.colour_map_from_image(
            image=image.name, use_peak=True, peak_position=0.8), {'FINISHED'})
        ramp = self.ramp.color_ramp

        def saturation(colour):
            return max(colour[:3]) - min(colour[:3])
        best = max((ramp.evaluate(j / 100.0) for j in range(101)), key=saturation)
        where = [j / 100.0 for j in range(101) if tuple(ramp.evaluate(j / 100.0)) == tuple(best)]
        self.assertLess(abs(where[0] - 0.8), 0.25, where)

    def test_colour_map_two_clusters_gives_a_warning_and_a_ramp(self):
        image = two_cluster_image()
        self.assertEqual(bpy.ops.moldtex.colour_map_from_image(image=image.name), {'FINISHED'})
        level, message = colour_map().last_report
        self.assertEqual(level, 'WARNING')
        self.assertIn("does not explain", message)
        self.assertIn("separate groups", message)
        elements = self.ramp.color_ramp.elements
        self.assertGreaterEqual(len(elements), 2)
        self.assertLessEqual(len(elements), 32)

    def test_colour_map_before_set_up_material_is_kept_for_it(self):
        h.clear_scene()
        obj = h.plane(resolution="128")
        self.assertIsNone(obj.active_material)
        self.assertEqual(bpy.ops.moldtex.colour_map_from_image(image=curve_image().name),
                         {'FINISHED'})
        self.assertIn("Set Up Material will use them", colour_map().last_report[1])
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        elements = obj.active_material.node_tree.nodes["Moldtex Ramp"].color_ramp.elements
        self.assertGreaterEqual(len(elements), 3)
        self.assertLess(distance_to_curve(tuple(elements[len(elements) // 2].color)), 0.08)

    def test_colour_map_refuses_missing_or_empty_images(self):
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.colour_map_from_image(image="No Such Image")
        self.assertIn("no image named", str(caught.exception))
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.colour_map_from_image(image="")
        self.assertIn("Pick an image", str(caught.exception))
        missing = bpy.data.images.new("Missing File", 4, 4)
        missing.source = 'FILE'
        missing.filepath = os.path.join(self.folder, "missing.png")
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.colour_map_from_image(image=missing.name)
        self.assertIn("no pixels", str(caught.exception))

    def test_colour_map_render_shows_the_ramp(self):
        self.assertEqual(bpy.ops.moldtex.colour_map_from_image(image=curve_image().name),
                         {'FINISHED'})
        # The pheromone image: a gradient along x, value (column + 0.5) / width.
        pheromone = self.obj.moldtex.image
        width, height = pheromone.size
        values = [(x + 0.5) / width for x in range(width)]
        pixels = [0.0] * (4 * width * height)
        for y in range(height):
            for x in range(width):
                pixels[4 * (y * width + x):4 * (y * width + x) + 4] = (values[x],) * 3 + (1.0,)
        pheromone.pixels.foreach_set(pixels)
        pheromone.update()
        rendered, size = self.render()
        ramp = self.ramp.color_ramp
        worst = 0.0
        for column in range(2, size - 2, 3):
            # Render pixel `column` sees texel floor((column + 0.5) / size * width).
            texel = int((column + 0.5) / size * width)
            expected = ramp.evaluate(values[texel])
            index = 4 * ((size // 2) * size + column)
            got = rendered[index:index + 3]
            worst = max(worst, max(abs(a - b) for a, b in zip(got, expected[:3])))
        self.assertLess(worst, 0.01, "the render does not show the ramp's colours")
        # And the picture spans the ramp: dark on the left, light on the right.
        left, right = rendered[4 * (size // 2) * size], rendered[4 * ((size // 2) * size + size - 1)]
        self.assertLess(left, 0.05)
        self.assertGreater(right, 0.8)

    def render(self):
        """Cycles, 32 x 32, 1 sample, CPU: the ramp's colour through an Emission shader
        seen by an orthographic camera filling the frame with the 2 x 2 plane."""
        scene = bpy.context.scene
        tree = self.obj.active_material.node_tree
        tree.nodes["Moldtex Texture"].interpolation = 'Closest'
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 1.0
        output = next(n for n in tree.nodes if n.type == 'OUTPUT_MATERIAL')
        tree.links.new(self.ramp.outputs["Color"], emission.inputs["Color"])
        tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
        camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
        scene.collection.objects.link(camera)
        camera.data.type = 'ORTHO'
        camera.data.ortho_scale = 2.0
        camera.location = (0.0, 0.0, 3.0)
        scene.camera = camera
        render = scene.render
        render.engine = 'CYCLES'
        render.resolution_x = render.resolution_y = 32
        render.resolution_percentage = 100
        render.image_settings.file_format = 'OPEN_EXR'  # scene linear, no view transform
        render.image_settings.color_depth = '32'
        render.film_transparent = False
        scene.cycles.samples = 1
        scene.cycles.use_denoising = False
        scene.cycles.pixel_filter_type = 'BOX'
        scene.cycles.filter_width = 0.01
        scene.cycles.device = 'CPU'
        path = os.path.join(self.folder, "render.exr")
        render.filepath = path
        bpy.ops.render.render(write_still=True)
        pixels, (width, _) = h.load_pixels(path)
        return pixels, width


if __name__ == "__main__":
    unittest.main()
