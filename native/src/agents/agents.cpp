#include "agents/agents.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/error.h"
#include "common/rng.h"
#include "shared/momas.h"

namespace moldtex {

namespace {

Walker random_area_point(const Surface& s, const std::vector<double>& cdf, double total,
                         CounterRng& rng) {
  double target = rng.next_double() * total;
  auto it = std::upper_bound(cdf.begin(), cdf.end(), target);
  uint32_t t = static_cast<uint32_t>(std::min<size_t>(it - cdf.begin(), cdf.size() - 1));
  while (s.degenerate[t] && t > 0) --t;  // only reachable through rounding at the end
  // Uniform point on a triangle by the square-root map (no rejection loop).
  float r1 = std::sqrt(rng.next_float()), r2 = rng.next_float();
  float angle = rng.next_float() * 2.f * std::numbers::pi_v<float>;
  return Walker{t, {1.f - r1, r1 * (1.f - r2), r1 * r2}, {std::cos(angle), std::sin(angle)}};
}

// Barycentrics of a UV point with respect to triangle t's UV corners, clamped onto it.
void uv_to_bary(const Surface& s, uint32_t t, double u, double v, float b[3]) {
  const float* uv = &s.corner_uvs[6 * t];
  double t00 = uv[2] - uv[0], t01 = uv[4] - uv[0], t10 = uv[3] - uv[1], t11 = uv[5] - uv[1];
  double det = t00 * t11 - t01 * t10;
  double du = u - uv[0], dv = v - uv[1];
  b[1] = det != 0 ? static_cast<float>((t11 * du - t01 * dv) / det) : 1.f / 3.f;
  b[2] = det != 0 ? static_cast<float>((-t10 * du + t00 * dv) / det) : 1.f / 3.f;
  b[0] = 1.f - b[1] - b[2];
  mtx_clamp_bary(b);
}

// A uniform point in texel `texel` on the triangle that covers it, preferring points
// whose texel is that texel (a few jittered tries, then the texel centre).
Walker texel_point(const Surface& s, const SpawnSpec& spec, uint32_t texel, CounterRng& rng) {
  const uint32_t t = static_cast<uint32_t>((*spec.texel_triangle)[texel]);
  const double x = texel % spec.width, y = texel / spec.width;
  Walker w{t, {1.f / 3, 1.f / 3, 1.f / 3}, {1.f, 0.f}};
  for (int attempt = 0; attempt < 5; ++attempt) {
    const double jx = attempt < 4 ? rng.next_double() : 0.5, jy = attempt < 4 ? rng.next_double() : 0.5;
    uv_to_bary(s, t, (x + jx) / spec.width, (y + jy) / spec.height, w.bary);
    float uv[2];
    s.evaluate(t, w.bary, nullptr, uv);
    if (mtx_texel_of_uv(uv[0], uv[1], spec.width, spec.height) == texel) break;
  }
  const float angle = rng.next_float() * 2.f * std::numbers::pi_v<float>;
  w.heading = {std::cos(angle), std::sin(angle)};
  return w;
}

}  // namespace

Agents spawn_agents(const Surface& s, const SpawnSpec& spec, ThreadPool& pool) {
  const bool by_texel = spec.texel_weights && !spec.texel_weights->empty() &&
                        (spec.shape == MOLDTEX_SEED_RANDOM || spec.shape == MOLDTEX_SEED_SPAWN_MAP);
  if (spec.shape == MOLDTEX_SEED_SPAWN_MAP && !by_texel)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The spawn map is empty: paint a spawn region (red channel of the fields)");
  std::vector<double> cdf;
  double total = 0;
  if (by_texel) {
    cdf.resize(spec.texel_weights->size());
    for (size_t i = 0; i < cdf.size(); ++i) cdf[i] = total += (*spec.texel_weights)[i];
  } else {
    cdf.resize(s.triangle_count());
    for (uint32_t t = 0; t < s.triangle_count(); ++t) cdf[t] = total += s.degenerate[t] ? 0.0 : s.areas[t];
  }
  if (!(total > 0))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "There is nowhere to spawn agents: paint a spawn region (red channel of the fields) "
         "outside the obstacles (green channel)");
  Agents a;
  a.resize(spec.count);
  const float two_pi = 2.f * std::numbers::pi_v<float>;
  pool.parallel_for(spec.count, 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      CounterRng rng(spec.seed, MTX_RNG_SPAWN, i, 0);
      Walker w{};
      if (spec.shape == MOLDTEX_SEED_RANDOM && !by_texel) {
        w = random_area_point(s, cdf, total, rng);
      } else if (by_texel) {
        const double target = rng.next_double() * total;
        size_t k = std::min<size_t>(std::upper_bound(cdf.begin(), cdf.end(), target) - cdf.begin(),
                                    cdf.size() - 1);
        while ((*spec.texel_weights)[k] <= 0 && k > 0) --k;  // rounding at the end
        w = texel_point(s, spec, static_cast<uint32_t>(k), rng);
      } else {
        Walker c{spec.center.triangle, {spec.center.bary[0], spec.center.bary[1], spec.center.bary[2]}, {1.f, 0.f}};
        mtx_clamp_bary(c.bary);
        float angle = rng.next_float() * two_pi;
        float length = 0;
        if (spec.shape == MOLDTEX_SEED_CIRCLE) {
          length = spec.radius;
        } else if (spec.shape == MOLDTEX_SEED_STARBURST) {
          const uint32_t ray = std::min(spec.rays - 1, static_cast<uint32_t>(angle / two_pi * spec.rays));
          angle = two_pi * static_cast<float>(ray) / static_cast<float>(spec.rays);
          length = rng.next_float() * spec.radius;
        }
        c.heading = {std::cos(angle), std::sin(angle)};
        w = c;
        if (length > 0) mtx_walk(s.frames.data(), s.adjacency.data(), &w, length, nullptr, 0);
        if (spec.shape == MOLDTEX_SEED_CIRCLE) w.heading = {-w.heading.x, -w.heading.y};
      }
      a.store(i, w);
      a.species[i] = static_cast<uint8_t>(i % spec.species_count);
    }
  });
  return a;
}

