#include "domain/seam_neighbours.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "shared/walk.h"

namespace moldtex {

namespace {

constexpr int kDx[4] = {-1, 1, 0, 0}, kDy[4] = {0, 0, -1, 1};

// Is texel i an island texel of UV island `island`?
bool on_island(const Surface& s, const TextureDomain& d, size_t i, uint32_t island) {
  return d.classes[i] == MOLDTEX_TEXEL_INSIDE && s.island[d.texel_triangle[i]] == island;
}

// The island texel at the surface point one texel (dx, dy) away from island texel
// (x, y), reached by walking the surface; the texel itself if none is found.
uint32_t walk_to_neighbour(const Surface& s, const TextureDomain& d, uint32_t x, uint32_t y,
                           int dx, int dy) {
  const uint32_t self = y * d.width + x;
  const uint32_t t = static_cast<uint32_t>(d.texel_triangle[self]);
  const float* uv = &s.corner_uvs[6 * t];
  const double W = d.width, H = d.height;
  // UV -> local frame: J = Q T^-1 (as Surface::metric).
  const double t00 = uv[2] - uv[0], t10 = uv[3] - uv[1], t01 = uv[4] - uv[0], t11 = uv[5] - uv[1];
  const double det = t00 * t11 - t01 * t10;
  if (det == 0.0) return self;
  const double i00 = t11 / det, i01 = -t01 / det, i10 = -t10 / det, i11 = t00 / det;
  const TriangleFrame& f = s.frames[t];
  const double j00 = f.a * i00 + f.bx * i10, j01 = f.a * i01 + f.bx * i11;
  const double j10 = f.by * i10, j11 = f.by * i11;
  // The texel centre's barycentrics (clamped: a centre on a shared edge may lie a hair
  // outside the triangle that won it).
  const double du = (x + 0.5) / W - uv[0], dv = (y + 0.5) / H - uv[1];
  float b[3];
  b[1] = static_cast<float>((t11 * du - t01 * dv) / det);
  b[2] = static_cast<float>((-t10 * du + t00 * dv) / det);
  b[0] = 1.f - b[1] - b[2];
  mtx_clamp_bary(b);
  const double ou = dx / W, ov = dy / H;
  const double fx = j00 * ou + j01 * ov, fy = j10 * ou + j11 * ov;
  const double length = std::sqrt(fx * fx + fy * fy);
  if (!(length > 0.0) || !std::isfinite(length)) return self;
  mtx_walker w{t, {b[0], b[1], b[2]}, {static_cast<float>(fx / length), static_cast<float>(fy / length)}};
  mtx_walk(s.frames.data(), s.adjacency.data(), &w, static_cast<float>(length), nullptr, 0);
  float at[2];
  s.evaluate(w.triangle, w.bary, nullptr, at);
  // The landing point's texel, or the nearest texel of the landing island around it (the
  // point may lie within a texel of its island's border, its texel centre just outside).
  const uint32_t island = s.island[w.triangle];
  const double px = at[0] * W, py = at[1] * H;
  if (!std::isfinite(px) || !std::isfinite(py)) return self;
  const long cx = static_cast<long>(std::floor(std::clamp(px, -4.0, W + 4.0)));
  const long cy = static_cast<long>(std::floor(std::clamp(py, -4.0, H + 4.0)));
  double best = 1e300;
  uint32_t found = self;
  for (long ny = cy - kGutterWidth; ny <= cy + kGutterWidth; ++ny)
    for (long nx = cx - kGutterWidth; nx <= cx + kGutterWidth; ++nx) {
      if (nx < 0 || ny < 0 || nx >= static_cast<long>(d.width) || ny >= static_cast<long>(d.height)) continue;
      const size_t i = static_cast<size_t>(ny) * d.width + static_cast<size_t>(nx);
      if (!on_island(s, d, i, island)) continue;
      const double ex = nx + 0.5 - px, ey = ny + 0.5 - py, d2 = ex * ex + ey * ey;
      if (d2 < best) {
        best = d2;
        found = static_cast<uint32_t>(i);
      }
    }
  return found;
}

}  // namespace

void build_seam_neighbours(const Surface& s, TextureDomain& d, ThreadPool& pool) {
  const uint32_t W = d.width, H = d.height;
  // Per-row lists, joined in row order: the same table for any thread count.
  std::vector<std::vector<uint32_t>> rows(H);
  pool.parallel_for(H, 8, [&](size_t begin, size_t end) {
    for (size_t y = begin; y < end; ++y)
      for (uint32_t x = 0; x < W; ++x) {
        const size_t i = y * W + x;
        if (d.classes[i] != MOLDTEX_TEXEL_INSIDE) continue;
        const uint32_t island = s.island[d.texel_triangle[i]];
        uint32_t nb[4];
        bool seam = false;
        for (int k = 0; k < 4; ++k) {
          const long nx = static_cast<long>(x) + kDx[k], ny = static_cast<long>(y) + kDy[k];
          const bool inside_grid = nx >= 0 && ny >= 0 && nx < static_cast<long>(W) && ny < static_cast<long>(H);
          const size_t ni = inside_grid ? static_cast<size_t>(ny) * W + static_cast<size_t>(nx) : i;
          if (inside_grid && on_island(s, d, ni, island)) {
            nb[k] = static_cast<uint32_t>(ni);
          } else {
            seam = true;
            nb[k] = walk_to_neighbour(s, d, x, static_cast<uint32_t>(y), kDx[k], kDy[k]);
          }
        }
        if (!seam) continue;
        rows[y].push_back(static_cast<uint32_t>(i));
        rows[y].insert(rows[y].end(), nb, nb + 4);
      }
  });
  for (const auto& row : rows)
    for (size_t j = 0; j < row.size(); j += 5) {
      d.seam_texel.push_back(row[j]);
      d.seam_neighbour.insert(d.seam_neighbour.end(), row.begin() + j + 1, row.begin() + j + 5);
    }
}

}  // namespace moldtex
