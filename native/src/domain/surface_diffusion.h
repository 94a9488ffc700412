// Surface diffusion on the texture domain (moldtex_sim_params.length_unit > 0): MoMaS'
// blur with its reach measured on the surface instead of in texels. A step adds the
// variance that the 3x3 Gaussian mixed by `mix` adds at one texel per length unit,
// mix / 2 * length_unit^2 per axis in 3D, so each texel's share in texel^2 is
// mix / 2 * (length_unit * texels per unit)^2 along each texel axis: little where texels
// are large in 3D (stretched UVs), much where they are small (UV poles, high resolution).
// Neighbours come from the grid, or across UV seams from the seam correspondence.
//
// Stability: one explicit pass may add at most 1 texel^2 (ax + ay <= 1), so a step runs
// `passes` passes over every texel (enough for a typical texel), and texels that need
// more (the small ones) run their extra passes from a short list. Work is bounded: at
// most kMaxDiffusionPasses passes per texel; beyond that a texel diffuses less.
#pragma once
#include <cstdint>
#include <vector>

#include "backends/cpu/thread_pool.h"
#include "domain/texture_domain.h"

namespace moldtex {

constexpr uint32_t kMaxDiffusionPasses = 16;

struct DiffusionPlan {
  float mix = -1.f, unit = -1.f;     // what it was made for
  uint32_t passes = 1;               // passes over every texel
  std::vector<float> triangle_coef;  // 2 per triangle: ax, ay of one pass
  // Texels that need more than `passes` passes, with their 4 neighbours (W, E, S, N),
  // their coefficients per pass (2 each) and their number of extra passes.
  std::vector<uint32_t> fine_texel, fine_neighbour, fine_extra;
  std::vector<float> fine_coef;
  uint32_t max_extra = 0;
  // The fine texels come most extra passes first, so those that take extra pass p are
  // the first fine_active[p - 1] of them (p = 1 .. max_extra): a pass visits only those.
  std::vector<uint32_t> fine_active;
  bool matches(float m, float u) const { return m == mix && u == unit; }
};

// mix = diffusion_rate * time_step; unit = length_unit (mesh units).
DiffusionPlan plan_surface_diffusion(const TextureDomain& d, float mix, float unit);

// One step of surface diffusion and evaporation of one plane: reads `in`, writes `out`
// (island texels; 0 elsewhere, the caller fills the gutter); `in` is used as scratch.
void surface_diffuse(const TextureDomain& d, const DiffusionPlan& plan, float* in, float* out,
                     std::vector<float>& scratch, float evaporation, ThreadPool& pool);

}  // namespace moldtex
