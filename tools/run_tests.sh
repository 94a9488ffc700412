#!/usr/bin/env bash
# Installs what is needed, builds everything, and runs every test: the GoogleTest suite
# (CTest), the Blender background tests on Debian's Blender (3.4) and on PyPI's bpy 4.2
# and 5.0, the interactive checks under a virtual X server, and the core under ASan/UBSan
# with its fuzz target (tools/run_sanitizers.sh).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
moldtex_install_packages
moldtex_build
# PoCL is installed above, so the OpenCL tests must run, not skip.
export MOLDTEX_REQUIRE_OPENCL=1

# Runs a command; if it fails, prints the crash reports Blender wrote meanwhile (the
# backtrace of a segfault), then fails as it did.
with_crash_report() {
  local marker rc=0
  marker="$(mktemp)"
  "$@" || rc=$?
  if ((rc)); then
    for report in "${TMPDIR:-/tmp}"/*.crash.txt; do
      [ -f "$report" ] && [ "$report" -nt "$marker" ] && { echo "== $report"; cat "$report"; }
    done
  fi
  rm -f "$marker"
  return "$rc"
}

echo "== CTest (native core)"
ctest --test-dir "$MOLDTEX_BUILD" --output-on-failure -j"$(nproc)"

echo "== Blender tests on $(blender --version 2>/dev/null | head -n1)"
with_crash_report blender -b --factory-startup --python-exit-code 1 \
  -P "$MOLDTEX_ROOT/blender_tests/run_all.py" -- --addon-dir "$MOLDTEX_BUILD/addon"

echo "== Viewport brush tool with simulated mouse and keys (Blender's interface under Xvfb)"
with_crash_report timeout 300 xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --enable-event-simulate \
  --python-exit-code 1 -P "$MOLDTEX_ROOT/blender_tests/gui_brush.py" -- \
  --addon-dir "$MOLDTEX_BUILD/addon"

echo "== Material Preview shows the pixels: viewport screenshots under Xvfb"
VIEWPORT_TMP="$(mktemp -d)"
# A saved file keeps the splash screen off the viewport.
blender -b --factory-startup --python-expr \
  "import bpy, sys; bpy.ops.wm.save_as_mainfile(filepath=sys.argv[-1])" \
  -- "$VIEWPORT_TMP/empty.blend" >/dev/null
with_crash_report timeout 300 xvfb-run -a -s "-screen 0 1024x768x24" blender --factory-startup \
  "$VIEWPORT_TMP/empty.blend" --python-exit-code 1 \
  -P "$MOLDTEX_ROOT/blender_tests/gui_viewport.py" -- --addon-dir "$MOLDTEX_BUILD/addon"
rm -rf "$VIEWPORT_TMP"

echo "== The sidebar at its default width: every label fits (Blender's interface under Xvfb)"
with_crash_report timeout 120 xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup \
  --python-exit-code 1 -P "$MOLDTEX_ROOT/blender_tests/gui_panel.py" -- \
  --addon-dir "$MOLDTEX_BUILD/addon" --screenshot "$MOLDTEX_BUILD/moldtex_sidebar.png"

for target in "venv-bpy $MOLDTEX_BPY_VERSION" "venv-bpy5 $MOLDTEX_BPY5_VERSION"; do
  # shellcheck disable=SC2086  # two words: the venv and the bpy version
  BPY_PYTHON="$(moldtex_bpy_python $target)"
  echo "== Blender tests on bpy $("$BPY_PYTHON" -c 'import bpy; print(bpy.app.version_string)' 2>/dev/null)"
  "$BPY_PYTHON" "$MOLDTEX_ROOT/blender_tests/run_all.py" --addon-dir "$MOLDTEX_BUILD/addon"
done

# Last, as it builds the core a second time: the core and its CTest suite under
# ASan/UBSan, then the C API fuzz target on a fixed set of inputs (10-18 minutes in all on 2 cores).
echo "== Native core under AddressSanitizer/UBSan and the C API fuzz target"
"$MOLDTEX_ROOT/tools/run_sanitizers.sh"

echo "== All Moldtex tests passed"
