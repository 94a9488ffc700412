#include "agents/momas_rules.h"

#include <atomic>
#include <cmath>
#include <numbers>

#include "common/rng.h"

namespace moldtex {

// The paper's vision distance is given in units of this many texels (Table 1 range
// 0.4-2 becomes 4-20 texels, around the classic 9-texel sensor offset).
constexpr float kVisionUnitTexels = 10.f;

MomasStepConstants momas_constants(const moldtex_sim_params& p, const TextureDomain& d,
                                   uint64_t seed, uint64_t step) {
  const float texel = static_cast<float>(d.texel_length);
  const float angle = p.vision_angle * std::numbers::pi_v<float> / 180.f;
  MomasStepConstants c;
  c.move_length = p.movement_speed * texel;
  c.sensor_length = p.vision_distance * kVisionUnitTexels * texel;
  c.sensor_cos = std::cos(angle);
  c.sensor_sin = std::sin(angle);
  c.max_turn = p.turn_speed * std::numbers::pi_v<float> * p.time_step;
  c.substeps = p.substeps;
  c.seed = seed;
  c.step = step;
  return c;
}

namespace {

struct NoEvents {
  void operator()(const Walker&, bool) const {}
};

inline uint32_t texel_at(const Surface& s, const TextureDomain& d, const Walker& w) {
  const float* uv = &s.corner_uvs[6 * w.triangle];
  float u = w.bary[0] * uv[0] + w.bary[1] * uv[2] + w.bary[2] * uv[4];
  float v = w.bary[0] * uv[1] + w.bary[1] * uv[3] + w.bary[2] * uv[5];
  return d.texel_of_uv(u, v);
}

inline float sense(const Surface& s, const TextureDomain& d, const float* pheromone,
                   const Walker& from, float c, float sn, float length) {
  Walker probe = from;
  rotate(probe.heading, c, sn);
  walk(s.frames.data(), s.adjacency.data(), probe, length, NoEvents{});
  return pheromone[texel_at(s, d, probe)];
}

}  // namespace

void momas_update_agents(const Surface& s, const TextureDomain& d, const MomasStepConstants& c,
                         const float* pheromone, uint8_t* marks, Agents& agents, size_t begin,
                         size_t end) {
  const float sub_length = c.move_length / static_cast<float>(c.substeps);
  for (size_t i = begin; i < end; ++i) {
    Walker w = agents.load(i);
    const float left = sense(s, d, pheromone, w, c.sensor_cos, c.sensor_sin, c.sensor_length);
    const float front = sense(s, d, pheromone, w, 1.f, 0.f, c.sensor_length);
    const float right = sense(s, d, pheromone, w, c.sensor_cos, -c.sensor_sin, c.sensor_length);

    // Steering: keep going only while the front is strictly strongest, else turn
    // toward the stronger side, or to a random side on a tie (so agents on bare
    // ground wander instead of running straight). The turn is scaled by r ~ U[0,1),
    // the paper's random jitter.
    CounterRng rng(c.seed, RngPurpose::Steer, i, c.step);
    const float r = rng.next_float();
    float turn = 0.f;
    if (!(front > left && front > right)) {
      const float side = left > right ? 1.f : (right > left ? -1.f : (rng.next_float() < 0.5f ? 1.f : -1.f));
      turn = side * r * c.max_turn;
    }
    if (turn != 0.f) {
      rotate(w.heading, std::cos(turn), std::sin(turn));
      w.heading = unit(w.heading);
    }

    // Move in equal substeps, leaving a deposit after each: a line-integrated trail
    // whose total length does not depend on the substep count.
    for (uint32_t k = 0; k < c.substeps; ++k) {
      walk(s.frames.data(), s.adjacency.data(), w, sub_length, NoEvents{});
      const uint32_t texel = texel_at(s, d, w);
      if (d.classes[texel] == MOLDTEX_TEXEL_INSIDE)
        std::atomic_ref<uint8_t>(marks[texel]).store(1, std::memory_order_relaxed);
    }
    agents.store(i, w);
  }
}

}  // namespace moldtex
