// The texture domain's lookup tables (domain/texture_domain.h), white-box: what the
// agents' fast paths rely on must hold for every texel, so each table is checked against
// its definition computed the slow way.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <cstring>
#include <random>
#include <vector>

#include "domain/texture_domain.h"
#include "agents/momas_rules.h"
#include "surface/surface.h"
#include "test_util.h"

namespace mtx {
namespace {

// A named mesh with its surface and texture domain.
struct Textured {
  const char* name;
  moldtex::Surface surface;
  moldtex::TextureDomain domain;
  Textured(const char* n, const Mesh& mesh, uint32_t width, uint32_t height) : name(n) {
    moldtex::ThreadPool pool(2);
    surface = moldtex::build_surface(mesh.desc());
    domain = moldtex::build_texture_domain(surface, width, height, pool);
  }
};

// The interior reach of texel (x, y) by its definition: the largest r such that the
// (2r + 1)^2 block around it lies in the texture and holds texels of its own island only.
int ReachByDefinition(const moldtex::TextureDomain& d, int x, int y) {
  const int w = int(d.width), h = int(d.height);
  const int32_t island = d.texel_island[size_t(y) * d.width + x];
  if (island < 0) return 0;
  int r = 0;
  for (;; ++r) {
    const int n = r + 1;  // can the block grow to radius n?
    if (x - n < 0 || y - n < 0 || x + n >= w || y + n >= h || n > 255) return r;
    for (int dy = -n; dy <= n; ++dy)
      for (int dx = -n; dx <= n; ++dx)
        if ((std::abs(dx) == n || std::abs(dy) == n) && d.texel_island[size_t(y + dy) * d.width + (x + dx)] != island)
          return r;
  }
}

// A footprint box within a texel's reach is marked and read without a test per texel
// (mtx_box_within_island), so a reach one too large would let a deposit land on another
// island or a gutter texel. Checked on meshes with one island touching the texture border
// (UV sphere, torus), six islands with gutters between (cube), and a plane filling the
// texture, at a size where blocks of many radii occur.
TEST(TextureDomain, InteriorReachIsTheLargestBlockOfOneIsland) {
  const Textured cases[] = {{"uv sphere", make_uv_sphere(32, 16, 1.0), 96, 80},
                            {"torus", make_torus(24, 12, 1.0, 0.3), 96, 80},
                            {"cube", make_cube(), 96, 80},
                            {"quad", make_quad(), 96, 80}};
  for (const Textured& c : cases) {
    const moldtex::TextureDomain& d = c.domain;
    ASSERT_EQ(d.interior_reach.size(), d.texel_count()) << c.name;
    int mismatches = 0, deepest = 0;
    for (int y = 0; y < int(d.height); ++y)
      for (int x = 0; x < int(d.width); ++x) {
        const int expected = ReachByDefinition(d, x, y);
        const int got = d.interior_reach[size_t(y) * d.width + x];
        deepest = std::max(deepest, got);
        if (got != expected && ++mismatches <= 5)
          ADD_FAILURE() << c.name << ": texel (" << x << ", " << y << ") reach " << got << ", by definition "
                        << expected;
        // The interior bit the continuous model's stencils use (derived from the reach):
        // set where the 3 x 3 block is one island.
        const size_t i = size_t(y) * d.width + x;
        EXPECT_EQ(expected >= 1, bool((d.interior_bits[i / 32] >> (i % 32)) & 1u)) << c.name << " texel " << i;
      }
    EXPECT_EQ(mismatches, 0) << c.name;
    // The quad fills the texture: its centre reaches 39 texels (80 / 2 - 1).
    if (std::string(c.name) == "quad") {
      EXPECT_EQ(deepest, 39);
    }
    std::printf("  %s: deepest reach %d texels\n", c.name, deepest);
  }
}


// The footprints' fast path (a box within the interior reach: no test per texel) must
// mark the same texels and read the same value, bit for bit, as the general path that
// tests each texel. Both run here on the same random points: on a cube (six islands
// with gutters between them) and a torus (seams on the texture border), with footprints
// of 2-3 and of 5-6 texels a side, and a random pheromone plane.
TEST(TextureDomain, FootprintsWithinTheReachMatchTheGeneralPath) {
  const uint32_t W = 128, H = 128;
  const Textured cases[] = {{"cube", make_cube(), W, H}, {"torus", make_torus(24, 12, 1.0, 0.3), W, H}};
  for (const Textured& c : cases) {
    const moldtex::Surface& surface = c.surface;
    const moldtex::TextureDomain& d = c.domain;
    const moldtex::mtx_surface_tables fast = moldtex::surface_tables(surface, d);  // as the agents get them
    moldtex::mtx_surface_tables general = fast;
    general.interior_reach = nullptr;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<float> uniform(0.f, 1.f);
    std::vector<float> pheromone(d.texel_count());
    for (float& v : pheromone) v = uniform(rng);
    for (float texels_per_unit : {2.5f, 5.5f}) {
      moldtex::mtx_momas_constants k{};
      k.width = W;
      k.height = H;
      k.species_count = 1;
      k.attraction[0] = 1.f;
      k.surface_mode = 1;
      k.length_unit = float(texels_per_unit * d.texel_length);
      std::vector<uint8_t> marks_fast(d.texel_count()), marks_general(d.texel_count());
      int points = 0, fast_points = 0, mark_differences = 0, reading_differences = 0;
      for (int n = 0; n < 3000; ++n) {
        moldtex::mtx_walker w{};
        w.triangle = uint32_t(rng() % surface.triangle_count());
        float b1 = uniform(rng), b2 = uniform(rng);
        if (b1 + b2 > 1.f) {
          b1 = 1.f - b1;
          b2 = 1.f - b2;
        }
        w.bary[0] = 1.f - b1 - b2;
        w.bary[1] = b1;
        w.bary[2] = b2;
        w.heading = {1.f, 0.f};
        float x, y;
        const uint32_t texel = moldtex::mtx_walker_texel_at(fast.corner_uvs, &w, W, H, &x, &y);
        ++points;
        std::fill(marks_fast.begin(), marks_fast.end(), 0);
        std::fill(marks_general.begin(), marks_general.end(), 0);
        moldtex::mtx_mark_footprint(fast, nullptr, marks_fast.data(), &w, texel, x, y, &k);
        moldtex::mtx_mark_footprint(general, nullptr, marks_general.data(), &w, texel, x, y, &k);
        mark_differences += marks_fast != marks_general;
        const float a = moldtex::mtx_sense_footprint(fast, pheromone.data(), nullptr, &w, texel, 0, &k);
        const float b = moldtex::mtx_sense_footprint(general, pheromone.data(), nullptr, &w, texel, 0, &k);
        reading_differences += std::memcmp(&a, &b, sizeof a) != 0;
        moldtex::mtx_footprint box;
        if (moldtex::mtx_footprint_box(fast, &w, &k, &box) &&
            moldtex::mtx_box_within_island(fast, texel, box.x0, box.x1, box.y0, box.y1, box.island, &k))
          ++fast_points;
      }
      std::printf("  %s, %.1f texels per unit: %d of %d points on the fast path\n", c.name, texels_per_unit,
                  fast_points, points);
      EXPECT_EQ(mark_differences, 0) << c.name << " " << texels_per_unit;
      EXPECT_EQ(reading_differences, 0) << c.name << " " << texels_per_unit;
      // Most points lie away from seams: the fast path is what runs (else this test
      // would compare the general path with itself).
      EXPECT_GT(fast_points, points / 2) << c.name << " " << texels_per_unit;
    }
  }
}

// Many small triangles, each its own UV island, scattered over the texture and past its
// border, overlapping one another, some under a texel across (they cover no texel
// centre, so no texel is theirs): the hardest case for TextureDomain::sole_reach.
Mesh ScatteredIslands(int count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> uniform(0.f, 1.f);
  Mesh m;
  for (int t = 0; t < count; ++t) {
    const float u = -0.1f + 1.2f * uniform(rng), v = -0.1f + 1.2f * uniform(rng);
    const float size = (t % 4 == 0 ? 0.005f : 0.06f) * (0.3f + uniform(rng));  // every 4th under a texel of 64
    for (int k = 0; k < 3; ++k) {
      m.positions.insert(m.positions.end(), {float(t) + uniform(rng), uniform(rng), float(k == 2) + uniform(rng)});
      m.triangles.push_back(uint32_t(3 * t + k));
      m.uvs.push_back(u + size * uniform(rng));
      m.uvs.push_back(v + size * uniform(rng));
    }
  }
  return m;
}

// MoMaS' lanes take a footprint box within a texel's sole reach as all of the lane's
// island without looking up the texel's island (agents/momas_lanes16.cpp): that holds if
// every point of any triangle that lies in a texel with a sole reach is of the texel's
// island, and if the reach's block holds only such texels of that island. Checked by
// definition: random points (a tenth on edges or corners) of every triangle of a UV
// sphere, a torus, a cube (six islands, gutters between) and scattered, overlapping
// islands; and on one island the sole reach is the interior reach plus one.
TEST(TextureDomain, SoleReachIsOnlyWhereNoOtherIslandReaches) {
  const Textured cases[] = {{"uv sphere", make_uv_sphere(32, 16, 1.0), 96, 80},
                            {"torus", make_torus(24, 12, 1.0, 0.3), 96, 80},
                            {"cube", make_cube(), 96, 80},
                            {"scattered islands", ScatteredIslands(400, 3), 64, 64}};
  for (const Textured& c : cases) {
    const moldtex::Surface& surface = c.surface;
    const moldtex::TextureDomain& d = c.domain;
    ASSERT_EQ(d.sole_reach.size(), d.texel_count()) << c.name;
    const bool one_island = *std::max_element(surface.island.begin(), surface.island.end()) == 0;
    size_t island_texels = 0, sole_texels = 0, block_errors = 0;
    for (int y = 0; y < int(d.height); ++y)
      for (int x = 0; x < int(d.width); ++x) {
        const size_t i = size_t(y) * d.width + x;
        const int sole = d.sole_reach[i];
        island_texels += d.texel_island[i] >= 0;
        sole_texels += sole > 0;
        if (d.texel_island[i] < 0) {
          EXPECT_EQ(sole, 0) << c.name << " texel " << i << " is no island's";
          continue;
        }
        if (one_island) {
          EXPECT_EQ(sole, std::min(d.interior_reach[i] + 1, 255)) << c.name << " texel " << i;
        }
        // The block of radius sole - 1: inside the texture, texels of the same island with
        // a sole reach only.
        for (int dy = -(sole - 1); dy <= sole - 1; ++dy)
          for (int dx = -(sole - 1); dx <= sole - 1; ++dx) {
            const int bx = x + dx, by = y + dy;
            const bool ok = bx >= 0 && by >= 0 && bx < int(d.width) && by < int(d.height) &&
                            d.texel_island[size_t(by) * d.width + bx] == d.texel_island[i] &&
                            d.sole_reach[size_t(by) * d.width + bx] > 0;
            block_errors += !ok;
          }
      }
    EXPECT_EQ(block_errors, 0u) << c.name;
    // Points of every triangle: where one lies in a texel with a sole reach, the texel is
    // of the triangle's island (the texel found as the lanes find it: x = u W in float,
    // truncated and clamped).
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<float> uniform(0.f, 1.f);
    size_t points = 0, on_sole = 0, wrong = 0;
    for (uint32_t t = 0; t < surface.triangle_count(); ++t) {
      for (int n = 0; n < 200; ++n) {
        float b[3] = {uniform(rng), uniform(rng), uniform(rng)};
        if (n % 10 == 0) b[n / 10 % 3] = 0.f;                      // on an edge
        if (n % 40 == 0) b[(n / 40 + 1) % 3] = 0.f;                // at a corner
        const float sum = b[0] + b[1] + b[2];
        if (!(sum > 0.f)) continue;
        for (float& w : b) w /= sum;
        moldtex::mtx_walker w{};
        w.triangle = t;
        w.bary[0] = b[0];
        w.bary[1] = b[1];
        w.bary[2] = b[2];
        float px, py;
        const uint32_t texel = moldtex::mtx_walker_texel_at(surface.corner_uvs.data(), &w, d.width, d.height, &px, &py);
        ++points;
        if (d.sole_reach[texel] == 0) continue;
        ++on_sole;
        if (d.texel_island[texel] != int32_t(surface.island[t]) && ++wrong <= 5)
          ADD_FAILURE() << c.name << ": a point of triangle " << t << " (island " << surface.island[t]
                        << ") lies in texel " << texel << " of island " << d.texel_island[texel]
                        << " with sole reach " << int(d.sole_reach[texel]);
      }
    }
    EXPECT_EQ(wrong, 0u) << c.name;
    std::printf("  %s: %zu of %zu island texels their island's alone; %zu of %zu points in them\n", c.name,
                sole_texels, island_texels, on_sole, points);
    // Not vacuous: most island texels are their island's alone, even among the scattered
    // islands (their overlaps and near misses leave the rest).
    EXPECT_GT(double(sole_texels), (one_island ? 0.999 : (std::string(c.name) == "cube" ? 0.95 : 0.3)) *
                                       double(island_texels))
        << c.name;
  }
}

}  // namespace
}  // namespace mtx
