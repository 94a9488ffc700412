// The continuous model (layton-intrinsic-slime.md §3.2; issue #10). Its promise, after
// the paper's Fig. 10: the pattern's character does not change with the discretisation
// (time step, agent count at a fixed U, texture resolution, UV stretch). Character is
// measured with three numbers on the texture, all in 3D:
//  - the mean concentration relative to U (Eq. 5),
//  - coverage: the 3D-area fraction where u > U (trails stand above the uniform level),
//  - a characteristic length: the gradient length mean(u) / mean |du/ds| in 3D, which is
//    proportional to the spacing of the trails.
// Each comparison averages two seeds at five times. The seed-to-seed spread of the same
// measures (the noise floor) is measured in SeedSpreadIsBelowTheTolerances: about 1% for
// the mean, 2% for coverage and 1% for the gradient length, so 10% leaves room above it.
// The first zero of the autocorrelation (issue #10's example of a length) is printed
// too but not asserted: it is set by the few largest structures on the torus and spreads
// 0.135-0.177 (25%) between seed pairs of the same run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>

#include "pattern_measures.h"
#include "test_backends.h"
#include "test_util.h"

namespace mtx {
namespace {

// A torus with UVs filling the texture: 3D area 4 pi^2 R r = 15.8.
const Mesh& Torus() {
  static const Mesh m = make_torus(64, 32, 1.0, 0.4);
  return m;
}

struct RunSpec {
  uint32_t size = 256;
  uint32_t agents = 40000;
  uint64_t seed = 1;
  double seconds = 4.0;
  uint32_t snapshots = 0;  // extra snapshots, 0.5 s apart, ending at `seconds`
  uint32_t threads = 0;
  const Mesh* mesh = nullptr;
  Backend backend = Backend::Cpu;
  moldtex_continuous_params p = turnover_look();
  bool keep_agents = false;  // read where the agents are at the end (Outcome::agents)
};

struct Outcome {
  std::vector<double> shown;  // u / U (channel R) at the end
  std::vector<std::vector<double>> snapshots;  // and `snapshots` before, 0.5 s apart
  moldtex_sim_stats stats{};
  std::vector<moldtex_surface_point> agents;  // where the agents are at the end (keep_agents)
};

Outcome Simulate(const RunSpec& r) {
  const Mesh& m = r.mesh ? *r.mesh : Torus();
  Outcome out;
  auto s = create_surface(m);
  EXPECT_TRUE(s) << LastError();
  if (!s) return out;
  moldtex_sim_config c = make_config(r.size, r.size, r.agents, r.seed);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  std::string why;
  EXPECT_TRUE(PinBackend(r.backend, c, &why)) << why;
  moldtex_sim_params mp = default_params();
  mp.thread_count = r.threads;
  auto sim = create_sim(s.get(), c, mp);
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return out;
  EXPECT_EQ(moldtex_sim_set_continuous_params(sim.get(), &r.p), MOLDTEX_OK) << LastError();
  auto advance_to = [&](double t) {
    const uint32_t steps = uint32_t(std::lround(t / r.p.time_step)) - uint32_t(get_stats(sim.get()).step_count);
    EXPECT_EQ(moldtex_sim_step(sim.get(), steps), MOLDTEX_OK) << LastError();
    const std::vector<float> rgba = read_rgba(sim.get(), r.size, r.size);
    std::vector<double> shown(size_t(r.size) * r.size);
    for (size_t i = 0; i < shown.size(); ++i) shown[i] = rgba[4 * i];
    return shown;
  };
  for (uint32_t k = r.snapshots; k > 0; --k) out.snapshots.push_back(advance_to(r.seconds - 0.5 * k));
  out.shown = advance_to(r.seconds);
  out.snapshots.push_back(out.shown);
  out.stats = get_stats(sim.get());
  if (r.keep_agents) {
    out.agents.resize(r.agents);
    EXPECT_EQ(moldtex_sim_read_agents(sim.get(), out.agents.data(), out.agents.size()), MOLDTEX_OK) << LastError();
  }
  return out;
}

struct Character {
  double mean = 0, coverage = 0, length = 0, correlation = 0;
};

Character Measure(const Mesh& m, uint32_t size, const std::vector<double>& shown) {
  const TexelGeometry g = Texels(m, size, size);
  Character c;
  c.mean = Mean(g, shown, [](uint32_t, uint32_t) { return true; });
  std::vector<double> above(shown.size());
  for (size_t i = 0; i < shown.size(); ++i) above[i] = shown[i] > 1.0 ? 1.0 : 0.0;
  c.coverage = Mean(g, above, [](uint32_t, uint32_t) { return true; });
  c.length = GradientLength(g, shown);
  c.correlation = CharacteristicLength(g, shown, 0.01, 1.5);
  return c;
}

// The mean character over seeds `first` and `first + 1`, each measured at 5 times 0.5 s
// apart (the pattern renews itself within a lifetime, so the snapshots are partly
// independent samples and their mean is steadier than one snapshot).
Character Character2(RunSpec r, uint64_t first = 1) {
  Character sum;
  r.snapshots = 4;
  for (uint64_t seed : {first, first + 1}) {
    r.seed = seed;
    const Outcome o = Simulate(r);
    for (const auto& shown : o.snapshots) {
      const Character c = Measure(r.mesh ? *r.mesh : Torus(), r.size, shown);
      const double n = 2.0 * o.snapshots.size();
      sum.mean += c.mean / n;
      sum.coverage += c.coverage / n;
      sum.length += c.length / n;
      sum.correlation += c.correlation / n;
    }
  }
  return sum;
}

std::string Str(const Character& c) {
  char b[160];
  std::snprintf(b, sizeof b, "mean %.3f U, coverage %.3f, gradient length %.4f (correlation zero %.3f)", c.mean,
                c.coverage, c.length, c.correlation);
  return b;
}

// |a / b - 1| for each measure within `tol`.
::testing::AssertionResult Same(const Character& a, const Character& b, double tol) {
  const double dm = std::fabs(a.mean / b.mean - 1), dc = std::fabs(a.coverage / b.coverage - 1),
               dl = std::fabs(a.length / b.length - 1);
  std::printf("  %s\n  vs %s\n  differences %.3f, %.3f, %.3f\n", Str(a).c_str(), Str(b).c_str(), dm, dc, dl);
  if (dm <= tol && dc <= tol && dl <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << Str(a) << " vs " << Str(b) << ": differences " << dm << ", " << dc
                                       << ", " << dl << " (tolerance " << tol << ")";
}

TEST(ContinuousModel, ParametersAreValidatedAndKept) {
  auto s = create_surface(Torus());
  moldtex_sim_config c = make_config(64, 64, 100, 1);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.backend = MOLDTEX_BACKEND_CPU;
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  moldtex_continuous_params p = turnover_look();
  p.sensor_angle = -30.f;  // chemo-repulsion is allowed
  p.mean_lifetime = 1.f;
  EXPECT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  moldtex_continuous_params back;
  moldtex_continuous_params_init(&back);
  ASSERT_EQ(moldtex_sim_get_continuous_params(sim.get(), &back), MOLDTEX_OK);
  EXPECT_EQ(back.sensor_angle, -30.f);
  EXPECT_EQ(back.mean_lifetime, 1.f);
  for (auto bad : {+[](moldtex_continuous_params& q) { q.turn_frequency = 0.f; },
                   +[](moldtex_continuous_params& q) { q.time_step = NAN; },
                   +[](moldtex_continuous_params& q) { q.diffusion_rate = -1.f; },
                   +[](moldtex_continuous_params& q) { q.sensor_angle = 200.f; },
                   +[](moldtex_continuous_params& q) { q.integrator = 7; }}) {
    moldtex_continuous_params q = turnover_look();
    bad(q);
    EXPECT_EQ(moldtex_sim_set_continuous_params(sim.get(), &q), MOLDTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_FALSE(LastError().empty());
  }
  // The bias field: one 3D vector per triangle, finite.
  const uint32_t triangles = Torus().triangle_count();
  std::vector<float> bias(size_t(triangles) * 3, 0.5f);
  EXPECT_EQ(moldtex_sim_set_bias(sim.get(), bias.data(), bias.size()), MOLDTEX_OK) << LastError();
  EXPECT_EQ(moldtex_sim_set_bias(sim.get(), bias.data(), bias.size() - 1), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("triangle_count * 3"), std::string::npos) << LastError();
  bias[7] = NAN;
  EXPECT_EQ(moldtex_sim_set_bias(sim.get(), bias.data(), bias.size()), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("triangle 2"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_sim_set_bias(sim.get(), nullptr, 0), MOLDTEX_OK);
  moldtex_continuous_params sym = turnover_look();
  sym.bias_symmetry = 7;
  EXPECT_EQ(moldtex_sim_set_continuous_params(sim.get(), &sym), MOLDTEX_ERROR_INVALID_ARGUMENT);
  moldtex_sim_config unknown = make_config(64, 64, 100, 1);
  unknown.model = 9;
  moldtex_sim raw = nullptr;
  const moldtex_sim_params defaults = default_params();
  EXPECT_EQ(moldtex_sim_create(s.get(), &unknown, &defaults, &raw), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("model"), std::string::npos) << LastError();
}

// U (Eq. 5) is what the mean concentration settles at: deposits add N_active r_dep per
// second, decay removes r_dec of the total, so the total settles at N_active r_dep / r_dec
// with N_active = N exp(-t_a / tau) in the steady state of ages. Without turnover every
// agent deposits, and the mean must equal U to float rounding (0.5%: the sum of
// 16k-texel planes in float over hundreds of steps). With turnover the active count
// fluctuates binomially, sd sqrt(N p (1 - p)) / (N p) = 0.8% for N = 40000,
// p = exp(-1): 3% is about 4 sd, and the measurement averages 5 samples.
TEST(ContinuousModel, MeanConcentrationSettlesAtU) {
  RunSpec r;
  r.size = 128;
  r.seconds = 2.0;  // 12 decay times: the start-up remnant is exp(-12.6) of U
  r.p.mean_lifetime = 0.f;
  r.p.activation_time = 0.f;
  Outcome o = Simulate(r);
  const double area = 4 * M_PI * M_PI * 0.4;
  const double u = r.agents * r.p.deposit_rate / (r.p.decay_rate * area);
  EXPECT_NEAR(o.stats.u_metric / u, 1.0, 0.02) << "U from the core: cell area vs the torus' area";
  EXPECT_NEAR(o.stats.mean_concentration / o.stats.u_metric, 1.0, 0.005);
  EXPECT_NEAR(o.stats.time, 2.0, 1e-3);
  r.p.mean_lifetime = 0.5f;
  r.p.activation_time = 0.5f;
  double ratio = 0;
  for (uint64_t seed : {1, 2, 3, 4, 5}) {
    r.seed = seed;
    o = Simulate(r);
    EXPECT_NEAR(o.stats.u_metric / (u * std::exp(-1.0)), 1.0, 0.02);
    ratio += o.stats.mean_concentration / o.stats.u_metric / 5;
  }
  EXPECT_NEAR(ratio, 1.0, 0.03);
}

// Every agent in one spot (a big bang) deposits into the same few texels in the same
// step: the 32-bit fixed-point sums must not overflow (an agent's deposit is at most
// (2^31 - 1) / agents units), so the amount after one step is exactly what the agents
// laid: N r_dep (1 - e^-k) / r_dec with k = r_dec dt (deposits spread over the step,
// then the step's decay; diffusion moves but keeps it). 1e-4: float sums of a plane.
TEST(ContinuousModel, DepositsOfAllAgentsInOneTexelDoNotOverflow) {
  auto s = create_surface(Torus());
  moldtex_sim_config c = make_config(64, 64, 400000, 1);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.backend = MOLDTEX_BACKEND_CPU;
  c.seed_shape = MOLDTEX_SEED_BIG_BANG;
  c.seed_center.triangle = 100;
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  moldtex_continuous_params p = turnover_look();
  p.mean_lifetime = 0.f;
  p.activation_time = 0.f;
  p.move_rate = 0.f;  // nobody leaves the spot
  ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  const moldtex_sim_stats st = get_stats(sim.get());
  const double k = double(p.decay_rate) * p.time_step;
  const double laid = 400000.0 * p.deposit_rate * -std::expm1(-k) / p.decay_rate;
  const double area = st.u_metric > 0 ? 400000.0 * p.deposit_rate / (p.decay_rate * st.u_metric) : 0;
  EXPECT_NEAR(st.mean_concentration * area / laid, 1.0, 1e-4);
}

TEST(ContinuousModel, SameSeedSameTextureForAnyThreadCount) {
  RunSpec r;
  r.size = 128;
  r.agents = 20000;
  r.seconds = 0.5;
  r.p.mean_lifetime = 0.3f;
  r.p.activation_time = 0.1f;
  r.threads = 1;
  const Outcome one = Simulate(r);
  for (uint32_t t : {2u, 4u}) {
    r.threads = t;
    const Outcome other = Simulate(r);
    ASSERT_EQ(other.shown.size(), one.shown.size());
    EXPECT_TRUE(std::equal(one.shown.begin(), one.shown.end(), other.shown.begin())) << t << " threads";
  }
}

// The noise floor of the character measures: two seeds against two other seeds.
TEST(ContinuousModel, SeedSpreadIsBelowTheTolerances) {
  RunSpec r;
  const Character a = Character2(r, 1), b = Character2(r, 3), c3 = Character2(r, 5);
  std::printf("seeds 5+6: %s\n", Str(c3).c_str());
  std::printf("seeds 1+2: %s\nseeds 3+4: %s\n", Str(a).c_str(), Str(b).c_str());
  EXPECT_TRUE(Same(a, b, 0.05)) << "the 10% tolerances below need a noise floor well under them";
  EXPECT_TRUE(Same(a, c3, 0.05));
  EXPECT_GT(a.coverage, 0.05) << "a pattern (trails above U) must have formed";
  EXPECT_LT(a.coverage, 0.6);
  EXPECT_GT(a.correlation, 0.05) << "cells of a few tenths of a unit";
  EXPECT_LT(a.correlation, 1.0);
}

// Fig. 10d: the time step from 1/30 to 1/240 s leaves the character within 10%.
TEST(ContinuousModel, CharacterDoesNotDependOnTheTimeStep) {
  RunSpec r;
  const Character reference = Character2(r);  // 1/60 s
  for (float dt : {1.f / 30.f, 1.f / 240.f}) {
    RunSpec q = r;
    q.p.time_step = dt;
    EXPECT_TRUE(Same(Character2(q), reference, 0.10)) << "dt = " << dt;
  }
}

// The contrast Fig. 10d draws: MoMaS (texel units, as the paper defines it) on the same
// torus for the same 4 simulated seconds at 1/60 and 1/240 s. Its pheromone is normalised
// by its own mean so the same measures apply. MoMaS' moves, deposits and blur are per
// step, so a smaller time step changes the pattern far beyond the continuous model's 10%.
Character MomasCharacter(float dt, uint64_t seed) {
  auto s = create_surface(Torus());
  moldtex_sim_config c = make_config(256, 256, 40000, seed);
  c.backend = MOLDTEX_BACKEND_CPU;
  moldtex_sim_params p = default_params();
  p.time_step = dt;
  auto sim = create_sim(s.get(), c, p);
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return {};
  EXPECT_EQ(moldtex_sim_step(sim.get(), uint32_t(std::lround(4.0 / dt))), MOLDTEX_OK);
  const std::vector<float> rgba = read_rgba(sim.get(), 256, 256);
  std::vector<double> f(rgba.size() / 4);
  for (size_t i = 0; i < f.size(); ++i) f[i] = rgba[4 * i];
  const TexelGeometry g = Texels(Torus(), 256, 256);
  const double mean = Mean(g, f, [](uint32_t, uint32_t) { return true; });
  for (double& v : f) v /= mean;
  Character ch = Measure(Torus(), 256, f);
  ch.mean = mean;  // the unnormalised mean pheromone
  return ch;
}

TEST(ContinuousModel, MomasInContrastDependsOnTheTimeStep) {
  const Character a = MomasCharacter(1.f / 60.f, 1), b = MomasCharacter(1.f / 240.f, 1);
  std::printf("MoMaS, mean pheromone / coverage above the mean / gradient length:\n");
  EXPECT_FALSE(Same(b, a, 0.10)) << "MoMaS was expected to change with the time step";
}

// Fig. 10c: four times the agents at a quarter of the deposit rate (U fixed).
TEST(ContinuousModel, CharacterDoesNotDependOnTheAgentCountAtFixedU) {
  RunSpec r;
  r.agents = 20000;
  const Character reference = Character2(r);
  r.agents = 80000;
  r.p.deposit_rate /= 4;
  EXPECT_TRUE(Same(Character2(r), reference, 0.10));
}

// Fig. 10b: the texture resolution doubled.
TEST(ContinuousModel, CharacterDoesNotDependOnTheResolution) {
  RunSpec r;
  const Character reference = Character2(r);
  r.size = 512;
  EXPECT_TRUE(Same(Character2(r), reference, 0.10));
}

// Fig. 5: turnover keeps the pattern uniform. Uniformity: the coefficient of variation
// of the mean concentration over 16 x 8 patches of the torus' UV grid (each an equal
// slice of the tube), lower is more uniform.
double PatchVariation(const Mesh& m, uint32_t size, const std::vector<double>& shown) {
  const TexelGeometry g = Texels(m, size, size);
  std::vector<double> means;
  for (uint32_t py = 0; py < 8; ++py)
    for (uint32_t px = 0; px < 16; ++px)
      means.push_back(Mean(g, shown, [&](uint32_t x, uint32_t y) {
        return x * 16 / size == px && y * 8 / size == py;
      }));
  const double mean = std::accumulate(means.begin(), means.end(), 0.0) / means.size();
  double var = 0;
  for (double v : means) var += (v - mean) * (v - mean) / means.size();
  return std::sqrt(var) / mean;
}

TEST(ContinuousModel, TurnoverMakesThePatternMoreUniform) {
  RunSpec r;
  r.seconds = 10.0;
  double off = 0, on = 0;
  for (uint64_t seed : {1, 2}) {
    r.seed = seed;
    r.p.mean_lifetime = 0.f;
    r.p.activation_time = 0.f;
    off += PatchVariation(Torus(), r.size, Simulate(r).shown) / 2;
    r.p.mean_lifetime = 0.2f;
    r.p.activation_time = 0.1f;
    on += PatchVariation(Torus(), r.size, Simulate(r).shown) / 2;
  }
  std::printf("patch variation: turnover off %.3f, tau 0.2 s %.3f\n", off, on);
  EXPECT_LT(on, 0.8 * off);
}

// UV stretch: a plane whose UVs are warped u -> u^2 (texels on the left are far smaller
// in 3D than on the right). The characteristic length in 3D must be the same in both
// halves within 10%.
TEST(ContinuousModel, StretchedUvsDoNotChangeTheLengthIn3D) {
  static const Mesh warped = make_uv_squared_plane(64);
  RunSpec r;
  r.mesh = &warped;
  r.size = 512;
  r.agents = 40000;
  double left = 0, right = 0;
  for (uint64_t seed : {1, 2}) {
    r.seed = seed;
    const std::vector<double> shown = Simulate(r).shown;
    TexelGeometry g = Texels(warped, r.size, r.size);
    for (int half = 0; half < 2; ++half) {
      TexelGeometry h = g;
      for (size_t i = 0; i < h.triangle.size(); ++i) {
        if (!h.inside(i)) continue;
        const double x = h.position[i][0];
        // 3D halves, away from the plane's border (0.3 units) and from the middle.
        const bool in = half == 0 ? (x > 0.3 && x < 1.8) : (x > 2.2 && x < 3.7);
        const double y = h.position[i][1];
        if (!in || y < 0.3 || y > 3.7) h.triangle[i] = -1;
      }
      (half == 0 ? left : right) += GradientLength(h, shown) / 2;
    }
  }
  std::printf("gradient length: compressed half %.4f, stretched half %.4f\n", left, right);
  EXPECT_NEAR(left / right, 1.0, 0.10);
}

// No trace of the texture-border seam (issue #9's check, on this model): the torus' UVs
// fill the texture, so the seam u = 0 runs along the border with no gutter between its
// sides. Per column line x (between columns x - 1 and x; x = 0 is the seam) two measures
// of u/U, time-averaged over 5 snapshots of 2 seeds: the mean over the two columns and
// the mean |difference| of the texel pairs straddling the line. The 255 other lines are
// placebos: the seam line's measures must lie within 3 standard deviations of theirs.
TEST(ContinuousModel, NoTraceOfTheTextureBorderSeam) {
  RunSpec r;
  r.snapshots = 4;
  const uint32_t n = r.size;
  std::vector<double> level(n, 0.0), straddle(n, 0.0);
  for (uint64_t seed : {1, 2}) {
    r.seed = seed;
    const Outcome o = Simulate(r);
    for (const auto& f : o.snapshots)
      for (uint32_t x = 0; x < n; ++x) {
        const uint32_t left = (x + n - 1) % n;
        for (uint32_t y = 0; y < n; ++y) {
          const double a = f[size_t(y) * n + left], b = f[size_t(y) * n + x];
          level[x] += (a + b) / 2;
          straddle[x] += std::fabs(a - b);
        }
      }
  }
  for (const std::vector<double>* m : {&level, &straddle}) {
    double mean = 0, sq = 0;
    for (uint32_t x = 1; x < n; ++x) mean += (*m)[x] / (n - 1);
    for (uint32_t x = 1; x < n; ++x) sq += ((*m)[x] - mean) * ((*m)[x] - mean) / (n - 2);
    const double z = ((*m)[0] - mean) / std::sqrt(sq);
    std::printf("%s: seam %.4g, other lines %.4g +- %.2g (z = %.2f)\n", m == &level ? "level" : "straddle",
                (*m)[0], mean, std::sqrt(sq), z);
    EXPECT_LT(std::fabs(z), 3.0) << (m == &level ? "level" : "straddle");
  }
}

// Directional bias (§3.3, Fig. 6; issue #12's first check): n = 2 along x on a plane
// whose texel grid is aligned with x and y. The pattern's structure tensor (gradients of
// u/U by central differences) gives an orientation coherence (lambda1 - lambda2) /
// (lambda1 + lambda2) and the trails' dominant direction (perpendicular to the dominant
// gradient). Without bias the network is isotropic: its coherence is the calibration.
struct Orientation {
  double coherence = 0, degrees = 0;
};

Orientation TrailOrientation(const std::vector<double>& f, uint32_t n) {
  double xx = 0, yy = 0, xy = 0;
  for (uint32_t y = 1; y + 1 < n; ++y)
    for (uint32_t x = 1; x + 1 < n; ++x) {
      const size_t i = size_t(y) * n + x;
      const double gx = (f[i + 1] - f[i - 1]) / 2, gy = (f[i + n] - f[i - n]) / 2;
      xx += gx * gx;
      yy += gy * gy;
      xy += gx * gy;
    }
  const double root = std::sqrt((xx - yy) * (xx - yy) + 4 * xy * xy);
  Orientation o;
  o.coherence = root / (xx + yy);
  double degrees = 0.5 * std::atan2(2 * xy, xx - yy) * 180 / M_PI + 90;  // trails: across the gradient
  while (degrees > 90) degrees -= 180;
  o.degrees = degrees;
  return o;
}

// Diagnostic (run by hand; open in #9): open boundaries on the unit plane. The texels
// within one sensor distance (0.09) of the rim against the whole plane, beside "placebo"
// rings of the same width farther in, and the agents per ring over the ring's area share
// (4 seeds x 5 snapshots pooled, defaults with turnover). Measured 2026-12-03, 256^2:
// band 1.32 (placebo rings 0.79-0.97), agents 1.24 / 0.95 / 0.82 / 0.77 / 1.04 from the
// rim inwards: agents gather at the rim and the pheromone follows them. Without deposits
// (MOLDTEX_RIM_DEPOSIT=0) the agents are uniform (0.99-1.01), so the walk is not the
// cause; without turnover (MOLDTEX_RIM_LIFETIME=0): band 1.32, agents 1.43 at the rim.
// Tried and reverted, each with the same result: sensor traces that stop at the rim
// (Layton et al.; 1.34) and, besides, agents scattered off it by the cosine law as MoMaS'
// agents are (1.31; agents 1.27 at the rim). Unlike MoMaS'
// (SurfaceUnits.OpenBoundariesNeitherLoseNorGain), the rim's excess here does not come
// from the boundary rule.
TEST(ContinuousModel, DISABLED_OpenBoundaryDiagnostics) {
  const Mesh m = make_quad();
  RunSpec r;
  r.mesh = &m;
  r.agents = 20000;
  r.snapshots = 4;
  r.keep_agents = true;
  if (const char* v = std::getenv("MOLDTEX_RIM_DEPOSIT")) r.p.deposit_rate = float(std::atof(v));
  if (const char* v = std::getenv("MOLDTEX_RIM_LIFETIME")) r.p.mean_lifetime = float(std::atof(v));
  const TexelGeometry g = Texels(m, r.size, r.size);
  std::vector<double> pooled(size_t(r.size) * r.size, 0.0);
  double density[5] = {0, 0, 0, 0, 0};
  for (uint64_t seed : {1, 2, 3, 4}) {
    r.seed = seed;
    const Outcome o = Simulate(r);
    for (const auto& shown : o.snapshots)
      for (size_t i = 0; i < shown.size(); ++i) pooled[i] += shown[i];
    for (const moldtex_surface_point& a : o.agents) {
      const Vec3 q = m.point(a);
      const double x = q[0], y = q[1];
      const double e = std::min(std::min(x, 1 - x), std::min(y, 1 - y));
      density[std::min(4, int(e / 0.09))] += 1;
    }
  }
  {
    double total = 0;
    for (double d : density) total += d;
    std::printf("  agents per ring / area share:");
    for (int b = 0; b < 5; ++b) {
      const double e0 = 0.09 * b, e1 = b == 4 ? 0.5 : 0.09 * (b + 1);
      const double share = (1 - 2 * e0) * (1 - 2 * e0) - (1 - 2 * e1) * (1 - 2 * e1);
      std::printf(" %.3f", density[b] / total / share);
    }
    std::printf("\n");
  }
  const double all = Mean(g, pooled, [](uint32_t, uint32_t) { return true; });
  auto ring = [&](double d0) {
    return Mean(g, pooled, [&](uint32_t x, uint32_t y) {
             const Vec3& p = g.position[size_t(y) * r.size + x];
             const double e = std::min(std::min(p[0], 1 - p[0]), std::min(p[1], 1 - p[1]));
             return e >= d0 && e < d0 + 0.09;
           }) / all;
  };
  const double band = ring(0);
  double lo = 1e9, hi = 0;
  std::printf("  boundary band %.3f; placebo rings:", band);
  for (double d = 0.09; d < 0.4; d += 0.09) {
    lo = std::min(lo, ring(d));
    hi = std::max(hi, ring(d));
    std::printf(" %.3f", ring(d));
  }
  std::printf(" (%.3f .. %.3f)\n", lo, hi);
}

TEST(ContinuousModel, BiasAlignsTheTrails) {
  static const Mesh plane = make_plane(8, 8, 0, 0, 4, 4, [](double x, double y) { return Vec2{x / 4, y / 4}; });
  auto s = create_surface(plane);
  ASSERT_TRUE(s) << LastError();
  const uint32_t triangles = plane.triangle_count();
  std::vector<float> along_x(size_t(triangles) * 3, 0.f);
  for (uint32_t t = 0; t < triangles; ++t) along_x[3 * t] = 1.f;
  Orientation off, on;
  for (uint64_t seed : {1, 2}) {
    for (int biased = 0; biased < 2; ++biased) {
      moldtex_sim_config c = make_config(256, 256, 40000, seed);
      c.model = MOLDTEX_MODEL_CONTINUOUS;
      c.backend = MOLDTEX_BACKEND_CPU;
      auto sim = create_sim(s.get(), c, default_params());
      ASSERT_TRUE(sim) << LastError();
      moldtex_continuous_params p = turnover_look();
      p.bias_strength = biased ? 4.f : 0.f;
      p.bias_symmetry = 2;
      ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
      ASSERT_EQ(moldtex_sim_set_bias(sim.get(), along_x.data(), along_x.size()), MOLDTEX_OK) << LastError();
      ASSERT_EQ(moldtex_sim_step(sim.get(), 240), MOLDTEX_OK);
      const std::vector<float> rgba = read_rgba(sim.get(), 256, 256);
      std::vector<double> f(256 * 256);
      for (size_t i = 0; i < f.size(); ++i) f[i] = rgba[4 * i];
      const Orientation o = TrailOrientation(f, 256);
      std::printf("seed %d, bias %s: coherence %.3f, trails at %.1f degrees\n", int(seed), biased ? "on" : "off",
                  o.coherence, o.degrees);
      Orientation& sum = biased ? on : off;
      sum.coherence += o.coherence / 2;
      sum.degrees += o.degrees / 2;
    }
  }
  EXPECT_GT(on.coherence, 2 * off.coherence + 0.1);
  EXPECT_NEAR(on.degrees, 0.0, 10.0);
}

// Respawns facing the bias (Fig. 8's sources): agents that never turn (omega 0) and feel
// no bias steering walk straight from where turnover puts them, so their trails show
// their starting headings. Facing the bias (along x): streaks along x, coherent; uniform
// headings: streaks every way, incoherent.
TEST(ContinuousModel, RespawnsFaceTheBias) {
  static const Mesh plane = make_plane(8, 8, 0, 0, 4, 4, [](double x, double y) { return Vec2{x / 4, y / 4}; });
  auto s = create_surface(plane);
  std::vector<float> along_x(size_t(plane.triangle_count()) * 3, 0.f);
  for (uint32_t t = 0; t < plane.triangle_count(); ++t) along_x[3 * t] = 1.f;
  Orientation o[2];
  for (int facing = 0; facing < 2; ++facing) {
    moldtex_sim_config c = make_config(256, 256, 20000, 4);
    c.model = MOLDTEX_MODEL_CONTINUOUS;
    c.backend = MOLDTEX_BACKEND_CPU;
    auto sim = create_sim(s.get(), c, default_params());
    ASSERT_TRUE(sim) << LastError();
    moldtex_continuous_params p = turnover_look();
    p.turn_rate = 0.f;
    p.mean_lifetime = 0.2f;
    p.activation_time = 0.f;
    p.bias_strength = 0.f;
    p.bias_spawn = uint32_t(facing);
    ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
    ASSERT_EQ(moldtex_sim_set_bias(sim.get(), along_x.data(), along_x.size()), MOLDTEX_OK);
    ASSERT_EQ(moldtex_sim_step(sim.get(), 120), MOLDTEX_OK);  // 2 s: ten lifetimes
    const std::vector<float> rgba = read_rgba(sim.get(), 256, 256);
    std::vector<double> f(256 * 256);
    for (size_t i = 0; i < f.size(); ++i) f[i] = rgba[4 * i];
    o[facing] = TrailOrientation(f, 256);
    std::printf("respawn %s: coherence %.3f, trails at %.1f degrees\n", facing ? "along the bias" : "any way",
                o[facing].coherence, o[facing].degrees);
  }
  EXPECT_GT(o[1].coherence, 2 * o[0].coherence + 0.1);
  EXPECT_NEAR(o[1].degrees, 0.0, 10.0);
}

// Found by the fuzzer. A sliver 262144 units long (two copies of one triangle, opposite
// windings) under backward Euler: conjugate gradients stop within a tolerance and left
// -1e-14 where u is near 0; a concentration is never negative (the exact solution of the
// M-matrix system is not), so every texel must read >= 0.
TEST(ContinuousModel, BackwardEulerNeverGivesNegativeConcentrations) {
  Mesh m;
  m.positions = {0, 2.5243549e-29f, 0, 1, 0, 0, -262144, 1.0000304f, 0, 0, 1, 0};
  m.triangles = {0, 1, 2, 0, 2, 1};
  m.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  m.triangle_uvs = m.triangles;
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  size_t negative = 0;
  for (uint64_t seed = 0; seed < 16; ++seed) {  // without the clamp most seeds give some
    moldtex_sim_config c = make_config(10, 11, 1, seed);
    c.model = MOLDTEX_MODEL_CONTINUOUS;
    c.species_count = 2;
    auto sim = create_sim(s.get(), c, default_params());
    ASSERT_TRUE(sim) << LastError();
    moldtex_continuous_params p;
    moldtex_continuous_params_init(&p);
    p.integrator = MOLDTEX_INTEGRATOR_BACKWARD;
    ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
      for (float v : read_rgba(sim.get(), 10, 11)) negative += !(v >= 0.f);
    }
  }
  EXPECT_EQ(negative, 0u);
}

// Found by the fuzzer: a deposit rate of 1e-38 makes U ~ 1e-39, and u / U overflowed a
// float to inf (and 1 / U, the sensing scale, too). Images and statistics stay finite.
TEST(ContinuousModel, ATinyUKeepsImagesAndStatisticsFinite) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(64, 64, 2000, 1);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  moldtex_continuous_params p = turnover_look();
  ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 10), MOLDTEX_OK) << LastError();
  p.deposit_rate = 1e-38f;  // U drops; the concentration laid so far stays
  ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 2), MOLDTEX_OK) << LastError();
  for (float v : read_rgba(sim.get(), 64, 64)) ASSERT_TRUE(std::isfinite(v) && v >= 0.f) << v;
  const moldtex_sim_stats st = get_stats(sim.get());
  EXPECT_TRUE(std::isfinite(st.coverage) && std::isfinite(st.presence)) << st.coverage << " " << st.presence;
}

