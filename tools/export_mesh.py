"""Writes Blender's Suzanne with Subdivision 2 (issue #15's real-model benchmark mesh,
15.7 k triangles, Blender's own UVs) to a file that moldtex_ab reads (CASE mesh=FILE),
so the C++ benchmark can time the real mesh without Blender in the loop (--sphere: the
UV sphere that tools/bench_suzanne.py compares it with).

  blender -b --factory-startup --python-exit-code 1 -P tools/export_mesh.py -- \\
      --addon-dir build/addon --out /tmp/suzanne.bin

Format: four little-endian uint32 counts (vertices, triangles, UVs, triangles with UV
indices), then positions (3 float32 each), triangles (3 uint32), UVs (2 float32) and
triangle UV indices (3 uint32), as the add-on passes them to the core.
"""

import argparse
import os
import struct
import sys


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description="export Suzanne (Subdivision 2) for moldtex_ab")
    parser.add_argument("--addon-dir", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--levels", type=int, default=2, help="Suzanne's subdivision levels")
    parser.add_argument("--sphere", action="store_true",
                        help="Blender's UV sphere 64 x 32 instead (the comparison bench_suzanne.py makes)")
    args = parser.parse_args(argv)
    sys.path.insert(0, os.path.abspath(args.addon_dir))
    import bpy
    from moldtex.data import mesh_export
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    if args.sphere:
        bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, calc_uvs=True)
    else:
        bpy.ops.mesh.primitive_monkey_add(calc_uvs=True)
        bpy.context.active_object.modifiers.new("Subdivision", 'SUBSURF').levels = args.levels
    obj = bpy.context.active_object
    arrays = mesh_export.export_object(obj, bpy.context.evaluated_depsgraph_get())
    with open(args.out, "wb") as f:
        f.write(struct.pack("<4I", len(arrays.positions) // 3, len(arrays.triangles) // 3,
                            len(arrays.uvs) // 2, len(arrays.triangle_uvs) // 3))
        for values in (arrays.positions, arrays.triangles, arrays.uvs, arrays.triangle_uvs):
            f.write(values.tobytes())
    print(f"wrote {args.out}: {len(arrays.positions) // 3} vertices, {len(arrays.triangles) // 3} triangles")


main()
