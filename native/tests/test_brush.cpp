// Brushes: painting a geodesic disk into an image (moldtex_surface_paint) and the slime
// brushes that add, erase and undo agents (moldtex_sim_add_agents / erase / undo).
// Distances are checked against geometry computed here: Euclidean on a plane, great
// circles on a sphere.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <tuple>
#include <vector>

#include "test_backends.h"

namespace mtx {
namespace {

// ---- images ------------------------------------------------------------------------------

// 3D point of each texel centre that lies inside a triangle's UV (valid = false else).
struct TexelCentres {
  uint32_t width, height;
  std::vector<Vec3> point;
  std::vector<char> valid;
  TexelCentres(const Mesh& m, uint32_t w, uint32_t h)
      : width(w), height(h), point(size_t(w) * h), valid(size_t(w) * h, 0) {
    for (uint32_t t = 0; t < m.triangle_count(); ++t) {
      const Vec2 a = m.corner_uv(t, 0), b = m.corner_uv(t, 1), c = m.corner_uv(t, 2);
      const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
      if (std::fabs(det) < 1e-14) continue;
      const int x0 = std::max(0, int(std::floor(std::min({a[0], b[0], c[0]}) * w))),
                x1 = std::min(int(w) - 1, int(std::ceil(std::max({a[0], b[0], c[0]}) * w))),
                y0 = std::max(0, int(std::floor(std::min({a[1], b[1], c[1]}) * h))),
                y1 = std::min(int(h) - 1, int(std::ceil(std::max({a[1], b[1], c[1]}) * h)));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const double u = (x + 0.5) / w, v = (y + 0.5) / h;
          const double b1 = ((u - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (v - a[1])) / det;
          const double b2 = ((b[0] - a[0]) * (v - a[1]) - (u - a[0]) * (b[1] - a[1])) / det;
          const double b0 = 1 - b1 - b2;
          if (b0 < -1e-12 || b1 < -1e-12 || b2 < -1e-12) continue;
          const size_t i = size_t(y) * w + x;
          if (valid[i]) continue;
          valid[i] = 1;
          point[i] = add(add(scale(m.corner(t, 0), b0), scale(m.corner(t, 1), b1)), scale(m.corner(t, 2), b2));
        }
    }
  }
};

moldtex_brush Brush(const moldtex_surface_point& centre, float radius) {
  moldtex_brush b;
  moldtex_brush_init(&b);
  b.center = centre;
  b.radius = radius;
  b.falloff = 0.f;
  return b;
}

uint32_t Paint(moldtex_surface s, uint32_t w, uint32_t h, std::vector<float>& img,
               const moldtex_brush& b) {
  uint32_t changed = 0;
  EXPECT_EQ(moldtex_surface_paint(s, w, h, img.data(), img.size(), &b, &changed), MOLDTEX_OK)
      << LastError();
  return changed;
}

// [-4, 4]^2 in 32 x 32 cells, UV = (x + 4) / 8: on a 64 x 64 image a texel is 0.125.
Mesh Plane() {
  return make_plane(32, 32, -4, -4, 4, 4, [](double x, double y) { return Vec2{(x + 4) / 8, (y + 4) / 8}; });
}
constexpr uint32_t kTex = 64;
constexpr double kTexel = 8.0 / kTex;

// Every texel whose centre lies within r - `margin` of the centre is painted (channel
// `ch` == value) and none beyond r + margin is touched; `dist` gives a texel centre's
// distance to the brush centre. Also reports the extreme distances it saw.
void ExpectDisk(const TexelCentres& tc, const std::vector<float>& img, uint32_t ch, float value,
                double r, double margin, const std::function<double(const Vec3&)>& dist,
                double* max_painted = nullptr, double* min_unpainted = nullptr) {
  double hi = 0, lo = 1e30;
  size_t inner = 0;
  for (size_t i = 0; i < tc.valid.size(); ++i) {
    for (uint32_t k = 0; k < 4; ++k)
      if (k != ch) { ASSERT_EQ(img[4 * i + k], 0.f) << "texel " << i << " channel " << k; }
    const bool painted = img[4 * i + ch] != 0.f;
    if (painted) { ASSERT_EQ(img[4 * i + ch], value) << "texel " << i; }
    if (!tc.valid[i]) continue;  // no centre on the surface: only the bound below applies
    const double d = dist(tc.point[i]);
    if (painted) hi = std::max(hi, d);
    else lo = std::min(lo, d);
    if (d <= r - margin) {
      ++inner;
      ASSERT_TRUE(painted) << "texel " << i << " at distance " << d << " < r - margin = " << r - margin;
    }
    if (d > r + margin) { ASSERT_FALSE(painted) << "texel " << i << " at distance " << d; }
  }
  EXPECT_GT(inner, 0u);
  if (max_painted) *max_painted = hi;
  if (min_unpainted) *min_unpainted = lo;
}

TEST(Brush, PaintFillsTheDiskOnAPlaneWithinOneTexel) {
  // A hard dab (falloff 0, strength 1) of radius 1.5 = 12 texels on the plane, where
  // geodesic = Euclidean: every texel whose centre is within r - 1 texel is painted,
  // none beyond r + 1 texel (a painted texel holds a surface point at d <= r, and its
  // centre is within half a diagonal, 0.71 texel, of every point of it). Other channels
  // stay 0 and `changed` counts the painted texels.
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const Vec3 c{0.3, -0.2, 0};
  moldtex_brush b = Brush(locate(m, c), 1.5f);
  b.channel = 1;
  std::vector<float> img(kTex * kTex * 4, 0.f);
  const uint32_t changed = Paint(s.get(), kTex, kTex, img, b);
  const TexelCentres tc(m, kTex, kTex);
  double hi = 0, lo = 0;
  ExpectDisk(tc, img, 1, 1.f, 1.5, kTexel, [&](const Vec3& p) { return norm(sub(p, c)); }, &hi, &lo);
  size_t painted = 0;
  for (size_t i = 0; i < kTex * kTex; ++i) painted += img[4 * i + 1] != 0.f;
  EXPECT_EQ(changed, painted);
  // Measured: painted centres reach r + 0.59 texel, unpainted ones start at r + 0.57.
  EXPECT_LE(hi, 1.5 + 0.71 * kTexel);
  EXPECT_GE(lo, 1.5 - 0.71 * kTexel);
  RecordProperty("max_painted_minus_r_texels", std::to_string((hi - 1.5) / kTexel));
  RecordProperty("min_unpainted_minus_r_texels", std::to_string((lo - 1.5) / kTexel));
}

TEST(Brush, PaintOnASphereCoversTheGeodesicDisk) {
  // On a 64 x 32 unit sphere (256 x 128 image: one texel is at most 2 pi / 256 = 0.0245
  // long), a dab of radius 0.6 at 30 deg N: the painted region is the great-circle disk of
  // radius 0.6 within one texel (the polyhedron's geodesics differ from great circles by
  // ~1e-3 relative, 0.03 texel here).
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  constexpr uint32_t W = 256, H = 128;
  const double texel = 2 * kPi / W;
  const double lat = kPi / 6, lon = 1.7;
  const Vec3 dir{std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
  moldtex_brush b = Brush(locate(m, dir), 0.6f);
  std::vector<float> img(W * H * 4, 0.f);
  Paint(s.get(), W, H, img, b);
  const TexelCentres tc(m, W, H);
  auto great_circle = [&](const Vec3& p) { return std::acos(std::clamp(dot(normalized(p), dir), -1.0, 1.0)); };
  double hi = 0, lo = 0;
  ExpectDisk(tc, img, 0, 1.f, 0.6, texel, great_circle, &hi, &lo);
  RecordProperty("max_painted_minus_r_texels", std::to_string((hi - 0.6) / texel));
  RecordProperty("min_unpainted_minus_r_texels", std::to_string((lo - 0.6) / texel));
}

TEST(Brush, PaintAcrossAUvSeamPaintsBothSides) {
  // The sphere's seam runs along longitude 0 (u = 0 on one side, u = 1 on the other). A
  // dab at the equator 0.05 rad east of it with radius 0.3 reaches both islands' sides:
  // texels near u = 0 and near u = 1 are painted, and the whole region is still the
  // great-circle disk within one texel.
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  auto s = create_surface(m);
  constexpr uint32_t W = 256, H = 128;
  const Vec3 dir{std::cos(0.05), std::sin(0.05), 0};
  moldtex_brush b = Brush(locate(m, dir), 0.3f);
  std::vector<float> img(W * H * 4, 0.f);
  Paint(s.get(), W, H, img, b);
  size_t west = 0, east = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x)
      if (img[4 * (size_t(y) * W + x)] != 0.f) (x < W / 2 ? east : west)++;
  // East of the seam: 0.05 + 0.3 rad = 14 texels; west: 0.25 rad = 10 texels.
  EXPECT_GT(east, 100u);
  EXPECT_GT(west, 100u);
  const TexelCentres tc(m, W, H);
  ExpectDisk(tc, img, 0, 1.f, 0.3, 2 * kPi / W,
             [&](const Vec3& p) { return std::acos(std::clamp(dot(normalized(p), dir), -1.0, 1.0)); });
}

TEST(Brush, EraseRestoresZeroAndStrengthBlends) {
  // ERASE targets 0: the same dab in erase mode returns every texel to exactly 0
  // (v += (0 - v) * 1). With strength 0.5 and value 1, two dabs give 0.75 exactly.
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_brush b = Brush(locate(m, {1, 1, 0}), 1.0f);
  b.channel = 3;
  std::vector<float> img(kTex * kTex * 4, 0.f);
  const uint32_t painted = Paint(s.get(), kTex, kTex, img, b);
  EXPECT_GT(painted, 100u);
  b.mode = MOLDTEX_BRUSH_ERASE;
  EXPECT_EQ(Paint(s.get(), kTex, kTex, img, b), painted);
  for (float v : img) ASSERT_EQ(v, 0.f);
  b.mode = MOLDTEX_BRUSH_PAINT;
  b.strength = 0.5f;
  Paint(s.get(), kTex, kTex, img, b);
  Paint(s.get(), kTex, kTex, img, b);
  size_t n = 0;
  for (size_t i = 0; i < kTex * kTex; ++i)
    if (img[4 * i + 3] != 0.f) {
      ASSERT_EQ(img[4 * i + 3], 0.75f);
      ++n;
    }
  EXPECT_EQ(n, painted);
}

TEST(Brush, FalloffIsHighAtTheCentreAndLowAtTheRim) {
  // falloff 1: w(x) = 1 - smoothstep(x). A texel's weight is w at its nearest sample,
  // within 0.71 texel of its centre, so it equals w(centre distance / r) within
  // max|w'| * 0.71 texel / r = 1.5 * 0.059 = 0.09. Centre texels > 0.95, rim (0.85 r ..
  // r) < 0.15.
  const Mesh m = Plane();
  auto s = create_surface(m);
  const Vec3 c{-0.4, 0.9, 0};
  const double r = 1.5;
  moldtex_brush b = Brush(locate(m, c), float(r));
  b.falloff = 1.f;
  std::vector<float> img(kTex * kTex * 4, 0.f);
  Paint(s.get(), kTex, kTex, img, b);
  const TexelCentres tc(m, kTex, kTex);
  double centre_min = 1, rim_max = 0, worst = 0;
  for (size_t i = 0; i < tc.valid.size(); ++i) {
    if (!tc.valid[i]) continue;
    const double x = norm(sub(tc.point[i], c)) / r;
    const double v = img[4 * i];
    if (x < 1) {
      const double w = 1 - x * x * (3 - 2 * x);
      worst = std::max(worst, std::fabs(v - w));
      EXPECT_NEAR(v, w, 0.09) << "texel " << i << " at x = " << x;
    }
    if (x < 0.05) centre_min = std::min(centre_min, v);
    if (x > 0.85 && x < 1) rim_max = std::max(rim_max, v);
  }
  EXPECT_GT(centre_min, 0.95);
  EXPECT_LT(rim_max, 0.15);
  RecordProperty("max_weight_error", std::to_string(worst));
}

TEST(Brush, InvalidPaintRequestsAreRefusedWithAMessage) {
  Mesh m = make_quad();
  m.uvs.push_back(0.5f);
  m.uvs.push_back(0.5f);
  for (int k = 0; k < 3; ++k) m.triangle_uvs[3 + k] = uint32_t(m.uvs.size() / 2 - 1);  // degenerate
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::vector<float> img(16 * 16 * 4, 0.f);
  moldtex_surface_point ok_centre{0, {0.6f, 0.3f, 0.1f}};
  auto refused = [&](moldtex_brush b, const char* word, uint32_t w = 16, size_t count = 16 * 16 * 4,
                     float* data = nullptr) {
    EXPECT_EQ(moldtex_surface_paint(s.get(), w, 16, data ? data : img.data(), count, &b, nullptr),
              MOLDTEX_ERROR_INVALID_ARGUMENT)
        << word;
    EXPECT_NE(LastError().find(word), std::string::npos) << LastError();
  };
  const moldtex_brush good = Brush(ok_centre, 0.2f);
  ASSERT_EQ(moldtex_surface_paint(s.get(), 16, 16, img.data(), img.size(), &good, nullptr), MOLDTEX_OK)
      << LastError();
  moldtex_brush b = good;
  b.radius = std::nanf("");
  refused(b, "radius");
  b.radius = 0.f;
  refused(b, "radius");
  b.radius = 1e31f;
  refused(b, "radius");
  b = good;
  b.strength = 1.5f;
  refused(b, "strength");
  b = good;
  b.falloff = -0.1f;
  refused(b, "falloff");
  b = good;
  b.channel = 4;
  refused(b, "channel");
  b = good;
  b.mode = 7;
  refused(b, "mode");
  b = good;
  b.value = std::numeric_limits<float>::infinity();
  refused(b, "value");
  b = good;
  b.center.triangle = 2;
  refused(b, "triangle");
  b = good;
  b.center.triangle = 1;  // collapsed in UV
  refused(b, "zero-area");
  b = good;
  b.center.bary[0] = 2.f;
  refused(b, "sum to 1");
  b = good;
  b.center.bary[1] = std::nanf("");
  refused(b, "barycentric");
  b = good;
  b.struct_size = 8;
  refused(b, "struct_size");
  refused(good, "too small", 16, 16 * 16 * 4 - 1);
  refused(good, "size", 0);
  EXPECT_EQ(moldtex_surface_paint(s.get(), 16, 16, nullptr, img.size(), &good, nullptr),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_surface_paint(s.get(), 16, 16, img.data(), img.size(), nullptr, nullptr),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_surface_paint(nullptr, 16, 16, img.data(), img.size(), &good, nullptr),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
}

// ---- slime brushes -----------------------------------------------------------------------

// Agents as a sorted multiset of (triangle, b0, b1, b2) for order-free comparisons.
std::vector<std::tuple<uint32_t, float, float, float>> Multiset(moldtex_sim sim, uint32_t n) {
  std::vector<std::tuple<uint32_t, float, float, float>> v;
  for (const auto& a : read_agents(sim, n)) v.emplace_back(a.triangle, a.bary[0], a.bary[1], a.bary[2]);
  std::sort(v.begin(), v.end());
  return v;
}

uint32_t Count(moldtex_sim sim) { return get_stats(sim).agent_count; }

class Slime : public ::testing::TestWithParam<Backend> {};

constexpr uint32_t kAgents = 4000;

TEST_P(Slime, AddGrowsByExactlyNInsideTheDiskAndIsDeterministic) {
  // 2000 agents added at (0.3, -0.2) with radius 1.5: the count grows by exactly 2000;
  // every new agent lies within r of the centre (1e-5 relative: float walks over a few
  // triangles); they are uniform over the disk: mean distance 2r/3 within 0.03 r (the
  // standard error of 2000 draws is 0.005 r). The same dab on a simulation with another
  // thread count (CPU) or on the other backend adds bit-identical agents.
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_sim_config c = make_config(kTex, kTex, kAgents, 5);
  MTX_PIN_BACKEND(c);
  moldtex_sim_params p = default_params();
  p.thread_count = 1;
  auto sim = create_sim(s.get(), c, p);
  ASSERT_TRUE(sim) << LastError();
  const Vec3 centre{0.3, -0.2, 0};
  const double r = 1.5;
  const moldtex_brush b = Brush(locate(m, centre), float(r));
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 2000, 1), MOLDTEX_OK) << LastError();
  ASSERT_EQ(Count(sim.get()), kAgents + 2000);
  const auto all = read_agents(sim.get(), kAgents + 2000);
  double mean = 0;
  for (uint32_t i = kAgents; i < kAgents + 2000; ++i) {  // added agents come last until a step
    ASSERT_TRUE(ValidPoint(all[i], m.triangle_count()));
    const double d = norm(sub(evaluate_position(s.get(), all[i]), centre));
    ASSERT_LE(d, r * (1 + 1e-5)) << "agent " << i;
    mean += d / 2000;
  }
  EXPECT_NEAR(mean, 2 * r / 3, 0.03 * r);

