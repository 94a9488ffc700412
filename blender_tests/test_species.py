"""Species, starting seeds and static fields (momas-paper.md §2.5) through the add-on."""

import array
import math
import os
import shutil
import tempfile
import unittest

import bpy

import helpers as h

MAZE_SIZE = 256


def _overlap(pixels):
    """Σ min(R, G) / Σ max(R, G): how much the two species' trails share texels."""
    low = high = 0.0
    for i in range(0, len(pixels), 4):
        r, g = pixels[i], pixels[i + 1]
        low += min(r, g)
        high += max(r, g)
    return low / high if high > 0.0 else 0.0


def _grid():
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=8, y_subdivisions=8, size=2.0,
                                    calc_uvs=True)
    return h.activate(bpy.context.active_object)


def _surface(obj):
    """An engine.Surface of obj's evaluated mesh, in the add-on's triangle order."""
    from moldtex.data.mesh_export import export_object
    mesh = export_object(obj, bpy.context.evaluated_depsgraph_get(), "")
    return h.engine().Surface(mesh.positions, mesh.triangles, mesh.uvs, mesh.triangle_uvs)


def _maze_image():
    """Spawn (R) below v = 0.3, a wall (G) across v in [0.5, 0.56) with a gap at
    u in [0.45, 0.55), and an attractor (B) above v = 0.6, the goal."""
    image = bpy.data.images.new("Maze", MAZE_SIZE, MAZE_SIZE, float_buffer=True)
    pixels = array.array("f", bytes(4 * 4 * MAZE_SIZE * MAZE_SIZE))
    for y in range(MAZE_SIZE):
        v = (y + 0.5) / MAZE_SIZE
        for x in range(MAZE_SIZE):
            u = (x + 0.5) / MAZE_SIZE
            i = 4 * (y * MAZE_SIZE + x)
            pixels[i] = 1.0 if v < 0.3 else 0.0
            pixels[i + 1] = 1.0 if (0.5 <= v < 0.56 and not 0.45 <= u < 0.55) else 0.0
            pixels[i + 2] = 1.0 if v > 0.6 else 0.0
            pixels[i + 3] = 1.0
    image.pixels.foreach_set(pixels)
    return image, pixels


class SpeciesTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        bpy.context.scene.cursor.location = (0.0, 0.0, 0.0)

    def _two_species_overlap(self, attraction_to_other):
        obj = _grid()
        h.configure(obj)
        obj.moldtex.species_count = 2
        for index, item in enumerate(obj.moldtex.species):
            item.attraction = tuple(1.0 if k == index else attraction_to_other
                                    for k in range(4))
        h.run(obj, 300)
        overlap = _overlap(h.image_pixels(obj))
        h.clear_scene()
        return overlap

    def test_repelling_species_separate(self):
        repel = self._two_species_overlap(-1.0)
        attract = self._two_species_overlap(1.0)
        print(f"\n  overlap Σmin/Σmax: repelling {repel:.3f}, attracting {attract:.3f}")
        self.assertLess(repel, 0.5 * attract)

    def test_species_settings_reach_the_core(self):
        obj = _grid()
        h.configure(obj, agents=2000)
        obj.moldtex.species_count = 3
        self.assertEqual(len(obj.moldtex.species), 3)
        self.assertEqual(tuple(obj.moldtex.species[1].attraction), (-1.0, 1.0, -1.0, -1.0))
        obj.moldtex.species[2].movement_speed = 1.5
        entry = h.run(obj, 2)
        self.assertEqual(entry.sim.get_config()["species_count"], 3)
        self.assertAlmostEqual(entry.sim.get_species_params(2)["movement_speed"], 1.5)
        obj.moldtex.species[1].attraction = (0.5, 1.0, -0.25, -1.0)  # live, no reset
        got = entry.sim.get_species_params(1)["attraction"]
        self.assertEqual(tuple(round(a, 4) for a in got), (0.5, 1.0, -0.25, -1.0))
        # A step (which sends the shared parameters) keeps the species' own behaviour.
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        self.assertAlmostEqual(entry.sim.get_species_params(2)["movement_speed"], 1.5)
        self.assertAlmostEqual(entry.sim.get_species_params(0)["movement_speed"],
                               obj.moldtex.species[0].movement_speed)

    def test_material_colours_by_species(self):
        obj = _grid()
        h.configure(obj, agents=2000)
        obj.moldtex.species_count = 2
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        nodes = obj.active_material.node_tree.nodes
        # Base Color comes through the fields overlay, whose base input is the colour.
        base = nodes["Moldtex Fields Overlay"].inputs[2]
        self.assertTrue(base.links[0].from_node.name.startswith("Moldtex Species"))
        obj.moldtex.species_count = 1  # back to the ramp
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        self.assertEqual(base.links[0].from_node.name, "Moldtex Ramp")
        self.assertFalse([n for n in nodes if n.name.startswith("Moldtex Species")])


class SeedAndFieldTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        bpy.context.scene.cursor.location = (0.0, 0.0, 0.0)

    def tearDown(self):
        bpy.context.scene.cursor.location = (0.0, 0.0, 0.0)

    def test_circle_at_the_cursor(self):
        bpy.ops.mesh.primitive_plane_add(size=4.0, location=(0.5, 0.25, 0.0))
        obj = h.activate(bpy.context.active_object)
        obj.scale = (2.0, 2.0, 2.0)  # the radius is in scene units, not the mesh's
        bpy.context.view_layer.update()
        cursor = (1.3, -0.6, 0.7)  # above the plane: its nearest point is (1.3, -0.6, 0)
        bpy.context.scene.cursor.location = cursor
        h.configure(obj, agents=3000)
        obj.moldtex.seed_shape = 'CIRCLE'
        obj.moldtex.seed_radius = 1.5
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        sim = h.live().get(obj.name).sim
        surface = _surface(obj)
        worst = 0.0
        for triangle, bary in sim.read_agents(3000):
            position, _uv = surface.evaluate(triangle, bary)
            world = obj.matrix_world @ __import__("mathutils").Vector(position)
            distance = math.dist(world, (1.3, -0.6, 0.0))
            worst = max(worst, abs(distance - 1.5) / 1.5)
        surface.release()
        print(f"\n  circle seed: worst relative radius error {worst:.2e}")
        self.assertLess(worst, 1e-3)

    def test_spawn_map_needs_a_spawn_region(self):
        obj = _grid()
        h.configure(obj, agents=2000)
        obj.moldtex.seed_shape = 'SPAWN_MAP'
        # Background mode turns the operator's error report into a RuntimeError.
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.reset()
        self.assertIn("no Fields image is set", str(caught.exception))
        walls = bpy.data.images.new("Walls", 64, 64, float_buffer=True)
        walls.pixels.foreach_set(array.array("f", [1.0, 1.0, 0.0, 1.0] * 64 * 64))
        obj.moldtex.fields_image = walls
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.reset()
        self.assertIn("no spawn region", str(caught.exception))
        self.assertIsNone(h.live().get(obj.name))

    def test_fields_image_is_resampled_nearest(self):
        obj = _grid()
        image = bpy.data.images.new("Small", 2, 2, float_buffer=True)
        # Blender's row order: row 0 is the bottom row.
        image.pixels.foreach_set(array.array("f", [0.1, 0, 0, 1, 0.2, 0, 0, 1,
                                                   0.3, 0, 0, 1, 0.4, 0, 0, 1]))
        obj.moldtex.fields_image = image
        from moldtex.sim import session as live
        fields = h.convert().fields_from_settings(obj.moldtex, 4, 4)
        red = [round(fields[4 * i], 4) for i in range(16)]
        self.assertEqual(red, [0.1, 0.1, 0.2, 0.2] * 2 + [0.3, 0.3, 0.4, 0.4] * 2)

    def test_maze_walls_and_goal(self):
        obj = h.add_primitive("sphere")
        h.configure(obj, resolution=str(MAZE_SIZE), agents=20000, movement_speed=2.0)
        image, pixels = _maze_image()
        obj.moldtex.fields_image = image
        obj.moldtex.seed_shape = 'SPAWN_MAP'
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        entry = h.live().get(obj.name)
        surface = _surface(obj)
        starts = [surface.evaluate(t, b)[1][1] for t, b in entry.sim.read_agents(20000)]
        self.assertLess(max(starts), 0.3 + 1.0 / MAZE_SIZE)  # all in the spawn region
        self.assertEqual(bpy.ops.moldtex.step(steps=600), {'FINISHED'})
        in_wall = at_goal = below = 0
        agents = entry.sim.read_agents(20000)
        for triangle, bary in agents:
            _position, (u, v) = surface.evaluate(triangle, bary)
            x = min(MAZE_SIZE - 1, max(0, int(u * MAZE_SIZE)))
            y = min(MAZE_SIZE - 1, max(0, int(v * MAZE_SIZE)))
            if pixels[4 * (y * MAZE_SIZE + x) + 1] > 0.5:
                in_wall += 1
            if v > 0.6:
                at_goal += 1
            if v < 0.5:
                below += 1
        surface.release()
        print(f"\n  maze: {in_wall} agents in walls, {at_goal} at the goal, {below} "
              f"still below the wall (of {len(agents)})")
        self.assertEqual(in_wall, 0)
        self.assertGreater(at_goal, 0)


class SpeciesPersistenceTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_test_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_species_and_fields_survive_save_and_reload(self):
        obj = _grid()
        name = obj.name
        settings = obj.moldtex
        settings.species_count = 2
        settings.species[1].movement_speed = 1.75
        settings.species[1].attraction = (0.25, 1.0, -0.5, -1.0)
        settings.species[0].color = (0.2, 0.4, 0.6)
        settings.seed_shape = 'STARBURST'
        settings.seed_radius = 0.75
        settings.seed_rays = 5
        image, _pixels = _maze_image()
        image.use_fake_user = True
        settings.fields_image = image
        path = os.path.join(self.folder, "moldtex_species.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        settings = bpy.data.objects[name].moldtex
        self.assertEqual(settings.species_count, 2)
        self.assertEqual(len(settings.species), 2)
        self.assertAlmostEqual(settings.species[1].movement_speed, 1.75)
        self.assertEqual(tuple(settings.species[1].attraction), (0.25, 1.0, -0.5, -1.0))
        self.assertEqual(tuple(round(c, 5) for c in settings.species[0].color),
                         (0.2, 0.4, 0.6))
        self.assertEqual(settings.seed_shape, 'STARBURST')
        self.assertAlmostEqual(settings.seed_radius, 0.75)
        self.assertEqual(settings.seed_rays, 5)
        self.assertEqual(settings.fields_image.name, "Maze")


if __name__ == "__main__":
    unittest.main()
