#include "domain/intrinsic_lattice.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "shared/intrinsic_lattice.h"
#include "shared/texel_sampling.h"

namespace moldtex {

namespace {

constexpr uint32_t kMaxLatticeGrid = 2048;  // nodes per side of one input triangle, at most
// More nodes than this in all is refused (4 bytes per node and plane, 24 fixed).
constexpr uint64_t kMaxLatticeNodes = uint64_t(1) << 30;

double longest_edge(const mtx_frame& f) {
  const double a = f.a, bx = f.bx, by = f.by;
  return std::max({a, std::hypot(bx, by), std::hypot(bx - a, by)});
}

}  // namespace

IntrinsicLattice build_intrinsic_lattice(const Surface& s, const mtx_surface_tables& tables, double spacing,
                                         ThreadPool& pool) {
  IntrinsicLattice L;
  const uint32_t nt = s.triangle_count();
  L.grid.assign(2ull * nt, 0);
  uint64_t total = 0;
  for (uint32_t t = 0; t < nt; ++t) {
    // Triangles without locator cells (dropped or of zero area) get one node, which
    // reads what the locator answers there.
    uint32_t G = 0;
    if (tables.locator_grid[2 * t + 1] != 0) {
      const double g = std::ceil(longest_edge(s.frames[t]) / std::max(spacing, 1e-300));
      G = static_cast<uint32_t>(std::clamp(g, 1.0, double(kMaxLatticeGrid)));
    }
    L.grid[2ull * t] = static_cast<uint32_t>(std::min<uint64_t>(total, 0xffffffffu));
    L.grid[2ull * t + 1] = G;
    total += uint64_t(G + 1) * (G + 2) / 2;
    if (total > kMaxLatticeNodes)
      fail(MOLDTEX_ERROR_TOO_LARGE, "The intrinsic domain's sampling lattice would need more than " +
                                        std::to_string(kMaxLatticeNodes) +
                                        " nodes: raise the bound (a coarser triangulation)");
  }
  L.vertex.resize(3 * total);
  L.weight.resize(3 * total);
  pool.parallel_for(nt, 256, [&](size_t begin, size_t end) {
    for (size_t t = begin; t < end; ++t) {
      const uint32_t first = L.grid[2 * t], G = L.grid[2 * t + 1];
      for (uint32_t i = 0; i <= G; ++i)
        for (uint32_t j = 0; i + j <= G; ++j) {
          float b[3];
          if (G == 0) {
            b[0] = b[1] = b[2] = 1.f / 3.f;
          } else {
            b[1] = float(double(i) / G);
            b[2] = float(double(j) / G);
            b[0] = float(double(G - i - j) / G);
          }
          const size_t n = mtx_lattice_node(first, int(G), int(i), int(j));
          mtx_locate_intrinsic(tables.locator_grid, tables.locator_cells, tables.locator_face, tables.locator_map,
                               tables.locator_next, tables.locator_across, tables.face_vertices,
                               static_cast<uint32_t>(t), b, &L.weight[3 * n], &L.vertex[3 * n]);
        }
    }
  });
  return L;
}

void IntrinsicLattice::gather(const float* values, size_t vertex_count, float* nodes, uint32_t planes,
                              ThreadPool& pool) const {
  const uint32_t count = node_count();
  pool.parallel_for(count, 8192, [&](size_t begin, size_t end) {
    for (size_t n = begin; n < end; ++n)
      mtx_lattice_gather_node(values, vertex.data(), weight.data(), nodes, static_cast<uint32_t>(n), count,
                              static_cast<uint32_t>(vertex_count), planes);
  });
}

void IntrinsicLattice::scatter(int32_t* node_sums, int32_t* vertex_sums, size_t vertex_count, uint32_t planes,
                               ThreadPool& pool) const {
  const uint32_t count = node_count();
  pool.parallel_for(count, 8192, [&](size_t begin, size_t end) {
    for (size_t n = begin; n < end; ++n)
      mtx_lattice_scatter_node(node_sums, vertex_sums, vertex.data(), weight.data(), static_cast<uint32_t>(n), count,
                               static_cast<uint32_t>(vertex_count), planes);
  });
}

std::vector<float> IntrinsicLattice::field(const std::vector<float>& f) const {
  std::vector<float> out(node_count(), 0.f);
  for (size_t n = 0; n < out.size(); ++n) {
    float v = 0.f, obstacle = 0.f;
    bool blocked = false;
    for (int k = 0; k < 3; ++k) {
      const float w = weight[3 * n + k], here = f[vertex[3 * n + k]];
      if (!(w > 0.f)) continue;
      if (here < MTX_OBSTACLE_THRESHOLD) {
        obstacle = blocked ? std::min(obstacle, here) : here;
        blocked = true;
      }
      v += w * here;
    }
    out[n] = blocked ? obstacle : v;
  }
  return out;
}

}  // namespace moldtex