  // The same on the CPU with 2 threads (and, for the OpenCL instance, on the CPU at all).
  moldtex_sim_config c2 = make_config(kTex, kTex, kAgents, 5);
  moldtex_sim_params p2 = default_params();
  p2.thread_count = 2;
  auto other = create_sim(s.get(), c2, p2);
  ASSERT_EQ(moldtex_sim_add_agents(other.get(), &b, 2000, 1), MOLDTEX_OK) << LastError();
  ASSERT_EQ(Count(other.get()), kAgents + 2000);
  const auto again = read_agents(other.get(), kAgents + 2000);
  for (uint32_t i = 0; i < kAgents + 2000; ++i) {
    ASSERT_EQ(again[i].triangle, all[i].triangle) << "agent " << i;
    ASSERT_EQ(std::memcmp(again[i].bary, all[i].bary, sizeof(all[i].bary)), 0) << "agent " << i;
  }
}

TEST_P(Slime, AgentsOfTheBrushSpeciesDepositInTheirChannel) {
  // Two species. Erase every agent (a disk larger than the plane; 0 agents is allowed),
  // step once (nothing deposits), then add 300 agents of species 1 and step once: only
  // channel 1 (G) gets pheromone, channel 0 (R) stays 0.
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_sim_config c = make_config(kTex, kTex, 1000, 8);
  c.species_count = 2;
  MTX_PIN_BACKEND(c);
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  moldtex_brush all = Brush(locate(m, {0, 0, 0}), 20.f);
  uint32_t removed = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(sim.get(), &all, 1, &removed), MOLDTEX_OK) << LastError();
  EXPECT_EQ(removed, 1000u);
  EXPECT_EQ(Count(sim.get()), 0u);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  for (float v : read_rgba(sim.get(), kTex, kTex)) ASSERT_TRUE(v == 0.f || v == 1.f);  // alpha mask only
  moldtex_brush b = Brush(locate(m, {1, 1, 0}), 1.f);
  b.channel = 1;
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 300, 2), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  const auto img = read_rgba(sim.get(), kTex, kTex);
  double r_sum = 0, g_sum = 0;
  for (size_t i = 0; i < kTex * kTex; ++i) {
    r_sum += img[4 * i];
    g_sum += img[4 * i + 1];
  }
  EXPECT_EQ(r_sum, 0.0);
  EXPECT_GT(g_sum, 10.0);
  b.channel = 2;  // the simulation has 2 species
  EXPECT_EQ(moldtex_sim_add_agents(sim.get(), &b, 1, 2), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("species"), std::string::npos) << LastError();
}