// Found by the fuzzer: a quad whose two triangles are degenerate, one in UV (a sliver
// 1e-10 wide) and one in 3D (its fourth corner on the first): texels over them cover
// no measurable surface (area 0), which the PDE divided by (NaN everywhere). They are
// no cells now; every value stays finite and the model, on the plane next to it, runs.
TEST(ContinuousModel, TexelsOverDegenerateTrianglesAreNoCells) {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 1e-30f, /* a normal quad beside it: */ 2, 0, 0, 3, 0, 0, 3, 1, 0,
                 2, 1, 0};
  m.triangles = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  // (The sliver runs along the diagonal of the left half, through texel centres.)
  m.uvs = {0, 0, 1e-10f, 0, 0.5f, 0.5f, 0, 0.5f, 0.5f, 0, 1, 0, 1, 1, 0.5f, 1};
  m.triangle_uvs = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(32, 32, 500, 1);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  moldtex_continuous_params p = turnover_look();
  ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 20), MOLDTEX_OK) << LastError();
  double right = 0;
  const std::vector<float> rgba = read_rgba(sim.get(), 32, 32);
  for (size_t i = 0; i < rgba.size(); ++i) {
    ASSERT_TRUE(std::isfinite(rgba[i]) && rgba[i] >= 0.f) << "texel " << i / 4 << ": " << rgba[i];
    if (i % 4 == 0 && (i / 4) % 32 >= 18) right += rgba[i];
  }
  EXPECT_GT(right, 0.0);  // the sound quad got pheromone
  const moldtex_sim_stats st = get_stats(sim.get());
  EXPECT_TRUE(std::isfinite(st.coverage) && std::isfinite(st.u_metric)) << st.coverage << " " << st.u_metric;
}

