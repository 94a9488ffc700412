// The surface: a triangle mesh with a UV layout, prepared for walking agents.
//
// Every triangle gets an isometric local 2D frame (corner 0 at the origin, corner 1 on
// the +x axis, corner 2 above it), so distances and angles measured in a frame are true
// 3D distances and angles. Agents carry their heading in the frame of the triangle they
// stand on; crossing an edge unfolds the heading into the neighbour's frame. This is
// what the metric tensor g(t) does in MoMaS, without inverting the 3x3 matrix L.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "moldtex.h"
#include "shared/walk.h"

namespace moldtex {

using Vec2 = mtx_vec2;
using TriangleFrame = mtx_frame;  // see shared/walk.h
using Walker = mtx_walker;

// Neighbour across edge i (the edge opposite corner i, from corner i+1 to corner i+2),
// packed as shared/walk.h describes; kNoNeighbour at open boundaries and next to
// zero-area triangles.
using AdjacencyCode = uint32_t;
constexpr AdjacencyCode kNoNeighbour = MTX_NO_NEIGHBOUR;

// The frame of a triangle with corners (0, 0), (a, 0), (bx, by), by > 0 (shared/walk.h).
TriangleFrame make_frame(double a, double bx, double by);

inline Vec2 frame_corner(const TriangleFrame& f, int c) {
  return c == 0 ? Vec2{0.f, 0.f} : (c == 1 ? Vec2{f.a, 0.f} : Vec2{f.bx, f.by});
}

struct Surface {
  // Input, kept for queries.
  std::vector<float> positions;            // 3 per vertex
  std::vector<uint32_t> triangles;         // 3 per triangle
  std::vector<float> corner_uvs;           // 6 per triangle
  bool generated_uvs = false;              // no UVs given: corner_uvs is triangle_atlas_uvs
  // Derived.
  std::vector<TriangleFrame> frames;
  // 9 per triangle: 3D position of corner 0 and the unit 3D x and y axes of its frame
  // (zeros for degenerate triangles), so a frame point (x, y) is at p0 + x X + y Y.
  std::vector<float> frame3d;
  std::vector<AdjacencyCode> adjacency;    // 3 per triangle
  // Each edge's neighbour unfolded into the triangle's frame: 3 MTX_UNFOLDED_FLOATS per
  // triangle (shared/walk.h; surface/unfolded_neighbours.h).
  std::vector<float> unfolded;
  std::vector<float> areas;                // 3D area per triangle
  std::vector<uint8_t> degenerate;         // 1 where the 3D or UV area is ~zero (3D: walkable_in_3d)
  std::vector<uint32_t> island;            // UV island id: joined across non-seam edges
  double area = 0, uv_area = 0;
  uint64_t fingerprint = 0;                // hash of positions, triangles and UVs
  uint32_t boundary_edges = 0, seam_edges = 0, degenerate_count = 0;

  uint32_t triangle_count() const { return static_cast<uint32_t>(frames.size()); }
  uint32_t vertex_count() const { return static_cast<uint32_t>(positions.size() / 3); }
  size_t bytes() const;

  // Metric tensor g(t) = J^T J for the UV -> 3D Jacobian J; row-major 2x2.
  std::array<double, 4> metric(uint32_t t) const;
  // 3D area covered by a unit of UV area in triangle t (sqrt det g).
  double area_per_uv_area(uint32_t t) const;
  void evaluate(uint32_t t, const float bary[3], float position[3], float uv[2]) const;
};

// Limits that build_surface enforces, so that the float arithmetic downstream stays
// defined. UVs: every texel index is computed as int(uv * size) with size <= 65536 (the
// brush image; 16384 for a simulation), so |uv| <= 1e4 keeps it below 2^31 (UDIM tiles
// 1001..1999 use u, v in 0 .. 100). Mesh size: the longest edge within 1e-9 .. 1e12, so
// the smallest non-degenerate triangle area (1e-12 of the longest edge squared) and the
// total area (<= 2^28 triangles) stay normal floats. Coordinates: within +-1e15, well
// inside the +-1e18 that ray casts accept.
constexpr double kMaxUvCoordinate = 1e4;
constexpr double kMinMeshSize = 1e-9, kMaxMeshSize = 1e12;
constexpr double kMaxCoordinate = 1e15;
static_assert(kMaxUvCoordinate * 65536.0 < 2147483647.0, "texel indices must fit in int");

// Builds and validates; throws moldtex::Error with a user-facing message.
Surface build_surface(const moldtex_mesh_desc& desc);

// The surface as a domain that needs no UVs sees it (the intrinsic domain): triangles
// whose UVs have zero area but whose 3D area is not zero get their frames and areas and
// join their neighbours, instead of being walls as the texture domain needs them (it
// cannot measure texels there). Triangles flat in 3D stay walls; the UV islands and the
// fingerprint are kept. Returns `surface` itself when no triangle changes.
std::shared_ptr<const Surface> walkable_in_3d(std::shared_ptr<const Surface> surface);

}  // namespace moldtex