TEST_P(Slime, EraseRemovesExactlyTheAgentsInsideAndUndoPutsThemBack) {
  // 4000 random agents; an erase dab (strength 1, falloff 0) of radius 1.2 at (-0.7, 0.4)
  // removes every agent within r and none beyond (agents within 1e-4 r of the rim are
  // not judged: float positions). Undo restores the count and the exact positions.
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_sim_config c = make_config(kTex, kTex, kAgents, 11);
  MTX_PIN_BACKEND(c);
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 3), MOLDTEX_OK);  // agents that have moved
  const Vec3 centre{-0.7, 0.4, 0};
  const double r = 1.2;
  const auto before = Multiset(sim.get(), kAgents);
  size_t inside = 0, outside = 0;
  for (const auto& a : read_agents(sim.get(), kAgents)) {
    const double d = norm(sub(evaluate_position(s.get(), a), centre));
    inside += d < r * (1 - 1e-4);
    outside += d > r * (1 + 1e-4);
  }
  ASSERT_GT(inside, 100u);
  const moldtex_brush b = Brush(locate(m, centre), float(r));
  uint32_t removed = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 7, &removed), MOLDTEX_OK) << LastError();
  EXPECT_GE(removed, inside);
  EXPECT_LE(removed, kAgents - outside);
  EXPECT_EQ(Count(sim.get()), kAgents - removed);
  size_t outside_after = 0;
  for (const auto& a : read_agents(sim.get(), kAgents - removed)) {
    const double d = norm(sub(evaluate_position(s.get(), a), centre));
    ASSERT_GE(d, r * (1 - 1e-4)) << "an agent inside the disk survived";
    outside_after += d > r * (1 + 1e-4);
  }
  EXPECT_EQ(outside_after, outside);
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 7), MOLDTEX_OK) << LastError();
  EXPECT_EQ(Count(sim.get()), kAgents);
  EXPECT_EQ(Multiset(sim.get(), kAgents), before);
  // Nothing left to undo in batch 7: a no-op.
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 7), MOLDTEX_OK) << LastError();
  EXPECT_EQ(Count(sim.get()), kAgents);
  RecordProperty("removed", std::to_string(removed));
}