TEST(ContinuousModel, CheckpointResumesExactly) {
  auto s = create_surface(Torus());
  moldtex_sim_config c = make_config(64, 64, 2000, 5);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.backend = MOLDTEX_BACKEND_CPU;
  moldtex_continuous_params p = turnover_look();
  p.mean_lifetime = 0.3f;
  p.activation_time = 0.1f;
  auto a = create_sim(s.get(), c, default_params());
  auto b = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(a && b) << LastError();
  ASSERT_EQ(moldtex_sim_set_continuous_params(a.get(), &p), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_step(a.get(), 40), MOLDTEX_OK);
  TempDir dir;
  const std::string path = (dir.path / "ck.bin").string();
  ASSERT_EQ(moldtex_sim_save_checkpoint(a.get(), path.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_load_checkpoint(b.get(), path.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(a.get(), 40), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_step(b.get(), 40), MOLDTEX_OK);
  EXPECT_EQ(read_rgba(a.get(), 64, 64), read_rgba(b.get(), 64, 64));
  moldtex_continuous_params back;
  moldtex_continuous_params_init(&back);
  ASSERT_EQ(moldtex_sim_get_continuous_params(b.get(), &back), MOLDTEX_OK);
  EXPECT_EQ(back.mean_lifetime, 0.3f);
}

// Both backends run the model from the same source (shared/continuous.h, shared/pde.h).
// They are not bit-identical (the device's sin, cos, log and exp round differently, and a
// different rounding soon sends one agent another way), so they must agree in character:
// the same 10% as the discretisation checks, over two seeds each.
TEST(ContinuousOpenCl, AgreesWithTheCpuInCharacter) {
  moldtex_sim_config probe = make_config(8, 8, 1, 1);
  std::string why;
  if (!PinBackend(Backend::OpenCl, probe, &why)) {
    if (OpenClRequiredByEnv()) FAIL() << "MOLDTEX_REQUIRE_OPENCL is set: " << why;
    GTEST_SKIP() << why;
  }
  RunSpec r;
  r.seconds = 3.0;
  const Character cpu = Character2(r);
  r.backend = Backend::OpenCl;
  const Character other = Character2(r);
    EXPECT_TRUE(Same(other, cpu, 0.10));
  EXPECT_NEAR(other.mean, 1.0, 0.01) << "the mean concentration is U on every backend";
}

// With no decay and no deposits the PDE only moves pheromone: the total stays (float
// rounding of ~1e-7 per step, random in sign, stays far below 1e-5 over 1000 steps).
class ContinuousBackends : public ::testing::TestWithParam<Backend> {};

TEST_P(ContinuousBackends, MassIsConservedOnEveryBackend) {
  // The torus steps every cell alike; the UV sphere's pole cells take local time steps.
  static const Mesh sphere = make_uv_sphere(64, 32, 1.0);
  for (const Mesh* m : {&Torus(), &sphere}) {
    SCOPED_TRACE(m == &sphere ? "UV sphere" : "torus");
    auto s = create_surface(*m);
    moldtex_sim_config c = make_config(128, 128, 20000, 3);
    c.model = MOLDTEX_MODEL_CONTINUOUS;
    MTX_PIN_BACKEND(c);
    auto sim = create_sim(s.get(), c, default_params());
    ASSERT_TRUE(sim) << LastError();
    moldtex_continuous_params p = turnover_look();
    p.diffusion_rate *= 4;  // several sub-steps, with fine ones at the sphere's poles
    ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK);
    ASSERT_EQ(moldtex_sim_step(sim.get(), 60), MOLDTEX_OK) << LastError();
    p.deposit_rate = 0.f;
    p.decay_rate = 0.f;
    ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
    const double before = get_stats(sim.get()).mean_concentration;
    ASSERT_GT(before, 0);
    ASSERT_EQ(moldtex_sim_step(sim.get(), 1000), MOLDTEX_OK) << LastError();
    EXPECT_NEAR(get_stats(sim.get()).mean_concentration / before, 1.0, 1e-5);
    const std::vector<float> rgba = read_rgba(sim.get(), 128, 128);
    for (size_t i = 0; i < rgba.size(); i += 4) ASSERT_TRUE(rgba[i] >= 0.f && std::isfinite(rgba[i])) << i / 4;
  }
}

MTX_BACKENDS(ContinuousBackends);

}  // namespace
}  // namespace mtx

