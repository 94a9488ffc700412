"""Two demo scenes of controllable patterns (layton-intrinsic-slime.md §3.3, Fig. 6, 8;
issue 12), built the way an artist would with the Map Tools and the Maps panel:

  stripes_along_a_limb  a long cylinder; Geodesic Distance from its base, Gradient to
                        Bias, Bias Symmetry 2: the continuous model's trails run along
                        the limb (Fig. 6's aligned stripes)
  veins_toward_a_sink   a disc (a square plane whose outside is a sink too); agents are
                        reborn on a rim band (Spawn map), pulled down the distance to a
                        sink at the centre (Lifetime map 0, bias toward it): branching
                        veins (Fig. 8)

  blender -b --factory-startup --python-exit-code 1 -P tools/demo_scenes.py -- \\
      --addon-dir build/addon --out out/demos

Writes <scene>.blend (settings, groups, maps and the grown image packed) and
<scene>.png (u / U, 8-bit) for each. The functions are reused by
blender_tests/test_demo_scenes.py at a smaller size.
"""

import argparse
import math
import os
import sys


def parse_args(argv):
    parser = argparse.ArgumentParser(description="Build Moldtex's demo scenes.")
    parser.add_argument("--addon-dir", required=True, help="the staged add-on (build/addon)")
    parser.add_argument("--out", required=True, help="output folder (created if needed)")
    parser.add_argument("--resolution", default="512", choices=["128", "256", "512", "1024", "2048"])
    parser.add_argument("--agents", type=int, default=60000)
    parser.add_argument("--seconds", type=float, default=6.0)
    return parser.parse_args(argv)


def fail(message):
    print(f"demo_scenes: {message}", file=sys.stderr)
    sys.exit(1)


def clear():
    import bpy
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)


def activate(obj):
    import bpy
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    return obj


def group(obj, name, inside):
    """A vertex group of weight 1 on the vertices where inside(co) holds."""
    vertex_group = obj.vertex_groups.new(name=name)
    vertex_group.add([v.index for v in obj.data.vertices if inside(v.co)], 1.0, 'REPLACE')
    return vertex_group


def set_map(obj, key, attribute, at0=None, at1=None):
    slot = getattr(obj.moldtex.maps, key)
    slot.source = 'ATTRIBUTE'
    slot.attribute = attribute
    if at0 is not None:
        slot.at0 = at0
    if at1 is not None:
        slot.at1 = at1
    slot.enabled = True


def continuous(obj, resolution, agents):
    settings = obj.moldtex
    settings.model = 'CONTINUOUS'
    settings.resolution = resolution
    settings.agent_count = agents
    cont = settings.continuous
    cont.mean_lifetime = 0.5
    cont.activation_time = 0.2
    return cont


def gradient_bias(obj, source_group, toward):
    """Map Tools: geodesic distance from `source_group`, then its gradient as the bias
    attribute (unit vectors toward 'UP' (away) or 'DOWN' (toward the source))."""
    import bpy
    tools = obj.moldtex_map_tools
    tools.distance_source = source_group
    if bpy.ops.moldtex.map_distance() != {'FINISHED'}:
        fail(f"Geodesic Distance failed on {obj.name}")
    tools.gradient_source = tools.distance_group
    tools.gradient_direction = toward
    tools.gradient_normalize = True
    if bpy.ops.moldtex.map_gradient_bias() != {'FINISHED'}:
        fail(f"Gradient to Bias failed on {obj.name}")
    cont = obj.moldtex.continuous
    cont.bias_source = 'ATTRIBUTE'
    cont.bias_attribute = tools.gradient_attribute


def stripes_along_a_limb(resolution="512", agents=60000, bias=True):
    """A cylinder 4 long, radius 0.5, along z, cut into rings so distances are smooth."""
    import bpy
    clear()
    bpy.ops.mesh.primitive_cylinder_add(vertices=48, radius=0.5, depth=4.0, calc_uvs=True,
                                        end_fill_type='NOTHING')
    obj = activate(bpy.context.active_object)
    obj.name = "Limb"
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.subdivide(number_cuts=23)
    bpy.ops.object.mode_set(mode='OBJECT')
    group(obj, "Base", lambda co: co.z < -1.99)
    cont = continuous(obj, resolution, agents)
    if bias:
        gradient_bias(obj, "Base", 'UP')
        cont.bias_strength = 8.0
        cont.bias_symmetry = 2  # along the limb, either way
    return obj


def veins_toward_a_sink(resolution="512", agents=60000, bias=True):
    """A 2 x 2 plane cut into 48 x 48 quads; the disc of radius 1 is the surface."""
    import bpy
    clear()
    bpy.ops.mesh.primitive_plane_add(size=2.0, calc_uvs=True)
    obj = activate(bpy.context.active_object)
    obj.name = "Disc"
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.subdivide(number_cuts=47)
    bpy.ops.object.mode_set(mode='OBJECT')
    radius = lambda co: math.hypot(co.x, co.y)
    group(obj, "Sink", lambda co: radius(co) < 0.06)
    group(obj, "Sinks", lambda co: radius(co) < 0.06 or radius(co) > 0.97)
    group(obj, "Rim", lambda co: 0.6 < radius(co) < 0.95)
    cont = continuous(obj, resolution, agents)
    set_map(obj, "mean_lifetime", "Sinks")   # At 1 = 0: agents die there
    set_map(obj, "spawn", "Rim")             # reborn only on the rim band
    if bias:
        gradient_bias(obj, "Sink", 'DOWN')
        cont.bias_strength = 30.0
        cont.bias_spawn = True               # reborn facing the sink
    return obj


SCENES = {"stripes_along_a_limb": stripes_along_a_limb, "veins_toward_a_sink": veins_toward_a_sink}


def grow(obj, seconds):
    """Reset and run `seconds` of simulated time; returns the live entry."""
    import bpy
    from moldtex.sim import session as live
    activate(obj)
    if bpy.ops.moldtex.setup_material() != {'FINISHED'}:
        fail("Setup Material failed")
    if bpy.ops.moldtex.reset() != {'FINISHED'}:
        fail("Reset failed")
    steps = max(1, round(seconds / obj.moldtex.time_step))
    if bpy.ops.moldtex.step(steps=steps) != {'FINISHED'}:
        fail("Step failed")
    return live.get(obj.name)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parse_args(argv)
    import addon_utils
    import bpy
    sys.path.insert(0, os.path.abspath(args.addon_dir))
    if addon_utils.enable("moldtex", default_set=True) is None:
        fail("could not enable the moldtex add-on")
    from moldtex import engine
    if not engine.available():
        fail(engine.status_text())
    os.makedirs(args.out, exist_ok=True)
    for name, build in SCENES.items():
        obj = build(args.resolution, args.agents)
        entry = grow(obj, args.seconds)
        png = os.path.join(args.out, name + ".png")
        entry.sim.write_image(png, engine.IMAGE_PNG8)
        obj.moldtex.image.pack()
        blend = os.path.join(os.path.abspath(args.out), name + ".blend")
        bpy.ops.wm.save_as_mainfile(filepath=blend)
        print(f"demo_scenes: {name}: {png}, {blend}")


if __name__ == "__main__":
    main()
