// Parameter maps and stimuli of the continuous model (layton-intrinsic-slime.md §3.3,
// Fig. 7, 8; issue #12): moldtex_sim_set_map. A map multiplies its parameter where the
// agent stands; a lifetime of 0 is a sink, spawn weights are sources; a read stimulus is
// sensed, a write stimulus adds pheromone. Every check here has an answer known in
// advance (an exact count, a steady state, or a uniform run of the same parameters).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>

#include "pattern_measures.h"
#include "test_backends.h"
#include "test_util.h"

namespace mtx {
namespace {

// A 2 x 2 plane (area 4), UV = xy / 2: texel (x, y) of an N x N texture lies at
// ((x + 0.5) 2 / N, (y + 0.5) 2 / N).
const Mesh& Plane() {
  static const Mesh m = make_plane(32, 32, 0.0, 0.0, 2.0, 2.0, [](double x, double y) { return Vec2{x / 2, y / 2}; });
  return m;
}

constexpr uint32_t kSize = 256;

using MapOf = std::function<float(double x, double y)>;  // plane coordinates

std::vector<float> MapImage(const MapOf& f, uint32_t size = kSize) {
  std::vector<float> m(size_t(size) * size);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) m[size_t(y) * size + x] = f((x + 0.5) * 2.0 / size, (y + 0.5) * 2.0 / size);
  return m;
}

struct MapRun {
  SurfacePtr surface;
  SimPtr sim;
};

MapRun Start(uint32_t agents, uint64_t seed, const moldtex_continuous_params& p,
             const std::vector<std::pair<uint32_t, MapOf>>& maps, Backend backend = Backend::Cpu,
             uint32_t threads = 0) {
  MapRun r;
  r.surface = create_surface(Plane());
  EXPECT_TRUE(r.surface) << LastError();
  moldtex_sim_config c = make_config(kSize, kSize, agents, seed);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  std::string why;
  EXPECT_TRUE(PinBackend(backend, c, &why)) << why;
  moldtex_sim_params mp = default_params();
  mp.thread_count = threads;
  r.sim = create_sim(r.surface.get(), c, mp);
  EXPECT_TRUE(r.sim) << LastError();
  if (!r.sim) return r;
  EXPECT_EQ(moldtex_sim_set_continuous_params(r.sim.get(), &p), MOLDTEX_OK) << LastError();
  for (const auto& [kind, f] : maps) {
    const std::vector<float> m = MapImage(f);
    EXPECT_EQ(moldtex_sim_set_map(r.sim.get(), kind, m.data(), m.size()), MOLDTEX_OK) << LastError();
  }
  return r;
}

std::vector<double> Shown(moldtex_sim sim) {
  const std::vector<float> rgba = read_rgba(sim, kSize, kSize);
  std::vector<double> shown(size_t(kSize) * kSize);
  for (size_t i = 0; i < shown.size(); ++i) shown[i] = rgba[4 * i];
  return shown;
}

std::vector<double> Simulate(uint32_t agents, uint64_t seed, const moldtex_continuous_params& p,
                             const std::vector<std::pair<uint32_t, MapOf>>& maps, double seconds,
                             Backend backend = Backend::Cpu, uint32_t threads = 0) {
  MapRun r = Start(agents, seed, p, maps, backend, threads);
  if (!r.sim) return {};
  EXPECT_EQ(moldtex_sim_step(r.sim.get(), uint32_t(std::lround(seconds / p.time_step))), MOLDTEX_OK) << LastError();
  if (const char* dump = std::getenv("MOLDTEX_TEST_DUMP")) {  // to look at: a PNG of u / U / 4
    static int n = 0;
    const std::string path = std::string(dump) + "_" + std::to_string(n++) + ".png";
    moldtex_sim_write_image(r.sim.get(), path.c_str(), MOLDTEX_IMAGE_PNG8);
  }
  return Shown(r.sim.get());
}

const TexelGeometry& Geometry() {
  static const TexelGeometry g = Texels(Plane(), kSize, kSize);
  return g;
}

// The CPU, and OpenCL where a device is usable (or required: MOLDTEX_REQUIRE_OPENCL).
std::vector<Backend> Backends() {
  std::vector<Backend> b = {Backend::Cpu};
  moldtex_sim_config probe = make_config(8, 8, 1, 1);
  std::string why;
  if (PinBackend(Backend::OpenCl, probe, &why) || OpenClRequiredByEnv()) b.push_back(Backend::OpenCl);
  return b;
}

const char* Name(Backend b) { return b == Backend::Cpu ? "CPU" : "OpenCL"; }

// Plane x of texel column tx.
double PlaneX(uint32_t tx) { return (tx + 0.5) * 2.0 / kSize; }

// A map of 1 everywhere changes nothing: each multiplier is applied exactly (x 1.0f), the
// deposit's fixed-point units are the same, and the clocks start from the same draws.
// (The sensor angle is rebuilt from atan2, and a spawn map draws one more number per
// respawn, so those two are left out of the bit comparison.)
TEST(ParameterMaps, MapsOfOneChangeNothing) {
  const auto one = [](double, double) { return 1.f; };
  const std::vector<double> plain = Simulate(6000, 3, turnover_look(), {}, 0.5);
  const std::vector<double> mapped = Simulate(6000, 3, turnover_look(),
                                              {{MOLDTEX_MAP_MOVE_RATE, one},
                                               {MOLDTEX_MAP_TURN_RATE, one},
                                               {MOLDTEX_MAP_SENSOR_DISTANCE, one},
                                               {MOLDTEX_MAP_DEPOSIT_RATE, one},
                                               {MOLDTEX_MAP_MEAN_LIFETIME, one},
                                               {MOLDTEX_MAP_ACTIVATION_TIME, one}},
                                              0.5);
  ASSERT_EQ(plain.size(), mapped.size());
  size_t differ = 0;
  for (size_t i = 0; i < plain.size(); ++i) differ += plain[i] != mapped[i];
  EXPECT_EQ(differ, 0u);
}

// Sinks and sources (Fig. 8, 18). Nobody moves (move rate x 0) and nobody decays by
// turnover (mean lifetime 0): the only deaths are in the sink, a disc where the lifetime
// map is 0, and the only births are by the spawn map, 1 in a left strip and 3 in a right
// one. After one step, exactly the agents that stood in the sink have been reborn, all
// in the strips, about 3 times as many on the right.
TEST(ParameterMaps, SinksKillAtOnceAndSpawnMapsPlaceTheReborn) {
  moldtex_continuous_params p = turnover_look();
  p.mean_lifetime = 0.f;
  auto in_sink = [](double x, double y) { return std::hypot(x - 1.0, y - 1.0) < 0.4; };
  auto strip = [](double x, double) { return x < 0.3 ? 1.f : x > 1.7 ? 3.f : 0.f; };
  const uint32_t agents = 20000;
  MapRun r = Start(agents, 5, p,
                   {{MOLDTEX_MAP_MOVE_RATE, [](double, double) { return 0.f; }},
                    {MOLDTEX_MAP_MEAN_LIFETIME, [&](double x, double y) { return in_sink(x, y) ? 0.f : 1.f; }},
                    {MOLDTEX_MAP_SPAWN, strip}});
  ASSERT_TRUE(r.sim);
  const std::vector<float> lifetime = MapImage([&](double x, double y) { return in_sink(x, y) ? 0.f : 1.f; });
  const std::vector<float> spawn = MapImage(strip);
  // Agents by where they stand: sink, left strip, right strip, elsewhere. (The backend
  // reorders agents in memory, so counts, not identities, are compared.)
  auto census = [&]() {
    std::array<size_t, 4> n{};
    for (const moldtex_surface_point& a : read_agents(r.sim.get(), agents)) {
      const Vec2 uv = evaluate_uv(r.surface.get(), a);
      const size_t t =
          size_t(std::min(kSize - 1, uint32_t(uv[1] * kSize))) * kSize + std::min(kSize - 1, uint32_t(uv[0] * kSize));
      ++n[lifetime[t] == 0.f ? 0 : spawn[t] == 1.f ? 1 : spawn[t] == 3.f ? 2 : 3];
    }
    return n;
  };
  const std::array<size_t, 4> before = census();
  ASSERT_EQ(moldtex_sim_step(r.sim.get(), 1), MOLDTEX_OK) << LastError();
  const std::array<size_t, 4> after = census();
  const size_t sunk = before[0], left = after[1] - before[1], right = after[2] - before[2];
  std::printf("  %zu of %u agents stood in the sink; %zu reborn on the left, %zu on the right\n", sunk, agents, left,
              right);
  EXPECT_GT(sunk, 2000u);  // the disc holds pi 0.16 / 4 = 12.6% of the area
  EXPECT_EQ(after[0], 0u);
  EXPECT_EQ(after[3], before[3]);  // nobody else moved or died
  EXPECT_EQ(left + right, sunk);
  // Right share 3 / 4; binomial sd sqrt(0.75 * 0.25 / 2500) = 0.009: +-0.04 is 4.5 sd.
  EXPECT_NEAR(double(right) / sunk, 0.75, 0.04);
}

// A write stimulus alone holds u / U at its value (the moldtex_sim_set_map promise): with
// nothing deposited (deposit map 0) the plane relaxes to 0.5 U where the stimulus is
// 0.5, as e^(-r_dec t), so after r_dec t = 12.6 it is there to 4e-6 (float rounding
// allows 1e-4). A negative stimulus empties its region and never makes it negative.
TEST(ParameterMaps, WriteStimulusAloneHoldsItsValueTimesU) {
  const moldtex_continuous_params p = turnover_look();
  MapRun r = Start(4000, 7, p,
                   {{MOLDTEX_MAP_DEPOSIT_RATE, [](double, double) { return 0.f; }},
                    {MOLDTEX_MAP_WRITE_STIMULUS, [](double x, double) { return x < 1.0 ? 0.5f : -0.5f; }}});
  ASSERT_TRUE(r.sim);
  ASSERT_EQ(moldtex_sim_step(r.sim.get(), 120), MOLDTEX_OK) << LastError();
  const std::vector<double> shown = Shown(r.sim.get());
  double worst_left = 0, worst_right = 0;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const double v = shown[size_t(y) * kSize + x];
      // Away from the middle, where diffusion mixes the two halves.
      if (PlaneX(x) < 0.8) worst_left = std::max(worst_left, std::fabs(v - 0.5));
      if (PlaneX(x) > 1.2) worst_right = std::max(worst_right, std::fabs(v));
      EXPECT_GE(v, 0.0);
    }
  EXPECT_LT(worst_left, 1e-4);
  EXPECT_EQ(worst_right, 0.0);
}

