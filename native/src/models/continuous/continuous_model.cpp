// The continuous model (layton-intrinsic-slime.md): rates in physical units, turn
// decisions at a fixed frequency, line-integrated additive deposits into a diffusion-decay
// PDE, turnover and the U metric; on the texture and the intrinsic domain. Its step:
// agents/continuous_rules.*, shared/continuous.h, shared/pde.h.
#include <algorithm>
#include <cmath>
#include <limits>

#include "agents/continuous_rules.h"
#include "agents/momas_rules.h"
#include "domain/texture_domain.h"
#include "backends/cpu/cpu_model_step.h"
#include "models/continuous/continuous_model.h"
#include "models/model.h"

namespace moldtex {

namespace {

class Continuous final : public Model {
 public:
  uint32_t id() const override { return MOLDTEX_MODEL_CONTINUOUS; }
  const char* name_in_text() const override { return "the continuous model"; }
  bool runs_on(uint32_t domain) const override {
    return domain == MOLDTEX_DOMAIN_TEXTURE || domain == MOLDTEX_DOMAIN_INTRINSIC;
  }
  // The deposit sums and the PDE's operator (CSR with reverse entries, rates, local time
  // stepping's scratch; backward Euler's matrix and vectors when it runs): about 200
  // bytes per texel.
  double extra_bytes_per_texel(const moldtex_sim_config& c) const override {
    const double planes = c.species_count;
    return planes * 8 + 200;
  }
  float max_plane_value() const override { return std::numeric_limits<float>::max(); }
  double time_step(const StepSettings& s) const override { return s.continuous.time_step; }
  std::unique_ptr<CpuModelStep> cpu_step(size_t /*texels*/, uint32_t /*species_count*/) const override {
    return continuous_cpu_step();
  }
  bool agent_clocks() const override { return true; }

  void update_u_metric(StepSettings& settings, const std::vector<double>& species_agents,
                       double cell_area) const override {
    settings.u_metric.assign(settings.species_count, 0.0);
    for (uint32_t k = 0; k < settings.species_count && k < species_agents.size(); ++k)
      settings.u_metric[k] = uniform_steady_state(settings.continuous, species_agents[k], cell_area);
  }

  // Shown as u / U: 1 is the uniform steady state, at any deposit rate, agent count or
  // surface area.
  void display(std::vector<float>& field, size_t cells, const StepSettings& settings) const override {
    for (uint32_t k = 0; k < settings.species_count; ++k) {
      const double u = k < settings.u_metric.size() ? settings.u_metric[k] : 0.0;
      if (!(std::isfinite(u) && u > 0)) continue;
      // In double, clamped: with a U near the float minimum (a deposit rate of 1e-38) the
      // ratio would overflow a float.
      const double scale = 1.0 / u;
      for (size_t i = 0; i < cells; ++i)
        field[k * cells + i] = static_cast<float>(
            std::min(double(field[k * cells + i]) * scale, double(std::numeric_limits<float>::max())));
    }
  }

  void stats(moldtex_sim_stats& s, const TextureDomain& d, const std::vector<float>& raw,
             const std::vector<float>& shown, const StepSettings& settings) const override {
    s.u_metric = settings.u_metric.empty() ? 0.0 : settings.u_metric[0];
    // Eq. 1's area-weighted mean over the island texels is the mean concentration.
    s.mean_concentration = measure(d, raw.data()).coverage;
    Model::stats(s, d, raw, shown, settings);
  }
};

}  // namespace

const Model& continuous_model() {
  static const Continuous model;
  return model;
}

}  // namespace moldtex
