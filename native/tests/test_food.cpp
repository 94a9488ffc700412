// Food with hunger (plasmodial-slime-readme.md, "Food Sources"): hungry agents are drawn
// to the nearest food source by an inverse-square attractor, eat within food_radius
// (hunger back to 0) and deplete finite sources. On a flat plane, where 3D distance is
// the distance an agent has to walk.
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <unistd.h>
#include <cstring>
#include <vector>

#include "test_backends.h"

namespace mtx {
namespace {

// [-4, 4]^2 in 32 x 32 cells on a 64 x 64 texture: one texel is 0.125 units.
Mesh Plane() {
  return make_plane(32, 32, -4, -4, 4, 4, [](double x, double y) { return Vec2{(x + 4) / 8, (y + 4) / 8}; });
}
constexpr uint32_t kTex = 64, kAgents = 4000;
const Vec3 kFood{2.0, 2.0, 0.0};

moldtex_sim_params Hungry(float rate) {
  moldtex_sim_params p = default_params();
  p.hunger_rate = rate;  // 1 per second: fully hungry 60 steps after eating
  p.food_radius = 0.25f; // two texels
  return p;
}

moldtex_food_source Source(float amount, float strength = 16.f) {
  moldtex_food_source f{};
  f.position[0] = static_cast<float>(kFood[0]);
  f.position[1] = static_cast<float>(kFood[1]);
  f.position[2] = static_cast<float>(kFood[2]);
  f.strength = strength;  // pull 1 (full blend) within 2 units
  f.amount = amount;
  return f;
}

double MeanDistance(moldtex_surface s, moldtex_sim sim) {
  double sum = 0;
  const auto agents = read_agents(sim, kAgents);
  for (const auto& a : agents) sum += norm(sub(evaluate_position(s, a), kFood));
  return sum / static_cast<double>(agents.size());
}

float Amount(moldtex_sim sim) {
  moldtex_food_source f{};
  uint32_t count = 0;
  EXPECT_EQ(moldtex_sim_get_food(sim, &f, 1, &count), MOLDTEX_OK) << LastError();
  EXPECT_EQ(count, 1u);
  return f.amount;
}

class Food : public ::testing::TestWithParam<Backend> {};

// Mean distance at steps 0, 50, 150, 300 with one source.
std::vector<double> RunFood(moldtex_surface s, moldtex_sim_config c, float rate, float amount,
                        std::vector<float>* amounts = nullptr) {
  auto sim = create_sim(s, c, Hungry(rate));
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return {};
  const moldtex_food_source f = Source(amount);
  EXPECT_EQ(moldtex_sim_set_food(sim.get(), &f, 1), MOLDTEX_OK) << LastError();
  std::vector<double> d{MeanDistance(s, sim.get())};
  uint32_t at = 0;
  for (uint32_t step : {50u, 150u, 300u, 600u}) {
    EXPECT_EQ(moldtex_sim_step(sim.get(), step - at), MOLDTEX_OK) << LastError();
    at = step;
    d.push_back(MeanDistance(s, sim.get()));
    if (amounts) amounts->push_back(Amount(sim.get()));
  }
  return d;
}

TEST_P(Food, HungryAgentsGatherAtTheSource) {
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(kTex, kTex, kAgents, 11);
  MTX_PIN_BACKEND(c);
  const auto fed = RunFood(s.get(), c, 4.f, -1.f);
  const auto off = RunFood(s.get(), c, 0.f, -1.f);
  ASSERT_EQ(fed.size(), 5u);
  ASSERT_EQ(off.size(), 5u);
  std::printf("mean distance with hunger %.3f %.3f %.3f %.3f, without %.3f %.3f %.3f %.3f\n",
              fed[0], fed[1], fed[2], fed[3], off[0], off[1], off[2], off[3]);
  // Measured (CPU / OpenCL, 2026-12-05), with Plasmodial Slime's weight |F| h^8: hungry
  // 3.98 -> 0.95 / 0.96 -> 0.78 / 0.66 -> 0.60 / 0.63 at steps 0, 50, 150, 300; without
  // hunger 3.98 -> 3.17 .. 4.14. Tolerances: the gathering must be strong (below 30% of the start
  // by step 50, 20% by step 300) and keep going (each later mean no more than 0.05 above
  // the previous: the standard error of a 4000-agent mean is ~0.01). Without hunger the
  // agents gather on their own network, wherever it forms: their mean distance from the
  // source is not an iid mean. Over seeds 1..12 (2026-12-05) it read 0.77-1.18 of the
  // start at step 300 on the two backends (standard deviation 0.10 of the start; a 15%
  // band, as until then, failed for 3 of 12 seeds on the CPU). Hence 35%, over three standard
  // deviations, far from the 0.15-0.25 that gathering at the source reaches.
  EXPECT_LT(fed[1], 0.3 * fed[0]);
  EXPECT_LT(fed[2], fed[1] + 0.05);
  EXPECT_LT(fed[3], fed[2] + 0.05);
  EXPECT_LT(fed[3], 0.2 * fed[0]);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_NEAR(off[k], off[0], 0.35 * off[0]) << "step index " << k;
    EXPECT_LT(fed[k], 0.3 * off[k]) << "step index " << k;
  }
}

TEST_P(Food, FiniteSourceEmptiesAndStopsAttracting) {
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(kTex, kTex, kAgents, 11);
  MTX_PIN_BACKEND(c);
  std::vector<float> amounts;
  const auto d = RunFood(s.get(), c, 4.f, 20000.f, &amounts);
  ASSERT_EQ(d.size(), 5u);
  ASSERT_EQ(amounts.size(), 4u);
  std::printf("left %.0f %.0f, mean distance %.3f %.3f %.3f %.3f %.3f\n", amounts[0],
              amounts[1], d[0], d[1], d[2], d[3], d[4]);
  // Measured (CPU / OpenCL): 8704 / 8202 units left at step 50 with the agents gathered
  // (mean distance 0.98 / 1.04), empty by step 150; then the agents spread again (mean
  // 4.7 .. 5.2 / 3.8 .. 5.5, as without food: about 4). Tolerances: gathered below 1.3
  // (a third of the start), spread again above 2.5 at 150, 300 and 600.
  EXPECT_GT(amounts[0], 0.f);
  EXPECT_LT(amounts[0], 20000.f);
  EXPECT_LT(d[1], 1.3);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_EQ(amounts[k], 0.f) << "an emptied source stays empty (amount clamped at 0)";
    EXPECT_GT(d[k + 1], 2.5) << "an empty source no longer attracts; step index " << k + 1;
  }
}

