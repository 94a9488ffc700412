"""Food sources: Empties in the Food collection attract hungry agents (hunger_rate)."""

import math
import os
import shutil
import tempfile
import unittest

import bpy
from mathutils import Vector

import helpers as h

STEPS = 150
AMOUNT = 400000  # food in the finite source (test_finite_food_is_eaten_...)
CORNER = (0.9, 0.9, 0.0)


def _plane():
    return h.subdivided_plane()


def _food(location=CORNER, strength=16.0, amount=None):
    collection = bpy.data.collections.new("Food")
    bpy.context.scene.collection.children.link(collection)
    empty = bpy.data.objects.new("Food Empty", None)
    empty.location = location
    empty["moldtex_strength"] = strength
    if amount is not None:
        empty["moldtex_amount"] = amount
    collection.objects.link(empty)
    bpy.context.view_layer.update()
    return collection, empty


def _mean_distance(obj, target):
    """Mean 3D (world) distance of the live simulation's agents to `target`."""
    from moldtex.data.mesh_export import export_object
    mesh = export_object(obj, bpy.context.evaluated_depsgraph_get(), "")
    surface = h.engine().Surface(mesh.positions, mesh.triangles, mesh.uvs,
                                 mesh.triangle_uvs)
    try:
        agents = h.live().get(obj.name).sim.read_agents(obj.moldtex.agent_count)
        total = 0.0
        for triangle, bary in agents:
            position, _uv = surface.evaluate(triangle, bary)
            total += math.dist(obj.matrix_world @ Vector(position), target)
    finally:
        surface.release()
    return total / len(agents)


class FoodTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        for collection in list(bpy.data.collections):
            bpy.data.collections.remove(collection)
        self.folder = tempfile.mkdtemp(prefix="moldtex_food_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def _run(self, hunger_rate, amount=None):
        obj = _plane()
        # Moved, so the Empty's world location must be taken into the mesh's space.
        obj.location = (3.0, -1.0, 0.5)
        bpy.context.view_layer.update()
        world_corner = tuple(obj.matrix_world @ Vector(CORNER))
        collection, empty = _food(world_corner, amount=amount)
        h.configure(obj, agents=5000, movement_speed=2.0)
        obj.moldtex.food_collection = collection
        obj.moldtex.hunger_rate = hunger_rate
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        start = _mean_distance(obj, world_corner)
        self.assertEqual(bpy.ops.moldtex.step(steps=STEPS), {'FINISHED'})
        end = _mean_distance(obj, world_corner)
        return obj, empty, start, end

    def test_hungry_agents_gather_at_the_food(self):
        _obj, _empty, start, end = self._run(4.0)
        _obj0, _empty0, start0, end0 = self._run(0.0)
        print(f"\n  food: mean distance {start:.3f} -> {end:.3f} with hunger 4, "
              f"{start0:.3f} -> {end0:.3f} without")
        # Starts uniform on the plane (about 1.4 from a corner). Hungry agents (h = 1
        # after 15 steps) head for the corner at 2 texels (1/64 unit) a step, so within
        # 150 steps most of them arrive: seen 1.41 -> 0.10. Without hunger the
        # spread stays uniform (seen within 2 %): the margins leave room for other
        # backends and seeds.
        self.assertLess(end, 0.6 * start)
        self.assertGreater(end0, 0.9 * start0)

    def test_finite_food_is_eaten_and_settings_survive_reload(self):
        # The agents eat 195,000-211,000 over STEPS steps (seeds 1, 2, 3 and the test's
        # 7, 2026-12-05): an amount of twice that is partly eaten whatever the random
        # draws (200,000, as until then, was eaten up for some of them).
        obj, empty, start, end = self._run(4.0, amount=AMOUNT)
        from moldtex.sim import session as live
        status = live.food_status(obj)
        self.assertEqual(len(status), 1)
        name, remaining = status[0]
        self.assertEqual(name, empty.name)
        print(f"\n  food: {remaining:.0f} of {AMOUNT} left after {STEPS} steps")
        self.assertLess(remaining, float(AMOUNT))
        self.assertGreater(remaining, 0.0)  # seen 199888 left: partly eaten
        self.assertGreaterEqual(remaining, 0.0)
        self.assertEqual(h.live().get(obj.name).sim.get_food()[0][2], remaining)
        # Another step neither refills nor re-sends it.
        self.assertEqual(bpy.ops.moldtex.step(steps=5), {'FINISHED'})
        self.assertLessEqual(live.food_status(obj)[0][1], remaining)
        # The panel draws the list (in background there is no panel: check its data).
        obj.moldtex.food_radius = 0.25
        name = obj.name
        path = os.path.join(self.folder, "food.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        obj = bpy.data.objects[name]
        self.assertEqual(obj.moldtex.food_collection.name, "Food")
        self.assertAlmostEqual(obj.moldtex.hunger_rate, 4.0, places=5)
        self.assertAlmostEqual(obj.moldtex.food_radius, 0.25, places=5)
        empties = list(obj.moldtex.food_collection.all_objects)
        self.assertEqual(len(empties), 1)
        self.assertEqual(empties[0]["moldtex_amount"], AMOUNT)
        # A Reset gives the food back.
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        self.assertEqual(live.food_status(obj)[0][1], float(AMOUNT))


if __name__ == "__main__":
    unittest.main()
