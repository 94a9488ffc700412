// Each triangle's edge neighbours unfolded into its frame (shared/walk.h,
// MTX_UNFOLDED_FLOATS), so that a short straight walk that leaves a triangle across
// one edge can be located in the neighbour, and in the neighbour's UVs, without walking.
#pragma once

#include "surface/surface.h"

namespace moldtex {

// Fills s.unfolded from s.frames, s.adjacency and s.corner_uvs (zeros across open
// boundaries and walls, which a caller tells from s.adjacency).
void unfold_neighbours(Surface& s);

}  // namespace moldtex
