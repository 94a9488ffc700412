// MoMaS (momas-paper.md): agents that set the texels they cross to their deposit, a blur
// and evaporation; in texel or surface units, at a detail of 1, 2 or 4 texels per image
// texel. Its step: agents/momas_rules.*, agents/momas_lanes*, shared/momas.h.
#include "agents/momas_rules.h"
#include "io/checkpoint.h"
#include "backends/cpu/cpu_model_step.h"
#include "models/momas/momas_model.h"
#include "models/model.h"

namespace moldtex {

namespace {

class Momas final : public Model {
 public:
  uint32_t id() const override { return MOLDTEX_MODEL_MOMAS; }
  const char* name_in_text() const override { return "MoMaS"; }
  bool supports_detail() const override { return true; }
  bool runs_on(uint32_t domain) const override { return domain == MOLDTEX_DOMAIN_TEXTURE; }
  float max_plane_value() const override { return kMaxPheromone; }
  double time_step(const StepSettings& s) const override { return s.params.time_step; }
  std::unique_ptr<CpuModelStep> cpu_step(size_t texels, uint32_t species_count) const override {
    return momas_cpu_step(texels, species_count);
  }
};

}  // namespace

const Model& momas_model() {
  static const Momas model;
  return model;
}

}  // namespace moldtex