// A diffusion-rate map of 0 in a band 4 texels wide is a wall (faces between two cells
// of the band conduct with the mean of 0 and 0): pheromone written on the left never
// reaches the right, exactly. Without the band it spreads over (the check's control).
TEST(ParameterMaps, DiffusionMapOfZeroIsAWall) {
  moldtex_continuous_params p = turnover_look();
  p.diffusion_rate = 0.02f;  // ten times the default: spreads across in 2 s
  for (Backend backend : Backends()) {
    auto right_of_band = [&](const std::vector<std::pair<uint32_t, MapOf>>& extra) {
      std::vector<std::pair<uint32_t, MapOf>> maps = {
          {MOLDTEX_MAP_DEPOSIT_RATE, [](double, double) { return 0.f; }},
          {MOLDTEX_MAP_WRITE_STIMULUS, [](double x, double) { return x < 0.9 ? 1.f : 0.f; }}};
      maps.insert(maps.end(), extra.begin(), extra.end());
      const std::vector<double> shown = Simulate(2000, 29, p, maps, 2.0, backend);
      return Mean(Geometry(), shown, [](uint32_t x, uint32_t) { return PlaneX(x) > 1.05 && PlaneX(x) < 1.3; });
    };
    const double open = right_of_band({});
    const double walled = right_of_band(
        {{MOLDTEX_MAP_DIFFUSION_RATE, [](double x, double) { return std::fabs(x - 1.0) < 4.0 / kSize ? 0.f : 1.f; }}});
    std::printf("  %s: u / U right of the band: %.3g open, %.3g walled\n", Name(backend), open, walled);
    EXPECT_GT(open, 1e-3);
    EXPECT_EQ(walled, 0.0);
  }
}

