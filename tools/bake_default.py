"""Moldtex's main job: grow the default slime-mold texture on Suzanne, bake its growth
as an EXR sequence, and render it.

  blender -b --factory-startup --python-exit-code 1 -P tools/bake_default.py -- \
      --addon-dir build/addon --out out/

Writes into --out: moldtex_sequence/Suzanne_0001.exr .. Suzanne_0024.exr (the growth,
one half-float EXR per frame, written by the core's bake worker, with
Suzanne_metrics.csv and a checkpoint beside them), moldtex_pheromone.png (the raw
pheromone of the last step, 8-bit grey), moldtex_render.png (a small Cycles render) and
moldtex_default.blend (the scene, with the float texture packed in it; Moldtex ▸ Bake
Sequence ▸ Use Baked Sequence plays the frames in its material).

The bake runs first: frame f is the state after f * steps-per-frame steps, so after
frame 24 the simulation has grown 24 * (steps // 24) steps; the remaining few steps run
live, and the still image and render show the state after --steps steps.
"""

import argparse
import math
import os
import sys
import time


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description="Bake the default Moldtex texture.")
    parser.add_argument("--addon-dir", required=True,
                        help="folder holding the staged 'moldtex' add-on (build/addon)")
    parser.add_argument("--out", required=True, help="output folder (created if needed)")
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--agents", type=int, default=300000)
    parser.add_argument("--resolution", default="1024",
                        choices=["256", "512", "1024", "2048", "4096", "8192"])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--subdivisions", type=int, default=2)
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--render-size", default="480x360")
    parser.add_argument("--preset", metavar="NAME",
                        help="a shipped look to apply first (e.g. coral_maze for the "
                             "continuous model); the agent count below still applies")
    parser.add_argument("--frames", type=int, default=24,
                        help="frames of the EXR sequence (0 = no sequence)")
    return parser.parse_args(argv)


def fail(message):
    print(f"bake_default: {message}", file=sys.stderr)
    sys.stderr.flush()
    sys.exit(1)


def enable_addon(addon_dir):
    import addon_utils
    addon_dir = os.path.abspath(addon_dir)
    if not os.path.isfile(os.path.join(addon_dir, "moldtex", "__init__.py")):
        fail(f"no add-on at {addon_dir}/moldtex: build it first "
             f"(cmake -S . -B build && cmake --build build)")
    sys.path.insert(0, addon_dir)
    if addon_utils.enable("moldtex", default_set=True) is None:
        fail("could not enable the moldtex add-on (see the messages above)")
    from moldtex import engine
    if not engine.available():
        fail(engine.status_text())
    print(engine.status_text())


def build_scene(args):
    import bpy
    from mathutils import Vector

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene

    bpy.ops.mesh.primitive_monkey_add(calc_uvs=True)
    suzanne = bpy.context.active_object
    suzanne.name = "Suzanne"
    if len(suzanne.data.uv_layers) == 0:
        bpy.ops.object.mode_set(mode='EDIT')
        bpy.ops.mesh.select_all(action='SELECT')
        bpy.ops.uv.smart_project()
        bpy.ops.object.mode_set(mode='OBJECT')
    for polygon in suzanne.data.polygons:
        polygon.use_smooth = True
    subdivision = suzanne.modifiers.new("Subdivision", 'SUBSURF')
    subdivision.levels = args.subdivisions
    subdivision.render_levels = args.subdivisions

    camera_data = bpy.data.cameras.new("Camera")
    camera_data.lens = 50.0
    camera = bpy.data.objects.new("Camera", camera_data)
    scene.collection.objects.link(camera)
    camera.location = (1.5, -5.6, 1.3)
    direction = Vector((0.0, 0.0, 0.1)) - camera.location
    camera.rotation_euler = direction.to_track_quat('-Z', 'Y').to_euler()
    scene.camera = camera

    key_data = bpy.data.lights.new("Key", 'AREA')
    key_data.energy = 600.0
    key_data.size = 3.0
    key = bpy.data.objects.new("Key", key_data)
    scene.collection.objects.link(key)
    key.location = (-3.0, -3.5, 4.0)
    key.rotation_euler = (Vector((0, 0, 0)) - key.location).to_track_quat(
        '-Z', 'Y').to_euler()

    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    background = world.node_tree.nodes.get("Background")
    if background is not None:
        background.inputs["Color"].default_value = (0.03, 0.03, 0.04, 1.0)
        background.inputs["Strength"].default_value = 1.0

    width, height = (int(v) for v in args.render_size.lower().split("x"))
    render = scene.render
    render.engine = 'CYCLES'
    render.resolution_x = width
    render.resolution_y = height
    render.resolution_percentage = 100
    render.image_settings.file_format = 'PNG'
    render.image_settings.color_mode = 'RGB'
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False  # Debian's Cycles has no OpenImageDenoise
    scene.cycles.device = 'CPU'

    view_layer = bpy.context.view_layer
    view_layer.objects.active = suzanne
    suzanne.select_set(True)
    return suzanne


