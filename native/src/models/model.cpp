#include "models/model.h"

#include <algorithm>

#include "agents/momas_rules.h"
#include "domain/texture_domain.h"

namespace moldtex {

void Model::update_u_metric(StepSettings& settings, const std::vector<double>&, double) const {
  settings.u_metric.assign(settings.species_count, 0.0);
}

// Species planes: one species' Eq. 1; several: the mean of each species' coverage, and
// presence where any species is.
void Model::stats(moldtex_sim_stats& s, const TextureDomain& d, const std::vector<float>&,
                  const std::vector<float>& field, const StepSettings& settings) const {
  const size_t texels = d.texel_count();
  const uint32_t planes = settings.species_count;
  if (planes == 1) {
    const FieldMetrics m = measure(d, field.data());
    s.coverage = m.coverage;
    s.presence = m.presence;
    return;
  }
  std::vector<float> any(texels, 0.f);
  for (uint32_t k = 0; k < planes; ++k) {
    const float* plane = field.data() + k * texels;
    s.coverage += measure(d, plane).coverage / planes;
    for (size_t i = 0; i < texels; ++i) any[i] = std::max(any[i], plane[i]);
  }
  s.presence = measure(d, any.data()).presence;
}

}  // namespace moldtex