TEST_P(Slime, UndoOfAnAddRemovesThemAndRedoingGivesTheSameAgents) {
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_sim_config c = make_config(kTex, kTex, 1000, 2);
  MTX_PIN_BACKEND(c);
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  const auto before = Multiset(sim.get(), 1000);
  moldtex_brush b = Brush(locate(m, {2, -1, 0}), 0.8f);
  // A stroke of two dabs in batch 3, another stroke in batch 4.
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 100, 3), MOLDTEX_OK) << LastError();
  b.center = locate(m, {2.3, -1, 0});
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 50, 3), MOLDTEX_OK);
  const auto with_stroke = Multiset(sim.get(), 1150);
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 70, 4), MOLDTEX_OK);
  EXPECT_EQ(Count(sim.get()), 1220u);
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 4), MOLDTEX_OK);
  EXPECT_EQ(Count(sim.get()), 1150u);
  EXPECT_EQ(Multiset(sim.get(), 1150), with_stroke);
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 3), MOLDTEX_OK);
  EXPECT_EQ(Count(sim.get()), 1000u);
  EXPECT_EQ(Multiset(sim.get(), 1000), before);
  // Redo: the same dabs in the same batch give the same agents.
  b.center = locate(m, {2, -1, 0});
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 100, 3), MOLDTEX_OK);
  b.center = locate(m, {2.3, -1, 0});
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 50, 3), MOLDTEX_OK);
  EXPECT_EQ(Multiset(sim.get(), 1150), with_stroke);
}

