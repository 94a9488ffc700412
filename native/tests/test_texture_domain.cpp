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

}  // namespace
}  // namespace mtx