// A decay-rate map of m: each cell decays at m r_dec. With a write stimulus s alone and
// no diffusion, a cell's steady state is known exactly: each step adds
// a = s U (e^k - 1) (k = r_dec dt) and decays by e^(-k m), so u = a / (e^(k m) - 1):
// s U where m = 1, s U / (e^k + 1) = 0.4738 s U where m = 2 (float rounding: 1e-4).
TEST(ParameterMaps, DecayMapSetsEachCellsDecay) {
  moldtex_continuous_params p = turnover_look();
  p.diffusion_rate = 0.f;
  for (Backend backend : Backends()) {
    const std::vector<double> shown =
        Simulate(2000, 31, p,
                 {{MOLDTEX_MAP_DEPOSIT_RATE, [](double, double) { return 0.f; }},
                  {MOLDTEX_MAP_WRITE_STIMULUS, [](double, double) { return 0.8f; }},
                  {MOLDTEX_MAP_DECAY_RATE, [](double x, double) { return x < 1.0 ? 1.f : 2.f; }}},
                 3.0, backend);
    const double k = double(p.decay_rate) * p.time_step;
    const double want_right = 0.8 * std::expm1(k) / std::expm1(2 * k);
    double worst_left = 0, worst_right = 0;
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        const double v = shown[size_t(y) * kSize + x];
        (PlaneX(x) < 1.0 ? worst_left : worst_right) =
            std::max(PlaneX(x) < 1.0 ? worst_left : worst_right, std::fabs(v - (PlaneX(x) < 1.0 ? 0.8 : want_right)));
      }
    std::printf("  %s: right half: want %.5f U; worst errors %.2g (left), %.2g (right)\n", Name(backend), want_right,
                worst_left, worst_right);
    EXPECT_LT(worst_left, 1e-4);
    EXPECT_LT(worst_right, 1e-4);
  }
}

