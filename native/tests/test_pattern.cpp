// Pheromone texture: deposit, evaporation, coverage (momas-paper.md Eq. 1, Fig. 8),
// texel classes and the gutter.
#include <algorithm>
#include <array>
#include <set>
#include <utility>
#include <unordered_set>

#include "test_util.h"

namespace mtx {
namespace {

// Plane run for the coverage figures: 96^2 texels, one agent per texel.
constexpr uint32_t kPlane = 96;
moldtex_sim_stats PlaneRun(float evaporation, uint32_t steps, std::vector<float>* rgba = nullptr) {
  const Mesh m = make_quad();
  auto s = create_surface(m);
  EXPECT_TRUE(s) << LastError();
  moldtex_sim_params p = default_params();
  p.evaporation_rate = evaporation;
  auto sim = create_sim(s.get(), make_config(kPlane, kPlane, kPlane * kPlane, 3), p);
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return {};
  EXPECT_EQ(moldtex_sim_step(sim.get(), steps), MOLDTEX_OK) << LastError();
  if (rgba) *rgba = read_rgba(sim.get(), kPlane, kPlane);
  return get_stats(sim.get());
}

TEST(Pattern, CoverageInPlausibleBandOnAPlane) {
  // After 300 steps (5 s) with the default parameters the trail network neither vanished
  // nor saturated the plane: 2% < coverage < 90%, and presence >= coverage
  // (ceil(x) >= x, Eq. 1).
  const auto st = PlaneRun(default_params().evaporation_rate, 300);
  EXPECT_GT(st.coverage, 0.02);
  EXPECT_LT(st.coverage, 0.90);
  EXPECT_GE(st.presence, st.coverage);
  EXPECT_LE(st.presence, 1.0);
  RecordProperty("coverage", std::to_string(st.coverage));
  RecordProperty("presence", std::to_string(st.presence));
}

// Mean coverage and presence sampled every 10 steps over [from, to) on a size^2 plane
// with one agent per texel, each sensor summing a square of radius sensor_size
// (0 = one texel). Sensors at Table 1's shortest distance (0.4 = 4 texels) keep the
// network's cells small, so the plane holds many of them and the mean is not at the
// mercy of a few cells merging.
std::pair<double, double> MeanCoverage(float evaporation, uint32_t from, uint32_t to,
                                       uint32_t size = 64, uint32_t sensor_size = 0, uint64_t seed = 3) {
  const Mesh m = make_quad();
  auto s = create_surface(m);
  EXPECT_TRUE(s) << LastError();
  moldtex_sim_params p = default_params();
  p.evaporation_rate = evaporation;
  p.vision_distance = 0.4f;
  p.sensor_size = sensor_size;
  auto sim = create_sim(s.get(), make_config(size, size, size * size, seed), p);
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return {};
  EXPECT_EQ(moldtex_sim_step(sim.get(), from), MOLDTEX_OK) << LastError();
  double cov = 0, pres = 0;
  int n = 0;
  for (uint32_t k = from; k < to; k += 10, ++n) {
    EXPECT_EQ(moldtex_sim_step(sim.get(), 10), MOLDTEX_OK) << LastError();
    const auto st = get_stats(sim.get());
    cov += st.coverage;
    pres += st.presence;
  }
  return {cov / n, pres / n};
}

TEST(Pattern, HigherEvaporationGivesLowerCoverage) {
  // momas-paper.md Fig. 8c: the slower the evaporation, the higher coverage and presence.
  // Over Table 1's range 0.2 .. 1, coverage averaged over steps 100 .. 300 (after the
  // initial peak, while the network forms; averaging removes the pattern's own
  // fluctuation) must fall by >= 5% at each step up (seeds 3..6 measured: 15-30%),
  // and presence must not rise.
  const double rates[] = {0.2, 0.5, 1.0};
  double prev_cov = 2, prev_pres = 2;
  for (double r : rates) {
    const auto [cov, pres] = MeanCoverage(float(r), 100, 300);
    SCOPED_TRACE("evaporation " + std::to_string(r) + ": coverage " + std::to_string(cov) +
                 " presence " + std::to_string(pres));
    EXPECT_LT(cov, 0.95 * prev_cov);
    EXPECT_LE(pres, prev_pres + 1e-12);
    RecordProperty("coverage_evap_" + std::to_string(r), std::to_string(cov));
    prev_cov = cov;
    prev_pres = pres;
  }
}

// Fig. 8c itself is measured after 70 s of simulation, in the stable phase of the
// pattern: coverage averaged over 60 .. 70 s (steps 3600 .. 4200) must still fall as
// evaporation rises. It does with MoMaS' square sensing kernel (sensor_size 2, a 5x5
// texel sum), not with the single texel (never ordered: 64^2 seeds 3..6, 96^2 seeds 3, 4,
// 128^2 seeds 3, 4; e.g. 64^2 seed 3: 0.22/0.26/0.31). One seed is not enough even so:
// at 96^2 coverage at evaporation 0.2 / 0.5 / 1 read, seeds 1..8 (2026-12-05),
// 0.208/0.157/0.125, 0.207/0.165/0.139, 0.211/0.148/0.163, 0.207/0.151/0.129,
// 0.206/0.209/0.126, 0.212/0.161/0.128, 0.211/0.170/0.127, 0.216/0.196/0.128: seeds 3 and
// 5 are out of order (a single seed's 0.5 and 1 spread by ~0.02-0.03, against steps of
// ~0.04 between the rates). The means of seeds 1..8 are compared: a step's paired
// difference over those seeds is 0.040 +- 0.008 and 0.036 +- 0.010 (mean +- standard
// error), so the order of the means fails by chance about once in several thousand
// draws of the random streams. ~80 s.
TEST(Pattern, HigherEvaporationGivesLowerCoverageAt70Seconds) {
  constexpr int kSeeds = 8;
  double prev_cov = 2;
  for (double r : {0.2, 0.5, 1.0}) {
    double cov = 0;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) cov += MeanCoverage(float(r), 3600, 4200, 96, 2, seed).first / kSeeds;
    std::printf("  evaporation %.1f: coverage %.4f (mean of %d seeds)\n", r, cov, kSeeds);
    SCOPED_TRACE("evaporation " + std::to_string(r) + ": coverage " + std::to_string(cov));
    EXPECT_LT(cov, prev_cov);
    RecordProperty("coverage_evap_" + std::to_string(r), std::to_string(cov));
    prev_cov = cov;
  }
}

TEST(Pattern, CoverageIsEquationOneOnAUniformPlane) {
  // On the UV = xy quad every texel covers the same 3D area and all are inside, so
  // Eq. 1 reduces to the plain texel mean (coverage) and the fraction of texels > 0
  // (presence). 1e-6: float texels summed in double.
  std::vector<float> rgba;
  const auto st = PlaneRun(0.5f, 120, &rgba);
  ASSERT_EQ(rgba.size(), size_t(kPlane) * kPlane * 4);
  double sum = 0;
  size_t positive = 0;
  for (size_t i = 0; i < rgba.size(); i += 4) {
    sum += rgba[i];
    positive += rgba[i] > 0;
  }
  EXPECT_NEAR(st.coverage, sum / (kPlane * kPlane), 1e-6);
  EXPECT_NEAR(st.presence, double(positive) / (kPlane * kPlane), 1e-6);
}

TEST(Pattern, DepositLandsInTheTexelUnderTheAgent) {
  // Standing agents (speed 0), no blur, no evaporation: after one step exactly the
  // texels under agents hold `deposit`. Checks the texel convention: column
  // floor(u * width), row floor(v * height) with row 0 at the bottom (Blender's order),
  // on a non-square texture so width and height cannot be swapped unnoticed.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 64, H = 40, N = 300;
  moldtex_sim_params p = default_params();
  p.movement_speed = 0;
  p.turn_speed = 0;
  p.evaporation_rate = 0;
  p.diffusion_rate = 0;
  p.deposit = 0.5f;
  p.substeps = 1;
  auto sim = create_sim(s.get(), make_config(W, H, N, 11), p);
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  const auto rgba = read_rgba(sim.get(), W, H);
  ASSERT_EQ(rgba.size(), size_t(W) * H * 4);
  std::set<size_t> under;
  size_t ambiguous = 0;
  for (const auto& a : read_agents(sim.get(), N)) {
    const Vec2 uv = evaluate_uv(s.get(), a);
    const double fx = uv[0] * W, fy = uv[1] * H;
    if (std::fabs(fx - std::round(fx)) < 1e-3 || std::fabs(fy - std::round(fy)) < 1e-3) {
      ++ambiguous;  // on a texel border: either side is right
      continue;
    }
    const size_t texel = size_t(std::floor(fy)) * W + size_t(std::floor(fx));
    under.insert(texel);
    EXPECT_EQ(rgba[4 * texel], 0.5f) << "no deposit under agent at uv (" << uv[0] << ", "
                                     << uv[1] << ")";
  }
  size_t nonzero = 0;
  for (size_t i = 0; i < size_t(W) * H; ++i) {
    nonzero += rgba[4 * i] != 0;
    EXPECT_TRUE(rgba[4 * i] == 0.0f || rgba[4 * i] == 0.5f) << "texel " << i << " = " << rgba[4 * i];
  }
  EXPECT_GE(nonzero, under.size());
  EXPECT_LE(nonzero, under.size() + ambiguous);
}

// Non-zero texels after one step of a single agent moving 8 texels in a straight line
// on the UV = xy quad (64^2), with `substeps` deposits along the move; the start and
// end of the move in texel units.
struct Trail {
  std::vector<std::array<int, 2>> texels;
  Vec2 from, to;
};
Trail OneMove(uint32_t substeps) {
  const uint32_t W = 64;
  const Mesh m = make_quad();
  auto s = create_surface(m);
  EXPECT_TRUE(s) << LastError();
  moldtex_sim_params p = default_params();
  p.movement_speed = 8;
  p.turn_speed = 0;
  p.vision_angle = 0;
  p.substeps = substeps;
  p.deposit = 1;
  p.diffusion_rate = 0;
  p.evaporation_rate = 0;
  for (uint64_t seed = 1; seed < 100; ++seed) {  // first spawn away from the border
    auto sim = create_sim(s.get(), make_config(W, W, 1, seed), p);
    EXPECT_TRUE(sim) << LastError();
    if (!sim) return {};
    const Vec2 a = evaluate_uv(s.get(), read_agents(sim.get(), 1).at(0));
    if (a[0] < 0.2 || a[0] > 0.8 || a[1] < 0.2 || a[1] > 0.8) continue;
    EXPECT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
    const Vec2 b = evaluate_uv(s.get(), read_agents(sim.get(), 1).at(0));
    Trail t{{}, {a[0] * W, a[1] * W}, {b[0] * W, b[1] * W}};
    const auto rgba = read_rgba(sim.get(), W, W);
    for (uint32_t i = 0; i < W * W; ++i)
      if (rgba[4 * i] > 0) t.texels.push_back({int(i % W), int(i / W)});
    return t;
  }
  ADD_FAILURE() << "no spawn away from the border in 100 seeds";
  return {};
}

TEST(Pattern, SubstepsDepositAContinuousTrail) {
  // Header: substeps = deposits along each move (a line-integrated trail). Eight
  // deposits along an 8-texel move mark a chain of 8-connected texels (>= 4: two
  // deposits 1 texel apart can share a texel on a diagonal) hugging the segment (texel
  // centres within 1 texel of it); one substep marks exactly one texel.
  const Trail t = OneMove(8);
  ASSERT_FALSE(t.texels.empty());
  EXPECT_GE(t.texels.size(), 4u);
  EXPECT_LE(t.texels.size(), 9u);
  const Vec2 d{t.to[0] - t.from[0], t.to[1] - t.from[1]};
  EXPECT_NEAR(std::hypot(d[0], d[1]), 8.0, 1e-3);  // speed is in texels
  const double len2 = d[0] * d[0] + d[1] * d[1];
  for (const auto& q : t.texels) {
    const double cx = q[0] + 0.5 - t.from[0], cy = q[1] + 0.5 - t.from[1];
    const double a = std::clamp((cx * d[0] + cy * d[1]) / len2, 0.0, 1.0);
    EXPECT_LE(std::hypot(cx - a * d[0], cy - a * d[1]), 1.0)
        << "texel (" << q[0] << ", " << q[1] << ") is off the move";
  }
  // 8-connected: grow from the first texel.
  std::vector<bool> seen(t.texels.size(), false);
  std::vector<size_t> todo{0};
  seen[0] = true;
  size_t reached = 1;
  while (!todo.empty()) {
    const size_t k = todo.back();
    todo.pop_back();
    for (size_t j = 0; j < t.texels.size(); ++j)
      if (!seen[j] && std::abs(t.texels[j][0] - t.texels[k][0]) <= 1 &&
          std::abs(t.texels[j][1] - t.texels[k][1]) <= 1) {
        seen[j] = true;
        ++reached;
        todo.push_back(j);
      }
  }
  EXPECT_EQ(reached, t.texels.size()) << "the trail has gaps";
  EXPECT_EQ(OneMove(1).texels.size(), 1u);
}

TEST(Pattern, EvaporationIsPerSecondAndLinear) {
  // Header units: evaporation_rate is pheromone lost per second, subtracted each step
  // as rate * time_step (the reference: texel -= decay * dt). Deposit 1 with standing
  // agents, then 30 steps (0.5 s) at 0.6/s with deposit 0 leave 1 - 0.3 = 0.7 (1e-5:
  // 30 float subtractions).
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 32, H = 32;
  moldtex_sim_params p = default_params();
  p.movement_speed = 0;
  p.turn_speed = 0;
  p.evaporation_rate = 0;
  p.diffusion_rate = 0;
  p.deposit = 1.0f;
  auto sim = create_sim(s.get(), make_config(W, H, 20, 5), p);
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  const auto before = read_rgba(sim.get(), W, H);
  p.deposit = 0.0f;
  p.evaporation_rate = 0.6f;
  ASSERT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 30), MOLDTEX_OK) << LastError();
  const auto after = read_rgba(sim.get(), W, H);
  ASSERT_EQ(after.size(), before.size());
  size_t checked = 0;
  for (size_t i = 0; i < before.size(); i += 4) {
    if (before[i] == 1.0f) {
      EXPECT_NEAR(after[i], 0.7, 1e-5);
      ++checked;
    } else {
      EXPECT_EQ(after[i], 0.0f);
    }
  }
  EXPECT_GT(checked, 0u);
}

