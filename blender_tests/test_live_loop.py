"""The live loop's pacing (a time per update, not a count), the defaults that show a
network within seconds, Step's count and its rerun from Adjust Last Operation, and Start
setting up the material. Timings are not asserted (they go to docs/PERFORMANCE.md):
only what the pacing does with the times it measures."""

import array
import unittest

import bpy

import helpers as h


class PacingTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.obj = h.plane(resolution="128", agents=3000)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        self.entry = h.live().get(self.obj.name)

    def test_step_for_time_runs_whole_steps_within_its_limits(self):
        live = h.live()
        before = self.entry.stats["step_count"]
        done = live.step_for_time(self.entry, self.obj, 0.0)
        self.assertEqual(done, 1, "at least one step, even with no time")
        done = live.step_for_time(self.entry, self.obj, 0.0, min_steps=5)
        self.assertEqual(done, 5)
        done = live.step_for_time(self.entry, self.obj, 60.0, max_steps=7)
        self.assertEqual(done, 7, "never more than max_steps, however much time")
        self.assertEqual(self.entry.stats["step_count"], before + 13,
                         "the cached stats count every step run")
        self.assertGreater(self.entry.step_seconds, 0.0, "a step's time was measured")
        # A time budget gives many steps of this tiny simulation (a step takes well
        # under a millisecond here, so 0.05 s holds far more than one).
        done = live.step_for_time(self.entry, self.obj, 0.05)
        self.assertGreater(done, 1)

    def test_a_thread_grows_it_between_updates_and_yields_to_any_other_use(self):
        live = h.live()
        engine = h.engine()
        settings = self.obj.moldtex
        self.assertEqual(settings.steps_per_update, 0, "time-paced by default")
        before = self.entry.stats["step_count"]
        live.start_stepper(self.entry, settings.update_time / 1000.0)
        import time
        began = time.perf_counter()

        def grown():
            return self.entry._stepper.sim.run_progress()["steps"]
        while grown() == 0 and time.perf_counter() - began < 30:
            time.sleep(0.01)
        self.assertGreater(grown(), 0, "the core stepped while Python slept")
        # The core's thread steps it: the core refuses any other call meanwhile, so it
        # never runs two calls on one simulation at once.
        with self.assertRaises(engine.EngineError) as raised:
            self.entry._sim.get_stats()
        self.assertEqual(raised.exception.status, engine.ERROR_BUSY)
        # Any use of entry.sim first stops the stepping; the count stays put afterwards
        # and the cached stats are the simulation's.
        steps = self.entry.sim.get_stats()["step_count"]
        self.assertGreater(steps, before)
        self.assertIsNone(self.entry._stepper)
        self.assertFalse(live.stepper_waiting(self.entry))
        self.assertEqual(live.stop_stepper(self.entry), 0, "already stopped")
        time.sleep(0.05)
        self.assertEqual(self.entry.sim.get_stats()["step_count"], steps)
        self.assertEqual(self.entry.stats["step_count"], steps)
        # Stopping it returns the steps it ran; a new one starts from there.
        live.start_stepper(self.entry, 0.01)
        while grown() == 0:
            time.sleep(0.005)
        time.sleep(0.05)
        ran = live.stop_stepper(self.entry)
        self.assertGreater(ran, 0)
        self.assertEqual(self.entry.sim.get_stats()["step_count"], steps + ran)
        self.assertEqual(self.entry.stats["step_count"], steps + ran)

    def test_stepping_thread_stops_when_the_simulation_goes(self):
        live = h.live()
        live.start_stepper(self.entry, 0.01)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})  # a new simulation
        self.assertIsNone(self.entry._stepper)
        self.assertEqual(self.entry.stats["step_count"], 0)
        live.start_stepper(self.entry, 0.01)
        live.free(self.obj.name)
        self.assertIsNone(self.entry._stepper)

    def test_steps_per_second_is_steps_over_wall_time(self):
        live = h.live()
        live.stop_pacing(self.entry)
        live.note_update(self.entry, 10, 100.0, 100.2)  # first update: no rate yet
        self.assertEqual(self.entry.steps_per_second, 0.0)
        # Next update begins 0.05 s after the last stepping ended and steps 20 steps
        # until 0.25 s after it: 20 steps in 0.25 s of wall time = 80 steps/s.
        live.note_update(self.entry, 20, 100.25, 100.45)
        self.assertAlmostEqual(self.entry.steps_per_second, 80.0, places=6)
        self.assertAlmostEqual(self.entry.update_overhead, 0.05, places=6)
        live.stop_pacing(self.entry)
        self.assertEqual(self.entry.steps_per_second, 0.0, "a pause is not slowness")


