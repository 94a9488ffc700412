#include "domain/intrinsic_lattice.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "domain/intrinsic_locator.h"
#include "shared/intrinsic_lattice.h"
#include "shared/texel_sampling.h"

namespace moldtex {

namespace {

constexpr uint32_t kMaxLatticeGrid = 2048;  // nodes per side of one input triangle, at most
// A sliver's lattice is as thin as the sliver (its triangles are similar to it), so nodes
// `spacing` apart along its long edges would crowd its short one: a triangle of aspect A
// would take ~A times the nodes of a well-shaped one of its area (a CAD cylinder of
// triangles 1000 times longer than wide: gigabytes). G is held to this many times the G
// of a lattice whose triangles have the area of an equilateral one of side `spacing`, so
// nodes stay within ~36x that count; beyond, the spacing along a sliver grows instead.
// 3 would engage on Fig. 4's sphere of slivers (its pattern then 10.1 % from the
// well-shaped sphere's, 8.8 % uncapped); 6 leaves it as uncapped.
constexpr double kMaxSliverFactor = 6.0;
// More nodes than this in all is refused (4 bytes per node and plane, 24 fixed).
constexpr uint64_t kMaxLatticeNodes = uint64_t(1) << 30;

double longest_edge(const mtx_frame& f) {
  const double a = f.a, bx = f.bx, by = f.by;
  return std::max({a, std::hypot(bx, by), std::hypot(bx - a, by)});
}

}  // namespace

IntrinsicLattice build_intrinsic_lattice(const Surface& s, const intrinsic::IntrinsicTriangulation& T,
                                         const std::vector<uint32_t>& input_face,
                                         const std::vector<uint32_t>& face_rank,
                                         const std::vector<uint32_t>& face_vertices, double spacing,
                                         ThreadPool& pool) {
  IntrinsicLattice L;
  const uint32_t nt = s.triangle_count();
  L.grid.assign(2ull * nt, 0);
  uint64_t total = 0;
  for (uint32_t t = 0; t < nt; ++t) {
    // Triangles the locator has no cells for (dropped, or of zero area) get one node,
    // which reads what the locator answers there (face 0, equal weights).
    uint32_t G = 0;
    if (input_face[t] != intrinsic::kInvalid && !s.degenerate[t]) {
      const double step = std::max(spacing, 1e-300);
      const double by_length = std::ceil(longest_edge(s.frames[t]) / step);
      const double by_area = std::ceil(std::sqrt(double(s.areas[t]) / (std::sqrt(3.0) / 4 * step * step)));
      const double g = std::min(by_length, kMaxSliverFactor * by_area);
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
  pool.parallel_for(nt, 16, [&](size_t begin, size_t end) {
    std::vector<std::array<double, 3>> bary;
    std::vector<uint32_t> node;
    for (size_t t = begin; t < end; ++t) {
      const uint32_t first = L.grid[2 * t], G = L.grid[2 * t + 1];
      if (G == 0) {
        for (int k = 0; k < 3; ++k) {
          L.vertex[3ull * first + k] = face_vertices[k];
          L.weight[3ull * first + k] = 1.f / 3.f;
        }
        continue;
      }
      // Row by row, each row in turn forwards and backwards, so the chain's steps stay
      // one node long; a hair inside the triangle (1e-6 of it), so no trace runs along
      // its edges.
      bary.clear();
      node.clear();
      constexpr double kInset = 1e-6;
      for (uint32_t i = 0; i <= G; ++i)
        for (uint32_t k = 0; k <= G - i; ++k) {
          const uint32_t j = i % 2 == 0 ? k : G - i - k;
          const double b1 = double(i) / G, b2 = double(j) / G, b0 = std::max(0.0, 1 - b1 - b2);
          bary.push_back({kInset / 3 + (1 - kInset) * b0, kInset / 3 + (1 - kInset) * b1,
                          kInset / 3 + (1 - kInset) * b2});
          node.push_back(mtx_lattice_node(first, int(G), int(i), int(j)));
        }
      const std::vector<LocatedPoint> at = locate_chain(T, input_face[t], bary);
      for (size_t q = 0; q < at.size(); ++q) {
        const uint32_t f = face_rank[at[q].point.face];
        for (int k = 0; k < 3; ++k) {
          L.vertex[3ull * node[q] + k] = face_vertices[3ull * f + k];
          L.weight[3ull * node[q] + k] = static_cast<float>(at[q].point.bary[k]);
        }
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
                               PrivateSums& per_thread, ThreadPool& pool) const {
  const uint32_t count = node_count();
  const int exclusive = per_thread.exclusive() ? 1 : 0;
  pool.parallel_for_threads(count, 8192, [&](size_t begin, size_t end, unsigned thread) {
    int32_t* const into = per_thread.for_thread(vertex_sums, thread);
    for (size_t n = begin; n < end; ++n)
      mtx_lattice_scatter_node(node_sums, into, vertex.data(), weight.data(), static_cast<uint32_t>(n), count,
                               static_cast<uint32_t>(vertex_count), planes, exclusive);
  });
  per_thread.fold_into(vertex_sums, pool);
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
