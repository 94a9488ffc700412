// MoMaS agent behaviour (momas-paper.md Algorithm 1, lines 9-23): sense at three
// sensors traced over the surface, steer toward the strongest, move, mark a deposit.
#pragma once
#include <cstdint>

#include "agents/agents.h"
#include "domain/texture_domain.h"
#include "moldtex.h"

namespace moldtex {

// Per-step constants derived once from the parameters and the layout.
struct MomasStepConstants {
  float move_length;    // 3D length of one move
  float sensor_length;  // 3D distance to the sensors
  float sensor_cos, sensor_sin;
  float max_turn;       // radians
  uint32_t substeps;
  uint64_t seed, step;
};

MomasStepConstants momas_constants(const moldtex_sim_params& p, const TextureDomain& d,
                                   uint64_t seed, uint64_t step);

// Updates agents [begin, end). Reads `pheromone` only; writes deposit marks (the same
// value 1 from every writer, so the order of writers cannot change the result).
void momas_update_agents(const Surface& surface, const TextureDomain& domain,
                         const MomasStepConstants& c, const float* pheromone, uint8_t* marks,
                         Agents& agents, size_t begin, size_t end);

}  // namespace moldtex
