# SPDX-License-Identifier: GPL-3.0-or-later
"""The Blender image that shows the pheromone, and the fast pixel upload.

Fast path: the core copies RGBA floats into a persistent array.array('f') and the same
array goes to Image.pixels.foreach_set (buffer protocol, no per-element Python work).
"""

import array

import bpy


def image_name(obj):
    return f"Moldtex {obj.name}"


def ensure_image(obj, width, height):
    """The object's pheromone image, created (float, Non-Color) or resized as needed."""
    settings = obj.moldtex
    image = settings.image
    if image is None:
        image = bpy.data.images.get(image_name(obj))
    if image is None:
        image = bpy.data.images.new(image_name(obj), width, height, alpha=True,
                                    float_buffer=True)
        image.colorspace_settings.name = 'Non-Color'
    elif tuple(image.size) != (width, height):
        if image.source == 'GENERATED':
            image.use_generated_float = True
            image.generated_width = width
            image.generated_height = height
        else:
            image.scale(width, height)
    if settings.image != image:
        settings.image = image
    return image


def read_pixels(image):
    """The image's pixels as one array('f') of width * height * channels floats."""
    width, height = image.size
    pixels = array.array("f", bytes(4 * image.channels * width * height))
    image.pixels.foreach_get(pixels)
    return pixels


def resample_nearest(source, source_width, source_height, channels, width, height):
    """RGBA floats of width × height from `channels`-channel pixels (nearest texel)."""
    fields = array.array("f", bytes(4 * 4 * width * height))
    count = min(channels, 4)
    columns = [min(source_width - 1, int((x + 0.5) * source_width / width))
               for x in range(width)]
    for y in range(height):
        row = min(source_height - 1, int((y + 0.5) * source_height / height))
        base = row * source_width
        target = 4 * y * width
        for x, column in enumerate(columns):
            start = channels * (base + column)
            out = target + 4 * x
            fields[out:out + count] = source[start:start + count]
    return fields


def upload(image, pixels):
    """Copies an RGBA float buffer of exactly the image's size into the image, and
    tells the viewport to draw it afresh."""
    image.pixels.foreach_set(pixels)
    image.update()
    # Setting pixels frees the image's GPU texture and redraws the viewport, but
    # Eevee's Material Preview keeps adding its new samples to the ones it accumulated
    # so far (temporal anti-aliasing), and once it has all of them it only shows that
    # accumulation: after Reset the old network stayed on screen, and while running the
    # texture was a blur of older states. A depsgraph update of the image restarts the
    # accumulation (Eevee's view_update); it does not recompile the material.
    # Checked by blender_tests/gui_viewport.py.
    image.update_tag()


def pack_for_save(image):
    """Packs a generated pheromone image so its pixels are saved in the .blend."""
    if image is None or image.source not in {'GENERATED', 'FILE'}:
        return
    if image.packed_file is not None and not image.is_dirty:
        return
    if image.source == 'FILE' and not image.is_dirty:
        return
    image.file_format = 'OPEN_EXR'
    image.pack()
