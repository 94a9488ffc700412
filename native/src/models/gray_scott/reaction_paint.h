// The slime brushes in the Gray-Scott model (moldtex.h, MOLDTEX_MODEL_GRAY_SCOTT), which
// has no agents: a dab paints the chemicals instead. Adding moves each texel of the disk
// toward a seed (V = 1, U = 0.5, the start's disks); erasing toward the bare state
// (V = 0, U = 1); by strength * w(d / radius) with the brush's falloff, like
// moldtex_surface_paint. The first value of every texel a stroke touches is kept, so
// the stroke can be undone exactly.
#pragma once
#include <array>
#include <cstdint>
#include <map>

#include "backends/cpu/thread_pool.h"
#include "models/model.h"
#include "domain/texture_domain.h"
#include "moldtex.h"
#include "surface/surface.h"

namespace moldtex {

// texel -> (V, U) before the stroke's first dab there.
using ReactionUndo = PaintUndo;

// One dab into `planes` (V then U, width * height each, read_rgba's order; the gutter is
// filled again afterwards). Returns how many texels changed. The brush is validated by
// the caller.
uint32_t paint_reaction(const Surface& s, const TextureDomain& d, float* planes, const moldtex_brush& brush,
                        bool erase, ReactionUndo& undo, ThreadPool& pool);

// Puts back what `undo` kept, then fills the gutter.
void restore_reaction(const TextureDomain& d, float* planes, const ReactionUndo& undo, ThreadPool& pool);

}  // namespace moldtex
