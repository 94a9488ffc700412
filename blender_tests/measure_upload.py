"""Measures the pixel upload at 2048²: moldtex_sim_read_rgba into a persistent
array('f'), Image.pixels.foreach_set of that array, and Image.update(). A measurement,
not a test: it prints figures and never fails on a timing.

  blender -b --factory-startup -P blender_tests/measure_upload.py -- --addon-dir build/addon
  build/venv-bpy/bin/python blender_tests/measure_upload.py --addon-dir build/addon
"""

import argparse
import os
import statistics
import sys
import time


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser()
    parser.add_argument("--addon-dir", required=True)
    parser.add_argument("--size", type=int, default=2048)
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args(argv)

    import bpy
    import addon_utils
    sys.path.insert(0, os.path.abspath(args.addon_dir))
    addon_utils.enable("moldtex", default_set=True)
    from moldtex import engine
    from moldtex.data import image_io
    from moldtex.sim import session as live

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    bpy.ops.mesh.primitive_uv_sphere_add(calc_uvs=True)
    obj = bpy.context.active_object
    settings = obj.moldtex
    settings.resolution = str(args.size)
    settings.agent_count = 100000
    assert bpy.ops.moldtex.reset() == {'FINISHED'}
    assert bpy.ops.moldtex.step(steps=20) == {'FINISHED'}
    entry = live.get(obj.name)
    image = image_io.ensure_image(obj, args.size, args.size)

    read, put, update, total = [], [], [], []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        live.read_pixels(entry)                 # core -> array('f')
        t1 = time.perf_counter()
        image.pixels.foreach_set(entry.pixels)  # array('f') -> Blender image
        t2 = time.perf_counter()
        image.update()
        t3 = time.perf_counter()
        read.append(t1 - t0)
        put.append(t2 - t1)
        update.append(t3 - t2)
        total.append(t3 - t0)

    def ms(values):
        return f"{1e3 * statistics.median(values):6.1f} ms (min {1e3 * min(values):.1f})"

    print(f"Blender {bpy.app.version_string}, {engine.status_text()}, "
          f"{args.size}x{args.size} RGBA float, median of {args.repeats}:")
    print(f"  read_rgba       {ms(read)}")
    print(f"  foreach_set     {ms(put)}")
    print(f"  image.update    {ms(update)}")
    print(f"  upload total    {ms(total)}")
    sys.stdout.flush()
    if not bpy.app.binary_path:  # bpy module: skip its crash-prone teardown
        os._exit(0)


if __name__ == "__main__":
    main()
