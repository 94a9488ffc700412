// Gray-Scott reaction-diffusion (moldtex.h, MOLDTEX_MODEL_GRAY_SCOTT) on the texel
// Laplacian: parameter checks, the sub-step count, the starting state, and the CPU step.
// The per-cell arithmetic is shared with OpenCL (shared/reaction.h).
#pragma once
#include <cstdint>
#include <vector>

#include "backends/cpu/thread_pool.h"
#include "domain/texel_laplacian.h"
#include "domain/texture_domain.h"
#include "moldtex.h"
#include "surface/surface.h"

namespace moldtex {

// Planes of a Gray-Scott state, in the backend's pheromone order.
constexpr uint32_t kReactionPlanes = 2;
constexpr uint32_t kReactionV = 0, kReactionU = 1;
// At most this many sub-steps per step; beyond, a step is refused.
constexpr uint32_t kMaxReactionSubsteps = 4096;

// Throws INVALID_ARGUMENT naming the first bad field.
void validate_reaction_params(const moldtex_reaction_params& params);

// Equal sub-steps per step (shared/reaction.h): (1 + F + k) h <= 0.5 and
// max(D_u, D_v) h rate <= 0.5 for 99% of the cells, but at most 4x what the median cell
// needs (the stiffer rest take their own loss implicitly and stay stable). Throws INVALID_ARGUMENT beyond kMaxReactionSubsteps.
// Gray-Scott's feed and kill maps (moldtex_sim_set_map FEED / KILL): per texel
// multipliers, the products capped at 1. Null = none.
struct ReactionMaps {
  const float* feed = nullptr;
  const float* kill = nullptr;
  float feed_max = 0, kill_max = 0;  // the largest effective F and k
};
// From the maps as given (empty = none) and their largest values.
ReactionMaps reaction_maps(const std::vector<float>& feed_map, float feed_largest, const std::vector<float>& kill_map,
                           float kill_largest, const moldtex_reaction_params& params);

uint32_t reaction_substeps(const TexelLaplacian& lap, const moldtex_reaction_params& params,
                           const ReactionMaps& maps = {});

// The starting state: 2 planes of width * height (V, then U; gutter filled): U = 1, V = 0,
// and V = 1, U = 0.5 within params.seed_radius (3D distance from the texel centre) of
// params.seed_count points drawn from `seed`: uniform by 3D area, or with probability ~
// texel_weights (3D area * spawn weight) when given.
std::vector<float> reaction_initial_state(const Surface& surface, const TextureDomain& domain,
                                          const moldtex_reaction_params& params, uint64_t seed,
                                          const std::vector<double>* texel_weights, ThreadPool& pool);

// One step of dt = params.time_step on planes (2 planes of texel_count, V then U) with
// scratch of the same size. Deterministic for any thread count. Gutter not filled.
void reaction_step(const TexelLaplacian& lap, const moldtex_reaction_params& params, float* planes,
                   std::vector<float>& scratch, size_t texel_count, ThreadPool& pool,
                   const ReactionMaps& maps = {});

}  // namespace moldtex
