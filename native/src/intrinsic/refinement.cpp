#include "intrinsic/refinement.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <set>
#include <sstream>

#include "common/error.h"
#include "intrinsic/delaunay_flip.h"

namespace moldtex::intrinsic {
namespace {

// Angle from vector u to vector w, counter-clockwise.
double angle_between(Vec2d u, Vec2d w) { return std::atan2(cross(u, w), dot(u, w)); }

// Angle between sides a and b of a triangle with opposite side c.
double angle_from_sides(double a, double b, double c) {
  return std::atan2(4.0 * triangle_area(a, b, c), a * a + b * b - c * c);
}

void push_correspondence_slots(Correspondence& c, uint32_t halfedges) {
  c.boundary_input_he.resize(halfedges, kInvalid);
  c.boundary_span.resize(halfedges, {0.0, 1.0});
}

std::array<uint32_t, 3> vertex_triple(const IntrinsicMesh& m, uint32_t f) {
  const auto h = m.face_halfedges(f);
  std::array<uint32_t, 3> k = {m.tail(h[0]), m.tail(h[1]), m.tail(h[2])};
  std::sort(k.begin(), k.end());
  return k;
}

}  // namespace

uint32_t insert_vertex(IntrinsicTriangulation& T, SurfacePoint p) {
  IntrinsicMesh& m = T.mesh;
  const uint32_t f = p.face;
  double s = 0;
  for (double& b : p.bary) s += (b = std::max(b, kMinInsertionBary));
  for (double& b : p.bary) b /= s;
  const auto P = m.layout(f);
  const Vec2d q = p.bary[0] * P[0] + p.bary[1] * P[1] + p.bary[2] * P[2];
  const auto hs = m.face_halfedges(f);
  uint32_t c[3];
  double turn[3];  // angle at corner k from its face edge to q
  for (int k = 0; k < 3; ++k) {
    c[k] = m.tail(hs[k]);
    turn[k] = angle_between(P[(k + 1) % 3] - P[k], q - P[k]);
  }

  const uint32_t v = m.vertex_count();
  m.vertex_he.push_back(kInvalid);
  m.angle_sum.push_back(2 * kPi);
  m.boundary.push_back(0);
  const uint32_t E = m.edge_count();
  for (int k = 0; k < 3; ++k) {
    m.length.push_back(norm(P[k] - q));
    m.he_vertex.push_back(c[k]);  // 2(E+k): c_k -> v
    m.he_vertex.push_back(v);     // 2(E+k)+1: v -> c_k
    for (int s2 = 0; s2 < 2; ++s2) {
      m.he_next.push_back(kInvalid);
      m.he_face.push_back(kInvalid);
      m.signpost.push_back(0.0);
    }
  }
  uint32_t F[3] = {f, m.face_count(), m.face_count() + 1};
  m.face_he.push_back(kInvalid);
  m.face_he.push_back(kInvalid);
  // Face F_k = (c_k, c_k+1, v): hs[k], c_k+1 -> v, v -> c_k.
  for (int k = 0; k < 3; ++k) m.link_face(F[k], hs[k], 2 * (E + (k + 1) % 3), 2 * (E + k) + 1);
  m.vertex_he[v] = 2 * E + 1;
  for (int k = 0; k < 3; ++k) {
    m.signpost[2 * (E + k)] = wrap_angle(m.signpost[hs[k]] + turn[k], m.angle_sum[c[k]]);
    m.signpost[2 * (E + k) + 1] = wrap_angle(angle_between(P[0] - q, P[k] - q), 2 * kPi);
  }

  // Input location: trace over the input mesh from the nearest corner.
  Correspondence& corr = T.corr;
  push_correspondence_slots(corr, m.halfedge_count());
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (norm(P[i] - q) < norm(P[k] - q)) k = i;
  const TraceResult r = trace_input_from_vertex(T, c[k], m.signpost[2 * (E + k)], m.length[E + k]);
  corr.location.push_back(r.point);
  // Arriving along direction d, the way back to c_k is -d: that is signpost(v -> c_k).
  corr.frame_angle.push_back(std::atan2(-r.direction.y, -r.direction.x) - m.signpost[2 * (E + k) + 1]);
  return v;
}

uint32_t split_boundary_edge(IntrinsicTriangulation& T, uint32_t h) {
  IntrinsicMesh& m = T.mesh;
  const uint32_t f = m.he_face[h], t = h ^ 1u;
  const uint32_t hbc = m.next(h), hca = m.next(hbc);
  const uint32_t c = m.tail(hca);
  const double L = m.len(h), lac = m.len(hca), lbc = m.len(hbc);
  const double half = 0.5 * L;
  const double lmc = 0.5 * std::sqrt(std::max(0.0, 2 * lac * lac + 2 * lbc * lbc - L * L));  // median

  const uint32_t v = m.vertex_count();
  m.vertex_he.push_back(kInvalid);
  m.angle_sum.push_back(kPi);
  m.boundary.push_back(1);
  const uint32_t E1 = m.edge_count(), E2 = E1 + 1;  // v-b and v-c
  m.length.push_back(half);
  m.length.push_back(lmc);
  const uint32_t b = m.head(h);
  const uint32_t tails[4] = {v, b, v, c};
  for (uint32_t tv : tails) {
    m.he_vertex.push_back(tv);
    m.he_next.push_back(kInvalid);
    m.he_face.push_back(kInvalid);
    m.signpost.push_back(0.0);
  }
  // vb = v->b and its outer side b->v (2 E1 + 1, no face); vc = v->c, cv = c->v.
  const uint32_t vb = 2 * E1, vc = 2 * E2, cv = 2 * E2 + 1;
  m.length[IntrinsicMesh::edge(h)] = half;
  m.he_vertex[t] = v;
  const uint32_t F2 = m.face_count();
  m.face_he.push_back(kInvalid);
  // f = (a, v, c): h, vc, hca. F2 = (v, b, c): vb, hbc, cv.
  m.link_face(f, h, vc, hca);
  m.link_face(F2, vb, hbc, cv);
  m.vertex_he[v] = vb;
  m.signpost[vb] = 0;
  m.signpost[vc] = angle_from_sides(half, lmc, lbc);
  m.signpost[cv] = wrap_angle(m.signpost[hca] + angle_from_sides(lac, lmc, half), m.angle_sum[c]);

  // Exactly halfway along the same input boundary edge.
  Correspondence& corr = T.corr;
  push_correspondence_slots(corr, m.halfedge_count());
  const uint32_t ih = corr.boundary_input_he[h];
  const auto span = corr.boundary_span[h];
  const double tm = 0.5 * (span[0] + span[1]);
  SurfacePoint loc;
  loc.face = T.input.he_face[ih];
  const int k = T.input.corner_index(ih);
  loc.bary[k] = 1 - tm;
  loc.bary[(k + 1) % 3] = tm;
  const auto Q = T.input.layout(loc.face);
  const Vec2d dir = Q[(k + 1) % 3] - Q[k];
  corr.location.push_back(loc);
  corr.frame_angle.push_back(std::atan2(dir.y, dir.x));
  corr.boundary_span[h] = {span[0], tm};
  corr.boundary_input_he[vb] = ih;
  corr.boundary_span[vb] = {tm, span[1]};
  return v;
}

RefineReport refine(IntrinsicTriangulation& T, const RefineOptions& options) {
  const double R = options.max_circumradius;
  if (!(R > 0) || !std::isfinite(R))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The circumradius bound of the intrinsic triangulation must be a positive number.");
  IntrinsicMesh& m = T.mesh;
  RefineReport rep;
  FlipReport fr = flip_to_delaunay(m);
  rep.flips += fr.flips;
  uint64_t cap = options.max_insertions;
  const double area = options.area > 0 ? options.area : m.total_area();
  if (cap == 0) cap = uint64_t(20.0 * std::min(area / (R * R), 1e12)) + 10ull * m.face_count() + 1000;

  // A face is left alone at a sharp input vertex v once both its edges at v are within
  // 2 R: its circumradius then comes from the small angle, not from its size.
  auto small_angle = [&](uint32_t f) {
    for (uint32_t h : m.face_halfedges(f)) {
      const uint32_t v = m.tail(h);
      if (v < T.input_vertex_count && m.angle_sum[v] < options.min_input_angle && m.len(h) <= 2 * R &&
          m.len(m.prev(h)) <= 2 * R)
        return true;
    }
    return false;
  };
  std::priority_queue<std::pair<double, uint32_t>> pq;
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const double r = m.circumradius(f);
    if (r > R) pq.push({r, f});
  }
  std::set<std::array<uint32_t, 3>> given_up;
  std::vector<uint32_t> touched, queue;
  bool flip_capped = fr.capped;
  const uint32_t start_vertices = m.vertex_count();
  uint64_t since_report = 0;
  while (!pq.empty() && !flip_capped) {
    if (options.progress && ++since_report == kProgressInterval) {
      since_report = 0;
      options.progress->check_cancel();
      const double grown = m.vertex_count() - start_vertices, to_grow = options.expected_vertices - start_vertices;
      options.progress->count.store(m.vertex_count(), std::memory_order_relaxed);
      options.progress->stage_fraction.store(to_grow > 0 ? std::min(0.99, grown / to_grow) : 0.5,
                                             std::memory_order_relaxed);
    }
    const uint32_t f = pq.top().second;
    pq.pop();
    if (!(m.circumradius(f) > R) || small_angle(f) || given_up.count(vertex_triple(m, f))) continue;
    if (rep.insertions + rep.boundary_splits >= cap) {
      rep.reason = StopReason::InsertionCap;
      break;
    }
    // Circumcentre in f's layout.
    const auto P = m.layout(f);
    const double x1 = P[1].x, x2 = P[2].x, y2 = P[2].y;
    const Vec2d cc{0.5 * x1, (x2 * x2 + y2 * y2 - x1 * x2) / (2 * y2)};
    const Vec2d g = (1.0 / 3) * (P[0] + P[1] + P[2]);
    SurfacePoint start;
    start.face = f;
    start.bary = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    const TraceResult tr = trace_from_point(m, start, cc - g, norm(cc - g));
    uint32_t v = kInvalid;
    if (tr.complete && tr.boundary_he != kInvalid) {
      if (m.len(tr.boundary_he) > 2 * kMinInsertionDistance * R) {
        v = split_boundary_edge(T, tr.boundary_he);
        ++rep.boundary_splits;
      }
    } else if (tr.complete) {
      const auto Q = m.layout(tr.point.face);
      const Vec2d q = tr.point.bary[0] * Q[0] + tr.point.bary[1] * Q[1] + tr.point.bary[2] * Q[2];
      // Ruppert's rule where the point landed: a boundary edge of that face whose
      // diametral circle contains the point is encroached: split it instead.
      const auto hs = m.face_halfedges(tr.point.face);
      uint32_t encroached = kInvalid;
      for (int k = 0; k < 3; ++k)
        if (m.he_face[hs[k] ^ 1u] == kInvalid && dot(Q[k] - q, Q[(k + 1) % 3] - q) < 0) encroached = hs[k];
      double nearest = HUGE_VAL;
      for (int k = 0; k < 3; ++k) nearest = std::min(nearest, norm(Q[k] - q));
      if (encroached != kInvalid) {
        if (m.len(encroached) > 2 * kMinInsertionDistance * R) {
          v = split_boundary_edge(T, encroached);
          ++rep.boundary_splits;
        }
      } else if (nearest > kMinInsertionDistance * R) {
        v = insert_vertex(T, tr.point);
        ++rep.insertions;
      }
    }
    if (v == kInvalid) {
      given_up.insert(vertex_triple(m, f));
      ++rep.given_up;
      continue;
    }
    // Flip around the new vertex: its link edges (and its own edges) may not be Delaunay.
    queue.clear();
    touched.clear();
    for (uint32_t h = m.vertex_he[v]; h != kInvalid;) {
      queue.push_back(IntrinsicMesh::edge(h));
      queue.push_back(IntrinsicMesh::edge(m.next(h)));
      touched.push_back(m.he_face[h]);
      h = m.ccw_next(h);
      if (h == m.vertex_he[v]) break;
    }
    fr = flip_to_delaunay(m, queue, 0, &touched);
    rep.flips += fr.flips;
    flip_capped = fr.capped;
    for (uint32_t tf : touched) {
      const double r = m.circumradius(tf);
      if (r > R) pq.push({r, tf});
    }
  }
  if (flip_capped) rep.reason = StopReason::FlipCap;

  for (uint32_t f = 0; f < m.face_count(); ++f) {
    if (!(m.circumradius(f) > R)) continue;
    if (small_angle(f))
      ++rep.skipped_small_angle;
    else
      ++rep.skipped_other;
  }
  std::ostringstream msg;
  if (rep.reason == StopReason::Converged) {
    msg << "Intrinsic triangulation refined to circumradius <= " << R << ": " << m.vertex_count() << " vertices, "
        << m.face_count() << " triangles";
    if (rep.skipped_small_angle + rep.skipped_other)
      msg << " (" << rep.skipped_small_angle << " triangles at sharp input corners and " << rep.skipped_other
          << " others left larger)";
    msg << ".";
  } else if (rep.reason == StopReason::InsertionCap) {
    msg << "Refinement of the intrinsic triangulation stopped after " << cap
        << " insertions with triangles still larger than the bound " << R << ": use a larger bound.";
  } else {
    msg << "Refinement of the intrinsic triangulation stopped: the Delaunay edge flips did not settle (a bug or "
           "extreme round-off; please report it).";
  }
  rep.message = msg.str();
  return rep;
}

}  // namespace moldtex::intrinsic
