#include "intrinsic/mollification.h"

#include <algorithm>

namespace moldtex::intrinsic {

double mean_edge_length(const IntrinsicMesh& m) {
  double sum = 0;
  uint32_t n = 0;
  for (uint32_t e = 0; e < m.edge_count(); ++e) {
    if (m.he_face[2 * e] == kInvalid && m.he_face[2 * e + 1] == kInvalid) continue;
    sum += m.length[e];
    ++n;
  }
  return n ? sum / n : 0.0;
}

double mollify(IntrinsicMesh& m, double delta) {
  double eps = 0;
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const auto h = m.face_halfedges(f);
    const double l[3] = {m.len(h[0]), m.len(h[1]), m.len(h[2])};
    for (int i = 0; i < 3; ++i) eps = std::max(eps, delta - (l[(i + 1) % 3] + l[(i + 2) % 3] - l[i]));
  }
  if (eps > 0)
    for (double& l : m.length) l += eps;
  return eps;
}

}  // namespace moldtex::intrinsic
