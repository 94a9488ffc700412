#include "pattern_measures.h"

#include <algorithm>
#include <cmath>

namespace mtx {

double TexelLength(const Mesh& m, uint32_t size) {
  return std::sqrt(m.total_area() / (m.total_uv_area() * double(size) * size));
}

TexelGeometry Texels(const Mesh& m, uint32_t W, uint32_t H) {
  TexelGeometry g;
  g.width = W;
  g.height = H;
  const double nan = std::nan("");
  g.position.assign(size_t(W) * H, Vec3{nan, nan, nan});
  g.area.assign(size_t(W) * H, 0.0);
  g.triangle.assign(size_t(W) * H, -1);
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    const Vec2 a = m.corner_uv(t, 0), b = m.corner_uv(t, 1), c = m.corner_uv(t, 2);
    const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if (std::fabs(det) < 1e-14) continue;
    const double per_texel = m.area(t) / (std::fabs(det) / 2) / (double(W) * H);
    const int x0 = std::max(0, int(std::floor(std::min({a[0], b[0], c[0]}) * W)) - 1);
    const int x1 = std::min(int(W) - 1, int(std::ceil(std::max({a[0], b[0], c[0]}) * W)));
    const int y0 = std::max(0, int(std::floor(std::min({a[1], b[1], c[1]}) * H)) - 1);
    const int y1 = std::min(int(H) - 1, int(std::ceil(std::max({a[1], b[1], c[1]}) * H)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double u = (x + 0.5) / W, v = (y + 0.5) / H;
        const double l1 = ((u - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (v - a[1])) / det;
        const double l2 = ((b[0] - a[0]) * (v - a[1]) - (u - a[0]) * (b[1] - a[1])) / det;
        const double l0 = 1 - l1 - l2;
        if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
        const size_t i = size_t(y) * W + x;
        g.triangle[i] = int(t);
        g.area[i] = per_texel;
        g.position[i] = add(add(scale(m.corner(t, 0), l0), scale(m.corner(t, 1), l1)), scale(m.corner(t, 2), l2));
      }
  }
  return g;
}

double Mean(const TexelGeometry& g, const std::vector<double>& field,
            const std::function<bool(uint32_t x, uint32_t y)>& in) {
  double a = 0, s = 0;
  for (uint32_t y = 0; y < g.height; ++y)
    for (uint32_t x = 0; x < g.width; ++x) {
      const size_t i = size_t(y) * g.width + x;
      if (!g.inside(i) || !in(x, y)) continue;
      a += g.area[i];
      s += g.area[i] * field[i];
    }
  return a > 0 ? s / a : 0;
}

double CharacteristicLength(const TexelGeometry& g, const std::vector<double>& f, double bin,
                            double max_distance, double level) {
  double mean = 0, area = 0;
  for (size_t i = 0; i < f.size(); ++i)
    if (g.inside(i)) {
      mean += g.area[i] * f[i];
      area += g.area[i];
    }
  mean /= area;
  double var = 0;
  for (size_t i = 0; i < f.size(); ++i)
    if (g.inside(i)) var += g.area[i] * (f[i] - mean) * (f[i] - mean);
  var /= area;
  const int bins = int(max_distance / bin) + 1;
  std::vector<double> sum(bins, 0), weight(bins, 0);
  const int W = int(g.width), H = int(g.height);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      if (!g.inside(i)) continue;
      for (int axis = 0; axis < 2; ++axis)
        for (int k = 1;; ++k) {
          const int nx = axis == 0 ? (x + k) % W : x, ny = axis == 1 ? (y + k) % H : y;
          const size_t j = size_t(ny) * W + nx;
          if (!g.inside(j)) break;
          const double d = norm(sub(g.position[i], g.position[j]));
          if (d >= max_distance || k > W) break;
          const int b = int(d / bin);
          const double w = std::sqrt(g.area[i] * g.area[j]);
          sum[b] += w * (f[i] - mean) * (f[j] - mean);
          weight[b] += w;
        }
    }
  double previous = 1.0 - level, previous_d = 0.0;
  for (int b = 0; b < bins; ++b) {
    if (weight[b] <= 0) continue;
    const double c = sum[b] / weight[b] / var - level, d = (b + 0.5) * bin;
    if (c <= 0) return previous_d + (d - previous_d) * previous / (previous - c);
    previous = c;
    previous_d = d;
  }
  return max_distance;
}

double GradientLength(const TexelGeometry& g, const std::vector<double>& f) {
  return GradientLength(g, f, [](uint32_t, uint32_t) { return true; });
}

double GradientLength(const TexelGeometry& g, const std::vector<double>& f,
                      const std::function<bool(uint32_t x, uint32_t y)>& in) {
  double slope = 0, weight = 0, mean = 0, area = 0;
  for (uint32_t y = 0; y < g.height; ++y)
    for (uint32_t x = 0; x < g.width; ++x) {
      const size_t i = size_t(y) * g.width + x;
      if (!g.inside(i) || !in(x, y)) continue;
      mean += g.area[i] * f[i];
      area += g.area[i];
      for (int axis = 0; axis < 2; ++axis) {
        if ((axis == 0 && x + 1 >= g.width) || (axis == 1 && y + 1 >= g.height)) continue;
        const size_t j = axis == 0 ? i + 1 : i + g.width;
        if (!g.inside(j)) continue;
        const double d = norm(sub(g.position[i], g.position[j]));
        if (!(d > 0)) continue;
        const double w = std::sqrt(g.area[i] * g.area[j]);
        slope += w * std::fabs(f[j] - f[i]) / d;
        weight += w;
      }
    }
  return slope > 0 ? (mean / area) / (slope / weight) : 0.0;
}

}  // namespace mtx
