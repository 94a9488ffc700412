#include "maps/heat_geodesic.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace moldtex::maps {

std::vector<double> heat_geodesic_distance(const Surface& s, const SurfaceFE& fe,
                                           const std::vector<uint8_t>& source, double time_factor) {
  const uint32_t n = fe.vertex_count;
  std::vector<double> distance(n, kUnreachableDistance);
  for (uint32_t i = 0; i < n; ++i)
    if (source[i] && !fe.used[i]) distance[i] = 0.0;
  std::vector<uint8_t> has_source(fe.component_count, 0);
  bool any = false;
  for (uint32_t i = 0; i < n; ++i)
    if (source[i] && fe.used[i]) has_source[fe.component[i]] = 1, any = true;
  if (!any) return distance;

  // 1. Heat: (M + t K) u = M u0, u0 the indicator of the sources. u0 is scaled far up so
  //    that the heat, which falls by a roughly constant factor per edge away from the
  //    sources, stays a normal double ~500 decades further out; the next step only needs
  //    its direction.
  constexpr double kHeatScale = 1e200;
  const double t = time_factor * fe.mean_edge * fe.mean_edge;
  std::vector<double> rhs(n, 0.0), zero(n, 0.0);
  std::vector<uint8_t> fixed(n, 0);
  for (uint32_t i = 0; i < n; ++i) {
    fixed[i] = !fe.used[i];
    if (source[i] && fe.used[i]) rhs[i] = kHeatScale * fe.mass[i];
  }
  const std::vector<double> u = solve_fixed(fe, 1.0, t, rhs, fixed, zero);

  // 2. X = -grad u / |grad u| per triangle (0 where the heat is flat or did not arrive).
  std::vector<double> X(3ull * fe.triangle_count);
  fe_gradient(fe, s, u.data(), X.data());
  for (uint32_t tri = 0; tri < fe.triangle_count; ++tri) {
    double* g = &X[3ull * tri];
    const double m = std::max({std::fabs(g[0]), std::fabs(g[1]), std::fabs(g[2])});
    if (!(m > 0) || !std::isfinite(m)) {
      g[0] = g[1] = g[2] = 0.0;
      continue;
    }
    const double a = g[0] / m, b = g[1] / m, c = g[2] / m;
    const double len = std::sqrt(a * a + b * b + c * c);
    g[0] = -a / len;
    g[1] = -b / len;
    g[2] = -c / len;
  }

  // 3. K phi = div X, one vertex per component pinned (K's null space is the constants
  //    of each component): a source where the component has one.
  const std::vector<double> b = fe_divergence(fe, s, X.data());
  std::vector<int64_t> pin(fe.component_count, -1);
  for (uint32_t i = 0; i < n; ++i) {
    if (!fe.used[i]) continue;
    int64_t& p = pin[fe.component[i]];
    if (p < 0 || (source[i] && !source[static_cast<uint32_t>(p)])) p = i;
  }
  for (int64_t p : pin)
    if (p >= 0) fixed[static_cast<uint32_t>(p)] = 1;
  const std::vector<double> phi = solve_fixed(fe, 0.0, 1.0, b, fixed, zero);

  // 4. Shift: the smallest value over each component's sources becomes 0.
  std::vector<double> shift(fe.component_count, std::numeric_limits<double>::infinity());
  for (uint32_t i = 0; i < n; ++i)
    if (source[i] && fe.used[i]) shift[fe.component[i]] = std::min(shift[fe.component[i]], phi[i]);
  for (uint32_t i = 0; i < n; ++i) {
    if (!fe.used[i] || !has_source[fe.component[i]]) continue;
    distance[i] = source[i] ? 0.0 : std::max(0.0, phi[i] - shift[fe.component[i]]);
  }
  return distance;
}

}  // namespace moldtex::maps
