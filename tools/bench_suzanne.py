"""Benchmark (issues 15 and 11): MoMaS on Suzanne with Subdivision 2 against a UV sphere,
both from Blender's own primitives, at 1024^2 with 300 k agents on the CPU backend (all
cores), core defaults otherwise. Prints agent-steps per second for each mesh (median of
alternated runs) and Suzanne's figure as a share of the sphere's. --intrinsic runs the
continuous model on the Intrinsic domain instead (issue 11's target case; the
triangulation's size from the texture, built before the timing starts).

  blender -b --factory-startup --python-exit-code 1 -P tools/bench_suzanne.py -- \
      --addon-dir build/addon [--runs 5] [--steps 20] [--intrinsic] [--threads N]

A benchmark, not a test: it asserts nothing and prints figures for docs/PERFORMANCE.md.
Suzanne is a real model's mesh: 15.7 k triangles after two subdivisions, many UV islands,
triangles of very different sizes, so agents cross edges far more often than on the
64 x 32 sphere (4 k triangles).
"""

import argparse
import os
import statistics
import sys
import time


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description="Suzanne vs UV sphere, agent-steps/s")
    parser.add_argument("--addon-dir", required=True)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--agents", type=int, default=300000)
    parser.add_argument("--resolution", type=int, default=1024)
    parser.add_argument("--intrinsic", action="store_true",
                        help="the continuous model on the Intrinsic domain (default: MoMaS on the texture)")
    parser.add_argument("--threads", type=int, default=0, help="0: all cores")
    return parser.parse_args(argv)


def make_objects():
    import bpy
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    bpy.ops.mesh.primitive_monkey_add(calc_uvs=True)
    suzanne = bpy.context.active_object
    subdivision = suzanne.modifiers.new("Subdivision", 'SUBSURF')
    subdivision.levels = 2
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, calc_uvs=True)
    sphere = bpy.context.active_object
    return {"suzanne": suzanne, "sphere": sphere}


def main():
    args = parse_args()
    sys.path.insert(0, os.path.abspath(args.addon_dir))
    import bpy
    from moldtex import engine
    from moldtex.data import mesh_export
    if not engine.available():
        sys.exit(engine.status_text())
    depsgraph = bpy.context.evaluated_depsgraph_get()
    sims = {}
    for name, obj in make_objects().items():
        arrays = mesh_export.export_object(obj, depsgraph)
        surface = engine.Surface(arrays.positions, arrays.triangles, arrays.uvs, arrays.triangle_uvs)
        config = {"width": args.resolution, "height": args.resolution, "agent_count": args.agents, "seed": 1}
        if args.intrinsic:
            config.update(model=engine.MODEL_CONTINUOUS, domain=engine.DOMAIN_INTRINSIC)
        sim = engine.Simulation(surface, config=config, params={"thread_count": args.threads})
        sim.step(args.steps)  # warm up: first touches, a sort, the pattern starting
        sims[name] = (surface, sim, arrays.triangle_count)
    rates = {name: [] for name in sims}
    for _ in range(args.runs):  # alternated, so drift in the machine's load hits both
        for name, (_, sim, _) in sims.items():
            start = time.perf_counter()
            sim.step(args.steps)
            rates[name].append(args.agents * args.steps / (time.perf_counter() - start))
    median = {name: statistics.median(values) for name, values in rates.items()}
    for name, (_, _, triangles) in sims.items():
        print(f"{name:8s} {triangles:6d} triangles, {args.resolution}^2, {args.agents} agents: "
              f"{median[name] / 1e6:.2f} M agent-steps/s (median of {args.runs} x {args.steps} steps; "
              f"runs {', '.join(f'{v / 1e6:.2f}' for v in rates[name])})")
    what = "continuous model, Intrinsic domain" if args.intrinsic else "MoMaS, texture domain"
    print(f"suzanne / sphere = {median['suzanne'] / median['sphere']:.2f} ({what}, "
          f"{args.threads or 'all'} threads)")


main()
