// MoMaS' step in SIMD lanes (the CPU backend only; OpenCL runs shared/momas.h per work
// item). A MoMaS step in texel units is the same few dozen float operations, loads and
// stores for every agent (probes through the triangle's affine map to texels or across
// a few edges, three reads, a turn, a move, a mark): the textbook SIMD loop of issue #15.
// The lanes run those operations in the order shared/momas.h runs them (the file is
// built without fused multiply-adds), so every agent ends bit for bit where the scalar
// code puts it; an agent whose trace or move must be walked (open boundaries, long
// walks) takes the scalar step in its lane's place.
#pragma once
#include <cstddef>
#include <cstdint>

#include "agents/agents.h"
#include "shared/momas.h"

namespace moldtex {

// The lanes this processor has (found at run time): 16 (AVX-512 F, DQ and BW, with BMI2), 8 (AVX2) or
// 0 (none: every step runs the scalar code).
unsigned momas_lane_width();

// A cap on the lanes, for tests and benchmarks that compare the kinds (0: the scalar code,
// 8: the AVX2 lanes even where AVX-512 exists); MOLDTEX_MOMAS_LANES=0|8|16 sets it at
// load. The results are the same bits whatever the cap.
void momas_lanes_limit(unsigned width);

// Whether momas_lanes_update runs steps with constants c in lanes (under the cap): MoMaS
// in texel units with one decision a step, one-texel sensors, no fields and no food with
// hunger, and tables small enough for 32-bit gather offsets.
bool momas_lanes_apply(const mtx_momas_constants& c, uint32_t triangle_count);

// Updates agents [begin, end) as momas_update_agents does (the same bits), 16 or 8 at a
// time; returns how many were stepped in the lanes (the rest ran the scalar code).
size_t momas_lanes_update(const mtx_surface_tables& tables, const mtx_momas_constants& c, const float* pheromone,
                          const float* field, uint8_t* marks, Agents& agents, size_t begin, size_t end);

}  // namespace moldtex
