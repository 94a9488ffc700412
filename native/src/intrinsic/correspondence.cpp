#include "intrinsic/correspondence.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "intrinsic/mollification.h"
#include "surface/surface.h"

namespace moldtex::intrinsic {
namespace {

Vec2d unit(Vec2d a) {
  const double n = norm(a);
  return n > 0 ? (1.0 / n) * a : Vec2d{1, 0};
}

// Clamps tiny negative weights (round-off) to 0 and renormalises.
void clean(std::array<double, 3>& b) {
  double s = 0;
  for (double& x : b) s += (x = std::max(x, 0.0));
  if (s > 0)
    for (double& x : b) x /= s;
  else
    b = {1.0 / 3, 1.0 / 3, 1.0 / 3};
}

}  // namespace

TraceResult trace_from_point(const IntrinsicMesh& m, const SurfacePoint& start, Vec2d dir, double distance) {
  TraceResult r;
  r.point = start;
  r.direction = unit(dir);
  if (!(distance > 0) || !(norm(dir) > 0)) return r;
  uint32_t f = start.face;
  auto P = m.layout(f);
  auto beta = start.bary;
  Vec2d d = unit(dir);
  double remaining = distance;
  const uint64_t cap = 8ull * m.face_count() + 1000;
  for (uint64_t step = 0;; ++step) {
    if (step > cap) {
      r.complete = false;
      break;
    }
    // Along p + t d the weights change at the constant rate gamma (they still sum to 1).
    const double area2 = cross(P[1] - P[0], P[2] - P[0]);
    std::array<double, 3> gamma;
    double gamma_scale = 0;
    for (int i = 0; i < 3; ++i) {
      gamma[i] = cross(P[(i + 2) % 3] - P[(i + 1) % 3], d) / area2;
      gamma_scale = std::max(gamma_scale, std::abs(gamma[i]));
    }
    // A line along an edge (a boundary edge, an edge through the start vertex) has
    // gamma ~ 0 there, of either sign by round-off: it does not leave through that edge.
    const double parallel = 1e-12 * gamma_scale;
    int exit = -1;
    double tmin = HUGE_VAL;
    for (int i = 0; i < 3; ++i) {
      if (!(gamma[i] < -parallel)) continue;
      const double t = std::max(beta[i], 0.0) / -gamma[i];
      if (t < tmin) tmin = t, exit = i;
    }
    if (exit < 0 || tmin >= remaining) {
      for (int i = 0; i < 3; ++i) beta[i] += remaining * gamma[i];
      clean(beta);
      r.point = {f, beta};
      r.direction = d;
      return r;
    }
    for (int i = 0; i < 3; ++i) beta[i] += tmin * gamma[i];
    beta[exit] = 0;
    clean(beta);
    remaining -= tmin;
    const uint32_t h = m.face_halfedges(f)[(exit + 1) % 3];  // corner exit+1 -> exit+2
    const uint32_t tw = IntrinsicMesh::twin(h);
    if (m.he_face[tw] == kInvalid) {
      r.point = {f, beta};
      r.direction = d;
      r.boundary_he = h;
      return r;
    }
    // Unfold into the neighbour: keep the components of d along the edge and across it.
    const int i1 = (exit + 1) % 3, i2 = (exit + 2) % 3;
    const double s = beta[i2] / std::max(beta[i1] + beta[i2], 1e-300);  // from tail(h) to head(h)
    const Vec2d th = unit(P[i2] - P[i1]);
    const double along = dot(d, th), across = cross(th, d);
    const uint32_t g = m.he_face[tw];
    const auto Q = m.layout(g);
    const int k = m.corner_index(tw);  // tw runs head(h) = corner k -> tail(h) = corner k+1
    const Vec2d th2 = unit(Q[k] - Q[(k + 1) % 3]);
    d = unit(along * th2 + across * Vec2d{-th2.y, th2.x});
    std::array<double, 3> nb{};
    nb[k] = s;
    nb[(k + 1) % 3] = 1 - s;
    nb[(k + 2) % 3] = 0;
    f = g;
    P = Q;
    beta = nb;
    ++r.faces;
  }
  r.point = {f, beta};
  r.direction = d;
  return r;
}

TraceResult trace_from_vertex(const IntrinsicMesh& m, uint32_t v, double angle, double distance) {
  if (m.vertex_he[v] == kInvalid) {  // a vertex no face uses: nowhere to go
    TraceResult r;
    r.complete = false;
    return r;
  }
  const double total = m.angle_sum[v];
  uint32_t best = kInvalid;
  double best_off = 0, best_miss = HUGE_VAL;
  const uint32_t start = m.vertex_he[v];
  uint32_t h = start;
  // Angles at a boundary vertex run over [0, total] without wrapping around.
  if (m.boundary[v]) angle = std::clamp(angle, 0.0, total);
  do {
    const double c = m.corner_angle(h);
    double off = m.boundary[v] ? angle - m.signpost[h] : wrap_angle(angle - m.signpost[h], total);
    if (m.boundary[v] && off >= -1e-12 && off < 0) off = 0;  // round-off at the first edge
    if (off >= 0 && off <= c) {
      best = h, best_off = off;
      break;
    }
    // Outside this wedge (round-off): remember the nearest wedge side, by how far the
    // angle lies past this wedge's end or before its start (a boundary vertex's angles
    // do not wrap around: only the side it is on counts).
    const double miss_end = off > c ? off - c : HUGE_VAL;
    const double miss_start = off < 0 ? -off : (m.boundary[v] ? HUGE_VAL : total - off);
    if (std::min(miss_end, miss_start) < best_miss) {
      best_miss = std::min(miss_end, miss_start);
      best = h;
      best_off = miss_end < miss_start ? c : 0.0;
    }
    h = m.ccw_next(h);
  } while (h != kInvalid && h != start);
  const uint32_t f = m.he_face[best];
  const int k = m.corner_index(best);
  const auto P = m.layout(f);
  const Vec2d e = unit(P[(k + 1) % 3] - P[k]);
  const double c = std::cos(best_off), s = std::sin(best_off);
  const Vec2d d{c * e.x - s * e.y, s * e.x + c * e.y};
  SurfacePoint p;
  p.face = f;
  p.bary[k] = 1;
  return trace_from_point(m, p, d, distance);
}

double tangent_angle(const IntrinsicMesh& m, uint32_t f, int k, Vec2d dir) {
  const uint32_t h = m.face_halfedges(f)[k];
  const auto P = m.layout(f);
  const Vec2d e = P[(k + 1) % 3] - P[k];
  const double a = std::atan2(cross(e, dir), dot(e, dir));
  const uint32_t v = m.tail(h);
  // A boundary vertex's angles do not wrap: the direction along its last boundary edge
  // is angle_sum, not 0.
  if (m.boundary[v]) return std::clamp(m.signpost[h] + a, 0.0, m.angle_sum[v]);
  return wrap_angle(m.signpost[h] + a, m.angle_sum[v]);
}

IntrinsicTriangulation build_intrinsic_triangulation(const std::vector<double>& positions,
                                                     const std::vector<uint32_t>& triangles, double margin) {
  IntrinsicTriangulation T;
  T.positions = positions;
  MeshBuildReport rep;
  T.input = build_input_mesh(positions, triangles, &T.input_triangle, &rep);
  if (T.input.face_count() == 0)
    fail(MOLDTEX_ERROR_INVALID_MESH, "The mesh has no triangle with three distinct vertices.");
  T.dropped_triangles = rep.dropped_triangles;
  T.triangles.resize(3ull * T.input_triangle.size());
  for (size_t f = 0; f < T.input_triangle.size(); ++f)
    for (int k = 0; k < 3; ++k) T.triangles[3 * f + k] = triangles[3ull * T.input_triangle[f] + k];
  T.mean_edge = mean_edge_length(T.input);
  if (!(T.mean_edge > 0)) fail(MOLDTEX_ERROR_INVALID_MESH, "Every edge of the mesh has zero length.");
  T.mollify_epsilon = mollify(T.input, margin * T.mean_edge);
  T.input.compute_signposts();
  T.mesh = T.input;
  const uint32_t nv = T.input.vertex_count();
  T.input_vertex_count = nv;
  Correspondence& c = T.corr;
  c.location.assign(nv, SurfacePoint{});
  c.frame_angle.assign(nv, 0.0);
  for (uint32_t v = 0; v < nv; ++v) {
    const uint32_t h = T.input.vertex_he[v];
    if (h == kInvalid) continue;
    c.location[v].face = T.input.he_face[h];
    c.location[v].bary[T.input.corner_index(h)] = 1;
  }
  const uint32_t nh = T.input.halfedge_count();
  c.boundary_input_he.assign(nh, kInvalid);
  c.boundary_span.assign(nh, {0.0, 1.0});
  for (uint32_t h = 0; h < nh; ++h)
    if (T.input.he_face[h] != kInvalid && T.input.he_face[h ^ 1u] == kInvalid) c.boundary_input_he[h] = h;
  return T;
}

IntrinsicTriangulation build_intrinsic_triangulation(const moldtex::Surface& surface, double margin) {
  return build_intrinsic_triangulation(std::vector<double>(surface.positions.begin(), surface.positions.end()),
                                       surface.triangles, margin);
}

TraceResult trace_input_from_vertex(const IntrinsicTriangulation& T, uint32_t v, double angle, double distance) {
  if (v < T.input_vertex_count) return trace_from_vertex(T.input, v, angle, distance);
  const double a = T.corr.frame_angle[v] + angle;
  return trace_from_point(T.input, T.corr.location[v], Vec2d{std::cos(a), std::sin(a)}, distance);
}

namespace {
// The corner of face f (layout P) nearest to q.
int nearest_corner(const std::array<Vec2d, 3>& P, Vec2d q) {
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (norm(P[i] - q) < norm(P[k] - q)) k = i;
  return k;
}
}  // namespace

SurfacePoint to_input(const IntrinsicTriangulation& T, const SurfacePoint& p) {
  const auto P = T.mesh.layout(p.face);
  const Vec2d q = p.bary[0] * P[0] + p.bary[1] * P[1] + p.bary[2] * P[2];
  const int k = nearest_corner(P, q);
  const uint32_t v = T.mesh.tail(T.mesh.face_halfedges(p.face)[k]);
  const double dist = norm(q - P[k]);
  if (!(dist > 1e-14 * T.mean_edge)) return T.corr.location[v];
  return trace_input_from_vertex(T, v, tangent_angle(T.mesh, p.face, k, q - P[k]), dist).point;
}

SurfacePoint to_intrinsic(const IntrinsicTriangulation& T, const SurfacePoint& p) {
  const auto P = T.input.layout(p.face);
  const Vec2d q = p.bary[0] * P[0] + p.bary[1] * P[1] + p.bary[2] * P[2];
  const int k = nearest_corner(P, q);
  const uint32_t v = T.input.tail(T.input.face_halfedges(p.face)[k]);
  const double dist = norm(q - P[k]);
  if (!(dist > 1e-14 * T.mean_edge)) {
    const uint32_t h = T.mesh.vertex_he[v];
    SurfacePoint s;
    s.face = T.mesh.he_face[h];
    s.bary[T.mesh.corner_index(h)] = 1;
    return s;
  }
  return trace_from_vertex(T.mesh, v, tangent_angle(T.input, p.face, k, q - P[k]), dist).point;
}

std::array<double, 3> input_position(const IntrinsicTriangulation& T, const SurfacePoint& p) {
  std::array<double, 3> x{0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    const double* v = &T.positions[3ull * T.triangles[3ull * p.face + k]];
    for (int i = 0; i < 3; ++i) x[i] += p.bary[k] * v[i];
  }
  return x;
}

}  // namespace moldtex::intrinsic
