"""Surface brushes driven by their operators: fields (obstacle, spawn), slime (agents)
and food (Empties), their undo/redo, and a Fields image repainted while running."""

import array
import math
import os
import shutil
import tempfile
import unittest

import bpy
from mathutils import Vector

import helpers as h

RESOLUTION = 128
TEXEL = 2.0 / RESOLUTION  # the 2 × 2 plane spans the whole UV square
DOWN = (0.0, 0.0, -1.0)


def _plane():
    obj = h.subdivided_plane()
    h.configure(obj, resolution=str(RESOLUTION), agents=4000)
    return obj


def _brush(**values):
    settings = bpy.context.scene.moldtex_brush
    defaults = dict(target='OBSTACLE', erase=False, radius=0.3, strength=1.0, falloff=0.0,
                    agents_per_dab=500, species=1, food_strength=2.0, food_amount=-1.0)
    defaults.update(values)
    for name, value in defaults.items():
        setattr(settings, name, value)
    return settings


def _stroke(obj, *points, direction=DOWN):
    """One stroke with a dab above each (x, y) point, cast straight down."""
    h.activate(obj)
    return bpy.ops.moldtex.brush_stroke(stroke=[
        {"name": "", "location": (x, y, 1.0), "direction": direction} for x, y in points])


def _channel(image, channel):
    width, height = image.size
    pixels = array.array("f", bytes(16 * width * height))
    image.pixels.foreach_get(pixels)
    return pixels[channel::4], width, height


def _texel_centre(index, width, height):
    x, y = index % width, index // width
    return (-1.0 + 2.0 * (x + 0.5) / width, -1.0 + 2.0 * (y + 0.5) / height)


def _inside(positions, centre, radius):
    return sum(1 for p in positions if math.dist(p[:2], centre) <= radius)


class BrushTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        for collection in list(bpy.data.collections):
            bpy.data.collections.remove(collection)
        self.folder = tempfile.mkdtemp(prefix="moldtex_brush_")
        bpy.context.scene.cursor.location = (0.0, 0.0, 0.0)

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_obstacle_disk_is_painted_within_the_radius_and_walls_off_agents(self):
        obj = _plane()
        _brush(target='OBSTACLE', radius=0.3)
        self.assertEqual(_stroke(obj, (0.2, -0.1)), {'FINISHED'})
        image = obj.moldtex.fields_image
        self.assertIsNotNone(image, "the first stroke makes a Fields image")
        self.assertEqual(tuple(image.size), (RESOLUTION, RESOLUTION))
        green, width, height = _channel(image, 1)
        inner = outer = 0
        for index, value in enumerate(green):
            d = math.dist(_texel_centre(index, width, height), (0.2, -0.1))
            # The radius is measured on the surface (flat here: Euclidean); a texel is
            # painted when a sample of the disk falls in it, so allow one texel of rim.
            if d <= 0.3 - TEXEL:
                inner += value < 0.999
            elif d > 0.3 + TEXEL:
                outer += value != 0.0
        self.assertEqual(inner, 0, "texels well inside the disk left unpainted")
        self.assertEqual(outer, 0, "texels beyond the radius painted")
        # The obstacle reaches the simulation: after 150 steps no agent stands in it
        # (a margin of one texel for agents on the rim's partly painted texels).
        h.run(obj, 150)
        positions = h.agent_positions(obj)
        self.assertEqual(_inside(positions, (0.2, -0.1), 0.3 - TEXEL), 0)
        self.assertGreater(len(positions), 3900)

    def test_fields_image_of_another_size_is_resampled_for_the_simulation(self):
        obj = _plane()
        image = bpy.data.images.new("Small Fields", 64, 64, alpha=True, float_buffer=True)
        obj.moldtex.fields_image = image
        h.run(obj, 1)
        radius = 0.4 - 2.0 / 64  # nearest resampling may move the rim by a 64² texel
        before = _inside(h.agent_positions(obj), (0.0, 0.0), radius)
        _brush(target='OBSTACLE', radius=0.4)
        self.assertEqual(_stroke(obj, (0.0, 0.0)), {'FINISHED'})
        self.assertEqual(tuple(obj.moldtex.fields_image.size), (64, 64), "painted in place")
        self.assertEqual(bpy.ops.moldtex.step(steps=100), {'FINISHED'})
        after = _inside(h.agent_positions(obj), (0.0, 0.0), radius)
        # The 128² simulation got the 64² wall: agents caught inside may walk out, none
        # walk in, so the ~450 there at the start dwindle (seen 8 left after 100 steps);
        # without the wall about as many would be inside as before.
        self.assertGreater(before, 300)
        self.assertLess(after, 0.2 * before)

    def test_fields_stroke_undo_and_redo(self):
        obj = _plane()
        _brush(target='ATTRACTOR', radius=0.25, falloff=1.0, strength=0.8)
        self.assertEqual(_stroke(obj, (-0.4, 0.4), (-0.2, 0.4)), {'FINISHED'})
        image = obj.moldtex.fields_image
        blue, width, height = _channel(image, 2)
        painted = list(blue)
        centre = painted[int((0.4 + 1) / 2 * height) * width + int((-0.4 + 1) / 2 * width)]
        self.assertGreater(centre, 0.5)
        # Falloff 1: the rim gets much less than the centre.
        rim = [v for i, v in enumerate(painted)
               if abs(math.dist(_texel_centre(i, width, height), (-0.3, 0.4)) - 0.3) < TEXEL
               and _texel_centre(i, width, height)[1] > 0.55]
        self.assertTrue(rim and max(rim) < 0.5 * centre, f"rim {max(rim or [0])}")
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'FINISHED'})
        self.assertEqual(max(_channel(image, 2)[0]), 0.0)
        self.assertEqual(bpy.ops.moldtex.brush_redo(), {'FINISHED'})
        self.assertEqual(list(_channel(image, 2)[0]), painted)
        self.assertEqual(bpy.ops.moldtex.brush_redo(), {'CANCELLED'})  # nothing left

    def test_spawn_brush_then_spawn_map_start(self):
        obj = _plane()
        _brush(target='SPAWN', radius=0.2)
        self.assertEqual(_stroke(obj, (-0.5, -0.5)), {'FINISHED'})
        obj.moldtex.seed_shape = 'SPAWN_MAP'
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        positions = h.agent_positions(obj)
        # Every agent starts in a painted texel: within the radius plus one texel.
        self.assertEqual(_inside(positions, (-0.5, -0.5), 0.2 + 1.5 * TEXEL), len(positions))

    def test_slime_adds_agents_in_the_disk_and_undo_removes_them(self):
        obj = _plane()
        h.run(obj, 1)
        before = h.agent_positions(obj)
        _brush(target='SLIME', radius=0.2, agents_per_dab=500)
        self.assertEqual(_stroke(obj, (0.5, 0.5), (0.5, 0.3)), {'FINISHED'})
        after = h.agent_positions(obj)
        self.assertEqual(len(after), len(before) + 1000)
        # Nothing moved (no step in between): the new agents are exactly the increase
        # inside the two disks (radius measured on the surface: flat, so Euclidean).
        def in_disks(points):
            return sum(1 for p in points if math.dist(p[:2], (0.5, 0.5)) <= 0.2 + 1e-4
                       or math.dist(p[:2], (0.5, 0.3)) <= 0.2 + 1e-4)
        self.assertEqual(in_disks(after) - in_disks(before), 1000)
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'FINISHED'})
        self.assertEqual(sorted(h.agent_positions(obj)), sorted(before))
        self.assertEqual(bpy.ops.moldtex.brush_redo(), {'FINISHED'})
        self.assertEqual(sorted(h.agent_positions(obj)), sorted(after),
                         "redo places the same agents again")
        # The simulation goes on with them.
        self.assertEqual(bpy.ops.moldtex.step(steps=5), {'FINISHED'})
        self.assertEqual(h.live().get(obj.name).sim.get_stats()["agent_count"],
                         len(before) + 1000)

    def test_slime_erase_and_undo(self):
        obj = _plane()
        h.run(obj, 1)
        before = h.agent_positions(obj)
        inside = _inside(before, (0.0, 0.0), 0.4)
        self.assertGreater(inside, 300)  # ~4000 * pi 0.16 / 4 = 500 expected
        _brush(target='SLIME', erase=True, radius=0.4)
        self.assertEqual(_stroke(obj, (0.0, 0.0)), {'FINISHED'})
        after = h.agent_positions(obj)
        self.assertEqual(len(after), len(before) - inside)
        self.assertEqual(_inside(after, (0.0, 0.0), 0.4 - 1e-4), 0)
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'FINISHED'})
        self.assertEqual(sorted(h.agent_positions(obj)), sorted(before))
        # Reset drops what the brush did; undoing a stroke of the old run then says so.
        self.assertEqual(bpy.ops.moldtex.brush_redo(), {'FINISHED'})
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'CANCELLED'})

    def test_food_brush_places_and_erases_empties(self):
        obj = _plane()
        obj.location = (3.0, 1.0, 0.0)
        bpy.context.view_layer.update()
        _brush(target='FOOD', radius=0.1, food_strength=3.0, food_amount=500.0)
        self.assertEqual(_stroke(obj, (3.5, 1.5)), {'FINISHED'})
        collection = obj.moldtex.food_collection
        self.assertIsNotNone(collection)
        empties = list(collection.all_objects)
        self.assertEqual(len(empties), 1)
        self.assertLess((empties[0].matrix_world.translation
                         - Vector((3.5, 1.5, 0.0))).length, 1e-4)
        self.assertEqual(empties[0]["moldtex_strength"], 3.0)
        self.assertEqual(empties[0]["moldtex_amount"], 500.0)
        # Erase around a point 0.05 away removes it; undo brings it back.
        _brush(target='FOOD', erase=True, radius=0.1)
        self.assertEqual(_stroke(obj, (3.55, 1.5)), {'FINISHED'})
        self.assertEqual(len(collection.all_objects), 0)
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'FINISHED'})
        self.assertEqual(len(collection.all_objects), 1)
        self.assertEqual(collection.all_objects[0]["moldtex_amount"], 500.0)
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'FINISHED'})
        self.assertEqual(len(collection.all_objects), 0)

    def test_food_at_the_3d_cursor_lands_on_the_surface(self):
        obj = _plane()
        _brush(target='OBSTACLE')
        bpy.context.scene.cursor.location = (0.3, -0.2, 0.7)  # above the plane
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.food_at_cursor(), {'FINISHED'})
        empties = list(obj.moldtex.food_collection.all_objects)
        self.assertEqual(len(empties), 1)
        # The nearest surface point: straight below the cursor.
        self.assertLess((empties[0].matrix_world.translation
                         - Vector((0.3, -0.2, 0.0))).length, 1e-5)
        self.assertEqual(bpy.context.scene.moldtex_brush.target, 'OBSTACLE',
                         "the brush settings are left as they were")
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'FINISHED'})
        self.assertEqual(len(obj.moldtex.food_collection.all_objects), 0)

    def test_the_brush_follows_an_edited_mesh(self):
        obj = _plane()
        _brush(target='OBSTACLE', radius=0.1)
        self.assertEqual(_stroke(obj, (0.8, 0.0)), {'FINISHED'})
        # Shrink the mesh itself to x in [-0.5, 0.5]: x = 0.8 is off the surface now.
        for vertex in obj.data.vertices:
            vertex.co.x *= 0.5
        obj.data.update()
        bpy.context.view_layer.update()
        self.assertEqual(_stroke(obj, (0.8, 0.0)), {'CANCELLED'})
        self.assertEqual(_stroke(obj, (0.4, 0.0)), {'FINISHED'})

    def test_show_fields_lays_the_painted_fields_over_the_pheromone(self):
        from moldtex.colour import material
        obj = _plane()
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        tree = obj.active_material.node_tree
        overlay = tree.nodes[material.OVERLAY_NODE]
        principled = next(n for n in tree.nodes if n.type == 'BSDF_PRINCIPLED')
        link = principled.inputs["Base Color"].links[0]
        self.assertEqual(link.from_node, overlay)
        self.assertEqual(tuple(overlay.inputs[1].default_value), (0.0, 0.0, 0.0),
                         "off by default: the pheromone colour is unchanged")
        _brush(target='OBSTACLE', radius=0.2)
        self.assertEqual(_stroke(obj, (0.0, 0.0)), {'FINISHED'})
        fields = tree.nodes[material.FIELDS_NODE]
        self.assertEqual(fields.image, obj.moldtex.fields_image)
        obj.moldtex.show_fields = True
        for value in overlay.inputs[1].default_value:
            self.assertAlmostEqual(value, material.OVERLAY_STRENGTH, places=6)
        obj.moldtex.show_fields = False
        self.assertEqual(tuple(overlay.inputs[1].default_value), (0.0, 0.0, 0.0))
        # Set Up Material again adds nothing.
        count = len(tree.nodes)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        self.assertEqual(len(tree.nodes), count)

    def test_a_stroke_that_misses_is_refused(self):
        obj = _plane()
        _brush(target='OBSTACLE')
        self.assertEqual(_stroke(obj, (5.0, 5.0)), {'CANCELLED'})
        self.assertEqual(_stroke(obj, (0.0, 0.0), direction=(0.0, 0.0, 1.0)),
                         {'CANCELLED'})  # pointing away from the plane
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'CANCELLED'})

    def test_repainted_fields_image_reaches_the_running_simulation(self):
        obj = _plane()
        _brush(target='OBSTACLE', radius=0.05)
        self.assertEqual(_stroke(obj, (0.9, 0.9)), {'FINISHED'})
        # Every agent starts at one point on the right half (big bang at the cursor).
        bpy.context.scene.cursor.location = (0.5, 0.0, 0.0)
        obj.moldtex.seed_shape = 'BIG_BANG'
        entry = h.run(obj, 1)
        live = h.live()
        # Repaint the image as Texture Paint would: a wall over the left half (x < 0).
        image = obj.moldtex.fields_image
        width, height = image.size
        pixels = array.array("f", bytes(16 * width * height))
        image.pixels.foreach_get(pixels)
        for index in range(width * height):
            if index % width < width // 2:
                pixels[4 * index + 1] = 1.0
        image.pixels.foreach_set(pixels)
        entry.fields_polled = 0.0
        self.assertTrue(live.poll_fields_image(entry, obj))
        entry.fields_polled = 0.0
        self.assertFalse(live.poll_fields_image(entry, obj), "unchanged: not sent again")
        self.assertEqual(bpy.ops.moldtex.step(steps=150), {'FINISHED'})
        positions = h.agent_positions(obj)
        # 150 steps of 1 texel carry agents 2.3 units from x = 0.5: without the new wall
        # many would be on the left (seen when the poll is skipped); with it, none.
        self.assertEqual(sum(1 for p in positions if p[0] < 0.0), 0)
        self.assertGreater(max(p[0] for p in positions) - min(p[0] for p in positions), 0.3)

    def test_painted_fields_survive_save_and_reload(self):
        obj = _plane()
        _brush(target='OBSTACLE', radius=0.3)
        self.assertEqual(_stroke(obj, (0.0, 0.0)), {'FINISHED'})
        green = list(_channel(obj.moldtex.fields_image, 1)[0])
        name = obj.name
        path = os.path.join(self.folder, "brush.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        obj = bpy.data.objects[name]
        image = obj.moldtex.fields_image
        self.assertIsNotNone(image)
        reloaded = _channel(image, 1)[0]
        # Packed as float EXR: the painted values come back (half floats hold 0 and 1
        # exactly).
        self.assertEqual(sum(1 for a, b in zip(green, reloaded) if abs(a - b) > 1e-3), 0)


if __name__ == "__main__":
    unittest.main()
