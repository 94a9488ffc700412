// The tangent step: walk a straightest path over the surface (supplementary Alg. 1).
//
// The walker keeps its position as barycentric weights and its heading as a unit vector
// in the isometric frame of the current triangle. Reaching an edge, it unfolds the
// heading about that edge into the neighbour's frame (keeping the angle to the edge,
// hence a geodesic), or reflects it at an open boundary (a bounce). Any number of edges
// may be crossed in one step; the distance travelled never depends on how the step is
// split into substeps.
#pragma once
#include <cmath>

#include "surface/surface.h"

namespace moldtex {

struct Walker {
  uint32_t triangle;
  float bary[3];
  Vec2 heading;  // unit vector in the local frame of `triangle`
};

// Enough for any sane step; stops a walker caught in a degenerate vertex fan.
constexpr int kMaxCrossingsPerWalk = 4096;
// Minimum sine between heading and edge after a crossing, so a walker that grazes an
// edge always enters the next triangle instead of bouncing between two forever.
constexpr float kMinCrossingSine = 1e-4f;

inline Vec2 frame_corner(const TriangleFrame& f, int c) {
  return c == 0 ? Vec2{0.f, 0.f} : (c == 1 ? Vec2{f.a, 0.f} : Vec2{f.bx, f.by});
}

inline Vec2 unit(Vec2 v) {
  float n = std::sqrt(v.x * v.x + v.y * v.y);
  return n > 0 ? Vec2{v.x / n, v.y / n} : Vec2{1.f, 0.f};
}

// Keeps barycentrics on the simplex despite rounding.
inline void clamp_bary(float b[3]) {
  for (int i = 0; i < 3; ++i) b[i] = b[i] < 0.f ? 0.f : b[i];
  float s = b[0] + b[1] + b[2];
  if (s > 0.f) {
    float inv = 1.f / s;
    b[0] *= inv;
    b[1] *= inv;
    b[2] *= inv;
  } else {
    b[0] = b[1] = b[2] = 1.f / 3.f;
  }
}

// Walks `length` 3D units. on_event(walker, is_bounce) is called after every edge
// crossing or bounce (for recording paths). Returns the number of crossings and bounces.
template <class OnEvent>
inline int walk(const TriangleFrame* frames, const std::array<AdjacencyCode, 3>* adjacency,
                Walker& w, float length, OnEvent&& on_event) {
  float remaining = length;
  for (int events = 0;; ++events) {
    const TriangleFrame& f = frames[w.triangle];
    // Heading in barycentric rates: Q * (db1, db2) = heading with Q = [[a, bx], [0, by]].
    float db2 = w.heading.y * f.inv_by;
    float db1 = (w.heading.x - f.bx * db2) * f.inv_a;
    float db[3] = {-(db1 + db2), db1, db2};
    float travel = remaining;
    int exit = -1;
    for (int i = 0; i < 3; ++i)
      if (db[i] < 0.f) {
        float tau = w.bary[i] > 0.f ? -w.bary[i] / db[i] : 0.f;
        if (tau < travel) {
          travel = tau;
          exit = i;
        }
      }
    for (int i = 0; i < 3; ++i) w.bary[i] += travel * db[i];
    if (exit < 0 || events >= kMaxCrossingsPerWalk) {
      clamp_bary(w.bary);
      return events;
    }
    w.bary[exit] = 0.f;
    clamp_bary(w.bary);
    remaining -= travel;

    const int j = (exit + 1) % 3, k = (exit + 2) % 3;
    const Vec2 e = f.edge[exit];
    const Vec2 inward{-e.y, e.x};  // corners are counter-clockwise in every frame
    const float along = w.heading.x * e.x + w.heading.y * e.y;
    const float across = std::fmax(std::fabs(w.heading.x * inward.x + w.heading.y * inward.y),
                                   kMinCrossingSine);
    const AdjacencyCode code = adjacency[w.triangle][exit];
    if (code == kNoNeighbour) {
      // Bounce: mirror the heading about the boundary edge.
      w.heading = unit(Vec2{along * e.x + across * inward.x, along * e.y + across * inward.y});
      on_event(w, true);
      continue;
    }
    const uint32_t next = code >> 3;
    const int edge = static_cast<int>((code >> 1) & 3u);
    const bool same_direction = code & 1u;
    const int jn = (edge + (same_direction ? 1 : 2)) % 3;  // corner of `next` equal to j
    const int kn = (edge + (same_direction ? 2 : 1)) % 3;  // corner of `next` equal to k
    const float bj = w.bary[j], bk = w.bary[k];
    w.bary[edge] = 0.f;
    w.bary[jn] = bj;
    w.bary[kn] = bk;
    // The shared edge runs j -> k; in `next` that is its counter-clockwise tangent, or
    // the reverse when `next` is wound the other way round.
    const Vec2 ccw = frames[next].edge[edge];
    const Vec2 en = same_direction ? ccw : Vec2{-ccw.x, -ccw.y};
    const Vec2 inward_next{-ccw.y, ccw.x};
    w.heading = unit(Vec2{along * en.x + across * inward_next.x, along * en.y + across * inward_next.y});
    w.triangle = next;
    on_event(w, false);
  }
}

inline void rotate(Vec2& v, float c, float s) {
  v = Vec2{c * v.x - s * v.y, s * v.x + c * v.y};
}

}  // namespace moldtex
