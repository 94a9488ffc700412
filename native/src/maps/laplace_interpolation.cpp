#include "maps/laplace_interpolation.h"

namespace moldtex::maps {

std::vector<double> laplace_interpolate(const SurfaceFE& fe, const std::vector<double>& values,
                                        const std::vector<uint8_t>& fixed, uint32_t* unconstrained) {
  const uint32_t n = fe.vertex_count;
  std::vector<uint8_t> anchored(fe.component_count, 0);
  for (uint32_t i = 0; i < n; ++i)
    if (fixed[i] && fe.used[i]) anchored[fe.component[i]] = 1;
  std::vector<uint8_t> held(n, 0);
  std::vector<double> x(n, 0.0);
  uint32_t loose = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (fixed[i]) {
      held[i] = 1;
      x[i] = values[i];
    } else if (!fe.used[i] || !anchored[fe.component[i]]) {
      held[i] = 1;  // stays 0
      ++loose;
    }
  }
  if (unconstrained) *unconstrained = loose;
  const std::vector<double> rhs(n, 0.0);
  return solve_fixed(fe, 0.0, 1.0, rhs, held, x);
}

}  // namespace moldtex::maps
