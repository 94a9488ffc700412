"""Looks (presets): every shipped preset loads through the preset menu's execute path,
grows on a torus with the coverage its look needs, and sets the colour ramp; the menu
lists shipped and own presets; saving and removing an own preset works."""

import math
import os
import types
import unittest

import bpy

import helpers as h
from test_ui import RecordingLayout

RESOLUTION = "128"  # agents scale with it: the presets' 512² counts / 16
STEPS = 200
SHIPPED = ("marble", "wood_grain", "golden_web", "lava_rivers", "moss", "metal_scratches")

# Coverage (Eq. 1) after 200 steps on the torus at 128², measured over seeds 0..7
# (the test uses seed 7): golden_web 0.36-0.47, lava_rivers 0.52-0.62, marble
# 0.65-0.75, metal_scratches 0.49-0.53, moss 0.43-0.47, wood_grain 0.82-0.85. The bands
# add about 0.11 on either side; what each look needs: networks with dark cells between
# them (web and moss below half; lava's rivers broader); marble's soft, diffused veins
# cover more; wood's banded ramp needs pheromone almost everywhere (the highest);
# scratches are sparse lines that still reach across the surface (not empty, not full).
# At 128² a texel is 4 pattern units across (the presets are made for 512²), and the
# torus's outer texels are 3.5x wider than tall: there deposits are sampled
# (mtx_mark_sampled). lava_rivers read 0.36-0.43 before that, against 0.60-0.61 at its
# own 512² (seeds 0-2); it now reads 0.52-0.62 at 128², nearer its own look.
BANDS = {
    "golden_web": (0.25, 0.58),
    "lava_rivers": (0.41, 0.73),
    "marble": (0.54, 0.86),
    "metal_scratches": (0.38, 0.64),
    "moss": (0.32, 0.58),
    "wood_grain": (0.71, 0.96),
}
# wood_grain: 0.73 in texel units, 0.93-0.94 in surface units on this torus, whose texels
# are 1.6x taller than wide in 3D along the minor circle: texel units drew its trails
# 1.6x too thin there; on a plane (square texels) the two agree (0.85 / 0.89 at 256²).


def presets_module():
    from moldtex.looks import presets
    return presets


def execute_preset(path):
    # What clicking an entry of MOLDTEX_MT_presets runs.
    return bpy.ops.moldtex.preset_apply(filepath=path)


def ramp_of(obj):
    ramp = obj.active_material.node_tree.nodes["Moldtex Ramp"].color_ramp
    return [(round(e.position, 4), tuple(round(c, 4) for c in e.color))
            for e in ramp.elements], ramp.interpolation


class ShippedPresetTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_all_six_looks_are_shipped(self):
        available = presets_module().available()
        for name in SHIPPED:
            self.assertIn(name, available)
            self.assertEqual(os.path.dirname(available[name]),
                             presets_module().shipped_directory())

    def test_every_preset_grows_its_look_on_a_torus(self):
        presets = presets_module()
        results = {}
        for name in SHIPPED:
            h.clear_scene()
            obj = h.add_primitive("torus")
            h.configure(obj, resolution=RESOLUTION, agents=1, seed=7)
            self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
            before = ramp_of(obj)
            self.assertEqual(execute_preset(presets.find(name)), {'FINISHED'})
            self.assertEqual(presets.menu_label(obj), bpy.path.display_name(name))
            settings = obj.moldtex
            self.assertGreater(settings.agent_count, 100, name)  # scaled from 512²
            self.assertNotEqual(ramp_of(obj), before, f"{name} kept the default ramp")
            stops, _ = ramp_of(obj)
            self.assertGreaterEqual(len(stops), 4, name)
            h.run(obj, STEPS)
            coverage = h.live().get(obj.name).stats["coverage"]
            results[name] = coverage
            low, high = BANDS[name]
            self.assertGreater(coverage, low, f"{name}: too little pheromone")
            self.assertLess(coverage, high, f"{name}: too much pheromone")
        print("  preset coverage:", ", ".join(f"{k} {v:.3f}" for k, v in results.items()))

    def test_agent_count_follows_the_pattern_unit(self):
        # marble counts 60 000 agents on 512 x 512 pattern units. Units: Surface fixes the
        # pattern unit on the model, so the count must not change with the resolution
        # (4x agents at 1024² grew a denser network: presets.agents_per_preset_agent) but
        # with the unit's size; Units: Texels keeps MoMaS' agents per texel.
        obj = h.add_primitive("torus")
        settings = obj.moldtex
        marble = presets_module().find("marble")

        def applied(**values):
            for name, value in values.items():
                setattr(settings, name, value)
            self.assertEqual(execute_preset(marble), {'FINISHED'})
            return settings.agent_count

        for resolution in ("128", "512", "1024"):
            self.assertEqual(applied(pattern_units='SURFACE', resolution=resolution), 60000)
        self.assertEqual(applied(pattern_scale=2.0), 15000)  # cells twice as long
        self.assertEqual(applied(pattern_scale=0.5), 240000)
        # Scale: Length at the unit Scale: Object 1 gives (√area / 512): the same count.
        from moldtex.sim import session as live
        area = h.units().surface_area(obj)
        self.assertGreater(area, 0.0)
        count = applied(pattern_scale=1.0, pattern_scale_mode='LENGTH',
                        pattern_length=math.sqrt(area) / 512)
        self.assertAlmostEqual(count / 60000, 1.0, delta=1e-3)
        self.assertEqual(applied(pattern_length=2 * math.sqrt(area) / 512), 15000)
        settings.pattern_scale_mode = 'OBJECT'
        for resolution, expected in (("128", 3750), ("512", 60000), ("1024", 240000)):
            self.assertEqual(applied(pattern_units='TEXELS', resolution=resolution), expected)
        # A saved look stores the count it was made with in the same units: applied again
        # at another resolution (texel units), it gives that resolution's count.
        settings.agent_count = 100000  # at 1024²: 25 000 on 512² texels
        text = presets_module().preset_text(obj)
        self.assertIn("s.agent_count = s.scaled_agent_count(25000)", text)

    def test_preset_before_the_material_still_sets_the_ramp(self):
        obj = h.add_primitive("torus")
        h.configure(obj, resolution=RESOLUTION, agents=1000)
        self.assertEqual(execute_preset(presets_module().find("lava_rivers")), {'FINISHED'})
        self.assertIsNone(obj.active_material)  # nothing to change yet: remembered
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        from moldtex.colour import material
        remembered, interpolation = material.preset_ramp(obj)
        self.assertEqual(len(remembered), 6)  # lava_rivers.py has six stops
        self.assertEqual(ramp_of(obj), ([(round(p, 4), tuple(round(c, 4) for c in color))
                                         for p, color in remembered], interpolation))

    def test_broken_preset_is_reported(self):
        path = os.path.join(bpy.app.tempdir or "/tmp", "moldtex_broken_preset.py")
        with open(path, "w") as file:
            file.write("import bpy\nbpy.context.object.moldtex.movement_speed = 'fast'\n")
        h.add_primitive("torus")
        try:
            with self.assertRaises(RuntimeError) as caught:
                execute_preset(path)
            self.assertIn("Failed to execute the preset", str(caught.exception))
        finally:
            os.remove(path)


class PresetMenuTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_menu_label_belongs_to_each_object(self):
        # A sphere that never had a preset does not show the torus's look.
        presets = presets_module()
        torus = h.add_primitive("torus")
        self.assertEqual(execute_preset(presets.find("marble")), {'FINISHED'})
        sphere = h.add_primitive("sphere")
        from test_ui import draw_all

        def menu_text(obj):
            return next(text for kind, text in draw_all(self, obj) if kind == "menu_text")
        self.assertEqual(menu_text(torus), "Marble")
        self.assertEqual(menu_text(sphere), "Presets")
        h.activate(sphere)
        self.assertEqual(execute_preset(presets.find("moss")), {'FINISHED'})
        self.assertEqual((menu_text(torus), menu_text(sphere)), ("Marble", "Moss"))
        # Saved with the file, per object.
        self.assertEqual(torus.moldtex.preset_name, "Marble")

    def test_each_entry_has_its_own_tooltip(self):
        presets = presets_module()
        operator = bpy.types.MOLDTEX_OT_preset_apply
        tips = {}
        for name in SHIPPED:
            props = types.SimpleNamespace(filepath=presets.find(name))
            tips[name] = operator.description(bpy.context, props)
        self.assertEqual(len(set(tips.values())), len(SHIPPED), tips)
        self.assertIn("veins", tips["marble"])
        self.assertIn("scratches", tips["metal_scratches"])
        for name, tip in tips.items():
            self.assertNotIn("Apply this look", tip, name)  # not the generic text

    def draw_menu(self):
        log = []
        menu = bpy.types.MOLDTEX_MT_presets
        fake = types.SimpleNamespace(layout=RecordingLayout(self, log),
                                     bl_idname=menu.bl_idname,
                                     preset_operator=menu.preset_operator,
                                     preset_add_operator=menu.preset_add_operator)
        fake.path_menu = types.MethodType(bpy.types.Menu.path_menu, fake)
        menu.draw(fake, bpy.context)
        return [text for kind, text in log if kind == "operator"]

    def test_menu_lists_shipped_and_own_presets_and_saves_removes(self):
        obj = h.add_primitive("torus")
        h.configure(obj, resolution=RESOLUTION, agents=2000, turn_speed=27.5)
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        entries = self.draw_menu()
        for label in ("Marble", "Wood Grain", "Golden Web", "Lava Rivers", "Moss",
                      "Metal Scratches"):
            self.assertIn(label, entries)
        self.assertIn("moldtex.preset_add", entries)  # the name field's add button

        # Save an own preset (into Blender's user presets folder), then remove it.
        name = "Moldtex Test Look 1234"
        user_root = bpy.utils.user_resource('SCRIPTS', path=os.path.join("presets",
                                                                        "moldtex"))
        # Leave the user's folders as they were: remove what saving created.
        created = []
        folder = user_root
        while not os.path.isdir(folder):
            created.append(folder)
            folder = os.path.dirname(folder)
        path = os.path.join(user_root, "Moldtex_Test_Look_1234.py")
        try:
            self.assertEqual(bpy.ops.moldtex.preset_add(name=name), {'FINISHED'})
            self.assertTrue(os.path.isfile(path), path)
            with open(path, encoding="utf-8") as file:
                text = file.read()
            self.assertIn("s.turn_speed = 27.5", text)
            self.assertIn("s.agent_count = s.scaled_agent_count(32000)", text)  # 2000 at 128²
            self.assertIn("s.apply_ramp([", text)
            self.assertIn("Moldtex Test Look 1234", self.draw_menu())
            self.assertEqual(obj.moldtex.preset_name, "Moldtex Test Look 1234")
            tip = bpy.types.MOLDTEX_OT_preset_apply.description(
                bpy.context, types.SimpleNamespace(filepath=path))
            self.assertIn("Moldtex Test Look 1234", tip)  # an own preset's tooltip
            obj.moldtex.turn_speed = 11.0
            self.assertEqual(execute_preset(path), {'FINISHED'})
            self.assertAlmostEqual(obj.moldtex.turn_speed, 27.5)
            # The - button removes the active object's own look.
            self.assertEqual(bpy.ops.moldtex.preset_add(remove_active=True), {'FINISHED'})
            self.assertFalse(os.path.exists(path))
            self.assertEqual(obj.moldtex.preset_name, "")
            self.assertEqual(bpy.ops.moldtex.preset_add(name=name), {'FINISHED'})
            self.assertEqual(bpy.ops.moldtex.preset_add(name=name, remove_name=True),
                             {'FINISHED'})
            self.assertFalse(os.path.exists(path))
        finally:
            if os.path.exists(path):
                os.remove(path)
            for folder in created:  # deepest first
                if os.path.isdir(folder) and not os.listdir(folder):
                    os.rmdir(folder)


if __name__ == "__main__":
    unittest.main()
