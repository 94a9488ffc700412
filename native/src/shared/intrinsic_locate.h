/* intrinsic_locate.h — where a point of the input mesh lies on the intrinsic
 * triangulation (domain/intrinsic_locator.h builds the tables), for agents that walk the
 * input mesh and read and deposit at the intrinsic vertices.
 *
 * Each input triangle is flat, and so is every intrinsic face; where an intrinsic face
 * overlaps an input triangle, its barycentrics are an affine function of the triangle's:
 * c = M b (3 x 3, b summing to 1). Each input triangle is cut into a grid of G x G cells
 * over (b1, b2), of which the G (G + 1) / 2 cells with i + j < G are kept (cell (i, j)
 * covers b1 in [i/G, (i+1)/G), b2 in [j/G, (j+1)/G), clipped to the triangle); each cell
 * lists the intrinsic faces that overlap it, each with its M. A lookup evaluates the
 * candidates of the point's cell and takes the first whose weights are all >= 0, or
 * else the one whose smallest weight is largest (a sliver the cell's samples missed:
 * clamped, an error of at most the sliver's width). */
#ifndef MOLDTEX_SHARED_INTRINSIC_LOCATE_H
#define MOLDTEX_SHARED_INTRINSIC_LOCATE_H

#ifndef __OPENCL_C_VERSION__
#include "shared/constants.h"
#include "shared/portable.h"
#endif

MTX_BEGIN_NAMESPACE

/* Weights this far below 0 still count as inside (float round-off of c = M b). */
#define MTX_LOCATE_SLACK 1e-5f

/* mtx_locator_cell's answer for an input triangle without cells. */
#define MTX_NO_CELL 0xffffffffu

/* A candidate's record: its face and the face's three vertices (face), and the first two
 * rows of its map (map; the third weight is 1 minus those two). */
#define MTX_LOCATE_FACE_STRIDE 4
#define MTX_LOCATE_MAP_STRIDE 6

/* At most this many steps of the walk that finishes a lookup. */
#define MTX_LOCATE_MAX_STEPS 32

/* grid: 2 per input triangle (first cell, G; G = 0: no cells); face: per candidate its
 * intrinsic face and that face's vertices; map: the first two rows of its M (row-major;
 * the third row is 1 minus them, as the weights sum to 1). Candidate `cell` is the cell's
 * first (its largest overlap), read straight from the cell's number; cells: per cell
 * where its other candidates start (they follow all the first ones), one more entry at
 * the end. When no candidate holds the point (one within
 * round-off of an edge), the lookup walks from the
 * best one across the edge opposite its most negative weight, face to face: next holds
 * per face and edge k (opposite corner k) the neighbour's face << 2 | m (its halfedge m
 * runs the edge, so its corner m + 2 lies across; MTX_NO_NEIGHBOUR at the boundary), and
 * across the weights (in this face) of that corner, 3 per edge; after a walk the face's
 * vertices come from face_vertices (3 per face). mtx_locate_intrinsic writes the weights
 * into c and the face's vertices into v and returns the face; it is the two steps below
 * in a row. */

/* The first step of a lookup (mtx_locate_intrinsic): the locator cell that holds the
 * point with weights b on input triangle `triangle`, or MTX_NO_CELL when that
 * triangle has no cells. Apart, so a backend can fetch the cells of a batch together. */
MTX_FN mtx_u32 mtx_locator_cell(MTX_GLOBAL const mtx_u32* grid, mtx_u32 triangle, const float* b) {
  const mtx_u32 first = grid[2 * triangle], g = grid[2 * triangle + 1];
  if (g == 0) return MTX_NO_CELL;
  const int G = MTX_CAST(int, g);
  int i = MTX_CAST(int, b[1] * MTX_CAST(float, G)), j = MTX_CAST(int, b[2] * MTX_CAST(float, G));
  i = i < 0 ? 0 : (i > G - 1 ? G - 1 : i);
  j = j < 0 ? 0 : (j > G - 1 - i ? G - 1 - i : j);
  return first + MTX_CAST(mtx_u32, i * G - (i * (i - 1)) / 2 + j);
}

