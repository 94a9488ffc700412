#include "intrinsic/intrinsic_mesh.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "common/error.h"

namespace moldtex::intrinsic {

double norm(Vec2d a) { return std::hypot(a.x, a.y); }

double triangle_area(double a, double b, double c) {
  // Kahan: sort a >= b >= c, then the four factors are each computed without cancellation.
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return p > 0 ? 0.25 * std::sqrt(p) : 0.0;
}

std::array<double, 3> barycentric(const std::array<Vec2d, 3>& P, Vec2d p) {
  const double total = cross(P[1] - P[0], P[2] - P[0]);
  std::array<double, 3> b;
  for (int i = 0; i < 3; ++i) b[i] = cross(P[(i + 1) % 3] - p, P[(i + 2) % 3] - p) / total;
  return b;
}

double wrap_angle(double a, double m) {
  double r = std::fmod(a, m);
  if (r < 0) r += m;
  if (r >= m) r = 0;
  return r;
}

std::array<uint32_t, 3> IntrinsicMesh::face_halfedges(uint32_t f) const {
  const uint32_t h0 = face_he[f], h1 = he_next[h0];
  return {h0, h1, he_next[h1]};
}

int IntrinsicMesh::corner_index(uint32_t h) const {
  const uint32_t h0 = face_he[he_face[h]];
  return h == h0 ? 0 : (h == he_next[h0] ? 1 : 2);
}

uint32_t IntrinsicMesh::ccw_next(uint32_t h) const {
  const uint32_t g = twin(prev(h));
  return he_face[g] == kInvalid ? kInvalid : g;
}

double IntrinsicMesh::face_area(uint32_t f) const {
  const auto h = face_halfedges(f);
  return triangle_area(len(h[0]), len(h[1]), len(h[2]));
}

void IntrinsicMesh::link_face(uint32_t f, uint32_t a, uint32_t b, uint32_t c) {
  he_next[a] = b;
  he_next[b] = c;
  he_next[c] = a;
  he_face[a] = he_face[b] = he_face[c] = f;
  face_he[f] = a;
}

double IntrinsicMesh::corner_angle(uint32_t h) const {
  // Sides a (h) and b (prev(h)) meet at tail(h); c is opposite. tan = 4A / (a^2 + b^2 - c^2).
  const double a = len(h), b = len(prev(h)), c = len(next(h));
  return std::atan2(4.0 * triangle_area(a, b, c), a * a + b * b - c * c);
}

double IntrinsicMesh::opposite_cotan(uint32_t h) const {
  const double a = len(h), b = len(next(h)), c = len(prev(h));
  const double area = triangle_area(a, b, c);
  if (!(area > 0)) return 0.0;  // mollified meshes have no zero-area face
  return (b * b + c * c - a * a) / (4.0 * area);
}

double IntrinsicMesh::circumradius(uint32_t f) const {
  const auto h = face_halfedges(f);
  const double a = len(h[0]), b = len(h[1]), c = len(h[2]);
  const double area = triangle_area(a, b, c);
  return area > 0 ? a * b * c / (4.0 * area) : HUGE_VAL;
}

std::array<Vec2d, 3> IntrinsicMesh::layout(uint32_t f) const {
  const auto h = face_halfedges(f);
  const double l0 = len(h[0]), l1 = len(h[1]), l2 = len(h[2]);
  // Corner 2 at distance l2 from corner 0 and l1 from corner 1.
  const double x = (l0 * l0 + l2 * l2 - l1 * l1) / (2.0 * l0);
  const double y = 2.0 * triangle_area(l0, l1, l2) / l0;
  return {Vec2d{0, 0}, Vec2d{l0, 0}, Vec2d{x, y}};
}

double IntrinsicMesh::total_area() const {
  double a = 0;
  for (uint32_t f = 0; f < face_count(); ++f) a += face_area(f);
  return a;
}

int64_t IntrinsicMesh::euler_characteristic() const {
  int64_t used = 0;
  for (uint32_t v = 0; v < vertex_count(); ++v) used += vertex_he[v] != kInvalid;
  return used - int64_t(edge_count()) + int64_t(face_count());
}

void IntrinsicMesh::compute_signposts() {
  signpost.assign(halfedge_count(), 0.0);
  angle_sum.assign(vertex_count(), 0.0);
  for (uint32_t v = 0; v < vertex_count(); ++v) {
    const uint32_t start = vertex_he[v];
    if (start == kInvalid) continue;
    double angle = 0;
    uint32_t h = start;
    do {
      signpost[h] = angle;
      angle += corner_angle(h);
      h = ccw_next(h);
    } while (h != kInvalid && h != start);
    angle_sum[v] = angle;
  }
}

IntrinsicMesh build_input_mesh(const std::vector<double>& positions, const std::vector<uint32_t>& triangles,
                               std::vector<uint32_t>* kept_triangles, MeshBuildReport* report) {
  MeshBuildReport rep;
  IntrinsicMesh m;
  const uint32_t nv = static_cast<uint32_t>(positions.size() / 3);
  const uint32_t nt = static_cast<uint32_t>(triangles.size() / 3);
  for (double p : positions)
    if (!std::isfinite(p)) fail(MOLDTEX_ERROR_INVALID_MESH, "The mesh has a vertex with a non-finite coordinate.");
  std::vector<uint32_t> kept;
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t* v = &triangles[3ull * t];
    for (int k = 0; k < 3; ++k)
      if (v[k] >= nv) fail(MOLDTEX_ERROR_INVALID_MESH, "A triangle refers to a vertex that does not exist.");
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      ++rep.dropped_triangles;
      continue;
    }
    kept.push_back(t);
  }

  // Directed edge (u, v) -> halfedge; an edge gets halfedge 2e for the direction seen
  // first and 2e+1 for the other.
  std::unordered_map<uint64_t, uint32_t> directed;
  directed.reserve(kept.size() * 4);
  const uint32_t nf = static_cast<uint32_t>(kept.size());
  m.face_he.assign(nf, kInvalid);
  uint32_t bad_edges = 0;
  auto key = [](uint32_t u, uint32_t v) { return (uint64_t(u) << 32) | v; };
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t* v = &triangles[3ull * kept[f]];
    uint32_t hs[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = v[k], b = v[(k + 1) % 3];
      if (directed.count(key(a, b))) {
        ++bad_edges;
        hs[k] = kInvalid;
        continue;
      }
      auto rev = directed.find(key(b, a));
      uint32_t h;
      if (rev != directed.end()) {
        h = rev->second ^ 1u;
      } else {
        h = m.halfedge_count();
        for (int s = 0; s < 2; ++s) {
          m.he_next.push_back(kInvalid);
          m.he_vertex.push_back(s == 0 ? a : b);
          m.he_face.push_back(kInvalid);
        }
        const double* pa = &positions[3ull * a];
        const double* pb = &positions[3ull * b];
        m.length.push_back(std::sqrt((pa[0] - pb[0]) * (pa[0] - pb[0]) + (pa[1] - pb[1]) * (pa[1] - pb[1]) +
                                     (pa[2] - pb[2]) * (pa[2] - pb[2])));
      }
      directed[key(a, b)] = h;
      hs[k] = h;
    }
    if (hs[0] == kInvalid || hs[1] == kInvalid || hs[2] == kInvalid) continue;
    m.link_face(f, hs[0], hs[1], hs[2]);
  }

  // Vertex fans: a manifold vertex's triangles form one fan (a disk, or a half-disk
  // starting at a boundary edge).
  m.vertex_he.assign(nv, kInvalid);
  m.boundary.assign(nv, 0);
  std::vector<uint32_t> incident(nv, 0), boundary_starts(nv, 0);
  for (uint32_t h = 0; h < m.halfedge_count(); ++h) {
    if (m.he_face[h] == kInvalid) {
      if (h % 2 == 0 || m.he_face[h ^ 1u] != kInvalid) ++rep.boundary_edges;
      continue;
    }
    const uint32_t v = m.he_vertex[h];
    ++incident[v];
    if (m.he_face[h ^ 1u] == kInvalid) {
      ++boundary_starts[v];
      m.vertex_he[v] = h;
      m.boundary[v] = 1;
    } else if (m.vertex_he[v] == kInvalid) {
      m.vertex_he[v] = h;
    }
  }
  uint32_t bad_vertices = 0;
  if (bad_edges == 0) {
    for (uint32_t v = 0; v < nv; ++v) {
      if (m.vertex_he[v] == kInvalid) {
        ++rep.unused_vertices;
        continue;
      }
      uint32_t count = 0;
      uint32_t h = m.vertex_he[v];
      do {
        ++count;
        h = m.ccw_next(h);
      } while (h != kInvalid && h != m.vertex_he[v] && count <= incident[v]);
      if (boundary_starts[v] > 1 || count != incident[v]) ++bad_vertices;
    }
  }
  if (bad_edges || bad_vertices) {
    std::ostringstream msg;
    msg << "The mesh is not manifold (";
    if (bad_edges) msg << bad_edges << " edge" << (bad_edges > 1 ? "s" : "") << " shared by more than two faces or by two faces with opposite normals";
    if (bad_edges && bad_vertices) msg << ", ";
    if (bad_vertices) msg << bad_vertices << " vertex" << (bad_vertices > 1 ? "es" : "") << " joining separate fans of faces";
    msg << "): the intrinsic triangulation needs a manifold surface. In Edit Mode, Select > Select All by "
           "Trait > Non Manifold shows them; split them (Edge Split, or Separate) or recalculate normals.";
    fail(MOLDTEX_ERROR_INVALID_MESH, msg.str());
  }
  if (kept_triangles) *kept_triangles = kept;
  if (report) *report = rep;
  return m;
}

}  // namespace moldtex::intrinsic
