"""Parameter maps and stimuli of the continuous model from Blender (addon/moldtex/maps,
issue 12): a map painted as a vertex group changes the pattern where painted (Deposit
brightens, a Lifetime sink empties, an Emitter adds pheromone), maps reach the core
with the panel's At 0 / At 1 / Strength, survive save and reload, apply in a bake and
on the command line, bad input gives a sentence (not a traceback), the Maps panel
draws and fits, Show opens Weight Paint, and presets leave maps alone.

The scene: a 2 x 2 plane cut into 16 x 16 quads (helpers.subdivided_plane), its UVs
filling the texture (texel column x covers u = (x + 0.5) / 128, so the left half of the
texture is the plane's x < 0), with a vertex group "Right" of weight 1 on x > 0 and
"Left" on x < 0. 4000 agents on 128², 2 simulated seconds (120 steps)."""

import os
import shutil
import subprocess
import tempfile
import types
import unittest

import bpy

import helpers as h
from test_ui import RecordingLayout, draw_all, labels

SIZE = 128
STEPS = 120
MARGIN = 4  # texels either side of the painted edge left out (weights blend there)


def maps_plane():
    obj = h.subdivided_plane()
    for name, inside in (("Right", lambda x: x > 0.01), ("Left", lambda x: x < -0.01)):
        group = obj.vertex_groups.new(name=name)
        group.add([v.index for v in obj.data.vertices if inside(v.co.x)], 1.0, 'REPLACE')
    h.configure(obj, resolution=str(SIZE), agents=4000)
    obj.moldtex.model = 'CONTINUOUS'
    obj.moldtex.pattern_scale = 1.0  # (configure sets MoMaS' test scale)
    return obj


def halves(pixels, size=SIZE):
    """Mean R (u / U) of the texture's left (x < 0) and right (x > 0) halves."""
    left = right = 0.0
    n_left = n_right = 0
    for y in range(size):
        row = 4 * y * size
        for x in range(size):
            value = pixels[row + 4 * x]
            if x < size // 2 - MARGIN:
                left += value
                n_left += 1
            elif x >= size // 2 + MARGIN:
                right += value
                n_right += 1
    return left / n_left, right / n_right


def set_map(obj, key, group, **values):
    slot = getattr(obj.moldtex.maps, key)
    slot.source = 'ATTRIBUTE'
    slot.attribute = group
    for name, value in values.items():
        setattr(slot, name, value)
    slot.enabled = True
    return slot


def operator_error(call):
    """The message of an operator's ERROR report (background mode raises it)."""
    try:
        result = call()
    except RuntimeError as error:
        return str(error)
    return f"no error: {result}"


class MapPatternTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_deposit_map_brightens_the_painted_half(self):
        engine = h.engine()
        obj = maps_plane()
        left, right = halves(h.run(obj, STEPS).sim.read_rgba())
        # Without a map both halves hold about U (u / U = 1): within 15 %.
        self.assertLess(abs(right / left - 1.0), 0.15, (left, right))
        set_map(obj, "deposit_rate", "Right", at0=1.0, at1=3.0)
        entry = h.run(obj, STEPS)
        values = entry.sim.get_map(engine.MAP_DEPOSIT_RATE)
        self.assertAlmostEqual(min(values), 1.0, places=5)  # At 0 where unpainted
        self.assertAlmostEqual(max(values), 3.0, places=5)  # At 1 where painted
        self.assertIsNone(entry.sim.get_map(engine.MAP_MOVE_RATE))  # off: not set
        left, right = halves(h.image_pixels(obj))
        # Agents spread evenly (the map does not move them) and lay 3 x the pheromone on
        # the right: u / U there is 3 x the left's. Measured 3.14 to 3.21 over seeds
        # 1 to 3; allowed 2.6 to 3.6, as diffusion carries some across the edge (the
        # MARGIN texels next to it are left out) and 4000 agents over 2 s leave the
        # halves' means a few per cent apart from seed to seed.
        self.assertTrue(2.6 < right / left < 3.6, (left, right))
        self.assertLess(abs(left - 1.0), 0.15, left)

    def test_lifetime_sink_empties_the_painted_half(self):
        obj = maps_plane()
        set_map(obj, "mean_lifetime", "Right")  # defaults: At 0 = 1, At 1 = 0 (a sink)
        slot = obj.moldtex.maps.mean_lifetime
        self.assertEqual((slot.at0, slot.at1), (1.0, 0.0))
        self.assertEqual(obj.moldtex.continuous.mean_lifetime, 0.0)  # no turnover else
        entry = h.run(obj, STEPS)
        left, right = halves(entry.sim.read_rgba())
        # Agents stepping into the sink die at once and are reborn anywhere (those
        # reborn in it die again): all live, and so lay, on the left: about 2 U there,
        # next to nothing on the right (measured 0.004 to 0.045 U over seeds 1 to 3).
        self.assertLess(right, 0.1, (left, right))
        self.assertGreater(left, 1.5, (left, right))
        self.assertEqual(entry.stats["agent_count"], 4000)  # reborn, not lost
        # A Spawn map on the left (a source) keeps the sink empty as well.
        set_map(obj, "spawn", "Left")
        left, right = halves(h.run(obj, STEPS).sim.read_rgba())
        self.assertLess(right, 0.1, (left, right))

    def test_emitter_adds_pheromone_and_lure_reaches_the_core(self):
        engine = h.engine()
        obj = maps_plane()
        set_map(obj, "write_stimulus", "Right", strength=3.0)
        entry = h.run(obj, STEPS)
        left, right = halves(entry.sim.read_rgba())
        # A write stimulus alone holds u / U at its strength; the agents add their own
        # U: about 1 + 3 on the right (measured 3.87 to 4.09), 1 on the left.
        self.assertTrue(3.4 < right < 4.6, right)
        self.assertLess(abs(left - 1.0), 0.2, left)
        # The Lure (read stimulus) gets Strength x weight, signed.
        set_map(obj, "read_stimulus", "Right", strength=-2.5)
        values = entry.sim.get_map(engine.MAP_READ_STIMULUS)  # sent at once, live
        self.assertAlmostEqual(min(values), -2.5, places=5)
        self.assertAlmostEqual(max(values), 0.0, places=5)


class OpenEdgeTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_absorbing_open_edges_reach_the_core_and_thin_the_border(self):
        engine = h.engine()
        obj = maps_plane()

        def border(pixels, width=6):
            """Mean u / U of the texels within `width` of the plane's edge."""
            total = count = 0
            for y in range(SIZE):
                for x in range(SIZE):
                    if min(x, y, SIZE - 1 - x, SIZE - 1 - y) < width:
                        total += pixels[4 * (y * SIZE + x)]
                        count += 1
            return total / count

        reflect = border(h.run(obj, STEPS).sim.read_rgba())
        obj.moldtex.continuous.boundary = 'ABSORB'
        entry = h.run(obj, STEPS)
        self.assertEqual(entry.sim.get_continuous_params()["boundary"], engine.BOUNDARY_ABSORB)
        absorb = border(entry.sim.read_rgba())
        print(f"  border u / U: reflect {reflect:.3f}, absorb {absorb:.3f}")
        # Agents that reach the edge die there (and are reborn anywhere): fewer trails
        # hug the border than when they turn back along it (measured 1.06 U reflecting,
        # 0.30 U absorbing; allowed: below 0.8 of the reflecting border).
        self.assertLess(absorb, 0.8 * reflect, (reflect, absorb))
        self.assertEqual(entry.stats["agent_count"], 4000)  # reborn, not lost


class MapLiveTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_changes_reach_the_live_simulation_only_when_needed(self):
        engine = h.engine()
        obj = maps_plane()
        entry = h.run(obj, 2)
        slot = set_map(obj, "move_rate", "Right", at0=0.5, at1=2.0)
        values = entry.sim.get_map(engine.MAP_MOVE_RATE)  # no Reset: the update sent it
        self.assertAlmostEqual(min(values), 0.5, places=5)
        self.assertAlmostEqual(max(values), 2.0, places=5)
        keys = dict(entry.map_keys)
        bpy.ops.moldtex.step(steps=2)
        self.assertEqual(entry.map_keys, keys)  # stepping sends nothing again
        slot.at1 = 4.0
        self.assertAlmostEqual(max(entry.sim.get_map(engine.MAP_MOVE_RATE)), 4.0, places=5)
        slot.enabled = False
        self.assertIsNone(entry.sim.get_map(engine.MAP_MOVE_RATE))
        # Ticked before a group is picked: off until then, no error while running.
        other = obj.moldtex.maps.turn_rate
        other.enabled = True
        self.assertEqual(entry.maps_error, "")
        self.assertIsNone(entry.sim.get_map(engine.MAP_TURN_RATE))
        other.source = 'IMAGE'
        image = bpy.data.images.new("Turning", 8, 8)
        image.pixels.foreach_set([1.0] * (8 * 8 * 4))  # white: At 1 everywhere
        other.image = image
        self.assertAlmostEqual(min(entry.sim.get_map(engine.MAP_TURN_RATE)), 2.0, places=5)
        # A wrong name while running: the panel's error, the simulation runs on.
        other.source = 'ATTRIBUTE'
        other.attribute = "Nowhere"
        self.assertIn("'Nowhere' is neither a vertex group", entry.maps_error)
        self.assertIn("Moldtex ▸ Maps", entry.maps_error)
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        self.assertIn("Nowhere", labels(draw_all(self, obj)))  # the Maps panel shows it
        other.attribute = "Left"
        self.assertEqual(entry.maps_error, "")

    def test_undo_brings_back_the_maps_it_restores(self):
        engine = h.engine()
        obj = maps_plane()
        name = obj.name
        set_map(obj, "deposit_rate", "Right", at1=3.0)
        entry = h.run(obj, 2)
        bpy.ops.ed.undo_push(message="deposit x 3")
        obj.moldtex.maps.deposit_rate.at1 = 5.0
        obj.moldtex.maps.move_rate.enabled = True  # (no group yet: off)
        bpy.ops.ed.undo_push(message="deposit x 5")
        self.assertAlmostEqual(max(entry.sim.get_map(engine.MAP_DEPOSIT_RATE)), 5.0,
                               places=5)
        bpy.ops.ed.undo()
        obj = h.activate(bpy.data.objects[name])  # a new wrapper after undo
        self.assertEqual(obj.moldtex.maps.deposit_rate.at1, 3.0)
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        entry = h.live().get(name)
        # The step sent the restored map again (its settings differ from the last sent).
        self.assertAlmostEqual(max(entry.sim.get_map(engine.MAP_DEPOSIT_RATE)), 3.0,
                               places=5)

    def test_maps_are_for_the_continuous_model_only(self):
        engine = h.engine()
        obj = maps_plane()
        set_map(obj, "read_stimulus", "Right", strength=2.0)
        obj.moldtex.model = 'MOMAS'
        entry = h.run(obj, 2)
        self.assertIsNone(entry.sim.get_map(engine.MAP_READ_STIMULUS))


class MapErrorTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_bad_input_gives_a_sentence_not_a_traceback(self):
        live = h.live()
        obj = maps_plane()
        h.activate(obj)
        slot = set_map(obj, "deposit_rate", "Missing")
        message = operator_error(bpy.ops.moldtex.reset)
        self.assertIn("Deposit map: 'Missing' is neither a vertex group of 'Plane'", message)
        self.assertIn("'Right'", message)  # the groups it has
        self.assertNotIn("Traceback", message)
        slot.attribute = ""
        self.assertIn("names no vertex group or attribute",
                      operator_error(bpy.ops.moldtex.reset))
        slot.source = 'IMAGE'
        self.assertIn("has no image", operator_error(bpy.ops.moldtex.reset))
        missing = bpy.data.images.new("Gone", 4, 4)  # a file image whose file is gone
        missing.source = 'FILE'
        missing.filepath = os.path.join(tempfile.gettempdir(), "moldtex_no_such_map.png")
        missing.reload()
        self.assertEqual(tuple(missing.size), (0, 0))
        slot.image = missing
        self.assertIn("has no pixels", operator_error(bpy.ops.moldtex.reset))
        slot.enabled = False
        # An all-zero spawn map: agents could be reborn nowhere.
        empty = obj.vertex_groups.new(name="Nothing")
        self.assertIsNotNone(empty)
        set_map(obj, "spawn", "Nothing")
        message = operator_error(bpy.ops.moldtex.reset)
        self.assertIn("Spawn map (Spawn) is 0 everywhere", message)
        self.assertIn("raise At 0", message)
        obj.moldtex.maps.spawn.at0 = 0.25
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        self.assertIsNotNone(live.get(obj.name).sim)


class MapFileTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_maps_test_")

    def tearDown(self):
        h.clear_scene()
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_maps_survive_save_and_reload_and_apply_in_a_bake_and_the_cli(self):
        from moldtex.maps.spec import MAPS, MULTIPLIER
        obj = maps_plane()
        image = bpy.data.images.new("Map Image", 4, 4)
        image.use_fake_user = True
        expected = {}
        for index, spec in enumerate(MAPS):
            slot = getattr(obj.moldtex.maps, spec.key)
            self.assertFalse(slot.enabled)  # every map starts off
            values = {"source": 'IMAGE' if index % 3 == 2 else 'ATTRIBUTE',
                      "attribute": f"group {index}"}
            if spec.role == MULTIPLIER:
                values.update(at0=0.125 * index, at1=2.5 + index)
            else:
                values.update(strength=-1.5 * index)
            for name, value in values.items():
                setattr(slot, name, value)
            slot.image = image
            expected[spec.key] = values
        # The one map that applies: Deposit x 3 on the right.
        set_map(obj, "deposit_rate", "Right", at0=1.0, at1=3.0)
        expected["deposit_rate"].update(source='ATTRIBUTE', attribute="Right", at0=1.0,
                                        at1=3.0)
        path = os.path.join(self.folder, "maps.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        obj = bpy.data.objects["Plane"]
        for spec in MAPS:
            slot = getattr(obj.moldtex.maps, spec.key)
            self.assertEqual(slot.enabled, spec.key == "deposit_rate", spec.key)
            self.assertEqual(slot.image.name, "Map Image")
            for name, value in expected[spec.key].items():
                self.assertEqual(getattr(slot, name), value, f"{spec.key}.{name}")

        # A bake applies the map (it builds its simulation as Reset does).
        h.activate(obj)
        out = os.path.join(self.folder, "bake")
        h.bake_settings(obj, out, 1, 2, STEPS // 2, "EXR_FLOAT")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertIsNotNone(entry.sim.get_map(h.engine().MAP_DEPOSIT_RATE))
        pixels, size = h.load_pixels(os.path.join(out, "Plane_0002.exr"))
        self.assertEqual(size, (SIZE, SIZE))
        left, right = halves(pixels)
        self.assertTrue(2.6 < right / left < 3.6, (left, right))  # as the live test
        bpy.ops.wm.save_mainfile()

        # So does the command line (a fresh Blender, or `python cli.py` with bpy).
        from test_cli import TIMEOUT, cli_command
        cli_out = os.path.join(self.folder, "cli")
        log = os.path.join(self.folder, "cli.log")
        with open(log, "w") as stream:
            status = subprocess.call(
                cli_command(path, ["--object", "Plane", "--out", cli_out, "--frames", "1",
                                   "2", "--steps-per-frame", str(STEPS // 2), "--format",
                                   "exr-float"]),
                stdout=stream, stderr=subprocess.STDOUT, timeout=TIMEOUT)
        with open(log, encoding="utf-8", errors="replace") as stream:
            text = stream.read()
        self.assertEqual(status, 0, text)
        cli_pixels, _size = h.load_pixels(os.path.join(cli_out, "Plane_0002.exr"))
        # The same seed, settings and maps: the same frame as the bake here.
        self.assertEqual(cli_pixels[0::4].tobytes(), pixels[0::4].tobytes())

        # A map naming a group the file lacks: exit status 1 and a sentence.
        obj.moldtex.maps.deposit_rate.attribute = "Gone"
        bpy.ops.wm.save_mainfile()
        with open(log, "w") as stream:
            status = subprocess.call(
                cli_command(path, ["--object", "Plane", "--out", cli_out, "--frames", "1",
                                   "1"]),
                stdout=stream, stderr=subprocess.STDOUT, timeout=TIMEOUT)
        with open(log, encoding="utf-8", errors="replace") as stream:
            text = stream.read()
        self.assertEqual(status, 1, text)
        self.assertIn("'Gone' is neither a vertex group", text)
        self.assertNotIn("Traceback", text)


class MapPanelTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_maps_panel_draws_every_map_and_fits(self):
        from moldtex.ui import panels as ui
        from moldtex.maps.spec import MAPS as ALL_MAPS
        from moldtex.models import continuous
        MAPS = [spec for spec in ALL_MAPS if spec.key in continuous.MODEL.map_keys]  # (Gray-Scott's
        # feed and kill are drawn only for that model: test_reaction.py)
        obj = maps_plane()
        obj.moldtex.model = 'MOMAS'
        self.assertNotIn(("prop", "at0"), draw_all(self, obj))  # continuous only
        obj.moldtex.model = 'CONTINUOUS'
        log = draw_all(self, obj)
        self.assertEqual([name for kind, name in log if kind == "prop"].count("enabled"),
                         len(MAPS))
        self.assertIn("Tick a setting", labels(log))
        image = bpy.data.images.new("Map Image", 4, 4)
        for index, spec in enumerate(MAPS):
            slot = getattr(obj.moldtex.maps, spec.key)
            slot.source = 'IMAGE' if index % 2 else 'ATTRIBUTE'
            slot.image = image
            slot.attribute = "Right"
            slot.enabled = True
        log = []  # the Maps panel alone
        ui.MOLDTEX_PT_continuous_maps.draw(
            types.SimpleNamespace(layout=RecordingLayout(self, log)),
            types.SimpleNamespace(active_object=obj, scene=bpy.context.scene))
        shown = [name for kind, name in log if kind in ("prop", "prop_search")]
        multipliers = sum(spec.role == "MULTIPLIER" for spec in MAPS)
        self.assertEqual(shown.count("at0"), multipliers)
        self.assertEqual(shown.count("strength"), len(MAPS) - multipliers)
        self.assertEqual(shown.count("image"), len(MAPS) // 2)
        self.assertEqual(shown.count("attribute"), len(MAPS) - len(MAPS) // 2)
        self.assertEqual([name for kind, name in log if kind == "operator"],
                         ["moldtex.map_show"] * len(MAPS))  # Show, one per map
        self.assertLess(ui.CLASSES.index(continuous.MOLDTEX_PT_continuous_bias),
                        ui.CLASSES.index(ui.MOLDTEX_PT_continuous_maps))
        import panel_fit
        if not panel_fit.fonts_work():
            self.skipTest("blf has no font in background mode here (Blender 3.4): "
                          "gui_panel.py checks the fit under Xvfb")
        context = types.SimpleNamespace(active_object=obj, scene=bpy.context.scene)
        self.assertEqual(panel_fit.labels_cut(context), [])
        obj.moldtex.maps.spawn.attribute = ""  # the "pick one" note
        obj.moldtex.maps.spawn.source = 'ATTRIBUTE'
        self.assertEqual(panel_fit.labels_cut(context), [])

    def test_show_opens_weight_paint_on_the_group(self):
        obj = maps_plane()
        set_map(obj, "deposit_rate", "Left")
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.map_show(map="deposit_rate"), {'FINISHED'})
        self.assertEqual(obj.mode, 'WEIGHT_PAINT')
        self.assertEqual(obj.vertex_groups.active.name, "Left")
        bpy.ops.object.mode_set(mode='OBJECT')
        obj.moldtex.maps.deposit_rate.attribute = "Nope"
        self.assertIn("neither a vertex group",
                      operator_error(lambda: bpy.ops.moldtex.map_show(map="deposit_rate")))
        self.assertEqual(obj.mode, 'OBJECT')


class MapPresetTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_presets_leave_maps_alone(self):
        from moldtex.looks import presets
        obj = maps_plane()
        h.activate(obj)
        set_map(obj, "deposit_rate", "Right", at1=3.0)
        self.assertEqual(bpy.ops.moldtex.preset_apply(filepath=presets.find("branching_veins")),
                         {'FINISHED'})
        slot = obj.moldtex.maps.deposit_rate
        self.assertEqual((slot.enabled, slot.attribute, slot.at1), (True, "Right", 3.0))
        # A saved look is about the parameters, not this object's groups and images.
        self.assertNotIn("maps", presets.preset_text(obj, "mine"))
        for path in presets.available().values():  # the shipped looks set no maps
            with open(path, encoding="utf-8") as file:
                self.assertNotIn(".maps", file.read(), path)


if __name__ == "__main__":
    unittest.main()
