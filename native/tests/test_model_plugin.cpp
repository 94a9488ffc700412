// Issue 49: a model is a plug-in. This file defines a model the library does not have (a
// field that only decays, e^(-r t)), registers it through models/model.h, and runs it
// through the C API: no file of the library names it. The executable links the core's
// objects statically (moldtex_objects), so that the registration reaches the library
// the C API calls.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "agents/momas_rules.h"
#include "backends/cpu/cpu_model_step.h"
#include "domain/texture_domain.h"
#include "mesh_fixtures.h"
#include "models/model.h"
#include "test_util.h"

namespace mtx {
namespace {

constexpr uint32_t kDecayModel = 1000;
constexpr float kRate = 0.5f;  // per second

class DecayStep final : public moldtex::CpuModelStep {
 public:
  void step(moldtex::CpuStepContext& x, const moldtex::StepSettings& settings, uint64_t, uint64_t,
            uint32_t*) override {
    const float keep = std::exp(-kRate * settings.params.time_step);
    for (float& v : x.planes) v *= keep;
  }
};

// No agents; every island texel starts at 1 and decays.
class Decay final : public moldtex::Model {
 public:
  uint32_t id() const override { return kDecayModel; }
  const char* name_in_text() const override { return "pure decay"; }
  void keep_config(moldtex_sim_config& c) const override {
    c.agent_count = 0;
    c.species_count = 1;
  }
  bool has_agents() const override { return false; }
  bool runs_on(uint32_t domain) const override { return domain == MOLDTEX_DOMAIN_TEXTURE; }
  float max_plane_value() const override { return 1.f; }
  double time_step(const moldtex::StepSettings& s) const override { return s.params.time_step; }
  std::unique_ptr<moldtex::CpuModelStep> cpu_step(size_t, uint32_t) const override {
    return std::make_unique<DecayStep>();
  }
  std::vector<float> initial_planes(const moldtex::Surface&, const moldtex::TextureDomain& d,
                                    const moldtex::StepSettings&, uint64_t, const std::vector<double>*,
                                    moldtex::ThreadPool&) const override {
    std::vector<float> plane(d.texel_count(), 0.f);
    for (size_t i = 0; i < plane.size(); ++i) plane[i] = d.classes[i] == MOLDTEX_TEXEL_OUTSIDE ? 0.f : 1.f;
    return plane;
  }
};

const Decay& RegisteredDecay() {
  static const Decay model;
  static const bool once = (moldtex::register_model(model), true);
  (void)once;
  return model;
}

TEST(ModelPlugin, ARegisteredModelRunsThroughTheCApi) {
  RegisteredDecay();
  auto surface = create_surface(make_uv_sphere(16, 8, 1.0));
  moldtex_sim_config config = make_config(32, 32, 1, 1);
  config.model = kDecayModel;
  config.backend = MOLDTEX_BACKEND_CPU;
  moldtex_sim_params params = default_params();
  auto sim = create_sim(surface.get(), config, params);
  ASSERT_TRUE(sim) << LastError();
  EXPECT_EQ(get_stats(sim.get()).agent_count, 0u);
  constexpr uint32_t kSteps = 90;
  ASSERT_EQ(moldtex_sim_step(sim.get(), kSteps), MOLDTEX_OK) << LastError();
  // e^(-r t) after t = 90 / 60 s; 90 float multiplications round within 1e-5.
  const double t = kSteps * double(params.time_step);
  const double expected = std::exp(-kRate * t);
  const std::vector<float> rgba = read_rgba(sim.get(), 32, 32);
  size_t inside = 0;
  for (size_t i = 0; i < rgba.size() / 4; ++i) {
    if (rgba[4 * i + 3] == 0.f) continue;  // outside the islands
    ++inside;
    ASSERT_NEAR(rgba[4 * i], expected, 1e-5 * expected) << "texel " << i;
  }
  EXPECT_GT(inside, 32u * 32u / 2);
  const moldtex_sim_stats stats = get_stats(sim.get());
  EXPECT_NEAR(stats.time, t, 1e-9);
  EXPECT_NEAR(stats.coverage, expected, 1e-5);  // the area-weighted mean of a uniform field
  // Its state goes through a checkpoint like any model's.
  TempDir dir;
  const std::string path = (dir.path / "decay.ckpt").string();
  ASSERT_EQ(moldtex_sim_save_checkpoint(sim.get(), path.c_str()), MOLDTEX_OK) << LastError();
  auto other = create_sim(surface.get(), config, params);
  ASSERT_EQ(moldtex_sim_load_checkpoint(other.get(), path.c_str()), MOLDTEX_OK) << LastError();
  EXPECT_EQ(read_rgba(other.get(), 32, 32), rgba);
  // The library's messages list it with the others.
  config.model = kDecayModel + 1;
  moldtex_sim unknown = nullptr;
  EXPECT_EQ(moldtex_sim_create(surface.get(), &config, &params, &unknown), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("pure decay"), std::string::npos) << LastError();
  // An id taken is refused.
  static const Decay twin;
  EXPECT_THROW(moldtex::register_model(twin), std::exception);
}

}  // namespace
}  // namespace mtx
