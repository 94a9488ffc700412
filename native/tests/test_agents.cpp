// Agents: spawning, movement lengths in 3D, staying valid over long runs.
#include <algorithm>
#include <numeric>
#include <random>

#include "agents/agents.h"
#include "backends/cpu/thread_pool.h"
#include "test_util.h"

namespace mtx {
namespace {

double TexelLength(moldtex_surface s, uint32_t w, uint32_t h) {
  moldtex_surface_info info;
  moldtex_surface_info_init(&info);
  EXPECT_EQ(moldtex_surface_get_info(s, &info), MOLDTEX_OK) << LastError();
  // Header, Units: one texel = sqrt(surface area / (UV area * width * height)).
  return std::sqrt(info.area / (info.uv_area * double(w) * h));
}

// Agents that keep their heading: no steering at all.
moldtex_sim_params StraightParams(float speed) {
  moldtex_sim_params p = default_params();
  p.movement_speed = speed;
  p.turn_speed = 0.0f;
  p.vision_angle = 0.0f;
  return p;
}

// 4-sigma binomial band around an expected fraction p for n draws.
void ExpectFraction(double got, double p, size_t n, const std::string& what) {
  const double sigma = std::sqrt(p * (1 - p) / double(n));
  EXPECT_NEAR(got, p, 4 * sigma) << what << " (4 sigma = " << 4 * sigma << ")";
}

// ---- movement lengths -----------------------------------------------------------------

// read_agents does not promise a stable agent order across steps (the CPU backend
// regroups agents in memory every few steps), so an agent is followed by running it
// alone: one simulation per agent, the seed picks where it spawns and its heading.
struct Move {
  Vec3 from, to;
};
std::vector<Move> SingleAgentMoves(moldtex_surface s, uint32_t w, uint32_t h,
                                   const moldtex_sim_params& p, int count, uint32_t steps) {
  std::vector<Move> moves;
  for (int seed = 0; seed < count; ++seed) {
    auto sim = create_sim(s, make_config(w, h, 1, 1000 + seed), p);
    EXPECT_TRUE(sim) << LastError();
    if (!sim) break;
    const auto a = read_agents(sim.get(), 1);
    EXPECT_EQ(moldtex_sim_step(sim.get(), steps), MOLDTEX_OK) << LastError();
    const auto b = read_agents(sim.get(), 1);
    if (a.size() != 1 || b.size() != 1) break;
    moves.push_back({evaluate_position(s, a[0]), evaluate_position(s, b[0])});
  }
  return moves;
}

TEST(AgentMotion, StepLengthIn3DIgnoresUvDistortion) {
  // momas-paper.md 2.2 (length rescaling): a step is movement_speed texels of true 3D
  // length wherever the UV map stretches. The distorted plane's du/dx varies 10x and
  // its 3D/UV aspect is 8:1. Tolerance 1e-3 relative (float positions).
  const Mesh m = make_distorted_plane(4);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 128, H = 128;
  const double step = 2.0 * TexelLength(s.get(), W, H);
  int checked = 0, low = 0, high = 0;
  for (const Move& mv : SingleAgentMoves(s.get(), W, H, StraightParams(2.0f), 400, 1)) {
    const double margin = 3 * step;  // away from the boundary: no bounce
    const Vec3& p0 = mv.from;
    if (p0[0] < margin || p0[0] > 8 - margin || p0[1] < margin || p0[1] > 1 - margin) continue;
    ++checked;
    low += p0[0] < 2.0;   // du/dx 1/4 .. 1/2 of the mean
    high += p0[0] > 6.0;  // du/dx 1.5 .. 2.5x the mean
    ASSERT_NEAR(norm(sub(mv.to, p0)), step, 1e-3 * step) << "agent from " << Str(p0);
  }
  EXPECT_GT(checked, 250);
  EXPECT_GT(low, 40);
  EXPECT_GT(high, 40);
}

TEST(AgentMotion, SpeedIsTexelsPerStepWhateverTheTimeStep) {
  // Header: movement_speed is texels travelled per step; time_step scales turning,
  // evaporation and diffusion, not the step length. Doubling time_step keeps the
  // step at speed * texel length (1e-3 relative).
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 64, H = 64;
  const double step = 1.5 * TexelLength(s.get(), W, H);
  moldtex_sim_params p = StraightParams(1.5f);
  p.time_step = 1.0f / 30.0f;
  int checked = 0;
  for (const Move& mv : SingleAgentMoves(s.get(), W, H, p, 50, 1)) {
    const Vec3& p0 = mv.from;
    if (p0[0] < 0.1 || p0[0] > 0.9 || p0[1] < 0.1 || p0[1] > 0.9) continue;
    ++checked;
    ASSERT_NEAR(norm(sub(mv.to, p0)), step, 1e-3 * step) << "agent from " << Str(p0);
  }
  EXPECT_GT(checked, 20);
}

TEST(AgentMotion, StraightAgentsWalkStraightLinesOnAPlane) {
  // With no steering, an agent's walk is a straightest path: on a plane, twenty steps
  // cover 20 step lengths as the crow flies, also when they cross from one triangle to
  // a neighbour with a very different UV stretch (the coarse 16 x 2 distorted plane:
  // the two rows' dv/dy differ 1.7x), i.e. the heading is carried in 3D, not kept
  // constant in UV. 1e-3 relative.
  const Mesh m = make_distorted_plane(2);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 128, H = 128;
  const double step = 0.5 * TexelLength(s.get(), W, H);
  int checked = 0;
  for (const Move& mv : SingleAgentMoves(s.get(), W, H, StraightParams(0.5f), 200, 20)) {
    const double margin = 21 * step;
    const Vec3& p0 = mv.from;
    if (p0[0] < margin || p0[0] > 8 - margin || p0[1] < margin || p0[1] > 1 - margin) continue;
    ++checked;
    ASSERT_NEAR(norm(sub(mv.to, p0)), 20 * step, 1e-3 * 20 * step) << "agent from " << Str(p0);
  }
  EXPECT_GT(checked, 60);
}

TEST(AgentMotion, StepLengthOnCurvedClosedMeshes) {
  // On the sphere a step of a few texels crosses at most a few triangles; its 3D
  // chord is the step length up to the bend at edges: chord >= 0.995 step (the
  // largest dihedral turn on a 64 x 32 sphere is ~6 deg) and never longer.
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 256, H = 256;
  const double step = 2.0 * TexelLength(s.get(), W, H);
  for (const Move& mv : SingleAgentMoves(s.get(), W, H, StraightParams(2.0f), 200, 1)) {
    const double d = norm(sub(mv.to, mv.from));
    ASSERT_LE(d, step * (1 + 1e-3)) << "agent from " << Str(mv.from);
    ASSERT_GE(d, step * 0.995) << "agent from " << Str(mv.from);
  }
}

TEST(AgentMotion, ReadAgentsIsAStableSetWithoutSteps) {
  // Reading twice without stepping gives the same agents in the same order.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(64, 64, 3000, 2), default_params());
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 5), MOLDTEX_OK);
  const auto a = read_agents(sim.get(), 3000), b = read_agents(sim.get(), 3000);
  ASSERT_EQ(a.size(), 3000u);
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(moldtex_surface_point)));
}

