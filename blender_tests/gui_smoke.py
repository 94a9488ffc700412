"""Interactive smoke check of Start/Pause (the modal timer) and the sidebar panel.

Timers and modal operators do not run in background mode, so this needs Blender's
interface; headless, run it under a virtual X server:

  xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup \
      --python-exit-code 1 -P blender_tests/gui_smoke.py -- --addon-dir build/addon \
      [--screenshot /tmp/moldtex_panel.png]

It starts the simulation with the Start button's operator, lets the timer drive it,
pauses with a second Start, checks the steps stopped, saves a screenshot of the
viewport; then runs the modal Bake Sequence (Start is refused meanwhile), cancels it
with a second press, resumes it to the end and checks the material plays the frames;
and quits with exit code 0 (or 1 on a failure). Not part of run_all.py.
Pass a .blend file before -P (any saved file) so the splash screen does not cover the
viewport. Under Xvfb Blender's event loop wakes only about once a second, so the
timer drives just a few updates there; on a desktop it runs at 30 updates a second.
"""

import argparse
import os
import sys
import traceback

import bpy

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--addon-dir", required=True)
parser.add_argument("--screenshot", default="")
parser.add_argument("--shading", default="MATERIAL", choices=["SOLID", "MATERIAL"])
ARGS = parser.parse_args(argv)

sys.path.insert(0, os.path.abspath(ARGS.addon_dir))
import addon_utils  # noqa: E402

addon_utils.enable("moldtex", default_set=True)
from moldtex.sim import session as live  # noqa: E402

STATE = {"phase": "start", "steps_at_pause": None, "waited": 0, "failures": []}


def view3d_override():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == 'VIEW_3D':
            region = next(r for r in area.regions if r.type == 'WINDOW')
            return {"window": window, "screen": window.screen, "area": area,
                    "region": region}
    raise RuntimeError("no 3D viewport")


def call(operator, *args):
    override = view3d_override()
    if hasattr(bpy.context, "temp_override"):
        with bpy.context.temp_override(**override):
            return operator(*args)
    return operator(override, *args)


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        STATE["failures"].append(message)


def finish():
    if STATE.get("bake_dir"):
        import shutil
        shutil.rmtree(STATE["bake_dir"], ignore_errors=True)
    code = 1 if STATE["failures"] else 0
    print(f"gui_smoke: {len(STATE['failures'])} failure(s)")
    sys.stdout.flush()
    os._exit(code)


def tick():
    try:
        return _tick()
    except Exception:
        traceback.print_exc()
        STATE["failures"].append("exception")
        finish()


