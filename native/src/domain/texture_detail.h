// A simulation finer than its image (moldtex_sim_config.detail): the texture domain runs
// at detail x detail texels per image texel, and whatever crosses the API per texel
// (the image, its classes, fields and maps) is converted here. Image texel (x, y) covers
// the fine texels (detail * x + i, detail * y + j), 0 <= i, j < detail.
#pragma once
#include <cstdint>
#include <vector>

#include "domain/texture_domain.h"

namespace moldtex {

// Per-image-texel values (`channels` interleaved per texel, width * height texels) given
// to every fine texel the image texel covers.
std::vector<float> finer_texels(const float* image, uint32_t width, uint32_t height, uint32_t channels,
                                uint32_t detail);

// `planes` planes of the fine domain `fine` (plane after plane) as planes of the image:
// each image texel the mean of its fine texels that are not outside the islands (cells
// and gutter, whose values are those across the seam), 0 where all are outside.
std::vector<float> image_planes(const std::vector<float>& fine, uint32_t planes, const TextureDomain& fine_domain,
                                uint32_t detail);

// The image texels' classes: inside where any fine texel is inside, else gutter where
// any is gutter, else outside.
std::vector<uint8_t> image_classes(const TextureDomain& fine_domain, uint32_t detail);

}  // namespace moldtex
