// The intrinsic domain's sampling lattice (shared/intrinsic_lattice.h): per input
// triangle a regular lattice of nodes about one intrinsic edge apart, each node located
// once on its intrinsic face. Every step the vertex values are interpolated onto the
// nodes (gather) and agents read and deposit there by arithmetic on their barycentrics;
// the nodes' deposits go on to the vertices with the same weights (scatter), so the
// total deposited is kept to the last unit.
//
// Why: locating every sensor probe and deposit on the fine intrinsic faces (a cell
// lookup and its candidates, shared/intrinsic_locate.h) took about half of an agent's
// step on a Suzanne-sized mesh (docs/PERFORMANCE.md); the gather costs one pass over
// the nodes per step, whatever the number of agents.
//
// What it changes: a reading is the linear interpolation over a lattice triangle of the
// intrinsic interpolant at its corners, and a deposit the adjoint: both smooth over about
// one intrinsic edge more than the exact hats, below the scale the bound resolves.
#pragma once
#include <cstdint>
#include <vector>

#include "backends/cpu/private_sums.h"
#include "backends/cpu/thread_pool.h"
#include "intrinsic/correspondence.h"
#include "surface/surface.h"

namespace moldtex {

struct IntrinsicLattice {
  std::vector<uint32_t> grid;     // 2 per surface triangle: first node, G
  std::vector<uint32_t> vertex;   // 3 per node: the vertices of the intrinsic face under it
  std::vector<float> weight;      // 3 per node: its barycentrics there

  uint32_t node_count() const { return static_cast<uint32_t>(vertex.size() / 3); }
  size_t bytes() const { return (grid.size() + vertex.size() + weight.size()) * 4; }

  // Node values of `planes` planes from vertex values (planes of vertex_count, into
  // planes of node_count()).
  void gather(const float* vertex_values, size_t vertex_count, float* node_values, uint32_t planes,
              ThreadPool& pool) const;
  // The nodes' deposit sums passed on to the vertices (added to vertex_sums, planes of
  // vertex_count) and cleared: each node splits its units over its three vertices by
  // their weights, the parts adding up exactly (mtx_texel_deposit). Each thread adds into
  // its own plane of per_thread (prepared for vertex_count * planes sums), folded into
  // vertex_sums at the end.
  void scatter(int32_t* node_sums, int32_t* vertex_sums, size_t vertex_count, uint32_t planes,
               PrivateSums& per_thread, ThreadPool& pool) const;
  // A static field at the nodes from its vertex values: an obstacle at any vertex of a
  // node's stencil (weight > 0) makes the node that obstacle, as a read over the exact
  // stencil would; elsewhere the interpolated value.
  std::vector<float> field(const std::vector<float>& vertex_field) const;
};

// Nodes about `spacing` apart along each input triangle's longest edge (G per
// triangle), each located on T by a chain of short traces (intrinsic_locator.h's
// locate_chain, in double precision: exact where the float locator's cells may clamp,
// as on slivers). input_face: per surface triangle its input face of T (kInvalid:
// none); face_rank: T's face numbers -> the domain's; face_vertices: 3 per face (the
// domain's numbering).
IntrinsicLattice build_intrinsic_lattice(const Surface& surface, const intrinsic::IntrinsicTriangulation& T,
                                         const std::vector<uint32_t>& input_face,
                                         const std::vector<uint32_t>& face_rank,
                                         const std::vector<uint32_t>& face_vertices, double spacing,
                                         ThreadPool& pool);

}  // namespace moldtex
