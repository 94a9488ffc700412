// What MoMaS' lanes of both widths share (agents/momas_lanes16.cpp: AVX-512,
// agents/momas_lanes8.cpp: AVX2; the dispatch in agents/momas_lanes.cpp): the agents
// they leave to the scalar step, and where a triangle's frame values lie.
#pragma once
#include <cstddef>
#include <cstdint>

#include "agents/agents.h"
#include "agents/momas_rules.h"
#include "shared/momas.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MOLDTEX_MOMAS_LANES_X86 1
// GCC 12 warns inside its own AVX-512 headers (their _mm512_undefined_* sources, which
// are meant to be left undefined) wherever these intrinsics are inlined; and about the
// ABI of vector values, which never cross a call here (every helper is inlined).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace moldtex {

// The agents the lanes leave (a trace or move that must be walked): they gather here and
// run through the scalar step (momas_update_listed) once 16 or more wait. Agents are independent within a step (each reads
// the step's field and its own state, and marks are the same byte from every writer).
struct Leftovers {
  const mtx_surface_tables& s;
  const mtx_momas_constants& c;
  const float* pheromone;
  const float* field;
  uint8_t* marks;
  Agents& agents;
  size_t pending[2 * kMomasBatch];  // 15 waiting and a group of 16 at most
  size_t waiting = 0, stepped = 0;

  // A group of agents from `first` (lanes `all`), of which the lanes `done` were stepped.
  void take(size_t first, unsigned done, unsigned all) {
    stepped += static_cast<size_t>(__builtin_popcount(done));
    for (unsigned rest = ~done & all; rest; rest &= rest - 1)
      pending[waiting++] = first + static_cast<size_t>(__builtin_ctz(rest));
    if (waiting >= kMomasBatch) {
      momas_update_listed(s, c, pheromone, field, marks, agents, pending, waiting);
      waiting = 0;
    }
  }
  // The agents [i, end) too few for a group, and everything pending; returns how many
  // the lanes stepped.
  size_t finish(size_t i, size_t end) {
    for (; i < end; ++i) pending[waiting++] = i;
    momas_update_listed(s, c, pheromone, field, marks, agents, pending, waiting);
    return stepped;
  }
};

// The frame's floats as the lanes gather them (shared/walk.h's mtx_frame).
constexpr int kFrameFloats = sizeof(mtx_frame) / sizeof(float);
static_assert(sizeof(mtx_frame) == 14 * sizeof(float), "mtx_frame is 14 floats");
constexpr int kInvA = offsetof(mtx_frame, inv_a) / sizeof(float);
constexpr int kBx = offsetof(mtx_frame, bx) / sizeof(float);
constexpr int kInvBy = offsetof(mtx_frame, inv_by) / sizeof(float);
constexpr int kAltitude = offsetof(mtx_frame, altitude) / sizeof(float);
constexpr int kEdge = offsetof(mtx_frame, edge) / sizeof(float);

// The most legs a move walks in the lanes (a walk with more leaves them).
constexpr int kWalkLegs = 8;

// Agents [begin, end) in 16 AVX-512 lanes (F and DQ) or in 8 AVX2 lanes (texel units
// only); each returns how many it stepped in the lanes. Callers check the processor.
size_t momas_lanes16(const mtx_surface_tables& s, const mtx_momas_constants& c, const float* pheromone,
                     const float* field, uint8_t* marks, Agents& agents, size_t begin, size_t end);
size_t momas_lanes8(const mtx_surface_tables& s, const mtx_momas_constants& c, const float* pheromone,
                    const float* field, uint8_t* marks, Agents& agents, size_t begin, size_t end);

}  // namespace moldtex
