"""Baking image sequences through moldtex.bake: the files, their pixels, the metrics,
cancel + resume, playback in the material (and in a Cycles render), and the live
simulation while a bake runs."""

import os
import shutil
import tempfile
import time
import unittest

import bpy

import helpers as h

SPF = 3  # steps per frame of the small bakes


def bake_module():
    from moldtex.bake import sequence as bake
    return bake


def frame_names(prefix, first, last, extension=".exr"):
    return [f"{prefix}{frame:04d}{extension}" for frame in range(first, last + 1)]


class BakeTestCase(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_bake_test_")

    def tearDown(self):
        h.clear_scene()  # frees live simulations and any bake still running
        shutil.rmtree(self.folder, ignore_errors=True)

    def sub(self, name):
        path = os.path.join(self.folder, name)
        os.makedirs(path, exist_ok=True)
        return path


class BakeFileTests(BakeTestCase):
    def test_ten_frames_equal_the_live_texture_at_those_frames(self):
        obj = h.plane()
        out = self.sub("float")
        h.bake_settings(obj, out, 1, 10, SPF, "EXR_FLOAT")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        # Exactly the frames, the metrics and the checkpoint: no .partial left over.
        self.assertEqual(sorted(os.listdir(out)),
                         frame_names("Plane_", 1, 10) + ["Plane_checkpoint.bin",
                                                         "Plane_metrics.csv"])
        # Frame f is the state after f * SPF steps of a fresh simulation with the same
        # seed: a float EXR holds the pheromone exactly (R = G = B = the "Y" channel).
        sim = h.fresh_sim(obj)
        try:
            for frame in range(1, 11):
                sim.step(SPF)
                expected = sim.read_rgba()
                pixels, size = h.load_pixels(os.path.join(out, f"Plane_{frame:04d}.exr"))
                self.assertEqual(size, (128, 128), frame)
                self.assertEqual(pixels[0::4].tobytes(), expected[0::4].tobytes(),
                                 f"frame {frame}: float EXR differs from the live texture")
                self.assertEqual(pixels[1::4].tobytes(), expected[0::4].tobytes())
        finally:
            sim.release()

        # Half floats keep 11 significant bits: within 1/2048 for values in [0, 1].
        half = self.sub("half")
        h.bake_settings(obj, half, 1, 3, SPF, "EXR_HALF", prefix="half_")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        sim = h.fresh_sim(obj)
        try:
            for frame in range(1, 4):
                sim.step(SPF)
                expected = sim.read_rgba()[0::4]
                pixels, size = h.load_pixels(os.path.join(half, f"half_{frame:04d}.exr"))
                self.assertEqual(size, (128, 128))
                worst = max(abs(a - b) for a, b in zip(pixels[0::4], expected))
                self.assertLessEqual(worst, 1.0 / 2048, f"half frame {frame}")
        finally:
            sim.release()

    def test_metrics_csv_has_one_row_per_frame_matching_its_pixels(self):
        obj = h.plane()
        out = self.sub("csv")
        h.bake_settings(obj, out, 4, 13, SPF, "EXR_FLOAT")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        with open(os.path.join(out, "Plane_metrics.csv"), encoding="utf-8") as file:
            self.assertEqual(file.readline().strip(), "frame,step,coverage,presence")
        rows = bake_module().read_metrics(os.path.join(out, "Plane_metrics.csv"))
        self.assertEqual([row["frame"] for row in rows], list(range(4, 14)))
        self.assertEqual([row["step"] for row in rows], [SPF * i for i in range(1, 11)])
        # On the plane every texel is inside the one island and covers the same 3D area,
        # so coverage (Eq. 1, area-weighted mean over the islands) is the plain mean of
        # the frame's texels; 1e-4 allows float-vs-double summation, nothing more.
        self.assertEqual(set(h.live().get(obj.name).sim.read_texel_classes()), {1})
        for row in rows:
            pixels, _ = h.load_pixels(os.path.join(out, f"Plane_{row['frame']:04d}.exr"))
            values = pixels[0::4]
            mean = sum(values) / len(values)
            self.assertAlmostEqual(row["coverage"], mean, delta=1e-4, msg=row)
            presence = sum(1 for v in values if v > 0) / len(values)
            self.assertAlmostEqual(row["presence"], presence, delta=1e-4, msg=row)
        self.assertGreater(rows[-1]["coverage"], 0.05)  # something grew

    def test_cancelled_bake_keeps_whole_frames_and_resume_is_bit_identical(self):
        # 20 steps a frame (about 15 ms here) so the cancel lands mid-sequence.
        obj = h.plane()
        full = self.sub("full")
        h.bake_settings(obj, full, 1, 12, 20, "EXR_HALF")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        reference = h.comparable_bytes(full)
        self.assertEqual(len(reference), 14)

        # The same simulation as the operator builds, baked through the engine and
        # cancelled once three frames are on disk (polled, no Python threads).
        engine = h.engine()
        cut = self.sub("cut")
        entry = h.live().ensure(obj, bpy.context.evaluated_depsgraph_get(), rebuild=True)
        job = engine.Bake(entry.sim, cut, 1, 12, 20, engine.IMAGE_EXR_HALF, "Plane_")
        deadline = time.monotonic() + 60.0
        while True:
            progress = job.progress()
            if progress["frames_done"] >= 3 or progress["state"] != engine.BAKE_RUNNING:
                break
            self.assertLess(time.monotonic(), deadline, "no frame in 60 s")
            time.sleep(0.001)
        job.cancel()
        job.wait()
        progress = job.progress()
        job.release()
        self.assertEqual(progress["state"], engine.BAKE_CANCELLED, progress)
        done = progress["frames_done"]
        self.assertGreaterEqual(done, 3)
        self.assertLess(done, 12, "finished before the cancel: make frames slower")
        self.assertEqual(progress["last_frame_written"], done)
        # Only whole frames, each loadable, plus the metrics and the checkpoint.
        self.assertEqual(sorted(os.listdir(cut)), frame_names("Plane_", 1, done) +
                         ["Plane_checkpoint.bin", "Plane_metrics.csv"])
        for name in frame_names("Plane_", 1, done):
            pixels, size = h.load_pixels(os.path.join(cut, name))
            self.assertEqual(size, (128, 128), name)
            self.assertEqual(len(pixels), 4 * 128 * 128)
            self.assertEqual(h.comparable_bytes(cut)[name], reference[name], name)
        self.assertEqual(len(bake_module().read_metrics(os.path.join(cut,
                                                                     "Plane_metrics.csv"))),
                         done)

        # Resume through the operator: the rest of the sequence, byte for byte.
        h.bake_settings(obj, cut, 1, 12, 20, "EXR_HALF", resume=True)
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        self.assertEqual(h.comparable_bytes(cut), reference)

    def test_png_formats_and_prefix(self):
        obj = h.plane(resolution="128", agents=800)
        out = self.sub("png")
        for image_format, extension, depth in (("PNG8", ".png", 8), ("PNG16", ".png", 16)):
            h.bake_settings(obj, out, 7, 8, SPF, image_format, prefix=f"rock {depth}/")
            self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
            # Unsafe characters become "_"; a prefix ending in a digit gets a "_" so the
            # frame number stays the last digits of the name.
            for name in frame_names(f"rock_{depth}_", 7, 8, extension):
                pixels, size = h.load_pixels(os.path.join(out, name))
                self.assertEqual(size, (128, 128))
        sim = h.fresh_sim(obj)
        try:
            sim.step(2 * SPF)
            expected = sim.read_rgba()[0::4]
        finally:
            sim.release()
        pixels, _ = h.load_pixels(os.path.join(out, "rock_16_0008.png"))
        worst = max(abs(a - b) for a, b in zip(pixels[0::4], expected))
        self.assertLessEqual(worst, 0.5 / 65535 + 1e-6)  # 16-bit rounding
        pixels, _ = h.load_pixels(os.path.join(out, "rock_8_0008.png"))
        worst = max(abs(a - b) for a, b in zip(pixels[0::4], expected))
        self.assertLessEqual(worst, 0.5 / 255 + 1e-6)  # 8-bit rounding


class BakeErrorTests(BakeTestCase):
    def call_bake(self):
        try:
            return bpy.ops.moldtex.bake(), ""
        except RuntimeError as error:
            return {'CANCELLED'}, str(error)

    def test_unsaved_file_with_relative_folder(self):
        obj = h.plane(resolution="128", agents=500)
        self.assertEqual(obj.moldtex.bake_directory, "//moldtex_bake/")  # the default
        result, message = self.call_bake()
        self.assertEqual(result, {'CANCELLED'})
        self.assertIn("has not been saved", message)

    def test_start_after_end_and_missing_object(self):
        obj = h.plane(resolution="128", agents=500)
        h.bake_settings(obj, self.folder, 9, 3, SPF)
        result, message = self.call_bake()
        self.assertIn("start frame 9 is after the end frame 3", message)
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.moldtex.bake(object_name="NoSuchObject")
        self.assertIn("no object named 'NoSuchObject'", str(caught.exception))

    def test_unwritable_folder(self):
        obj = h.plane(resolution="128", agents=500)
        h.bake_settings(obj, "/proc/moldtex_cannot_be_here", 1, 2, SPF)
        result, message = self.call_bake()
        self.assertEqual(result, {'CANCELLED'})
        self.assertIn("/proc/moldtex_cannot_be_here", message)

    def test_resume_with_other_steps_per_frame_is_refused(self):
        obj = h.plane(resolution="128", agents=500)
        h.bake_settings(obj, self.folder, 1, 3, SPF)
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        h.bake_settings(obj, self.folder, 1, 5, SPF + 1, resume=True)
        result, message = self.call_bake()
        self.assertEqual(result, {'CANCELLED'})
        self.assertIn("another frame range or steps per frame", message)
        # Blender keeps working and the object bakes again without resume.
        h.bake_settings(obj, self.folder, 1, 5, SPF + 1)
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})


