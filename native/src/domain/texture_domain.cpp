#include "domain/texture_domain.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <vector>

#include "domain/seam_neighbours.h"
#include "shared/field.h"
#include "shared/walk.h"

namespace moldtex {

size_t TextureDomain::bytes() const {
  return texel_triangle.capacity() * 4 + classes.capacity() + gutter_texel.capacity() * 4 +
         gutter_source.capacity() * 4 + triangle_area_scale.capacity() * 4 +
         texels_per_unit.capacity() * 4 + seam_texel.capacity() * 4 + seam_neighbour.capacity() * 4 +
         texel_island.capacity() * 4 + interior_bits.capacity() * 4 +
         interior_reach.capacity() + sole_reach.capacity();
}

namespace {

// Texel centres covered by each triangle's UV image. Shared edges are inclusive, so no
// texel between two triangles of an island is lost; the later triangle wins a tie.
void rasterize(const Surface& s, TextureDomain& d) {
  const float W = static_cast<float>(d.width), H = static_cast<float>(d.height);
  for (uint32_t t = 0; t < s.triangle_count(); ++t) {
    if (s.degenerate[t]) continue;
    const float* uv = &s.corner_uvs[6 * t];
    float x[3], y[3];
    for (int c = 0; c < 3; ++c) {
      x[c] = uv[2 * c] * W;
      y[c] = uv[2 * c + 1] * H;
    }
    float area2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    float sign = area2 > 0 ? 1.f : -1.f;  // mirrored UV islands wind clockwise
    const float eps = -1e-5f * std::fabs(area2);
    int x0 = std::max(0, static_cast<int>(std::floor(std::min({x[0], x[1], x[2]}) - 0.5f)));
    int x1 = std::min(static_cast<int>(d.width) - 1,
                      static_cast<int>(std::ceil(std::max({x[0], x[1], x[2]}) - 0.5f)));
    int y0 = std::max(0, static_cast<int>(std::floor(std::min({y[0], y[1], y[2]}) - 0.5f)));
    int y1 = std::min(static_cast<int>(d.height) - 1,
                      static_cast<int>(std::ceil(std::max({y[0], y[1], y[2]}) - 0.5f)));
    for (int iy = y0; iy <= y1; ++iy)
      for (int ix = x0; ix <= x1; ++ix) {
        float px = ix + 0.5f, py = iy + 0.5f;
        bool inside = true;
        for (int e = 0; e < 3 && inside; ++e) {
          int a = (e + 1) % 3, b = (e + 2) % 3;
          float f = sign * ((x[b] - x[a]) * (py - y[a]) - (y[b] - y[a]) * (px - x[a]));
          inside = f >= eps;
        }
        if (inside) {
          size_t i = static_cast<size_t>(iy) * d.width + ix;
          d.texel_triangle[i] = static_cast<int32_t>(t);
          d.classes[i] = MOLDTEX_TEXEL_INSIDE;
        }
      }
  }
}

// Barycentrics of a UV point with respect to triangle t's UV corners (may be negative).
bool uv_bary(const Surface& s, uint32_t t, float u, float v, float b[3]) {
  const float* uv = &s.corner_uvs[6 * t];
  double t00 = uv[2] - uv[0], t01 = uv[4] - uv[0], t10 = uv[3] - uv[1], t11 = uv[5] - uv[1];
  double det = t00 * t11 - t01 * t10;
  if (det == 0) return false;
  double du = u - uv[0], dv = v - uv[1];
  b[1] = static_cast<float>((t11 * du - t01 * dv) / det);
  b[2] = static_cast<float>((-t10 * du + t00 * dv) / det);
  b[0] = 1.f - b[1] - b[2];
  return true;
}

// Where a UV point just beyond edge `edge` of triangle t lands when the surface is
// unfolded into the neighbour across that edge; returns false if it cannot say.
bool across_seam(const Surface& s, const TextureDomain& d, uint32_t t, const float b[3], int edge,
                 uint32_t& texel) {
  AdjacencyCode code = s.adjacency[3 * t + edge];
  if (code == kNoNeighbour) return false;
  uint32_t n = code >> 3;
  int ne = static_cast<int>((code >> 1) & 3u);
  bool same_direction = code & 1u;
  int j = (edge + 1) % 3, k = (edge + 2) % 3;
  int jn = (ne + (same_direction ? 1 : 2)) % 3, kn = (ne + (same_direction ? 2 : 1)) % 3;
  const TriangleFrame& f = s.frames[t];
  const TriangleFrame& g = s.frames[n];
  // Local point and its position relative to the shared edge.
  Vec2 p{b[1] * f.a + b[2] * f.bx, b[2] * f.by};
  Vec2 qj = frame_corner(f, j), qk = frame_corner(f, k);
  Vec2 e{qk.x - qj.x, qk.y - qj.y};
  float len2 = e.x * e.x + e.y * e.y;
  float along = ((p.x - qj.x) * e.x + (p.y - qj.y) * e.y) / len2;
  float out = -((p.x - qj.x) * -e.y + (p.y - qj.y) * e.x) / std::sqrt(len2);  // > 0 beyond
  Vec2 rj = frame_corner(g, jn), rk = frame_corner(g, kn);
  Vec2 ccw = g.edge[ne];
  Vec2 q{rj.x + along * (rk.x - rj.x) - out * ccw.y, rj.y + along * (rk.y - rj.y) + out * ccw.x};
  float c2 = q.y / g.by, c1 = (q.x - g.bx * c2) / g.a;
  float c[3] = {1.f - c1 - c2, c1, c2};
  mtx_clamp_bary(c);
  float uv[2];
  s.evaluate(n, c, nullptr, uv);
  // The landing point is within a texel of the island border, so its texel centre may
  // lie just outside: take the nearest island texel of the neighbour's island around it.
  const float x = uv[0] * d.width, y = uv[1] * d.height;
  const int cx = static_cast<int>(x), cy = static_cast<int>(y);
  float best = 1e30f;
  for (int dy = -kGutterWidth; dy <= kGutterWidth; ++dy)
    for (int dx = -kGutterWidth; dx <= kGutterWidth; ++dx) {
      int nx = cx + dx, ny = cy + dy;
      if (nx < 0 || ny < 0 || nx >= static_cast<int>(d.width) || ny >= static_cast<int>(d.height)) continue;
      size_t i = static_cast<size_t>(ny) * d.width + nx;
      if (d.classes[i] != MOLDTEX_TEXEL_INSIDE || s.island[d.texel_triangle[i]] != s.island[n]) continue;
      float ex = nx + 0.5f - x, ey = ny + 0.5f - y, d2 = ex * ex + ey * ey;
      if (d2 < best) {
        best = d2;
        texel = static_cast<uint32_t>(i);
      }
    }
  return best < 1e30f;
}

void build_gutter(const Surface& s, TextureDomain& d, ThreadPool& pool) {
  const int W = static_cast<int>(d.width), H = static_cast<int>(d.height);
  // Rows are processed in parallel into per-row lists, then joined in row order so
  // the gutter list is the same for any thread count.
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> rows(H);
  pool.parallel_for(H, 8, [&](size_t begin, size_t end) {
    for (size_t y = begin; y < end; ++y) {
      for (int x = 0; x < W; ++x) {
        size_t i = y * W + x;
        if (d.classes[i] != MOLDTEX_TEXEL_OUTSIDE) continue;
        int best = -1, best_d2 = 1 << 30;
        for (int dy = -kGutterWidth; dy <= kGutterWidth; ++dy)
          for (int dx = -kGutterWidth; dx <= kGutterWidth; ++dx) {
            int nx = x + dx, ny = static_cast<int>(y) + dy;
            if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
            size_t ni = static_cast<size_t>(ny) * W + nx;
            int d2 = dx * dx + dy * dy;
            if (d.classes[ni] == MOLDTEX_TEXEL_INSIDE && d2 < best_d2) {
              best_d2 = d2;
              best = static_cast<int>(ni);
            }
          }
        if (best < 0) continue;
        uint32_t source = static_cast<uint32_t>(best);
        uint32_t t = static_cast<uint32_t>(d.texel_triangle[best]);
        float b[3];
        float u = (x + 0.5f) / W, v = (y + 0.5f) / H;
        if (uv_bary(s, t, u, v, b)) {
          int edge = static_cast<int>(std::min_element(b, b + 3) - b);
          uint32_t across = 0;
          if (b[edge] < 0 && across_seam(s, d, t, b, edge, across)) source = across;
        }
        rows[y].push_back({static_cast<uint32_t>(i), source});
      }
    }
  });
  for (auto& row : rows)
    for (auto [texel, source] : row) {
      d.gutter_texel.push_back(texel);
      d.gutter_source.push_back(source);
      d.classes[texel] = MOLDTEX_TEXEL_GUTTER;
    }
}

// The interior reach of every texel (see TextureDomain::interior_reach): one less than
// the chessboard distance to the nearest texel of another island (or none), the
// texture's outside counting as another island. Two chamfer passes, each texel taking the
// distance of its same-island neighbours plus one: the straight chessboard path to the
// nearest other texel runs through texels of the same island only, so this is exact.
// Texels where `left_out` is set count as no island's (none when it is null).
std::vector<uint8_t> interior_reach_of(const std::vector<int32_t>& island_of, uint32_t width, uint32_t height,
                                       const std::vector<uint8_t>* left_out = nullptr) {
  const int w = static_cast<int>(width), h = static_cast<int>(height);
  auto island = [&](size_t i) { return left_out && (*left_out)[i] ? -1 : island_of[i]; };
  std::vector<int> dist(island_of.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (island(size_t(y) * width + x) >= 0) dist[size_t(y) * width + x] = std::min({x + 1, y + 1, w - x, h - y});
  auto relax = [&](int x, int y, int dx, int dy) {
    const size_t i = size_t(y) * width + x;
    const int32_t own = island(i);
    if (own < 0) return;
    const int nx = x + dx, ny = y + dy;
    if (nx < 0 || ny < 0 || nx >= w || ny >= h) return;  // the initial distance holds it
    const size_t j = size_t(ny) * width + nx;
    dist[i] = std::min(dist[i], island(j) == own ? dist[j] + 1 : 1);
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      relax(x, y, -1, 0);
      relax(x, y, -1, -1);
      relax(x, y, 0, -1);
      relax(x, y, 1, -1);
    }
  for (int y = h - 1; y >= 0; --y)
    for (int x = w - 1; x >= 0; --x) {
      relax(x, y, 1, 0);
      relax(x, y, 1, 1);
      relax(x, y, 0, 1);
      relax(x, y, -1, 1);
    }
  std::vector<uint8_t> reach(island_of.size(), 0);
  for (size_t i = 0; i < reach.size(); ++i) reach[i] = static_cast<uint8_t>(std::clamp(dist[i] - 1, 0, 255));
  return reach;
}

// The island texels whose square (grown by kTouchMargin texels) a triangle of another
// island touches: set to 1 in `shared` (left empty with one island); returns whether
// there are any. A triangle touches the squares its UV image overlaps (separating axes:
// the squares' rows and columns, then its three edges' normals; a UV image without area,
// every square of its bounding box), and the border texels its points beyond the
// texture's border clamp onto. Only texels of another island are tested (most squares a
// triangle touches are its own island's).
constexpr double kTouchMargin = 1.0 / 64;  // far more than float rounding moves a point
bool shared_texels(const Surface& s, const TextureDomain& d, std::vector<uint8_t>& shared) {
  shared.clear();
  if (s.island.empty() || *std::max_element(s.island.begin(), s.island.end()) == 0) return false;
  shared.assign(d.texel_count(), 0);
  const int W = static_cast<int>(d.width), H = static_cast<int>(d.height);
  bool any = false;
  const double m = kTouchMargin;
  for (uint32_t t = 0; t < s.triangle_count(); ++t) {
    const float* uv = &s.corner_uvs[6 * t];
    double x[3], y[3];
    for (int c = 0; c < 3; ++c) {
      x[c] = double(uv[2 * c]) * W;
      y[c] = double(uv[2 * c + 1]) * H;
    }
    const int32_t island = static_cast<int32_t>(s.island[t]);
    auto other = [&](int ix, int iy) {
      const int32_t own = d.texel_island[static_cast<size_t>(iy) * d.width + ix];
      return own >= 0 && own != island;
    };
    auto touch = [&](int ix, int iy) {
      shared[static_cast<size_t>(iy) * d.width + ix] = 1;
      any = true;
    };
    const double lo_x = std::min({x[0], x[1], x[2]}) - m, hi_x = std::max({x[0], x[1], x[2]}) + m;
    const double lo_y = std::min({y[0], y[1], y[2]}) - m, hi_y = std::max({y[0], y[1], y[2]}) + m;
    const int x0 = static_cast<int>(std::clamp(std::floor(lo_x), 0.0, double(W - 1)));
    const int x1 = static_cast<int>(std::clamp(std::floor(hi_x), 0.0, double(W - 1)));
    const int y0 = static_cast<int>(std::clamp(std::floor(lo_y), 0.0, double(H - 1)));
    const int y1 = static_cast<int>(std::clamp(std::floor(hi_y), 0.0, double(H - 1)));
    // Beyond the border: the clamped column or row along the bounding box.
    for (int iy = y0; iy <= y1; ++iy) {
      if (lo_x < 0 && other(0, iy)) touch(0, iy);
      if (hi_x >= W && other(W - 1, iy)) touch(W - 1, iy);
    }
    for (int ix = x0; ix <= x1; ++ix) {
      if (lo_y < 0 && other(ix, 0)) touch(ix, 0);
      if (hi_y >= H && other(ix, H - 1)) touch(ix, H - 1);
    }
    // Each edge's inner side: f = g . (p - a) >= 0, f / |g| the distance; over a square f
    // is at most its value at the centre plus half its two slopes (the slack, with the
    // margin).
    const double area2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    const double sign = area2 > 0 ? 1.0 : -1.0;
    const bool flat = !(std::fabs(area2) > 1e-9);
    double gx[3], gy[3], slack[3];
    for (int e = 0; e < 3; ++e) {
      const int a = (e + 1) % 3, b = (e + 2) % 3;
      gx[e] = -sign * (y[b] - y[a]);
      gy[e] = sign * (x[b] - x[a]);
      slack[e] = 0.5 * (std::fabs(gx[e]) + std::fabs(gy[e])) + m * std::hypot(gx[e], gy[e]);
    }
    for (int iy = y0; iy <= y1; ++iy)
      for (int ix = x0; ix <= x1; ++ix) {
        if (!other(ix, iy)) continue;
        bool overlaps = true;
        for (int e = 0; e < 3 && overlaps && !flat; ++e) {
          const int a = (e + 1) % 3;
          overlaps = gx[e] * (ix + 0.5 - x[a]) + gy[e] * (iy + 0.5 - y[a]) + slack[e] >= 0;
        }
        if (overlaps) touch(ix, iy);
      }
  }
  return any;
}

}  // namespace

TextureDomain build_texture_domain(const Surface& s, uint32_t width, uint32_t height,
                                   ThreadPool& pool) {
  TextureDomain d;
  d.width = width;
  d.height = height;
  d.texel_triangle.assign(d.texel_count(), -1);
  d.classes.assign(d.texel_count(), MOLDTEX_TEXEL_OUTSIDE);
  rasterize(s, d);
  build_gutter(s, d, pool);
  d.triangle_area_scale.resize(s.triangle_count());
  for (uint32_t t = 0; t < s.triangle_count(); ++t)
    d.triangle_area_scale[t] = static_cast<float>(s.area_per_uv_area(t));
  d.texel_length = std::sqrt(s.area / (s.uv_area * static_cast<double>(width) * height));
  d.texels_per_unit.assign(2 * static_cast<size_t>(s.triangle_count()), 0.f);
  for (uint32_t t = 0; t < s.triangle_count(); ++t) {
    const auto g = s.metric(t);
    if (g[0] > 0 && g[3] > 0) {
      d.texels_per_unit[2 * t] = static_cast<float>(width / std::sqrt(g[0]));
      d.texels_per_unit[2 * t + 1] = static_cast<float>(height / std::sqrt(g[3]));
    }
  }
  build_seam_neighbours(s, d, pool);
  d.texel_island.assign(d.texel_count(), -1);
  for (size_t i = 0; i < d.texel_count(); ++i)
    if (d.classes[i] == MOLDTEX_TEXEL_INSIDE && d.texel_triangle[i] >= 0)
      d.texel_island[i] = static_cast<int32_t>(s.island[d.texel_triangle[i]]);
  d.interior_reach = interior_reach_of(d.texel_island, width, height);
  {
    // Where no texel is shared, the sole reach is the interior reach.
    std::vector<uint8_t> shared;
    d.sole_reach = shared_texels(s, d, shared) ? interior_reach_of(d.texel_island, width, height, &shared)
                                               : d.interior_reach;
    pool.parallel_for(d.texel_count(), 1 << 16, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i)
        d.sole_reach[i] = d.texel_island[i] >= 0 && (shared.empty() || !shared[i])
                              ? static_cast<uint8_t>(std::min(d.sole_reach[i] + 1, 255))
                              : uint8_t{0};
    });
  }
  // A texel is interior (its 3 x 3 block one island) where its reach is at least 1.
  d.interior_bits.assign((d.texel_count() + 31) / 32, 0u);
  for (size_t i = 0; i < d.texel_count(); ++i)
    if (d.interior_reach[i] >= 1) d.interior_bits[i / 32] |= 1u << (i % 32);
  return d;
}

