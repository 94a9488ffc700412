/* field.h — per-texel pheromone operations of the texture domain. */
#ifndef MOLDTEX_SHARED_FIELD_H
#define MOLDTEX_SHARED_FIELD_H

#ifndef __OPENCL_C_VERSION__
#include "shared/constants.h"
#include "shared/portable.h"
#endif

MTX_BEGIN_NAMESPACE

/* New value of island texel x of a row: p + mix * (blur3x3(p) - p) - evaporation,
 * clamped to [0, 1], from the row (r1), the rows above and below (r0, r2; null beyond the
 * texture) and their classes (c0, c1, c2). The 3x3 Gaussian (1 2 1 outer product) weighs
 * only island and gutter texels, so island borders neither darken nor leak; outside
 * texels hold 0. Rows, not a plane, so that a caller may hold them anywhere (the CPU's
 * deposited rows). */
MTX_FN float mtx_diffuse_evaporate_rows(MTX_GLOBAL const float* r0, MTX_GLOBAL const float* r1,
                                        MTX_GLOBAL const float* r2, MTX_GLOBAL const mtx_u8* c0,
                                        MTX_GLOBAL const mtx_u8* c1, MTX_GLOBAL const mtx_u8* c2, int x,
                                        int width, float mix, float evaporation) {
  float sum = 0.0f, weight = 0.0f;
  for (int dy = -1; dy <= 1; ++dy) {
    MTX_GLOBAL const float* row = dy < 0 ? r0 : (dy == 0 ? r1 : r2);
    MTX_GLOBAL const mtx_u8* cls = dy < 0 ? c0 : (dy == 0 ? c1 : c2);
    if (row == 0) continue;
    const float wy = dy == 0 ? 2.0f : 1.0f;
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx;
      if (nx < 0 || nx >= width) continue;
      const float w = wy * (dx == 0 ? 2.0f : 1.0f);
      sum += w * row[nx];
      weight += cls[nx] != MTX_TEXEL_OUTSIDE ? w : 0.0f;
    }
  }
  const float p = r1[x];
  const float v = p + mix * (sum / weight - p) - evaporation;
  return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

/* The same for texel (x, y) of a plane `in` of width x height texels. */
MTX_FN float mtx_diffuse_evaporate_texel(MTX_GLOBAL const float* in,
                                          MTX_GLOBAL const mtx_u8* classes, int x, int y,
                                          int width, int height, float mix, float evaporation) {
  const mtx_u32 row = MTX_CAST(mtx_u32, y) * MTX_CAST(mtx_u32, width);
  const mtx_u32 w = MTX_CAST(mtx_u32, width);
  MTX_GLOBAL const float* r0 = y > 0 ? in + (row - w) : 0;
  MTX_GLOBAL const float* r2 = y + 1 < height ? in + (row + w) : 0;
  MTX_GLOBAL const mtx_u8* c0 = y > 0 ? classes + (row - w) : 0;
  MTX_GLOBAL const mtx_u8* c2 = y + 1 < height ? classes + (row + w) : 0;
  return mtx_diffuse_evaporate_rows(r0, in + row, r2, c0, classes + row, c2, x, width, mix, evaporation);
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