class BusyTests(BakeTestCase):
    def test_live_simulation_waits_while_a_bake_runs(self):
        obj = h.plane(resolution="128", agents=3000)
        h.bake_settings(obj, self.folder, 1, 200, 20)  # long: cancelled below
        bake = bake_module()
        job = bake.BakeJob(obj, bpy.context.evaluated_depsgraph_get(),
                           bake.plan_for(obj, bpy.context.scene))
        try:
            entry = h.live().get(obj.name)
            self.assertTrue(entry.baking)
            # Start says why it cannot run (before it would complain about background
            # mode); Step and Reset are refused with the same words, not a crash.
            self.assertIn("Cannot start: a bake is running on 'Plane'",
                          self._start_message())
            for name in ("step", "reset"):
                with self.assertRaises(RuntimeError, msg=name) as caught:
                    getattr(bpy.ops.moldtex, name)()
                self.assertIn("bake is running on 'Plane'", str(caught.exception), name)
            with self.assertRaises(RuntimeError) as caught:
                bpy.ops.moldtex.bake()
            self.assertIn("bake is running", str(caught.exception))
            obj.moldtex.turn_speed = 33.0  # no push while baking (the core is busy)
            self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
            job.cancel()
            progress = job.finish()
        finally:
            if not job.finished:
                job.cancel()
                job.finish()
        self.assertEqual(progress["state"], h.engine().BAKE_CANCELLED)
        self.assertFalse(entry.baking)
        self.assertIn("cancelled", entry.bake_summary)
        # Free again: the live simulation steps on.
        self.assertEqual(bpy.ops.moldtex.step(steps=2), {'FINISHED'})

    def _start_message(self):
        try:
            bpy.ops.moldtex.start()
        except RuntimeError as error:
            return str(error)
        return ""


