"""The Moldtex sidebar at its default width in Blender's interface: a screenshot of it
and a check that every label fits (blender_tests/panel_fit.py, with the interface's
font and scale). Needs a window; headless, under a virtual X server:

  xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup \
      --python-exit-code 1 -P blender_tests/gui_panel.py -- --addon-dir build/addon \
      [--screenshot /tmp/moldtex_sidebar.png] [--all-open]

--all-open opens every sub-panel for the screenshot (use a taller screen, e.g.
1600x2400, to see them all). On Blender before 4.2 a script cannot pick the sidebar's
tab, so the Moldtex panels are shown in the first tab (Item) there, below Transform: the
width is the same. Exits 0 when every label fits, 1 otherwise.
"""

import argparse
import faulthandler
import os
import sys
import traceback
import types

import bpy

# A crash (of Blender, a driver or the core) prints every Python thread's stack, so a
# crash seen once on CI says where it happened.
faulthandler.enable(all_threads=True)

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--addon-dir", required=True)
parser.add_argument("--screenshot", default="")
parser.add_argument("--all-open", action="store_true")
ARGS = parser.parse_args(argv)

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.abspath(ARGS.addon_dir))
sys.path.insert(0, HERE)
import addon_utils  # noqa: E402

addon_utils.enable("moldtex", default_set=True)
from moldtex.ui import panels as ui  # noqa: E402
import panel_fit  # noqa: E402

FAILURES = []
OLD_TABS = not hasattr(bpy.types.Region, "active_panel_category")


def reregister_panels():
    for cls in reversed(ui.CLASSES):
        bpy.utils.unregister_class(cls)
    for cls in ui.CLASSES:
        if OLD_TABS:
            cls.bl_category = "Item"
        if ARGS.all_open and hasattr(cls, "bl_options"):
            cls.bl_options = set(cls.bl_options) - {'DEFAULT_CLOSED'}
        bpy.utils.register_class(cls)


def view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == 'VIEW_3D':
            return window, area
    raise RuntimeError("no 3D viewport")


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        FAILURES.append(message)


def setup():
    window, area = view3d()
    region = next(r for r in area.regions if r.type == 'WINDOW')
    with bpy.context.temp_override(window=window, area=area, region=region):
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj, do_unlink=True)
        bpy.ops.mesh.primitive_monkey_add()
        bpy.ops.moldtex.setup_material()
    space = area.spaces.active
    space.show_region_ui = True
    for other in area.regions:
        if other.type == 'UI' and not OLD_TABS:
            other.active_panel_category = "Moldtex"
    return 2.0


def measure():
    try:
        window, area = view3d()
        sidebar = next(r for r in area.regions if r.type == 'UI')
        scale = bpy.context.preferences.system.ui_scale or 1.0
        # The sidebar opens at its default width, 220 px at interface scale 1.
        check(abs(sidebar.width - 220 * scale) <= 2,
              f"the sidebar is at its default width ({sidebar.width} px, scale {scale:.3f})")
        obj = bpy.context.view_layer.objects.active
        context = types.SimpleNamespace(active_object=obj, scene=bpy.context.scene)
        states = 0
        for state in panel_fit.busy_scene_states():
            states += 1
            cut = panel_fit.labels_cut(context, scale)
            check(not cut, f"every label fits ({state}){': cut ' + repr(cut) if cut else ''}")
        check(states > 0, "panel states drawn")
        if ARGS.screenshot:
            with bpy.context.temp_override(window=window, area=area):
                bpy.ops.screen.screenshot(filepath=ARGS.screenshot)
            print(f"screenshot: {ARGS.screenshot} (sidebar at x {sidebar.x}..."
                  f"{sidebar.x + sidebar.width}, y {sidebar.y}...{sidebar.y + sidebar.height}"
                  f" from the bottom of a {window.width} x {window.height} window)")
    except Exception:
        traceback.print_exc()
        FAILURES.append("exception")
    print(f"gui_panel: {len(FAILURES)} failure(s)")
    sys.stdout.flush()
    os._exit(1 if FAILURES else 0)


reregister_panels()
bpy.app.timers.register(setup, first_interval=1.0)
bpy.app.timers.register(measure, first_interval=4.0)
