// Correspondence between the intrinsic triangulation and the input mesh, both ways, by
// signposts (Sharp, Soliman & Crane 2019; our own implementation).
//
// Why signposts and not integer coordinates (Gillespie et al. 2021): integer (normal)
// coordinates are exact under flips and need no floating-point tracing, but every
// operation must update per-edge crossing counts and roundabouts, and recovering a point's
// location needs the full common-subdivision machinery; that is a much larger body of
// code to get right. Signposts are one angle per halfedge, updated locally by flips and
// insertions (intrinsic_mesh.h, delaunay_flip.cpp, refinement.cpp), and a location query
// is one straight-line trace, which the simulation also needs for agents. Their weakness,
// round-off in long traces, is bounded here because every trace is short: from a corner
// of the face the point lies in, never across the mesh. The tests measure the round trip.
//
// Both directions are one primitive: trace a straight line (a geodesic: the surface is
// flat inside faces and across edges, so unfolding face after face keeps the line
// straight) of given direction and length over a mesh.
//  * Intrinsic -> input: a point in intrinsic face f lies at some angle and distance from
//    a corner i of f. That angle is a direction in i's tangent space (signposts). If i is
//    an input vertex, the same angle leaves i on the input mesh (input and intrinsic mesh
//    share the vertex and its angles); if i was inserted, `frame_angle[i]` says which
//    direction in its input triangle's layout has angle 0. Trace that far on the input.
//  * Input -> intrinsic: a point in input triangle T lies at some angle and distance from
//    a corner v of T, an input vertex, which is also an intrinsic vertex with the same
//    angles: trace that far on the intrinsic mesh.
//  * Every intrinsic vertex stores its input location (input face + barycentrics), set
//    when it is inserted, by the first kind of trace.
// Boundary vertices inserted by splitting a boundary edge are placed exactly: a boundary
// edge of the intrinsic mesh always lies along one input boundary edge (flips never
// touch boundary edges), and its span along it is kept (boundary_span).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "intrinsic/intrinsic_mesh.h"

namespace moldtex {
struct Surface;
}

namespace moldtex::intrinsic {

struct TraceResult {
  SurfacePoint point;                // where the line ends
  Vec2d direction;                   // unit direction of travel there, in point.face's layout
  uint32_t boundary_he = kInvalid;   // the line stopped on this boundary edge (its inner side)
  uint32_t faces = 0;                // faces entered
  bool complete = true;              // false: the step cap stopped it (point: where it got)
};

// Straight line from `start` with direction `dir` (start.face's layout; need not be unit)
// for `distance`. Stops early at the boundary.
TraceResult trace_from_point(const IntrinsicMesh& m, const SurfacePoint& start, Vec2d dir, double distance);
// Straight line leaving vertex v at tangent angle `angle` (signpost convention).
TraceResult trace_from_vertex(const IntrinsicMesh& m, uint32_t v, double angle, double distance);

struct Correspondence {
  // Per intrinsic vertex: its point on the input mesh (input face numbering).
  std::vector<SurfacePoint> location;
  // Per inserted vertex: the direction, in location.face's layout, of its tangent angle 0.
  std::vector<double> frame_angle;
  // Per intrinsic halfedge: for the inner side of a boundary edge, the input boundary
  // halfedge it lies on and the span [t0, t1] along it (0 = that halfedge's tail).
  std::vector<uint32_t> boundary_input_he;
  std::vector<std::array<double, 2>> boundary_span;
};

struct IntrinsicTriangulation {
  IntrinsicMesh input;   // the input mesh, mollified; never changed after building
  IntrinsicMesh mesh;    // the intrinsic triangulation
  Correspondence corr;
  uint32_t input_vertex_count = 0;
  std::vector<double> positions;        // input, 3 per vertex
  std::vector<uint32_t> triangles;      // 3 per input face (the kept triangles)
  std::vector<uint32_t> input_triangle; // per input face: index of its triangle in the input
  double mollify_epsilon = 0;           // added to every edge length
  uint32_t dropped_triangles = 0;
  double mean_edge = 0;
};

// Builds the input mesh and the intrinsic triangulation (a copy, not yet flipped) from
// positions (3 per vertex) and triangles (3 per triangle), mollified with margin
// margin * mean edge length. Throws moldtex::Error on invalid or non-manifold input.
IntrinsicTriangulation build_intrinsic_triangulation(const std::vector<double>& positions,
                                                     const std::vector<uint32_t>& triangles,
                                                     double margin = 1e-6);

// The same for a validated Surface (surface/surface.h): its vertices are the mesh's
// positions, shared by the triangles on both sides of a UV seam (UVs are per corner), so
// seams do not cut the intrinsic mesh; only open boundaries do.
IntrinsicTriangulation build_intrinsic_triangulation(const moldtex::Surface& surface, double margin = 1e-6);

// Line from intrinsic vertex v at its tangent angle `angle`, traced over the input mesh.
TraceResult trace_input_from_vertex(const IntrinsicTriangulation& T, uint32_t v, double angle, double distance);
// Intrinsic point -> input point (input face numbering).
SurfacePoint to_input(const IntrinsicTriangulation& T, const SurfacePoint& p);
// Input point (input face numbering) -> intrinsic point.
SurfacePoint to_intrinsic(const IntrinsicTriangulation& T, const SurfacePoint& p);
// 3D position of an input point.
std::array<double, 3> input_position(const IntrinsicTriangulation& T, const SurfacePoint& p);
// Angle of `dir` at corner k of face f, in the tangent space of that corner's vertex.
double tangent_angle(const IntrinsicMesh& m, uint32_t f, int k, Vec2d dir);

}  // namespace moldtex::intrinsic