TEST_P(Slime, EraseAndUndoKeepTheAgentsInTheirOrder) {
  // An agent's random streams are keyed by its place in the list, so the brushes must
  // keep that order: after an erase dab the survivors in their old order; after its undo
  // the survivors, then the erased agents in their old order (the CPU edits its arrays in
  // place, OpenCL exports and imports: both must give this).
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_sim_config c = make_config(kTex, kTex, kAgents, 13);
  MTX_PIN_BACKEND(c);
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 2), MOLDTEX_OK);
  auto same = [](const moldtex_surface_point& a, const moldtex_surface_point& b) {
    return a.triangle == b.triangle && std::memcmp(a.bary, b.bary, sizeof(a.bary)) == 0;
  };
  const auto before = read_agents(sim.get(), kAgents);
  const Vec3 centre{0.5, 0.5, 0};
  const double r = 1.0;
  const moldtex_brush b = Brush(locate(m, centre), float(r));  // strength 1, hard edge
  uint32_t removed = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 9, &removed), MOLDTEX_OK) << LastError();
  ASSERT_GT(removed, 100u);
  const auto after = read_agents(sim.get(), kAgents - removed);
  // Each survivor is the next agent of `before` that the disk did not take.
  std::vector<moldtex_surface_point> erased;
  size_t k = 0;
  for (const auto& a : before) {
    if (k < after.size() && same(a, after[k]))
      ++k;
    else
      erased.push_back(a);
  }
  ASSERT_EQ(k, after.size()) << "the survivors are not in their old order";
  ASSERT_EQ(erased.size(), removed);
  for (const auto& a : erased) EXPECT_LE(norm(sub(evaluate_position(s.get(), a), centre)), r * (1 + 1e-4));
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 9), MOLDTEX_OK) << LastError();
  const auto undone = read_agents(sim.get(), kAgents);
  for (size_t i = 0; i < after.size(); ++i) ASSERT_TRUE(same(undone[i], after[i])) << "agent " << i;
  for (size_t i = 0; i < erased.size(); ++i) ASSERT_TRUE(same(undone[after.size() + i], erased[i])) << "erased " << i;
}

