"""Does Material Preview show the pixels? Screenshots of the 3D viewport compared with
the pheromone image the viewport drew, in Blender's interface under Xvfb:

0. on the way: Start before Set Up Material sets the material up; a long Step
   (LONG_STEP steps) runs modally (the interface runs meanwhile) and Adjust Last
   Operation reruns it with another count from where it started;
1. after Step (a network) and then Reset (all zero: the model must show the ramp's
   zero colour everywhere, not the network it showed before);
2. while Start runs (each redraw must show the pixels of that moment, not samples
   accumulated over older states);
3. after a cancelled Bake, when Start runs again (the viewport and the panel's step
   count must follow the live simulation, not the bake's last state);
4. (after the Intrinsic domain's build-ahead checks) a dense grid without UVs on the
   Intrinsic domain: the viewport must show its vertex colours (cell means against the
   mean ramp colour of the vertices in each cell).

  blender -b --factory-startup --python-expr \\
      "import bpy; bpy.ops.wm.save_as_mainfile(filepath='/tmp/empty.blend')"
  xvfb-run -a -s "-screen 0 1024x768x24" blender --factory-startup /tmp/empty.blend \\
      --python-exit-code 1 -P blender_tests/gui_viewport.py -- --addon-dir build/addon

(the .blend keeps the splash screen off the viewport). Exits 0 when every check passed,
1 otherwise. Not part of run_all.py (background mode draws nothing).

How it compares: a 2×2 plane fills most of an orthographic top view (overlays off,
Standard view transform). The plane is cut into 16 × 16 cells; for each cell the mean
luminance of its screen pixels (inset by 15% so edges and anti-aliasing do not count)
is compared with the mean pheromone of its texels in the image as it was when the
viewport last drew (a draw handler copies the image's pixels at every redraw of the
viewport, because the screenshot reads the last frame drawn, and the image may have
changed since). Cell means make the comparison independent of texture filtering,
mipmaps and Eevee's sub-pixel jitter. Lighting and the ramp are monotonic but not
linear, so the measure is the correlation of the two over the cells: a network drawn
as it is gives about 0.98 here, a blend of older states drawn over it 0.85–0.95 (see
MIN_CORRELATION), and against a blank image it is undefined (hence the std check after
Reset).
"""

import argparse
import faulthandler
import array
import os
import shutil
import sys
import tempfile
import time
import traceback

import bpy

# A crash (of Blender, a driver or the core) prints every Python thread's stack, so a
# crash seen once on CI says where it happened.
faulthandler.enable(all_threads=True)

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--addon-dir", required=True)
parser.add_argument("--keep-screenshots", default="",
                    help="copy the screenshots into this folder")
ARGS = parser.parse_args(argv)

sys.path.insert(0, os.path.abspath(ARGS.addon_dir))
import addon_utils  # noqa: E402

addon_utils.enable("moldtex", default_set=True)
from moldtex.sim import session as live  # noqa: E402
from moldtex.settings import units  # noqa: E402

NAME = "Canvas"
EXPORTS = []  # objects whose mesh live.export_object read (the intrinsic Start)
GRID = 16
# The network's cells differ by about 0.2 in mean luminance (std over the cells). A
# viewport that draws its pixels correlates at 0.974–0.985 with them (Blender 3.4 under
# Xvfb, llvmpipe); with the accumulation fault (image_io.upload without its depsgraph
# tag) the same runs gave 0.85–0.95 while running and 0.92–0.95 after the bake.
MIN_CORRELATION = 0.96
# After Reset every cell must show the same colour: the network's cells differ by a
# standard deviation of ~0.2; a blank image drawn gives ~0.0002 (dithering).
MAX_BLANK_STD = 0.01
WAIT_LIMIT = 90.0  # seconds for Eevee to compile the material under llvmpipe
BARE = "Bare"  # the mesh without UVs
# The vertex colours are interpolated across each triangle before the ramp (the image's
# texels too, but the cells' expected values are means of ramp(vertex value)): measured
# below; a viewport without the colours has a uniform screen (no correlation).
MIN_VERTEX_CORRELATION = 0.9

STATE = {"phase": "setup", "failures": [], "drawn": None, "draws": 0, "since": 0.0,
         "shots": 0, "tmp": tempfile.mkdtemp(prefix="moldtex_gui_viewport_")}


def view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == 'VIEW_3D':
            region = next(r for r in area.regions if r.type == 'WINDOW')
            return window, area, region
    raise RuntimeError("no 3D viewport")