// A deposit map of 2 everywhere doubles the steady state: mean u = 2 U (Eq. 5 with twice
// r_dep). The model holds the mean to about 1% of U (test_continuous), so 3% of 2 U.
TEST(ParameterMaps, DepositMapScalesTheSteadyState) {
  const std::vector<double> shown =
      Simulate(10000, 9, turnover_look(), {{MOLDTEX_MAP_DEPOSIT_RATE, [](double, double) { return 2.f; }}}, 2.0);
  const double mean = Mean(Geometry(), shown, [](uint32_t, uint32_t) { return true; });
  std::printf("  mean u / U = %.4f\n", mean);
  EXPECT_NEAR(mean, 2.0, 0.06);
}

// A read stimulus (Fig. 7): agents sense thin strokes (an H, 0.06 wide, under the
// sensor distance 0.09) of value 2 (twice the uniform steady state) on top of the
// trails. Sensing compares three probes, so what steers is the stimulus' edges: thin
// strokes are all edge, and the network gathers along them. The trails trace the H, and
// around it the network keeps its character: coverage (area where u > U) within 25% of
// the run without the stimulus.
TEST(ParameterMaps, ReadStimulusDrawsTheNetworkIntoItsShape) {
  auto stroke = [](double x, double y) {
    const bool upright = (std::fabs(x - 0.63) < 0.03 || std::fabs(x - 1.37) < 0.03) && y > 0.4 && y < 1.6;
    const bool bar = std::fabs(y - 1.0) < 0.03 && x > 0.63 && x < 1.37;
    return upright || bar;
  };
  const TexelGeometry& g = Geometry();
  // The strokes cover 5% of the plane, so where trails happen to cross them varies from
  // seed to seed (without the stimulus, 1.35 for one seed): two seeds each.
  std::vector<double> plain, stim;
  for (uint64_t seed : {11, 12}) {
    const std::vector<double> a = Simulate(10000, seed, turnover_look(), {}, 3.0);
    const std::vector<double> b =
        Simulate(10000, seed, turnover_look(),
                 {{MOLDTEX_MAP_READ_STIMULUS, [&](double x, double y) { return stroke(x, y) ? 2.f : 0.f; }}}, 3.0);
    plain.insert(plain.end(), a.begin(), a.end());
    stim.insert(stim.end(), b.begin(), b.end());
  }
  // Both seeds' images stacked: the geometry repeated twice.
  TexelGeometry g2 = g;
  g2.height *= 2;
  g2.position.insert(g2.position.end(), g.position.begin(), g.position.end());
  g2.area.insert(g2.area.end(), g.area.begin(), g.area.end());
  g2.triangle.insert(g2.triangle.end(), g.triangle.begin(), g.triangle.end());
  auto on = [&](uint32_t x, uint32_t y) { return stroke(PlaneX(x), PlaneX(y % kSize)); };
  auto far = [&](uint32_t x, uint32_t y) {
    // Around the strokes, within the H's box grown by 0.2, but not on them or within a
    // sensor distance of them, and away from the plane's edge (where agents turn back).
    const double px = PlaneX(x), py = PlaneX(y % kSize);
    bool near = false;
    for (double dx : {-0.1, 0.0, 0.1})
      for (double dy : {-0.1, 0.0, 0.1}) near = near || stroke(px + dx, py + dy);
    return px > 0.4 && px < 1.6 && py > 0.2 && py < 1.8 && !near;
  };
  auto coverage = [&](const std::vector<double>& f, const std::function<bool(uint32_t, uint32_t)>& in) {
    std::vector<double> above(f.size());
    for (size_t i = 0; i < f.size(); ++i) above[i] = f[i] > 1.0;
    return Mean(g2, above, in);
  };
  std::printf(
      "  strokes covered: %.3f with the stimulus, %.3f without; u / U there %.2f vs %.2f; "
      "coverage around %.3f vs %.3f\n",
      coverage(stim, on), coverage(plain, on), Mean(g2, stim, on), Mean(g2, plain, on), coverage(stim, far),
      coverage(plain, far));
  // The H is traced: most of it above U (the strokes' ends and joints are rounded off by
  // the trails' width), where without the stimulus trails cover it only as much as they
  // cross it by chance. Measured on seeds 11, 12 and on the same seeds shifted by 1000,
  // 2000 and 3000 (MOLDTEX_TEST_SEED_OFFSET, 2026-12-05): 0.84 / 0.72 / 0.85 / 0.82 with
  // the stimulus, 0.39 / 0.25 / 0.28 / 0.28 without. 0.75, as until then, held by luck;
  // 0.65 lies below every pair measured and far above the chance crossings.
  EXPECT_GT(coverage(stim, on), 0.65);
  EXPECT_LT(coverage(plain, on), 0.6);
  EXPECT_GT(Mean(g2, stim, on), 1.5 * Mean(g2, plain, on));
  EXPECT_NEAR(coverage(stim, far) / coverage(plain, far), 1.0, 0.25);
}

