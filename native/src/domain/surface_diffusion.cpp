#include "domain/surface_diffusion.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <type_traits>
#include <vector>

#include "domain/seam_neighbours.h"
#include "shared/field.h"

namespace moldtex {

namespace {

// Passes a texel with per-step variance (ax, ay) in texel^2 needs: ax + ay <= 1 per pass.
uint32_t passes_for(double ax, double ay) {
  const double need = std::ceil(ax + ay - 1e-9);
  return static_cast<uint32_t>(std::clamp(need, 1.0, static_cast<double>(kMaxDiffusionPasses)));
}

// One pass over texels x = 1 .. W - 2 of a row with rows above and below (`row` points at
// the row's texel 0 in a plane of width W): as mtx_surface_diffuse with every neighbour
// present, without the tests for the texture's border; 0 where the texel is no island
// texel. (Not vectorised: GCC 12 does not gather the coefficients by triangle.)
void diffuse_inner_row(const float* row, uint32_t W, const uint8_t* classes, const int32_t* triangle,
                       const float* coef, float evaporation, float* out) {
  const float* up = row - W;
  const float* down = row + W;
  for (uint32_t x = 1; x + 1 < W; ++x) {
    const bool inside = classes[x] == MOLDTEX_TEXEL_INSIDE;
    const size_t t = inside ? static_cast<size_t>(triangle[x]) : 0;
    const float v = mtx_surface_diffuse(row[x], row[x - 1], row[x + 1], up[x], down[x], coef[2 * t],
                                        coef[2 * t + 1], evaporation);
    out[x] = inside ? v : 0.f;
  }
}

}  // namespace

DiffusionPlan plan_surface_diffusion(const TextureDomain& d, float mix, float unit) {
  DiffusionPlan plan;
  plan.mix = mix;
  plan.unit = unit;
  // Passes for a texel of the mean size (length_unit / texel_length texels per unit).
  const double typical = unit / d.texel_length;
  plan.passes = passes_for(0.5 * mix * typical * typical, 0.5 * mix * typical * typical);
  const size_t triangles = d.texels_per_unit.size() / 2;
  std::vector<uint32_t> triangle_passes(triangles, 1);
  plan.triangle_coef.assign(2 * triangles, 0.f);
  for (size_t t = 0; t < triangles; ++t) {
    const double sx = unit * d.texels_per_unit[2 * t], sy = unit * d.texels_per_unit[2 * t + 1];
    double ax = 0.5 * mix * sx * sx, ay = 0.5 * mix * sy * sy;
    const uint32_t n = std::max(plan.passes, passes_for(ax, ay));
    // Beyond the pass limit, the texel diffuses less rather than blowing up.
    const double cap = static_cast<double>(n);
    if (ax + ay > cap) {
      const double shrink = cap / (ax + ay);
      ax *= shrink;
      ay *= shrink;
    }
    triangle_passes[t] = n;
    plan.triangle_coef[2 * t] = static_cast<float>(ax / n);
    plan.triangle_coef[2 * t + 1] = static_cast<float>(ay / n);
  }
  // Texels whose triangle needs more passes than every texel gets.
  std::vector<int32_t> seam_index;
  for (size_t i = 0; i < d.texel_count(); ++i) {
    if (d.classes[i] != MOLDTEX_TEXEL_INSIDE) continue;
    const uint32_t t = static_cast<uint32_t>(d.texel_triangle[i]);
    if (triangle_passes[t] <= plan.passes) continue;
    if (seam_index.empty()) {
      seam_index.assign(d.texel_count(), -1);
      for (size_t j = 0; j < d.seam_texel.size(); ++j) seam_index[d.seam_texel[j]] = static_cast<int32_t>(j);
    }
    const uint32_t x = static_cast<uint32_t>(i % d.width), y = static_cast<uint32_t>(i / d.width);
    plan.fine_texel.push_back(static_cast<uint32_t>(i));
    for (int k = 0; k < 4; ++k)
      plan.fine_neighbour.push_back(seam_index[i] >= 0 ? d.seam_neighbour[4 * seam_index[i] + k]
                                                       : grid_neighbour(d, x, y, k));
    plan.fine_coef.push_back(plan.triangle_coef[2 * t]);
    plan.fine_coef.push_back(plan.triangle_coef[2 * t + 1]);
    plan.fine_extra.push_back(triangle_passes[t] - plan.passes);
    plan.max_extra = std::max(plan.max_extra, triangle_passes[t] - plan.passes);
  }
  // Most extra passes first (stable, so the order is the texels' among equals): each
  // extra pass then runs over a prefix of the list. Each pass reads the field as the
  // last one left it and writes all its texels after, so the order changes no result.
  std::vector<uint32_t> order(plan.fine_texel.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return plan.fine_extra[a] > plan.fine_extra[b]; });
  // Each list in that order (`stride` entries per texel).
  auto reordered = [&](const auto& list, size_t stride) {
    std::remove_cvref_t<decltype(list)> out;
    out.reserve(list.size());
    for (uint32_t j : order)
      for (size_t k = 0; k < stride; ++k) out.push_back(list[stride * j + k]);
    return out;
  };
  plan.fine_texel = reordered(plan.fine_texel, 1);
  plan.fine_neighbour = reordered(plan.fine_neighbour, 4);
  plan.fine_coef = reordered(plan.fine_coef, 2);
  plan.fine_extra = reordered(plan.fine_extra, 1);
  plan.fine_active.assign(plan.max_extra, 0u);
  for (uint32_t extra : plan.fine_extra)
    for (uint32_t p = 1; p <= extra; ++p) ++plan.fine_active[p - 1];
  return plan;
}