def call(operator, *args, **kwargs):
    window, area, region = view3d()
    override = {"window": window, "screen": window.screen, "area": area, "region": region}
    if hasattr(bpy.context, "temp_override"):
        with bpy.context.temp_override(**override):
            return operator(*args, **kwargs)
    return operator(override, *args, **kwargs)


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    sys.stdout.flush()
    if not condition:
        STATE["failures"].append(message)


def finish():
    entry = live.get(NAME)
    if entry is not None and entry.running:
        entry.stop_requested = True
    shutil.rmtree(STATE["tmp"], ignore_errors=True)
    print(f"gui_viewport: {len(STATE['failures'])} failure(s)")
    sys.stdout.flush()
    os._exit(1 if STATE["failures"] else 0)


def image_pixels(image):
    width, height = image.size
    pixels = array.array("f", bytes(4 * image.channels * width * height))
    image.pixels.foreach_get(pixels)
    return pixels


def on_draw():
    """Copies the pheromone image as the viewport draws it (see the module doc)."""
    obj = bpy.data.objects.get(NAME)
    image = obj.moldtex.image if obj is not None else None
    if image is None or image.size[0] == 0:
        return
    STATE["drawn"] = (tuple(image.size), image_pixels(image))
    STATE["draws"] += 1


def screen_cells(label):
    """Mean luminance of the screen pixels of each of the GRID × GRID cells of the 2 × 2
    square at the origin (inset, see the module doc), row by row from the bottom."""
    from bpy_extras import view3d_utils
    _window, area, region = view3d()
    STATE["shots"] += 1
    path = os.path.join(STATE["tmp"], f"{STATE['shots']:02d}_{label}.png")
    call(bpy.ops.screen.screenshot, filepath=path)
    if ARGS.keep_screenshots:
        os.makedirs(ARGS.keep_screenshots, exist_ok=True)
        shutil.copy(path, ARGS.keep_screenshots)
    shot = bpy.data.images.load(path, check_existing=False)
    width, height = shot.size
    channels = shot.channels
    pixels = image_pixels(shot)
    bpy.data.images.remove(shot)
    rv3d = area.spaces.active.region_3d
    screen = []
    inset = 0.15
    for j in range(GRID):
        for i in range(GRID):
            corner0 = view3d_utils.location_3d_to_region_2d(
                region, rv3d, (2.0 * (i + inset) / GRID - 1.0, 2.0 * (j + inset) / GRID - 1.0, 0.0))
            corner1 = view3d_utils.location_3d_to_region_2d(
                region, rv3d, (2.0 * (i + 1 - inset) / GRID - 1.0,
                               2.0 * (j + 1 - inset) / GRID - 1.0, 0.0))
            x0, x1 = int(corner0.x) + region.x, int(corner1.x) + region.x
            y0, y1 = int(corner0.y) + region.y, int(corner1.y) + region.y
            total = count = 0
            for y in range(y0, y1 + 1):
                start = channels * (y * width + x0)
                stop = channels * (y * width + x1 + 1)
                row_r = pixels[start:stop:channels]
                row_g = pixels[start + 1:stop:channels]
                row_b = pixels[start + 2:stop:channels]
                total += sum(luminance(linear(r), linear(g), linear(b))
                             for r, g, b in zip(row_r, row_g, row_b))
                count += len(row_r)
            screen.append(total / max(1, count))
    return screen


def ramp_table(obj):
    """The luminance of obj's Moldtex ramp at LEVELS + 1 evenly spaced positions."""
    ramp = obj.active_material.node_tree.nodes["Moldtex Ramp"]
    return [luminance(ramp.color_ramp.evaluate(k / LEVELS)) for k in range(LEVELS + 1)]


def correlate(label, screen, expected):
    """(correlation, screen std, expected std) of two lists over the cells."""
    n = len(screen)
    mean_s, mean_e = sum(screen) / n, sum(expected) / n
    sxx = sum((s - mean_s) ** 2 for s in screen)
    syy = sum((e - mean_e) ** 2 for e in expected)
    sxy = sum((s - mean_s) * (e - mean_e) for s, e in zip(screen, expected))
    correlation = sxy / (sxx * syy) ** 0.5 if sxx > 0.0 and syy > 0.0 else float("nan")
    result = (correlation, (sxx / n) ** 0.5, (syy / n) ** 0.5)
    print(f"     {label}: correlation {correlation:.3f}, screen std {result[1]:.4f}, "
          f"pixel std {result[2]:.4f}, {STATE['draws']} draws")
    return result


