// Determinism: a bake is reproducible bit-for-bit from its seed, whatever the thread
// count, the stepping rhythm, or a reset in between.
#include <thread>

#include "test_util.h"

namespace mtx {
namespace {

constexpr uint32_t kW = 128, kH = 128, kAgents = 10000, kSteps = 48;  // 3 agent regroupings

struct Snapshot {
  std::vector<float> rgba;
  std::vector<moldtex_surface_point> agents;
};

Snapshot Take(moldtex_sim sim) { return {read_rgba(sim, kW, kH), read_agents(sim, kAgents)}; }

bool SameBits(const Snapshot& a, const Snapshot& b) {
  return a.rgba.size() == b.rgba.size() && a.agents.size() == b.agents.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0 &&
         std::memcmp(a.agents.data(), b.agents.data(),
                     a.agents.size() * sizeof(moldtex_surface_point)) == 0;
}

size_t DifferentTexels(const Snapshot& a, const Snapshot& b) {
  size_t n = 0;
  for (size_t i = 0; i < std::min(a.rgba.size(), b.rgba.size()); ++i) n += a.rgba[i] != b.rgba[i];
  return n;
}

// The cube: seams, gutter, sensing across islands — everything that could race.
Snapshot Simulate(uint32_t threads, uint64_t seed, uint32_t steps = kSteps) {
  const Mesh m = make_cube();
  auto s = create_surface(m);
  EXPECT_TRUE(s) << LastError();
  if (!s) return {};
  moldtex_sim_params p = default_params();
  p.thread_count = threads;
  auto sim = create_sim(s.get(), make_config(kW, kH, kAgents, seed), p);
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return {};
  EXPECT_EQ(moldtex_sim_step(sim.get(), steps), MOLDTEX_OK) << LastError();
  return Take(sim.get());
}

TEST(Determinism, SameSeedBitIdenticalForOneTwoFourThreads) {
  // Header: same seed => bit-identical results for any thread count (memcmp).
  const Snapshot one = Simulate(1, 42);
  ASSERT_EQ(one.rgba.size(), size_t(kW) * kH * 4);
  ASSERT_EQ(one.agents.size(), kAgents);
  const Snapshot two = Simulate(2, 42);
  const Snapshot four = Simulate(4, 42);
  const Snapshot all = Simulate(0, 42);
  EXPECT_TRUE(SameBits(one, two)) << DifferentTexels(one, two) << " floats differ (1 vs 2)";
  EXPECT_TRUE(SameBits(one, four)) << DifferentTexels(one, four) << " floats differ (1 vs 4)";
  EXPECT_TRUE(SameBits(one, all)) << DifferentTexels(one, all) << " floats differ (1 vs all)";
  // And the run did something: pheromone is present.
  size_t nonzero = 0;
  for (size_t i = 0; i < one.rgba.size(); i += 4) nonzero += one.rgba[i] > 0;
  EXPECT_GT(nonzero, 1000u);
  static_assert(kSteps % 6 == 0, "ChangingThreadCountMidRunChangesNothing steps in sixths");
}

TEST(Determinism, SameSeedSameResultWhenRepeated) {
  EXPECT_TRUE(SameBits(Simulate(2, 7), Simulate(2, 7)));
}

TEST(Determinism, DifferentSeedsDiffer) {
  // Different seeds give different spawns and hence different textures.
  const Snapshot a = Simulate(2, 1), b = Simulate(2, 2);
  EXPECT_GT(DifferentTexels(a, b), 1000u);
  EXPECT_NE(0, std::memcmp(a.agents.data(), b.agents.data(),
                           a.agents.size() * sizeof(moldtex_surface_point)));
}

TEST(Determinism, ResetEqualsFreshSimulation) {
  // Header: reset clears the pheromone and respawns the agents from the config's seed.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(kW, kH, kAgents, 42), default_params());
  ASSERT_TRUE(sim) << LastError();
  const Snapshot spawn = Take(sim.get());
  ASSERT_EQ(moldtex_sim_step(sim.get(), kSteps), MOLDTEX_OK) << LastError();
  const Snapshot first = Take(sim.get());

  ASSERT_EQ(moldtex_sim_reset(sim.get()), MOLDTEX_OK) << LastError();
  const Snapshot after_reset = Take(sim.get());
  EXPECT_TRUE(SameBits(spawn, after_reset)) << "reset must restore the spawn state exactly";
  const auto st = get_stats(sim.get());
  EXPECT_EQ(st.step_count, 0u);
  EXPECT_EQ(st.coverage, 0.0);
  EXPECT_EQ(st.presence, 0.0);

  ASSERT_EQ(moldtex_sim_step(sim.get(), kSteps), MOLDTEX_OK) << LastError();
  EXPECT_TRUE(SameBits(first, Take(sim.get()))) << "run after reset differs from the first run";
  EXPECT_TRUE(SameBits(first, Simulate(0, 42))) << "differs from a fresh simulation";
}

TEST(Determinism, SteppingRhythmDoesNotMatter) {
  // The live preview steps a few per timer tick, the bake many per frame: the
  // sequence of single steps must be the same (step(48) == 48 x step(1) == 13 + 35).
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto a = create_sim(s.get(), make_config(kW, kH, kAgents, 42), default_params());
  auto b = create_sim(s.get(), make_config(kW, kH, kAgents, 42), default_params());
  ASSERT_TRUE(a && b) << LastError();
  ASSERT_EQ(moldtex_sim_step(a.get(), 13), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_step(a.get(), kSteps - 13), MOLDTEX_OK);
  for (uint32_t i = 0; i < kSteps; ++i) ASSERT_EQ(moldtex_sim_step(b.get(), 1), MOLDTEX_OK);
  const Snapshot once = Simulate(0, 42);
  EXPECT_TRUE(SameBits(once, Take(a.get())));
  EXPECT_TRUE(SameBits(once, Take(b.get())));
}

TEST(Determinism, ChangingThreadCountMidRunChangesNothing) {
  // thread_count is a live parameter; switching it between steps keeps the same bits.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_params p = default_params();
  p.thread_count = 1;
  auto sim = create_sim(s.get(), make_config(kW, kH, kAgents, 42), p);
  ASSERT_TRUE(sim) << LastError();
  for (uint32_t k = 0; k < 6; ++k) {
    p.thread_count = (k % 3 == 0) ? 1 : (k % 3 == 1 ? 4 : 2);
    ASSERT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_OK) << LastError();
    ASSERT_EQ(moldtex_sim_step(sim.get(), kSteps / 6), MOLDTEX_OK) << LastError();
  }
  EXPECT_TRUE(SameBits(Simulate(1, 42), Take(sim.get())));
}

TEST(Determinism, IndependentHandlesRunConcurrently) {
  // Header: different handles are independent; two simulations stepped at the same
  // time on two threads give the same bits as one run alone.
  const Snapshot alone = Simulate(2, 42);
  Snapshot x, y;
  std::thread tx([&] { x = Simulate(2, 42); });
  std::thread ty([&] { y = Simulate(2, 42); });
  tx.join();
  ty.join();
  EXPECT_TRUE(SameBits(alone, x));
  EXPECT_TRUE(SameBits(alone, y));
}

}  // namespace
}  // namespace mtx
