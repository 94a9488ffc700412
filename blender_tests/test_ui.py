"""The sidebar panels draw without errors in every state, and only reference
properties, operators and icons that exist (panels cannot be drawn in background
mode, so draw() runs against a recording layout)."""

import types
import unittest

import bpy

import helpers as h

ICONS = set(bpy.types.UILayout.bl_rna.functions["label"].parameters["icon"]
            .enum_items.keys())


class RecordingLayout:
    """Stands in for bpy.types.UILayout and checks what it is asked to show."""

    def __init__(self, test, log):
        self.test = test
        self.log = log
        self.use_property_split = False
        self.scale_y = 1.0
        self.enabled = True
        self.emboss = 'NORMAL'

    def _child(self, *args, **kwargs):
        return RecordingLayout(self.test, self.log)

    row = column = box = split = grid_flow = _child

    def _icon(self, kwargs):
        icon = kwargs.get("icon", "NONE")
        self.test.assertIn(icon, ICONS, f"unknown icon {icon}")

    def label(self, text="", icon="NONE", **kwargs):
        self._icon({"icon": icon})
        self.log.append(("label", text))

    def prop(self, data, name, **kwargs):
        self._icon(kwargs)
        self.test.assertIn(name, data.bl_rna.properties.keys(), f"no property {name}")
        self.log.append(("prop", name))

    def prop_search(self, data, name, search_data, search_name, **kwargs):
        self._icon(kwargs)
        self.test.assertIn(name, data.bl_rna.properties.keys())
        self.test.assertIn(search_name, search_data.bl_rna.properties.keys())
        self.log.append(("prop_search", name))

    def operator(self, idname, text="", **kwargs):
        self._icon(kwargs)
        category, name = idname.split(".")
        rna = getattr(getattr(bpy.ops, category), name).get_rna_type()  # raises if missing
        self.log.append(("operator", text or idname))
        return OperatorProps(self.test, rna, idname)

    def menu(self, idname, text="", **kwargs):
        self._icon(kwargs)
        self.test.assertTrue(hasattr(bpy.types, idname), f"no menu {idname}")
        self.log.append(("menu", idname))

    def separator(self, **kwargs):
        pass


class OperatorProps:
    """What layout.operator() returns: only the operator's properties may be set."""

    def __init__(self, test, rna, idname):
        object.__setattr__(self, "_test", test)
        object.__setattr__(self, "_names", set(rna.properties.keys()))
        object.__setattr__(self, "_idname", idname)

    def __setattr__(self, name, value):
        self._test.assertIn(name, self._names, f"{self._idname} has no property {name}")
        object.__setattr__(self, name, value)


def draw_all(test, obj):
    from moldtex import ui
    log = []
    context = types.SimpleNamespace(active_object=obj, scene=bpy.context.scene)
    for panel in ui.CLASSES:
        if hasattr(panel, "poll") and not panel.poll(context):
            continue
        panel.draw(types.SimpleNamespace(layout=RecordingLayout(test, log)), context)
    return log


def labels(log):
    # Joined by spaces: the panel wraps long messages over several labels.
    return " ".join(text for kind, text in log if kind == "label")


class PanelTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_no_object(self):
        log = draw_all(self, None)
        self.assertIn("Select a mesh object", labels(log))
        self.assertIn("Moldtex core", labels(log))

    def test_mesh_without_uvs(self):
        obj = h.mesh_object("NoUV", [(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 2)],
                            with_uvs=False)
        self.assertIn("No UV map", labels(draw_all(self, obj)))

    def test_species_and_start_settings_are_shown(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        obj.moldtex.species_count = 2
        obj.moldtex.seed_shape = 'STARBURST'
        log = draw_all(self, obj)
        shown = [name for kind, name in log if kind == "prop"]
        self.assertIn("seed_radius", shown)
        self.assertIn("seed_rays", shown)
        self.assertEqual(shown.count("color"), 2)  # one box per species
        self.assertEqual(shown.count("attraction"), 4)  # 2 species × 2 others
        self.assertIn("Centre: the surface point nearest the 3D cursor.",
                      labels(log))

    def test_idle_then_running_then_needs_reset(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        log = draw_all(self, obj)
        shown = {name for kind, name in log if kind == "prop"}
        self.assertEqual(shown, {"pattern_units", "pattern_scale", "time_step",
                                 "movement_speed", "turn_speed", "vision_distance",
                                 "vision_angle", "sensor_size", "evaporation_rate",
                                 "diffusion_rate",
                                 "deposit", "substeps", "resolution", "agent_count",
                                 "seed", "backend", "steps_per_update", "update_time",
                                 "thread_count",
                                 "image", "bake_use_scene_range", "bake_frame_start",
                                 "bake_frame_end", "bake_steps_per_frame",
                                 "bake_directory", "bake_format", "bake_prefix",
                                 "bake_resume", "species_count", "seed_shape",
                                 "fields_source", "fields_image", "food_collection",
                                 "hunger_rate", "food_radius",
                                 # the Brush panel (scene settings; obstacle target)
                                 "target", "erase", "radius", "strength", "falloff",
                                 "show_fields"})
        self.assertIn(("prop_search", "uv_map"), log)
        self.assertIn(("menu", "MOLDTEX_MT_presets"), log)
        buttons = [name for kind, name in log if kind == "operator"]
        self.assertEqual(buttons[0], "moldtex.preset_add")  # + and - beside the menu
        # Set Up Material, then Start (the order of the work).
        self.assertEqual(buttons[2], "moldtex.setup_material")
        self.assertEqual(buttons[3], "Start")
        self.assertIn("Bake Sequence", buttons)
        self.assertIn("moldtex.use_baked_sequence", buttons)
        # The bake panel names the files; an unsaved file cannot use the default
        # //moldtex_bake/ folder, which is said, not raised.
        if bpy.data.filepath:  # an earlier test saved the session's file
            self.assertIn("48 frames: Torus_0001.exr … Torus_0048.exr", labels(log))
        else:
            self.assertIn("has not been saved", labels(log))
        obj.moldtex.bake_directory = "/tmp/somewhere"
        obj.moldtex.bake_prefix = "rock 2"
        self.assertIn("48 frames: rock_2_0001.exr … rock_2_0048.exr",
                      labels(draw_all(self, obj)))
        self.assertIn("Not running yet", labels(log))

        h.run(obj, 3)
        h.live().get(obj.name).running = True  # as the modal Start sets it
        log = draw_all(self, obj)
        self.assertEqual([n for k, n in log if k == "operator"][3], "Pause")
        text = labels(log)
        self.assertIn("Coverage", text)
        self.assertIn("2,000", text)  # agents
        # The live loop's speed, in steps per second of wall time (live.note_update).
        h.live().get(obj.name).steps_per_second = 123.4
        self.assertIn("123 steps/s", labels(draw_all(self, obj)))
        h.live().get(obj.name).running = False

        obj.moldtex.seed += 1
        self.assertIn("press Reset", labels(draw_all(self, obj)))

    def test_brush_panel_follows_the_target(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        settings = bpy.context.scene.moldtex_brush
        settings.target = 'SLIME'
        obj.moldtex.species_count = 2
        shown = [name for kind, name in draw_all(self, obj) if kind == "prop"]
        self.assertIn("agents_per_dab", shown)
        self.assertIn("species", shown)
        self.assertIn("falloff", shown)  # erasing slime fades towards the rim
        settings.target = 'FOOD'
        shown = [name for kind, name in draw_all(self, obj) if kind == "prop"]
        self.assertNotIn("falloff", shown)  # an Empty is placed or removed whole
        self.assertIn("food_strength", shown)
        self.assertIn("food_amount", shown)
        # A stroke shows up on the Undo button.
        settings.target = 'OBSTACLE'
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.brush_stroke(stroke=[
            {"name": "", "location": (0.0, 0.0, 0.0), "direction": (0.0, 0.0, 0.0)}]),
            {'FINISHED'})
        buttons = [name for kind, name in draw_all(self, obj) if kind == "operator"]
        self.assertIn("Undo (1)", buttons)
        self.assertIn("Redo (0)", buttons)
        settings.target = 'OBSTACLE'

    def test_engine_load_error_is_shown(self):
        engine = h.engine()
        saved = engine._lib, engine.LOAD_ERROR
        try:
            engine._lib = None
            engine.LOAD_ERROR = "libmoldtex.so was not found next to the add-on"
            text = labels(draw_all(self, None))
        finally:
            engine._lib, engine.LOAD_ERROR = saved
        self.assertIn("Engine unavailable", text)
        self.assertIn("not found", text)


if __name__ == "__main__":
    unittest.main()


class LoaderTests(unittest.TestCase):
    def test_missing_library_is_reported_not_raised(self):
        import os
        engine = h.engine()
        h.clear_scene()
        obj = h.add_primitive("torus")
        h.configure(obj, agents=1000)
        os.environ["MOLDTEX_LIBRARY"] = "/nonexistent/libmoldtex.so"
        try:
            engine._load()
            self.assertFalse(engine.available())
            self.assertIn("/nonexistent/libmoldtex.so", engine.status_text())
            with self.assertRaises(RuntimeError) as caught:  # CANCELLED + report
                bpy.ops.moldtex.step()
            self.assertIn("does not exist", str(caught.exception))
            # Set Up Material needs no engine.
            self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        finally:
            del os.environ["MOLDTEX_LIBRARY"]
            engine._load()
        self.assertTrue(engine.available(), engine.status_text())
        self.assertEqual(bpy.ops.moldtex.step(), {'FINISHED'})