struct Snapshot {
  std::vector<float> rgba;
  std::vector<moldtex_surface_point> agents;
  std::vector<moldtex_food_source> food;
};

Snapshot Take(moldtex_sim sim) {
  Snapshot s{read_rgba(sim, kTex, kTex), read_agents(sim, kAgents), {}};
  uint32_t count = 0;
  s.food.resize(MOLDTEX_MAX_FOOD_SOURCES);
  EXPECT_EQ(moldtex_sim_get_food(sim, s.food.data(), MOLDTEX_MAX_FOOD_SOURCES, &count), MOLDTEX_OK);
  s.food.resize(count);
  return s;
}

bool SameBits(const Snapshot& a, const Snapshot& b) {
  return a.rgba.size() == b.rgba.size() && a.agents.size() == b.agents.size() &&
         a.food.size() == b.food.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0 &&
         std::memcmp(a.agents.data(), b.agents.data(), a.agents.size() * sizeof(a.agents[0])) == 0 &&
         std::memcmp(a.food.data(), b.food.data(), a.food.size() * sizeof(a.food[0])) == 0;
}

// Eating follows simulated time in surface units: an agent at a source eats one unit per
// decision, and agents decide once per MoMaS tick (60 a simulated second) at any time
// step: every 2nd step at 1/120 s, twice a step at 1/30 s. With a radius that holds the
// whole plane every agent is at the source all the time, so one simulated second eats
// exactly agents x 60 units at 1/60, 1/120 and 1/30 s (integer counts, exact in a
// float below 2^24). Texel units keep MoMaS' one decision per step: 1/120 s eats per
// step, twice as much per second (the known answer the count must tell apart).
TEST_P(Food, SurfaceUnitsEatPerSecondAtAnyTimeStep) {
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  constexpr uint32_t kEaters = 1000;
  constexpr float kStart = 1.0e6f;
  moldtex_sim_config c = make_config(kTex, kTex, kEaters, 5);
  MTX_PIN_BACKEND(c);
  auto eaten = [&](float steps_per_second, bool surface) -> double {
    moldtex_sim_params p = Hungry(1.f);
    p.food_radius = 100.f;  // the whole plane
    p.time_step = 1.f / steps_per_second;
    if (surface) p.length_unit = 8.f / kTex;  // one texel
    auto sim = create_sim(s.get(), c, p);
    EXPECT_TRUE(sim) << LastError();
    if (!sim) return -1.0;
    const moldtex_food_source f = Source(kStart);
    EXPECT_EQ(moldtex_sim_set_food(sim.get(), &f, 1), MOLDTEX_OK) << LastError();
    EXPECT_EQ(moldtex_sim_step(sim.get(), uint32_t(steps_per_second)), MOLDTEX_OK) << LastError();
    return double(kStart) - double(Amount(sim.get()));
  };
  for (float rate : {60.f, 120.f, 30.f}) EXPECT_EQ(eaten(rate, true), 60.0 * kEaters) << "1/" << rate << " s";
  EXPECT_EQ(eaten(120.f, false), 120.0 * kEaters) << "texel units, 1/120 s";
}

