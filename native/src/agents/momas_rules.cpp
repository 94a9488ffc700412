#include "agents/momas_rules.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace moldtex {

bool momas_decides(float time_step, uint64_t step) {
  const double ticks = 60.0 * double(time_step);  // MoMaS ticks per step, under 1
  // A whole number m of steps per tick (1/120, 1/240 s...): every m-th step, from the
  // first, however the time step rounds (0.5 in a float is 0.49999999).
  const double m = std::round(1.0 / ticks);
  if (std::fabs(m * ticks - 1.0) < 1e-5) return step % uint64_t(m) == 0;
  // Otherwise the steps during which a tick falls: [step, step + 1) * ticks holds a
  // whole number.
  return std::ceil(double(step) * ticks) < double(step + 1) * ticks;
}

MomasStepConstants momas_constants(const StepSettings& settings, const TextureDomain& d,
                                   uint64_t seed, uint64_t step) {
  const moldtex_sim_params& p = settings.params;
  // Surface units: a "texel" of the parameters is length_unit in 3D at any resolution,
  // and a move covers movement_speed texels per 1/60 s of simulated time.
  const bool surface_units = p.length_unit > 0.f;
  const float texel = surface_units ? p.length_unit : static_cast<float>(d.texel_length);
  const float ticks = surface_units ? 60.f * p.time_step : 1.f;
  // Surface units: agents sense and turn once per 1/60 s, MoMaS' tick. Under 1/60 s on
  // the steps where a tick falls, moving straight on between (momas_decides); over it,
  // as many times a step as ticks fall in it (the nearest whole number), each decision
  // followed by its share of the move. Only where a step does not hold a whole number of
  // ticks is the turn scaled to the time between decisions.
  const bool clocked = surface_units && ticks < 1.f;
  const uint32_t decisions = surface_units && ticks > 1.f ? static_cast<uint32_t>(std::lround(ticks)) : 1u;
  const float decision_interval = clocked ? 1.f / 60.f : p.time_step / static_cast<float>(decisions);
  MomasStepConstants c{};
  c.seed = seed;
  c.step = step;
  c.steer_key = mtx_rng_key(seed, MTX_RNG_STEER);
  for (uint32_t s = 0; s < settings.species_count; ++s) {
    const moldtex_species_params& sp = settings.species[s];
    const float angle = sp.vision_angle * std::numbers::pi_v<float> / 180.f;
    c.move_length[s] = sp.movement_speed * texel * ticks / static_cast<float>(decisions);
    c.sensor_length[s] = sp.vision_distance * MTX_VISION_UNIT_TEXELS * texel;
    c.sensor_cos[s] = std::cos(angle);
    c.sensor_sin[s] = std::sin(angle);
    c.max_turn[s] = sp.turn_speed * std::numbers::pi_v<float> * decision_interval;
    for (uint32_t k = 0; k < settings.species_count; ++k)
      c.attraction[MTX_MAX_SPECIES * s + k] = sp.attraction[k];
  }
  c.substeps = p.substeps;
  c.width = d.width;
  c.height = d.height;
  c.species_count = settings.species_count;
  c.has_fields = settings.has_fields ? 1u : 0u;
  c.hunger_step = p.hunger_rate * p.time_step;
  c.food_radius = p.food_radius;
  c.sensor_size = p.sensor_size;
  c.length_unit = surface_units ? p.length_unit : 0.f;
  c.surface_mode = surface_units ? 1u : 0u;
  c.turn_jitter = surface_units ? std::sqrt((1.f / 60.f) / decision_interval) : 1.f;
  c.coast = clocked && !momas_decides(p.time_step, step) ? 1u : 0u;
  c.decisions = decisions;
  c.food_count = c.hunger_step > 0.f ? static_cast<uint32_t>(settings.food.size() / 4) : 0u;
  return c;
}

mtx_surface_tables surface_tables(const Surface& s, const TextureDomain& d) {
  return mtx_surface_tables{s.frames.data(), s.adjacency.data(), s.corner_uvs.data(),
                            d.classes.data(), s.frame3d.data(), nullptr, nullptr,
                            d.texels_per_unit.data(), s.island.data(),
                            d.texel_island.data(), d.interior_bits.data(), nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, 0u,
                            nullptr, nullptr, d.interior_reach.data(), s.unfolded.data(), d.sole_reach.data()};
}

namespace {

// Agents agent(0) .. agent(n - 1) (n <= kMomasBatch), all of a step. In a batch: trace every
// agent's sensors first and ask for the texels they end on, so the batch's reads travel
// from memory together instead of one after another.
template <class Agent>
void update_batch(const mtx_surface_tables& tables, const MomasStepConstants& c, const float* pheromone,
                  const float* field, uint8_t* marks, Agents& agents, size_t n, Agent agent) {
  Walker w[kMomasBatch];
  mtx_momas_probes probes[kMomasBatch];
  const size_t plane = size_t(c.width) * c.height;
  for (size_t j = 0; j < n; ++j) {
    const size_t i = agent(j);
    w[j] = agents.load(i);
    const uint32_t species = agents.species[i];
    mtx_momas_probe(tables, &w[j], species, &c, &probes[j]);
    const float* own = pheromone + species * plane;
    for (int k = 0; k < 3; ++k) __builtin_prefetch(own + probes[j].texel[k]);
    // Surface units read a footprint around each probe texel: the rows above and
    // below, and whether the block there is all one island.
    if (c.surface_mode && !c.coast)
      for (int k = 0; k < 3; ++k) {
        const uint32_t t = probes[j].texel[k];
        __builtin_prefetch(own + (t >= c.width ? t - c.width : t));
        __builtin_prefetch(own + (t + c.width < plane ? t + c.width : t));
        __builtin_prefetch(tables.interior_reach + t);
        __builtin_prefetch(tables.texel_island + t);
      }
    // Where it moves and marks: the mark's byte (texel units) or, in surface units,
    // the class there first.
    if (c.surface_mode)
      __builtin_prefetch(tables.classes + probes[j].here);
    else
      __builtin_prefetch(marks + species * plane + probes[j].here, 1);
  }
  for (size_t j = 0; j < n; ++j) {
    const size_t i = agent(j);
    float hunger = agents.hunger[i];
    mtx_momas_agent_finish(tables, pheromone, field, marks, &w[j], &hunger, agents.species[i], i, &c, &probes[j]);
    agents.store(i, w[j]);
    agents.hunger[i] = hunger;
  }
}

}  // namespace

void momas_update_agents(const mtx_surface_tables& tables, const MomasStepConstants& c,
                         const float* pheromone, const float* field, uint8_t* marks,
                         Agents& agents, size_t begin, size_t end) {
  for (size_t b = begin; b < end; b += kMomasBatch)
    update_batch(tables, c, pheromone, field, marks, agents, std::min(kMomasBatch, end - b),
                 [b](size_t j) { return b + j; });
}

void momas_update_listed(const mtx_surface_tables& tables, const MomasStepConstants& c, const float* pheromone,
                         const float* field, uint8_t* marks, Agents& agents, const size_t* listed, size_t n) {
  for (size_t b = 0; b < n; b += kMomasBatch)
    update_batch(tables, c, pheromone, field, marks, agents, std::min(kMomasBatch, n - b),
                 [listed, b](size_t j) { return listed[b + j]; });
}

}  // namespace moldtex
