// Brushes (moldtex_brush): painting a geodesic disk into an RGBA image over the UV
// layout, and the geometry of the slime brushes (placing agents in a disk, telling
// which agents stand in one). The simulation's agent bookkeeping is in sim.cpp.
#pragma once
#include <cstdint>

#include "agents/agents.h"
#include "moldtex.h"
#include "surface/surface.h"

namespace moldtex {

// Throws INVALID_ARGUMENT unless the brush is usable on this surface: radius in
// [1e-30, 1e30); strength and falloff in [0, 1]; mode known; value finite; centre
// triangle in range and not degenerate, barycentrics finite, >= 0 and summing to 1.
// channel is checked by the caller (image channel or species).
void validate_brush(const Surface& s, const moldtex_brush& brush);

// w(x): 1 for x <= 1 - falloff, then a smoothstep down to 0 at x = 1; 0 beyond.
float brush_weight(float x, float falloff);

// One dab (see moldtex_surface_paint); returns how many texels changed.
uint32_t paint_dab(const Surface& s, uint32_t width, uint32_t height, float* rgba,
                   const moldtex_brush& brush);

// `count` agents uniform over the disk (walked from the centre at a uniform angle for
// r * sqrt(u), r = disk_reach(s, centre, radius): the radius unless the disk holds the
// whole reachable surface), headings uniform, hunger 0, of species brush.channel, tagged
// `batch`. Agent j is a pure function of (seed, batch, first_index + j).
Agents place_disk_agents(const Surface& s, const moldtex_brush& brush, uint32_t count,
                         uint64_t seed, uint16_t batch, uint64_t first_index, ThreadPool& pool);

// Which agents an erase dab removes: out[i] = 1 for agent i when it stands within the
// disk and, with weight p = strength * w(d / radius), a draw keyed on (seed, batch,
// dab, i) is below p (always for p = 1). `width` x `height`: the texture whose texel
// size sets the sampling density.
std::vector<uint8_t> erase_mask(const Surface& s, const moldtex_brush& brush, const Agents& agents,
                                uint32_t width, uint32_t height, uint64_t seed, uint16_t batch,
                                uint64_t dab);

}  // namespace moldtex
