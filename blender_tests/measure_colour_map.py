"""Measures Colour Map from Image on a 4K (3840 x 2160) image: reading the pixels
(Image.pixels.foreach_get into an array('f'), no numpy) and the core's
moldtex_colour_ramp_from_pixels, for a float and an 8-bit image. A measurement, not a
test: it prints figures and never fails on a timing.

  blender -b --factory-startup -P blender_tests/measure_colour_map.py -- --addon-dir build/addon
  build/venv-bpy/bin/python blender_tests/measure_colour_map.py --addon-dir build/addon
"""

import argparse
import array
import os
import sys
import time


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser()
    parser.add_argument("--addon-dir", required=True)
    parser.add_argument("--width", type=int, default=3840)
    parser.add_argument("--height", type=int, default=2160)
    args = parser.parse_args(argv)

    import bpy
    import addon_utils
    sys.path.insert(0, os.path.abspath(args.addon_dir))
    addon_utils.enable("moldtex", default_set=True)
    from moldtex.colour import colour_map
    from moldtex import engine
    from moldtex.data import image_io

    width, height = args.width, args.height
    # One row: black -> red -> yellow -> white along x; every row the same.
    row = array.array("f")
    for x in range(width):
        s = 3.0 * (x + 0.5) / width
        row.extend((min(s, 1.0), min(max(s - 1.0, 0.0), 1.0), min(max(s - 2.0, 0.0), 1.0), 1.0))
    pixels = row * height
    for float_buffer in (True, False):
        image = bpy.data.images.new(f"Measure {float_buffer}", width, height, alpha=True,
                                    float_buffer=float_buffer)
        image.pixels.foreach_set(pixels)
        start = time.perf_counter()
        read, channels, srgb = colour_map.image_colours(image)
        read_seconds = time.perf_counter() - start
        start = time.perf_counter()
        stops, info = engine.colour_ramp_from_pixels(read, channels=channels, srgb_encoded=srgb)
        core_seconds = time.perf_counter() - start
        print(f"{width}x{height} {'float' if float_buffer else '8-bit'} image: read pixels "
              f"{read_seconds:.3f} s, core {core_seconds:.3f} s, total "
              f"{read_seconds + core_seconds:.3f} s; {len(stops)} stops, explained "
              f"{info['explained']:.3f}, mean error {info['mean_error']:.2f} dE")
        bpy.data.images.remove(image)
        del read
    del image_io


if __name__ == "__main__":
    main()