TEST(Pattern, ChannelsAndRangeOnTheSphere) {
  // Header: one species gives R = G = B = pheromone in [0, 1] and A = 1 on the islands.
  const Mesh m = make_uv_sphere(32, 16, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(128, 64, 10000, 9), default_params());
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 50), MOLDTEX_OK) << LastError();
  const auto rgba = read_rgba(sim.get(), 128, 64);
  const auto cls = read_classes(sim.get(), 128, 64);
  ASSERT_EQ(cls.size(), 128u * 64u);
  for (size_t i = 0; i < cls.size(); ++i) {
    const float* t = &rgba[4 * i];
    ASSERT_TRUE(t[0] >= 0.0f && t[0] <= 1.0f) << "texel " << i << " = " << t[0];
    ASSERT_EQ(t[0], t[1]);
    ASSERT_EQ(t[0], t[2]);
    if (cls[i] == MOLDTEX_TEXEL_INSIDE) {
      ASSERT_EQ(t[3], 1.0f) << "texel " << i;
    }
  }
}

// ---- texel classes and gutter ------------------------------------------------------

TEST(TexelClasses, FullSquareLayoutIsAllInside) {
  // The quad's UVs cover [0,1]^2: every texel centre is inside an island.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(48, 32, 100, 1), default_params());
  ASSERT_TRUE(sim) << LastError();
  const auto cls = read_classes(sim.get(), 48, 32);
  ASSERT_EQ(cls.size(), 48u * 32u);
  for (size_t i = 0; i < cls.size(); ++i) ASSERT_EQ(cls[i], MOLDTEX_TEXEL_INSIDE) << "texel " << i;
}

