"""Stress check for the live loop beside Blender's own operators (not part of CI: it
runs for minutes). Start grows the mold on a plane in Material Preview while a timer
takes a screenshot every 0.05 s, loads it and reads its pixels, and a draw handler reads
the pheromone image at every redraw, as blender_tests/gui_viewport.py does once a
second. With the former Python stepping thread Blender 3.4 segfaulted within 4 minutes
(twice in two runs); with the core's own thread it runs through (docs/ARCHITECTURE.md).
It prints "survived N shots" and exits 0, or Blender crashes.

  blender -b --factory-startup --python-expr \
      "import bpy, sys; bpy.ops.wm.save_as_mainfile(filepath=sys.argv[-1])" -- /tmp/empty.blend
  xvfb-run -a -s "-screen 0 1024x768x24" blender --factory-startup /tmp/empty.blend \
      -P tools/stress_live_screenshots.py -- --addon-dir build/addon --seconds 300
  (--mode sync steps in the timer instead: Steps per Update 5.)"""
import argparse
import array
import faulthandler
import os
import sys
import tempfile
import time

import bpy

faulthandler.enable(all_threads=True)  # a crash prints every Python thread's stack

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--addon-dir", required=True)
parser.add_argument("--mode", choices=("threaded", "sync"), default="threaded")
parser.add_argument("--seconds", type=float, default=300.0)
ARGS = parser.parse_args(argv)

sys.path.insert(0, os.path.abspath(ARGS.addon_dir))
import addon_utils  # noqa: E402

addon_utils.enable("moldtex", default_set=True)
from moldtex.sim import session as live  # noqa: E402

NAME = "Canvas"
STATE = {"phase": "setup", "began": 0.0, "shots": 0}
FOLDER = tempfile.mkdtemp(prefix="moldtex_stress_")


def view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == 'VIEW_3D':
            return window, area, next(r for r in area.regions if r.type == 'WINDOW')
    raise RuntimeError("no 3D viewport")


def call(operator, *args, **kwargs):
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, screen=window.screen, area=area,
                                   region=region):
        return operator(*args, **kwargs)


def read_pixels(image):
    pixels = array.array("f", bytes(4 * image.channels * image.size[0] * image.size[1]))
    image.pixels.foreach_get(pixels)
    return pixels


def tick():
    if STATE["phase"] == "setup":
        for other in list(bpy.data.objects):
            bpy.data.objects.remove(other, do_unlink=True)
        call(bpy.ops.mesh.primitive_plane_add, size=2.0)
        obj = bpy.context.view_layer.objects.active
        obj.name = NAME
        obj.moldtex.resolution = "256"
        obj.moldtex.agent_count = 16000
        if ARGS.mode == "sync":
            obj.moldtex.steps_per_update = 5
        _window, area, _region = view3d()
        area.spaces.active.shading.type = 'MATERIAL'
        area.spaces.active.overlay.show_overlays = False
        STATE["phase"] = "start"
        return 2.0
    if STATE["phase"] == "start":
        print("start", call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT'))
        STATE["phase"] = "shots"
        STATE["began"] = time.time()
        return 0.5
    if time.time() - STATE["began"] > ARGS.seconds:
        print(f"survived {STATE['shots']} shots, "
              f"steps {live.get(NAME).stats['step_count']}")
        sys.stdout.flush()
        os._exit(0)
    STATE["shots"] += 1
    path = os.path.join(FOLDER, f"shot{STATE['shots'] % 3}.png")
    call(bpy.ops.screen.screenshot, filepath=path)
    shot = bpy.data.images.load(path, check_existing=False)
    read_pixels(shot)
    bpy.data.images.remove(shot)
    return 0.05


def on_draw():
    obj = bpy.data.objects.get(NAME)
    image = obj.moldtex.image if obj is not None else None
    if image is not None and image.size[0] > 0:
        read_pixels(image)


bpy.types.SpaceView3D.draw_handler_add(on_draw, (), 'WINDOW', 'POST_PIXEL')
bpy.app.timers.register(tick, first_interval=1.0)