/* The rest of the lookup, in the point's cell (mtx_locator_cell). */
MTX_FN mtx_u32 mtx_locate_in_cell(MTX_GLOBAL const mtx_u32* cells, MTX_GLOBAL const mtx_u32* face,
                                  MTX_GLOBAL const float* map, MTX_GLOBAL const mtx_u32* next,
                                  MTX_GLOBAL const float* across, MTX_GLOBAL const mtx_u32* face_vertices,
                                  mtx_u32 cell, const float* b, float* c, mtx_u32* v) {
  if (cell == MTX_NO_CELL) {
    c[0] = c[1] = c[2] = 1.0f / 3.0f;
    v[0] = face_vertices[0];
    v[1] = face_vertices[1];
    v[2] = face_vertices[2];
    return 0;
  }
  /* The first candidate is record `cell` (no read of cells[] before it); the others, if
   * it does not hold the point, cells[cell] to cells[cell + 1]. */
  mtx_u32 chosen = cell;
  float best_score = -1e30f, best_c[3] = {1.0f / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f};
  const mtx_u32 rest = cells[cell], count = 1u + (cells[cell + 1] - rest);
  for (mtx_u32 n = 0; n < count; ++n) {
    const mtx_u32 k = n == 0 ? cell : rest + n - 1u;
    MTX_GLOBAL const float* m = map + MTX_LOCATE_MAP_STRIDE * k;
    float w[3];
    w[0] = m[0] * b[0] + m[1] * b[1] + m[2] * b[2];
    w[1] = m[3] * b[0] + m[4] * b[1] + m[5] * b[2];
    w[2] = 1.0f - w[0] - w[1];
    const float score = mtx_min(w[0], mtx_min(w[1], w[2]));
    if (score > best_score) {
      best_score = score;
      chosen = k;
      best_c[0] = w[0];
      best_c[1] = w[1];
      best_c[2] = w[2];
      if (score >= -MTX_LOCATE_SLACK) break;
    }
  }
  MTX_GLOBAL const mtx_u32* record = face + MTX_LOCATE_FACE_STRIDE * chosen;
  mtx_u32 best = record[0];
  v[0] = record[1];
  v[1] = record[2];
  v[2] = record[3];
  /* The walk: with weights w in face f and w[k] < 0, the corner d across edge k has
   * weights e in f, so the point is w[a] - w[k] e[a] / e[k] of a, the same for b, and
   * w[k] / e[k] of d (a, b the edge's corners k + 1, k + 2). */
  for (int step = 0; step < MTX_LOCATE_MAX_STEPS && best_score < -MTX_LOCATE_SLACK; ++step) {
    const int k = best_c[0] <= best_c[1] ? (best_c[0] <= best_c[2] ? 0 : 2) : (best_c[1] <= best_c[2] ? 1 : 2);
    const mtx_u32 code = next[3 * best + MTX_CAST(mtx_u32, k)];
    if (code == MTX_NO_NEIGHBOUR) break;
    MTX_GLOBAL const float* e = across + 9 * best + 3 * k;
    if (!(e[k] < 0.0f)) break;
    const int a = (k + 1) % 3, bb = (k + 2) % 3;
    const float t = best_c[k] / e[k];
    const float wa = best_c[a] - t * e[a], wb = best_c[bb] - t * e[bb];
    const int m = MTX_CAST(int, code & 3u);
    /* In the neighbour the edge runs b -> a: its corner m is b, m + 1 is a. */
    best = code >> 2;
    best_c[m] = wb;
    best_c[(m + 1) % 3] = wa;
    best_c[(m + 2) % 3] = t;
    best_score = mtx_min(best_c[0], mtx_min(best_c[1], best_c[2]));
    v[0] = face_vertices[3 * best];
    v[1] = face_vertices[3 * best + 1];
    v[2] = face_vertices[3 * best + 2];
  }
  float sum = 0.0f;
  for (int r = 0; r < 3; ++r) {
    c[r] = best_c[r] > 0.0f ? best_c[r] : 0.0f;
    sum += c[r];
  }
  if (sum > 0.0f) {
    for (int r = 0; r < 3; ++r) c[r] /= sum;
  } else {
    c[0] = c[1] = c[2] = 1.0f / 3.0f;
  }
  return best;
}

MTX_FN mtx_u32 mtx_locate_intrinsic(MTX_GLOBAL const mtx_u32* grid, MTX_GLOBAL const mtx_u32* cells,
                                    MTX_GLOBAL const mtx_u32* face, MTX_GLOBAL const float* map,
                                    MTX_GLOBAL const mtx_u32* next, MTX_GLOBAL const float* across,
                                    MTX_GLOBAL const mtx_u32* face_vertices, mtx_u32 triangle, const float* b,
                                    float* c, mtx_u32* v) {
  return mtx_locate_in_cell(cells, face, map, next, across, face_vertices, mtx_locator_cell(grid, triangle, b), b,
                            c, v);
}

MTX_END_NAMESPACE

#endif