TEST_P(Food, HungerOffIsBitIdenticalToNoFood) {
  // Header: hunger_rate 0 (the default) turns food off; results equal a simulation
  // without food bit for bit, on each backend.
  auto s = create_surface(Plane());
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(kTex, kTex, kAgents, 5);
  MTX_PIN_BACKEND(c);
  auto plain = create_sim(s.get(), c, default_params());
  auto fed = create_sim(s.get(), c, Hungry(0.f));
  ASSERT_TRUE(plain && fed) << LastError();
  const moldtex_food_source f[2] = {Source(-1.f), Source(100.f, 50.f)};
  ASSERT_EQ(moldtex_sim_set_food(fed.get(), f, 2), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(plain.get(), 60), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_step(fed.get(), 60), MOLDTEX_OK);
  Snapshot a = Take(plain.get()), b = Take(fed.get());
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(0, std::memcmp(a.agents.data(), b.agents.data(), a.agents.size() * sizeof(a.agents[0])));
  ASSERT_EQ(b.food.size(), 2u);
  EXPECT_EQ(b.food[1].amount, 100.f) << "nothing is eaten while hunger is off";
}

TEST_P(Food, CheckpointRoundTripWithHungerIsBitIdentical) {
  // Header: a checkpoint restores the state exactly (hunger and food amounts included):
  // save at step 40, run to 80; a fresh simulation without food loaded from it and run
  // 40 steps matches bit for bit.
  auto s = create_surface(Plane());
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(kTex, kTex, kAgents, 8);
  MTX_PIN_BACKEND(c);
  const std::string path = ::testing::TempDir() + "moldtex_food_" + std::to_string(getpid()) +
                           (GetParam() == Backend::Cpu ? "_cpu.bin" : "_opencl.bin");
  struct Remove {
    std::string p;
    ~Remove() { std::remove(p.c_str()); }
  } remove{path};
  auto a = create_sim(s.get(), c, Hungry(4.f));
  ASSERT_TRUE(a) << LastError();
  const moldtex_food_source f[2] = {Source(20000.f), Source(-1.f, 2.f)};
  moldtex_food_source g = f[1];
  g.position[0] = -2.f;
  const moldtex_food_source both[2] = {f[0], g};
  ASSERT_EQ(moldtex_sim_set_food(a.get(), both, 2), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_step(a.get(), 40), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_save_checkpoint(a.get(), path.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(a.get(), 40), MOLDTEX_OK);
  auto b = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(b) << LastError();
  ASSERT_EQ(moldtex_sim_load_checkpoint(b.get(), path.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(b.get(), 40), MOLDTEX_OK);
  const Snapshot sa = Take(a.get()), sb = Take(b.get());
  EXPECT_TRUE(SameBits(sa, sb));
  ASSERT_EQ(sa.food.size(), 2u);
  EXPECT_LT(sa.food[0].amount, 20000.f) << "agents did eat";
  moldtex_sim_params p;
  moldtex_sim_params_init(&p);
  ASSERT_EQ(moldtex_sim_get_params(b.get(), &p), MOLDTEX_OK);
  EXPECT_EQ(p.hunger_rate, 4.f);
}


TEST(FoodCpu, DepletionDoesNotDependOnThreadCount) {
  // Eaters are counted with integer atomics and subtracted after the agent pass, so 1 and
  // 2 threads agree bit for bit (agents, pheromone and amounts left).
  auto s = create_surface(Plane());
  ASSERT_TRUE(s) << LastError();
  const moldtex_sim_config c = make_config(kTex, kTex, kAgents, 3);
  Snapshot out[2];
  for (uint32_t t = 1; t <= 2; ++t) {
    moldtex_sim_params p = Hungry(4.f);
    p.thread_count = t;
    auto sim = create_sim(s.get(), c, p);
    ASSERT_TRUE(sim) << LastError();
    const moldtex_food_source f = Source(20000.f);
    ASSERT_EQ(moldtex_sim_set_food(sim.get(), &f, 1), MOLDTEX_OK);
    ASSERT_EQ(moldtex_sim_step(sim.get(), 70), MOLDTEX_OK);
    out[t - 1] = Take(sim.get());
  }
  EXPECT_TRUE(SameBits(out[0], out[1]));
  ASSERT_EQ(out[0].food.size(), 1u);
  EXPECT_LT(out[0].food[0].amount, 20000.f);
}

TEST(FoodCpu, RefusesBadInput) {
  auto s = create_surface(Plane());
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(kTex, kTex, 100, 1), default_params());
  ASSERT_TRUE(sim) << LastError();
  const float nan = std::nanf(""), inf = INFINITY;
  moldtex_food_source f = Source(10.f);
  std::vector<moldtex_food_source> many(MOLDTEX_MAX_FOOD_SOURCES + 1, f);
  EXPECT_EQ(moldtex_sim_set_food(sim.get(), many.data(), MOLDTEX_MAX_FOOD_SOURCES + 1),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError(), "");
  EXPECT_EQ(moldtex_sim_set_food(sim.get(), many.data(), MOLDTEX_MAX_FOOD_SOURCES), MOLDTEX_OK);
  EXPECT_EQ(moldtex_sim_set_food(sim.get(), nullptr, 1), MOLDTEX_ERROR_INVALID_ARGUMENT);
  for (int field = 0; field < 5; ++field)
    for (float bad : {nan, inf}) {
      moldtex_food_source g = f;
      (field < 3 ? g.position[field] : (field == 3 ? g.strength : g.amount)) = bad;
      EXPECT_EQ(moldtex_sim_set_food(sim.get(), &g, 1), MOLDTEX_ERROR_INVALID_ARGUMENT) << field;
    }
  f.strength = -1.f;
  EXPECT_EQ(moldtex_sim_set_food(sim.get(), &f, 1), MOLDTEX_ERROR_INVALID_ARGUMENT);
  // A refused call changes nothing: the 64 sources are still there.
  uint32_t count = 0;
  EXPECT_EQ(moldtex_sim_get_food(sim.get(), nullptr, 0, &count), MOLDTEX_OK);
  EXPECT_EQ(count, MOLDTEX_MAX_FOOD_SOURCES);
  EXPECT_EQ(moldtex_sim_get_food(sim.get(), nullptr, 0, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_get_food(sim.get(), nullptr, 1, &count), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_set_food(sim.get(), nullptr, 0), MOLDTEX_OK);  // clears
  EXPECT_EQ(moldtex_sim_get_food(sim.get(), nullptr, 0, &count), MOLDTEX_OK);
  EXPECT_EQ(count, 0u);

  for (float bad : {-1.f, nan, inf, 2000.f}) {
    moldtex_sim_params p = default_params();
    p.hunger_rate = bad;
    EXPECT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_ERROR_INVALID_ARGUMENT) << bad;
    p = default_params();
    p.food_radius = bad < 0 || !std::isfinite(bad) ? bad : -bad;
    EXPECT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_ERROR_INVALID_ARGUMENT) << bad;
  }
}

