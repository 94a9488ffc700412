// Gray-Scott's step on the CPU backend: the reaction and diffusion of V and U on the
// domain's cell graph (reaction_diffusion.h).
#include <memory>

#include "backends/cpu/cpu_model_step.h"
#include "common/error.h"
#include "models/gray_scott/gray_scott_model.h"
#include "models/gray_scott/reaction_diffusion.h"

namespace moldtex {

namespace {

class GrayScottCpuStep final : public CpuModelStep {
 public:
  void step(CpuStepContext& x, const StepSettings& settings, uint64_t, uint64_t, uint32_t*) override {
    const TexelLaplacian& base = x.operators.laplacian();
    if (x.species_count < kReactionPlanes) fail(MOLDTEX_ERROR_INTERNAL, "The Gray-Scott model needs two planes");
    const size_t cells = x.planes.size() / x.species_count;  // values per plane
    const ParameterMaps& maps = x.operators.maps_for(*settings.maps);
    reaction_step(laplacian_for(maps, base, x.operators.mapped()), settings.reaction, x.planes.data(), x.scratch,
                  cells, x.pool,
                  reaction_maps(maps.feed(), maps.largest[MOLDTEX_MAP_FEED], maps.kill(),
                                maps.largest[MOLDTEX_MAP_KILL], settings.reaction));
    if (x.intrinsic) return;
    for (uint32_t k = 0; k < kReactionPlanes; ++k) fill_gutter(x.domain, x.planes.data() + k * cells, x.pool);
  }
};

}  // namespace

std::unique_ptr<CpuModelStep> gray_scott_cpu_step() { return std::make_unique<GrayScottCpuStep>(); }

}  // namespace moldtex
