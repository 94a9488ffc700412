#include "agents/agents.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/rng.h"

namespace moldtex {

Agents spawn_uniform(const Surface& s, uint32_t count, uint64_t seed, ThreadPool& pool) {
  std::vector<double> cdf(s.triangle_count());
  double total = 0;
  for (uint32_t t = 0; t < s.triangle_count(); ++t) {
    total += s.degenerate[t] ? 0.0 : s.areas[t];
    cdf[t] = total;
  }
  Agents a;
  a.resize(count);
  pool.parallel_for(count, 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      CounterRng rng(seed, MTX_RNG_SPAWN, i, 0);
      double target = rng.next_double() * total;
      auto it = std::upper_bound(cdf.begin(), cdf.end(), target);
      uint32_t t = static_cast<uint32_t>(std::min<size_t>(it - cdf.begin(), cdf.size() - 1));
      while (s.degenerate[t] && t > 0) --t;  // only reachable through rounding at the end
      // Uniform point on a triangle by the square-root map (no rejection loop).
      float r1 = std::sqrt(rng.next_float()), r2 = rng.next_float();
      float angle = rng.next_float() * 2.f * std::numbers::pi_v<float>;
      Walker w{t, {1.f - r1, r1 * (1.f - r2), r1 * r2}, {std::cos(angle), std::sin(angle)}};
      a.store(i, w);
    }
  });
  return a;
}

void sort_by_tile(const Surface& s, uint32_t width, uint32_t height, Agents& a) {
  constexpr uint32_t kTile = 32;
  const uint32_t tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
  const size_t n = a.size();
  std::vector<uint32_t> key(n), start(static_cast<size_t>(tiles_x) * tiles_y + 1, 0);
  for (size_t i = 0; i < n; ++i) {
    Walker w = a.load(i);
    float uv[2];
    s.evaluate(w.triangle, w.bary, nullptr, uv);
    auto tile = [](float x, uint32_t size, uint32_t tiles) {
      int v = static_cast<int>(x * static_cast<float>(size)) / static_cast<int>(kTile);
      return static_cast<uint32_t>(v < 0 ? 0 : (v >= static_cast<int>(tiles) ? tiles - 1 : v));
    };
    key[i] = tile(uv[1], height, tiles_y) * tiles_x + tile(uv[0], width, tiles_x);
    ++start[key[i] + 1];
  }
  for (size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  Agents sorted;
  sorted.resize(n);
  for (size_t i = 0; i < n; ++i) sorted.store(start[key[i]]++, a.load(i));
  a = std::move(sorted);
}

}  // namespace moldtex
