// Linear finite elements on the input mesh (Layton et al. §6, issue 12): the cotangent
// stiffness matrix K (the weak-form Laplacian, positive semi-definite), the lumped
// (barycentric) mass matrix M, the per-triangle gradient and the integrated divergence.
//
// The FE nodes are the vertices of moldtex_mesh_desc: UV seams split UVs, not positions,
// so a field over the vertices is continuous across seams. Triangles with (near) zero 3D
// area are skipped; vertices no kept triangle uses ("unused") get no stiffness and no
// mass: the solvers below hold them fixed (see solve_fixed).
#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Sparse>

#include "surface/surface.h"

namespace moldtex::maps {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

struct SurfaceFE {
  uint32_t vertex_count = 0;
  uint32_t triangle_count = 0;
  SparseMatrix stiffness;               // K_ij = sum_t A_t grad phi_i . grad phi_j
  std::vector<double> mass;             // lumped: a third of each kept triangle's area
  std::vector<uint8_t> kept;            // per triangle: 1 if its 3D area is not ~0
  std::vector<double> areas;            // per triangle (0 where not kept)
  std::vector<double> grad_basis;       // 9 per triangle: grad phi_c (3D) of corner c
  std::vector<uint8_t> used;            // per vertex: in at least one kept triangle
  std::vector<int32_t> component;       // per vertex: component id over kept triangles, -1 unused
  uint32_t component_count = 0;
  double mean_edge = 0;                 // mean length of the kept triangles' edges
  double total_area = 0;
};

// Builds the FE operators of a validated surface. Never fails on geometry: a surface with
// no kept triangle gives empty operators (every vertex unused).
SurfaceFE build_surface_fe(const Surface& s);

// Per-triangle gradient of the piecewise-linear function u (one value per vertex):
// 3 doubles per triangle, 0 for triangles not kept. Exact for linear functions.
void fe_gradient(const SurfaceFE& fe, const Surface& s, const double* u, double* out);
// Integrated divergence paired with fe_gradient: b_i = sum_t A_t grad phi_i . X_t, i.e.
// the right-hand side of K phi = b, the least-squares fit grad phi ~ X.
std::vector<double> fe_divergence(const SurfaceFE& fe, const Surface& s, const double* X);

// Solves (a M + b K) x = rhs on the vertices with fixed[i] == 0, with x given (x_in) on the
// fixed vertices (Dirichlet); returns x (the fixed entries copied). Eigen's SimplicialLDLT;
// the caller makes sure every component of free vertices is non-singular (a > 0, or a
// fixed vertex in it). Throws moldtex::Error if the factorisation fails or the result is
// not finite.
std::vector<double> solve_fixed(const SurfaceFE& fe, double a, double b, const std::vector<double>& rhs,
                                const std::vector<uint8_t>& fixed, const std::vector<double>& x_in);

}  // namespace moldtex::maps
