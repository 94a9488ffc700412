// Intrinsic Delaunay triangulation by edge flips (Sharp, Soliman & Crane 2019 §3; our own
// implementation). An interior edge ij with opposite angles alpha (in one triangle) and
// beta (in the other) is locally Delaunay when alpha + beta <= pi, equivalently when its
// cotangent weight (cot alpha + cot beta) / 2 is non-negative. A non-Delaunay edge is
// flipped: the two triangles form a quad (laid out in the plane from the five lengths)
// that is strictly convex at i and j, since alpha + beta > pi puts each of the other two
// corners outside the opposite triangle's circumcircle, and the flipped edge joins the
// two opposite corners with the length of that diagonal in the layout. The surface's
// metric does not change: each new triangle is a piece of the same flat quad.
//
// The queue holds every edge once at the start; a flip re-queues the four quad edges.
// Termination: in exact arithmetic the flip algorithm terminates on any intrinsic
// triangulation of a surface (Bobenko & Springborn 2007, "A discrete Laplace-Beltrami
// operator for simplicial surfaces"; Indermitte et al. 2001 for the Delaunay flip on
// polyhedral surfaces), as each Delaunay flip lowers an energy and no triangulation
// repeats. In floating point, an edge is
// flipped only when alpha + beta > pi + kFlipTolerance, and a cap on the number of flips
// (reported) bounds the work regardless.
#pragma once
#include <cstdint>
#include <vector>

#include "intrinsic/intrinsic_mesh.h"

namespace moldtex::intrinsic {

constexpr double kFlipTolerance = 1e-12;

// Sum of the two angles opposite an interior edge (0 for a boundary edge).
double opposite_angle_sum(const IntrinsicMesh& m, uint32_t e);
bool is_delaunay(const IntrinsicMesh& m, uint32_t e, double tolerance = kFlipTolerance);

// Flips interior edge e (connectivity, length, signposts). Returns false, changing
// nothing, when the edge is on the boundary, borders the same face twice, or its quad is
// not strictly convex at the edge's ends (the flip would leave the surface).
bool flip_edge(IntrinsicMesh& m, uint32_t e);

struct FlipReport {
  uint64_t flips = 0;
  bool capped = false;  // stopped at max_flips with non-Delaunay edges possibly left
};

// Flips until every interior edge is locally Delaunay. `queue`: the edges to check first
// (all edges when empty). `touched_faces` (optional) receives the faces each flip changed.
FlipReport flip_to_delaunay(IntrinsicMesh& m, std::vector<uint32_t> queue = {}, uint64_t max_flips = 0,
                            std::vector<uint32_t>* touched_faces = nullptr);

}  // namespace moldtex::intrinsic
