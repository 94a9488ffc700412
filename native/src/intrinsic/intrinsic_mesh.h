// An intrinsic triangle mesh (issue 11, layton-intrinsic-slime.md §3.1): connectivity as
// halfedges plus one length per edge, and nothing else. No vertex positions: the geometry
// of every triangle is whatever its three edge lengths say, laid out in the plane on
// demand. This is the data that both the input mesh and its intrinsic triangulation are
// made of; the intrinsic one is then changed by flips and insertions, the input one never.
//
// Halfedges come in pairs: halfedge 2e and 2e+1 are the two sides of edge e, so the twin
// of h is h ^ 1. A halfedge with a face runs counter-clockwise around it; a halfedge
// without one (kInvalid face) is the outer side of a boundary edge. Faces are triangles:
// next(next(next(h))) == h. The connectivity may become non-simplicial (two edges joining
// the same pair of vertices, an edge from a vertex to itself): nothing here looks up an
// edge by its vertices.
//
// Vertices: the input mesh's vertices (the positions of moldtex_mesh_desc, so vertices are
// shared across UV seams: a seam splits UVs, not positions) keep their indices; inserted
// vertices follow. A vertex has a total angle (the sum of its corner angles; 2 pi at a
// flat interior vertex, the interior angle at a boundary vertex) and every halfedge with a
// face carries a *signpost*: the angle of its direction at its tail vertex, measured
// counter-clockwise from the vertex's reference direction, in [0, total angle). A boundary
// vertex's reference direction is its first boundary edge (the outgoing one with a face on
// its left), so the angles from there sweep the interior; an interior input vertex's is
// its first outgoing edge at build time and never changes: flips and insertions add
// directions, the angles of the old ones stay. Angles are not rescaled to 2 pi, so an
// input vertex's angles mean the same direction on the input mesh and on the intrinsic
// one (both carry the same lengths around it).
//
// Non-manifold input is refused (moldtex::fail, MOLDTEX_ERROR_INVALID_MESH, with the
// number of offending edges and vertices and where Blender selects them): an edge with
// more than two triangles, two triangles winding an edge the same way, or a vertex whose
// triangles form more than one fan. Triangles that repeat a vertex index have no area and
// no interior and are dropped (counted); zero-area triangles with three distinct vertices
// are kept, mollification (mollification.h) gives them a positive area.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace moldtex::intrinsic {

constexpr uint32_t kInvalid = 0xffffffffu;
constexpr double kPi = 3.14159265358979323846;

struct Vec2d {
  double x = 0, y = 0;
};
inline Vec2d operator+(Vec2d a, Vec2d b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2d operator-(Vec2d a, Vec2d b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2d operator*(double s, Vec2d a) { return {s * a.x, s * a.y}; }
inline double dot(Vec2d a, Vec2d b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2d a, Vec2d b) { return a.x * b.y - a.y * b.x; }
double norm(Vec2d a);

// A point on a mesh: a face and barycentric weights of its three corners, in the order of
// the face's halfedges starting at face_he (corner k is the tail of the k-th halfedge).
struct SurfacePoint {
  uint32_t face = kInvalid;
  std::array<double, 3> bary = {0, 0, 0};
};

struct IntrinsicMesh {
  // Per halfedge.
  std::vector<uint32_t> he_next;    // next halfedge around the face; kInvalid without a face
  std::vector<uint32_t> he_vertex;  // tail vertex
  std::vector<uint32_t> he_face;    // kInvalid on the outer side of a boundary edge
  std::vector<double> signpost;     // direction at the tail (see above); halfedges with a face
  // Per edge.
  std::vector<double> length;
  // Per face.
  std::vector<uint32_t> face_he;
  // Per vertex.
  std::vector<uint32_t> vertex_he;  // an outgoing halfedge with a face (boundary: the first
                                    // boundary edge, signpost 0); kInvalid if unused
  std::vector<double> angle_sum;    // total angle
  std::vector<uint8_t> boundary;    // 1 on the boundary

  uint32_t vertex_count() const { return static_cast<uint32_t>(vertex_he.size()); }
  uint32_t edge_count() const { return static_cast<uint32_t>(length.size()); }
  uint32_t face_count() const { return static_cast<uint32_t>(face_he.size()); }
  uint32_t halfedge_count() const { return static_cast<uint32_t>(he_vertex.size()); }

  static uint32_t twin(uint32_t h) { return h ^ 1u; }
  static uint32_t edge(uint32_t h) { return h >> 1; }
  uint32_t next(uint32_t h) const { return he_next[h]; }
  uint32_t prev(uint32_t h) const { return he_next[he_next[h]]; }
  uint32_t tail(uint32_t h) const { return he_vertex[h]; }
  uint32_t head(uint32_t h) const { return he_vertex[h ^ 1u]; }
  double len(uint32_t h) const { return length[h >> 1]; }
  bool is_boundary_edge(uint32_t e) const {
    return he_face[2 * e] == kInvalid || he_face[2 * e + 1] == kInvalid;
  }
  // The halfedges of face f, from face_he.
  std::array<uint32_t, 3> face_halfedges(uint32_t f) const;
  // Index (0..2) of halfedge h in its face's order.
  int corner_index(uint32_t h) const;
  // Counter-clockwise next outgoing halfedge around tail(h), kInvalid past the last one
  // of a boundary vertex (requires a face on h).
  uint32_t ccw_next(uint32_t h) const;

  // Geometry from the lengths.
  double face_area(uint32_t f) const;
  // Angle at tail(h) inside face(h).
  double corner_angle(uint32_t h) const;
  // Makes the halfedges a -> b -> c -> a face f: their next links and face, and f's
  // halfedge (a). Slot f must exist.
  void link_face(uint32_t f, uint32_t a, uint32_t b, uint32_t c);
  // Cotangent of the angle opposite halfedge h in its face.
  double opposite_cotan(uint32_t h) const;
  double circumradius(uint32_t f) const;
  // Corners of face f in the plane: corner 0 at the origin, corner 1 on +x, corner 2
  // above (counter-clockwise).
  std::array<Vec2d, 3> layout(uint32_t f) const;
  double total_area() const;
  // Euler characteristic V - E + F over the used vertices.
  int64_t euler_characteristic() const;

  // Recomputes every vertex's total angle and every signpost from the lengths, taking each
  // vertex's reference direction from vertex_he (call once after building and mollifying).
  void compute_signposts();
};

// Area of a triangle with side lengths a, b, c (Kahan's stable Heron formula); 0 when the
// lengths violate the triangle inequality.
double triangle_area(double a, double b, double c);
// Barycentric weights of p in the triangle with corners P.
std::array<double, 3> barycentric(const std::array<Vec2d, 3>& P, Vec2d p);
// a modulo m into [0, m).
double wrap_angle(double a, double m);

struct MeshBuildReport {
  uint32_t dropped_triangles = 0;  // repeated vertex index
  uint32_t boundary_edges = 0;
  uint32_t unused_vertices = 0;
};

// Connectivity and 3D edge lengths of an input triangle mesh (positions: 3 per vertex,
// triangles: 3 indices per triangle). kept_triangles (optional) receives, per face, the
// index of its input triangle; face f's corner k is that triangle's corner k. Signposts
// are not computed yet (mollify first, then compute_signposts). Throws moldtex::Error on
// out-of-range indices, non-finite positions and non-manifold input.
IntrinsicMesh build_input_mesh(const std::vector<double>& positions, const std::vector<uint32_t>& triangles,
                               std::vector<uint32_t>* kept_triangles, MeshBuildReport* report);

}  // namespace moldtex::intrinsic
