"""The add-on as Blender 4.2+ installs it (the extension manifest) and the version
differences it must handle (Blender 5.0's blend-relative path option)."""

import os
import subprocess
import sys
import unittest
import warnings

import bpy

import helpers as h


def manifest_path():
    from moldtex import engine
    return os.path.join(engine.ADDON_DIR, "blender_manifest.toml")


class ManifestTests(unittest.TestCase):
    def test_manifest_declares_file_access(self):
        import tomllib
        with open(manifest_path(), "rb") as file:
            manifest = tomllib.load(file)
        reason = manifest.get("permissions", {}).get("files", "")
        self.assertTrue(reason, "bakes write files: [permissions] files needs a reason")
        # Blender's rules for a reason: short, no closing full stop.
        self.assertLessEqual(len(reason), 64)
        self.assertFalse(reason.endswith("."))

    def test_versions_are_the_cores(self):
        # One source: native/include/moldtex.h's MOLDTEX_VERSION_*, staged into bl_info
        # and the manifest; the core reports the same (moldtex_version_string).
        import tomllib
        import moldtex
        from moldtex import engine
        self.assertIsNone(engine.LOAD_ERROR)
        with open(manifest_path(), "rb") as file:
            manifest = tomllib.load(file)
        self.assertEqual(manifest["version"], engine.VERSION)
        self.assertEqual(".".join(map(str, moldtex.bl_info["version"])), engine.VERSION)

    def test_blenders_own_validator_accepts_it(self):
        tool = os.path.join(bpy.utils.system_resource('SCRIPTS'), "addons_core", "bl_pkg",
                            "cli", "blender_ext.py")
        if not os.path.isfile(tool):
            self.skipTest("this Blender has no extension validator (before 4.2)")
        from moldtex import engine
        python = sys.executable  # (the bpy module's venv, or Blender's own Python)
        result = subprocess.run([python, tool, "validate", engine.ADDON_DIR],
                                capture_output=True, text=True, timeout=60)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertIn("Success", result.stdout + result.stderr)


class PathOptionTests(unittest.TestCase):
    def test_blend_relative_folder_without_warning(self):
        h.clear_scene()
        obj = h.add_primitive("torus")
        prop = obj.moldtex.bl_rna.properties["bake_directory"]
        has_option = bpy.app.version >= (5, 0, 0)
        if hasattr(prop, "is_path_supports_blend_relative"):
            self.assertTrue(prop.is_path_supports_blend_relative)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            obj.moldtex.bake_directory = "//moldtex_bake/"
            obj.moldtex.bake_directory = "//elsewhere/"
        messages = [str(w.message) for w in caught]
        self.assertFalse([m for m in messages if "blend relative" in m], messages)
        self.assertEqual(obj.moldtex.bake_directory, "//elsewhere/")
        if has_option:  # 5.0 warns without the option: the add-on must declare it
            from moldtex.settings import properties
            self.assertIn('PATH_SUPPORTS_BLEND_RELATIVE', properties.PATH_OPTIONS)


if __name__ == "__main__":
    unittest.main()
