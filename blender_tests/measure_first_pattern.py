"""How long until a network is recognisable on Suzanne? A measurement, not a test: it
prints figures and never fails on a timing (docs/PERFORMANCE.md, "The first seconds").

  build/venv-bpy/bin/python blender_tests/measure_first_pattern.py --addon-dir build/addon \\
      [--config 512:60000 --config 1024:200000 ...] [--steps 1500]

For each resolution:agents it grows the mold on Suzanne (generated UVs, defaults
otherwise) and, every --every steps, measures the pheromone's *network contrast*: the
coefficient of variation (std / mean) of the pheromone averaged over 4 × 4-texel
blocks that lie inside the UV islands. Random trails (the first tens of steps) average
out over a block; a network's veins and empty cells do not. "Recognisable" is the
first step at which the contrast reaches 1.0 (the blocks' std equals their mean: veins
and empty cells over the whole surface); "crisp" is the first at 80% of the contrast
after --steps steps (a formed network, 1.2–1.7). Times are the stepping time and the
process CPU time up to that step (numpy's measure excluded); the live loop's wall time
is measured by measure_live_start.py.
"""

import argparse
import os
import sys
import time


def contrast(np, pheromone, inside, width, height):
    p = pheromone.reshape(height, width)
    m = inside.reshape(height, width)
    h, w = height // 4 * 4, width // 4 * 4
    blocks = p[:h, :w].reshape(h // 4, 4, w // 4, 4).mean(axis=(1, 3))
    full = m[:h, :w].reshape(h // 4, 4, w // 4, 4).all(axis=(1, 3))
    values = blocks[full]
    mean = values.mean()
    return float(values.std() / mean) if mean > 0 else 0.0


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser()
    parser.add_argument("--addon-dir", required=True)
    parser.add_argument("--config", action="append", default=[])
    parser.add_argument("--steps", type=int, default=1500)
    parser.add_argument("--every", type=int, default=10)
    parser.add_argument("--subdivide", type=int, default=0)
    parser.add_argument("--param", action="append", default=[],
                        help="NAME=VALUE: a setting other than its default")
    args = parser.parse_args(argv)
    configs = args.config or ["512:60000", "1024:200000"]

    import bpy
    import addon_utils
    import numpy as np
    sys.path.insert(0, os.path.abspath(args.addon_dir))
    addon_utils.enable("moldtex", default_set=True)
    from moldtex import engine
    from moldtex.sim import session as live

    for config in configs:
        size, agents = (int(v) for v in config.split(":"))
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj, do_unlink=True)
        bpy.ops.mesh.primitive_monkey_add(calc_uvs=True)
        obj = bpy.context.active_object
        if args.subdivide:
            modifier = obj.modifiers.new("Subdivision", 'SUBSURF')
            modifier.levels = args.subdivide
        settings = obj.moldtex
        settings.resolution = str(size)
        settings.agent_count = agents
        for item in args.param:
            name, value = item.split("=")
            setattr(settings, name, type(getattr(settings, name))(value))
        assert bpy.ops.moldtex.reset() == {'FINISHED'}
        entry = live.get(obj.name)
        sim = entry.sim
        inside = np.frombuffer(sim.read_texel_classes(), dtype=np.uint8) == engine.TEXEL_INSIDE
        buffer = np.zeros(size * size * 4, dtype=np.float32)
        curve = []
        stepping = cpu = 0.0
        steps = 0
        while steps < args.steps:
            began, began_cpu = time.perf_counter(), time.process_time()
            sim.step(args.every)
            stepping += time.perf_counter() - began
            cpu += time.process_time() - began_cpu
            steps += args.every
            sim.read_rgba(buffer)
            curve.append((steps, stepping, cpu,
                          contrast(np, buffer[0::4], inside, size, size)))
        reference = curve[-1][3]
        hit = next((point for point in curve if point[3] >= 0.8 * reference), None)
        seen = next((point for point in curve if point[3] >= 1.0), None)
        rate = steps / stepping
        load = os.getloadavg()[0]
        print(f"{size}² {agents} agents (subdivision {args.subdivide}) {' '.join(args.param)}: {rate:.1f} steps/s "
              f"(core; {steps / cpu:.1f} steps per CPU-second, load {load:.1f}), contrast "
              f"after {steps} steps {reference:.3f}; "
              + (f"recognisable (1.0) at step {seen[0]} = {seen[1]:.1f} s of stepping, "
                 f"{seen[2]:.1f} CPU-s; " if seen else "never 1.0; ")
              + (f"crisp (80% of it) at step {hit[0]} = {hit[1]:.1f} s of stepping, "
                 f"{hit[2]:.1f} CPU-s" if hit else "never 80%"))
        print("  curve: " + ", ".join(f"{p[0]}:{p[3]:.2f}" for p in curve[::5]))
        sys.stdout.flush()
    sys.stdout.flush()
    os._exit(0)


if __name__ == "__main__":
    main()