def screen_vs_pixels(label):
    """(correlation, screen std, pixel std) over the GRID × GRID cells."""
    screen = screen_cells(label)
    (tex_width, tex_height), texels = STATE["drawn"]
    # The colour each texel is given: the ramp's luminance at its pheromone (a table).
    table = ramp_table(bpy.data.objects[NAME])
    shown = array.array("f", [table[min(LEVELS, max(0, int(v * LEVELS + 0.5)))]
                              for v in texels[0::4]])
    expected = []
    for j in range(GRID):
        for i in range(GRID):
            tx0, tx1 = i * tex_width // GRID, (i + 1) * tex_width // GRID
            ty0, ty1 = j * tex_height // GRID, (j + 1) * tex_height // GRID
            total = 0.0
            for y in range(ty0, ty1):
                total += sum(shown[y * tex_width + tx0:y * tex_width + tx1])
            expected.append(total / ((tx1 - tx0) * (ty1 - ty0)))
    return correlate(label, screen, expected)


def screen_vs_vertices(obj, label):
    """(correlation, screen std, vertex std) over the GRID × GRID cells, for a mesh
    without UVs: each cell's expected luminance is the mean, over the mesh vertices in
    it, of the ramp's luminance at the vertex colour the add-on wrote (through the
    material's Map Range: 0 .. the display maximum)."""
    from moldtex.colour import material
    screen = screen_cells(label)
    table = ramp_table(obj)
    top = material.display_maximum(obj)
    attribute = obj.data.color_attributes["Moldtex"]
    values = array.array("f", bytes(16 * len(attribute.data)))
    attribute.data.foreach_get("color", values)
    positions = array.array("f", bytes(12 * len(obj.data.vertices)))
    obj.data.vertices.foreach_get("co", positions)
    sums, counts = [0.0] * (GRID * GRID), [0] * (GRID * GRID)
    for k, value in enumerate(values[0::4]):
        u, v = (positions[3 * k] + 1.0) / 2.0 * GRID, (positions[3 * k + 1] + 1.0) / 2.0 * GRID
        i, j = int(u), int(v)
        if not (0 <= i < GRID and 0 <= j < GRID):
            continue
        if min(u - i, v - j) < 0.15 or max(u - i, v - j) > 0.85:  # (the cells' inset)
            continue
        level = min(LEVELS, max(0, int(value / top * LEVELS + 0.5)))
        sums[j * GRID + i] += table[level]
        counts[j * GRID + i] += 1
    expected = [a / max(1, c) for a, c in zip(sums, counts)]
    return correlate(label, screen, expected)


LEVELS = 1024


def luminance(r, g=None, b=None):
    if g is None:
        r, g, b = r[0], r[1], r[2]
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def linear(value):
    """sRGB display value (the screenshot, Standard view transform) to linear."""
    return value / 12.92 if value <= 0.04045 else ((value + 0.055) / 1.055) ** 2.4


# The long Step's count: long enough that the timer (every 0.25 s) sees it part-way on a
# fast machine (16,000 agents at 256² ran about 1,000 steps a second under Xvfb on the
# 2-core CI machine in 2026-12; 300 steps, the count before, once ended within 0.5 s).
LONG_STEP = 2000


def comparable_pattern(settings):
    """256², 16,000 agents, one pattern unit per texel, as the 512² default has: at 256²
    the default unit would be half a texel, a pattern finer than the 16 x 16 cells can
    compare."""
    settings.resolution = "256"
    settings.pattern_scale = units.REFERENCE_RESOLUTION / 256
    settings.agent_count = 16000


def tick():
    try:
        return _tick()
    except Exception:
        traceback.print_exc()
        STATE["failures"].append("exception")
        finish()


def goto(phase):
    STATE["phase"] = phase
    STATE["since"] = time.perf_counter()


def waited():
    return time.perf_counter() - STATE["since"]