namespace {

// The texel passes run as wide as the CPU allows: GCC builds these loops for AVX2 and for
// plain x86-64 and picks one at load time. The same operations in the same order either
// way (no fused multiply-add: AVX2 does not bring it), so the same bits on any machine.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define MTX_WIDE_LOOP __attribute__((target_clones("avx2", "default")))
#else
#define MTX_WIDE_LOOP
#endif

// Row y's island interior (x = 1 .. W - 2) from rows y - 1, y, y + 1: the blur's sum over
// 16 in the same order as mtx_diffuse_evaporate_rows adds it (bit-identical), every
// weight counted (texels at island borders are redone by the caller).
MTX_WIDE_LOOP void blur_interior_row(const float* r0, const float* r1, const float* r2, float* o, int W, float mix,
                                     float evaporation) {
  for (int x = 1; x + 1 < W; ++x) {
    float sum = 0.f;
    sum += r0[x - 1];
    sum += 2.f * r0[x];
    sum += r0[x + 1];
    sum += 2.f * r1[x - 1];
    sum += 4.f * r1[x];
    sum += 2.f * r1[x + 1];
    sum += r2[x - 1];
    sum += 2.f * r2[x];
    sum += r2[x + 1];
    const float p = r1[x];
    const float v = p + mix * (sum / 16.f - p) - evaporation;
    o[x] = v < 0.f ? 0.f : (v > 1.f ? 1.f : v);
  }
}

// A texel's value once its mark is applied: max(value, deposit) where marked on an
// island texel (agents mark whatever texel they stand on). Without branches, so loops
// over it vectorise: marks fall where agents happen to be, and a branch on each would be
// mispredicted about as often as not.
inline float deposited(uint8_t mark, uint8_t cls, float value, float deposit) {
  const bool hit = (mark != 0) & (cls == MTX_TEXEL_INSIDE);
  return hit ? std::max(value, deposit) : value;
}

// Row y of the plane as apply_deposits leaves it, into `row`; clears the row's marks if
// `clear` (no other chunk reads them).
MTX_WIDE_LOOP void deposited_row(const float* p, uint8_t* marks, const uint8_t* classes, float deposit, int y,
                                 int W, bool clear, float* row) {
  const size_t at = static_cast<size_t>(y) * W;
  const float* const value = p + at;
  uint8_t* const mark = marks + at;
  const uint8_t* const cls = classes + at;
  const float amount = deposit;
  for (int x = 0; x < W; ++x) row[x] = deposited(mark[x], cls[x], value[x], amount);
  if (clear) std::memset(mark, 0, static_cast<size_t>(W));
}

}  // namespace

