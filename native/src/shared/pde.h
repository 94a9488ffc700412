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

/* Local time stepping (domain/texel_laplacian.h, LocalSteppingPlan): within one coarse
 * sub-step the few stiff cells ("fine", is_fine[texel] = 1) take several fine sub-steps
 * of length h, reading their fine neighbours' current values (cur) and their coarse
 * neighbours' values frozen at the coarse sub-step's start (frozen). What flows in from
 * each coarse neighbour is summed in flux[k] (the row's CSR entry k), and the coarse
 * neighbour gives up exactly that amount (mtx_coarse_cell), so the total is conserved. */
MTX_FN float mtx_fine_cell(MTX_GLOBAL const mtx_u32* rows, MTX_GLOBAL const mtx_u32* start,
                           MTX_GLOBAL const mtx_u32* col, MTX_GLOBAL const float* weight,
                           MTX_GLOBAL const float* area, MTX_GLOBAL const mtx_u8* is_fine,
                           MTX_GLOBAL const float* frozen, MTX_GLOBAL const float* cur,
                           MTX_GLOBAL float* flux, mtx_u32 r, float h) {
  const mtx_u32 i = rows[r];
  const float ui = cur[i];
  float total = 0.0f;
  for (mtx_u32 k = start[r]; k < start[r + 1]; ++k) {
    const mtx_u32 j = col[k];
    const int fine = is_fine[j];
    const float f = weight[k] * ((fine ? cur[j] : frozen[j]) - ui);
    total += f;
    if (!fine) flux[k] += h * f;
  }
  return ui + h / area[i] * total;
}

/* A coarse cell's sub-step of length h: forward Euler with its coarse neighbours, minus
 * what its fine neighbours drew from it (flux at the reverse entry, reverse[k] being the
 * entry (j -> i) of the entry (i -> j)), times `decay`. */
MTX_FN float mtx_coarse_cell(MTX_GLOBAL const mtx_u32* rows, MTX_GLOBAL const mtx_u32* start,
                             MTX_GLOBAL const mtx_u32* col, MTX_GLOBAL const float* weight,
                             MTX_GLOBAL const float* area, MTX_GLOBAL const mtx_u8* is_fine,
                             MTX_GLOBAL const mtx_u32* reverse, MTX_GLOBAL const float* in,
                             MTX_GLOBAL const float* flux, mtx_u32 r, float h, float decay) {
  const mtx_u32 i = rows[r];
  const float ui = in[i];
  float total = 0.0f, drawn = 0.0f;
  for (mtx_u32 k = start[r]; k < start[r + 1]; ++k) {
    const mtx_u32 j = col[k];
    if (is_fine[j])
      drawn += flux[reverse[k]];
    else
      total += weight[k] * (in[j] - ui);
  }
  return (ui + (h * total - drawn) / area[i]) * decay;
}

/* A write stimulus (moldtex_sim_set_map): value * amount added to concentration u,
 * never below 0 (a negative stimulus removes what is there). */
MTX_FN float mtx_write_stimulus(float u, float value, float amount) {
  const float v = u + value * amount;
  return v > 0.0f ? v : 0.0f;
}

MTX_END_NAMESPACE

#endif
