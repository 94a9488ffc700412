// MoMaS agent behaviour on the CPU: the per-agent rule itself lives in shared/momas.h,
// compiled here as C++ and in the OpenCL backend as OpenCL C.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "agents/agents.h"
#include "domain/texture_domain.h"
#include "moldtex.h"
#include "shared/momas.h"

namespace moldtex {

using MomasStepConstants = mtx_momas_constants;

// What a backend needs for one step: the shared parameters and each species' behaviour.
struct ParameterMaps;  // agents/parameter_maps.h

struct StepSettings {
  moldtex_sim_params params{};
  moldtex_species_params species[MTX_MAX_SPECIES]{};
  uint32_t species_count = 1;
  bool has_fields = false;
  // Food sources with food left, 4 floats each (x, y, z, strength); read while
  // params.hunger_rate > 0. Filled by the simulation before every step.
  std::vector<float> food;
  // The behaviour model (moldtex_model) and, for MOLDTEX_MODEL_CONTINUOUS, its parameters
  // and U (Eq. 5) of each species, which sensing divides by.
  uint32_t model = MOLDTEX_MODEL_MOMAS;
  moldtex_continuous_params continuous{};
  std::vector<double> u_metric;
  // MOLDTEX_MODEL_GRAY_SCOTT's parameters.
  moldtex_reaction_params reaction{};
  // Directional bias: 2 per triangle in its local frame (empty = none).
  std::vector<float> bias;
  // Parameter maps and stimuli of the continuous model (never null in a simulation).
  std::shared_ptr<const ParameterMaps> maps;
};

// Surface units at a time step under 1/60 s: whether agents sense and turn at step
// `step` (MoMaS' rule is a turn per 1/60 s tick; deciding every shorter step and scaling
// the turn made the pattern depend on the time step: 17% shorter cells at 1/240 than at
// 1/120). True on the steps during which a tick of a 60 Hz clock falls.
bool momas_decides(float time_step, uint64_t step);

MomasStepConstants momas_constants(const StepSettings& settings, const TextureDomain& d,
                                   uint64_t seed, uint64_t step);

mtx_surface_tables surface_tables(const Surface& surface, const TextureDomain& domain);

// Updates agents [begin, end); see shared/momas.h for why this is thread-safe and
// deterministic. In batches of kMomasBatch agents (every probe first, its texels asked for).
constexpr size_t kMomasBatch = 16;
void momas_update_agents(const mtx_surface_tables& tables, const MomasStepConstants& c,
                         const float* pheromone, const float* field, uint8_t* marks,
                         Agents& agents, size_t begin, size_t end);

// ... or the agents listed[0 .. n) (the ones MoMaS' SIMD lanes leave, agents/momas_lanes.h).
void momas_update_listed(const mtx_surface_tables& tables, const MomasStepConstants& c, const float* pheromone,
                         const float* field, uint8_t* marks, Agents& agents, const size_t* listed, size_t n);

}  // namespace moldtex
