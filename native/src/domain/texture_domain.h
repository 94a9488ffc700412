// The texture domain (MoMaS): pheromone lives in a UV texture. This file owns the
// layout (which texel belongs to which triangle, which texels form the gutter around
// the UV islands) and the per-step field operations (deposit, seam-aware Gaussian blur,
// evaporation) and the coverage/presence metrics of momas-paper.md Eq. 1.
#pragma once
#include <cstdint>
#include <vector>

#include "backends/cpu/thread_pool.h"
#include "surface/surface.h"

namespace moldtex {

// Texels this far (Chebyshev) from an island are gutter: wide enough for bilinear
// filtering and the first mip level not to pull in black from outside.
constexpr int kGutterWidth = 2;

struct TextureDomain {
  uint32_t width = 0, height = 0;
  std::vector<int32_t> texel_triangle;  // triangle whose UV covers the texel centre, or -1
  std::vector<uint8_t> classes;         // MOLDTEX_TEXEL_* per texel
  // Gutter texel i copies texel gutter_source[i]: the texel across the seam where the
  // edge has a neighbour in another island, else the nearest texel of its own island.
  std::vector<uint32_t> gutter_texel, gutter_source;
  std::vector<float> triangle_area_scale;  // 3D area per UV area, for Eq. 1 weights
  double texel_length = 0;                 // 3D length of one texel on this mesh
  // Texels per mesh unit along the texel axes, 2 per triangle: W / |dP/du|, H / |dP/dv|
  // (0 for degenerate triangles). Surface units scale footprints and diffusion by it.
  std::vector<float> texels_per_unit;
  // The seam correspondence (see seam_neighbours.h): island texels with a west, east,
  // south or north neighbour that is not a texel of their own island (a UV seam, an
  // island that touches another, the texture border, an open boundary), and for each
  // the 4 texels (W, E, S, N) at the same surface points, found by walking the surface.
  std::vector<uint32_t> seam_texel, seam_neighbour;
  // The UV island of each island texel (-1 for gutter and outside texels): one load for
  // "is this texel a cell of my island" (the continuous model's bilinear stencils).
  std::vector<int32_t> texel_island;
  // One bit per texel (32 per word): set when the texel and its 8 neighbours are all
  // cells of one island, so a bilinear stencil around a point in it needs no check. A
  // small table (1 MiB texels: 128 KiB) that stays in cache.
  std::vector<uint32_t> interior_bits;
  // Per texel, the largest r (at most 255) such that the (2r + 1)^2 block around it holds
  // texels of its own island only, inside the texture (0 off the islands): 1 is an
  // interior bit. A MoMaS footprint box in surface units that lies within that block
  // needs no "texel of my island" test per texel (mtx_box_within_island).
  std::vector<uint8_t> interior_reach;
  // The same reach over the island texels that are their island's alone: texels whose
  // square (grown by a rounding margin) the UV image of no other island's triangle
  // touches, nor clamps onto from beyond the texture's border. Per texel 0 if it is not
  // such a texel, else 1 + that reach (at most 254). A point of any triangle that lies in
  // such a texel's square belongs to the texel's island, so a footprint box within the
  // block is all of the point's island without looking up the texel's island (MoMaS'
  // sixteen lanes: one table read instead of two).
  std::vector<uint8_t> sole_reach;

  size_t texel_count() const { return static_cast<size_t>(width) * height; }
  size_t bytes() const;

  uint32_t texel_of_uv(float u, float v) const {
    float x = u * static_cast<float>(width), y = v * static_cast<float>(height);
    int ix = static_cast<int>(x), iy = static_cast<int>(y);
    ix = ix < 0 ? 0 : (ix >= static_cast<int>(width) ? static_cast<int>(width) - 1 : ix);
    iy = iy < 0 ? 0 : (iy >= static_cast<int>(height) ? static_cast<int>(height) - 1 : iy);
    return static_cast<uint32_t>(iy) * width + static_cast<uint32_t>(ix);
  }
};

TextureDomain build_texture_domain(const Surface& surface, uint32_t width, uint32_t height,
                                   ThreadPool& pool);

// pheromone[i] = max(pheromone[i], deposit) where marks[i] is set; clears the marks.
void apply_deposits(const TextureDomain& d, float* pheromone, uint8_t* marks, float deposit,
                    ThreadPool& pool);
// Copies every gutter texel from its source.
void fill_gutter(const TextureDomain& d, float* pheromone, ThreadPool& pool);
// Deposit, gutter and blur in one pass over the plane, bit for bit as these one after
// another: p = max(p, deposit) on marked island texels; every gutter texel copies its
// source; out = clamp(p + mix * (blur3x3(p) - p) - evaporation, 0, 1) on island texels,
// 0 elsewhere (the blur weighs only island and gutter texels, so borders neither darken
// nor leak; mtx_diffuse_evaporate_rows). p itself keeps its values but for its gutter
// texels, which take their deposited sources': each texel's deposited value is
// computed where the blur reads it, so the plane is read once and never written
// (OpenCL runs the three as kernels). Clears the marks.
void deposit_diffuse_evaporate(const TextureDomain& d, float* p, uint8_t* marks, float deposit, float* out,
                               float mix, float evaporation, ThreadPool& pool);

struct FieldMetrics {
  double coverage = 0, presence = 0;
};
FieldMetrics measure(const TextureDomain& d, const float* pheromone);

}  // namespace moldtex
