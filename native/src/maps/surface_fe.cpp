#include "maps/surface_fe.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include <Eigen/SparseCholesky>

#include "common/error.h"

namespace moldtex::maps {
namespace {

struct D3 {
  double x, y, z;
};
D3 sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(D3 a) { return std::sqrt(dot(a, a)); }
D3 vertex(const Surface& s, uint32_t v) {
  return {s.positions[3ull * v], s.positions[3ull * v + 1], s.positions[3ull * v + 2]};
}

uint32_t find(std::vector<uint32_t>& parent, uint32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

}  // namespace

SurfaceFE build_surface_fe(const Surface& s) {
  SurfaceFE fe;
  const uint32_t nv = s.vertex_count(), nt = static_cast<uint32_t>(s.triangles.size() / 3);
  fe.vertex_count = nv;
  fe.triangle_count = nt;
  fe.mass.assign(nv, 0.0);
  fe.kept.assign(nt, 0);
  fe.areas.assign(nt, 0.0);
  fe.grad_basis.assign(9ull * nt, 0.0);
  fe.used.assign(nv, 0);

  // Relative threshold, as build_surface uses: sizes do not matter, shapes do.
  double max_edge = 0;
  for (uint32_t t = 0; t < nt; ++t)
    for (int c = 0; c < 3; ++c)
      max_edge = std::max(max_edge, norm(sub(vertex(s, s.triangles[3 * t + (c + 1) % 3]),
                                             vertex(s, s.triangles[3 * t + c]))));
  const double area_eps = 1e-12 * max_edge * max_edge;

  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(9ull * nt);
  std::vector<uint32_t> parent(nv);
  std::iota(parent.begin(), parent.end(), 0u);
  double edge_sum = 0;
  uint64_t edge_count = 0;
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t* v = &s.triangles[3ull * t];
    const D3 p[3] = {vertex(s, v[0]), vertex(s, v[1]), vertex(s, v[2])};
    const D3 n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    const double twice_area = norm(n);
    if (!(0.5 * twice_area > area_eps) || v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
    fe.kept[t] = 1;
    const double area = 0.5 * twice_area;
    fe.areas[t] = area;
    fe.total_area += area;
    const D3 un = {n.x / twice_area, n.y / twice_area, n.z / twice_area};
    // grad phi_c = (N x e_c) / (2A), e_c the edge opposite corner c, running from corner
    // c+1 to corner c+2 (counter-clockwise about N).
    D3 g[3];
    for (int c = 0; c < 3; ++c) {
      const D3 e = sub(p[(c + 2) % 3], p[(c + 1) % 3]);
      const D3 r = cross(un, e);
      g[c] = {r.x / twice_area, r.y / twice_area, r.z / twice_area};
      double* out = &fe.grad_basis[9ull * t + 3 * c];
      out[0] = g[c].x;
      out[1] = g[c].y;
      out[2] = g[c].z;
      edge_sum += norm(e);
      ++edge_count;
    }
    for (int i = 0; i < 3; ++i) {
      fe.mass[v[i]] += area / 3.0;
      fe.used[v[i]] = 1;
      for (int j = 0; j < 3; ++j)
        triplets.emplace_back(static_cast<int>(v[i]), static_cast<int>(v[j]), area * dot(g[i], g[j]));
    }
    parent[find(parent, v[1])] = find(parent, v[0]);
    parent[find(parent, v[2])] = find(parent, v[0]);
  }
  fe.mean_edge = edge_count ? edge_sum / double(edge_count) : 0.0;
  fe.stiffness.resize(static_cast<int>(nv), static_cast<int>(nv));
  fe.stiffness.setFromTriplets(triplets.begin(), triplets.end());
  fe.stiffness.makeCompressed();

  fe.component.assign(nv, -1);
  std::vector<int32_t> id_of_root(nv, -1);
  for (uint32_t i = 0; i < nv; ++i) {
    if (!fe.used[i]) continue;
    const uint32_t r = find(parent, i);
    if (id_of_root[r] < 0) id_of_root[r] = static_cast<int32_t>(fe.component_count++);
    fe.component[i] = id_of_root[r];
  }
  return fe;
}

void fe_gradient(const SurfaceFE& fe, const Surface& s, const double* u, double* out) {
  for (uint32_t t = 0; t < fe.triangle_count; ++t) {
    double g[3] = {0, 0, 0};
    if (fe.kept[t]) {
      for (int c = 0; c < 3; ++c) {
        const double value = u[s.triangles[3ull * t + c]];
        const double* b = &fe.grad_basis[9ull * t + 3 * c];
        for (int k = 0; k < 3; ++k) g[k] += value * b[k];
      }
    }
    std::copy(g, g + 3, out + 3ull * t);
  }
}

std::vector<double> fe_divergence(const SurfaceFE& fe, const Surface& s, const double* X) {
  std::vector<double> b(fe.vertex_count, 0.0);
  for (uint32_t t = 0; t < fe.triangle_count; ++t) {
    if (!fe.kept[t]) continue;
    const double* x = X + 3ull * t;
    for (int c = 0; c < 3; ++c) {
      const double* g = &fe.grad_basis[9ull * t + 3 * c];
      b[s.triangles[3ull * t + c]] += fe.areas[t] * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
    }
  }
  return b;
}

std::vector<double> solve_fixed(const SurfaceFE& fe, double a, double b, const std::vector<double>& rhs,
                                const std::vector<uint8_t>& fixed, const std::vector<double>& x_in) {
  const uint32_t n = fe.vertex_count;
  std::vector<double> x(x_in);
  std::vector<int> index(n, -1);
  int free_count = 0;
  for (uint32_t i = 0; i < n; ++i)
    if (!fixed[i]) index[i] = free_count++;
  if (free_count == 0) return x;

  // A_FF and rhs_F - A_FC x_C, from the columns of K (symmetric) and the diagonal M.
  Eigen::VectorXd r(free_count);
  for (uint32_t i = 0; i < n; ++i)
    if (index[i] >= 0) r[index[i]] = rhs[i];
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<size_t>(fe.stiffness.nonZeros()) + free_count);
  for (uint32_t j = 0; j < n; ++j) {
    if (index[j] >= 0 && a != 0.0) triplets.emplace_back(index[j], index[j], a * fe.mass[j]);
    for (SparseMatrix::InnerIterator it(fe.stiffness, static_cast<int>(j)); it; ++it) {
      const int i = it.row();
      if (index[i] < 0) continue;
      const double value = b * it.value();
      if (index[j] >= 0)
        triplets.emplace_back(index[i], index[j], value);
      else
        r[index[i]] -= value * x[j];
    }
  }
  SparseMatrix A(free_count, free_count);
  A.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<SparseMatrix> ldlt;
  ldlt.compute(A);
  if (ldlt.info() != Eigen::Success)
    fail(MOLDTEX_ERROR_INTERNAL, "The surface map solve could not factorise its matrix (" +
                                     std::to_string(free_count) + " unknowns)");
  const Eigen::VectorXd y = ldlt.solve(r);
  if (ldlt.info() != Eigen::Success || !y.allFinite())
    fail(MOLDTEX_ERROR_INVALID_MESH,
         "The surface map solve gave non-finite values: the mesh probably has near-degenerate "
         "triangles (slivers); try Mesh > Clean Up > Degenerate Dissolve");
  for (uint32_t i = 0; i < n; ++i)
    if (index[i] >= 0) x[i] = y[index[i]];
  return x;
}

}  // namespace moldtex::maps
