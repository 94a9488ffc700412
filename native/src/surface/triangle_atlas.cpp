#include "surface/triangle_atlas.h"

#include <cmath>

namespace moldtex {

std::vector<float> triangle_atlas_uvs(uint32_t triangle_count) {
  uint32_t g = static_cast<uint32_t>(std::ceil(std::sqrt(static_cast<double>(triangle_count))));
  while (static_cast<uint64_t>(g) * g < triangle_count) ++g;  // sqrt's rounding
  if (g == 0) g = 1;
  const double cell = 1.0 / g, lo = 0.15 * cell, hi = 0.85 * cell;
  std::vector<float> uvs(6ull * triangle_count);
  for (uint32_t t = 0; t < triangle_count; ++t) {
    const double u0 = (t % g) * cell, v0 = (t / g) * cell;
    const double corners[6] = {u0 + lo, v0 + lo, u0 + hi, v0 + lo, u0 + lo, v0 + hi};
    for (int k = 0; k < 6; ++k) uvs[6ull * t + k] = static_cast<float>(corners[k]);
  }
  return uvs;
}

}  // namespace moldtex
