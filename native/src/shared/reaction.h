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

/* V's ceiling. With u <= 1 (which the update keeps), dv/dt <= v^2 - (F + k) v, so where
 * D_u is so much larger than D_v that neighbours refill u faster than the cell uses it
 * (u held near 1), V runs to infinity in finite time. Normal patterns peak at v ~ 1.6 (the
 * seeds' first seconds), far below the ceiling; it only keeps such extreme settings finite. */
#define MTX_REACTION_MAX_V 4.0f

/* Cell rows[r] (texel i) after one sub-step of length h, forward Euler
 *   U* = U + du (L U)_i + h (F (1 - U) - U V^2)
 *   V* = V + dv (L V)_i + h (U V^2 - (F + k) V)
 * with (L X)_i = 1 / A_i sum_j c_ij (X_j - X_i) over the CSR row start[r] .. start[r + 1],
 * du = h D_u, dv = h D_v. A cell too stiff for h (du rate_r > 0.5, rate_r = sum_j c_ij /
 * A_i: the few tiny texels at UV poles or pinches) takes its own diffusion loss
 * implicitly instead: U' = (U* + du rate_r U) / (1 + du rate_r) (likewise V), which
 * follows its neighbours' mean rather than overshooting; every weight is then
 * non-negative, so U stays in [0, 1] while h (1 + F + k) <= 0.5; V is kept in
 * [0, MTX_REACTION_MAX_V].
 * With use_feed_map (use_kill_map), F (k) is multiplied by feed_map[i] (kill_map[i]) and
 * capped at 1, the parameters' own range (moldtex_sim_set_map FEED / KILL).
 * Reads only v_in and u_in and writes only v_out[i] and u_out[i]: every cell is
 * independent of the others and of the order they run in. */
MTX_FN void mtx_gray_scott_cell(MTX_GLOBAL const mtx_u32* rows, MTX_GLOBAL const mtx_u32* start,
                                MTX_GLOBAL const mtx_u32* col, MTX_GLOBAL const float* weight,
                                MTX_GLOBAL const float* area, MTX_GLOBAL const float* rate,
                                MTX_GLOBAL const float* v_in, MTX_GLOBAL const float* u_in,
                                MTX_GLOBAL float* v_out, MTX_GLOBAL float* u_out, mtx_u32 r, float h,
                                float du, float dv, float feed, float kill,
                                MTX_GLOBAL const float* feed_map, MTX_GLOBAL const float* kill_map,
                                mtx_u32 use_feed_map, mtx_u32 use_kill_map) {
  const mtx_u32 i = rows[r];
  if (use_feed_map) {
    feed *= feed_map[i];
    feed = feed < 1.0f ? feed : 1.0f;
  }
  if (use_kill_map) {
    kill *= kill_map[i];
    kill = kill < 1.0f ? kill : 1.0f;
  }
  const float ui = u_in[i], vi = v_in[i];
  float flux_u = 0.0f, flux_v = 0.0f;
  for (mtx_u32 k = start[r]; k < start[r + 1]; ++k) {
    const mtx_u32 j = col[k];
    flux_u += weight[k] * (u_in[j] - ui);
    flux_v += weight[k] * (v_in[j] - vi);
  }
  const float inv_area = area[i] > 0.0f ? 1.0f / area[i] : 0.0f;
  const float uvv = ui * vi * vi;
  float u = ui + du * inv_area * flux_u + h * (feed * (1.0f - ui) - uvv);
  float v = vi + dv * inv_area * flux_v + h * (uvv - (feed + kill) * vi);
  const float su = du * rate[r], sv = dv * rate[r];
  if (su > 0.5f) u = (u + su * ui) / (1.0f + su);
  if (sv > 0.5f) v = (v + sv * vi) / (1.0f + sv);
  u_out[i] = u > 0.0f ? u : 0.0f;
  v_out[i] = v > 0.0f ? (v < MTX_REACTION_MAX_V ? v : MTX_REACTION_MAX_V) : 0.0f;
}

MTX_END_NAMESPACE

#endif