def _tick():
    phase = STATE["phase"]
    obj = bpy.data.objects.get(NAME)
    if phase == "setup":
        for other in list(bpy.data.objects):
            bpy.data.objects.remove(other, do_unlink=True)
        call(bpy.ops.mesh.primitive_plane_add, size=2.0)
        obj = bpy.context.view_layer.objects.active
        obj.name = NAME
        comparable_pattern(obj.moldtex)
        bpy.context.scene.view_settings.view_transform = 'Standard'
        _window, area, _region = view3d()
        space = area.spaces.active
        space.show_region_ui = False
        space.show_region_toolbar = False
        space.overlay.show_overlays = False
        space.shading.type = 'MATERIAL'
        from mathutils import Quaternion
        rv3d = space.region_3d
        rv3d.view_perspective = 'ORTHO'
        rv3d.view_rotation = Quaternion((1.0, 0.0, 0.0, 0.0))  # looking down -Z
        rv3d.view_location = (0.0, 0.0, 0.0)
        rv3d.view_distance = 2.6
        # Start before Set Up Material sets the material up itself.
        from moldtex.colour import material
        check(call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT') == {'RUNNING_MODAL'},
              "Start without Set Up Material")
        node = material.moldtex_node(obj, material.TEXTURE_NODE)
        check(node is not None and node.image is obj.moldtex.image,
              "…set up the material with the pheromone image")
        goto("first_pause")
        return 1.0
    if phase == "first_pause":
        call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')  # pause
        goto("long_step")
        return 0.5
    if phase == "long_step":
        entry = live.get(NAME)
        STATE["before_step"] = entry.stats["step_count"]
        # What this script set directly (the name, settings) gets an undo step, as the
        # same edits made in the interface would: Adjust Last Operation undoes to it.
        call(bpy.ops.ed.undo_push, message="Set up the test scene")
        # A long Step runs modally: the interface keeps running and shows progress.
        result = call(bpy.ops.moldtex.step, 'INVOKE_DEFAULT', steps=LONG_STEP)
        check(result == {'RUNNING_MODAL'}, f"a {LONG_STEP}-step Step runs modally ({result})")
        goto("stepping")
        return 0.25
    if phase == "stepping":
        entry = live.get(NAME)
        if entry.stepping and waited() < 120.0:
            STATE["seen_stepping"] = entry.stats["step_count"]
            return 0.25
        check(not entry.stepping, "the Step ended")
        check(entry.stats["step_count"] == STATE["before_step"] + LONG_STEP,
              f"it ran {LONG_STEP} steps ({STATE['before_step']} → {entry.stats['step_count']})")
        check(STATE["before_step"] < STATE.get("seen_stepping", -1)
              < STATE["before_step"] + LONG_STEP,
              f"the timer saw it part-way ({STATE.get('seen_stepping')}): the interface "
              f"ran while it stepped")
        # Adjust Last Operation: the Step again with 120 steps, from where it started.
        last = bpy.context.window_manager.operators[-1]
        check(last.bl_idname == "MOLDTEX_OT_step", f"Step is the last operation "
                                                   f"({last.bl_idname})")
        last.properties.steps = 120
        result = call(bpy.ops.ed.undo_redo)
        check(result == {'FINISHED'}, f"redo ({result})")
        STATE["redone"] = True
        goto("redone")
        return 1.0
    if phase == "redone":
        entry = live.get(NAME)
        check(entry.stats["step_count"] == STATE["before_step"] + 120,
              f"Adjust Last Operation reran the Step with 120 steps from where it started "
              f"({STATE['before_step']} → {entry.stats['step_count']})")
        call(bpy.ops.moldtex.step, 'INVOKE_DEFAULT', steps=180)  # back to 300 in all
        goto("stepping_again")
        return 0.5
    if phase == "stepping_again":
        entry = live.get(NAME)
        if entry.stepping and waited() < 120.0:
            return 0.5
        goto("network")
        return 1.0
    if phase == "network":
        # Eevee compiles the material in the background: wait until it draws the network.
        correlation, _screen_std, _pixel_std = screen_vs_pixels("network")
        if not correlation > MIN_CORRELATION and waited() < WAIT_LIMIT:
            return 1.0
        check(correlation > MIN_CORRELATION,
              f"after 300 steps the viewport shows the network ({correlation:.3f})")
        STATE["network_std"] = _screen_std
        time.sleep(0.5)
        goto("settled")
        return 3.0  # let Eevee finish its samples: the stale state is an old, done one
    if phase == "settled":
        check(call(bpy.ops.moldtex.reset, 'INVOKE_DEFAULT') == {'FINISHED'}, "reset")
        goto("after_reset")
        return 2.0
    if phase == "after_reset":
        _correlation, screen_std, pixel_std = screen_vs_pixels("after_reset")
        check(pixel_std == 0.0, "after Reset the pixels are blank")
        check(screen_std < MAX_BLANK_STD,
              f"after Reset the viewport shows the blank image, not the network "
              f"(cell std {screen_std:.4f} < {MAX_BLANK_STD}; the network had "
              f"{STATE['network_std']:.3f})")
        check(call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT') == {'RUNNING_MODAL'}, "start")
        goto("running")
        STATE["samples"] = []
        return 2.0
    if phase == "running":
        entry = live.get(NAME)
        correlation, _screen_std, pixel_std = screen_vs_pixels("running")
        if pixel_std > 0.0:
            STATE["samples"].append((entry.stats["step_count"], correlation))
        if waited() < 8.0:
            return 1.0
        worst = min((c for _s, c in STATE["samples"]), default=float("nan"))
        check(len(STATE["samples"]) >= 3 and worst > MIN_CORRELATION,
              f"while running, each screenshot shows the pixels drawn "
              f"(steps, correlation: {[(s, round(c, 3)) for s, c in STATE['samples']]})")
        call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')  # pause
        goto("bake")
        return 1.0
    if phase == "bake":
        entry = live.get(NAME)
        check(not entry.running, "paused")
        settings = obj.moldtex
        settings.bake_use_scene_range = False
        settings.bake_frame_start, settings.bake_frame_end = 1, 200
        settings.bake_steps_per_frame = 20
        settings.bake_directory = STATE["tmp"] + "/bake/"
        STATE["live_steps"] = entry.stats["step_count"]
        check(call(bpy.ops.moldtex.bake, 'INVOKE_DEFAULT') == {'RUNNING_MODAL'},
              "bake starts")
        goto("baking")
        return 1.0
    if phase == "baking":
        entry = live.get(NAME)
        progress = entry.bake_progress or {}
        if progress.get("frames_done", 0) < 10 and waited() < 60.0:
            return 0.5
        call(bpy.ops.moldtex.bake, 'INVOKE_DEFAULT')  # the button again = cancel
        goto("cancelled")
        return 1.0
    if phase == "cancelled":
        entry = live.get(NAME)
        check(not entry.baking, f"bake cancelled ({entry.bake_summary})")
        check(call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT') == {'RUNNING_MODAL'},
              "start after the cancelled bake")
        STATE["samples"] = []
        goto("after_bake")
        return 2.0
    if phase == "after_bake":
        entry = live.get(NAME)
        correlation, _screen_std, pixel_std = screen_vs_pixels("after_bake")
        sim_steps = entry.sim.get_stats()["step_count"] if not entry.baking else None
        STATE["samples"].append((entry.stats["step_count"], sim_steps, correlation))
        if waited() < 5.0:
            return 1.0
        check(all(c > MIN_CORRELATION for _a, _b, c in STATE["samples"]),
              f"after the cancelled bake the viewport shows the live pixels "
              f"(panel steps, core steps, correlation: {STATE['samples']})")
        check(all(a == b for a, b, _c in STATE["samples"]),
              "the panel's step count is the simulation's")
        call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')  # pause
        goto("intrinsic_start")
        return 1.0
    # The Intrinsic domain: Start first builds the triangulation on the core's thread
    # (~180 k vertices at 512², seconds here) while the interface runs and shows its
    # progress; Start pressed again cancels it; once built, the simulation uses it.
    if phase == "intrinsic_start":
        entry = live.get(NAME)
        check(not entry.running, "paused before the Intrinsic domain")
        settings = obj.moldtex
        settings.model = 'CONTINUOUS'
        settings.domain = 'INTRINSIC'
        settings.resolution = "512"
        check(call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT') == {'RUNNING_MODAL'},
              "Start with the Intrinsic domain runs modally")
        goto("intrinsic_building")
        return 0.3
    if phase == "intrinsic_building":
        progress = live.domain_build_status(obj)
        check(progress is not None and progress["state"] == 0 and progress["fraction"] < 1.0,
              f"the triangulation builds while the interface runs ({progress})")
        check(not live.get(NAME).running, "the simulation waits for it")
        call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')  # pressed again: cancel
        goto("intrinsic_cancelled")
        return 1.0
    if phase == "intrinsic_cancelled":
        entry = live.get(NAME)
        check(live.domain_build_status(obj) is None and not entry.running,
              "Start pressed again cancelled the build, and nothing started")
        check(entry.sim.get_config()["domain"] == 0,
              "the simulation is the one from before (Texture domain)")
        # Count the mesh exports of this Start: the build's arrays make the simulation too.
        STATE["export_object"] = live.export_object
        EXPORTS.clear()

        def counting_export(*args, **kwargs):
            EXPORTS.append(args[0].name)
            return STATE["export_object"](*args, **kwargs)

        live.export_object = counting_export
        check(call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT') == {'RUNNING_MODAL'},
              "Start again")
        goto("intrinsic_running")
        return 0.5
    if phase == "intrinsic_running":
        entry = live.get(NAME)
        if not entry.running and waited() < 60.0:
            return 0.5
        info = entry.domain_info or {}
        check(entry.running and info.get("domain") == 1 and info.get("from_cache"),
              f"after the build the simulation runs on the triangulation it made ({info})")
        print(f"     intrinsic: {info.get('cell_count', 0):,} vertices, built ahead in "
              f"{waited():.1f} s")
        check(EXPORTS == [NAME], f"Start read the mesh once, for the build and the "
                                 f"simulation ({len(EXPORTS)} exports)")
        live.export_object = STATE["export_object"]
        call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')  # pause
        goto("intrinsic_bake")
        return 1.0
    # Bake builds ahead too (another resolution: a triangulation not built yet).
    if phase == "intrinsic_bake":
        obj.moldtex.resolution = "256"
        check(call(bpy.ops.moldtex.bake, 'INVOKE_DEFAULT') == {'RUNNING_MODAL'},
              "Bake with the Intrinsic domain runs modally")
        progress = live.domain_build_status(obj)
        check(progress is not None and progress["state"] == 0,
              f"it builds the triangulation first ({progress})")
        goto("intrinsic_baking")
        return 0.5
    if phase == "intrinsic_baking":
        entry = live.get(NAME)
        # (entry.bake_progress still holds the cancelled bake's until the new one starts)
        started = entry.baking and (entry.config or {}).get("width") == 256
        frames = (entry.bake_progress or {}).get("frames_done", 0) if started else 0
        if frames < 2 and waited() < 60.0:
            return 0.5
        info = entry.domain_info or {}
        check(started and frames >= 2 and info.get("from_cache") and info.get("domain") == 1
              and 0 < info.get("cell_count", 0) < 100000,
              f"then the bake runs on the 256² triangulation it built ({frames} frames; {info})")
        call(bpy.ops.moldtex.bake, 'INVOKE_DEFAULT')  # cancel
        goto("bare_setup")
        return 1.0
    # A mesh without UVs (issue 11): the Intrinsic domain runs on it and the viewport
    # shows its vertex colours through the material's Color Attribute node.
    if phase == "bare_setup":
        check(not live.get(NAME).baking, "the Intrinsic bake was cancelled")
        for other in list(bpy.data.objects):
            bpy.data.objects.remove(other, do_unlink=True)
        call(bpy.ops.mesh.primitive_grid_add, x_subdivisions=128, y_subdivisions=128, size=2.0)
        bare = bpy.context.view_layer.objects.active
        bare.name = BARE
        while len(bare.data.uv_layers):
            bare.data.uv_layers.remove(bare.data.uv_layers[0])
        settings = bare.moldtex
        settings.model = 'CONTINUOUS'
        settings.domain = 'INTRINSIC'
        comparable_pattern(settings)
        check(call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT') == {'RUNNING_MODAL'},
              "Start on a mesh without UVs (Intrinsic domain)")
        goto("bare_running")
        return 1.0
    if phase == "bare_running":
        entry = live.get(BARE)
        steps = entry.stats.get("step_count", 0) if entry is not None and entry.has_sim else 0
        if steps < 150 and waited() < 90.0:
            return 0.5
        check(steps >= 150 and entry.vertex_colours, f"it runs and colours the vertices "
                                                     f"({steps} steps)")
        call(bpy.ops.moldtex.start, 'INVOKE_DEFAULT')  # pause
        goto("bare_shown")
        return 2.0
    if phase == "bare_shown":
        bare = bpy.data.objects[BARE]
        correlation, screen_std, vertex_std = screen_vs_vertices(bare, "no_uvs")
        if not correlation > MIN_VERTEX_CORRELATION and waited() < WAIT_LIMIT:
            return 1.0  # (Eevee compiles the new material)
        check(correlation > MIN_VERTEX_CORRELATION,
              f"the viewport shows the vertex colours ({correlation:.3f}; cell std "
              f"{screen_std:.3f} on screen, {vertex_std:.3f} from the vertices)")
        goto("end")
        return 0.5
    if phase == "end":
        finish()
    return None


bpy.types.SpaceView3D.draw_handler_add(on_draw, (), 'WINDOW', 'POST_PIXEL')
bpy.app.timers.register(tick, first_interval=1.0)
