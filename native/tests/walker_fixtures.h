// Fixtures of the white-box tests of the agents' geometry (test_sensor_probes.cpp,
// test_momas_lanes.cpp): a mesh with mixed winding, a random walker on a surface.
#pragma once
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>

#include "surface/surface.h"
#include "test_util.h"

namespace mtx {

// The mesh with every other triangle wound the other way round (corners 1 and 2 and
// their UVs swapped), so half the edges join neighbours of opposite winding.
inline Mesh FlipEveryOther(Mesh m) {
  const bool shared_uvs = !m.triangle_uvs.empty();
  for (uint32_t t = 1; t < m.triangle_count(); t += 2) {
    std::swap(m.triangles[3 * t + 1], m.triangles[3 * t + 2]);
    if (shared_uvs) {
      std::swap(m.triangle_uvs[3 * t + 1], m.triangle_uvs[3 * t + 2]);
    } else {
      std::swap(m.uvs[6 * t + 2], m.uvs[6 * t + 4]);
      std::swap(m.uvs[6 * t + 3], m.uvs[6 * t + 5]);
    }
  }
  return m;
}

// A walker at a uniformly random point of a random non-degenerate triangle, heading in a
// uniformly random direction.
inline moldtex::mtx_walker RandomWalker(const moldtex::Surface& surface, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> uniform(0.f, 1.f);
  moldtex::mtx_walker w{};
  do w.triangle = uint32_t(rng() % surface.triangle_count());
  while (surface.degenerate[w.triangle]);
  float b1 = uniform(rng), b2 = uniform(rng);
  if (b1 + b2 > 1.f) b1 = 1.f - b1, b2 = 1.f - b2;
  w.bary[0] = 1.f - b1 - b2;
  w.bary[1] = b1;
  w.bary[2] = b2;
  const float angle = 6.2831853f * uniform(rng);
  w.heading = {std::cos(angle), std::sin(angle)};
  return w;
}

}  // namespace mtx