class DefaultsTests(unittest.TestCase):
    def test_defaults_are_sized_for_a_pattern_within_seconds(self):
        # docs/PERFORMANCE.md, "The first seconds": 512² with 60 000 agents (the
        # marble preset's density) shows a network on Suzanne within 10 s on 2 cores,
        # where 1024² with 200 000 agents needed about a minute.
        h.clear_scene()
        obj = h.add_primitive("monkey")
        settings = obj.moldtex
        self.assertEqual(settings.resolution, "512")
        self.assertEqual(settings.agent_count, 60000)
        self.assertEqual(settings.steps_per_update, 0)


class StepTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.obj = h.plane(resolution="128", agents=3000)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        self.entry = h.live().get(self.obj.name)

    def test_step_count_is_an_operator_property_shown_for_adjusting(self):
        properties = bpy.ops.moldtex.step.get_rna_type().properties
        self.assertIn("steps", properties.keys())
        # Adjust Last Operation shows operators that are both REGISTER and UNDO.
        from moldtex.operators import simulation as operators
        self.assertLessEqual({'REGISTER', 'UNDO'}, operators.MOLDTEX_OT_step.bl_options)
        self.assertEqual(bpy.ops.moldtex.step(steps=12), {'FINISHED'})
        self.assertEqual(self.entry.stats["step_count"], 12)

    def test_rerun_with_another_count_starts_where_the_step_started(self):
        # What Adjust Last Operation does: the last Step runs again with a new count,
        # from the state before it (not on top of it).
        live = h.live()
        self.assertEqual(bpy.ops.moldtex.step(steps=5), {'FINISHED'})
        before = h.image_pixels(self.obj)
        self.assertEqual(bpy.ops.moldtex.step(steps=30), {'FINISHED'})
        self.assertEqual(self.entry.stats["step_count"], 35)
        self.assertTrue(live.restore_step_snapshot(self.entry))
        self.assertEqual(self.entry.stats["step_count"], 5)
        self.entry.sim.read_rgba(self.entry.pixels)
        self.assertEqual(array.array("f", self.entry.pixels), before,
                         "the state before the Step, exactly")
        # Once something else ran, the snapshot is not the state before "the last
        # Step" any more: it is not used.
        self.assertEqual(bpy.ops.moldtex.step(steps=3), {'FINISHED'})
        live.step(self.entry, self.obj, 1)
        self.assertFalse(live.restore_step_snapshot(self.entry))
        self.assertEqual(self.entry.stats["step_count"], 9)


class StartSetsUpMaterialTests(unittest.TestCase):
    def test_start_sets_up_the_material_when_there_is_none(self):
        # Start needs the interface (gui_viewport.py presses it); the part that sets up
        # the material is this function, which Start calls before showing the image.
        from moldtex.colour import material
        from moldtex.operators import simulation as operators
        h.clear_scene()
        obj = h.plane(resolution="128", agents=3000)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        entry = h.live().get(obj.name)
        self.assertIsNone(material.moldtex_node(obj, material.TEXTURE_NODE))
        note = operators.ensure_material(obj, entry)
        self.assertIn("Material Preview", note)
        node = material.moldtex_node(obj, material.TEXTURE_NODE)
        self.assertIsNotNone(node)
        self.assertIs(node.image, obj.moldtex.image)
        self.assertEqual(operators.ensure_material(obj, entry), "", "only once")


if __name__ == "__main__":
    unittest.main()
