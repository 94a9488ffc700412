// Per-corner values baked into a texture over the UV layout
// (moldtex_surface_rasterize_corners): the texture domain's texel -> triangle raster
// decides which triangle a texel belongs to, its gutter decides what a gutter texel
// copies, so the image lines up texel for texel with a simulation's of the same size.
#pragma once
#include <cstddef>
#include <cstdint>

#include "surface/surface.h"

namespace moldtex {

// Texture sides accepted here: the simulation's limits (sim.cpp).
constexpr uint32_t kMinRasterSide = 8, kMaxRasterSide = 16384;

// Validates the request (sizes, counts, finite values) and writes width * height * 4
// floats to rgba (capacity float_count). Throws moldtex::Error with a user-facing
// message.
void rasterize_corners(const Surface& surface, uint32_t width, uint32_t height,
                       const float* corner_rgba, size_t corner_float_count, float* rgba,
                       size_t float_count);

}  // namespace moldtex
