#include "maps/map_diffusion.h"

#include <algorithm>

namespace moldtex::maps {

std::vector<double> diffuse_map(const SurfaceFE& fe, const std::vector<double>& values, double t) {
  const uint32_t n = fe.vertex_count;
  std::vector<uint8_t> fixed(n, 0);
  std::vector<double> rhs(n, 0.0), x(n, 0.0);
  for (uint32_t i = 0; i < n; ++i) {
    fixed[i] = !fe.used[i];
    rhs[i] = fe.mass[i] * values[i];
    if (fe.used[i]) x[i] = values[i];
  }
  if (!(t > 0)) return x;
  t = std::min(t, 1e3 * std::max(fe.total_area, fe.mean_edge * fe.mean_edge));
  return solve_fixed(fe, 1.0, t, rhs, fixed, x);
}

}  // namespace moldtex::maps