// ---- spawning ---------------------------------------------------------------------------

TEST(AgentSpawn, UniformBy3DArea) {
  // Header: agents spawn uniformly by area. On the two-density strip region A (x < 1)
  // has 1/4 of the 3D area but 8/9 of the triangles and 1/2 of the UV area, so
  // spawning by index or by UV area is caught. Uniform barycentrics are checked by
  // the x histogram (the region-B triangles are 3 units long). 4-sigma binomial.
  const Mesh m = make_two_density_strip();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t N = 200000;
  auto sim = create_sim(s.get(), make_config(64, 64, N, 1234), default_params());
  ASSERT_TRUE(sim) << LastError();
  const auto pts = read_agents(sim.get(), N);
  ASSERT_EQ(pts.size(), N);
  size_t in_a = 0;
  std::vector<size_t> xbins(8, 0), ybins(4, 0);
  for (const auto& p : pts) {
    ASSERT_TRUE(ValidPoint(p, m.triangle_count()));
    const Vec3 q = evaluate_position(s.get(), p);
    in_a += q[0] < 1.0;
    xbins[std::min(7, int(q[0] / 0.5))]++;
    ybins[std::min(3, int(q[1] / 0.25))]++;
  }
  ExpectFraction(double(in_a) / N, 0.25, N, "fraction in the small-triangle region");
  for (int b = 0; b < 8; ++b)
    ExpectFraction(double(xbins[b]) / N, 1.0 / 8, N, "x bin " + std::to_string(b));
  for (int b = 0; b < 4; ++b)
    ExpectFraction(double(ybins[b]) / N, 1.0 / 4, N, "y bin " + std::to_string(b));
}