TEST_P(Slime, AStrokeOfDabsGivesTheCpusAgentsAndTheyAllStep) {
  // Five dabs of 100 agents: a device writes only the new agents where its buffers have
  // room (after the first dab grows them by a quarter) and grows them again on the
  // third. The agents must be the CPU's bit for bit, and every added agent must then
  // step (a count the kernels did not see would leave the last ones standing).
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_sim_config c = make_config(kTex, kTex, 1000, 21);
  MTX_PIN_BACKEND(c);
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  moldtex_sim_config cpu_config = make_config(kTex, kTex, 1000, 21);
  cpu_config.backend = MOLDTEX_BACKEND_CPU;
  auto cpu = create_sim(s.get(), cpu_config, default_params());
  ASSERT_TRUE(cpu) << LastError();
  moldtex_brush b = Brush(locate(m, {0, 0, 0}), 0.7f);
  for (int dab = 0; dab < 5; ++dab) {
    b.center = locate(m, {-1.0 + 0.4 * dab, 0.5, 0});
    ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 100, 5), MOLDTEX_OK) << LastError();
    ASSERT_EQ(moldtex_sim_add_agents(cpu.get(), &b, 100, 5), MOLDTEX_OK) << LastError();
  }
  ASSERT_EQ(Count(sim.get()), 1500u);
  const auto added = read_agents(sim.get(), 1500);
  const auto expected = read_agents(cpu.get(), 1500);
  for (size_t i = 0; i < added.size(); ++i) {
    ASSERT_EQ(added[i].triangle, expected[i].triangle) << "agent " << i;
    ASSERT_EQ(std::memcmp(added[i].bary, expected[i].bary, sizeof(added[i].bary)), 0) << "agent " << i;
  }
  ASSERT_EQ(moldtex_sim_step(sim.get(), 3), MOLDTEX_OK) << LastError();
  const auto moved = read_agents(sim.get(), 1500);
  int still = 0;
  for (size_t i = 1000; i < 1500; ++i) {
    ASSERT_TRUE(ValidPoint(moved[i], m.triangle_count()));
    still += moved[i].triangle == added[i].triangle &&
             std::memcmp(moved[i].bary, added[i].bary, sizeof(added[i].bary)) == 0;
  }
  EXPECT_EQ(still, 0) << "added agents that did not move in 3 steps";
}

TEST_P(Slime, BrushesKeepTheContinuousModelsUMetricTrue) {
  // U (Eq. 5) is proportional to the live agents of species 0: it must follow every add,
  // erase and undo exactly (counts are integers), and come back to its first value.
  auto s = create_surface(Plane());
  moldtex_sim_config c = make_config(kTex, kTex, kAgents, 17);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  MTX_PIN_BACKEND(c);
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  const double u0 = get_stats(sim.get()).u_metric;
  ASSERT_GT(u0, 0.0);
  auto u_per_agent = [&] { return get_stats(sim.get()).u_metric / Count(sim.get()) / (u0 / kAgents); };
  moldtex_brush b = Brush(locate(Plane(), {-1, 1, 0}), 1.f);
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 1500, 2), MOLDTEX_OK) << LastError();
  EXPECT_EQ(Count(sim.get()), kAgents + 1500);
  EXPECT_NEAR(u_per_agent(), 1.0, 1e-12);
  b.center = locate(Plane(), {-0.5, 1, 0});
  uint32_t removed = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 3, &removed), MOLDTEX_OK) << LastError();
  ASSERT_GT(removed, 0u);
  EXPECT_NEAR(u_per_agent(), 1.0, 1e-12);
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 3), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 2), MOLDTEX_OK);
  EXPECT_EQ(Count(sim.get()), kAgents);
  EXPECT_EQ(get_stats(sim.get()).u_metric, u0);
}

