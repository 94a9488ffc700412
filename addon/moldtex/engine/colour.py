# SPDX-License-Identifier: GPL-3.0-or-later
"""The colour map from an image (layton-intrinsic-slime.md §3.4): a ramp fitted by the
core's Isomap."""

import ctypes

from . import library
from .library import (_buffer_address, _check, _require)
from .structs import *  # noqa: F401,F403  (the header's constants and structs)


# ---- colour map from an image (Layton et al. §3.4) ----------------------------------

def colour_ramp_from_pixels(pixels, channels=4, srgb_encoded=False, sample_count=1500,
                            max_stops=MAX_RAMP_STOPS, reverse=False, peak_position=-1.0,
                            tolerance=1.0, neighbour_count=10):
    """Colour map of an image's pixel colours (moldtex_colour_ramp_from_pixels):
    pixels is an array('f') (or float32 numpy array) of `channels` (3 or 4) floats per
    pixel. Returns (stops, info): stops = [(position, (r, g, b, a))] in linear RGB,
    darker end first unless reverse; info = dict of moldtex_colour_ramp_info (explained:
    0..1, how well one variable describes the image)."""
    _require()
    address, count = _buffer_address(pixels, ("f",), writable=False)
    desc = ColourRampDesc()
    library._lib.moldtex_colour_ramp_desc_init(ctypes.byref(desc))
    desc.channels = int(channels)
    desc.srgb_encoded = 1 if srgb_encoded else 0
    desc.sample_count = int(sample_count)
    desc.max_stops = int(max_stops)
    desc.reverse = 1 if reverse else 0
    desc.peak_position = float(peak_position)
    desc.tolerance = float(tolerance)
    desc.neighbour_count = int(neighbour_count)
    stops = (ColourStop * MAX_RAMP_STOPS)()
    info = ColourRampInfo()
    library._lib.moldtex_colour_ramp_info_init(ctypes.byref(info))
    pixel_count = count // max(1, int(channels))
    _check(library._lib.moldtex_colour_ramp_from_pixels(ctypes.c_void_p(address), pixel_count,
                                                ctypes.byref(desc), stops, MAX_RAMP_STOPS,
                                                ctypes.byref(info)),
           "Extracting a colour map")
    result = [(float(stops[i].position), tuple(float(c) for c in stops[i].color))
              for i in range(info.stop_count)]
    return result, {name: getattr(info, name) for name, _ in ColourRampInfo._fields_
                    if name != "struct_size"}