void apply_deposits(const TextureDomain& d, float* p, uint8_t* marks, float deposit,
                    ThreadPool& pool) {
  // With the pointers in locals, since a store through the uint8_t marks may alias
  // anything and would otherwise reload them every texel. Every texel's value is stored,
  // unchanged where unmarked: the same result.
  pool.parallel_for(d.texel_count(), 1 << 16, [&](size_t begin, size_t end) {
    const uint8_t* const cls = d.classes.data();
    float* const value = p;
    uint8_t* const mark = marks;
    const float amount = deposit;
    for (size_t i = begin; i < end; ++i) {
      value[i] = deposited(mark[i], cls[i], value[i], amount);
      mark[i] = 0;
    }
  });
}

void fill_gutter(const TextureDomain& d, float* p, ThreadPool& pool) {
  pool.parallel_for(d.gutter_texel.size(), 1 << 14, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) p[d.gutter_texel[i]] = p[d.gutter_source[i]];
  });
}

void deposit_diffuse_evaporate(const TextureDomain& d, float* p, uint8_t* marks, float deposit, float* out,
                               float mix, float evaporation, ThreadPool& pool) {
  const int W = static_cast<int>(d.width), H = static_cast<int>(d.height);
  const uint8_t* classes = d.classes.data();
  // Gutter texels hold their sources' deposited values (a gutter texel is no island
  // texel, so its own value is what the blur then reads).
  pool.parallel_for(d.gutter_texel.size(), 1 << 14, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const uint32_t s = d.gutter_source[i];
      p[d.gutter_texel[i]] = deposited(marks[s], classes[s], p[s], deposit);
    }
  });
  // Rows whose marks another chunk reads (each chunk's first and last) are cleared after.
  std::mutex shared_rows_mutex;
  std::vector<int> shared_rows;
  pool.parallel_for(H, 4, [&](size_t begin_row, size_t end_row) {
    const int begin = static_cast<int>(begin_row), end = static_cast<int>(end_row);
    // Three deposited rows, y - 1, y and y + 1, in a ring.
    std::vector<float> ring(3 * static_cast<size_t>(W));
    auto slot = [&](int row) { return ring.data() + static_cast<size_t>((row + 3) % 3) * W; };
    auto fill = [&](int row) {
      deposited_row(p, marks, classes, deposit, row, W, row > begin && row < end - 1, slot(row));
    };
    if (begin > 0) fill(begin - 1);
    fill(begin);
    const uint32_t* interior = d.interior_bits.data();
    for (int y = begin; y < end; ++y) {
      if (y + 1 < H) fill(y + 1);
      const float* const rows[3] = {y > 0 ? slot(y - 1) : nullptr, slot(y), y + 1 < H ? slot(y + 1) : nullptr};
      float* o = out + static_cast<size_t>(y) * W;
      if (y >= 1 && y + 1 < H) {
        // Inside an island (the texel's 3x3 block all cells of one island) every weight
        // counts: one branch-free loop the compiler vectorises.
        blur_interior_row(rows[0], rows[1], rows[2], o, W, mix, evaporation);
      }
      // Texels at island borders (32 interior texels in a row, done above, skipped at once).
      const uint8_t* c1 = classes + static_cast<size_t>(y) * W;
      for (int x = 0; x < W; ++x) {
        const size_t i = static_cast<size_t>(y) * W + x;
        if (i % 32 == 0 && x + 32 <= W && interior[i / 32] == 0xffffffffu) {
          x += 31;
          continue;
        }
        if ((interior[i / 32] >> (i % 32)) & 1u) continue;
        o[x] = c1[x] == MOLDTEX_TEXEL_INSIDE
                   ? mtx_diffuse_evaporate_rows(rows[0], rows[1], rows[2], rows[0] ? c1 - W : nullptr, c1,
                                                rows[2] ? c1 + W : nullptr, x, W, mix, evaporation)
                   : 0.f;
      }
    }
    std::lock_guard<std::mutex> lock(shared_rows_mutex);
    shared_rows.push_back(begin);
    if (end - 1 > begin) shared_rows.push_back(end - 1);
  });
  for (int row : shared_rows) std::memset(marks + static_cast<size_t>(row) * W, 0, static_cast<size_t>(W));
}

FieldMetrics measure(const TextureDomain& d, const float* p) {
  double full = 0, covered = 0, present = 0;
  for (size_t i = 0; i < d.texel_count(); ++i) {
    if (d.classes[i] != MOLDTEX_TEXEL_INSIDE) continue;
    double w = d.triangle_area_scale[d.texel_triangle[i]];
    full += w;
    covered += w * p[i];
    present += p[i] > 0.f ? w : 0.0;
  }
  FieldMetrics m;
  if (full > 0) {
    m.coverage = covered / full;
    m.presence = present / full;
  }
  return m;
}

}  // namespace moldtex