// A move-rate map of 1 on the left half and 3 on the right: each half takes the look of
// a uniform run at its own move rate. The prediction is the uniform runs' ratio of
// gradient lengths (trail spacing; faster agents make finer trails here: about 0.89); the
// halves of the mapped run must show it on the same side of 1 and within 0.05 (the
// border between the halves is left out). One seed is not enough: over seeds 13-20 the
// mapped run's ratio spread 0.83-0.98 (standard deviation 0.047) and the prediction's
// 0.86-0.96 (0.029), so one seed missed 0.05 for 3 of those 8 (seed 13, used alone until
// 2026-12-05, passed by luck). The lengths are therefore pooled over those 8 seeds (their
// means' ratios: the difference's standard deviation about 0.02, so 0.05 is 2.6 of them;
// measured 0.897 against 0.887).
TEST(ParameterMaps, MoveRateMapGivesEachHalfItsOwnScale) {
  moldtex_continuous_params fast = turnover_look();
  fast.move_rate *= 3.f;
  const TexelGeometry& g = Geometry();
  auto left = [&](uint32_t x, uint32_t) { return PlaneX(x) < 0.85; };
  auto right = [&](uint32_t x, uint32_t) { return PlaneX(x) > 1.15; };
  constexpr uint64_t kFirstSeed = 13, kSeeds = 8;
  double slow = 0, quick = 0, mapped_left = 0, mapped_right = 0;
  for (uint64_t seed = kFirstSeed; seed < kFirstSeed + kSeeds; ++seed) {
    const std::vector<double> slow_run = Simulate(10000, seed, turnover_look(), {}, 3.0);
    const std::vector<double> fast_run = Simulate(10000, seed, fast, {}, 3.0);
    const std::vector<double> mapped = Simulate(
        10000, seed, turnover_look(), {{MOLDTEX_MAP_MOVE_RATE, [](double x, double) { return x < 1.0 ? 1.f : 3.f; }}}, 3.0);
    slow += GradientLength(g, slow_run);
    quick += GradientLength(g, fast_run);
    mapped_left += GradientLength(g, mapped, left);
    mapped_right += GradientLength(g, mapped, right);
  }
  const double predicted = quick / slow, measured = mapped_right / mapped_left;
  std::printf("  gradient length over %d seeds: slow %.4f, fast %.4f (ratio %.3f); mapped left %.4f, right %.4f (ratio %.3f)\n",
              int(kSeeds), slow / kSeeds, quick / kSeeds, predicted, mapped_left / kSeeds, mapped_right / kSeeds, measured);
  EXPECT_GT(std::fabs(predicted - 1.0), 0.08) << "the move rate must change the scale for this test to mean anything";
  EXPECT_EQ(predicted > 1.0, measured > 1.0);
  EXPECT_NEAR(measured, predicted, 0.05);
}

// Absorbing boundaries (Fig. 18): an agent that meets the plane's open edge dies there and
// is reborn. Agents outside a central square move 3 units a step (every one of them
// meets the edge), those inside it do not move (move map 0) and the spawn map puts every
// rebirth inside it. After one step, every agent either stands where it started in the
// square or lies on the edge; after the second, all are in the square. Reflecting
// instead, no agent stops on the edge (and some walk into the square).
TEST(ParameterMaps, AbsorbingBoundariesKillAgentsAtTheEdge) {
  // Texels 102 .. 153 on both axes (maps are read per texel, so the square's edges lie
  // on texel edges: 102 * 2 / 256 = 0.796875).
  auto centre = [](double x, double y) { return std::fabs(x - 1.0) < 0.203125 && std::fabs(y - 1.0) < 0.203125; };
  for (uint32_t boundary : {MOLDTEX_BOUNDARY_ABSORB, MOLDTEX_BOUNDARY_REFLECT}) {
    moldtex_continuous_params p = turnover_look();
    p.mean_lifetime = 0.f;
    p.move_rate = 3.f / p.time_step;
    p.boundary = boundary;
    const uint32_t agents = 4000;
    MapRun r = Start(agents, 37, p,
                     {{MOLDTEX_MAP_MOVE_RATE, [&](double x, double y) { return centre(x, y) ? 0.f : 1.f; }},
                      {MOLDTEX_MAP_SPAWN, [&](double x, double y) { return centre(x, y) ? 1.f : 0.f; }}});
    ASSERT_TRUE(r.sim);
    auto census = [&]() {  // (in the square, on the edge, elsewhere)
      std::array<size_t, 3> n{};
      for (const moldtex_surface_point& a : read_agents(r.sim.get(), agents)) {
        const Vec3 q = evaluate_position(r.surface.get(), a);
        const double edge = std::min(std::min(q[0], 2.0 - q[0]), std::min(q[1], 2.0 - q[1]));
        ++n[centre(q[0], q[1]) ? 0 : edge < 1e-4 ? 1 : 2];
      }
      return n;
    };
    const std::array<size_t, 3> start = census();
    ASSERT_EQ(moldtex_sim_step(r.sim.get(), 1), MOLDTEX_OK) << LastError();
    const std::array<size_t, 3> one = census();
    ASSERT_EQ(moldtex_sim_step(r.sim.get(), 1), MOLDTEX_OK) << LastError();
    const std::array<size_t, 3> two = census();
    std::printf(
        "  %s: start %zu in the square; after one step %zu / %zu on the edge / %zu elsewhere; after two "
        "%zu in the square\n",
        boundary == MOLDTEX_BOUNDARY_ABSORB ? "absorb" : "reflect", start[0], one[0], one[1], one[2], two[0]);
    EXPECT_GT(start[0], 100u);  // the square is 4% of the plane
    if (boundary == MOLDTEX_BOUNDARY_ABSORB) {
      EXPECT_EQ(one[0], start[0]);
      EXPECT_EQ(one[1], agents - start[0]);
      EXPECT_EQ(two[0], size_t(agents));
    } else {
      EXPECT_LT(one[1], 10u);
      EXPECT_LT(two[0], start[0] + 400);  // only those walking into the square by chance
    }
  }
}

