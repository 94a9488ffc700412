// Agent state as a structure of arrays: triangle, two barycentric weights (the third is
// 1 - b1 - b2), a unit heading in the triangle's local frame, the species and the
// hunger in [0, 1] (food with hunger), and the brush batch that added it (0 = spawned
// at reset; host-side bookkeeping of the slime brushes, never read by the step), and
// the clocks of the continuous model (turn-decision clock, age, exposure and its
// threshold; see shared/continuous.h). 43 bytes per agent.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "backends/cpu/thread_pool.h"
#include "surface/surface.h"

namespace moldtex {

struct Agents {
  std::vector<uint32_t> triangle;
  std::vector<float> b1, b2, hx, hy;
  std::vector<uint8_t> species;
  std::vector<float> hunger;
  std::vector<uint16_t> batch;
  std::vector<float> clock, age, exposure, threshold;

  size_t size() const { return triangle.size(); }
  // f(a's array, b's array) for each of the arrays, in one order (a and b may be the same,
  // either may be const): what is done to every array alike (resizing, counting,
  // copying, reordering) is written once.
  template <class A, class B, class F>
  static void for_each_array(A& a, B& b, F&& f) {
    f(a.triangle, b.triangle);
    f(a.b1, b.b1);
    f(a.b2, b.b2);
    f(a.hx, b.hx);
    f(a.hy, b.hy);
    f(a.species, b.species);
    f(a.hunger, b.hunger);
    f(a.batch, b.batch);
    f(a.clock, b.clock);
    f(a.age, b.age);
    f(a.exposure, b.exposure);
    f(a.threshold, b.threshold);
  }
  void resize(size_t n) {
    for_each_array(*this, *this, [n](auto&, auto& v) { v.resize(n); });
  }
  size_t bytes() const {
    size_t total = 0;
    for_each_array(*this, *this, [&total](const auto& v, const auto&) { total += v.capacity() * sizeof(v[0]); });
    return total;
  }

  Walker load(size_t i) const {
    return Walker{triangle[i], {1.f - b1[i] - b2[i], b1[i], b2[i]}, {hx[i], hy[i]}};
  }
  void store(size_t i, const Walker& w) {
    triangle[i] = w.triangle;
    b1[i] = w.bary[1];
    b2[i] = w.bary[2];
    hx[i] = w.heading.x;
    hy[i] = w.heading.y;
  }
  // Everything about agent i of `from` into slot i here.
  void copy_from(size_t i, const Agents& from, size_t j) {
    for_each_array(from, *this, [i, j](const auto& source, auto& target) { target[i] = source[j]; });
  }
  // Appends the agents of `from` after these (0 where an array of `from` is short, as
  // batch tags may be). An array that must grow takes an eighth more room than it
  // needs, so a stroke of small dabs moves the agents seldom (not the doubling of a
  // vector, a lot of memory for millions of agents). If an array cannot grow, every
  // array is left as it was.
  void append(const Agents& from) {
    const size_t n = size(), m = from.size();
    try {
      for_each_array(from, *this, [n, m](const auto& source, auto& target) {
        if (target.capacity() < n + m) target.reserve(n + std::max(m, n / 8));
        target.resize(n + m);
        std::copy_n(source.begin(), std::min(source.size(), m), target.begin() + n);
      });
    } catch (...) {
      resize(n);
      throw;
    }
  }
  // Drops the agents whose entry of `drop` (one per agent) is not 0; the rest keep their
  // order. In place, one array at a time.
  void remove_marked(const std::vector<uint8_t>& drop) {
    size_t first = 0;  // (agents before the first dropped one stay where they are)
    while (first < drop.size() && !drop[first]) ++first;
    for_each_array(*this, *this, [&drop, first](auto&, auto& v) {
      size_t kept = std::min(first, v.size());
      for (size_t i = kept; i < v.size(); ++i)
        if (!drop[i]) v[kept++] = v[i];
      v.resize(kept);
    });
  }
};

// Agents begin .. end in batches of `Batch`, a step split in stages: the first stage(i, j)
// for every agent i of a batch (j its place in the batch), then the next stage for each,
// and so on. Each stage has the memory reads of the next under way for a whole batch
// before any agent of it needs them.
template <size_t Batch, class... Stages>
void for_each_in_batches(size_t begin, size_t end, Stages&&... stages) {
  for (size_t b = begin; b < end; b += Batch) {
    const size_t n = std::min(Batch, end - b);
    auto run = [&](auto& stage) {
      for (size_t j = 0; j < n; ++j) stage(b + j, j);
    };
    (run(stages), ...);
  }
}

// What sort_by_tile keeps between calls: the keys and the sorted copy, so a regrouping
// every few steps allocates (and page-faults) nothing once they have grown.
struct TileSortScratch {
  std::vector<uint32_t> key, start, dest;
  Agents sorted;
};

// Reorders agents by the texture tile they stand in (a stable counting sort), so that
// neighbouring agents read neighbouring texels and stay in cache. Deterministic: the
// keys are computed on the pool's threads, each agent's alone, and a stable sort has one
// result, however its counting and copying are split among the threads.
void sort_by_tile(const Surface& surface, uint32_t width, uint32_t height, Agents& agents,
                  TileSortScratch& scratch, ThreadPool& pool);

// Reorders agents by the surface triangle they stand on (the same stable counting sort).
// For domains whose memory follows the mesh, not the texture (the intrinsic
// triangulation): no UV coordinate enters the order, so neither does it enter the
// agents' random streams (keyed by their index).
void sort_by_triangle(uint32_t triangle_count, Agents& agents, TileSortScratch& scratch, ThreadPool& pool);

// How to place agents (moldtex_sim_config's seed fields, validated).
struct SpawnSpec {
  uint32_t count = 0;
  uint64_t seed = 0;
  uint32_t species_count = 1;  // agent i gets species i % species_count
  uint32_t shape = 0;          // a moldtex_seed_shape
  moldtex_surface_point center{};
  float radius = 0;
  uint32_t rays = 8;
  // Texel weights for SPAWN_MAP (and RANDOM when obstacles exist): width * height, with
  // obstacle and non-island texels at 0; empty = none.
  const std::vector<double>* texel_weights = nullptr;
  const std::vector<int32_t>* texel_triangle = nullptr;
  uint32_t width = 0, height = 0;
};

// Places agents as `spec` says. Agent i depends only on (seed, i), never on the thread
// that placed it. RANDOM without texel weights: uniform by 3D area (triangle chosen by
// area, barycentrics uniform on the triangle), headings uniform over the full circle.
// Throws INVALID_ARGUMENT if texel weights are needed and all zero.
Agents spawn_agents(const Surface& surface, const SpawnSpec& spec, ThreadPool& pool);

}  // namespace moldtex
