// Laplace interpolation between regions with fixed values (Layton et al. §6, Fig. 17):
// the harmonic function (K x = 0 on the free vertices) that takes the given values on the
// fixed vertices, i.e. the smoothest blend (least Dirichlet energy) between them.
#pragma once
#include <cstdint>
#include <vector>

#include "maps/surface_fe.h"

namespace moldtex::maps {

// x with x_i = values[i] where fixed[i] != 0 and (K x)_i = 0 elsewhere. Free vertices of a
// connected component without any fixed vertex, and free vertices that no non-degenerate
// triangle uses, get 0 (their count in *unconstrained if not null).
std::vector<double> laplace_interpolate(const SurfaceFE& fe, const std::vector<double>& values,
                                        const std::vector<uint8_t>& fixed, uint32_t* unconstrained = nullptr);

}  // namespace moldtex::maps