// Holes of a thresholded pattern: connected regions (4-neighbour) of texels with
// u <= level inside the disc of radius `radius` around the plane's centre that reach
// neither the disc's rim nor the sink at the centre (radius `sink`): enclosed cells.
size_t EnclosedCells(const std::vector<double>& shown, double level, double radius, double sink) {
  std::vector<int> label(shown.size(), 0);
  auto inside = [&](uint32_t x, uint32_t y) { return std::hypot(PlaneX(x) - 1.0, PlaneX(y) - 1.0) < radius; };
  size_t holes = 0;
  std::vector<size_t> stack;
  for (uint32_t y0 = 0; y0 < kSize; ++y0)
    for (uint32_t x0 = 0; x0 < kSize; ++x0) {
      const size_t i0 = size_t(y0) * kSize + x0;
      if (label[i0] || !inside(x0, y0) || shown[i0] > level) continue;
      bool open = false;
      size_t area = 0;
      label[i0] = 1;
      stack.assign(1, i0);
      while (!stack.empty()) {
        const size_t i = stack.back();
        stack.pop_back();
        ++area;
        const uint32_t x = uint32_t(i % kSize), y = uint32_t(i / kSize);
        if (std::hypot(PlaneX(x) - 1.0, PlaneX(y) - 1.0) < sink) open = true;
        const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
        for (int d = 0; d < 4; ++d) {
          const int nx = int(x) + dx[d], ny = int(y) + dy[d];
          if (nx < 0 || ny < 0 || nx >= int(kSize) || ny >= int(kSize) || !inside(nx, ny)) {
            open = true;
            continue;
          }
          const size_t j = size_t(ny) * kSize + nx;
          if (label[j] || shown[j] > level) continue;
          label[j] = 1;
          stack.push_back(j);
        }
      }
      holes += !open && area >= 4;  // (specks of a few texels are noise, not cells)
    }
  return holes;
}

// Fig. 8: agents born on the rim of a disc (spawn map on its outer band), facing and
// pulled toward a sink at its centre (lifetime map 0; also beyond the rim, the disc's
// outside), lay a branching pattern: trails merge on their way in, like veins, and
// enclose almost no cells. The same run without the bias makes a network of closed
// cells. Cells are counted on the thresholded pattern (above its mean over the disc),
// for two seeds. The look is the default one at half its lengths (sensor distance, move
// rate, and diffusion by the square), so the disc holds several cells; bias 30 / s turns
// an agent toward the centre within a few hundredths of a second.
TEST(ParameterMaps, BiasTowardASinkBranches) {
  const Mesh& m = Plane();
  std::vector<float> inward(3 * size_t(m.triangle_count()));  // unit, toward the centre
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 c = scale(add(add(m.corner(t, 0), m.corner(t, 1)), m.corner(t, 2)), 1.0 / 3);
    const double l = std::max(1e-9, std::hypot(1.0 - c[0], 1.0 - c[1]));
    inward[3 * t] = float((1.0 - c[0]) / l);
    inward[3 * t + 1] = float((1.0 - c[1]) / l);
  }
  auto radius = [](double x, double y) { return std::hypot(x - 1.0, y - 1.0); };
  const std::vector<std::pair<uint32_t, MapOf>> maps = {
      {MOLDTEX_MAP_MEAN_LIFETIME,
       [&](double x, double y) { return radius(x, y) < 0.08 || radius(x, y) > 0.98 ? 0.f : 1.f; }},
      {MOLDTEX_MAP_SPAWN, [&](double x, double y) { return radius(x, y) > 0.6 && radius(x, y) < 0.95 ? 1.f : 0.f; }}};
  size_t holes[2] = {0, 0};
  for (uint64_t seed : {41, 42})
    for (int biased = 0; biased < 2; ++biased) {
      moldtex_continuous_params p = turnover_look();
      p.sensor_distance *= 0.5f;
      p.move_rate *= 0.5f;
      p.diffusion_rate *= 0.25f;
      p.bias_strength = biased ? 30.f : 0.f;
      p.bias_spawn = biased ? 1u : 0u;
      MapRun r = Start(20000, seed, p, maps);
      ASSERT_TRUE(r.sim);
      ASSERT_EQ(moldtex_sim_set_bias(r.sim.get(), inward.data(), inward.size()), MOLDTEX_OK) << LastError();
      ASSERT_EQ(moldtex_sim_step(r.sim.get(), 360), MOLDTEX_OK) << LastError();
      if (const char* dump = std::getenv("MOLDTEX_TEST_DUMP"))
        moldtex_sim_write_image(
            r.sim.get(), (std::string(dump) + (biased ? "_biased_" : "_free_") + std::to_string(seed) + ".png").c_str(),
            MOLDTEX_IMAGE_PNG8);
      // Trails: above the mean over the disc (U is the mean over the whole plane, and the
      // agents live in the disc).
      const std::vector<double> shown = Shown(r.sim.get());
      auto disc = [&](uint32_t x, uint32_t y) { return radius(PlaneX(x), PlaneX(y)) < 0.95; };
      holes[biased] += EnclosedCells(shown, Mean(Geometry(), shown, disc), 0.95, 0.1);
    }
  std::printf("  enclosed cells (two seeds): %zu without the bias, %zu with it\n", holes[0], holes[1]);
  EXPECT_GE(holes[0], 6u);
  EXPECT_LE(3 * holes[1], holes[0]);
}

