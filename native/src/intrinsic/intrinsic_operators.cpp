#include "intrinsic/intrinsic_operators.h"

namespace moldtex::intrinsic {

IntrinsicOperators build_intrinsic_operators(const IntrinsicMesh& m) {
  IntrinsicOperators ops;
  const int nv = static_cast<int>(m.vertex_count());
  ops.mass.assign(nv, 0.0);
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(12ull * m.face_count());
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const double third = m.face_area(f) / 3.0;
    for (uint32_t h : m.face_halfedges(f)) {
      const int i = static_cast<int>(m.tail(h)), j = static_cast<int>(m.head(h));
      ops.mass[i] += third;
      const double w = 0.5 * m.opposite_cotan(h);
      triplets.emplace_back(i, j, -w);
      triplets.emplace_back(j, i, -w);
      triplets.emplace_back(i, i, w);
      triplets.emplace_back(j, j, w);
    }
  }
  ops.stiffness.resize(nv, nv);
  ops.stiffness.setFromTriplets(triplets.begin(), triplets.end());
  ops.stiffness.makeCompressed();
  return ops;
}

}  // namespace moldtex::intrinsic
