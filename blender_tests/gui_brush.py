"""Interactive check of the viewport brush tool (moldtex.brush_paint) with simulated
mouse and key events: a left-drag paints an obstacle stroke into the Fields image,
Ctrl+Z inside the tool takes it back, Ctrl+Shift+Z redoes it, E switches to erasing,
Esc leaves the tool.

Simulated events need Blender's interface and --enable-event-simulate; headless:

  xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup \
      --enable-event-simulate --python-exit-code 1 -P blender_tests/gui_brush.py -- \
      --addon-dir build/addon [--screenshot /tmp/moldtex_brush.png]

Exits 0 when every check passed, 1 otherwise. Not part of run_all.py (background mode
has no window, so no modal tool and no events).
"""

import argparse
import faulthandler
import array
import os
import sys
import traceback

import bpy

# A crash (of Blender, a driver or the core) prints every Python thread's stack, so a
# crash seen once on CI says where it happened.
faulthandler.enable(all_threads=True)

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--addon-dir", required=True)
parser.add_argument("--screenshot", default="",
                    help="save a screenshot of the window with the tool active here")
ARGS = parser.parse_args(argv)

sys.path.insert(0, os.path.abspath(ARGS.addon_dir))
import addon_utils  # noqa: E402

addon_utils.enable("moldtex", default_set=True)
from moldtex.brush import session as brush  # noqa: E402

STATE = {"phase": "setup", "failures": []}
RESOLUTION = 128


def view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == 'VIEW_3D':
            region = next(r for r in area.regions if r.type == 'WINDOW')
            return window, area, region


def call(operator, *args, **kwargs):
    window, area, region = view3d()
    override = {"window": window, "screen": window.screen, "area": area, "region": region}
    if hasattr(bpy.context, "temp_override"):
        with bpy.context.temp_override(**override):
            return operator(*args, **kwargs)
    return operator(override, *args, **kwargs)


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        STATE["failures"].append(message)


def finish():
    print(f"gui_brush: {len(STATE['failures'])} failure(s)")
    sys.stdout.flush()
    os._exit(1 if STATE["failures"] else 0)


def window_point(x, y):
    """Window coordinates of the world point (x, y, 0)."""
    from bpy_extras import view3d_utils
    _window, area, region = view3d()
    rv3d = area.spaces.active.region_3d
    point = view3d_utils.location_3d_to_region_2d(region, rv3d, (x, y, 0.0))
    return int(point.x) + region.x, int(point.y) + region.y


def simulate(kind, value='NOTHING', at=None, **modifiers):
    window = bpy.context.window_manager.windows[0]
    x, y = at if at is not None else window_point(0.0, 0.0)
    window.event_simulate(kind, value, x=x, y=y, **modifiers)


def green_at(obj, x, y):
    image = obj.moldtex.fields_image
    if image is None:
        return None
    width, height = image.size
    pixels = array.array("f", bytes(16 * width * height))
    image.pixels.foreach_get(pixels)
    column = min(width - 1, int((x + 1.0) / 2.0 * width))
    row = min(height - 1, int((y + 1.0) / 2.0 * height))
    return pixels[4 * (row * width + column) + 1]


def tick():
    try:
        return _tick()
    except Exception:
        traceback.print_exc()
        STATE["failures"].append("exception")
        finish()


