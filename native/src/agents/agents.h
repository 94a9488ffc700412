// Agent state as a structure of arrays: triangle, two barycentric weights (the third is
// 1 - b1 - b2) and a unit heading in the triangle's local frame. 20 bytes per agent.
#pragma once
#include <cstdint>
#include <vector>

#include "backends/cpu/thread_pool.h"
#include "surface/surface.h"

namespace moldtex {

struct Agents {
  std::vector<uint32_t> triangle;
  std::vector<float> b1, b2, hx, hy;

  size_t size() const { return triangle.size(); }
  void resize(size_t n) {
    triangle.resize(n);
    b1.resize(n);
    b2.resize(n);
    hx.resize(n);
    hy.resize(n);
  }
  size_t bytes() const { return triangle.capacity() * 4 + (b1.capacity() + b2.capacity() + hx.capacity() + hy.capacity()) * 4; }

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
};

// Places `count` agents uniformly by 3D area (triangle chosen by area, barycentrics
// uniform on the triangle) with headings uniform over the full circle. Agent i depends
// only on (seed, i), never on the thread that placed it.
// Reorders agents by the texture tile they stand in (a stable counting sort), so that
// neighbouring agents read neighbouring texels and stay in cache. Deterministic.
void sort_by_tile(const Surface& surface, uint32_t width, uint32_t height, Agents& agents);

Agents spawn_uniform(const Surface& surface, uint32_t count, uint64_t seed, ThreadPool& pool);

}  // namespace moldtex