TEST(FoodCpu, OlderParamsStructGetsFoodOff) {
  // Header: fields are appended; a caller whose struct ends at thread_count gets the
  // defaults (hunger_rate 0, food_radius 0.1), and get_params writes only its size.
  auto s = create_surface(Plane());
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(kTex, kTex, 100, 1), Hungry(4.f));
  ASSERT_TRUE(sim) << LastError();
  moldtex_sim_params old = default_params();
  old.struct_size = offsetof(moldtex_sim_params, hunger_rate);
  old.hunger_rate = 123.f;  // beyond the caller's struct: must be ignored
  ASSERT_EQ(moldtex_sim_set_params(sim.get(), &old), MOLDTEX_OK) << LastError();
  moldtex_sim_params back;
  moldtex_sim_params_init(&back);
  ASSERT_EQ(moldtex_sim_get_params(sim.get(), &back), MOLDTEX_OK);
  EXPECT_EQ(back.hunger_rate, 0.f);
  EXPECT_FLOAT_EQ(back.food_radius, 0.1f);
  old.struct_size = 4;
  EXPECT_EQ(moldtex_sim_set_params(sim.get(), &old), MOLDTEX_ERROR_INVALID_ARGUMENT);
}

MTX_BACKENDS(Food);

}  // namespace
}  // namespace mtx