namespace {

// Where a stable counting sort by scratch.key (< buckets) sends each agent
// (scratch.dest), in parallel: the agents cut into one run per thread, each run counts its
// keys, and agent i of run r with key b goes after every agent of a smaller key and every
// earlier agent of key b (those of runs before r, then its own run's): the one order of a
// stable sort, whatever the thread count.
void sort_destinations(TileSortScratch& scratch, size_t n, size_t buckets, ThreadPool& pool) {
  // Runs of at least 65,536 agents, and their counts together within 4 Mi words (16 MiB),
  // however many threads and buckets (mesh triangles, on the intrinsic domain) there are.
  const size_t runs = std::max<size_t>(1, std::min({size_t(pool.size()), n / 65536, (size_t(1) << 22) / std::max<size_t>(buckets, 1)}));
  const size_t run_length = (n + runs - 1) / runs;
  const uint32_t* key = scratch.key.data();
  std::vector<uint32_t>& count = scratch.start;  // runs x buckets, then each run's offsets
  count.assign(runs * buckets, 0);
  scratch.dest.resize(n);
  pool.parallel_for(runs, 1, [&](size_t r0, size_t r1) {
    for (size_t r = r0; r < r1; ++r) {
      uint32_t* c = count.data() + r * buckets;
      for (size_t i = r * run_length, end = std::min(n, i + run_length); i < end; ++i) ++c[key[i]];
    }
  });
  uint32_t next = 0;
  for (size_t b = 0; b < buckets; ++b)
    for (size_t r = 0; r < runs; ++r) {
      const uint32_t k = count[r * buckets + b];
      count[r * buckets + b] = next;
      next += k;
    }
  pool.parallel_for(runs, 1, [&](size_t r0, size_t r1) {
    for (size_t r = r0; r < r1; ++r) {
      uint32_t* offset = count.data() + r * buckets;
      uint32_t* dest = scratch.dest.data();
      for (size_t i = r * run_length, end = std::min(n, i + run_length); i < end; ++i) dest[i] = offset[key[i]]++;
    }
  });
}

// Array `from` reordered into `to` by dest (to[dest[i]] = from[i]), in parallel.
template <class T>
void scatter_by(const std::vector<uint32_t>& dest, const std::vector<T>& from, std::vector<T>& to,
                ThreadPool& pool) {
  to.resize(from.size());
  const uint32_t* d = dest.data();
  const T* f = from.data();
  T* t = to.data();
  pool.parallel_for(from.size(), 1 << 16, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) t[d[i]] = f[i];
  });
}

// Stable counting sort of the agents by scratch.key (< buckets), array by array.
void sort_by_key(Agents& a, TileSortScratch& scratch, size_t buckets, ThreadPool& pool) {
  const size_t n = a.size();
  sort_destinations(scratch, n, buckets, pool);
  Agents& sorted = scratch.sorted;
  const std::vector<uint32_t>& dest = scratch.dest;
  Agents::for_each_array(a, sorted, [&](const auto& from, auto& to) { scatter_by(dest, from, to, pool); });
  std::swap(a, sorted);  // the old order becomes the next call's scratch
}

}  // namespace

void sort_by_tile(const Surface& s, uint32_t width, uint32_t height, Agents& a,
                  TileSortScratch& scratch, ThreadPool& pool) {
  constexpr uint32_t kTile = 32;
  const uint32_t tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
  const size_t n = a.size();
  std::vector<uint32_t>& key = scratch.key;
  key.resize(n);
  pool.parallel_for(n, 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      Walker w = a.load(i);
      float uv[2];
      s.evaluate(w.triangle, w.bary, nullptr, uv);
      auto tile = [](float x, uint32_t size, uint32_t tiles) {
        // Clamped before the cast (surfaces keep |uv| <= 1e4, but a float -> int
        // conversion out of range would be undefined); the same tiles as clamping after.
        const float f = x * static_cast<float>(size);
        if (!(f >= 0.f)) return 0u;
        if (f >= static_cast<float>(size)) return tiles - 1;
        return std::min(static_cast<uint32_t>(f) / kTile, tiles - 1);
      };
      key[i] = tile(uv[1], height, tiles_y) * tiles_x + tile(uv[0], width, tiles_x);
    }
  });
  sort_by_key(a, scratch, static_cast<size_t>(tiles_x) * tiles_y, pool);
}

void sort_by_triangle(uint32_t triangle_count, Agents& a, TileSortScratch& scratch, ThreadPool& pool) {
  const size_t buckets = std::max<size_t>(triangle_count, 1);
  std::vector<uint32_t>& key = scratch.key;
  key.resize(a.size());
  pool.parallel_for(a.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) key[i] = std::min<uint32_t>(a.triangle[i], uint32_t(buckets - 1));
  });
  sort_by_key(a, scratch, buckets, pool);
}

}  // namespace moldtex
