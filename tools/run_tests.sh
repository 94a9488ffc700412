#!/usr/bin/env bash
# Installs what is needed, builds everything, and runs every test: the GoogleTest suite
# (CTest), the Blender background tests on Debian's Blender and on PyPI's bpy, and the
# core under ASan/UBSan with its fuzz target (tools/run_sanitizers.sh).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
moldtex_install_packages
moldtex_build
# PoCL is installed above, so the OpenCL tests must run, not skip.
export MOLDTEX_REQUIRE_OPENCL=1

echo "== CTest (native core)"
ctest --test-dir "$MOLDTEX_BUILD" --output-on-failure -j"$(nproc)"

echo "== Blender tests on $(blender --version 2>/dev/null | head -n1)"
blender -b --factory-startup --python-exit-code 1 \
  -P "$MOLDTEX_ROOT/blender_tests/run_all.py" -- --addon-dir "$MOLDTEX_BUILD/addon"

echo "== Viewport brush tool with simulated mouse and keys (Blender's interface under Xvfb)"
timeout 300 xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --enable-event-simulate \
  --python-exit-code 1 -P "$MOLDTEX_ROOT/blender_tests/gui_brush.py" -- \
  --addon-dir "$MOLDTEX_BUILD/addon"

BPY_PYTHON="$(moldtex_bpy_python)"
echo "== Blender tests on bpy $("$BPY_PYTHON" -c 'import bpy; print(bpy.app.version_string)' 2>/dev/null)"
"$BPY_PYTHON" "$MOLDTEX_ROOT/blender_tests/run_all.py" --addon-dir "$MOLDTEX_BUILD/addon"

# Last, as it builds the core a second time: the core and its CTest suite under
# ASan/UBSan, then the C API fuzz target for a fixed minute (about 6 minutes in all).
echo "== Native core under AddressSanitizer/UBSan and the C API fuzz target"
"$MOLDTEX_ROOT/tools/run_sanitizers.sh"

echo "== All Moldtex tests passed"
