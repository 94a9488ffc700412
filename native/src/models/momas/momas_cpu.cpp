// MoMaS' step on the CPU backend: agents sense and mark where they deposit (in SIMD lanes
// where they can), then per species deposit, blur and evaporate.
#include <algorithm>
#include <memory>

#include "agents/momas_lanes.h"
#include "agents/momas_rules.h"
#include "backends/cpu/cpu_model_step.h"
#include "common/error.h"
#include "domain/surface_diffusion.h"
#include "models/model.h"
#include "models/momas/momas_model.h"

namespace moldtex {

namespace {

class MomasCpuStep final : public CpuModelStep {
 public:
  MomasCpuStep(size_t texels, uint32_t species_count) : marks_(texels * species_count, 0) {}

  void clear() override { std::fill(marks_.begin(), marks_.end(), 0); }
  size_t bytes() const override { return marks_.capacity(); }

  void step(CpuStepContext& x, const StepSettings& settings, uint64_t seed, uint64_t step_index,
            uint32_t* eaters) override {
    if (x.intrinsic)
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The Intrinsic domain runs " + models_on(MOLDTEX_DOMAIN_INTRINSIC) +
                                               "; MoMaS works in texels: use the Texture domain");
    const TextureDomain& d = x.domain;
    const moldtex_sim_params& p = settings.params;
    const MomasStepConstants c = momas_constants(settings, d, seed, step_index);
    // Agents drift apart in memory order as they move; regroup them now and then.
    if (step_index % kSortInterval == 0) sort_by_tile(x.surface, d.width, d.height, x.agents, x.sort_scratch, x.pool);
    // 1. Agents sense the field as it was at the start of the step (read-only) and mark
    //    where they deposit: no thread reads what another is writing.
    mtx_surface_tables tables = surface_tables(x.surface, d);
    if (c.food_count > 0) {
      std::fill(eaters, eaters + c.food_count, 0u);
      tables.food = settings.food.data();
      tables.eaters = eaters;
    }
    const float* field = c.has_fields ? x.field.data() : nullptr;
    // The common case in SIMD lanes where the processor and the step allow (the same bits).
    const bool lanes = momas_lanes_apply(c, x.surface.triangle_count());
    Agents& agents = x.agents;
    float* pheromone = x.planes.data();
    x.pool.parallel_for(agents.size(), 1024, [&](size_t begin, size_t end) {
      if (lanes)
        momas_lanes_update(tables, c, pheromone, field, marks_.data(), agents, begin, end);
      else
        momas_update_agents(tables, c, pheromone, field, marks_.data(), agents, begin, end);
    });
    // 2. Per species: deposit, make the gutter hold the texels across each seam, then blur
    //    (which then mixes across seams) and evaporate; in texel units in one pass
    //    (deposit_diffuse_evaporate).
    const size_t texels = d.texel_count();
    const float mix = std::min(1.f, p.diffusion_rate * p.time_step);
    const bool surface_units = p.length_unit > 0.f;
    if (surface_units && !plan_.matches(p.diffusion_rate * p.time_step, p.length_unit))
      plan_ = plan_surface_diffusion(d, p.diffusion_rate * p.time_step, p.length_unit);
    for (uint32_t k = 0; k < x.species_count; ++k) {
      float* plane = x.planes.data() + k * texels;
      if (surface_units) {
        apply_deposits(d, plane, marks_.data() + k * texels, settings.species[k].deposit, x.pool);
        surface_diffuse(d, plan_, plane, x.scratch.data() + k * texels, fine_scratch_,
                        p.evaporation_rate * p.time_step, x.pool);
        continue;
      }
      deposit_diffuse_evaporate(d, plane, marks_.data() + k * texels, settings.species[k].deposit,
                                x.scratch.data() + k * texels, mix, p.evaporation_rate * p.time_step, x.pool);
    }
    x.planes.swap(x.scratch);
    for (uint32_t k = 0; k < x.species_count; ++k) fill_gutter(d, x.planes.data() + k * texels, x.pool);
  }

 private:
  std::vector<uint8_t> marks_;  // where agents deposit this step, per species
  // Surface units: the diffusion plan for the current mix and length unit.
  DiffusionPlan plan_;
  std::vector<float> fine_scratch_;
};

}  // namespace

std::unique_ptr<CpuModelStep> momas_cpu_step(size_t texels, uint32_t species_count) {
  return std::make_unique<MomasCpuStep>(texels, species_count);
}

}  // namespace moldtex
