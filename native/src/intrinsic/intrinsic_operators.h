// Linear finite elements on the intrinsic triangulation (issue 11): the cotangent
// stiffness matrix and the lumped mass matrix, from edge lengths alone.
//
// For a face with corners i, j, k, the hat functions' gradients satisfy
//   A grad phi_i . grad phi_j = -cot(theta_k) / 2,
// theta_k the angle at k, so the stiffness (weak-form Laplacian, positive semi-definite)
//   K_ij = -(cot alpha_ij + cot beta_ij) / 2   (i != j, the angles opposite edge ij),
//   K_ii = -sum_j K_ij,
// and K u = 0 for u linear over a flat region (linear precision). On an intrinsic
// Delaunay triangulation every weight (cot alpha + cot beta) / 2 is >= 0 (Bobenko &
// Springborn 2007): K is an M-matrix, and the discrete heat flow has a maximum principle.
// Mass: barycentric lumping, a third of each face's area to each corner. The
// Laplace-Beltrami operator is Delta u ~ -M^-1 K u (pointwise at the vertices).
// Cotangents come from lengths: cot theta_k = (a^2 + b^2 - c^2) / (4 A), c opposite k.
#pragma once
#include <vector>

#include <Eigen/Sparse>

#include "intrinsic/intrinsic_mesh.h"

namespace moldtex::intrinsic {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

struct IntrinsicOperators {
  SparseMatrix stiffness;    // vertex_count x vertex_count
  std::vector<double> mass;  // lumped, per vertex (0 for unused vertices)
};

IntrinsicOperators build_intrinsic_operators(const IntrinsicMesh& m);

}  // namespace moldtex::intrinsic
