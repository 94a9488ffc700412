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

/* Local time stepping (domain/texel_laplacian.h, LocalSteppingPlan) sorts the cells into
 * three classes (step_class, one byte per texel): */
#define MTX_STEP_COARSE 0u /* a coarse cell with no fine neighbour (nearly all of them) */
#define MTX_STEP_FINE 1u   /* a stiff cell, sub-stepped more finely */
#define MTX_STEP_BORDER 2u /* a coarse cell with a fine neighbour */

/* Within one coarse sub-step the few stiff cells (MTX_STEP_FINE) take several fine sub-steps
 * of length h, reading their fine neighbours' current values (cur) and their coarse
 * neighbours' values frozen at the coarse sub-step's start (frozen, per texel). The fine
 * cells keep their own compact copy of their rows (LocalSteppingPlan): fine cell f's
 * entries e = fine_start[f] .. fine_start[f + 1], each a neighbour fine_nbr[e] (a texel,
 * or MTX_FINE_NEIGHBOUR | the fine index of a fine neighbour) with conductance
 * fine_weight[e]; its area fine_area[f]; its value cur[f]. What flows in from each coarse
 * neighbour is summed in flux[e], and the coarse neighbour gives up exactly that amount
 * (mtx_coarse_cell), so the total is conserved. The fine cells lie scattered over the
 * matrix: read in place, each row cost several misses to memory per fine sub-step. */
#define MTX_FINE_NEIGHBOUR 0x80000000u
MTX_FN float mtx_fine_cell(MTX_GLOBAL const mtx_u32* fine_start, MTX_GLOBAL const mtx_u32* fine_nbr,
                           MTX_GLOBAL const float* fine_weight, MTX_GLOBAL const float* fine_area,
                           MTX_GLOBAL const float* frozen, MTX_GLOBAL const float* cur,
                           MTX_GLOBAL float* flux, mtx_u32 f, float h) {
  const float ui = cur[f];
  float total = 0.0f;
  for (mtx_u32 e = fine_start[f]; e < fine_start[f + 1]; ++e) {
    const mtx_u32 n = fine_nbr[e];
    const int fine = (n & MTX_FINE_NEIGHBOUR) != 0u;
    const float q = fine_weight[e] * ((fine ? cur[n & ~MTX_FINE_NEIGHBOUR] : frozen[n]) - ui);
    total += q;
    if (!fine) flux[e] += h * q;
  }
  return ui + h / fine_area[f] * total;
}

/* A coarse cell's sub-step of length h: forward Euler with its coarse neighbours, minus
 * what its fine neighbours drew from it (flux[link[k]] for its entry k towards a fine
 * cell: the flux of that cell's compact entry back to this one), times `decay`. Only
 * MTX_STEP_BORDER cells have fine neighbours: the others skip the per-neighbour test
 * (half the cost of the row) and compute the same expression with drawn = 0, so the same
 * bits. */
MTX_FN float mtx_coarse_cell(MTX_GLOBAL const mtx_u32* rows, MTX_GLOBAL const mtx_u32* start,
                             MTX_GLOBAL const mtx_u32* col, MTX_GLOBAL const float* weight,
                             MTX_GLOBAL const float* area, MTX_GLOBAL const mtx_u8* step_class,
                             MTX_GLOBAL const mtx_u32* link, MTX_GLOBAL const float* in,
                             MTX_GLOBAL const float* flux, mtx_u32 r, float h, float decay) {
  const mtx_u32 i = rows[r];
  const float ui = in[i];
  float total = 0.0f, drawn = 0.0f;
  if (step_class[i] == MTX_STEP_COARSE) {
    for (mtx_u32 k = start[r]; k < start[r + 1]; ++k) total += weight[k] * (in[col[k]] - ui);
  } else {
    for (mtx_u32 k = start[r]; k < start[r + 1]; ++k) {
      const mtx_u32 j = col[k];
      if (step_class[j] == MTX_STEP_FINE)
        drawn += flux[link[k]];
      else
        total += weight[k] * (in[j] - ui);
    }
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
