// The seam correspondence of the texture domain: for every island texel whose stencil
// neighbour (one texel west, east, south or north) is not a texel of the same UV
// island, the texel that really lies there on the surface. Found by walking the surface
// from the texel's centre by the 3D length and direction of that one-texel UV offset, so
// it crosses UV seams whether or not gutter texels fit between the islands: seams on the
// texture border (a torus, a cylinder, a UV sphere's meridian), islands that touch, and
// split vertices. At an open boundary the walk reflects, so the neighbour is a texel on
// the texel's own side (no flow out of the surface).
#pragma once

#include "backends/cpu/thread_pool.h"
#include "domain/texture_domain.h"
#include "surface/surface.h"

namespace moldtex {

// Fills d.seam_texel and d.seam_neighbour (needs d.texel_triangle and d.classes).
// The same lists for any thread count.
void build_seam_neighbours(const Surface& surface, TextureDomain& d, ThreadPool& pool);

// Neighbour `direction` (0 W, 1 E, 2 S, 3 N) of island texel (x, y) read directly from
// the grid, or the texel itself where the grid ends.
inline uint32_t grid_neighbour(const TextureDomain& d, uint32_t x, uint32_t y, int direction) {
  const uint32_t i = y * d.width + x;
  switch (direction) {
    case 0: return x > 0 ? i - 1 : i;
    case 1: return x + 1 < d.width ? i + 1 : i;
    case 2: return y > 0 ? i - d.width : i;
    default: return y + 1 < d.height ? i + d.width : i;
  }
}

}  // namespace moldtex
