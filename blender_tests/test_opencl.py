"""The OpenCL backend, through the panel's Backend setting and the operators.

Where no OpenCL device exists, the tests that need one skip with the reason, or FAIL
when the environment sets MOLDTEX_REQUIRE_OPENCL=1 (tools/run_tests.sh does: it
installs PoCL, so OpenCL must work there).
"""

import os
import shutil
import tempfile
import unittest

import bpy

import helpers as h
from test_ui import draw_all, labels

STEPS = 200
# Same seed, but the OpenCL backend draws its random numbers in another order than the
# CPU one, so the two images differ texel by texel: only their statistics must agree.
# Coverage on this sphere after 200 steps varied from 0.385 to 0.443 over 6 seeds on
# the CPU (and the same on PoCL); CPU and OpenCL runs of one seed differed by 0.002 ..
# 0.031. 0.08 allows two independent draws of that spread, while the defects that
# matter (no diffusion, no evaporation, deposits in the wrong texels, agents stuck)
# move coverage by well over 0.1.
COVERAGE_TOLERANCE = 0.08


def first_opencl_device(test):
    """The engine's first OpenCL device, or skips/fails the test with the reason."""
    devices, reason = h.engine().opencl_devices()
    if devices:
        return devices[0]
    message = f"no OpenCL device: {reason}"
    if os.environ.get("MOLDTEX_REQUIRE_OPENCL") == "1":
        test.fail(message + " (MOLDTEX_REQUIRE_OPENCL=1 requires one)")
    test.skipTest(message)


def backend_identifiers(obj):
    from moldtex.settings import properties
    return [item[0] for item in properties.backend_items(obj.moldtex, bpy.context)]


class DeviceListTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_devices_listed_in_the_backend_chooser(self):
        engine = h.engine()
        devices, reason = engine.opencl_devices()
        self.assertIsInstance(devices, list)
        self.assertIsInstance(reason, str)
        if devices:
            self.assertEqual(reason, "")
        else:
            self.assertTrue(reason, "no devices and no reason")
        obj = h.add_primitive("sphere")
        from moldtex.settings import properties
        expected = ["AUTO", "CPU"] + [properties.device_identifier(d) for d in devices]
        self.assertEqual(backend_identifiers(obj), expected)
        self.assertEqual(obj.moldtex.backend, "AUTO")  # the default
        for device in devices:
            self.assertTrue(device["name"])
            self.assertGreater(device["global_memory_bytes"], 0)
        first_opencl_device(self)  # skip/fail below when there is none

    def test_no_opencl_is_a_reason_not_an_exception(self):
        engine = h.engine()
        saved = engine.library._lib, engine.library.LOAD_ERROR, engine.library._opencl_cache
        try:
            engine.library._lib, engine.library.LOAD_ERROR, engine.library._opencl_cache = None, "lib gone", None
            devices, reason = engine.opencl_devices(refresh=True)
        finally:
            engine.library._lib, engine.library.LOAD_ERROR, engine.library._opencl_cache = saved
        self.assertEqual(devices, [])
        self.assertIn("lib gone", reason)

    def test_panel_shows_why_opencl_is_unavailable(self):
        engine = h.engine()
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        saved = engine.library._opencl_cache
        why = ("No OpenCL runtime was found (libOpenCL.so.1): install your GPU "
               "driver's OpenCL support")
        try:
            engine.library._opencl_cache = ([], why)
            self.assertEqual(backend_identifiers(obj), ["AUTO", "CPU"])
            text = labels(draw_all(self, obj))
        finally:
            engine.library._opencl_cache = saved
            backend_identifiers(obj)  # rebuild the chooser's items
        self.assertIn("OpenCL unavailable", text)
        self.assertIn("libOpenCL.so.1", text)

    def test_reason_with_a_driver_code_fits_the_sidebar(self):
        # A machine without an OpenCL driver (most artists' laptops) shows the ICD
        # loader's code, one long word of capitals: wrapped by character count its
        # piece "_PLATFORM_NOT_FOUND_K" drew 142 px in a line of 138 (2026-12-05).
        import types
        import panel_fit
        if not panel_fit.fonts_work():
            self.skipTest("blf has no font in background mode here (Blender 3.4): "
                          "gui_panel.py checks this under Xvfb")
        engine = h.engine()
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        saved = engine.library._opencl_cache
        why = ("The OpenCL runtime found no platform (CL_PLATFORM_NOT_FOUND_KHR, no OpenCL "
               "driver is installed (-1001)): install an OpenCL driver, e.g. Debian's "
               "pocl-opencl-icd for the CPU")
        context = types.SimpleNamespace(active_object=obj, scene=bpy.context.scene)
        try:
            engine.library._opencl_cache = ([], why)
            backend_identifiers(obj)
            self.assertIn("CL_PLATFORM_NOT_", labels(draw_all(self, obj)))
            self.assertEqual(panel_fit.labels_cut(context), [])
        finally:
            engine.library._opencl_cache = saved
            backend_identifiers(obj)


class OpenCLRunTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()

    def test_pattern_on_opencl_matches_cpu(self):
        device = first_opencl_device(self)
        from moldtex.settings import properties
        obj = h.add_primitive("sphere")
        h.configure(obj)
        obj.moldtex.backend = properties.device_identifier(device)
        self.assertEqual(obj.moldtex.backend_type, 'OPENCL')
        self.assertEqual(obj.moldtex.opencl_device_name, device["name"])
        self.assertEqual(bpy.ops.moldtex.setup_material(), {'FINISHED'})
        entry = h.run(obj, STEPS)  # the first run may compile the kernels (seconds)
        self.assertTrue(entry.backend_name.startswith("OpenCL:"), entry.backend_name)
        self.assertIn(device["name"], entry.backend_name)
        self.assertEqual(entry.config["backend"], h.engine().BACKEND_OPENCL)
        self.assertEqual(entry.backend_note, "")
        h.check_pattern(self, obj, entry, "sphere on OpenCL", STEPS)
        opencl_coverage = entry.stats["coverage"]
        # The panel shows which backend runs.
        self.assertIn("OpenCL:", labels(draw_all(self, obj)))

        obj.moldtex.backend = "CPU"
        self.assertTrue(h.live().needs_reset(obj))  # a backend change needs a Reset
        entry = h.run(obj, STEPS)
        self.assertTrue(entry.backend_name.startswith("CPU"), entry.backend_name)
        h.check_pattern(self, obj, entry, "sphere on CPU", STEPS)
        cpu_coverage = entry.stats["coverage"]
        self.assertLess(abs(opencl_coverage - cpu_coverage), COVERAGE_TOLERANCE,
                        f"coverage OpenCL {opencl_coverage:.3f} vs CPU "
                        f"{cpu_coverage:.3f}")

    def test_auto_shows_backend_and_reason(self):
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        self.assertEqual(obj.moldtex.backend, "AUTO")
        entry = h.run(obj, 2)
        devices, reason = h.engine().opencl_devices()
        if any(d["is_gpu"] for d in devices):
            self.assertTrue(entry.backend_name.startswith("OpenCL:"), entry.backend_name)
        else:
            # Auto falls back to the CPU silently and says why.
            self.assertEqual(entry.backend_name.split(" ")[0], "CPU")
            self.assertIn("OpenCL not used", entry.backend_name)
        self.assertIn("Backend: " + entry.backend_name.split(" ")[0],
                      labels(draw_all(self, obj)))

    def test_nonexistent_device_is_reported_not_a_crash(self):
        # A script sets the stored indices (no device name): they are used as they
        # are, and the core refuses device 99 with a message the operator reports.
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        h.run(obj, 2)
        settings = obj.moldtex
        settings.backend_type = 'OPENCL'
        settings.opencl_device_name = ""
        settings.opencl_platform = 0
        settings.opencl_device = 99
        self.assertEqual(settings.backend, "AUTO")  # shown as Auto, never invalid
        with self.assertRaises(RuntimeError) as caught:  # CANCELLED + ERROR report
            bpy.ops.moldtex.reset()
        message = str(caught.exception)
        devices, reason = h.engine().opencl_devices()
        if devices:
            self.assertIn("no OpenCL device 99", message)
        self.assertIn("Backend", message)  # says where to pick another one
        entry = h.live().get(obj.name)
        self.assertEqual(entry.stats["step_count"], 2)  # the old simulation is kept
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})
        settings.backend = "CPU"
        entry = h.run(obj, 3)
        self.assertTrue(entry.backend_name.startswith("CPU"))

    def test_device_out_of_memory_is_reported_not_a_crash(self):
        # A real out-of-memory needs gigabytes; the core's failure is stood in for at
        # the engine boundary, so the operator path is the one a user would hit.
        engine = h.engine()
        obj = h.add_primitive("torus")
        h.configure(obj, agents=2000)
        h.run(obj, 2)
        obj.moldtex.backend_type = 'OPENCL'
        message = ("The OpenCL device ran out of memory while allocating device memory "
                   "(CL_MEM_OBJECT_ALLOCATION_FAILURE (-4)): lower the texture "
                   "resolution or the number of agents, or use the CPU backend")
        real = engine.Simulation

        def refuse(*args, **kwargs):
            raise engine.EngineError(message, engine.ERROR_OUT_OF_MEMORY)
        engine.Simulation = refuse
        try:
            with self.assertRaises(RuntimeError) as caught:
                bpy.ops.moldtex.reset()
        finally:
            engine.Simulation = real
        self.assertIn(message, str(caught.exception))
        self.assertEqual(h.live().get(obj.name).stats["step_count"], 2)  # kept
        self.assertEqual(bpy.ops.moldtex.step(steps=1), {'FINISHED'})


