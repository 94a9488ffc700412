// Building the intrinsic domain ahead with progress and cancel (moldtex_domain_build_*,
// issue 11): what an interface needs to show a long build and let the user stop it.
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>
#include <vector>

#include "test_util.h"

namespace mtx {
namespace {

struct BuildDeleter {
  void operator()(moldtex_domain_build_t* p) const { moldtex_domain_build_release(p); }
};
using BuildPtr = std::unique_ptr<moldtex_domain_build_t, BuildDeleter>;

const Mesh& Torus() {
  static const Mesh m = make_torus(64, 32, 1.0, 0.4);
  return m;
}

moldtex_sim_config IntrinsicConfig(uint32_t size) {
  moldtex_sim_config c = make_config(size, size, 1000, 1);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.domain = MOLDTEX_DOMAIN_INTRINSIC;
  c.backend = MOLDTEX_BACKEND_CPU;
  return c;
}

BuildPtr Start(moldtex_surface s, const moldtex_sim_config& c, moldtex_status* status = nullptr) {
  moldtex_domain_build out = nullptr;
  const moldtex_status st = moldtex_domain_build_start(s, &c, 0, &out);
  if (status) *status = st;
  else EXPECT_EQ(st, MOLDTEX_OK) << LastError();
  return BuildPtr(out);
}

moldtex_domain_build_progress Progress(moldtex_domain_build b) {
  moldtex_domain_build_progress p;
  moldtex_domain_build_progress_init(&p);
  EXPECT_EQ(moldtex_domain_build_get_progress(b, &p), MOLDTEX_OK) << LastError();
  return p;
}

// A build polled every 2 ms: the stage and the fraction only grow, the fraction ends at 1
// with the stage Done, the vertex count is the domain's, and the simulation created next
// with the same config reuses it (from_cache) instead of building again.
TEST(DomainBuild, ReportsProgressAndTheSimulationReusesIt) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s);
  const moldtex_sim_config c = IntrinsicConfig(192);
  auto build = Start(s.get(), c);
  ASSERT_TRUE(build);
  std::vector<moldtex_domain_build_progress> seen;
  for (;;) {
    seen.push_back(Progress(build.get()));
    if (seen.back().state != MOLDTEX_BAKE_RUNNING) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_EQ(moldtex_domain_build_wait(build.get()), MOLDTEX_OK) << LastError();
  const auto& last = seen.back();
  EXPECT_EQ(last.state, uint32_t(MOLDTEX_BAKE_FINISHED));
  EXPECT_EQ(last.stage, uint32_t(MOLDTEX_BUILD_DONE));
  EXPECT_EQ(last.fraction, 1.0);
  EXPECT_EQ(last.from_cache, 0u);
  EXPECT_GT(last.seconds, 0.0);
  int refining = 0, partway = 0;
  for (size_t i = 1; i < seen.size(); ++i) {
    EXPECT_GE(seen[i].stage, seen[i - 1].stage) << i;
    EXPECT_GE(seen[i].fraction, seen[i - 1].fraction) << i;
    refining += seen[i].stage == MOLDTEX_BUILD_REFINING && seen[i].vertex_count > 0;
    partway += seen[i].fraction > 0.1 && seen[i].fraction < 0.9;
  }
  // A build of about a second seen every 2 ms: many looks during the refinement, with
  // the fraction moving between (the estimate is not just 0 then 1).
  std::printf("%zu looks, %d while refining, %d part-way; %u vertices in %.2f s\n", seen.size(), refining, partway,
              last.vertex_count, last.seconds);
  EXPECT_GT(refining, 5);
  EXPECT_GT(partway, 5);

  moldtex_sim_params mp = default_params();
  auto sim = create_sim(s.get(), c, mp);
  ASSERT_TRUE(sim) << LastError();
  moldtex_domain_info info;
  moldtex_domain_info_init(&info);
  ASSERT_EQ(moldtex_sim_get_domain_info(sim.get(), &info), MOLDTEX_OK) << LastError();
  EXPECT_EQ(info.from_cache, 1u);
  EXPECT_EQ(info.cell_count, last.vertex_count);

  // Built again: the cache answers at once.
  auto again = Start(s.get(), c);
  ASSERT_EQ(moldtex_domain_build_wait(again.get()), MOLDTEX_OK) << LastError();
  EXPECT_EQ(Progress(again.get()).from_cache, 1u);
}

// Cancel stops a refinement part-way within a fraction of a second (it is checked every
// 1024 insertions, ~10 ms of work; 0.5 s allows for a loaded machine), says Cancelled,
// and leaves nothing in the cache: the same build starts from scratch.
TEST(DomainBuild, CancelStopsItAndKeepsNothing) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s);
  const moldtex_sim_config c = IntrinsicConfig(640);  // ~300 k vertices: several seconds
  auto build = Start(s.get(), c);
  ASSERT_TRUE(build);
  moldtex_domain_build_progress p;
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    p = Progress(build.get());
  } while (p.state == MOLDTEX_BAKE_RUNNING && !(p.stage == MOLDTEX_BUILD_REFINING && p.vertex_count > 0));
  ASSERT_EQ(p.state, uint32_t(MOLDTEX_BAKE_RUNNING)) << "the build ended before it could be cancelled";
  const auto asked = std::chrono::steady_clock::now();
  moldtex_domain_build_cancel(build.get());
  EXPECT_EQ(moldtex_domain_build_wait(build.get()), MOLDTEX_ERROR_CANCELLED);
  const double latency = std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
  EXPECT_NE(LastError().find("Cancelled"), std::string::npos) << LastError();
  p = Progress(build.get());
  std::printf("cancelled at %.0f%% (%u vertices) after %.3f s\n", 100 * p.fraction, p.vertex_count, latency);
  EXPECT_EQ(p.state, uint32_t(MOLDTEX_BAKE_CANCELLED));
  EXPECT_LT(p.fraction, 1.0);
  EXPECT_LT(latency, 0.5);

  auto again = Start(s.get(), c);
  ASSERT_TRUE(again);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(Progress(again.get()).from_cache, 0u);
  // Released while running: cancels and waits (no thread left behind, no crash).
}

