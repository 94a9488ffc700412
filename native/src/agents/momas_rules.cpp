#include "agents/momas_rules.h"

#include <cmath>
#include <numbers>

namespace moldtex {

MomasStepConstants momas_constants(const moldtex_sim_params& p, const TextureDomain& d,
                                   uint64_t seed, uint64_t step) {
  const float texel = static_cast<float>(d.texel_length);
  const float angle = p.vision_angle * std::numbers::pi_v<float> / 180.f;
  MomasStepConstants c{};
  c.seed = seed;
  c.step = step;
  c.move_length = p.movement_speed * texel;
  c.sensor_length = p.vision_distance * MTX_VISION_UNIT_TEXELS * texel;
  c.sensor_cos = std::cos(angle);
  c.sensor_sin = std::sin(angle);
  c.max_turn = p.turn_speed * std::numbers::pi_v<float> * p.time_step;
  c.substeps = p.substeps;
  c.width = d.width;
  c.height = d.height;
  return c;
}

mtx_surface_tables surface_tables(const Surface& s, const TextureDomain& d) {
  return mtx_surface_tables{s.frames.data(), s.adjacency.data(), s.corner_uvs.data(),
                            d.classes.data()};
}

void momas_update_agents(const mtx_surface_tables& tables, const MomasStepConstants& c,
                         const float* pheromone, uint8_t* marks, Agents& agents, size_t begin,
                         size_t end) {
  for (size_t i = begin; i < end; ++i) {
    Walker w = agents.load(i);
    mtx_momas_agent_step(tables, pheromone, marks, &w, i, &c);
    agents.store(i, w);
  }
}

}  // namespace moldtex
