// Geodesic distance from a region with the heat method (Crane, Weischedel and Wardetzky
// 2013; Layton et al. §6, Fig. 15-16): one backward-Euler heat step from the sources, the
// normalised negative gradient of the heat, and a Poisson solve for the function whose
// gradient fits it best.
#pragma once
#include <cstdint>
#include <vector>

#include "maps/surface_fe.h"

namespace moldtex::maps {

// Value given to vertices that no source can reach over the surface: vertices of a
// connected component (over the non-degenerate triangles) without a source vertex, and
// vertices no non-degenerate triangle uses (unless they are sources themselves: 0).
constexpr double kUnreachableDistance = -1.0;

// Distance per vertex from the vertices with source[i] != 0. The heat flows for
// t = time_factor * h^2, h the mean edge length (Crane et al.'s choice for time_factor 1;
// larger values give smoother, slightly longer distances). The result is shifted so that
// each component's smallest value over its sources is 0; sources are exactly 0 and no
// distance is negative. If no vertex is a source every value is kUnreachableDistance.
// On meshes several hundred edges across the heat from a small source underflows far
// away (the solve keeps ~500 decades of range); raise time_factor there.
std::vector<double> heat_geodesic_distance(const Surface& s, const SurfaceFE& fe,
                                           const std::vector<uint8_t>& source, double time_factor);

}  // namespace moldtex::maps
