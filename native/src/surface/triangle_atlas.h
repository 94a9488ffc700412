// A placeholder UV layout for meshes that come without one: every triangle its own small
// island, on a square grid of cells. The intrinsic domain keeps its concentrations on the
// surface and needs UVs only to write a texture, so such a mesh can still run there (its
// result is read per mesh vertex, moldtex_sim_read_vertex_rgba); the texture domain keeps
// the pheromone in texels and refuses such a surface.
#pragma once
#include <cstdint>
#include <vector>

namespace moldtex {

// 6 floats per triangle (u, v of its three corners): triangle t in grid cell
// (t mod g, t div g), g = ceil(sqrt(triangle_count)), a right triangle spanning 70% of the
// cell's side. Islands never overlap; the 30% between them leaves gutter texels once a cell
// is a few texels wide.
std::vector<float> triangle_atlas_uvs(uint32_t triangle_count);

}  // namespace moldtex
