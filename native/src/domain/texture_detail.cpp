#include "domain/texture_detail.h"

#include "moldtex.h"

namespace moldtex {

std::vector<float> finer_texels(const float* image, uint32_t width, uint32_t height, uint32_t channels,
                                uint32_t detail) {
  const size_t fine_width = size_t(width) * detail;
  std::vector<float> fine(fine_width * height * detail * channels);
  for (size_t y = 0; y < size_t(height) * detail; ++y)
    for (size_t x = 0; x < fine_width; ++x) {
      const float* from = image + ((y / detail) * width + x / detail) * channels;
      float* to = fine.data() + (y * fine_width + x) * channels;
      for (uint32_t c = 0; c < channels; ++c) to[c] = from[c];
    }
  return fine;
}

std::vector<float> image_planes(const std::vector<float>& fine, uint32_t planes, const TextureDomain& d,
                                uint32_t detail) {
  const uint32_t width = d.width / detail, height = d.height / detail;
  const size_t fine_texels = d.texel_count(), texels = size_t(width) * height;
  std::vector<float> image(texels * planes, 0.f);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x) {
      double sum[4] = {0, 0, 0, 0};
      uint32_t count = 0;
      for (uint32_t j = 0; j < detail; ++j)
        for (uint32_t i = 0; i < detail; ++i) {
          const size_t f = (y * detail + j) * d.width + x * detail + i;
          if (d.classes[f] == MOLDTEX_TEXEL_OUTSIDE) continue;
          ++count;
          for (uint32_t k = 0; k < planes && k < 4; ++k) sum[k] += fine[k * fine_texels + f];
        }
      if (count == 0) continue;
      for (uint32_t k = 0; k < planes && k < 4; ++k)
        image[k * texels + y * width + x] = static_cast<float>(sum[k] / count);
    }
  return image;
}

std::vector<uint8_t> image_classes(const TextureDomain& d, uint32_t detail) {
  const uint32_t width = d.width / detail, height = d.height / detail;
  std::vector<uint8_t> image(size_t(width) * height, MOLDTEX_TEXEL_OUTSIDE);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x) {
      uint8_t c = MOLDTEX_TEXEL_OUTSIDE;
      for (uint32_t j = 0; j < detail; ++j)
        for (uint32_t i = 0; i < detail; ++i) {
          const uint8_t f = d.classes[(y * detail + j) * d.width + x * detail + i];
          if (f == MOLDTEX_TEXEL_INSIDE || (f == MOLDTEX_TEXEL_GUTTER && c == MOLDTEX_TEXEL_OUTSIDE)) c = f;
        }
      image[y * width + x] = c;
    }
  return image;
}

}  // namespace moldtex
