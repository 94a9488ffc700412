// Gray-Scott reaction-diffusion (layton-intrinsic-slime.md's reaction-diffusion looks):
// no agents, two chemicals V and U on the cell graph of either domain. Its step:
// reaction_diffusion.* and shared/reaction.h; its brushes: reaction_paint.*.
#include <limits>

#include "agents/momas_rules.h"
#include "domain/texture_domain.h"
#include "models/gray_scott/reaction_diffusion.h"
#include "models/gray_scott/reaction_paint.h"
#include "backends/cpu/cpu_model_step.h"
#include "models/gray_scott/gray_scott_model.h"
#include "models/model.h"

namespace moldtex {

namespace {

class GrayScott final : public Model {
 public:
  uint32_t id() const override { return MOLDTEX_MODEL_GRAY_SCOTT; }
  const char* name_in_text() const override { return "Gray-Scott"; }
  void keep_config(moldtex_sim_config& c) const override {  // two planes (V, U), no agents
    c.agent_count = 0;
    c.species_count = kReactionPlanes;
  }
  bool has_agents() const override { return false; }
  bool runs_on(uint32_t domain) const override {
    return domain == MOLDTEX_DOMAIN_TEXTURE || domain == MOLDTEX_DOMAIN_INTRINSIC;
  }
  float max_plane_value() const override { return std::numeric_limits<float>::max(); }
  double time_step(const StepSettings& s) const override { return s.reaction.time_step; }
  std::unique_ptr<CpuModelStep> cpu_step(size_t /*texels*/, uint32_t /*species_count*/) const override {
    return gray_scott_cpu_step();
  }

  std::vector<float> initial_planes(const Surface& surface, const TextureDomain& domain,
                                    const StepSettings& settings, uint64_t seed, const std::vector<double>* weights,
                                    ThreadPool& pool) const override {
    return reaction_initial_state(surface, domain, settings.reaction, seed, weights, pool);
  }
  // A dab seeds V (adding) or clears it (erasing).
  uint32_t paint(const Surface& surface, const TextureDomain& domain, float* planes, const moldtex_brush& brush,
                 bool erase, PaintUndo& undo, ThreadPool& pool) const override {
    return paint_reaction(surface, domain, planes, brush, erase, undo, pool);
  }
  void unpaint(const TextureDomain& domain, float* planes, const PaintUndo& undo, ThreadPool& pool) const override {
    restore_reaction(domain, planes, undo, pool);
  }

  // Mean V, and where V > 0.1.
  void stats(moldtex_sim_stats& s, const TextureDomain& d, const std::vector<float>&,
             const std::vector<float>& shown, const StepSettings&) const override {
    const size_t texels = d.texel_count();
    const float* v = shown.data() + kReactionV * texels;
    s.coverage = measure(d, v).coverage;
    std::vector<float> spots(texels, 0.f);
    for (size_t i = 0; i < texels; ++i) spots[i] = v[i] > 0.1f ? 1.f : 0.f;
    s.presence = measure(d, spots.data()).presence;
  }
};

}  // namespace

const Model& gray_scott_model() {
  static const GrayScott model;
  return model;
}

}  // namespace moldtex
