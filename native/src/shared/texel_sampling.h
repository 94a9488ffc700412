/* texel_sampling.h — the texture domain's point operations for the continuous model:
 * the concentration at a surface point (bilinear over the texel cells) and a deposit
 * at a surface point (spread over the same cells with the same weights). These are the
 * two calls an agent makes on its domain; another domain (an intrinsic triangulation)
 * provides the same two with its own basis functions: the linear hats of its vertices
 * (vertex_cells), or, where agents read and deposit, of its sampling lattice's nodes
 * (lattice; shared/intrinsic_lattice.h).
 *
 * The bilinear stencil of a point takes the four texels around it. For a deposit a
 * texel counts only when it is a cell of the point's own UV island (an island texel);
 * the weights of the others go to the cells that do count, so a deposit lands whole on
 * the island, and the PDE's seam couplings carry it across seams. A reading also counts
 * gutter texels, which hold the texels across their seams, so a sensor next to a seam
 * reads across it (and a probe beyond a seam walks over it into the other island). */
#ifndef MOLDTEX_SHARED_TEXEL_SAMPLING_H
#define MOLDTEX_SHARED_TEXEL_SAMPLING_H

#ifndef __OPENCL_C_VERSION__
#include "shared/constants.h"
#include "shared/intrinsic_lattice.h"
#include "shared/intrinsic_locate.h"
#include "shared/momas.h"
#include "shared/portable.h"
#include "shared/walk.h"
#endif

MTX_BEGIN_NAMESPACE

/* Deposits are fixed-point integer sums, so their total does not depend on the order
 * of the adds (bit-identical for any thread count). One agent's deposit of a step is
 * k->deposit_units units (continuous.h): at most 2^24 and at most (2^31 - 1) / agents,
 * so even every agent depositing into one texel cannot overflow a 32-bit sum. */
typedef struct mtx_texel_stencil {
  mtx_u32 cell[4];
  float weight[4]; /* sum to 1 over the counted cells; 0 for the others */
  int count;       /* 0: no cell of the island near the point (nothing to read or write) */
} mtx_texel_stencil;

MTX_FN void mtx_texel_stencil_of(MTX_TABLES s, const mtx_walker* w, mtx_u32 width,
                                 mtx_u32 height, int reading, mtx_texel_stencil* st) {
  if (s.lattice) { /* the intrinsic domain's lattice: three nodes of the point's triangle */
    mtx_lattice_corners(s.lattice, w->triangle, w->bary, st->cell, st->weight);
    st->cell[3] = st->cell[0];
    st->weight[3] = 0.0f;
    st->count = 3;
    return;
  }
  if (s.vertex_cells) { /* the intrinsic domain: its face's three vertices, linear hats */
    float c[3];
    mtx_u32 v[3];
    mtx_locate_intrinsic(s.locator_grid, s.locator_cells, s.locator_face, s.locator_map, s.locator_next,
                         s.locator_across, s.face_vertices, w->triangle, w->bary, c, v);
    for (int k = 0; k < 3; ++k) {
      st->cell[k] = v[k];
      st->weight[k] = c[k];
    }
    st->cell[3] = st->cell[0];
    st->weight[3] = 0.0f;
    st->count = 3;
    return;
  }
  MTX_GLOBAL const float* uv = s.corner_uvs + 6 * w->triangle;
  const float x = (w->bary[0] * uv[0] + w->bary[1] * uv[2] + w->bary[2] * uv[4]) * MTX_CAST(float, width) - 0.5f;
  const float y = (w->bary[0] * uv[1] + w->bary[1] * uv[3] + w->bary[2] * uv[5]) * MTX_CAST(float, height) - 0.5f;
  const int x0 = mtx_floor_int(x), y0 = mtx_floor_int(y);
  const float fx = x - MTX_CAST(float, x0), fy = y - MTX_CAST(float, y0);
  /* Fast path: the texel holding the point is interior (its 3x3 block lies in one
   * island), so all four texels are cells of the point's island. */
  const mtx_u32 home = x >= 0.0f && y >= 0.0f
                           ? MTX_CAST(mtx_u32, MTX_CAST(int, y + 0.5f)) * width + MTX_CAST(mtx_u32, MTX_CAST(int, x + 0.5f))
                           : 0u;
  if (x >= 0.0f && y >= 0.0f && x + 0.5f < MTX_CAST(float, width) && y + 0.5f < MTX_CAST(float, height) &&
      (s.interior_bits[home >> 5] >> (home & 31u)) & 1u) {
    const mtx_u32 i0 = MTX_CAST(mtx_u32, y0) * width + MTX_CAST(mtx_u32, x0);
    st->cell[0] = i0;
    st->cell[1] = i0 + 1;
    st->cell[2] = i0 + width;
    st->cell[3] = i0 + width + 1;
    st->weight[0] = (1.0f - fx) * (1.0f - fy);
    st->weight[1] = fx * (1.0f - fy);
    st->weight[2] = (1.0f - fx) * fy;
    st->weight[3] = fx * fy;
    st->count = 4;
    return;
  }
  const mtx_u32 island = s.island[w->triangle];
  float total = 0.0f;
  int counted[4] = {0, 0, 0, 0};
  st->count = 0;
  for (int k = 0; k < 4; ++k) {
    const int ix = x0 + (k & 1), iy = y0 + (k >> 1);
    const float wk = ((k & 1) ? fx : 1.0f - fx) * ((k >> 1) ? fy : 1.0f - fy);
    st->cell[k] = 0;
    st->weight[k] = 0.0f;
    if (ix < 0 || iy < 0 || ix >= MTX_CAST(int, width) || iy >= MTX_CAST(int, height)) continue;
    const mtx_u32 i = MTX_CAST(mtx_u32, iy) * width + MTX_CAST(mtx_u32, ix);
    /* A reading also takes gutter texels: each holds the texel across its seam (filled
     * after every step), so a sensor next to a seam reads across it. Deposits go to
     * cells only. */
    if (s.texel_island[i] != MTX_CAST(int, island) && !(reading && s.classes[i] == MTX_TEXEL_GUTTER)) continue;
    st->cell[k] = i;
    st->weight[k] = wk;
    counted[k] = 1;
    total += wk;
    st->count += 1;
  }
  if (st->count == 0) return;
  if (!(total > 0.0f)) {
    /* Only cells of weight 0 counted (the point lies on a texel centre line next to
     * foreign texels): they share equally. */
    for (int k = 0; k < 4; ++k) st->weight[k] = counted[k] ? 1.0f : 0.0f;
    total = MTX_CAST(float, st->count);
  }
  for (int k = 0; k < 4; ++k) st->weight[k] /= total;
}

