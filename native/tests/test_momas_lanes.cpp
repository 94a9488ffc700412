// MoMaS' step in SIMD lanes (agents/momas_lanes.h), white-box: every agent must end each
// step bit for bit where the scalar code (momas_update_agents) puts it, with the same
// marks, at 16 lanes and at 8, whichever way it went: probes inside its triangle or traced
// across edges, a move that stays inside, walks across edges or leaves the lanes for the
// scalar code (open boundaries), turns to either side or on a tie, one species or
// several, texel or surface units (footprints summed and marked in the lanes or lane by
// lane), steps with and without sensing. The comparison sees a rounding only where it
// moves a texel or a decision (an end's weight one ulp off seldom does), so the lanes
// also follow the scalar code's order of operations line by line.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "agents/agents.h"
#include "agents/momas_lanes.h"
#include "agents/momas_rules.h"
#include "domain/texture_domain.h"
#include "walker_fixtures.h"
#include "surface/surface.h"
#include "test_util.h"

namespace mtx {
namespace {

struct LaneCase {
  const char* name;
  Mesh mesh;
};

// Agents at random points of `surface`, of species 0 .. species - 1.
moldtex::Agents RandomAgents(const moldtex::Surface& surface, size_t count, uint32_t species, uint64_t seed) {
  std::mt19937_64 rng(seed);
  moldtex::Agents agents;
  agents.resize(count);
  for (size_t i = 0; i < count; ++i) {
    agents.store(i, RandomWalker(surface, rng));
    agents.species[i] = uint8_t(i % species);
    agents.hunger[i] = 0.25f;
  }
  return agents;
}

// A pheromone field of few levels, a third of it zero: equal readings (ties, turns to a
// random side) as well as strict ones.
std::vector<float> LevelField(size_t texels, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<float> f(texels);
  const float levels[] = {0.f, 0.f, 0.25f, 0.5f, 1.f, 3.f};
  for (float& v : f) v = levels[rng() % 6];
  return f;
}

// Whether two agent sets hold the same bits in every array the step writes.
size_t Differing(const moldtex::Agents& a, const moldtex::Agents& b) {
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const bool same = a.triangle[i] == b.triangle[i] && std::memcmp(&a.b1[i], &b.b1[i], 4) == 0 &&
                      std::memcmp(&a.b2[i], &b.b2[i], 4) == 0 && std::memcmp(&a.hx[i], &b.hx[i], 4) == 0 &&
                      std::memcmp(&a.hy[i], &b.hy[i], 4) == 0 && std::memcmp(&a.hunger[i], &b.hunger[i], 4) == 0;
    differ += !same;
  }
  return differ;
}

// Settings with the given move and sensor (in texels, or in length units where
// length_unit > 0), sensor angle (degrees), substeps, species (species 1 avoids species
// 0) and time step (0: the default).
moldtex::StepSettings Settings(float move, float sensor, float angle, uint32_t substeps, uint32_t species,
                               float length_unit, float time_step) {
  moldtex::StepSettings s;
  s.params = default_params();
  s.params.length_unit = length_unit;
  if (time_step > 0.f) s.params.time_step = time_step;
  s.params.substeps = substeps;
  s.species_count = species;
  for (uint32_t k = 0; k < species; ++k) {
    moldtex_species_params_init(&s.species[k], k);
    s.species[k].movement_speed = move;
    s.species[k].vision_distance = sensor / MTX_VISION_UNIT_TEXELS;
    s.species[k].vision_angle = angle;
    s.species[k].turn_speed = 0.25f + 0.1f * float(k);
  }
  if (species > 1) s.species[1].attraction[0] = -0.5f;
  return s;
}

TEST(MomasLanes, StepsAreTheScalarStepsBitForBit) {
  if (moldtex::momas_lane_width() < 8) GTEST_SKIP() << "neither AVX-512 nor AVX2 here: every step runs the scalar code";
  const LaneCase cases[] = {{"plane", make_quad()},
                            {"uv sphere", make_uv_sphere(32, 16, 1.0)},
                            {"fine uv sphere", make_uv_sphere(128, 64, 1.0)},
                            {"torus", make_torus(24, 12, 1.0, 0.3)},
                            {"flipped torus", FlipEveryOther(make_torus(24, 12, 1.0, 0.3))},
                            {"cube", make_cube()},
                            {"open cylinder", make_open_cylinder(16, 6, 0.5, 1.0)}};
  struct Motion {
    float move, sensor, angle;
    uint32_t substeps, species;
    float texels_per_unit;  // surface units with a length unit of this many texels; 0: texel units
    float time_step;        // 0: the default (1/60 s)
  };
  // Texel units: Jones' geometry, a long sensor, a move over several texels in substeps, a
  // sensor angle of 0 (three probes alike), two species. Surface units (16 lanes only):
  // footprints of 2 x 2 texels, footprints within a texel, two species, and steps without
  // sensing (1/120 s: every other step coasts).
  const Motion motions[] = {{1, 9, 45, 1, 1, 0, 0},       {1, 25, 22.5f, 1, 1, 0, 0}, {6, 9, 45, 3, 1, 0, 0},
                            {2, 12, 0, 1, 1, 0, 0},       {1.5f, 9, 30, 2, 2, 0, 0},  {1, 0.9f, 45, 2, 1, 2, 0},
                            {1, 0.5f, 30, 2, 2, 0.7f, 0}, {1, 0.9f, 45, 2, 1, 2, 1.f / 120}};
  constexpr uint32_t kSide = 256;
  moldtex::ThreadPool pool(2);
  for (unsigned width : {8u, 16u}) {
  if (width > moldtex::momas_lane_width()) continue;
  moldtex::momas_lanes_limit(width);
  size_t in_lanes_all = 0, steps_all = 0;
  for (const LaneCase& lc : cases) {
    const moldtex::Surface surface = moldtex::build_surface(lc.mesh.desc());
    const moldtex::TextureDomain domain = moldtex::build_texture_domain(surface, kSide, kSide, pool);
    const moldtex::mtx_surface_tables tables = moldtex::surface_tables(surface, domain);
    for (const Motion& m : motions) {
      const float unit = float(domain.texel_length) * m.texels_per_unit;
      const moldtex::StepSettings settings = Settings(m.move, m.sensor, m.angle, m.substeps, m.species, unit, m.time_step);
      if (unit > 0.f && width < 16) continue;  // surface units run in 16 lanes only
      const size_t planes = size_t(kSide) * kSide * m.species;
      const std::vector<float> pheromone = LevelField(planes, 5);
      moldtex::Agents scalar = RandomAgents(surface, 4000 + 7, m.species, 3);  // not a multiple of 16
      moldtex::Agents lanes = scalar;
      size_t differ = 0, marks_differ = 0, moved = 0, in_lanes = 0;
      for (uint64_t step = 0; step < 4; ++step) {
        const moldtex::mtx_momas_constants c = moldtex::momas_constants(settings, domain, 9, step);
        ASSERT_TRUE(moldtex::momas_lanes_apply(c, surface.triangle_count())) << lc.name;
        std::vector<uint8_t> scalar_marks(planes, 0), lane_marks(planes, 0);
        const moldtex::Agents before = scalar;
        moldtex::momas_update_agents(tables, c, pheromone.data(), nullptr, scalar_marks.data(), scalar, 0, scalar.size());
        // Lanes over two ranges, as threads take them, the first not a multiple of 16.
        in_lanes += moldtex::momas_lanes_update(tables, c, pheromone.data(), nullptr, lane_marks.data(), lanes, 0, 1000);
        in_lanes += moldtex::momas_lanes_update(tables, c, pheromone.data(), nullptr, lane_marks.data(), lanes, 1000,
                                                lanes.size());
        differ += Differing(scalar, lanes);
        marks_differ += size_t(std::count_if(scalar_marks.begin(), scalar_marks.end(), [&](const uint8_t& v) {
          return v != lane_marks[size_t(&v - scalar_marks.data())];
        }));
        moved += Differing(scalar, before);
        lanes = scalar;  // the next step from the same state, even after a difference
      }
      std::printf("%2u lanes, %-14s move %.1f sensor %4.1f angle %4.1f substeps %u species %u unit %.1f dt %.4f: %5.1f%% in lanes, %zu agent-steps differ, %zu marks differ\n",
                  width, lc.name, m.move, m.sensor, m.angle, m.substeps, m.species, m.texels_per_unit,
                  m.time_step, 100.0 * double(in_lanes) / double(4 * scalar.size()),
                  differ, marks_differ);
      in_lanes_all += in_lanes;
      steps_all += 4 * scalar.size();
      EXPECT_EQ(differ, 0u) << lc.name << ", " << width << " lanes";
      EXPECT_EQ(marks_differ, 0u) << lc.name << ", " << width << " lanes";
      EXPECT_GT(moved, 4u * 3000u) << lc.name;  // the agents did step
    }
  }
  // Both ways exercised: most agent-steps in the lanes, thousands in the scalar code (the
  // tails of ranges, open boundaries, long traces on the fine sphere).
  std::printf("%2u lanes: %zu of %zu agent-steps in lanes\n", width, in_lanes_all, steps_all);
  EXPECT_GT(in_lanes_all, steps_all / 2) << width << " lanes";
  EXPECT_GT(steps_all - in_lanes_all, 10000u) << width << " lanes";
  }
  moldtex::momas_lanes_limit(16);
}

}  // namespace
}  // namespace mtx
