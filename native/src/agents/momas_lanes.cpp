#include "agents/momas_lanes.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdlib>

#include "agents/momas_lanes_shared.h"
#include "agents/momas_rules.h"
#include "surface/trace_lanes.h"

namespace moldtex {

namespace {

// The cap on the lanes: 16, or what MOLDTEX_MOMAS_LANES says at load (0: the scalar
// code; 8: the AVX2 lanes on a processor that has both kinds).
unsigned initial_limit() {
  const char* text = std::getenv("MOLDTEX_MOMAS_LANES");
  if (!text || !*text) return 16u;
  const long value = std::strtol(text, nullptr, 10);
  return value >= 16 ? 16u : (value >= 8 ? 8u : 0u);
}

std::atomic<unsigned> g_limit{initial_limit()};

#ifdef MOLDTEX_MOMAS_LANES_X86
bool detect_lanes() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("bmi2");
}

#endif

}  // namespace

unsigned momas_lane_width() {
#ifdef MOLDTEX_MOMAS_LANES_X86
  // AVX2 as the trace lanes find it.
  static const unsigned width = detect_lanes() ? 16u : (trace_lane_width() >= 8u ? 8u : 0u);
  return width;
#else
  return 0u;
#endif
}

void momas_lanes_limit(unsigned width) { g_limit.store(width, std::memory_order_relaxed); }

namespace {

unsigned lanes_now() { return std::min(momas_lane_width(), g_limit.load(std::memory_order_relaxed)); }

}  // namespace

bool momas_lanes_apply(const mtx_momas_constants& c, uint32_t triangle_count) {
#ifdef MOLDTEX_MOMAS_LANES_X86
  const unsigned width = lanes_now();
  if (width < 8u) return false;
  const uint64_t planes_texels = uint64_t(c.width) * c.height * c.species_count;
  // Surface units (footprint sensing and marks, steps without sensing): 16 lanes only.
  const bool units = c.surface_mode == 0u ? c.coast == 0u : width >= 16u;
  return units && c.decisions <= 1u && c.sensor_size == 0u && c.has_fields == 0u &&
         !(c.hunger_step > 0.0f) && c.substeps >= 1u && c.species_count >= 1u &&
         c.species_count <= MTX_MAX_SPECIES && planes_texels < (1ull << 31) &&
         uint64_t(triangle_count) * kFrameFloats < (1ull << 31);
#else
  (void)c;
  (void)triangle_count;
  return false;
#endif
}

size_t momas_lanes_update(const mtx_surface_tables& tables, const mtx_momas_constants& c, const float* pheromone,
                          const float* field, uint8_t* marks, Agents& agents, size_t begin, size_t end) {
#ifdef MOLDTEX_MOMAS_LANES_X86
  const unsigned width = lanes_now();
  if (width >= 16u) return momas_lanes16(tables, c, pheromone, field, marks, agents, begin, end);
  if (width >= 8u) return momas_lanes8(tables, c, pheromone, field, marks, agents, begin, end);
#endif
  momas_update_agents(tables, c, pheromone, field, marks, agents, begin, end);
  return 0;
}

}  // namespace moldtex
