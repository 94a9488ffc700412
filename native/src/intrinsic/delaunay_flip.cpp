#include "intrinsic/delaunay_flip.h"

#include <cmath>
#include <deque>
#include <unordered_set>

namespace moldtex::intrinsic {

double opposite_angle_sum(const IntrinsicMesh& m, uint32_t e) {
  const uint32_t h = 2 * e, t = 2 * e + 1;
  if (m.he_face[h] == kInvalid || m.he_face[t] == kInvalid) return 0.0;
  // The angle opposite h sits at the tail of prev(h).
  return m.corner_angle(m.prev(h)) + m.corner_angle(m.prev(t));
}

bool is_delaunay(const IntrinsicMesh& m, uint32_t e, double tolerance) {
  return opposite_angle_sum(m, e) <= kPi + tolerance;
}

bool flip_edge(IntrinsicMesh& m, uint32_t e) {
  const uint32_t h = 2 * e, t = 2 * e + 1;
  const uint32_t f1 = m.he_face[h], f2 = m.he_face[t];
  if (f1 == kInvalid || f2 == kInvalid || f1 == f2) return false;
  // Face f1 = (a, b, c): h = a->b, hbc = b->c, hca = c->a. Face f2 = (b, a, d):
  // t = b->a, had = a->d, hdb = d->b.
  const uint32_t hbc = m.next(h), hca = m.next(hbc), had = m.next(t), hdb = m.next(had);
  const uint32_t a = m.tail(h), b = m.tail(t), c = m.tail(hca), d = m.tail(hdb);
  // Convex at a and at b (the two corners the flip splits).
  const double angle_a = m.corner_angle(h) + m.corner_angle(had);
  const double angle_b = m.corner_angle(hbc) + m.corner_angle(t);
  if (!(angle_a < kPi) || !(angle_b < kPi)) return false;
  // Layout: a at the origin, b on +x, c above, d below.
  const double l = m.length[e];
  const double lac = m.len(hca), lbc = m.len(hbc), lad = m.len(had), lbd = m.len(hdb);
  const double cx = (l * l + lac * lac - lbc * lbc) / (2 * l);
  const double cy = 2 * triangle_area(l, lac, lbc) / l;
  const double dx = (l * l + lad * lad - lbd * lbd) / (2 * l);
  const double dy = -2 * triangle_area(l, lad, lbd) / l;
  const double new_length = std::hypot(cx - dx, cy - dy);
  if (!(new_length > 0) || !std::isfinite(new_length)) return false;

  // New faces: f1 = (d, c, a) with h = d->c, hca, had; f2 = (c, d, b) with t = c->d, hdb, hbc.
  m.he_vertex[h] = d;
  m.he_vertex[t] = c;
  m.link_face(f1, h, hca, had);
  m.link_face(f2, t, hdb, hbc);
  m.length[e] = new_length;
  if (m.vertex_he[a] == h) m.vertex_he[a] = had;
  if (m.vertex_he[b] == t) m.vertex_he[b] = hbc;
  // Signposts: d->c follows d->b counter-clockwise across the corner of f2 at d; c->d
  // follows c->a across the corner of f1 at c.
  m.signpost[h] = wrap_angle(m.signpost[hdb] + m.corner_angle(hdb), m.angle_sum[d]);
  m.signpost[t] = wrap_angle(m.signpost[hca] + m.corner_angle(hca), m.angle_sum[c]);
  return true;
}

FlipReport flip_to_delaunay(IntrinsicMesh& m, std::vector<uint32_t> queue, uint64_t max_flips,
                            std::vector<uint32_t>* touched_faces) {
  FlipReport report;
  const uint32_t ne = m.edge_count();
  if (max_flips == 0) max_flips = 1000ull * ne + 1000;
  // Queue membership: a flag per edge for a full pass; a hash set when only a few edges
  // are queued (after one insertion), so that pass costs O(changes), not O(edges).
  const bool full = queue.empty();
  std::vector<uint8_t> flags(full ? ne : 0, 0);
  std::unordered_set<uint32_t> members;
  auto is_queued = [&](uint32_t e) { return full ? flags[e] != 0 : members.count(e) != 0; };
  auto set_queued = [&](uint32_t e, bool on) {
    if (full)
      flags[e] = on;
    else if (on)
      members.insert(e);
    else
      members.erase(e);
  };
  std::deque<uint32_t> q;
  auto push = [&](uint32_t e) {
    if (!is_queued(e)) q.push_back(e), set_queued(e, true);
  };
  if (full)
    for (uint32_t e = 0; e < ne; ++e) push(e);
  else
    for (uint32_t e : queue) push(e);
  while (!q.empty()) {
    const uint32_t e = q.front();
    q.pop_front();
    set_queued(e, false);
    if (m.is_boundary_edge(e) || is_delaunay(m, e)) continue;
    if (report.flips >= max_flips) {
      report.capped = true;
      break;
    }
    if (!flip_edge(m, e)) continue;
    ++report.flips;
    const uint32_t h = 2 * e, t = 2 * e + 1;
    if (touched_faces) touched_faces->push_back(m.he_face[h]), touched_faces->push_back(m.he_face[t]);
    for (uint32_t g : {m.next(h), m.prev(h), m.next(t), m.prev(t)}) push(IntrinsicMesh::edge(g));
  }
  return report;
}

}  // namespace moldtex::intrinsic
