/* intrinsic_lattice.h — where agents read and deposit on the intrinsic domain: a lattice
 * of sample nodes on each input triangle (domain/intrinsic_lattice.h builds it).
 *
 * The intrinsic triangulation's vertex values are interpolated once per step onto the
 * nodes (each node lies on one intrinsic face, with fixed weights), so an agent's point,
 * given as barycentrics b of its input triangle, reads three nodes of its own triangle
 * found by arithmetic alone, with no search for its intrinsic face. Deposits go the other
 * way: into the same three nodes, which pass them on to their faces' vertices with the
 * same weights after the agents' step (the adjoint, so the mass is kept exactly).
 *
 * Triangle t with G = lattice[2 t + 1] >= 1 has the (G + 1) (G + 2) / 2 nodes (i, j),
 * i + j <= G, at b1 = i / G, b2 = j / G, numbered row by row from lattice[2 t]: node
 * (i, j) is first + i (G + 1) - i (i - 1) / 2 + j. Each square (i, j) of the grid is cut
 * along its diagonal into a lower triangle (i, j), (i + 1, j), (i, j + 1) and an upper
 * one (i + 1, j + 1), (i, j + 1), (i + 1, j); a point reads the linear interpolation over
 * the one that holds it. G = 0 (a triangle the locator has no cells for): one node. */
#ifndef MOLDTEX_SHARED_INTRINSIC_LATTICE_H
#define MOLDTEX_SHARED_INTRINSIC_LATTICE_H

#ifndef __OPENCL_C_VERSION__
#include "shared/constants.h"
#include "shared/portable.h"
#endif

MTX_BEGIN_NAMESPACE

/* The node number of (i, j) on a triangle of G whose nodes start at `first`. */
MTX_FN mtx_u32 mtx_lattice_node(mtx_u32 first, int G, int i, int j) {
  return first + MTX_CAST(mtx_u32, i * (G + 1) - (i * (i - 1)) / 2 + j);
}

/* The three nodes around the point with weights b on triangle `triangle` (cells) and
 * their weights (weight, summing to 1). */
MTX_FN void mtx_lattice_corners(MTX_GLOBAL const mtx_u32* lattice, mtx_u32 triangle, const float* b,
                                mtx_u32* cells, float* weight) {
  const mtx_u32 first = lattice[2 * triangle], g = lattice[2 * triangle + 1];
  if (g == 0) {
    cells[0] = cells[1] = cells[2] = first;
    weight[0] = 1.0f;
    weight[1] = weight[2] = 0.0f;
    return;
  }
  const int G = MTX_CAST(int, g);
  const float x = b[1] * MTX_CAST(float, G), y = b[2] * MTX_CAST(float, G);
  int i = MTX_CAST(int, x), j = MTX_CAST(int, y);
  i = i < 0 ? 0 : (i > G - 1 ? G - 1 : i);
  j = j < 0 ? 0 : (j > G - 1 - i ? G - 1 - i : j);
  float fx = x - MTX_CAST(float, i), fy = y - MTX_CAST(float, j);
  fx = fx < 0.0f ? 0.0f : (fx > 1.0f ? 1.0f : fx);
  fy = fy < 0.0f ? 0.0f : (fy > 1.0f ? 1.0f : fy);
  const mtx_u32 here = mtx_lattice_node(first, G, i, j);
  const mtx_u32 above = here + MTX_CAST(mtx_u32, G + 1 - i); /* node (i + 1, j) */
  if (fx + fy > 1.0f && i + j + 2 <= G) { /* the upper triangle */
    cells[0] = above + 1u;
    cells[1] = here + 1u;
    cells[2] = above;
    weight[0] = fx + fy - 1.0f;
    weight[1] = 1.0f - fx;
    weight[2] = 1.0f - fy;
    return;
  }
  if (fx + fy > 1.0f) { /* beyond the triangle's long edge (round-off): onto it */
    const float s = fx + fy;
    fx /= s;
    fy /= s;
  }
  cells[0] = here;
  cells[1] = above;
  cells[2] = here + 1u;
  weight[0] = mtx_max(1.0f - fx - fy, 0.0f);
  weight[1] = fx;
  weight[2] = fy;
}

/* Node n's value in each of `planes` planes: the vertex values (planes of `vertices`)
 * interpolated with the node's weights (vertex, weight: 3 per node) into planes of
 * `count` nodes. */
MTX_FN void mtx_lattice_gather_node(MTX_GLOBAL const float* u, MTX_GLOBAL const mtx_u32* vertex,
                                    MTX_GLOBAL const float* weight, MTX_GLOBAL float* nodes, mtx_u32 n,
                                    mtx_u32 count, mtx_u32 vertices, mtx_u32 planes) {
  const mtx_u32 v0 = vertex[3 * MTX_CAST(mtx_u64, n)], v1 = vertex[3 * MTX_CAST(mtx_u64, n) + 1],
                v2 = vertex[3 * MTX_CAST(mtx_u64, n) + 2];
  const float w0 = weight[3 * MTX_CAST(mtx_u64, n)], w1 = weight[3 * MTX_CAST(mtx_u64, n) + 1],
              w2 = weight[3 * MTX_CAST(mtx_u64, n) + 2];
  for (mtx_u32 p = 0; p < planes; ++p) {
    MTX_GLOBAL const float* plane = u + MTX_CAST(mtx_u64, p) * vertices;
    const float a = w0 * plane[v0], b = w1 * plane[v1], c = w2 * plane[v2];
    nodes[MTX_CAST(mtx_u64, p) * count + n] = (a + b) + c;
  }
}

MTX_END_NAMESPACE

#endif
