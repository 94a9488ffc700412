// Point location from the input mesh onto the intrinsic triangulation, built once per
// domain (the lookup is shared/intrinsic_locate.h, the same code on every backend).
//
// Agents walk the input mesh (few, large triangles: few edge crossings per step) and
// read and deposit at the intrinsic vertices (many, small triangles; through the sampling
// lattice of domain/intrinsic_lattice.h, whose nodes this locator places), the design the
// paper leaves as future work (layton-intrinsic-slime.md §6): a walk over the fine
// intrinsic faces crossed ~25 of them per agent step (a sensor probe spans several) and
// ran 7x slower than the texture domain (docs/PERFORMANCE.md).
//
// Building: each input triangle gets a grid of about one cell per intrinsic face that
// overlaps it. The cells' corners and centres are located on the intrinsic
// triangulation by a chain of short traces (locate_chain); each cell lists the faces
// that overlap it (those its samples landed in and their neighbours across edges
// through the cell, the largest overlap first), each with the affine map from the input
// triangle's barycentrics to the face's.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "backends/cpu/thread_pool.h"
#include "intrinsic/correspondence.h"
#include "shared/intrinsic_locate.h"
#include "surface/surface.h"

namespace moldtex {

// A point of an input face found on the intrinsic triangulation, and the angle that turns
// a direction in the input face's frame into one in the intrinsic face's frame.
struct LocatedPoint {
  intrinsic::SurfacePoint point;  // intrinsic face (the triangulation's own numbering)
  double turn = 0;
};

// Points of input face `face` (barycentrics) located on the intrinsic triangulation: the
// first by a trace from the face's nearest corner, each next one by a short trace from
// the one before (the input face is flat, so the displacement between them is one
// straight line on both meshes); a trace that fails starts over from a corner.
std::vector<LocatedPoint> locate_chain(const intrinsic::IntrinsicTriangulation& T, uint32_t face,
                                       const std::vector<std::array<double, 3>>& bary);

// One point from its input face's nearest corner (to_intrinsic with the turn).
LocatedPoint locate_from_corner(const intrinsic::IntrinsicTriangulation& T, uint32_t face,
                                const std::array<double, 3>& bary);

// The other way: a point of intrinsic face `face` (T's numbering) on the input mesh, and
// the turn from the intrinsic face's frame into the input face's.
LocatedPoint locate_on_input(const intrinsic::IntrinsicTriangulation& T, uint32_t face,
                             const std::array<double, 3>& bary);

struct IntrinsicLocator {
  std::vector<uint32_t> grid;   // 2 per surface triangle: first cell, G
  std::vector<uint32_t> cells;  // first candidate per cell, and the end
  // Per candidate, MTX_LOCATE_FACE_STRIDE words: its intrinsic face (the domain's
  // numbering) and the face's three vertices, so a lookup reads one 16-byte record.
  std::vector<uint32_t> face;
  // Per candidate, MTX_LOCATE_MAP_STRIDE floats: the first two rows of c = M b (the
  // third weight is 1 minus them).
  std::vector<float> map;
  // The walk's steps (shared/intrinsic_locate.h): per face and edge the neighbour (face
  // << 2 | its halfedge on the edge) and the weights here of its corner across (3).
  std::vector<uint32_t> next;
  std::vector<float> across;

  size_t bytes() const {
    return (grid.size() + cells.size() + face.size() + map.size() + next.size() + across.size()) * 4;
  }
};

// input_face: per surface triangle its input face of T (kInvalid: none); face_rank: T's
// face numbers -> the domain's, face_order the other way; face_vertices: 3 per face (the
// domain's numbering); face_area: the mean intrinsic face area.
IntrinsicLocator build_intrinsic_locator(const Surface& surface, const intrinsic::IntrinsicTriangulation& T,
                                         const std::vector<uint32_t>& input_face,
                                         const std::vector<uint32_t>& face_rank,
                                         const std::vector<uint32_t>& face_order,
                                         const std::vector<uint32_t>& face_vertices, double face_area,
                                         ThreadPool& pool);

}  // namespace moldtex