TEST_P(Slime, ResetDropsBrushAgentsAndStashesAndSteppingWorks) {
  // After adds and an erase the simulation steps (agents stay valid, pheromone grows,
  // the count is unchanged by stepping); reset returns to config.agent_count, and an
  // undo after reset finds nothing to restore.
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_sim_config c = make_config(kTex, kTex, 1000, 4);
  MTX_PIN_BACKEND(c);
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  moldtex_brush b = Brush(locate(m, {-1, -1, 0}), 1.f);
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 3000, 1), MOLDTEX_OK) << LastError();
  b.center = locate(m, {1.5, 1.5, 0});
  uint32_t removed = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 2, &removed), MOLDTEX_OK) << LastError();
  const uint32_t n = 4000 - removed;
  ASSERT_EQ(Count(sim.get()), n);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 20), MOLDTEX_OK) << LastError();  // crosses a CPU re-sort
  EXPECT_EQ(Count(sim.get()), n);
  for (const auto& a : read_agents(sim.get(), n)) ASSERT_TRUE(ValidPoint(a, m.triangle_count()));
  EXPECT_GT(get_stats(sim.get()).coverage, 0.0);
  // Undo after stepping: the brush agents (wherever they walked) go, the erased come back.
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 1), MOLDTEX_OK);
  EXPECT_EQ(Count(sim.get()), n - 3000);
  ASSERT_EQ(moldtex_sim_reset(sim.get()), MOLDTEX_OK);
  EXPECT_EQ(Count(sim.get()), 1000u);
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 2), MOLDTEX_OK);  // stash dropped by reset
  EXPECT_EQ(Count(sim.get()), 1000u);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 2), MOLDTEX_OK);
}

TEST_P(Slime, SoftEraseRemovesAboutTheWeightedShareDeterministically) {
  // falloff 1, strength 1: each agent in the disk goes with probability w(d/r); uniform
  // agents give a share of int_0^1 w(x) 2x dx = 0.3 (0.2 .. 0.4 for ~700 agents: the
  // binomial standard deviation is 0.02). The same dab on an identical simulation
  // removes the same number.
  const Mesh m = Plane();
  auto s = create_surface(m);
  moldtex_sim_config c = make_config(kTex, kTex, 20000, 6);
  MTX_PIN_BACKEND(c);
  auto a = create_sim(s.get(), c, default_params());
  auto b2 = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(a && b2) << LastError();
  const Vec3 centre{0.5, 0.5, 0};
  moldtex_brush b = Brush(locate(m, centre), 1.2f);
  b.falloff = 1.f;
  size_t inside = 0;
  for (const auto& p : read_agents(a.get(), 20000)) inside += norm(sub(evaluate_position(s.get(), p), centre)) <= 1.2;
  uint32_t ra = 0, rb = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(a.get(), &b, 1, &ra), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_erase_agents(b2.get(), &b, 1, &rb), MOLDTEX_OK);
  EXPECT_EQ(ra, rb);
  const double share = double(ra) / double(inside);
  EXPECT_GT(share, 0.2);
  EXPECT_LT(share, 0.4);
  RecordProperty("share", std::to_string(share));
}

MTX_BACKENDS(Slime);

TEST(SlimeCpu, CheckpointWithBrushAgentsResumesExactly) {
  // A simulation with brush agents (count != config.agent_count) saves a checkpoint that
  // loads into a fresh simulation of the same config: same count, and 10 further steps
  // give bit-identical pheromone.
  const Mesh m = Plane();
  auto s = create_surface(m);
  const moldtex_sim_config c = make_config(kTex, kTex, 1000, 12);
  auto sim = create_sim(s.get(), c, default_params());
  moldtex_brush b = Brush(locate(m, {0, 0, 0}), 1.f);
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 777, 1), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 5), MOLDTEX_OK);
  const std::string path = ::testing::TempDir() + "moldtex_brush_checkpoint.bin";
  ASSERT_EQ(moldtex_sim_save_checkpoint(sim.get(), path.c_str()), MOLDTEX_OK) << LastError();
  auto resumed = create_sim(s.get(), c, default_params());
  ASSERT_EQ(moldtex_sim_load_checkpoint(resumed.get(), path.c_str()), MOLDTEX_OK) << LastError();
  EXPECT_EQ(Count(resumed.get()), 1777u);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 10), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_step(resumed.get(), 10), MOLDTEX_OK);
  EXPECT_EQ(read_rgba(sim.get(), kTex, kTex), read_rgba(resumed.get(), kTex, kTex));
  // Batches are not saved: undo on the resumed simulation has nothing to undo.
  ASSERT_EQ(moldtex_sim_undo_agents(resumed.get(), 1), MOLDTEX_OK);
  EXPECT_EQ(Count(resumed.get()), 1777u);
  std::remove(path.c_str());
}

