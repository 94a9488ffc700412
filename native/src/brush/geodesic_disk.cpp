#include "brush/geodesic_disk.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <queue>
#include <utility>
#include <vector>

namespace moldtex {

namespace {

constexpr float kAlongRay = 0.5f;   // sample spacing along a ray, in texel widths
constexpr float kAcrossRays = 0.5f; // spacing between rays at the rim, in texel widths
constexpr float kMaxStepsPerRadius = 1024.f;
constexpr int kEventCapacity = 64;
constexpr size_t kMaxCentresPerTriangle = 64;
constexpr uint32_t kWidthMemo = 64;   // texel widths remembered per sampling pass
constexpr int kStuckCrossings = 32;    // edge crossings in one step (of <= a texel or r / 1024)
// Edge crossings a dab may walk (its sampling passes; the pilot a quarter more): ~0.3 s. Sane dabs cross a few edges per
// sample and stay far below (<= 4.3 million samples); only slivers narrower than a step
// reach it, and then the dab ends with the rays walked so far.
constexpr int64_t kMaxCrossingsPerDab = int64_t{1} << 24;

struct P3 {
  double x, y, z;
};

P3 position(const Surface& s, const Walker& w) {
  float p[3];
  s.evaluate(w.triangle, w.bary, p, nullptr);
  return {p[0], p[1], p[2]};
}

double length(P3 a, P3 b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}

Vec2 frame_point(const TriangleFrame& f, const float b[3]) {
  return {b[1] * f.a + b[2] * f.bx, b[2] * f.by};
}

// One sampling pass; returns the narrowest texel width met.
double sample_pass(const Surface& s, const Walker& start, float radius, uint32_t width,
                   uint32_t height, float step, float rim_spacing, DiskVisitor* visitor,
                   int64_t& budget) {
  double narrowest = texel_width(s, start.triangle, width, height);
  // Each triangle's texel width, remembered: a ray meets the same few triangles again
  // and again (on a sliver, two of them at every step).
  struct Met {
    uint32_t triangle = UINT32_MAX;
    double width = 0;
  };
  Met memo[kWidthMemo];
  auto meet = [&](uint32_t t) {
    if (s.degenerate[t]) return;
    Met& m = memo[t % kWidthMemo];
    if (m.triangle != t) m = {t, texel_width(s, t, width, height)};
    narrowest = std::min(narrowest, m.width);
  };
  if (!(step > 0.f)) return narrowest;  // no progress possible (radii >= 1e-30 never get here)
  const float two_pi = 2.f * std::numbers::pi_v<float>;
  const uint32_t rays = std::max<uint32_t>(
      8, static_cast<uint32_t>(std::ceil(two_pi * radius / std::max(rim_spacing, 1e-30f))));
  Walker events[kEventCapacity];
  for (uint32_t ray = 0; ray < rays && budget > 0; ++ray) {
    // Ray i = odd * 2^k is needed only where the rays that are multiples of 2^(k+1) lie
    // more than rim_spacing apart: beyond d = rim_spacing * rays / (2^(k+1) * 2 pi).
    float d_start = 0.f;
    if (ray != 0) {
      const uint32_t k = static_cast<uint32_t>(std::countr_zero(ray));
      const double apart = std::ldexp(1.0, static_cast<int>(k) + 1) * two_pi / rays;  // radians
      d_start = static_cast<float>(rim_spacing / apart);
    }
    Walker w = start;
    const float angle = two_pi * static_cast<float>(ray) / static_cast<float>(rays);
    w.heading = {std::cos(angle), std::sin(angle)};
    uint32_t first = 0;
    if (d_start >= radius) continue;
    if (d_start > 0.f) {
      first = static_cast<uint32_t>(std::ceil(d_start / step));
      if (static_cast<float>(first) * step > radius) continue;
      // Walk to the first sample in chunks of 16 steps (no visits before it).
      uint32_t done = 0;
      bool stuck = false;
      while (done < first && !stuck) {
        const uint32_t n = std::min<uint32_t>(16, first - done);
        const int c = mtx_walk(s.frames.data(), s.adjacency.data(), &w, static_cast<float>(n) * step, nullptr, 0);
        budget -= c;
        stuck = c >= MTX_MAX_CROSSINGS_PER_WALK;
        done += n;
      }
      if (stuck) continue;
    }
    float d = static_cast<float>(first) * step;
    if (visitor) visitor->visit(ray, w, d, true);
    meet(w.triangle);
    while (d < radius) {
      const bool last = radius - d <= step;
      const float len = last ? radius - d : step;
      const Walker before = w;
      const int crossings = mtx_walk(s.frames.data(), s.adjacency.data(), &w, len, events, kEventCapacity);
      budget -= crossings;
      // Crossings between the samples: the path length is the sum of straight 3D segments.
      double travelled = d;
      P3 at = crossings > 0 ? position(s, before) : P3{};
      for (int e = 0; e < std::min(crossings, kEventCapacity); ++e) {
        const P3 p = position(s, events[e]);
        travelled += length(at, p);
        at = p;
        meet(events[e].triangle);
        if (visitor) visitor->visit(ray, events[e], std::min(static_cast<float>(travelled), radius), false);
      }
      d = last ? radius : d + step;
      if (w.triangle != before.triangle) meet(w.triangle);
      if (visitor) visitor->visit(ray, w, d, true);
      // A step across this many edges is a ray caught bouncing in a sliver far narrower
      // than a texel (sane steps cross a few): it ends here, or a dab there would cost
      // thousands of crossings per sample (found by the fuzz target).
      if (crossings >= kStuckCrossings || budget <= 0) break;
    }
  }
  return narrowest;
}

}  // namespace

double texel_width(const Surface& s, uint32_t t, uint32_t width, uint32_t height) {
  if (s.degenerate[t]) return std::numeric_limits<double>::infinity();
  const auto g = s.metric(t);
  // The texel's image is the parallelogram spanned by J (1/W, 0) and J (0, 1/H): its
  // smallest width is its area over its longest side.
  const double su = std::sqrt(std::max(0.0, g[0])) / width, sv = std::sqrt(std::max(0.0, g[3])) / height;
  const double area = std::sqrt(std::max(0.0, g[0] * g[3] - g[1] * g[2])) / (double(width) * height);
  const double side = std::max(su, sv);
  return side > 0 && area > 0 ? area / side : std::numeric_limits<double>::infinity();
}

float disk_reach(const Surface& s, const moldtex_surface_point& center, float radius) {
  float c[3];
  float bary[3] = {center.bary[0], center.bary[1], center.bary[2]};
  mtx_clamp_bary(bary);
  s.evaluate(center.triangle, bary, c, nullptr);
  const P3 centre{c[0], c[1], c[2]};
  auto vertex = [&](uint32_t v) {
    return P3{s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]};
  };
  double farthest = 0;
  for (uint32_t v = 0; v < s.vertex_count(); ++v) farthest = std::max(farthest, length(centre, vertex(v)));
  if (radius <= farthest) return radius;
  // Dijkstra over the triangles the walker can enter (adjacency: walls excluded).
  const uint32_t nt = s.triangle_count();
  auto corner = [&](uint32_t t, int k) { return vertex(s.triangles[3 * t + k]); };
  auto centroid = [&](uint32_t t) {
    const P3 a = corner(t, 0), b = corner(t, 1), d = corner(t, 2);
    return P3{(a.x + b.x + d.x) / 3, (a.y + b.y + d.y) / 3, (a.z + b.z + d.z) / 3};
  };
  std::vector<double> dist(nt, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[center.triangle] = length(centre, centroid(center.triangle));
  queue.push({dist[center.triangle], center.triangle});
  double extent = 0;
  while (!queue.empty()) {
    const auto [d, t] = queue.top();
    queue.pop();
    if (d > dist[t]) continue;
    const P3 ct = centroid(t);
    double spread = 0;
    for (int k = 0; k < 3; ++k) spread = std::max(spread, length(ct, corner(t, k)));
    extent = std::max(extent, d + spread);
    for (int e = 0; e < 3; ++e) {
      const uint32_t code = s.adjacency[3 * t + e];
      if (code == kNoNeighbour) continue;
      const uint32_t n = code >> 3;
      const P3 a = corner(t, (e + 1) % 3), b = corner(t, (e + 2) % 3);
      const P3 mid{(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
      const double dn = d + length(ct, mid) + length(mid, centroid(n));
      if (dn < dist[n]) {
        dist[n] = dn;
        queue.push({dn, n});
      }
    }
  }
  return static_cast<float>(std::min<double>(radius, 2.0 * extent));
}

std::vector<uint8_t> reachable_triangles(const Surface& s, uint32_t triangle) {
  std::vector<uint8_t> reached(s.triangle_count(), 0);
  std::vector<uint32_t> stack{triangle};
  reached[triangle] = 1;
  while (!stack.empty()) {
    const uint32_t t = stack.back();
    stack.pop_back();
    for (int e = 0; e < 3; ++e) {
      const uint32_t code = s.adjacency[3 * t + e];
      if (code == kNoNeighbour || reached[code >> 3]) continue;
      reached[code >> 3] = 1;
      stack.push_back(code >> 3);
    }
  }
  return reached;
}

void sample_disk(const Surface& s, const moldtex_surface_point& center, float brush_radius,
                 uint32_t width, uint32_t height, DiskVisitor& visitor) {
  const float radius = disk_reach(s, center, brush_radius);
  Walker start{center.triangle, {center.bary[0], center.bary[1], center.bary[2]}, {1.f, 0.f}};
  mtx_clamp_bary(start.bary);
  const float min_step = radius / kMaxStepsPerRadius;
  // Pilot: 64 steps per radius, to find the texel widths around the centre.
  int64_t pilot_budget = kMaxCrossingsPerDab / 4, budget = kMaxCrossingsPerDab;
  double h = sample_pass(s, start, radius, width, height, radius / 64.f, radius / 64.f, nullptr, pilot_budget);
  for (int attempt = 0;; ++attempt) {
    const float step = std::max(min_step, static_cast<float>(kAlongRay * h));
    const float rim = std::max(min_step * (kAcrossRays / kAlongRay), static_cast<float>(kAcrossRays * h));
    visitor.begin(step);
    const double met = sample_pass(s, start, radius, width, height, step, rim, &visitor, budget);
    // Narrower texels than the pilot saw: sample again at their spacing (twice at most).
    if (attempt >= 2 || !(met < 0.7 * h) || step <= min_step || budget <= 0) break;
    h = met;
  }
}

void DiskDistance::begin(float step) {
  tolerance_ = 0.02f * step;
  centres_.clear();
  reached_.assign(surface_.triangle_count(), 0);
  last_triangle_ = UINT32_MAX;
  last_list_ = nullptr;
}

void DiskDistance::visit(uint32_t, const Walker& w, float distance, bool) {
  const Vec2 p = frame_point(surface_.frames[w.triangle], w.bary);
  const Vec2 c{p.x - distance * w.heading.x, p.y - distance * w.heading.y};
  if (w.triangle != last_triangle_) {
    last_list_ = &centres_[w.triangle];
    last_triangle_ = w.triangle;
    reached_[w.triangle] = 1;
  }
  std::vector<Vec2>& list = *last_list_;
  if (list.size() >= kMaxCentresPerTriangle) return;  // full: nothing more is recorded
  for (const Vec2& q : list)
    if (std::fabs(q.x - c.x) <= tolerance_ && std::fabs(q.y - c.y) <= tolerance_) return;
  list.push_back(c);
}

float DiskDistance::distance(uint32_t triangle, const float bary[3]) const {
  if (triangle >= reached_.size() || !reached_[triangle]) return std::numeric_limits<float>::infinity();
  auto it = centres_.find(triangle);
  if (it == centres_.end()) return std::numeric_limits<float>::infinity();
  const Vec2 p = frame_point(surface_.frames[triangle], bary);
  float best = std::numeric_limits<float>::infinity();
  for (const Vec2& c : it->second) best = std::min(best, std::hypot(p.x - c.x, p.y - c.y));
  return best;
}

}  // namespace moldtex
