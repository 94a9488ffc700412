// The texture domain's lookup tables (domain/texture_domain.h), white-box: what the
// agents' fast paths rely on must hold for every texel, so each table is checked against
// its definition computed the slow way.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "domain/texture_domain.h"
#include "surface/surface.h"
#include "test_util.h"

namespace mtx {
namespace {

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
  struct Case {
    const char* name;
    Mesh mesh;
  };
  const Case cases[] = {{"uv sphere", make_uv_sphere(32, 16, 1.0)},
                        {"torus", make_torus(24, 12, 1.0, 0.3)},
                        {"cube", make_cube()},
                        {"quad", make_quad()}};
  for (const Case& c : cases) {
    moldtex::ThreadPool pool(2);
    const moldtex::Surface surface = moldtex::build_surface(c.mesh.desc());
    const moldtex::TextureDomain d = moldtex::build_texture_domain(surface, 96, 80, pool);
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
        // Its first level is the interior bit the continuous model's stencils use.
        const size_t i = size_t(y) * d.width + x;
        EXPECT_EQ(got >= 1, bool((d.interior_bits[i / 32] >> (i % 32)) & 1u)) << c.name << " texel " << i;
      }
    EXPECT_EQ(mismatches, 0) << c.name;
    // The quad fills the texture: its centre reaches 39 texels (80 / 2 - 1).
    if (std::string(c.name) == "quad") {
      EXPECT_EQ(deepest, 39);
    }
    std::printf("  %s: deepest reach %d texels\n", c.name, deepest);
  }
}

}  // namespace
}  // namespace mtx
