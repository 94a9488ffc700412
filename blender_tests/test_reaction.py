"""Gray-Scott reaction-diffusion from Blender (issue 13): the Model choice makes a
Gray-Scott simulation with the panel's rates converted to mesh units through the pattern
unit, the three shipped looks grow their patterns, the material shows V (the image's R)
over the Display Range, a bake resumes byte for byte, and the panel, presets and command
line offer it all."""

import math
import os
import shutil
import tempfile
import unittest

import bpy

import helpers as h
from test_ui import draw_all, labels

LOOKS = ("reaction_spots", "reaction_labyrinth", "reaction_worms")
# Suzanne at 128² with Pattern Scale 4: one pattern unit is about one texel, as at the
# looks' own 512² with Pattern Scale 1, at a sixteenth of the cost.
SIZE = "128"
SCALE = 4.0


def presets_module():
    from moldtex.looks import presets
    return presets


def gray_scott(kind="monkey", look=None):
    obj = h.add_primitive(kind)
    h.configure(obj, resolution=SIZE)
    if look:
        assert bpy.ops.moldtex.preset_apply(filepath=presets_module().find(look)) == {'FINISHED'}
    obj.moldtex.model = 'GRAY_SCOTT'
    obj.moldtex.pattern_scale = SCALE
    return obj


def island_v(entry):
    pixels = entry.sim.read_rgba()
    classes = entry.sim.read_texel_classes()
    return [pixels[4 * i] for i, c in enumerate(classes) if c == 1]


class ReactionModelTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def tearDown(self):
        # The scene's brush back to painting obstacles (the brush test leaves it erasing
        # slime), so later tests start from the defaults.
        import importlib
        importlib.import_module("test_brush")._brush()

    def test_model_choice_makes_a_gray_scott_simulation(self):
        engine, live = h.engine(), h.live()
        obj = gray_scott()
        entry = h.run(obj, 5)
        sim = entry.sim
        self.assertEqual(sim.get_config()["model"], engine.MODEL_GRAY_SCOTT)
        self.assertEqual(entry.stats["agent_count"], 0)
        self.assertAlmostEqual(entry.stats["time"], 5.0, places=5)  # 5 steps of 1 s
        # Rates in pattern units² per second become mesh units² through the unit.
        unit = h.units().pattern_unit(obj.moldtex, entry.surface_info["area"])
        core = sim.get_reaction_params()
        reaction = obj.moldtex.reaction
        self.assertAlmostEqual(core["diffusion_u"] / (reaction.diffusion_u * unit * unit),
                               1.0, places=5)
        self.assertAlmostEqual(core["diffusion_v"] / (reaction.diffusion_v * unit * unit),
                               1.0, places=5)
        self.assertAlmostEqual(core["seed_radius"] / (reaction.seed_radius * unit), 1.0,
                               places=5)
        self.assertEqual(core["seed_count"], reaction.seed_count)
        # The seeds are there: V = 1 in the disks, 0 elsewhere, U = 1 away from them.
        pixels = sim.read_rgba()
        self.assertGreater(max(pixels[0::4]), 0.5)
        self.assertEqual(max(pixels[1::4]), 1.0)
        # A rate reaches the running simulation at once; the seeds wait for Reset.
        reaction.feed = 0.05
        self.assertAlmostEqual(sim.get_reaction_params()["feed"], 0.05, places=6)
        self.assertFalse(live.needs_reset(obj))
        reaction.seed_count = 9
        self.assertTrue(live.needs_reset(obj))
        entry = h.run(obj, 1)
        self.assertEqual(entry.sim.get_reaction_params()["seed_count"], 9)
        self.assertFalse(live.needs_reset(obj))

    def test_the_looks_grow_their_patterns_and_the_material_shows_v(self):
        # 2500 simulated seconds. Measured (V > 0.1 share of the island area, mean V):
        # spots 0.36 / 0.105, labyrinth 0.64 / 0.175, worms 0.37 / 0.114 on this
        # Suzanne; the bands leave about 0.1 either side, and ask for a pattern, not a flat
        # field: the V of the island texels spreads (std > 0.05) between 0 and V's
        # ceiling (4, reaction.h).
        bands = {"reaction_spots": (0.25, 0.65), "reaction_labyrinth": (0.4, 0.8),
                 "reaction_worms": (0.2, 0.6)}
        seen = {}
        for look in LOOKS:
            h.clear_scene()
            obj = gray_scott(look=look)
            self.assertEqual(obj.moldtex.model, 'GRAY_SCOTT')
            entry = h.run(obj, 2500)
            values = island_v(entry)
            mean = sum(values) / len(values)
            std = math.sqrt(sum((v - mean) ** 2 for v in values) / len(values))
            presence = entry.stats["presence"]
            seen[look] = (presence, mean, std)
            self.assertTrue(all(math.isfinite(v) and 0.0 <= v <= 4.0 for v in values), look)
            self.assertGreater(std, 0.05, f"{look}: V is flat")
            low, high = bands[look]
            self.assertGreater(presence, low, look)
            self.assertLess(presence, high, look)
            # The material reads V alone (R: G holds U, near 1 where V is 0) over the
            # look's display range.
            self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
            nodes = obj.active_material.node_tree.nodes
            span = nodes["Moldtex Range"]
            self.assertEqual(span.inputs[0].links[0].from_node.name, "Moldtex V")
            self.assertEqual(span.inputs[0].links[0].from_socket.name, "Red")
            self.assertAlmostEqual(span.inputs[2].default_value,
                                   obj.moldtex.reaction.display_range, places=6)
            # Back to MoMaS: the Range node reads the (grey) image whole again.
            obj.moldtex.model = 'MOMAS'
            h.run(obj, 1)
            bpy.ops.moldtex.step(steps=1)
            from moldtex.colour import material
            material.sync_display_range(obj)
            self.assertNotIn("Moldtex V", nodes)
            self.assertEqual(span.inputs[0].links[0].from_node.name, "Moldtex Texture")
        print("  looks (V > 0.1, mean V, std V):",
              ", ".join(f"{k} {p:.2f}/{m:.3f}/{s:.3f}" for k, (p, m, s) in seen.items()))

    def test_the_slime_brush_seeds_v_and_undo_takes_it_back(self):
        # A 2 × 2 plane (UVs fill the square); the labyrinth's seeds are made tiny so
        # that V comes from the brush: a stroke of two dabs at full strength, no falloff.
        import importlib
        test_brush = importlib.import_module("test_brush")
        obj = h.subdivided_plane()
        h.configure(obj, resolution=SIZE)
        obj.moldtex.model = 'GRAY_SCOTT'
        obj.moldtex.pattern_scale = SCALE
        obj.moldtex.reaction.seed_count = 1
        obj.moldtex.reaction.seed_radius = 0.01
        entry = h.run(obj, 1)
        before = entry.sim.read_rgba()
        test_brush._brush(target='SLIME', radius=0.2, falloff=0.0)
        self.assertEqual(test_brush._stroke(obj, (0.5, 0.5), (-0.5, -0.5)), {'FINISHED'})
        seeded = entry.sim.read_rgba()
        size = int(SIZE)

        def texels_near(pixels, x, y, radius):
            # V of the texels whose centre (plane coordinates) lies within radius.
            found = []
            for j in range(size):
                for i in range(size):
                    px, py = (i + 0.5) / size * 2 - 1, (j + 0.5) / size * 2 - 1
                    if math.dist((px, py), (x, y)) <= radius:
                        found.append(pixels[4 * (j * size + i)])
            return found

        for x, y in ((0.5, 0.5), (-0.5, -0.5)):
            inside = texels_near(seeded, x, y, 0.17)
            self.assertGreater(len(inside), 50)
            self.assertEqual(min(inside), 1.0)  # V = 1: a seed
        self.assertEqual(max(texels_near(seeded, 0.5, -0.5, 0.2)), 0.0)  # not touched
        self.assertEqual(entry.stats["agent_count"], 0)
        self.assertEqual(bpy.ops.moldtex.brush_undo(), {'FINISHED'})
        self.assertEqual(list(entry.sim.read_rgba()), list(before))
        self.assertEqual(bpy.ops.moldtex.brush_redo(), {'FINISHED'})
        self.assertEqual(list(entry.sim.read_rgba()), list(seeded))
        # The seeds grow into the pattern.
        self.assertEqual(bpy.ops.moldtex.step(steps=400), {'FINISHED'})
        self.assertGreater(h.live().get(obj.name).stats["presence"], 0.1)
        # Erasing everywhere clears V.
        test_brush._brush(target='SLIME', erase=True, radius=3.0, falloff=0.0)
        self.assertEqual(test_brush._stroke(obj, (0.0, 0.0)), {'FINISHED'})
        self.assertEqual(max(entry.sim.read_rgba()[0::4]), 0.0)


class ReactionMapTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_kill_and_feed_maps_bare_the_painted_half_and_reach_a_running_simulation(self):
        # The 2 × 2 plane with a "Right" group (x > 0); the labyrinth at 128², Pattern
        # Scale 4. Kill At 1 = 2 (k 0.12 there) bares the right half: measured mean V
        # 0.17 left, 1.1e-4 right after 1500 s (the core's own test: 0.19 / 4e-5).
        import test_maps
        obj = test_maps.maps_plane()
        obj.moldtex.model = 'GRAY_SCOTT'
        obj.moldtex.pattern_scale = SCALE
        self.assertEqual(bpy.ops.moldtex.preset_apply(
            filepath=presets_module().find("reaction_labyrinth")), {'FINISHED'})
        # The Maps panel offers the three maps Gray-Scott reads (diffusion, feed, kill),
        # not the continuous model's twelve.
        log = draw_all(self, obj)
        self.assertEqual(sum(1 for entry in log if entry == ("prop", "enabled")), 3)
        test_maps.set_map(obj, "kill", "Right", at0=1.0, at1=2.0)
        entry = h.run(obj, 1500)
        left, right = test_maps.halves(entry.sim.read_rgba())
        print(f"  kill map: mean V left {left:.4f}, right {right:.6f}")
        self.assertGreater(left, 0.1)
        self.assertLess(right, 1e-3)
        self.assertIsNotNone(entry.sim.get_map(h.engine().MAP_KILL))
        # Off, then a feed map of 0 on the left, while it runs: the next steps get it
        # (no Reset), and the left half starves (the right, bare, stays bare).
        obj.moldtex.maps.kill.enabled = False
        test_maps.set_map(obj, "feed", "Left", at0=1.0, at1=0.0)
        self.assertIsNone(entry.sim.get_map(h.engine().MAP_KILL))
        self.assertEqual(bpy.ops.moldtex.step(steps=1500), {'FINISHED'})
        left, right = test_maps.halves(entry.sim.read_rgba())
        print(f"  then a feed map: mean V left {left:.6f}, right {right:.6f}")
        self.assertLess(left, 1e-3)


class ReactionBakeTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_reaction_bake_")

    def tearDown(self):
        h.clear_scene()
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_bake_holds_v_and_resumes_byte_for_byte(self):
        obj = gray_scott(kind="sphere", look="reaction_labyrinth")
        full = os.path.join(self.folder, "full")
        cut = os.path.join(self.folder, "cut")
        h.bake_settings(obj, full, 1, 6, 100, "EXR_HALF")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        reference = h.comparable_bytes(full)
        # Frame 6 holds what a fresh simulation holds after 600 steps (half floats).
        sim = h.fresh_sim(obj)
        try:
            sim.step(600)
            expected = sim.read_rgba()
        finally:
            sim.release()
        pixels, size = h.load_pixels(os.path.join(full, "Sphere_0006.exr"))
        self.assertEqual(size, (128, 128))
        worst = max(abs(a - b) for a, b in zip(pixels[0::4], expected[0::4]))
        self.assertLessEqual(worst, 1.0 / 1024)  # half float: 11 bits on values < 2
        self.assertGreater(max(pixels[0::4]), 0.2)  # V grew
        # Three frames, then the rest resumed from their checkpoint: the same files.
        h.bake_settings(obj, cut, 1, 3, 100, "EXR_HALF")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        h.bake_settings(obj, cut, 1, 6, 100, "EXR_HALF", resume=True)
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        self.assertEqual(h.comparable_bytes(cut), reference)

    def test_model_and_looks_from_the_command_line(self):
        from moldtex import cli
        gray_scott(kind="sphere")
        bpy.ops.wm.save_as_mainfile(filepath=os.path.join(self.folder, "scene.blend"))
        out = os.path.join(self.folder, "cli")
        self.assertEqual(cli.run(["--object", "Sphere", "--out", out, "--frames", "1", "2",
                                  "--steps-per-frame", "20", "--preset", "reaction_worms",
                                  "--model", "gray-scott"]), 0)
        obj = bpy.data.objects["Sphere"]
        self.assertEqual(obj.moldtex.model, 'GRAY_SCOTT')
        self.assertAlmostEqual(obj.moldtex.reaction.feed, 0.078, places=6)
        self.assertEqual(h.live().get("Sphere").sim.get_config()["model"],
                         h.engine().MODEL_GRAY_SCOTT)
        pixels, _ = h.load_pixels(os.path.join(out, "Sphere_0002.exr"))
        self.assertGreater(max(pixels[0::4]), 0.1)


class ReactionPanelTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def shown(self, obj):
        return {name for kind, name in draw_all(self, obj) if kind == "prop"}

    def test_the_panels_follow_the_model(self):
        obj = gray_scott()
        shown = self.shown(obj)
        self.assertLessEqual({"feed", "kill", "diffusion_u", "diffusion_v", "time_step",
                              "seed_count", "seed_radius", "display_range",
                              "pattern_scale"}, shown)
        # No agents: none of the agent models' settings.
        self.assertEqual(shown & {"agent_count", "species_count", "movement_speed",
                                  "move_rate", "evaporation_rate", "decay_rate"}, set())
        entry = h.run(obj, 3)
        text = labels(draw_all(self, obj))
        self.assertIn("Mean V", text)
        self.assertIn(f"{entry.stats['coverage']:.3f}", text)
        self.assertIn("3.00 s", text)
        self.assertNotIn("Agents", text.replace("no agents", ""))

    def test_a_saved_look_keeps_the_model_and_its_rates(self):
        presets = presets_module()
        obj = gray_scott()
        obj.moldtex.reaction.feed = 0.0421
        obj.moldtex.reaction.seed_count = 77
        text = presets.preset_text(obj, "mine")
        h.clear_scene()
        other = h.add_primitive("torus")
        path = os.path.join(tempfile.mkdtemp(prefix="moldtex_look_"), "mine.py")
        try:
            with open(path, "w") as file:
                file.write(text)
            self.assertEqual(bpy.ops.moldtex.preset_apply(filepath=path), {'FINISHED'})
        finally:
            shutil.rmtree(os.path.dirname(path), ignore_errors=True)
        self.assertEqual(other.moldtex.model, 'GRAY_SCOTT')
        self.assertAlmostEqual(other.moldtex.reaction.feed, 0.0421, places=6)
        self.assertEqual(other.moldtex.reaction.seed_count, 77)


if __name__ == "__main__":
    unittest.main()
