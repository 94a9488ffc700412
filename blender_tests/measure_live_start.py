"""Wall time from pressing Start to step N in Blender's interface, Material Preview on
Suzanne: what the live loop gives, redraw included. A measurement, not a test
(docs/PERFORMANCE.md, "The first seconds"); run under Xvfb:

  blender -b --factory-startup --python-expr \\
      "import bpy; bpy.ops.wm.save_as_mainfile(filepath='/tmp/empty.blend')"
  xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup /tmp/empty.blend \\
      -P blender_tests/measure_live_start.py -- --addon-dir build/addon --target-step 350 \\
      [--resolution 1024 --agents 200000 --steps-per-update 2] [--seconds 30]

--target-step: the step at which measure_first_pattern.py found the network
recognisable for the same resolution and agents (the simulation is deterministic: the
live loop reaches the same state at the same step).
"""

import argparse
import os
import sys
import time

import bpy

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--addon-dir", required=True)
parser.add_argument("--target-step", type=int, required=True)
parser.add_argument("--resolution", default="")
parser.add_argument("--agents", type=int, default=0)
parser.add_argument("--steps-per-update", type=int, default=-1)
parser.add_argument("--seconds", type=float, default=30.0)
ARGS = parser.parse_args(argv)

sys.path.insert(0, os.path.abspath(ARGS.addon_dir))
import addon_utils  # noqa: E402

addon_utils.enable("moldtex", default_set=True)
from moldtex.sim import session as live  # noqa: E402

STATE = {"phase": "setup", "log": []}


def override():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    return {"window": window, "screen": window.screen, "area": area, "region": region}


def tick():
    if STATE["phase"] == "setup":
        for obj in list(bpy.data.objects):
            if obj.type == 'MESH':
                bpy.data.objects.remove(obj, do_unlink=True)
        with bpy.context.temp_override(**override()):
            bpy.ops.mesh.primitive_monkey_add(calc_uvs=True)
        obj = bpy.context.view_layer.objects.active
        settings = obj.moldtex
        if ARGS.resolution:
            settings.resolution = ARGS.resolution
        if ARGS.agents:
            settings.agent_count = ARGS.agents
        if ARGS.steps_per_update >= 0:
            settings.steps_per_update = ARGS.steps_per_update
        area = override()["area"]
        area.spaces.active.shading.type = 'MATERIAL'
        with bpy.context.temp_override(**override()):
            bpy.ops.moldtex.setup_material()
        STATE["name"] = obj.name
        STATE["phase"] = "compile"
        return 5.0  # let Eevee compile the material before the clock starts
    entry = live.get(STATE["name"])
    if STATE["phase"] == "compile":
        STATE["start"] = time.perf_counter()
        with bpy.context.temp_override(**override()):
            bpy.ops.moldtex.start('INVOKE_DEFAULT')
        STATE["phase"] = "running"
        return 0.25
    now = time.perf_counter() - STATE["start"]
    steps = entry.stats["step_count"]
    STATE["log"].append((now, steps, entry.steps_per_second))
    if steps >= ARGS.target_step and "hit" not in STATE:
        STATE["hit"] = now
    if now < ARGS.seconds and "hit" not in STATE:
        return 0.25
    settings = bpy.data.objects[STATE["name"]].moldtex
    print(f"{settings.resolution}² {settings.agent_count} agents, steps per update "
          f"{settings.steps_per_update or 'auto'}, load {os.getloadavg()[0]:.1f}: " +
          (f"step {ARGS.target_step} reached {STATE['hit']:.1f} s after Start"
           if "hit" in STATE else
           f"step {steps} after {now:.1f} s (target {ARGS.target_step} not reached)"))
    print("  (s, steps, panel steps/s): " + ", ".join(
        f"({t:.1f}, {s}, {r:.0f})" for t, s, r in STATE["log"]))
    sys.stdout.flush()
    os._exit(0)


bpy.app.timers.register(tick, first_interval=1.0)