struct CubeRun {
  static constexpr uint32_t W = 128, H = 128;
  std::vector<float> rgba;
  std::vector<uint8_t> cls;
  double uv_area = 0;
};

CubeRun RunCube() {
  CubeRun r;
  const Mesh m = make_cube();
  r.uv_area = m.total_uv_area();
  auto s = create_surface(m);
  EXPECT_TRUE(s) << LastError();
  if (!s) return r;
  auto sim = create_sim(s.get(), make_config(CubeRun::W, CubeRun::H, 10000, 17), default_params());
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return r;
  EXPECT_EQ(moldtex_sim_step(sim.get(), 60), MOLDTEX_OK) << LastError();
  r.rgba = read_rgba(sim.get(), CubeRun::W, CubeRun::H);
  r.cls = read_classes(sim.get(), CubeRun::W, CubeRun::H);
  return r;
}

TEST(TexelClasses, CubeLayoutHasInsideGutterAndOutside) {
  // Inside texels cover the UV area up to one texel along the island borders; the
  // six separated islands leave a gutter ring and empty space.
  const CubeRun r = RunCube();
  ASSERT_EQ(r.cls.size(), size_t(CubeRun::W) * CubeRun::H);
  size_t count[3] = {0, 0, 0};
  for (uint8_t c : r.cls) {
    ASSERT_LE(c, 2u) << "unknown class";
    count[c]++;
  }
  const double n = double(CubeRun::W) * CubeRun::H;
  const double perimeter_texels = 6 * 4 * 0.21 * CubeRun::W;
  EXPECT_NEAR(count[MOLDTEX_TEXEL_INSIDE] / n, r.uv_area, perimeter_texels / n);
  EXPECT_GT(count[MOLDTEX_TEXEL_GUTTER], 0u);
  EXPECT_GT(count[MOLDTEX_TEXEL_OUTSIDE], 0u);
}

