/* field.h — per-texel pheromone operations of the texture domain. */
#ifndef MOLDTEX_SHARED_FIELD_H
#define MOLDTEX_SHARED_FIELD_H

#ifndef __OPENCL_C_VERSION__
#include "shared/constants.h"
#include "shared/portable.h"
#endif

MTX_BEGIN_NAMESPACE

/* New value of island texel (x, y): p + mix * (blur3x3(p) - p) - evaporation, clamped
 * to [0, 1]. The 3x3 Gaussian (1 2 1 outer product) weighs only island and gutter
 * texels, so island borders neither darken nor leak; outside texels hold 0. */
MTX_FN float mtx_diffuse_evaporate_texel(MTX_GLOBAL const float* in,
                                          MTX_GLOBAL const mtx_u8* classes, int x, int y,
                                          int width, int height, float mix, float evaporation) {
  float sum = 0.0f, weight = 0.0f;
  for (int dy = -1; dy <= 1; ++dy) {
    const int ny = y + dy;
    if (ny < 0 || ny >= height) continue;
    const float wy = dy == 0 ? 2.0f : 1.0f;
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx;
      if (nx < 0 || nx >= width) continue;
      const mtx_u32 ni = MTX_CAST(mtx_u32, ny) * MTX_CAST(mtx_u32, width) + MTX_CAST(mtx_u32, nx);
      const float w = wy * (dx == 0 ? 2.0f : 1.0f);
      sum += w * in[ni];
      weight += classes[ni] != MTX_TEXEL_OUTSIDE ? w : 0.0f;
    }
  }
  const float p = in[MTX_CAST(mtx_u32, y) * MTX_CAST(mtx_u32, width) + MTX_CAST(mtx_u32, x)];
  const float v = p + mix * (sum / weight - p) - evaporation;
  return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

/* Surface diffusion (moldtex_sim_params.length_unit > 0), one explicit pass on island
 * texel value u with its four neighbours along the texel axes (west, east, south, north):
 *   u + ax / 2 (w + e - 2u) + ay / 2 (s + n - 2u) - evaporation, clamped to [0, 1].
 * ax, ay are this pass's share of the variance (in texels^2) that the step adds along
 * each axis; the caller splits a step into passes so that ax + ay <= 1 (a kernel with
 * non-negative weights: no oscillation, no blow-up). A neighbour that does not exist
 * (open boundary) is the texel itself: nothing flows out. */
MTX_FN float mtx_surface_diffuse(float u, float w, float e, float s, float n, float ax,
                                 float ay, float evaporation) {
  const float v = u + 0.5f * ax * (w + e - 2.0f * u) + 0.5f * ay * (s + n - 2.0f * u) - evaporation;
  return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

MTX_END_NAMESPACE

#endif