TEST(AgentSpawn, UniformOnTheSphereByArea) {
  // Lat-long triangles shrink towards the poles; uniform-by-area spawning puts
  // (1 - cos 30deg) / 2 = 6.7% of agents above latitude 60 deg (index-uniform
  // spawning would put ~1/6 there). 4-sigma binomial plus 0.3% for the polyhedron.
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t N = 100000;
  auto sim = create_sim(s.get(), make_config(64, 64, N, 77), default_params());
  ASSERT_TRUE(sim) << LastError();
  const auto pts = read_agents(sim.get(), N);
  ASSERT_EQ(pts.size(), N);
  size_t cap = 0, north = 0;
  for (const auto& p : pts) {
    const Vec3 q = evaluate_position(s.get(), p);
    cap += q[2] > std::sin(60 * kPi / 180) * norm(q);
    north += q[2] > 0;
  }
  const double p_cap = (1 - std::cos(30 * kPi / 180)) / 2;
  EXPECT_NEAR(double(cap) / N, p_cap, 4 * std::sqrt(p_cap * (1 - p_cap) / N) + 0.003);
  ExpectFraction(double(north) / N, 0.5, N, "northern hemisphere");
}

TEST(AgentSpawn, HeadingsCoverTheFullCircle) {
  // Spawn headings cover the full circle (the reference code used only [0, pi)):
  // one straight step on the UV = xy quad shows an agent's heading; each 45-degree
  // sector gets 1/8 of the agents (4-sigma binomial over 2000 single-agent runs).
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::vector<size_t> sectors(8, 0);
  size_t n = 0;
  for (const Move& mv : SingleAgentMoves(s.get(), 64, 64, StraightParams(2.0f), 2000, 1)) {
    const Vec3& p0 = mv.from;
    if (p0[0] < 0.05 || p0[0] > 0.95 || p0[1] < 0.05 || p0[1] > 0.95) continue;
    const Vec3 d = sub(mv.to, p0);
    double a = std::atan2(d[1], d[0]);
    if (a < 0) a += 2 * kPi;
    sectors[std::min(7, int(a / (kPi / 4)))]++;
    ++n;
  }
  ASSERT_GT(n, 1500u);
  for (int k = 0; k < 8; ++k)
    ExpectFraction(double(sectors[k]) / n, 1.0 / 8, n, "sector " + std::to_string(k));
}

// ---- long runs ----------------------------------------------------------------------------

struct LongRunCase {
  const char* name;
  Mesh mesh;
  uint32_t width, height, agents, steps;
  float speed;
  std::function<void(const Vec3&)> bounds;
};

