// Gray-Scott reaction-diffusion as a third model (issue #13, second half): U and V on the
// texture domain with the surface-measuring texel Laplacian (moldtex.h,
// MOLDTEX_MODEL_GRAY_SCOTT). Pattern lengths are measured on the texture in 3D
// (pattern_measures.h): the first zero of V's autocorrelation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "pattern_measures.h"
#include "test_backends.h"
#include "test_util.h"

namespace mtx {
namespace {

// The presets of the add-on, in the classic pixel units (D_u 0.2, D_v 0.1 per second,
// dt 1 s) with one "pixel" = `scale` mesh units.
struct Preset {
  const char* name;
  float feed, kill;
};
constexpr Preset kSpots{"spots", 0.035f, 0.065f};
constexpr Preset kLabyrinth{"labyrinth", 0.037f, 0.06f};
constexpr Preset kWorms{"worms", 0.078f, 0.061f};

moldtex_reaction_params Params(const Preset& p, double scale, uint32_t seeds) {
  moldtex_reaction_params r;
  moldtex_reaction_params_init(&r);
  r.feed = p.feed;
  r.kill = p.kill;
  r.diffusion_u = float(0.2 * scale * scale);
  r.diffusion_v = float(0.1 * scale * scale);
  r.seed_count = seeds;
  r.seed_radius = float(3 * scale);
  return r;
}

// A 1 x 1 plane (UV = xy).
const Mesh& Plane() {
  static const Mesh m = make_plane(16, 16, 0, 0, 1, 1, [](double x, double y) { return Vec2{x, y}; });
  return m;
}

struct RdRun {
  const Mesh* mesh = nullptr;
  uint32_t width = 128, height = 128;
  uint64_t seed = 1;
  uint32_t steps = 2000;
  uint32_t threads = 0;
  Backend backend = Backend::Cpu;
  moldtex_reaction_params p{};
};

struct Result {
  std::vector<float> rgba;  // R = V, G = U
  std::vector<double> v;
  moldtex_sim_stats stats{};
  bool ok = false;
};

SimPtr MakeSim(moldtex_surface s, const RdRun& r) {
  moldtex_sim_config c = make_config(r.width, r.height, 0, r.seed);
  c.model = MOLDTEX_MODEL_GRAY_SCOTT;
  std::string why;
  if (!PinBackend(r.backend, c, &why)) return nullptr;
  moldtex_sim_params mp = default_params();
  mp.thread_count = r.threads;
  auto sim = create_sim(s, c, mp);
  if (!sim) return sim;
  EXPECT_EQ(moldtex_sim_set_reaction_params(sim.get(), &r.p), MOLDTEX_OK) << LastError();
  EXPECT_EQ(moldtex_sim_reset(sim.get()), MOLDTEX_OK) << LastError();  // seeds from p
  return sim;
}

Result Simulate(const RdRun& r) {
  Result out;
  auto s = create_surface(*r.mesh);
  EXPECT_TRUE(s) << LastError();
  if (!s) return out;
  auto sim = MakeSim(s.get(), r);
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return out;
  EXPECT_EQ(moldtex_sim_step(sim.get(), r.steps), MOLDTEX_OK) << LastError();
  out.rgba = read_rgba(sim.get(), r.width, r.height);
  out.v.resize(size_t(r.width) * r.height);
  for (size_t i = 0; i < out.v.size(); ++i) out.v[i] = out.rgba[4 * i];
  out.stats = get_stats(sim.get());
  out.ok = true;
  return out;
}

double Spacing(const RdRun& r, const Result& o, double max_distance) {
  const TexelGeometry g = Texels(*r.mesh, r.width, r.height);
  return CharacteristicLength(g, o.v, 0.5 / r.width, max_distance);
}

// Finite and within [0, 1.5] everywhere, and not uniform (a pattern).
void ExpectSaneField(const Result& o, const char* what) {
  double lo = 1e9, hi = -1e9;
  for (size_t i = 0; i < o.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    ASSERT_TRUE(std::isfinite(o.rgba[i])) << what << " texel value " << i / 4;
    lo = std::min(lo, double(o.rgba[i]));
    hi = std::max(hi, double(o.rgba[i]));
  }
  EXPECT_GE(lo, 0.0) << what;
  EXPECT_LE(hi, 1.5) << what;
  double vlo = 1e9, vhi = -1e9;
  for (double x : o.v) vlo = std::min(vlo, x), vhi = std::max(vhi, x);
  EXPECT_GT(vhi - vlo, 0.1) << what << ": V is uniform (" << vlo << " .. " << vhi << ")";
}

TEST(ReactionDiffusion, Explore) {
  for (const Preset* p : {&kSpots, &kLabyrinth, &kWorms}) {
    RdRun r;
    r.mesh = &Plane();
    r.p = Params(*p, 1.0 / 128, 64);
    r.steps = 3000;
    const Result o = Simulate(r);
    ASSERT_TRUE(o.ok);
    std::printf("%s: mean V %.4f presence %.3f spacing %.4f\n", p->name, o.stats.coverage, o.stats.presence,
                Spacing(r, o, 0.4));
  }
}

}  // namespace
}  // namespace mtx