class BackendPersistenceTests(unittest.TestCase):
    def setUp(self):
        h.clear_scene()
        self.folder = tempfile.mkdtemp(prefix="moldtex_test_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def _save_and_reload(self, name):
        path = os.path.join(self.folder, "moldtex_backend.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        return bpy.data.objects[name]

    def test_backend_survives_save_and_reload(self):
        from moldtex.settings import properties
        devices, _reason = h.engine().opencl_devices()
        cpu = h.add_primitive("torus")
        cpu.name = "OnCPU"
        cpu.moldtex.backend = "CPU"
        chosen = h.add_primitive("sphere")
        chosen.name = "OnDevice"
        wanted = properties.device_identifier(devices[0]) if devices else "AUTO"
        chosen.moldtex.backend = wanted
        self._save_and_reload("OnCPU")
        self.assertEqual(bpy.data.objects["OnCPU"].moldtex.backend, "CPU")
        settings = bpy.data.objects["OnDevice"].moldtex
        self.assertEqual(settings.backend, wanted)
        if devices:
            self.assertEqual(settings.backend_type, 'OPENCL')
            self.assertEqual(settings.opencl_device_name, devices[0]["name"])
        first_opencl_device(self)  # the device part needs one

    def test_file_from_a_machine_with_another_device_falls_back_to_auto(self):
        obj = h.add_primitive("torus")
        name = obj.name
        h.configure(obj, agents=2000)
        settings = obj.moldtex
        # What the chooser stores for a device that this machine does not have.
        settings.backend_type = 'OPENCL'
        settings.opencl_platform = 3
        settings.opencl_device = 1
        settings.opencl_device_name = "Imaginary GPU 9000"
        settings.opencl_platform_name = "Imaginary Platform"
        obj = self._save_and_reload(name)
        settings = obj.moldtex
        self.assertEqual(settings.backend, "AUTO")
        self.assertEqual(settings.opencl_device_name, "Imaginary GPU 9000")  # kept
        text = labels(draw_all(self, obj))
        self.assertIn("Imaginary GPU 9000", text)
        self.assertIn("Auto is used", text)
        h.activate(obj)
        self.assertEqual(bpy.ops.moldtex.reset(), {'FINISHED'})  # a warning, no error
        entry = h.live().get(name)
        self.assertEqual(entry.config["backend"], h.engine().BACKEND_AUTO)
        self.assertIn("Imaginary GPU 9000", entry.backend_note)
        self.assertIn("Imaginary GPU 9000", labels(draw_all(self, obj)))
        self.assertEqual(bpy.ops.moldtex.step(steps=2), {'FINISHED'})
        # Picking a backend replaces the missing device.
        settings.backend = "CPU"
        self.assertEqual(h.convert().backend_note(settings), "")
        self.assertEqual(settings.backend, "CPU")


if __name__ == "__main__":
    unittest.main()
