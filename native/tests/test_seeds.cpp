// Starting seeds (moldtex_sim_config.seed_shape): circle, big bang, starburst and spawn
// map, on a flat plane where geodesic distances are plain 3D distances.
#include <algorithm>
#include <cmath>
#include <vector>

#include "test_backends.h"

namespace mtx {
namespace {

// [-4, 4]^2 in 32 x 32 cells, UV = (x + 4) / 8: on a 64 x 64 texture one texel is
// 0.125 units long, so a movement speed of 1 texel moves 0.125.
Mesh Plane() {
  return make_plane(32, 32, -4, -4, 4, 4, [](double x, double y) { return Vec2{(x + 4) / 8, (y + 4) / 8}; });
}
constexpr uint32_t kTex = 64;
constexpr double kTexel = 8.0 / kTex;

// Agents walk straight: no turning (turn speed 0) and nothing to sense (all three
// sensors at the same place: vision angle 0).
moldtex_sim_params Straight() {
  moldtex_sim_params p = default_params();
  p.turn_speed = 0;
  p.vision_angle = 0;
  return p;
}

std::vector<double> Distances(moldtex_surface s, moldtex_sim sim, uint32_t n, const Vec3& c) {
  std::vector<double> d;
  for (const auto& a : read_agents(sim, n)) d.push_back(norm(sub(evaluate_position(s, a), c)));
  return d;
}

class Seeds : public ::testing::TestWithParam<Backend> {};

TEST_P(Seeds, CircleStartsOnTheRadiusAndHeadsInward) {
  // Header: CIRCLE puts every agent on the geodesic circle of radius seed_radius around
  // seed_center, heading toward the centre. On a plane, geodesic = Euclidean: every
  // agent at R (1e-4 relative: float positions after a walk over several triangles),
  // and one straight step later at R - 1 texel.
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(kTex, kTex, 2000, 7);
  MTX_PIN_BACKEND(c);
  const Vec3 centre{0.3, -0.2, 0};
  c.seed_shape = MOLDTEX_SEED_CIRCLE;
  c.seed_center = locate(m, centre);
  c.seed_radius = 2.5f;
  auto sim = create_sim(s.get(), c, Straight());
  ASSERT_TRUE(sim) << LastError();
  for (double d : Distances(s.get(), sim.get(), 2000, centre)) ASSERT_NEAR(d, 2.5, 2.5e-4);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  for (double d : Distances(s.get(), sim.get(), 2000, centre)) ASSERT_NEAR(d, 2.5 - kTexel, 2.5e-4);
}

TEST_P(Seeds, BigBangStartsEveryAgentAtTheCentre) {
  // Header: BIG_BANG puts all agents at seed_center (1e-6: float barycentrics).
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(kTex, kTex, 500, 3);
  MTX_PIN_BACKEND(c);
  const Vec3 centre{-1.1, 0.7, 0};
  c.seed_shape = MOLDTEX_SEED_BIG_BANG;
  c.seed_center = locate(m, centre);
  auto sim = create_sim(s.get(), c, Straight());
  ASSERT_TRUE(sim) << LastError();
  for (double d : Distances(s.get(), sim.get(), 500, centre)) ASSERT_LT(d, 1e-6);
  // Headings are random over the full circle: after one straight step every agent is one
  // texel away and the mean position stays near the centre (|mean| < 0.1 texel for 500
  // uniform headings: standard error 0.045 texel per axis).
  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  Vec3 mean{0, 0, 0};
  for (const auto& a : read_agents(sim.get(), 500)) {
    const Vec3 p = evaluate_position(s.get(), a);
    ASSERT_NEAR(norm(sub(p, centre)), kTexel, 1e-5);
    mean = add(mean, scale(sub(p, centre), 1.0 / 500));
  }
  EXPECT_LT(norm(mean), 0.1 * kTexel);
}

TEST_P(Seeds, StarburstPlacesAgentsOnRaysHeadingOutward) {
  // Header: STARBURST puts agents on seed_rays rays at equal angles, at distances in
  // [0, R], heading outward. Azimuths (taken where the distance is > 0.05 R, so float
  // positions fix them to ~1e-5 rad) agree modulo 2 pi / rays within 1e-3 rad, every
  // ray gets agents, and one straight step moves the mean distance out by one texel.
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(kTex, kTex, 3000, 11);
  MTX_PIN_BACKEND(c);
  const Vec3 centre{0.1, 0.2, 0};
  const double R = 3.0;
  c.seed_shape = MOLDTEX_SEED_STARBURST;
  c.seed_center = locate(m, centre);
  c.seed_radius = float(R);
  c.seed_rays = 8;
  auto sim = create_sim(s.get(), c, Straight());
  ASSERT_TRUE(sim) << LastError();
  const double sector = 2 * kPi / 8;
  bool have_ref = false;
  double ref = 0, mean_before = 0;
  std::vector<int> per_ray(8, 0);
  for (const auto& a : read_agents(sim.get(), 3000)) {
    const Vec3 d = sub(evaluate_position(s.get(), a), centre);
    const double r = norm(d);
    mean_before += r / 3000;
    ASSERT_LE(r, R * (1 + 1e-4));
    if (r < 0.05 * R) continue;
    const double az = std::atan2(d[1], d[0]);
    if (!have_ref) {
      ref = az;
      have_ref = true;
    }
    const double off = std::remainder(az - ref, sector);
    ASSERT_LT(std::fabs(off), 1e-3) << "azimuth " << az << " is off every ray";
    const int ray = int(std::lround((az - ref) / sector)) % 8;
    ++per_ray[(ray + 8) % 8];
  }
  for (int k = 0; k < 8; ++k) EXPECT_GT(per_ray[k], 0) << "ray " << k << " is empty";
  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  double mean_after = 0;
  for (double r : Distances(s.get(), sim.get(), 3000, centre)) mean_after += r / 3000;
  EXPECT_NEAR(mean_after - mean_before, kTexel, 1e-4);
}

// Fields with a spawn weight of 1 in texels [x0, x1) x [y0, y1), 0 elsewhere.
std::vector<float> SpawnBox(uint32_t w, uint32_t h, uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1) {
  std::vector<float> f(size_t(w) * h * 4, 0.f);
  for (uint32_t y = y0; y < y1; ++y)
    for (uint32_t x = x0; x < x1; ++x) f[4 * (size_t(y) * w + x)] = 1.f;
  return f;
}

uint32_t TexelOf(const Vec2& uv, uint32_t w, uint32_t h) {
  const int x = std::clamp(int(uv[0] * w), 0, int(w) - 1), y = std::clamp(int(uv[1] * h), 0, int(h) - 1);
  return uint32_t(y) * w + uint32_t(x);
}

TEST_P(Seeds, SpawnMapPutsEveryAgentInAPaintedTexel) {
  // Header: SPAWN_MAP picks texels with probability ~ R * 3D area: with R = 1 in a
  // 10 x 6 texel box and 0 elsewhere every agent stands in the box, and (uniform area)
  // each texel gets about 1/60 of them (every texel is hit by 3000 agents: expected 50).
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const std::vector<float> fields = SpawnBox(kTex, kTex, 10, 20, 40, 46);
  moldtex_sim_config c = make_config(kTex, kTex, 3000, 5);
  MTX_PIN_BACKEND(c);
  c.seed_shape = MOLDTEX_SEED_SPAWN_MAP;
  c.fields_rgba = fields.data();
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  std::vector<int> hits(size_t(kTex) * kTex, 0);
  for (const auto& a : read_agents(sim.get(), 3000)) {
    const uint32_t t = TexelOf(evaluate_uv(s.get(), a), kTex, kTex);
    ASSERT_GT(fields[4 * t], 0.f) << "agent in texel " << t % kTex << ", " << t / kTex;
    ++hits[t];
  }
  for (uint32_t y = 40; y < 46; ++y)
    for (uint32_t x = 10; x < 20; ++x) EXPECT_GT(hits[y * kTex + x], 0) << x << ", " << y;
  // A reset respawns from the same map, identically (deterministic in the seed).
  const auto before = read_agents(sim.get(), 3000);
  ASSERT_EQ(moldtex_sim_reset(sim.get()), MOLDTEX_OK);
  const auto after = read_agents(sim.get(), 3000);
  for (size_t i = 0; i < before.size(); ++i) ASSERT_EQ(std::memcmp(&before[i], &after[i], sizeof(before[i])), 0);
}

MTX_BACKENDS(Seeds);

TEST(SeedsCpu, EmptySpawnMapIsRefusedWithAMessage) {
  // Header: a spawn map with no weight (or weight only under obstacles) is refused with
  // INVALID_ARGUMENT and a message that says to paint a spawn region, at create and at
  // set_fields; it never loops forever looking for a place.
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::vector<float> empty(size_t(kTex) * kTex * 4, 0.f);
  moldtex_sim_config c = make_config(kTex, kTex, 100, 5);
  c.seed_shape = MOLDTEX_SEED_SPAWN_MAP;
  c.fields_rgba = empty.data();
  moldtex_status st = MOLDTEX_OK;
  EXPECT_FALSE(create_sim(s.get(), c, default_params(), &st));
  EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("paint a spawn region"), std::string::npos) << LastError();
  // Weight only under obstacles.
  std::vector<float> walled = SpawnBox(kTex, kTex, 0, 8, 0, 8);
  for (uint32_t y = 0; y < 8; ++y)
    for (uint32_t x = 0; x < 8; ++x) walled[4 * (y * kTex + x) + 1] = 1.f;
  c.fields_rgba = walled.data();
  EXPECT_FALSE(create_sim(s.get(), c, default_params(), &st));
  EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("paint a spawn region"), std::string::npos) << LastError();
  // No fields at all.
  c.fields_rgba = nullptr;
  EXPECT_FALSE(create_sim(s.get(), c, default_params(), &st));
  EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("paint a spawn region"), std::string::npos) << LastError();
  // A working spawn-map simulation refuses an empty map later and keeps its own.
  const std::vector<float> good = SpawnBox(kTex, kTex, 0, 8, 0, 8);
  c.fields_rgba = good.data();
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  EXPECT_EQ(moldtex_sim_set_fields(sim.get(), empty.data(), empty.size()), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("paint a spawn region"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_sim_reset(sim.get()), MOLDTEX_OK) << LastError();
}

TEST(SeedsCpu, DefaultSeedIsUnchangedRandomSpawn) {
  // Header: seed_shape defaults to RANDOM, the behaviour before seeds existed; a config
  // that says RANDOM explicitly spawns bit-identically to one that relies on the default.
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(kTex, kTex, 300, 9);
  EXPECT_EQ(c.seed_shape, uint32_t(MOLDTEX_SEED_RANDOM));
  EXPECT_EQ(c.species_count, 1u);
  EXPECT_EQ(c.seed_rays, 8u);
  EXPECT_EQ(c.fields_rgba, nullptr);
  auto a = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(a) << LastError();
  const auto pa = read_agents(a.get(), 300);
  double spread = 0;
  for (const auto& p : pa) spread += norm(evaluate_position(s.get(), p)) / 300;
  EXPECT_GT(spread, 1.5);  // uniform on [-4, 4]^2: mean distance from the centre ~3.06
}

}  // namespace
}  // namespace mtx
