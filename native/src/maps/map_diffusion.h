// Short-time diffusion of a per-vertex map (Layton et al. §6, Fig. 14: blurring a painted
// map over the surface, across UV seams): one backward-Euler step (M + t K) x = M x0.
// The M-weighted integral sum_i M_i x_i is conserved exactly (K's columns sum to 0), the
// maximum principle holds on non-obtuse meshes, and t -> 0 gives x0.
#pragma once
#include <cstdint>
#include <vector>

#include "maps/surface_fe.h"

namespace moldtex::maps {

// t in mesh units squared: the continuous heat kernel after time t is a Gaussian of
// standard deviation sqrt(2 t) along each surface direction, so a blur of radius r
// (standard deviation) is t = r^2 / 2. Times beyond 1000 x the surface area (when the
// result has long become each component's mean) are clamped there, to keep the matrix
// well conditioned. Vertices no non-degenerate triangle uses get 0.
std::vector<double> diffuse_map(const SurfaceFE& fe, const std::vector<double>& values, double t);

}  // namespace moldtex::maps