// Same seed, same maps: the same bits on 1 and 2 threads.
TEST(ParameterMaps, DeterministicAcrossThreadCounts) {
  const std::vector<std::pair<uint32_t, MapOf>> maps = {
      {MOLDTEX_MAP_MOVE_RATE, [](double x, double) { return float(0.5 + x); }},
      {MOLDTEX_MAP_SENSOR_ANGLE, [](double, double y) { return float(0.5 + y / 2); }},
      {MOLDTEX_MAP_MEAN_LIFETIME, [](double x, double y) { return std::hypot(x - 1, y - 1) < 0.3 ? 0.f : 1.f; }},
      {MOLDTEX_MAP_SPAWN, [](double x, double) { return x < 0.5 ? 1.f : 0.f; }},
      {MOLDTEX_MAP_WRITE_STIMULUS, [](double x, double) { return x > 1.5 ? 0.3f : 0.f; }}};
  const std::vector<double> one = Simulate(6000, 17, turnover_look(), maps, 0.5, Backend::Cpu, 1);
  const std::vector<double> two = Simulate(6000, 17, turnover_look(), maps, 0.5, Backend::Cpu, 2);
  ASSERT_EQ(one.size(), two.size());
  size_t differ = 0;
  for (size_t i = 0; i < one.size(); ++i) differ += one[i] != two[i];
  EXPECT_EQ(differ, 0u);
}