class PlaybackTests(BakeTestCase):
    FIRST, LAST = 5, 8

    def test_material_plays_the_sequence_frame_by_frame(self):
        obj = h.plane()
        blend = os.path.join(self.folder, "playback.blend")
        bpy.ops.wm.save_as_mainfile(filepath=blend)
        obj = bpy.data.objects["Plane"]
        h.activate(obj)
        h.bake_settings(obj, "//seq/", self.FIRST, self.LAST, SPF, "EXR_FLOAT")
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})

        node = obj.active_material.node_tree.nodes["Moldtex Texture"]
        image = node.image
        self.assertEqual(image.name, "Moldtex Plane baked")
        self.assertEqual(image.source, 'SEQUENCE')
        self.assertEqual(image.colorspace_settings.name, 'Non-Color')
        self.assertEqual(image.filepath, "//seq/Plane_0005.exr")  # relative: portable
        user = node.image_user
        self.assertEqual((user.frame_start, user.frame_offset, user.frame_duration),
                         (self.FIRST, self.FIRST - 1, self.LAST - self.FIRST + 1))
        self.assertTrue(user.use_auto_refresh)

        # The depsgraph evaluates the image user of the evaluated material (what
        # renders use): at scene frame f it resolves to file f; after the last frame
        # it holds the last one.
        scene = bpy.context.scene
        for frame in range(self.FIRST, self.LAST + 2):
            scene.frame_set(frame)
            evaluated = obj.active_material.evaluated_get(
                bpy.context.evaluated_depsgraph_get())
            evaluated_user = evaluated.node_tree.nodes["Moldtex Texture"].image_user
            expected = min(frame, self.LAST)
            self.assertEqual(evaluated_user.frame_current, expected)
            self.assertEqual(os.path.basename(image.filepath_from_user(
                image_user=evaluated_user)), f"Plane_{expected:04d}.exr")

        # What a render shows: Cycles at two frames, the texture through an Emission
        # shader seen by an orthographic camera, one render pixel per texel.
        seq = os.path.join(self.folder, "seq")
        renders = {frame: self.render(obj, frame) for frame in (6, 8)}
        files = {frame: h.load_pixels(os.path.join(seq, f"Plane_{frame:04d}.exr"))[0]
                 for frame in (6, 8)}
        for frame in (6, 8):
            other = 8 if frame == 6 else 6
            same = max(abs(a - b) for a, b in zip(renders[frame][0::4], files[frame][0::4]))
            different = max(abs(a - b) for a, b in zip(renders[frame][0::4],
                                                       files[other][0::4]))
            # Emission of a Non-Color texel is its value; only float rounding differs.
            self.assertLess(same, 1e-4, f"render of frame {frame} != file {frame}")
            self.assertGreater(different, 0.1, f"frames {frame} and {other} look alike")

        # Stepping the live simulation shows the live image again; Use Baked Sequence
        # brings the sequence back.
        self.assertEqual(bpy.ops.moldtex.step(), {'FINISHED'})
        self.assertEqual(node.image, obj.moldtex.image)
        self.assertEqual(bpy.ops.moldtex.use_baked_sequence(), {'FINISHED'})
        self.assertEqual(node.image, image)

    def render(self, obj, frame):
        scene = bpy.context.scene
        tree = obj.active_material.node_tree
        texture = tree.nodes["Moldtex Texture"]
        texture.interpolation = 'Closest'  # a render pixel sees exactly one texel
        emission = tree.nodes.get("Test Emission") or tree.nodes.new("ShaderNodeEmission")
        emission.name = "Test Emission"
        emission.inputs["Strength"].default_value = 1.0
        output = next(n for n in tree.nodes if n.type == 'OUTPUT_MATERIAL')
        tree.links.new(texture.outputs["Color"], emission.inputs["Color"])
        tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
        if scene.camera is None:
            camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
            scene.collection.objects.link(camera)
            camera.data.type = 'ORTHO'
            camera.data.ortho_scale = 2.0  # the 2 x 2 plane fills the frame
            camera.location = (0.0, 0.0, 3.0)
            scene.camera = camera
        render = scene.render
        render.engine = 'CYCLES'
        render.resolution_x = render.resolution_y = 128
        render.resolution_percentage = 100
        render.image_settings.file_format = 'OPEN_EXR'  # scene-linear, no view transform
        render.image_settings.color_depth = '32'
        render.film_transparent = False
        scene.cycles.samples = 1
        scene.cycles.use_denoising = False
        scene.cycles.pixel_filter_type = 'BOX'
        scene.cycles.filter_width = 0.01
        scene.cycles.device = 'CPU'
        path = os.path.join(self.folder, f"render_{frame}.exr")
        render.filepath = path
        scene.frame_set(frame)
        bpy.ops.render.render(write_still=True)
        return h.load_pixels(path)[0]


if __name__ == "__main__":
    unittest.main()
