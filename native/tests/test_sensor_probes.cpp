// MoMaS' sensor probes (shared/momas.h, mtx_momas_probe), white-box: a trace that stays
// inside the agent's triangle, or crosses a few edges into neighbours unfolded one after
// another (surface/unfolded_neighbours.h, mtx_trace_unfolded), is located without
// walking. Where each trace ends must be where the walk it stands for ends, on every kind
// of edge: UV seams, folds, poles, neighbours wound the other way round, open boundaries.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "agents/momas_rules.h"
#include "domain/texture_domain.h"
#include "surface/surface.h"
#include "surface/trace_lanes.h"
#include "walker_fixtures.h"
#include "test_util.h"

namespace mtx {
namespace {

struct ProbeCase {
  const char* name;
  Mesh mesh;
};

struct Agreement {
  int probes = 0, unwalked = 0, far = 0, other_triangle = 0;
  double worst = 0;  // texels
};

// Probes of `count` random agents (random triangle, weights and heading; sensor length
// `length` mesh units, sensor angle 30 degrees), located with the tables as given,
// against each trace walked (mtx_walk_until, stopping at open boundaries).
Agreement CompareWithWalks(const moldtex::Surface& surface, const moldtex::mtx_surface_tables& tables,
                           uint32_t side, float length, int count, uint64_t seed) {
  moldtex::mtx_momas_constants k{};
  k.width = k.height = side;
  k.species_count = 1;
  k.sensor_length[0] = length;
  k.sensor_cos[0] = std::cos(0.5236f);
  k.sensor_sin[0] = std::sin(0.5236f);
  std::mt19937_64 rng(seed);
  Agreement a;
  for (int n = 0; n < count; ++n) {
    const moldtex::mtx_walker w = RandomWalker(surface, rng);
    moldtex::mtx_momas_probes p;
    moldtex::mtx_momas_probe(tables, &w, 0, &k, &p);
    for (int i = 0; i < 3; ++i) {
      moldtex::mtx_walker at = w;
      if (i != 1) at.heading = moldtex::mtx_rotate(w.heading, k.sensor_cos[0], i == 0 ? k.sensor_sin[0] : -k.sensor_sin[0]);
      const int crossings = moldtex::mtx_walk_until(surface.frames.data(), surface.adjacency.data(), &at, length, nullptr, 0,
                                                    MTX_BOUNDARY_STOP, nullptr);
      float x, y;
      moldtex::mtx_walker_texel_at(surface.corner_uvs.data(), &at, side, side, &x, &y);
      ++a.probes;
      a.unwalked += crossings >= 0 && crossings <= MTX_UNFOLDED_HOPS;
      const double d = std::max(std::fabs(x - p.x[i]), std::fabs(y - p.y[i]));
      a.worst = std::max(a.worst, d);
      a.far += d > 1e-3;
      a.other_triangle += at.triangle != p.triangle[i];
    }
  }
  return a;
}

// Tolerance: the texel coordinates agree within 0.001 texels (float weights round at
// about 1e-7, times a 512-texel texture, through a few unfoldings, and the walk clamps
// its weights at each crossing), and the trace ends on the same triangle, except
// for a few in 10^4 that end within rounding of a seam edge, where one side's UVs and
// the other's are far apart. Sensor lengths from a fifth of a triangle to three
// triangles, so traces cross zero, one and several edges.
TEST(SensorProbes, TracesEndWhereTheirWalksEnd) {
  const ProbeCase cases[] = {{"uv sphere", make_uv_sphere(32, 16, 1.0)},
                             {"torus", make_torus(24, 12, 1.0, 0.3)},
                             {"cube", make_cube()},
                             {"flipped torus", FlipEveryOther(make_torus(24, 12, 1.0, 0.3))},
                             {"open cylinder", make_open_cylinder(16, 6, 0.5, 1.0)}};
  constexpr uint32_t kSide = 512;
  for (const ProbeCase& c : cases) {
    const moldtex::Surface surface = moldtex::build_surface(c.mesh.desc());
    moldtex::ThreadPool pool(2);
    const moldtex::TextureDomain domain = moldtex::build_texture_domain(surface, kSide, kSide, pool);
    const moldtex::mtx_surface_tables tables = moldtex::surface_tables(surface, domain);
    ASSERT_NE(tables.unfolded, nullptr);
    const double edge = std::sqrt(2.0 * surface.area / surface.triangle_count());  // a typical edge
    for (double lengths : {0.2, 0.7, 3.0}) {
      const Agreement a = CompareWithWalks(surface, tables, kSide, float(lengths * edge), 4000, 11);
      std::printf("%-14s length %.1f edges: %d probes, %d within the unfolded hops, worst %.2e texels, %d far, %d on another triangle\n",
                  c.name, lengths, a.probes, a.unwalked, a.worst, a.far, a.other_triangle);
      EXPECT_EQ(a.far, 0) << c.name << " at " << lengths << " edges: worst " << a.worst << " texels";
      EXPECT_LE(a.other_triangle, a.probes / 2000) << c.name << " at " << lengths << " edges";
    }
  }
}

// The same check fails when the unfolded neighbours are wrong: with the weights at each
// neighbour's corners 1 and 2 swapped (the neighbour mirrored), traces that cross an
// edge end elsewhere. (Tables taken from the wrong edge are not enough: the
// traces then fail their own checks and are walked.)
TEST(SensorProbes, AWrongUnfoldingIsCaught) {
  const Mesh mesh = make_torus(24, 12, 1.0, 0.3);
  moldtex::Surface surface = moldtex::build_surface(mesh.desc());
  for (size_t e = 0; e < surface.unfolded.size(); e += MTX_UNFOLDED_FLOATS)
    for (int m = 0; m < 3; ++m) std::swap(surface.unfolded[e + m], surface.unfolded[e + 3 + m]);
  moldtex::ThreadPool pool(2);
  const moldtex::TextureDomain domain = moldtex::build_texture_domain(surface, 512, 512, pool);
  const double edge = std::sqrt(2.0 * surface.area / surface.triangle_count());
  const Agreement a = CompareWithWalks(surface, moldtex::surface_tables(surface, domain), 512, float(0.7 * edge), 4000, 11);
  std::printf("neighbours mirrored: %d of %d probes far\n", a.far, a.probes);
  EXPECT_GT(a.far, a.probes / 20) << "worst " << a.worst << " texels";
}

// The traces in SIMD lanes (surface/trace_lanes.h) are the scalar traces bit for bit:
// the same ends (triangle and weights, compared as bits) and the same traces left to the
// walk, on every kind of edge, at lengths from a fifth of a triangle to twelve triangles
// (past MTX_UNFOLDED_HOPS crossings, so lanes leave at the limit too), in batches whose
// sizes are not multiples of 16 (part-filled vectors).
TEST(SensorProbes, TraceLanesAreTheScalarTracesBitForBit) {
  if (moldtex::trace_lane_width() < 8) GTEST_SKIP() << "neither AVX-512F nor AVX2 here: the lanes run the scalar code";
  const ProbeCase cases[] = {{"uv sphere", make_uv_sphere(32, 16, 1.0)},
                             {"fine uv sphere", make_uv_sphere(128, 64, 1.0)},
                             {"torus", make_torus(24, 12, 1.0, 0.3)},
                             {"cube", make_cube()},
                             {"flipped torus", FlipEveryOther(make_torus(24, 12, 1.0, 0.3))},
                             {"open cylinder", make_open_cylinder(16, 6, 0.5, 1.0)}};
  for (const ProbeCase& c : cases) {
    const moldtex::Surface surface = moldtex::build_surface(c.mesh.desc());
    const uint32_t triangles = surface.triangle_count();
    const double edge = std::sqrt(2.0 * surface.area / triangles);
    std::mt19937_64 rng(7);
    for (unsigned width : {8u, 16u}) {
    if (width > moldtex::trace_lane_width()) continue;
    int traces = 0, located = 0, walked = 0, differ = 0;
    for (double lengths : {0.2, 0.7, 3.0, 12.0})
      for (size_t batch : {size_t(64), size_t(37), size_t(5)})
        for (int round = 0; round < 40; ++round) {
          moldtex::TraceLanes lanes, scalar;
          lanes.count = batch;
          for (size_t i = 0; i < batch; ++i) {
            const moldtex::mtx_walker w = RandomWalker(surface, rng);
            float s[3], e[3];
            moldtex::mtx_trace_ends(surface.frames.data(), &w, float(lengths * edge), s, e);
            lanes.triangle[i] = w.triangle;
            for (int k = 0; k < 3; ++k) lanes.s[k][i] = s[k], lanes.e[k][i] = e[k];
          }
          scalar = lanes;
          uint8_t in_lanes[moldtex::kTraceLanes], one_by_one[moldtex::kTraceLanes];
          moldtex::trace_lanes_limit(1);
          moldtex::trace_hops_lanes(surface.adjacency.data(), surface.unfolded.data(), triangles, scalar, one_by_one);
          moldtex::trace_lanes_limit(width);
          moldtex::trace_hops_lanes(surface.adjacency.data(), surface.unfolded.data(), triangles, lanes, in_lanes);
          for (size_t i = 0; i < batch; ++i) {
            ++traces;
            bool same = in_lanes[i] == one_by_one[i];
            if (same && in_lanes[i]) {
              same = lanes.triangle[i] == scalar.triangle[i];
              for (int k = 0; k < 3; ++k)
                same = same && std::memcmp(&lanes.e[k][i], &scalar.e[k][i], sizeof(float)) == 0;
            }
            differ += !same;
            located += in_lanes[i] != 0;
            walked += in_lanes[i] == 0;
          }
        }
    std::printf("%-14s %2u lanes, %d traces: %d located, %d left to the walk, %d differ\n", c.name, width, traces,
                located, walked, differ);
    EXPECT_EQ(differ, 0) << c.name << ", " << width << " lanes";
    EXPECT_GT(located, traces / 2) << c.name;  // both outcomes exercised
    EXPECT_GT(walked, 0) << c.name;
    }
  }
  moldtex::trace_lanes_limit(16);
}

}  // namespace
}  // namespace mtx
