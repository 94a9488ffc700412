#include "domain/corner_raster.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "domain/texture_domain.h"

namespace moldtex {

namespace {

// Barycentric weights of the UV point (u, v) in triangle t's UV corners, clamped into
// the triangle (a texel centre on a shared edge may lie a rounding error outside).
void texel_bary(const Surface& s, uint32_t t, double u, double v, double b[3]) {
  const float* uv = &s.corner_uvs[6 * t];
  const double e1u = uv[2] - uv[0], e2u = uv[4] - uv[0];
  const double e1v = uv[3] - uv[1], e2v = uv[5] - uv[1];
  const double det = e1u * e2v - e2u * e1v;  // non-zero: degenerate triangles cover no texel
  const double du = u - uv[0], dv = v - uv[1];
  b[1] = (e2v * du - e2u * dv) / det;
  b[2] = (-e1v * du + e1u * dv) / det;
  b[0] = 1.0 - b[1] - b[2];
  double sum = 0;
  for (int k = 0; k < 3; ++k) sum += b[k] = std::max(0.0, b[k]);
  for (int k = 0; k < 3; ++k) b[k] /= sum;
}

}  // namespace

void rasterize_corners(const Surface& s, uint32_t width, uint32_t height,
                       const float* corner_rgba, size_t corner_float_count, float* rgba,
                       size_t float_count) {
  if (width < kMinRasterSide || height < kMinRasterSide || width > kMaxRasterSide ||
      height > kMaxRasterSide)
    fail(width > kMaxRasterSide || height > kMaxRasterSide ? MOLDTEX_ERROR_TOO_LARGE
                                                           : MOLDTEX_ERROR_INVALID_ARGUMENT,
         "Texture size " + std::to_string(width) + " x " + std::to_string(height) + " is outside " +
             std::to_string(kMinRasterSide) + " .. " + std::to_string(kMaxRasterSide) +
             " texels per side");
  if (corner_rgba == nullptr || rgba == nullptr)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "NULL argument");
  const size_t need_corners = static_cast<size_t>(s.triangle_count()) * 12;
  if (corner_float_count != need_corners)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The corner values need triangle_count * 3 corners * 4 floats (" +
             std::to_string(need_corners) + "), got " + std::to_string(corner_float_count));
  const size_t texels = static_cast<size_t>(width) * height;
  if (float_count < texels * 4)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The RGBA buffer is too small: it needs width * height * 4 floats (" +
             std::to_string(texels * 4) + ")");
  for (size_t i = 0; i < corner_float_count; ++i)
    if (!std::isfinite(corner_rgba[i]))
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
           "The corner values contain a NaN or infinite value at triangle " +
               std::to_string(i / 12) + ", corner " + std::to_string(i / 4 % 3));

  ThreadPool pool(0);
  const TextureDomain d = build_texture_domain(s, width, height, pool);
  pool.parallel_for(height, 4, [&](size_t begin, size_t end) {
    for (size_t y = begin; y < end; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        const size_t i = y * width + x;
        float* out = rgba + 4 * i;
        if (d.classes[i] != MOLDTEX_TEXEL_INSIDE) {
          std::fill(out, out + 4, 0.f);
          continue;
        }
        const uint32_t t = static_cast<uint32_t>(d.texel_triangle[i]);
        double b[3];
        texel_bary(s, t, (x + 0.5) / width, (y + 0.5) / height, b);
        const float* c = corner_rgba + 12 * static_cast<size_t>(t);
        for (int ch = 0; ch < 4; ++ch)
          out[ch] = static_cast<float>(b[0] * c[ch] + b[1] * c[4 + ch] + b[2] * c[8 + ch]);
      }
  });
  // Gutter sources are island texels, filled above.
  for (size_t g = 0; g < d.gutter_texel.size(); ++g)
    std::copy_n(rgba + 4 * static_cast<size_t>(d.gutter_source[g]), 4,
                rgba + 4 * static_cast<size_t>(d.gutter_texel[g]));
}

}  // namespace moldtex