// Maps are part of the state: a checkpoint keeps them, and the run resumes exactly.
TEST(ParameterMaps, CheckpointKeepsTheMaps) {
  TempDir dir;
  const std::string path = (dir.path / "maps.ckpt").string();
  const std::vector<std::pair<uint32_t, MapOf>> maps = {
      {MOLDTEX_MAP_TURN_RATE, [](double x, double) { return float(0.5 + x / 2); }},
      {MOLDTEX_MAP_SPAWN, [](double, double y) { return y < 1 ? 1.f : 2.f; }},
      {MOLDTEX_MAP_READ_STIMULUS, [](double x, double) { return x < 0.5 ? -0.5f : 0.f; }}};
  MapRun a = Start(4000, 19, turnover_look(), maps);
  ASSERT_TRUE(a.sim);
  ASSERT_EQ(moldtex_sim_step(a.sim.get(), 20), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_save_checkpoint(a.sim.get(), path.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(a.sim.get(), 20), MOLDTEX_OK);
  MapRun b = Start(4000, 19, turnover_look(), {});  // no maps of its own
  ASSERT_TRUE(b.sim);
  ASSERT_EQ(moldtex_sim_load_checkpoint(b.sim.get(), path.c_str()), MOLDTEX_OK) << LastError();
  for (const auto& [kind, f] : maps) {
    std::vector<float> got(size_t(kSize) * kSize);
    uint32_t set = 0;
    ASSERT_EQ(moldtex_sim_get_map(b.sim.get(), kind, got.data(), got.size(), &set), MOLDTEX_OK) << LastError();
    EXPECT_EQ(set, 1u) << "map " << kind;
  }
  ASSERT_EQ(moldtex_sim_step(b.sim.get(), 20), MOLDTEX_OK);
  EXPECT_EQ(Shown(a.sim.get()), Shown(b.sim.get()));
}

// Bad maps are refused with a message, and the simulation keeps what it had.
TEST(ParameterMaps, BadMapsAreRefusedWithAMessage) {
  MapRun r = Start(1000, 1, turnover_look(), {});
  ASSERT_TRUE(r.sim);
  std::vector<float> m(size_t(kSize) * kSize, 1.f);
  auto refused = [&](uint32_t kind, const std::vector<float>& v, size_t count, const char* word) {
    EXPECT_EQ(moldtex_sim_set_map(r.sim.get(), kind, v.data(), count), MOLDTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(LastError().find(word), std::string::npos) << LastError();
  };
  refused(MOLDTEX_MAP_COUNT, m, m.size(), "Unknown map");
  refused(MOLDTEX_MAP_MOVE_RATE, m, m.size() - 1, "width * height");
  std::vector<float> bad = m;
  bad[77] = std::nanf("");
  refused(MOLDTEX_MAP_MOVE_RATE, bad, bad.size(), "texel 77");
  bad[77] = -1.f;
  refused(MOLDTEX_MAP_TURN_RATE, bad, bad.size(), "texel 77");
  bad[77] = 2000.f;
  refused(MOLDTEX_MAP_DEPOSIT_RATE, bad, bad.size(), "1000");
  bad[77] = -1.f;
  EXPECT_EQ(moldtex_sim_set_map(r.sim.get(), MOLDTEX_MAP_READ_STIMULUS, bad.data(), bad.size()), MOLDTEX_OK);
  std::vector<float> zero(m.size(), 0.f);
  refused(MOLDTEX_MAP_SPAWN, zero, zero.size(), "spawn map is zero");
  uint32_t set = 7;
  ASSERT_EQ(moldtex_sim_get_map(r.sim.get(), MOLDTEX_MAP_SPAWN, nullptr, 0, &set), MOLDTEX_OK);
  EXPECT_EQ(set, 0u);
  EXPECT_EQ(moldtex_sim_set_map(r.sim.get(), MOLDTEX_MAP_READ_STIMULUS, nullptr, 0), MOLDTEX_OK);
  EXPECT_EQ(moldtex_sim_step(r.sim.get(), 2), MOLDTEX_OK);
}

// The OpenCL backend reads the same maps: under move-rate, lifetime/spawn, write,
// diffusion and decay maps, its pattern has the CPU's mean and gradient length within 5% (the backends agree
// to about 1% without maps, test_continuous). The two backends' runs of one seed part
// ways within a few steps (their sums round differently), so each is one draw of the
// pattern: the means of 4 seeds are compared. One seed, as until 2026-12-05, held by luck:
// with the seeds shifted by 3000 (MOLDTEX_TEST_SEED_OFFSET) its gradient lengths
// differed by 9%.
TEST(ParameterMaps, OpenClAgreesWithTheCpu) {
  moldtex_sim_config probe = make_config(8, 8, 1, 1);
  std::string why;
  if (!PinBackend(Backend::OpenCl, probe, &why)) {
    if (OpenClRequiredByEnv()) FAIL() << why;
    GTEST_SKIP() << why;
  }
  const std::vector<std::pair<uint32_t, MapOf>> maps = {
      {MOLDTEX_MAP_MOVE_RATE, [](double x, double) { return x < 1.0 ? 1.f : 1.5f; }},
      {MOLDTEX_MAP_MEAN_LIFETIME, [](double x, double y) { return std::hypot(x - 1, y - 1) < 0.2 ? 0.f : 1.f; }},
      {MOLDTEX_MAP_SPAWN, [](double x, double) { return x < 0.5 ? 1.f : 0.2f; }},
      {MOLDTEX_MAP_WRITE_STIMULUS, [](double x, double) { return x > 1.6 ? 0.5f : 0.f; }},
      {MOLDTEX_MAP_DIFFUSION_RATE, [](double, double y) { return float(0.5 + y); }},
      {MOLDTEX_MAP_DECAY_RATE, [](double x, double y) { return std::hypot(x - 0.5, y - 1.5) < 0.3 ? 3.f : 1.f; }}};
  const TexelGeometry& g = Geometry();
  auto all = [](uint32_t, uint32_t) { return true; };
  constexpr uint64_t kFirstSeed = 23, kSeeds = 4;
  double mean[2] = {0, 0}, length[2] = {0, 0};
  for (uint64_t seed = kFirstSeed; seed < kFirstSeed + kSeeds; ++seed)
    for (int b = 0; b < 2; ++b) {
      const std::vector<double> f = Simulate(10000, seed, turnover_look(), maps, 2.0, b ? Backend::OpenCl : Backend::Cpu);
      mean[b] += Mean(g, f, all) / kSeeds;
      length[b] += GradientLength(g, f) / kSeeds;
    }
  std::printf("  mean %.4f vs %.4f, gradient length %.4f vs %.4f\n", mean[0], mean[1], length[0], length[1]);
  EXPECT_NEAR(mean[1] / mean[0], 1.0, 0.05);
  EXPECT_NEAR(length[1] / length[0], 1.0, 0.05);
}

}  // namespace
}  // namespace mtx
