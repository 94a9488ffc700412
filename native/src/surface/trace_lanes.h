// Sensor traces located through the unfolded neighbours many at a time, in SIMD lanes
// where the processor has them: AVX-512F or AVX2 (the CPU backend only; OpenCL runs
// shared/walk.h's mtx_trace_hops per work item). On fine meshes a trace crosses several
// edges (about 5 on Suzanne's intrinsic domain): each crossing is a load that waits on
// the one before and an edge choice that a branch predictor cannot learn. In lanes the
// crossings of many traces overlap, and the choices become masks.
//
// The lanes run the same float operations in the same order as mtx_trace_hops (its
// file is compiled without contraction into fused multiply-adds, as the rest of the
// library is for the baseline x86-64), so every result is bit for bit the scalar one:
// the same ends, the same traces left to the walk.
#pragma once
#include <cstddef>
#include <cstdint>

#include "shared/walk.h"

namespace moldtex {

// Up to kTraceLanes traces as structure of arrays: each trace's triangle and its start and
// end weights there (mtx_trace_ends).
constexpr size_t kTraceLanes = 128;
struct TraceLanes {
  uint32_t triangle[kTraceLanes];
  float s[3][kTraceLanes];
  float e[3][kTraceLanes];
  size_t count = 0;
};

// Runs mtx_trace_hops on traces 0 .. count - 1: located[i] = 1 with triangle[i] and
// e[.][i] where trace i ends, or 0 (the trace must be walked; its entries are then
// meaningless); s is only read. `triangle_count`: the surface's (lanes index the
// tables with 32-bit offsets, so larger surfaces run the scalar code).
void trace_hops_lanes(const uint32_t* adjacency, const float* unfolded, uint32_t triangle_count, TraceLanes& lanes,
                      uint8_t* located);

// The lanes trace_hops_lanes uses on this processor (found at run time): 16 (AVX-512F),
// 8 (AVX2) or 1 (mtx_trace_hops one trace after another); and a cap on them for tests
// and benchmarks, which compare the kinds (trace_lanes_limit(1): the scalar code).
unsigned trace_lane_width();
void trace_lanes_limit(unsigned width);

}  // namespace moldtex