TEST(SlimeCpu, EraseOnASphereFollowsGreatCircles) {
  // On a 64 x 32 unit sphere, an erase dab of radius 0.8 removes the agents within
  // great-circle distance 0.8 of its centre: no survivor is nearer than 0.8 - 0.005 and
  // the count lies between the agents within 0.795 and within 0.805 (0.005: the
  // polyhedron's geodesics differ from great circles by < 1%; measured nearest survivor
  // 0.8010, removed 7500 of 7484 inside 0.8).
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  auto s = create_surface(m);
  auto sim = create_sim(s.get(), make_config(256, 128, 50000, 3), default_params());
  ASSERT_TRUE(sim) << LastError();
  const Vec3 dir = normalized({0.3, 0.5, 0.6});
  auto gc = [&](const moldtex_surface_point& p) {
    return std::acos(std::clamp(dot(normalized(evaluate_position(s.get(), p)), dir), -1.0, 1.0));
  };
  size_t lo = 0, hi = 0;
  for (const auto& a : read_agents(sim.get(), 50000)) {
    lo += gc(a) <= 0.795;
    hi += gc(a) <= 0.805;
  }
  const moldtex_brush b = Brush(locate(m, dir), 0.8f);
  uint32_t removed = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 1, &removed), MOLDTEX_OK) << LastError();
  EXPECT_GE(removed, lo);
  EXPECT_LE(removed, hi);
  double nearest = 10;
  for (const auto& a : read_agents(sim.get(), 50000 - removed)) nearest = std::min(nearest, gc(a));
  EXPECT_GE(nearest, 0.795);
  RecordProperty("nearest_survivor", std::to_string(nearest));
}

TEST(SlimeCpu, InvalidRequestsAreRefusedWithAMessage) {
  const Mesh m = Plane();
  auto s = create_surface(m);
  auto sim = create_sim(s.get(), make_config(kTex, kTex, 100, 1), default_params());
  const moldtex_brush b = Brush(locate(m, {0, 0, 0}), 1.f);
  EXPECT_EQ(moldtex_sim_add_agents(sim.get(), &b, 10, 0), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("batch"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_sim_add_agents(sim.get(), &b, 10, 65536), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 0, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_undo_agents(sim.get(), 0), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_add_agents(sim.get(), &b, 1u << 26, 1), MOLDTEX_ERROR_TOO_LARGE);
  EXPECT_NE(LastError().find("limit"), std::string::npos) << LastError();
  moldtex_brush bad = b;
  bad.radius = -1.f;
  EXPECT_EQ(moldtex_sim_add_agents(sim.get(), &bad, 10, 1), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("radius"), std::string::npos) << LastError();
  bad = b;
  bad.center.triangle = m.triangle_count();
  EXPECT_EQ(moldtex_sim_erase_agents(sim.get(), &bad, 1, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_add_agents(sim.get(), nullptr, 10, 1), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_add_agents(nullptr, &b, 10, 1), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(get_stats(sim.get()).agent_count, 100u);  // nothing changed
}

TEST(SlimeCpu, BrushesAreRefusedWhileABakeOwnsTheSimulation) {
  const Mesh m = Plane();
  auto s = create_surface(m);
  auto sim = create_sim(s.get(), make_config(kTex, kTex, 3000, 1), default_params());
  moldtex_bake_desc d;
  moldtex_bake_desc_init(&d);
  const std::string dir = ::testing::TempDir();
  d.directory = dir.c_str();
  d.file_prefix = "moldtex_brush_busy_";
  d.first_frame = 1;
  d.last_frame = 500;
  d.steps_per_frame = 50;
  d.write_checkpoints = 0;
  moldtex_bake bake = nullptr;
  ASSERT_EQ(moldtex_bake_start(sim.get(), &d, &bake), MOLDTEX_OK) << LastError();
  const moldtex_brush b = Brush(locate(m, {0, 0, 0}), 1.f);
  EXPECT_EQ(moldtex_sim_add_agents(sim.get(), &b, 10, 1), MOLDTEX_ERROR_BUSY);
  EXPECT_NE(LastError().find("bake"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 1, nullptr), MOLDTEX_ERROR_BUSY);
  EXPECT_EQ(moldtex_sim_undo_agents(sim.get(), 1), MOLDTEX_ERROR_BUSY);
  moldtex_bake_cancel(bake);
  EXPECT_EQ(moldtex_bake_wait(bake), MOLDTEX_OK);
  moldtex_bake_release(bake);
  EXPECT_EQ(moldtex_sim_add_agents(sim.get(), &b, 10, 1), MOLDTEX_OK) << LastError();
  for (int f = 1; f <= 500; ++f) {
    char name[128];
    std::snprintf(name, sizeof(name), "%smoldtex_brush_busy_%04d.exr", dir.c_str(), f);
    std::remove(name);
  }
  std::remove((dir + "moldtex_brush_busy_metrics.csv").c_str());
}

}  // namespace
}  // namespace mtx