TEST(DomainBuild, RefusesWhatNoSimulationWouldRun) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s);
  moldtex_status status;
  moldtex_sim_config c = IntrinsicConfig(64);
  c.domain = MOLDTEX_DOMAIN_TEXTURE;
  EXPECT_FALSE(Start(s.get(), c, &status));
  EXPECT_EQ(status, MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("Intrinsic"), std::string::npos) << LastError();
  c = IntrinsicConfig(64);
  c.model = MOLDTEX_MODEL_MOMAS;
  EXPECT_FALSE(Start(s.get(), c, &status));
  EXPECT_NE(LastError().find("Texture domain"), std::string::npos) << LastError();
  c = IntrinsicConfig(64);
  c.intrinsic_bound = std::nanf("");
  EXPECT_FALSE(Start(s.get(), c, &status));
  EXPECT_NE(LastError().find("bound"), std::string::npos) << LastError();
  c = IntrinsicConfig(64);
  c.width = 100000;
  EXPECT_FALSE(Start(s.get(), c, &status));
  moldtex_domain_build out = reinterpret_cast<moldtex_domain_build>(1);
  EXPECT_EQ(moldtex_domain_build_start(nullptr, &c, 0, &out), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(out, nullptr);
  EXPECT_EQ(moldtex_domain_build_wait(nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  moldtex_domain_build_progress p;
  moldtex_domain_build_progress_init(&p);
  EXPECT_EQ(moldtex_domain_build_get_progress(nullptr, &p), MOLDTEX_ERROR_INVALID_ARGUMENT);
  moldtex_domain_build_cancel(nullptr);
  moldtex_domain_build_release(nullptr);
}

// Two simulations on one cached domain share its Laplacian and the PDE's plan, scratch
// and lanes (texel_laplacian.h): stepped at once from two threads, each must still give
// what one simulation alone gives, bit for bit (the Laplacian's guard serialises their
// PDE steps; with the guard taken out, 2 of 3 runs had 709-1755 of the 11,455 vertices
// differ: both wrote the same scratch).
TEST(DomainBuild, TwoSimulationsOnOneCachedDomainStepAtOnce) {
  // The UV sphere's poles leave small cells, so the PDE steps them locally (fine cells
  // with their scratch), the part the two would share.
  auto s = create_surface(make_uv_sphere(64, 32, 1.0));
  ASSERT_TRUE(s);
  moldtex_sim_config c = IntrinsicConfig(128);
  c.agent_count = 20000;
  moldtex_sim_params p = default_params();
  p.thread_count = 1;
  const uint32_t steps = 40;
  auto values = [&](moldtex_sim sim) {
    moldtex_domain_info info;
    moldtex_domain_info_init(&info);
    EXPECT_EQ(moldtex_sim_get_domain_info(sim, &info), MOLDTEX_OK) << LastError();
    std::vector<float> v(info.cell_count);
    EXPECT_EQ(moldtex_sim_read_intrinsic_vertices(sim, nullptr, v.data(), info.cell_count), MOLDTEX_OK)
        << LastError();
    return v;
  };
  std::vector<float> alone;
  {
    auto sim = create_sim(s.get(), c, p);
    ASSERT_TRUE(sim) << LastError();
    ASSERT_EQ(moldtex_sim_step(sim.get(), steps), MOLDTEX_OK) << LastError();
    alone = values(sim.get());
  }
  auto a = create_sim(s.get(), c, p), b = create_sim(s.get(), c, p);
  ASSERT_TRUE(a && b) << LastError();
  moldtex_domain_info info;
  moldtex_domain_info_init(&info);
  ASSERT_EQ(moldtex_sim_get_domain_info(b.get(), &info), MOLDTEX_OK);
  ASSERT_EQ(info.from_cache, 1u) << "the second simulation must share the first one's domain";
  moldtex_status sa = MOLDTEX_OK, sb = MOLDTEX_OK;
  std::thread ta([&] { for (uint32_t i = 0; i < steps && sa == MOLDTEX_OK; ++i) sa = moldtex_sim_step(a.get(), 1); });
  std::thread tb([&] { for (uint32_t i = 0; i < steps && sb == MOLDTEX_OK; ++i) sb = moldtex_sim_step(b.get(), 1); });
  ta.join();
  tb.join();
  ASSERT_EQ(sa, MOLDTEX_OK);
  ASSERT_EQ(sb, MOLDTEX_OK);
  const std::vector<float> va = values(a.get()), vb = values(b.get());
  ASSERT_EQ(va.size(), alone.size());
  ASSERT_EQ(vb.size(), alone.size());
  size_t differ_a = 0, differ_b = 0;
  for (size_t i = 0; i < alone.size(); ++i) {
    differ_a += std::memcmp(&va[i], &alone[i], 4) != 0;
    differ_b += std::memcmp(&vb[i], &alone[i], 4) != 0;
  }
  std::printf("%zu vertices: %zu and %zu differ from one simulation alone after %u steps in parallel\n", alone.size(),
              differ_a, differ_b, steps);
  EXPECT_EQ(differ_a, 0u);
  EXPECT_EQ(differ_b, 0u);
}

}  // namespace
}  // namespace mtx