def bake_sequence(suzanne, args, out):
    """Bakes frames 1..args.frames with the core's bake worker (synchronous in
    background mode, one progress line per frame). Returns (plan, steps done, seconds)."""
    import bpy
    from moldtex.bake import sequence as bake

    settings = suzanne.moldtex
    steps_per_frame = max(1, args.steps // args.frames)
    settings.bake_use_scene_range = False
    settings.bake_frame_start = 1
    settings.bake_frame_end = args.frames
    settings.bake_steps_per_frame = steps_per_frame
    settings.bake_directory = os.path.join(out, "moldtex_sequence")
    settings.bake_format = 'EXR_HALF'
    settings.bake_resume = False
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, args.frames
    began = time.perf_counter()
    # use_sequence=False: the still and the render below show the live texture.
    if bpy.ops.moldtex.bake(object_name=suzanne.name, use_sequence=False) != {'FINISHED'}:
        fail("the sequence bake did not finish")
    return (bake.plan_for(suzanne, scene), args.frames * steps_per_frame,
            time.perf_counter() - began)


def grow(suzanne, args, out):
    import bpy
    from moldtex.sim import session as live

    settings = suzanne.moldtex
    settings.resolution = args.resolution
    settings.agent_count = args.agents
    settings.seed = args.seed
    if bpy.ops.moldtex.setup_material() != {'FINISHED'}:
        fail("Set Up Material failed")
    if bpy.ops.moldtex.reset() != {'FINISHED'}:
        fail("Reset failed")
    entry = live.get(suzanne.name)
    info = entry.surface_info
    print(f"Surface: {info['triangle_count']} triangles, {info['seam_edge_count']} seam "
          f"edges; {args.agents} agents on {args.resolution}² texels")
    done, chunk = 0, 50
    plan = None
    began = time.perf_counter()
    if args.frames > 0:
        plan, done, seconds = bake_sequence(suzanne, args, out)
        print(f"Baked {args.frames} frames ({done} steps) in {seconds:.1f} s")
    while done < args.steps:
        n = min(chunk, args.steps - done)
        if bpy.ops.moldtex.step(steps=n) != {'FINISHED'}:
            fail("Step failed")
        done += n
        stats = entry.stats
        elapsed = time.perf_counter() - began
        if settings.model == 'CONTINUOUS':
            shown = (f"t {stats['time']:5.2f} s  mean u/U "
                     f"{stats['mean_concentration'] / stats['u_metric']:5.3f}")
        else:
            shown = (f"coverage {100 * stats['coverage']:5.1f} %  "
                     f"presence {100 * stats['presence']:5.1f} %")
        print(f"  step {done:5d}/{args.steps}  {shown}  "
              f"{done * args.agents / elapsed / 1e6:5.2f} M agent-steps/s")
        sys.stdout.flush()
    if plan is not None and done == plan.frame_count * plan.steps_per_frame:
        # No live step after the bake: copy its last state into the live image.
        from moldtex.data import image_io
        image = image_io.ensure_image(suzanne, entry.sim.width, entry.sim.height)
        image_io.upload(image, live.read_pixels(entry))
    return time.perf_counter() - began, plan


def main():
    args = parse_args()
    import bpy

    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    enable_addon(args.addon_dir)
    suzanne = build_scene(args)
    if args.preset:
        from moldtex.looks import presets
        path = presets.find(args.preset)
        if not path:
            fail(f"no preset '{args.preset}' (presets: {', '.join(sorted(presets.available()))})")
        if bpy.ops.moldtex.preset_apply(filepath=path) != {'FINISHED'}:
            fail(f"the preset {args.preset} did not apply")
        print(f"Preset: {args.preset} (model {suzanne.moldtex.model})")
    seconds, plan = grow(suzanne, args, out)
    print(f"Grew {args.steps} steps in {seconds:.1f} s")

    scene = bpy.context.scene
    pheromone_path = os.path.join(out, "moldtex_pheromone.png")
    # save_render writes a Non-Color image's raw values (no view transform) and keeps
    # the image generated, so the float pixels stay in the .blend.
    suzanne.moldtex.image.save_render(pheromone_path, scene=scene)

    render_path = os.path.join(out, "moldtex_render.png")
    scene.render.filepath = render_path
    began = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    print(f"Rendered {scene.render.resolution_x}x{scene.render.resolution_y}, "
          f"{scene.cycles.samples} samples in {time.perf_counter() - began:.1f} s")

    blend_path = os.path.join(out, "moldtex_default.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend_path)  # packs the texture (save_pre)

    sequence = ([plan.frame_path(f) for f in range(plan.first_frame, plan.last_frame + 1)]
                if plan is not None else [])
    for path in [pheromone_path, render_path, blend_path] + sequence:
        if not os.path.isfile(path):
            fail(f"{path} was not written")
    print("Moldtex bake written:")
    if plan is not None:
        print(f"  EXR sequence       {plan.directory}/{plan.describe_files()} "
              f"({plan.frame_count} frames, {plan.steps_per_frame} steps each)")
        print(f"  sequence metrics   {plan.metrics_path}")
    print(f"  pheromone texture  {pheromone_path}")
    print(f"  Cycles render      {render_path}")
    print(f"  scene              {blend_path}")
    sys.stdout.flush()
    if not bpy.app.binary_path:  # bpy module: skip its crash-prone teardown
        os._exit(0)


if __name__ == "__main__":
    main()