def _tick():
    phase = STATE["phase"]
    obj = bpy.data.objects.get("Canvas")
    if phase == "setup":
        for o in list(bpy.data.objects):
            bpy.data.objects.remove(o, do_unlink=True)
        call(bpy.ops.mesh.primitive_plane_add, 'EXEC_DEFAULT', size=2.0)
        obj = bpy.context.view_layer.objects.active
        obj.name = "Canvas"
        obj.moldtex.resolution = str(RESOLUTION)
        _window, area, _region = view3d()
        space = area.spaces.active
        space.show_region_ui = False
        rv3d = space.region_3d
        from mathutils import Quaternion
        rv3d.view_perspective = 'ORTHO'
        rv3d.view_rotation = Quaternion((1.0, 0.0, 0.0, 0.0))  # looking down -Z
        rv3d.view_location = (0.0, 0.0, 0.0)
        rv3d.view_distance = 3.0
        if ARGS.screenshot:  # show the painted fields over the pheromone material
            call(bpy.ops.moldtex.setup_material)
            space.shading.type = 'MATERIAL'
        settings = bpy.context.scene.moldtex_brush
        settings.target = 'OBSTACLE'
        settings.erase = False
        settings.radius = 0.15
        settings.strength = 1.0
        settings.falloff = 0.0
        STATE["phase"] = "invoke"
        return 0.5
    if phase == "invoke":
        result = call(bpy.ops.moldtex.brush_paint, 'INVOKE_DEFAULT')
        check(result == {'RUNNING_MODAL'}, f"the tool starts ({result})")
        start, end = window_point(-0.5, 0.3), window_point(0.5, 0.3)
        simulate('MOUSEMOVE', at=start)
        simulate('LEFTMOUSE', 'PRESS', at=start)
        for i in range(1, 11):
            t = i / 10.0
            simulate('MOUSEMOVE', at=(round(start[0] + t * (end[0] - start[0])),
                                      round(start[1] + t * (end[1] - start[1]))))
        simulate('LEFTMOUSE', 'RELEASE', at=end)
        STATE["phase"] = "painted"
        return 1.0
    if phase == "painted":
        values = [green_at(obj, x, 0.3) for x in (-0.5, 0.0, 0.5)]
        check(all(v is not None and v > 0.99 for v in values),
              f"the drag painted a wall along its path ({values})")
        check(green_at(obj, 0.0, -0.3) == 0.0, "nothing painted away from it")
        check(brush.counts("Canvas") == (1, 0), f"one stroke recorded "
              f"({brush.counts('Canvas')})")
        if ARGS.screenshot:
            window, area, region = view3d()
            space = area.spaces.active
            space.show_region_ui = True
            for other in area.regions:
                if other.type == 'UI':
                    try:
                        other.active_panel_category = "Moldtex"
                    except (AttributeError, TypeError):
                        pass
            call(bpy.ops.screen.screenshot, filepath=ARGS.screenshot)
            space.show_region_ui = False
        simulate('Z', 'PRESS', ctrl=True)
        simulate('Z', 'RELEASE', ctrl=True)
        STATE["phase"] = "undone"
        return 1.0
    if phase == "undone":
        check(green_at(obj, 0.0, 0.3) == 0.0, "Ctrl+Z in the tool took the stroke back")
        check(brush.counts("Canvas") == (0, 1), "…and it can be redone")
        simulate('Z', 'PRESS', ctrl=True, shift=True)
        simulate('Z', 'RELEASE', ctrl=True, shift=True)
        STATE["phase"] = "redone"
        return 1.0
    if phase == "redone":
        check((green_at(obj, 0.0, 0.3) or 0.0) > 0.99, "Ctrl+Shift+Z redid it")
        simulate('E', 'PRESS')
        simulate('E', 'RELEASE')
        point = window_point(0.0, 0.3)
        simulate('MOUSEMOVE', at=point)
        simulate('LEFTMOUSE', 'PRESS', at=point)
        simulate('LEFTMOUSE', 'RELEASE', at=point)
        STATE["phase"] = "erased"
        return 1.0
    if phase == "erased":
        check(bpy.context.scene.moldtex_brush.erase, "E switched to erasing")
        check(green_at(obj, 0.0, 0.3) == 0.0, "an erasing click cleared the wall there")
        check((green_at(obj, 0.5, 0.3) or 0.0) > 0.99, "…and only there")
        simulate('ESC', 'PRESS')
        simulate('ESC', 'RELEASE')
        STATE["phase"] = "left"
        return 1.0
    if phase == "left":
        point = window_point(0.0, -0.5)
        simulate('LEFTMOUSE', 'PRESS', at=point)
        simulate('LEFTMOUSE', 'RELEASE', at=point)
        STATE["phase"] = "after"
        return 1.0
    if phase == "after":
        check(green_at(obj, 0.0, -0.5) == 0.0, "after Esc a click no longer paints")
        check(brush.counts("Canvas") == (2, 0), f"two strokes in the history "
              f"({brush.counts('Canvas')})")
        finish()
    return None


bpy.app.timers.register(tick, first_interval=1.0)