void LongRun(const LongRunCase& c) {
  SCOPED_TRACE(c.name);
  auto s = create_surface(c.mesh);
  ASSERT_TRUE(s) << LastError();
  const SurfaceIndex index(c.mesh);
  moldtex_sim_params p = default_params();
  p.movement_speed = c.speed;
  auto sim = create_sim(s.get(), make_config(c.width, c.height, c.agents, 2024), p);
  ASSERT_TRUE(sim) << LastError();
  for (uint32_t done = 0; done < c.steps; done += 10) {
    ASSERT_EQ(moldtex_sim_step(sim.get(), 10), MOLDTEX_OK) << LastError();
    const auto pts = read_agents(sim.get(), c.agents);
    ASSERT_EQ(pts.size(), c.agents);
    for (uint32_t i = 0; i < c.agents; ++i) {
      ASSERT_TRUE(ValidPoint(pts[i], c.mesh.triangle_count()))
          << "agent " << i << " after " << done + 10 << " steps";
      const Vec3 q = evaluate_position(s.get(), pts[i]);
      ASSERT_LE(index.distance(q), 1e-5) << "agent " << i << " off the surface at " << Str(q);
      if (c.bounds) c.bounds(q);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  const auto st = get_stats(sim.get());
  EXPECT_EQ(st.step_count, c.steps);
  EXPECT_EQ(st.agent_count, c.agents);
  EXPECT_GE(st.coverage, 0.0);
  EXPECT_LE(st.coverage, 1.0);
}

auto InUnitSquare = [](const Vec3& q) {
  ASSERT_GE(q[0], -1e-6) << Str(q);
  ASSERT_LE(q[0], 1 + 1e-6) << Str(q);
  ASSERT_GE(q[1], -1e-6) << Str(q);
  ASSERT_LE(q[1], 1 + 1e-6) << Str(q);
  ASSERT_NEAR(q[2], 0.0, 1e-7) << Str(q);
};

TEST(AgentLongRun, PlaneWithBoundary100kAgentSteps) {
  // 1000 agents x 100 steps on an 8 x 8 plane: every agent stays in a valid triangle
  // with valid barycentrics and inside the plane's bounds (bounced, never escaped).
  LongRun({"plane", make_plane(8, 8, 0, 0, 1, 1, [](double x, double y) { return Vec2{x, y}; }),
           64, 64, 1000, 100, 1.5f, InUnitSquare});
}

TEST(AgentLongRun, OpenCylinder100kAgentSteps) {
  LongRun({"cylinder", make_open_cylinder(32, 8, 0.5, 1.0), 64, 64, 1000, 100, 1.5f,
           [](const Vec3& q) {
             ASSERT_GE(q[2], -1e-6) << Str(q);
             ASSERT_LE(q[2], 1 + 1e-6) << Str(q);
           }});
}

TEST(AgentLongRun, FastAgentsBounceManyTimesPerStep) {
  // Hard-limit speed (64 texels) on a 16 x 16 texture: each step is 4 plane widths,
  // so every step bounces several times.
  LongRun({"fast plane", make_quad(), 16, 16, 1000, 100, 64.0f, InUnitSquare});
}

TEST(AgentLongRun, ClosedMeshesWithSeams) {
  // Cube, sphere and torus: agents cross UV seams thousands of times.
  LongRun({"cube", make_cube(), 64, 64, 1000, 100, 2.0f, nullptr});
  LongRun({"sphere", make_uv_sphere(32, 16, 1.0), 64, 64, 1000, 100, 2.0f, nullptr});
  LongRun({"torus", make_torus(24, 12, 1.0, 0.35), 64, 64, 1000, 100, 2.0f, nullptr});
}

TEST(AgentLongRun, DistortedPlaneHighSpeed) {
  LongRun({"distorted", make_distorted_plane(2), 64, 64, 1000, 100, 16.0f, [](const Vec3& q) {
             ASSERT_GE(q[0], -1e-5) << Str(q);
             ASSERT_LE(q[0], 8 + 1e-5) << Str(q);
             ASSERT_GE(q[1], -1e-6) << Str(q);
             ASSERT_LE(q[1], 1 + 1e-6) << Str(q);
           }});
}

// ---- read_agents contract -----------------------------------------------------------------

TEST(AgentRead, WritesMinOfCapacityAndAgentCount) {
  // Header: writes min(capacity, agent_count) points — never past either.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(32, 32, 100, 1), default_params());
  ASSERT_TRUE(sim) << LastError();
  const moldtex_surface_point sentinel{0xDEADBEEFu, {7.0f, 7.0f, 7.0f}};
  std::vector<moldtex_surface_point> small(20, sentinel);
  ASSERT_EQ(moldtex_sim_read_agents(sim.get(), small.data(), 10), MOLDTEX_OK) << LastError();
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(ValidPoint(small[i], 2));
  for (int i = 10; i < 20; ++i) EXPECT_EQ(small[i].triangle, 0xDEADBEEFu) << "wrote past capacity";
  std::vector<moldtex_surface_point> big(150, sentinel);
  ASSERT_EQ(moldtex_sim_read_agents(sim.get(), big.data(), 150), MOLDTEX_OK) << LastError();
  for (int i = 0; i < 100; ++i) EXPECT_TRUE(ValidPoint(big[i], 2));
  for (int i = 100; i < 150; ++i) EXPECT_EQ(big[i].triangle, 0xDEADBEEFu) << "wrote past agent_count";
  // The first 10 are the same agents in both reads.
  EXPECT_EQ(0, std::memcmp(small.data(), big.data(), 10 * sizeof(moldtex_surface_point)));
}

// ---- regrouping agents in memory -----------------------------------------------------------

// The regrouping (a counting sort, parallel since 2026-12-05) must give the one order of
// a stable sort by key, whatever the thread count: agents' random streams are keyed by
// their index, so any other order would change results with the thread count. 300,000
// agents with random triangles among 5,000 (several runs of 65,536 per thread, many ties),
// every field of each agent tagged by its original index, sorted twice in a row (the
// second reuses the scratch, and sorts an already sorted list), against std::stable_sort.
TEST(AgentRegroup, ParallelCountingSortIsTheStableSortForAnyThreadCount) {
  constexpr size_t kAgents = 300000;
  constexpr uint32_t kTriangles = 5000;
  moldtex::Agents original;
  original.resize(kAgents);
  std::mt19937 rng(7);
  for (size_t i = 0; i < kAgents; ++i) {
    original.triangle[i] = uint32_t(rng() % kTriangles);
    const float tag = float(i);
    original.b1[i] = tag;
    original.b2[i] = tag + 0.5f;
    original.hx[i] = -tag;
    original.hy[i] = tag * 2;
    original.species[i] = uint8_t(i % 251);
    original.hunger[i] = tag + 0.25f;
    original.batch[i] = uint16_t(i % 65521);
    original.clock[i] = tag + 1;
    original.age[i] = tag + 2;
    original.exposure[i] = tag + 3;
    original.threshold[i] = tag + 4;
  }
  std::vector<size_t> order(kAgents);
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return original.triangle[a] < original.triangle[b]; });
  for (unsigned threads : {1u, 2u, 3u, 5u}) {
    moldtex::ThreadPool pool(threads);
    moldtex::Agents a = original;
    moldtex::TileSortScratch scratch;
    for (int pass = 0; pass < 2; ++pass) {
      moldtex::sort_by_triangle(kTriangles, a, scratch, pool);
      ASSERT_EQ(a.size(), kAgents);
      for (size_t k = 0; k < kAgents; ++k) {
        const size_t i = order[k];
        ASSERT_EQ(a.triangle[k], original.triangle[i]) << threads << " threads, pass " << pass << ", slot " << k;
        ASSERT_EQ(a.b1[k], original.b1[i]) << threads << " threads, slot " << k;
        ASSERT_EQ(a.b2[k], original.b2[i]);
        ASSERT_EQ(a.hx[k], original.hx[i]);
        ASSERT_EQ(a.hy[k], original.hy[i]);
        ASSERT_EQ(a.species[k], original.species[i]);
        ASSERT_EQ(a.hunger[k], original.hunger[i]);
        ASSERT_EQ(a.batch[k], original.batch[i]);
        ASSERT_EQ(a.clock[k], original.clock[i]);
        ASSERT_EQ(a.age[k], original.age[i]);
        ASSERT_EQ(a.exposure[k], original.exposure[i]);
        ASSERT_EQ(a.threshold[k], original.threshold[i]);
      }
    }
  }
}

}  // namespace
}  // namespace mtx
