"""The headless bake (addon/moldtex/cli.py): exit statuses, a bake killed with SIGKILL
that resumes to exactly the files of an uninterrupted bake, and the --command entry of
Blender 4.2+.

Blender 3.4 runs the script as `blender -b FILE -P cli.py -- ...`; the bpy wheel has no
Blender executable, so there the same script runs as `python cli.py --blend FILE ...`
(its bpy-module mode)."""

import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import bpy

import helpers as h

TIMEOUT = 180  # seconds for one subprocess (a cold Blender start takes about 2)


def cli_path():
    import moldtex
    return os.path.join(os.path.dirname(moldtex.__file__), "cli.py")


def cli_command(blend, args):
    if bpy.app.binary_path:
        return ([bpy.app.binary_path, "-b", "--factory-startup", blend, "-P", cli_path(),
                 "--"] + args)
    return [sys.executable, cli_path(), "--blend", blend] + args


def frames_in(folder, prefix="Plane_"):
    return sorted(name for name in os.listdir(folder)
                  if name.startswith(prefix) and name.endswith(".exr"))


class CliTestCase(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_cli_test_")
        self.obj = h.plane()
        self.blend = os.path.join(self.folder, "scene.blend")
        bpy.ops.wm.save_as_mainfile(filepath=self.blend)
        self.obj = bpy.data.objects["Plane"]

    def tearDown(self):
        h.clear_scene()
        shutil.rmtree(self.folder, ignore_errors=True)

    def run_cli(self, args):
        log = os.path.join(self.folder, "cli.log")
        with open(log, "w") as out:
            status = subprocess.call(cli_command(self.blend, args), stdout=out,
                                     stderr=subprocess.STDOUT, timeout=TIMEOUT)
        with open(log, encoding="utf-8", errors="replace") as file:
            return status, file.read()


class CliStatusTests(CliTestCase):
    def test_bad_argument_exits_2(self):
        status, output = self.run_cli(["--object", "Plane", "--format", "tiff"])
        self.assertEqual(status, 2, output)
        self.assertIn("invalid choice: 'tiff'", output)

    def test_missing_object_exits_1(self):
        status, output = self.run_cli(["--object", "Nope", "--out", self.folder])
        self.assertEqual(status, 1, output)
        self.assertIn("there is no object named 'Nope'", output)
        self.assertIn("mesh objects: Plane", output)

    def test_python_expr_style_fails_with_status_1(self):
        if not bpy.app.binary_path:
            self.skipTest("the bpy module has no Blender executable for --python-expr")
        parent = os.path.dirname(os.path.dirname(cli_path()))
        expression = ("import sys; sys.path.insert(0, %r); import addon_utils; "
                      "addon_utils.enable('moldtex'); import bpy; "
                      "bpy.ops.moldtex.bake(object_name='Nope')" % parent)
        log = os.path.join(self.folder, "expr.log")
        with open(log, "w") as out:
            status = subprocess.call([bpy.app.binary_path, "-b", "--factory-startup",
                                      self.blend, "--python-exit-code", "1",
                                      "--python-expr", expression],
                                     stdout=out, stderr=subprocess.STDOUT, timeout=TIMEOUT)
        with open(log, encoding="utf-8", errors="replace") as file:
            output = file.read()
        self.assertEqual(status, 1, output)
        self.assertIn("There is no object named 'Nope'", output)


class KilledBakeTests(CliTestCase):
    FRAMES, SPF = 40, 40  # about 30 ms a frame here: the kill lands mid-sequence

    def test_killed_bake_resumes_to_the_uninterrupted_files(self):
        # The reference: the same look, frames and steps baked in this process.
        h.activate(self.obj)
        path = self.preset_path("golden_web")
        bpy.ops.moldtex.preset_apply(filepath=path)
        reference = os.path.join(self.folder, "reference")
        h.bake_settings(self.obj, reference, 1, self.FRAMES, self.SPF, "EXR_HALF")
        self.assertEqual(bpy.ops.moldtex.bake(), {'FINISHED'})
        expected = h.comparable_bytes(reference)

        killed = os.path.join(self.folder, "killed")
        args = ["--object", "Plane", "--out", killed, "--frames", "1", str(self.FRAMES),
                "--steps-per-frame", str(self.SPF), "--format", "exr-half",
                "--preset", "golden_web"]
        log = open(os.path.join(self.folder, "killed.log"), "w")
        process = subprocess.Popen(cli_command(self.blend, args), stdout=log,
                                   stderr=subprocess.STDOUT)
        try:
            deadline = time.monotonic() + TIMEOUT
            while True:
                if os.path.isdir(killed) and len(frames_in(killed)) >= 2:
                    break
                self.assertIsNone(process.poll(), "the bake ended before it was killed")
                self.assertLess(time.monotonic(), deadline, "no frames written")
                time.sleep(0.005)
            os.kill(process.pid, signal.SIGKILL)
        finally:
            process.wait()
            log.close()
        self.assertEqual(process.returncode, -signal.SIGKILL)

        # Whatever is under a frame name is a whole frame (the right one), numbered
        # without gaps; at most a .partial file is left besides the CSV and checkpoint.
        names = frames_in(killed)
        count = len(names)
        self.assertGreaterEqual(count, 2)
        self.assertLess(count, self.FRAMES, "finished before the kill: slow the frames")
        self.assertEqual(names, [f"Plane_{f:04d}.exr" for f in range(1, count + 1)])
        got = h.comparable_bytes(killed)
        for name in names:
            pixels, size = h.load_pixels(os.path.join(killed, name))
            self.assertEqual(size, (128, 128), name)
            self.assertEqual(len(pixels), 4 * 128 * 128, name)
            self.assertEqual(got[name], expected[name], name)
        others = set(os.listdir(killed)) - set(names) - {"Plane_metrics.csv",
                                                         "Plane_checkpoint.bin"}
        self.assertTrue(all(name.endswith(".partial") for name in others), others)

        # Rerun with --resume: exit 0, and the folder equals the uninterrupted bake's.
        status, output = self.run_cli(args + ["--resume"])
        self.assertEqual(status, 0, output)
        self.assertIn("Moldtex bake: resuming after frame", output)
        self.assertIn(f"Moldtex bake: frame {self.FRAMES}/{self.FRAMES} (coverage", output)
        self.assertIn(f"moldtex bake: {self.FRAMES} frames Plane_0001.exr", output)
        self.assertEqual(h.comparable_bytes(killed), expected)

    @staticmethod
    def preset_path(name):
        from moldtex.looks import presets
        return presets.find(name)


class InProcessCliTests(CliTestCase):
    def test_run_in_this_process(self):
        from moldtex import cli
        out = os.path.join(self.folder, "here")
        status = cli.run(["--object", "Plane", "--out", out, "--frames", "2", "4",
                          "--steps-per-frame", "2", "--format", "png8", "--prefix", "p_",
                          "--preset", "Metal Scratches"])
        self.assertEqual(status, 0)
        self.assertEqual(frames_in(out, "p_"), [])  # png8: .png files
        self.assertEqual(sorted(n for n in os.listdir(out) if n.endswith(".png")),
                         ["p_0002.png", "p_0003.png", "p_0004.png"])
        self.assertAlmostEqual(self.obj.moldtex.turn_speed, 2.0)  # the preset applied
        node = self.obj.active_material.node_tree.nodes["Moldtex Texture"]
        self.assertEqual(node.image.source, 'SEQUENCE')  # and playback is wired
        # More bad arguments (status 2), checked here to spare Blender starts.
        self.assertEqual(cli.run(["--object", "Plane", "--steps-per-frame", "0"]), 2)
        self.assertEqual(cli.run(["--object", "Plane", "--frames", "9", "3"]), 2)
        self.assertEqual(cli.run(["--out", out]), 2)  # --object is required
        self.assertEqual(cli.run(["--object", "Plane", "--out", out, "--preset",
                                  "no_such_look"]), 2)
        self.assertEqual(cli.run(["--object", "Camera"]), 1)  # not in this file

    def test_command_entry_of_blender_4_2(self):
        if not hasattr(bpy.utils, "register_cli_command"):
            self.skipTest("Blender %s has no --command (register_cli_command is 4.2+)"
                          % bpy.app.version_string)
        # The bpy module has no command line to pass --command to: check that the
        # add-on registered "moldtex" and call the registered function directly.
        import moldtex
        from moldtex import cli
        self.assertEqual(len(moldtex._cli_commands), 1)
        out = os.path.join(self.folder, "command")
        status = cli.command(["bake", "--object", "Plane", "--out", out, "--frames", "1",
                              "3", "--steps-per-frame", "2"])
        self.assertEqual(status, 0)
        self.assertEqual(frames_in(out), ["Plane_0001.exr", "Plane_0002.exr",
                                          "Plane_0003.exr"])
        self.assertEqual(cli.command([]), 2)
        self.assertEqual(cli.command(["render"]), 2)
        self.assertEqual(cli.command(["bake", "--object", "Nope"]), 1)


if __name__ == "__main__":
    unittest.main()
