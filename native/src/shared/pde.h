/* pde.h — one forward-Euler row of the continuous model's diffusion-decay PDE
 * (layton-intrinsic-slime.md Eq. 2) on the texel Laplacian (domain/texel_laplacian.h),
 * shared by the CPU backend and the OpenCL kernel pde_diffuse so both run the same
 * arithmetic. */
#ifndef MOLDTEX_SHARED_PDE_H
#define MOLDTEX_SHARED_PDE_H

#ifndef __OPENCL_C_VERSION__
#include "shared/portable.h"
#endif

MTX_BEGIN_NAMESPACE

/* New concentration of cell rows[r] after one sub-step of length h = r_dif * dt / n:
 *   (u_i + h / A_i * sum_j c_ij (u_j - u_i)) * decay
 * over the CSR row start[r] .. start[r + 1] (neighbour texels col, conductances weight),
 * A_i = area[rows[r]]. `decay` is 1 except on a step's last sub-step, where it applies
 * exp(-r_dec dt) in the same pass. Reads only `in`, so every row is independent of the
 * others and of the order they run in. Written as the flux form (u_j - u_i), not
 * sum c_ij u_j - u_i sum c_ij: a constant field stays exactly constant. */
MTX_FN float mtx_diffuse_cell(MTX_GLOBAL const mtx_u32* rows, MTX_GLOBAL const mtx_u32* start,
                              MTX_GLOBAL const mtx_u32* col, MTX_GLOBAL const float* weight,
                              MTX_GLOBAL const float* area, MTX_GLOBAL const float* in,
                              mtx_u32 r, float h, float decay) {
  const mtx_u32 i = rows[r];
  const float ui = in[i];
  float flux = 0.0f;
  for (mtx_u32 k = start[r]; k < start[r + 1]; ++k) flux += weight[k] * (in[col[k]] - ui);
  return (ui + h / area[i] * flux) * decay;
}

MTX_END_NAMESPACE

#endif