TEST(TexelClasses, OutsideTexelsAreExactlyZero) {
  // Header: all outside texels (not gutter) are 0 — in every channel, so a material
  // sampling them (mipmaps, alpha) sees nothing.
  const CubeRun r = RunCube();
  ASSERT_EQ(r.rgba.size(), size_t(CubeRun::W) * CubeRun::H * 4);
  size_t outside = 0;
  for (size_t i = 0; i < r.cls.size(); ++i) {
    if (r.cls[i] != MOLDTEX_TEXEL_OUTSIDE) continue;
    ++outside;
    for (int c = 0; c < 4; ++c) {
      ASSERT_EQ(r.rgba[4 * i + c], 0.0f) << "texel " << i << " channel " << c;
    }
  }
  EXPECT_GT(outside, 0u);
}

TEST(TexelClasses, GutterIsFilledWithCopiesOfIslandTexels) {
  // Header: gutter texels hold copies of their neighbours across the seam. After a run
  // some gutter texels are non-zero, and every gutter value is the value of some
  // inside texel (a copy, not a blend or a stale value). Which texel is copied is
  // checked in Diffusion.GutterNextToAnIslandCopiesTheOtherSideOfTheSeam.
  const CubeRun r = RunCube();
  ASSERT_EQ(r.rgba.size(), size_t(CubeRun::W) * CubeRun::H * 4);
  std::unordered_set<float> inside;
  for (size_t i = 0; i < r.cls.size(); ++i)
    if (r.cls[i] == MOLDTEX_TEXEL_INSIDE) inside.insert(r.rgba[4 * i]);
  size_t gutter_nonzero = 0, not_a_copy = 0;
  for (size_t i = 0; i < r.cls.size(); ++i)
    if (r.cls[i] == MOLDTEX_TEXEL_GUTTER) {
      const float v = r.rgba[4 * i];
      gutter_nonzero += v > 0;
      not_a_copy += !inside.count(v);
      EXPECT_EQ(r.rgba[4 * i + 1], v);
      EXPECT_EQ(r.rgba[4 * i + 2], v);
    }
  EXPECT_GT(gutter_nonzero, 0u);
  EXPECT_EQ(not_a_copy, 0u);
}

TEST(TexelClasses, ReadClassesIsStableAndLayoutOnly) {
  // Classes depend on the layout only: the same before and after stepping.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(64, 64, 2000, 3), default_params());
  ASSERT_TRUE(sim) << LastError();
  const auto c0 = read_classes(sim.get(), 64, 64);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 20), MOLDTEX_OK);
  EXPECT_EQ(c0, read_classes(sim.get(), 64, 64));
}

}  // namespace
}  // namespace mtx
