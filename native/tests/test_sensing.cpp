// Sensing kernel (moldtex_sim_params.sensor_size): MoMaS' reference code sums a
// (2r+1)^2 texel square around each sensor; 0 keeps the single texel under it.
#include <cstddef>
#include <cstring>

#include "test_backends.h"

namespace mtx {
namespace {

constexpr uint32_t kTex = 96, kAgents = 6000, kSteps = 60;

struct Outcome {
  std::vector<float> rgba;
  std::vector<moldtex_surface_point> agents;
  double coverage = 0;
};

bool SameBits(const Outcome& a, const Outcome& b) {
  return a.rgba.size() == b.rgba.size() && a.agents.size() == b.agents.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0 &&
         std::memcmp(a.agents.data(), b.agents.data(),
                     a.agents.size() * sizeof(moldtex_surface_point)) == 0;
}

class Sensing : public ::testing::TestWithParam<Backend> {
 protected:
  // kSteps steps on the cube (seams, boundary-free) with params `p`; false when skipped.
  bool Step(const moldtex_sim_params& p, Outcome* out) {
    const Mesh m = make_cube();
    auto s = create_surface(m);
    EXPECT_TRUE(s) << LastError();
    moldtex_sim_config c = make_config(kTex, kTex, kAgents, 17);
    std::string why;
    if (!PinBackend(GetParam(), c, &why)) {
      if (OpenClRequiredByEnv()) ADD_FAILURE() << "MOLDTEX_REQUIRE_OPENCL is set: " << why;
      return false;
    }
    auto sim = create_sim(s.get(), c, p);
    EXPECT_TRUE(sim) << LastError();
    if (!sim) return false;
    EXPECT_EQ(moldtex_sim_step(sim.get(), kSteps), MOLDTEX_OK) << LastError();
    out->rgba = read_rgba(sim.get(), kTex, kTex);
    out->agents = read_agents(sim.get(), kAgents);
    out->coverage = get_stats(sim.get()).coverage;
    return true;
  }
};

TEST_P(Sensing, SizeZeroIsBitIdenticalToACallerWithoutTheField) {
  // Header: sensor_size was appended with default 0 = the single texel, "bit for bit as
  // before the field existed". A caller whose struct ends at food_radius (any value
  // past its struct_size is ignored) and one that sets 0 get the same texture and
  // agents; a 2-texel square does change the run, so the field reaches the kernel.
  moldtex_sim_params old = default_params();
  old.struct_size = offsetof(moldtex_sim_params, sensor_size);
  old.sensor_size = 3;  // beyond the caller's struct: must be ignored
  moldtex_sim_params zero = default_params();
  zero.sensor_size = 0;
  moldtex_sim_params square = default_params();
  square.sensor_size = 2;
  Outcome a, b, c;
  if (!Step(old, &a)) GTEST_SKIP() << "no OpenCL device";
  ASSERT_TRUE(Step(zero, &b));
  ASSERT_TRUE(Step(square, &c));
  ASSERT_EQ(a.rgba.size(), size_t(kTex) * kTex * 4);
  EXPECT_TRUE(SameBits(a, b));
  EXPECT_FALSE(SameBits(a, c));
  // The square still forms trails (2% < coverage < 90%, as the single texel does).
  EXPECT_GT(c.coverage, 0.02);
  EXPECT_LT(c.coverage, 0.90);
}

MTX_BACKENDS(Sensing);

TEST(SensingParams, SizeIsValidatedAndRoundTrips) {
  // Header: hard range 0 .. 4; moldtex_sim_params_init sets 0.
  moldtex_sim_params p;
  moldtex_sim_params_init(&p);
  EXPECT_EQ(p.sensor_size, 0u);
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(32, 32, 100, 1), p);
  ASSERT_TRUE(sim) << LastError();
  for (uint32_t bad : {5u, 100u, 0xffffffffu}) {
    p.sensor_size = bad;
    EXPECT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_ERROR_INVALID_ARGUMENT) << bad;
  }
  p.sensor_size = 4;
  ASSERT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 2), MOLDTEX_OK) << LastError();
  moldtex_sim_params back;
  moldtex_sim_params_init(&back);
  ASSERT_EQ(moldtex_sim_get_params(sim.get(), &back), MOLDTEX_OK) << LastError();
  EXPECT_EQ(back.sensor_size, 4u);
}

}  // namespace
}  // namespace mtx
