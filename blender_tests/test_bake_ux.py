"""What the Bake panel tells an artist: a short default range (not the scene's 250
frames), that a bake starts from step 0, elapsed time and an estimate while it runs,
and live stats that follow the bake instead of reading "Steps 0"."""

import shutil
import tempfile
import time
import types
import unittest

import bpy

import helpers as h
from test_ui import draw_all, labels


class BakeDefaultsTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_default_range_is_two_seconds_not_the_scene(self):
        from moldtex.bake import sequence as bake
        obj = h.plane()
        scene = bpy.context.scene
        scene.frame_start, scene.frame_end = 1, 250
        plan = bake.plan_for(obj, scene) if bpy.data.filepath else None
        settings = obj.moldtex
        self.assertFalse(settings.bake_use_scene_range)
        self.assertEqual((settings.bake_frame_start, settings.bake_frame_end), (1, 48))
        if plan is not None:
            self.assertEqual(plan.frame_count, 48)
        settings.bake_use_scene_range = True  # still there for those who want it
        self.assertEqual(bake.frame_range(obj, scene), (1, 250))

    def test_panel_says_a_bake_starts_from_step_zero(self):
        obj = h.plane()
        obj.moldtex.bake_directory = "/tmp/somewhere"
        self.assertIn("Bakes from step 0", labels(draw_all(self, obj)))


class TimingTextTests(unittest.TestCase):
    def test_elapsed_and_estimate(self):
        from moldtex.bake import sequence as bake
        entry = types.SimpleNamespace(
            bake_started=100.0, bake_resumed_frames=0,
            bake_progress={"first_frame": 1, "last_frame": 48, "frames_done": 5})
        # 5 frames in 10 s: 43 frames left take about 86 s.
        self.assertEqual(bake.timing_text(entry, now=110.0),
                         "0:10 elapsed, about 1:26 left")
        # A resumed bake: only the frames this run baked tell its speed.
        entry.bake_resumed_frames = 3
        entry.bake_progress["frames_done"] = 5  # 2 baked in 10 s, 43 left: 215 s
        self.assertEqual(bake.timing_text(entry, now=110.0),
                         "0:10 elapsed, about 3:35 left")
        entry.bake_progress["frames_done"] = 3  # none baked yet: no estimate
        self.assertEqual(bake.timing_text(entry, now=4000.0), "1:05:00 elapsed")
        entry.bake_started = None
        self.assertEqual(bake.timing_text(entry), "")


class BakingPanelTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_test_bake_ux_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_stats_follow_the_bake(self):
        from moldtex.bake import sequence as bake
        obj = h.plane(resolution="128", agents=2000)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})
        self.assertEqual(bpy.ops.moldtex.step(steps=40), {'FINISHED'})
        h.bake_settings(obj, self.folder, 1, 400, 10)
        plan = bake.plan_for(obj, bpy.context.scene)
        job = bake.BakeJob(obj, bpy.context.evaluated_depsgraph_get(), plan)
        try:
            began = time.perf_counter()
            while job.poll()["frames_done"] < 3 and time.perf_counter() - began < 60:
                time.sleep(0.02)
            text = labels(draw_all(self, obj))
            progress = job.progress
            steps = progress["step_count"]
            self.assertGreaterEqual(steps, 30)
            # The main panel's Steps is the bake's, not the stats cached before it
            # (which read 0: the bake restarted the simulation).
            self.assertIn(f"{steps:,} (bake)", text)
            self.assertIn("elapsed", text)
            self.assertIn("left", text)
        finally:
            job.cancel()
            job.finish()
        entry = h.live().get(obj.name)
        # A cancel stops after the current step, possibly part-way through a frame.
        self.assertEqual(entry.stats["step_count"], entry.sim.get_stats()["step_count"],
                         "after the bake the stats are the simulation's")
        self.assertGreaterEqual(entry.stats["step_count"], job.progress["step_count"])


if __name__ == "__main__":
    unittest.main()
