/* reaction.h — one forward-Euler sub-step of the Gray-Scott reaction-diffusion model
 * (moldtex.h, MOLDTEX_MODEL_GRAY_SCOTT) on the texel Laplacian (domain/texel_laplacian.h),
 * shared by the CPU backend and the OpenCL kernel gray_scott_substep so both run the same
 * arithmetic. */
#ifndef MOLDTEX_SHARED_REACTION_H
#define MOLDTEX_SHARED_REACTION_H

#ifndef __OPENCL_C_VERSION__
#include "shared/portable.h"
#endif

MTX_BEGIN_NAMESPACE

/* Cell rows[r] (texel i) after one sub-step of length h, explicit in the reaction and
 * in the neighbours, implicit in the cell's own diffusion loss (a diagonally implicit,
 * linearised Euler step):
 *   U' = (U + du S_U + h (F (1 - U) - U V^2)) / (1 + du rate_r)
 *   V' = (V + dv S_V + h (U V^2 - (F + k) V)) / (1 + dv rate_r)
 * with S_X = 1 / A_i sum_j c_ij X_j over the CSR row start[r] .. start[r + 1] and
 * rate_r = 1 / A_i sum_j c_ij, du = h D_u, dv = h D_v. Where du rate_r is small this is
 * forward Euler up to O(h^2); where it is large (the few tiny texels at UV poles or
 * pinches) the cell follows its neighbours' mean instead of overshooting, so no cell
 * needs sub-steps for its own stiffness: every weight is non-negative, the new value is
 * bounded by the old ones and the reaction's (h (1 + F + k) <= 1 keeps it >= 0).
 * Reads only v_in and u_in and writes only v_out[i] and u_out[i]: every cell is
 * independent of the others and of the order they run in. */
MTX_FN void mtx_gray_scott_cell(MTX_GLOBAL const mtx_u32* rows, MTX_GLOBAL const mtx_u32* start,
                                MTX_GLOBAL const mtx_u32* col, MTX_GLOBAL const float* weight,
                                MTX_GLOBAL const float* area, MTX_GLOBAL const float* rate,
                                MTX_GLOBAL const float* v_in, MTX_GLOBAL const float* u_in,
                                MTX_GLOBAL float* v_out, MTX_GLOBAL float* u_out, mtx_u32 r, float h,
                                float du, float dv, float feed, float kill) {
  const mtx_u32 i = rows[r];
  const float ui = u_in[i], vi = v_in[i];
  float sum_u = 0.0f, sum_v = 0.0f;
  for (mtx_u32 k = start[r]; k < start[r + 1]; ++k) {
    const mtx_u32 j = col[k];
    sum_u += weight[k] * u_in[j];
    sum_v += weight[k] * v_in[j];
  }
  const float inv_area = area[i] > 0.0f ? 1.0f / area[i] : 0.0f;
  const float uvv = ui * vi * vi;
  const float u = (ui + du * inv_area * sum_u + h * (feed * (1.0f - ui) - uvv)) / (1.0f + du * rate[r]);
  const float v = (vi + dv * inv_area * sum_v + h * (uvv - (feed + kill) * vi)) / (1.0f + dv * rate[r]);
  u_out[i] = u > 0.0f ? u : 0.0f;
  v_out[i] = v > 0.0f ? v : 0.0f;
}

MTX_END_NAMESPACE

#endif
