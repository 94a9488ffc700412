// MoMaS' common case in SIMD lanes (the CPU backend only; OpenCL runs shared/momas.h per
// work item). Most agent-steps of MoMaS in texel units sense and move without leaving
// their triangle: the flat plane's always, a 2048^2 UV sphere's almost always. There an
// agent's step is the same few dozen float operations, loads and stores for every agent
// (probes through the triangle's affine map to texels, three reads, a turn, a move, a
// mark): the textbook SIMD loop of issue #15. The lanes run those operations in the
// order shared/momas.h runs them (the file is built without fused multiply-adds), so
// every agent ends bit for bit where the scalar code puts it; an agent whose probes or
// move may leave its triangle takes the scalar code in its lane's place.
#pragma once
#include <cstddef>
#include <cstdint>

#include "agents/agents.h"
#include "shared/momas.h"

namespace moldtex {

// Whether this processor has the lanes (AVX-512 F and DQ).
bool momas_lanes_supported();

// Whether momas_lanes_update can run steps with constants c on this processor: AVX-512 (F
// and DQ), MoMaS in texel units with one decision a step, one-texel sensors, no fields and
// no food with hunger, and tables small enough for 32-bit gather offsets.
bool momas_lanes_apply(const mtx_momas_constants& c, uint32_t triangle_count);

// Updates agents [begin, end) as momas_update_agents does (the same bits), 16 at a time;
// returns how many were stepped in the lanes (the rest ran the scalar code).
size_t momas_lanes_update(const mtx_surface_tables& tables, const mtx_momas_constants& c, const float* pheromone,
                        const float* field, uint8_t* marks, Agents& agents, size_t begin, size_t end);

// Off (or on again) for tests and benchmarks, which compare the two; also off when the
// environment variable MOLDTEX_MOMAS_LANES is 0 at load.
void momas_lanes_enable(bool on);

}  // namespace moldtex
