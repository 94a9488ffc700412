// Delaunay refinement of the intrinsic triangulation (Chew 1993 / Ruppert 1995 in the
// intrinsic setting of Sharp, Soliman & Crane 2019 §4; our own implementation): insert
// circumcentres until no triangle's circumradius exceeds a bound, so every triangle is
// small (circumradius <= bound) and, away from small input angles, well shaped (Chew's
// argument: an inserted circumcentre lies at least the bound from every vertex, so edges
// stay no shorter than about the bound and angles bounded below).
//
// One step: take the face with the largest circumradius R > bound. Trace a straight line
// over the intrinsic mesh from its barycentre towards its circumcentre (the circumcentre
// of an obtuse triangle lies outside it, possibly several faces away).
//  * The line reaches the circumcentre: insert a vertex there (its input location by the
//    correspondence, correspondence.h), then flip to Delaunay around it.
//  * The line hits the boundary first: the circumcentre would lie outside the surface, so
//    the boundary edge it crossed is *encroached*: split it at its midpoint instead
//    (Ruppert's rule; the midpoint's circumcircle is the edge's diametral circle). The
//    same when the circumcentre lands inside the diametral circle of a boundary edge of
//    the face it lands in (else a vertex could be inserted a hair inside the boundary).
//
// Guards against non-termination (each counted in the report):
//  * Small input angles: Ruppert's termination proof needs input angles >= 60 degrees; no
//    insertion can widen the angle at an input vertex whose total angle (a cone of the
//    surface, or a sharp boundary corner) is small. A face at such a vertex v whose
//    circumradius exceeds the bound although both its edges at v are already no longer
//    than 2 * bound owes its circumradius to the angle, not to its size: refining it would
//    only pile vertices up around v (and the disk of radius R around a point near a sharp
//    cone wraps around it, where the empty-circumcircle spacing argument fails). Such
//    faces are skipped; larger faces at v are refined as usual, so the skipped ones lie
//    within 2 * bound of v.
//  * Floating-point rechecks: each popped face's circumradius is recomputed (flips since
//    it was queued may have fixed it); a point that lands within kMinInsertionDistance *
//    bound of an existing vertex (possible only by round-off: the circumcircle of a
//    Delaunay face is empty), or a boundary edge shorter than twice that, is not
//    inserted/split: the face is given up (remembered by its vertex triple).
//  * A cap on insertions (default from the expected vertex count, see below): reaching it
//    stops with StopReason::InsertionCap and a message.
// Expected size: Chew's triangles have circumradii between about bound/2 and bound, so
// areas between ~0.3 and ~1.3 bound^2 and about area / bound^2 * [0.4, 1.6] vertices.
#pragma once
#include <cstdint>
#include <string>

#include "common/progress.h"
#include "intrinsic/correspondence.h"

namespace moldtex::intrinsic {

constexpr double kMinInsertionDistance = 1e-3;
// Barycentric weights below this are raised to it before inserting a vertex into a face:
// a point on (or within round-off of) an edge becomes a point just inside the face; the
// sliver next to it is not Delaunay and the flips that follow remove it.
constexpr double kMinInsertionBary = 1e-4;

struct RefineOptions {
  double max_circumradius = 0;           // the bound, in mesh units (> 0)
  double min_input_angle = kPi / 3;      // skip faces at input vertices with a smaller total angle
  uint64_t max_insertions = 0;           // 0: 20 * area / bound^2 + 10 * faces + 1000
  // The surface's own 3D area for that default (0: the triangulation's). Mollification
  // can inflate the triangulation's area by orders of magnitude on a needle (a triangle
  // 5e11 long and 1 wide became 1e5 times wider), and the cap with it.
  double area = 0;
  // Optional: reports the vertex count and the fraction of expected_vertices reached
  // (stage_fraction), and stops with MOLDTEX_ERROR_CANCELLED when asked to (checked
  // every kProgressInterval insertions).
  WorkProgress* progress = nullptr;
  double expected_vertices = 0;
};
constexpr uint64_t kProgressInterval = 1024;

enum class StopReason { Converged, InsertionCap, FlipCap };

struct RefineReport {
  StopReason reason = StopReason::Converged;
  uint64_t insertions = 0;       // circumcentres inserted
  uint64_t boundary_splits = 0;  // encroached boundary edges split
  uint64_t flips = 0;
  uint64_t given_up = 0;         // faces given up by the floating-point rechecks
  // Faces left with circumradius > bound, by cause.
  uint32_t skipped_small_angle = 0;
  uint32_t skipped_other = 0;
  std::string message;           // why it stopped, for the user
};

// Vertex insertion at an intrinsic point (weights clamped, see kMinInsertionBary); sets
// signposts, lengths and the new vertex's input location. Returns the new vertex. The
// caller flips afterwards (the three edges of the old face may no longer be Delaunay).
uint32_t insert_vertex(IntrinsicTriangulation& T, SurfacePoint p);
// Splits the boundary edge whose inner side is halfedge h at its midpoint. Returns the new
// vertex.
uint32_t split_boundary_edge(IntrinsicTriangulation& T, uint32_t h);

// Flips to Delaunay, then refines. Throws moldtex::Error for a bound that is not a
// positive finite number.
RefineReport refine(IntrinsicTriangulation& T, const RefineOptions& options);

}  // namespace moldtex::intrinsic