void surface_diffuse(const TextureDomain& d, const DiffusionPlan& plan, float* in, float* out,
                     std::vector<float>& scratch, float evaporation, ThreadPool& pool) {
  const uint32_t W = d.width, H = d.height;
  float* src = in;
  float* dst = out;
  for (uint32_t pass = 0; pass < plan.passes; ++pass) {
    const float evap = pass == 0 ? evaporation : 0.f;
    pool.parallel_for(H, 4, [&](size_t begin, size_t end) {
      for (uint32_t y = static_cast<uint32_t>(begin); y < end; ++y) {
        const bool inner = y > 0 && y + 1 < H && W > 2;
        if (inner) {
          const size_t row = static_cast<size_t>(y) * W;
          diffuse_inner_row(src + row, W, d.classes.data() + row, d.texel_triangle.data() + row,
                            plan.triangle_coef.data(), evap, dst + row);
        }
        for (uint32_t x = 0; x < W; x += inner ? W - 1 : 1) {  // (inner rows: their ends only)
          const size_t i = static_cast<size_t>(y) * W + x;
          if (d.classes[i] != MOLDTEX_TEXEL_INSIDE) {
            dst[i] = 0.f;
            continue;
          }
          const float* c = &plan.triangle_coef[2 * static_cast<size_t>(d.texel_triangle[i])];
          const float u = src[i];
          dst[i] = mtx_surface_diffuse(u, x > 0 ? src[i - 1] : u, x + 1 < W ? src[i + 1] : u,
                                       y > 0 ? src[i - W] : u, y + 1 < H ? src[i + W] : u, c[0], c[1], evap);
        }
      }
    });
    // Texels at seams: the same with the neighbours across the seam.
    pool.parallel_for(d.seam_texel.size(), 1 << 12, [&](size_t begin, size_t end) {
      for (size_t j = begin; j < end; ++j) {
        const uint32_t i = d.seam_texel[j];
        const uint32_t* n = &d.seam_neighbour[4 * j];
        const float* c = &plan.triangle_coef[2 * static_cast<size_t>(d.texel_triangle[i])];
        dst[i] = mtx_surface_diffuse(src[i], src[n[0]], src[n[1]], src[n[2]], src[n[3]], c[0], c[1], evap);
      }
    });
    std::swap(src, dst);
  }
  if (src != out) std::memcpy(out, src, d.texel_count() * sizeof(float));
  // Extra passes of the small texels, in place through a scratch list; pass p visits
  // only the texels that take it (the others keep their values).
  scratch.resize(plan.fine_texel.size());
  for (uint32_t pass = 1; pass <= plan.max_extra; ++pass) {
    const size_t fine = plan.fine_active[pass - 1];
    pool.parallel_for(fine, 1 << 12, [&](size_t begin, size_t end) {
      for (size_t j = begin; j < end; ++j) {
        const uint32_t i = plan.fine_texel[j];
        const uint32_t* n = &plan.fine_neighbour[4 * j];
        scratch[j] = mtx_surface_diffuse(out[i], out[n[0]], out[n[1]], out[n[2]], out[n[3]],
                                         plan.fine_coef[2 * j], plan.fine_coef[2 * j + 1], 0.f);
      }
    });
    pool.parallel_for(fine, 1 << 14, [&](size_t begin, size_t end) {
      for (size_t j = begin; j < end; ++j) out[plan.fine_texel[j]] = scratch[j];
    });
  }
}

}  // namespace moldtex
