#include "surface/unfolded_neighbours.h"

#include <cmath>

namespace moldtex {

namespace {

struct P2 {
  double x, y;
};

P2 corner(const TriangleFrame& f, int c) {
  const Vec2 q = frame_corner(f, c);
  return P2{q.x, q.y};
}

// An affine function of a frame point, g(q) = g0 + gx qx + gy qy.
struct Affine {
  double g0, gx, gy;
};

}  // namespace

void unfold_neighbours(Surface& s) {
  const uint32_t nt = s.triangle_count();
  s.unfolded.assign(size_t(nt) * 3 * MTX_UNFOLDED_FLOATS, 0.f);
  for (uint32_t t = 0; t < nt; ++t) {
    const TriangleFrame& f = s.frames[t];
    for (int i = 0; i < 3; ++i) {
      const AdjacencyCode code = s.adjacency[3 * t + i];
      if (code == kNoNeighbour) continue;
      const uint32_t n = code >> 3;
      const int ne = static_cast<int>((code >> 1) & 3u);
      const bool same_direction = code & 1u;
      // Corners of n equal to t's corners j = i + 1 and k = i + 2 (as mtx_walk_leg).
      const int jn = (ne + (same_direction ? 1 : 2)) % 3, kn = 3 - ne - jn;
      const P2 pi = corner(f, i), pj = corner(f, (i + 1) % 3), pk = corner(f, (i + 2) % 3);
      // n's third corner, seen from the shared edge in n's own frame: how far along the
      // edge (from j) and how far off it; in t's frame it lies that far beyond edge i.
      const TriangleFrame& g = s.frames[n];
      const P2 qj = corner(g, jn), qk = corner(g, kn), qo = corner(g, ne);
      const double ex = qk.x - qj.x, ey = qk.y - qj.y, en = std::sqrt(ex * ex + ey * ey);
      const double ox = qo.x - qj.x, oy = qo.y - qj.y;
      const double along = (ox * ex + oy * ey) / en, off = std::fabs(ox * ey - oy * ex) / en;
      const double tx = pk.x - pj.x, ty = pk.y - pj.y, tn = std::sqrt(tx * tx + ty * ty);
      const double ux = tx / tn, uy = ty / tn;
      // The normal of edge i pointing into t (toward corner i).
      double nx = -uy, ny = ux;
      if ((pi.x - pj.x) * nx + (pi.y - pj.y) * ny < 0) nx = -nx, ny = -ny;
      const P2 po{pj.x + along * ux - off * nx, pj.y + along * uy - off * ny};
      // n's weights over t's frame: q = pj + wk (pk - pj) + wo (po - pj).
      const double ax = pk.x - pj.x, ay = pk.y - pj.y, bx = po.x - pj.x, by = po.y - pj.y;
      const double det = ax * by - ay * bx;
      if (!(std::fabs(det) > 0)) continue;  // not reached: walls border degenerate triangles
      // wk = ((q - pj) x b) / det, wo = (a x (q - pj)) / det.
      const Affine wk{(-pj.x * by + pj.y * bx) / det, by / det, -bx / det};
      const Affine wo{(-ax * pj.y + ay * pj.x) / det, -ay / det, ax / det};
      const Affine wj{1 - wk.g0 - wo.g0, -wk.gx - wo.gx, -wk.gy - wo.gy};
      // The neighbour's own weights at its corners 1 and 2 (its corner 0's is 1 minus
      // these), so a trace carried across needs no reordering.
      auto weight_at = [&](int corner) { return corner == jn ? wj : (corner == kn ? wk : wo); };
      // In t's weights (b1, b2): q = (a b1 + bx b2, by b2).
      const Affine fs[2] = {weight_at(1), weight_at(2)};
      float* out = &s.unfolded[(size_t(t) * 3 + i) * MTX_UNFOLDED_FLOATS];
      for (int m = 0; m < 2; ++m) {
        out[3 * m] = static_cast<float>(fs[m].g0);
        out[3 * m + 1] = static_cast<float>(fs[m].gx * f.a);
        out[3 * m + 2] = static_cast<float>(fs[m].gx * f.bx + fs[m].gy * f.by);
      }
    }
  }
}

}  // namespace moldtex