/* The cell whose parameter-map values hold at the walker's point: its texel, or on the
 * intrinsic domain the vertex of its face it is nearest to (the largest weight). */
MTX_FN mtx_u32 mtx_point_cell(MTX_TABLES s, const mtx_walker* w, mtx_u32 width, mtx_u32 height) {
  if (s.vertex_cells) {
    float c[3];
    mtx_u32 v[3];
    mtx_locate_intrinsic(s.locator_grid, s.locator_cells, s.locator_face, s.locator_map, s.locator_next,
                         s.locator_across, s.face_vertices, w->triangle, w->bary, c, v);
    const int k = c[0] >= c[1] ? (c[0] >= c[2] ? 0 : 2) : (c[1] >= c[2] ? 1 : 2);
    return v[k];
  }
  return mtx_walker_texel(s.corner_uvs, w, width, height);
}

/* Adds `value` units to sums[index]: a plain add where the sums are the caller's own
 * (`exclusive`: no other thread writes them meanwhile, as a CPU thread's private plane),
 * else an atomic one (OpenCL always). Integer adds either way, so the sums do not depend
 * on the order. */
MTX_FN void mtx_add_units(MTX_GLOBAL mtx_i32* sums, mtx_u32 index, mtx_i32 value, int exclusive) {
#ifdef __OPENCL_C_VERSION__
  (void)exclusive;
  MTX_ADD_I32(sums, index, value);
#else
  if (exclusive)
    sums[index] += value;
  else
    MTX_ADD_I32(sums, index, value);
#endif
}

/* Adds `units` (a whole number of fixed-point units) to the stencil's cells in
 * proportion to their weights. The parts add up exactly to `units`: the last counted
 * cell takes the rounding remainder. `exclusive` as mtx_add_units. */
MTX_FN void mtx_texel_deposit(MTX_GLOBAL mtx_i32* sums, const mtx_texel_stencil* st, mtx_i32 units,
                              int exclusive) {
  mtx_i32 left = units;
  int last = -1;
  for (int k = 0; k < 4; ++k)
    if (st->weight[k] > 0.0f) last = k;
  for (int k = 0; k < 4; ++k) {
    if (!(st->weight[k] > 0.0f)) continue;
    mtx_i32 q = k == last ? left : MTX_CAST(mtx_i32, st->weight[k] * MTX_CAST(float, units) + 0.5f);
    q = q > left ? left : q;
    left -= q;
    if (q != 0) mtx_add_units(sums, st->cell[k], q, exclusive);
  }
}

/* The intrinsic lattice's node n: its deposit sums (planes of `count`) passed on to its
 * face's vertices (planes of `vertices`) by its weights, as a deposit at the node's point
 * (mtx_texel_deposit: parts adding up exactly), and cleared. Integer adds, so the sums do
 * not depend on the order the nodes are done in. */
MTX_FN void mtx_lattice_scatter_node(MTX_GLOBAL mtx_i32* node_sums, MTX_GLOBAL mtx_i32* sums,
                                     MTX_GLOBAL const mtx_u32* vertex, MTX_GLOBAL const float* weight,
                                     mtx_u32 n, mtx_u32 count, mtx_u32 vertices, mtx_u32 planes,
                                     int exclusive) {
  /* The node's vertices and weights are read only where it holds a deposit (many nodes
   * hold none: most of what the pass would read). */
  mtx_texel_stencil st;
  int read = 0;
  for (mtx_u32 p = 0; p < planes; ++p) {
    MTX_GLOBAL mtx_i32* in = node_sums + MTX_CAST(mtx_u64, p) * count + n;
    const mtx_i32 q = *in;
    if (q == 0) continue;
    *in = 0;
    if (!read) {
      for (int k = 0; k < 3; ++k) {
        st.cell[k] = vertex[3 * MTX_CAST(mtx_u64, n) + k];
        st.weight[k] = weight[3 * MTX_CAST(mtx_u64, n) + k];
      }
      st.cell[3] = st.cell[0];
      st.weight[3] = 0.0f;
      st.count = 3;
      read = 1;
    }
    mtx_texel_deposit(sums + MTX_CAST(mtx_u64, p) * vertices, &st, q, exclusive);
  }
}

/* The concentration that `units` of fixed-point deposit add to a cell of 3D area
 * `area`, `amount` being the amount of one unit. */
MTX_FN float mtx_deposit_concentration(mtx_i32 units, float amount, float area) {
  return MTX_CAST(float, units) * amount / area;
}

MTX_END_NAMESPACE

#endif