def _tick():
    phase = STATE["phase"]
    obj = bpy.data.objects.get("Torus")
    if phase == "start":
        for o in list(bpy.data.objects):
            if o.type == 'MESH':
                bpy.data.objects.remove(o, do_unlink=True)
        call(bpy.ops.mesh.primitive_torus_add)
        obj = bpy.context.view_layer.objects.active
        obj.name = "Torus"
        obj.moldtex.resolution = "512"
        obj.moldtex.agent_count = 50000
        # Run on the first OpenCL device when there is one (the panel then shows
        # "Backend: OpenCL: <device>"), else on Auto.
        from moldtex import engine
        from moldtex.settings import properties
        devices, _reason = engine.opencl_devices()
        if devices:
            obj.moldtex.backend = properties.device_identifier(devices[0])
        check(call(bpy.ops.moldtex.setup_material) == {'FINISHED'}, "set up material")
        override = view3d_override()
        space = override["area"].spaces.active
        space.shading.type = ARGS.shading
        space.show_region_ui = True
        for region in override["area"].regions:
            if region.type == 'UI':
                try:
                    region.active_panel_category = "Moldtex"
                except (AttributeError, TypeError):
                    pass
        result = call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')
        check(result == {'RUNNING_MODAL'}, f"start returns RUNNING_MODAL ({result})")
        STATE["phase"] = "running"
        return 2.0
    if phase == "running":
        entry = live.get("Torus")
        steps = entry.stats["step_count"] if entry else 0
        # The first step on OpenCL builds the kernel (seconds on a loaded machine); the
        # live loop's thread runs it while the interface goes on, so wait for it.
        if steps == 0 and STATE["waited"] < 30:
            STATE["waited"] += 1
            return 1.0
        check(entry is not None and entry.running, "simulation is running")
        check(steps > 0, f"the live loop stepped it ({steps} steps)")
        wanted = "OpenCL:" if obj.moldtex.backend_type == 'OPENCL' else ""
        check(entry is not None and entry.backend_name.startswith(wanted),
              f"runs on the chosen backend ({entry.backend_name if entry else None})")
        obj.moldtex.turn_speed = 45.0  # change a parameter while it runs
        check(abs(entry.sim.get_params()["turn_speed"] - 45.0) < 1e-4,
              "parameter change reached the running simulation")
        call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')  # the button again = pause
        STATE["phase"] = "pausing"
        return 0.5
    if phase == "pausing":
        entry = live.get("Torus")
        check(not entry.running, "paused after pressing Start again")
        STATE["steps_at_pause"] = entry.stats["step_count"]
        STATE["phase"] = "paused"
        return 1.0
    if phase == "paused":
        entry = live.get("Torus")
        check(entry.stats["step_count"] == STATE["steps_at_pause"],
              "no steps while paused")
        result = call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')  # resume
        check(result == {'RUNNING_MODAL'}, "resumes")
        STATE["phase"] = "resumed"
        return 1.5
    if phase == "resumed":
        entry = live.get("Torus")
        check(entry.stats["step_count"] > STATE["steps_at_pause"], "resumed stepping")
        if ARGS.screenshot:
            override = view3d_override()
            if hasattr(bpy.context, "temp_override"):
                with bpy.context.temp_override(**override):
                    bpy.ops.screen.screenshot(filepath=ARGS.screenshot)
            else:
                bpy.ops.screen.screenshot(override, filepath=ARGS.screenshot)
            print(f"screenshot: {ARGS.screenshot}")
        # Deleting the object while it runs stops the modal and frees the sim.
        bpy.data.objects.remove(obj, do_unlink=True)
        STATE["phase"] = "deleted"
        return 0.5
    if phase == "deleted":
        check(live.get("Torus") is None, "deleting the object freed its simulation")
        return start_bake()
    if phase == "baking":
        entry = live.get("Torus")
        check(entry is not None and entry.baking, "the modal bake is running")
        progress = entry.bake_progress if entry else {}
        check(bool(progress) and progress["frames_done"] > 0,
              f"its timer polled the progress ({progress.get('frames_done')} frames)")
        try:
            call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')
            check(False, "Start is refused while baking")
        except RuntimeError as error:
            check("a bake is running" in str(error), f"Start says: {error}")
        screenshot("_bake")
        call(bpy.ops.moldtex.bake, 'INVOKE_DEFAULT')  # the button again = cancel
        STATE["phase"] = "cancelling"
        return 1.5
    if phase == "cancelling":
        entry = live.get("Torus")
        check(not entry.baking, "cancelled by pressing Bake again")
        check("cancelled" in entry.bake_summary, f"summary: {entry.bake_summary}")
        frames = sorted(n for n in os.listdir(STATE["bake_dir"]) if n.endswith(".exr"))
        check(0 < len(frames) < 30, f"whole frames kept ({len(frames)})")
        obj.moldtex.bake_resume = True
        result = call(bpy.ops.moldtex.bake, 'INVOKE_DEFAULT')
        check(result == {'RUNNING_MODAL'}, f"resume starts ({result})")
        STATE["phase"] = "resuming"
        STATE["waited"] = 0
        return 1.0
    if phase == "resuming":
        entry = live.get("Torus")
        if entry.baking and STATE["waited"] < 60:
            STATE["waited"] += 1
            return 1.0
        check(not entry.baking, "the resumed bake ended")
        frames = sorted(n for n in os.listdir(STATE["bake_dir"]) if n.endswith(".exr"))
        check(len(frames) == 30, f"all 30 frames ({len(frames)})")
        node = obj.active_material.node_tree.nodes["Moldtex Texture"]
        check(node.image is not None and node.image.source == 'SEQUENCE',
              "the material plays the sequence")
        finish()
    return None


def screenshot(suffix):
    if not ARGS.screenshot:
        return
    root, extension = os.path.splitext(ARGS.screenshot)
    path = f"{root}{suffix}{extension}"
    override = view3d_override()
    if hasattr(bpy.context, "temp_override"):
        with bpy.context.temp_override(**override):
            bpy.ops.screen.screenshot(filepath=path)
    else:
        bpy.ops.screen.screenshot(override, filepath=path)
    print(f"screenshot: {path}")


def start_bake():
    """Modal bake (the Bake Sequence button): runs, refuses Start, cancels, resumes."""
    import tempfile
    call(bpy.ops.mesh.primitive_torus_add)
    obj = bpy.context.view_layer.objects.active
    obj.name = "Torus"
    settings = obj.moldtex
    settings.resolution = "256"
    settings.agent_count = 20000
    settings.bake_use_scene_range = False
    settings.bake_frame_start, settings.bake_frame_end = 1, 30
    settings.bake_steps_per_frame = 20
    STATE["bake_dir"] = tempfile.mkdtemp(prefix="moldtex_gui_bake_")
    settings.bake_directory = STATE["bake_dir"]
    check(call(bpy.ops.moldtex.setup_material) == {'FINISHED'}, "set up material (bake)")
    result = call(bpy.ops.moldtex.bake, 'INVOKE_DEFAULT')
    check(result == {'RUNNING_MODAL'}, f"bake returns RUNNING_MODAL ({result})")
    STATE["phase"] = "baking"
    return 1.5


bpy.app.timers.register(tick, first_interval=1.0)
