/* walk.h — the tangent step: walk a straightest path over the surface (MoMaS
 * supplementary Alg. 1, done by unfolding instead of projecting).
 *
 * Every triangle has an isometric local 2D frame (corner 0 at the origin, corner 1 on
 * +x, corner 2 above), so lengths and angles in a frame are true 3D lengths and angles.
 * A walker keeps its position as barycentric weights and its heading as a unit vector
 * in the frame of its triangle. At an edge it unfolds the heading about that edge into
 * the neighbour's frame (keeping the angle to the edge, hence a geodesic). At an open
 * boundary it bounces (mirrors the heading), scatters (a new heading by the cosine law)
 * or stops, as the caller asks. Any number of edges may be crossed in one walk. */
#ifndef MOLDTEX_SHARED_WALK_H
#define MOLDTEX_SHARED_WALK_H

#ifndef __OPENCL_C_VERSION__
#include "shared/constants.h"
#include "shared/portable.h"
#include "shared/rng.h"
#endif

MTX_BEGIN_NAMESPACE

/* What a walk does at an open boundary edge. */
#define MTX_BOUNDARY_BOUNCE 0  /* mirrors the heading about the edge (a specular bounce) */
#define MTX_BOUNDARY_STOP 1    /* ends there and returns -1 (sensor traces; absorption) */
/* Leaves the edge in a random direction drawn by the cosine (Lambert) law about the
 * inward normal. Like a bounce, it keeps a free random walk uniform over the surface;
 * unlike a bounce, it does not guide a walker along the wall at a grazing angle, so a
 * trail along an open boundary holds its agents no better than a trail elsewhere. */
#define MTX_BOUNDARY_SCATTER 2

typedef struct mtx_vec2 {
  float x, y;
} mtx_vec2;

/* Local frame of a triangle: q0 = (0,0), q1 = (a,0), q2 = (bx,by) with by > 0; cached
 * 1/a, 1/by, the unit tangent of each edge i, running counter-clockwise from corner
 * i+1 to corner i+2, and the altitude from corner i to edge i (2 area / edge i's length):
 * a point with weights b lies b[i] altitude[i] from edge i. */
typedef struct mtx_frame {
  float a, bx, by;
  float inv_a, inv_by;
  mtx_vec2 edge[3];
  float altitude[3];
} mtx_frame;

/* The neighbour across edge i of triangle t unfolded into t's frame (built by
 * surface/unfolded_neighbours.cpp): MTX_UNFOLDED_FLOATS floats at
 * unfolded[(3t + i) * MTX_UNFOLDED_FLOATS], two affine functions of a point's weights
 * (b1, b2) in t, extended past t's edges, each as (c0, c1, c2) for c0 + c1 b1 + c2 b2:
 * the point's weights in the neighbour at its own corners 1 and 2 (its weight at corner
 * 0 is 1 minus these). Zeros where adjacency[3t+i] is MTX_NO_NEIGHBOUR. */
#define MTX_UNFOLDED_FLOATS 6
/* The most edges a trace crosses through the unfolded neighbours (mtx_trace_unfolded)
 * before it is left to the walk. */
#define MTX_UNFOLDED_HOPS 16

/* Neighbour across edge i of triangle t is adjacency[3t+i], packed as
 * (triangle << 3) | (edge_in_neighbour << 1) | same_direction, where same_direction = 1
 * when the neighbour is wound the other way round; MTX_NO_NEIGHBOUR at walls. */

typedef struct mtx_walker {
  mtx_u32 triangle;
  float bary[3];
  mtx_vec2 heading; /* unit vector in the frame of `triangle` */
} mtx_walker;

MTX_FN mtx_vec2 mtx_unit(mtx_vec2 v) {
  float n = sqrt(v.x * v.x + v.y * v.y);
  mtx_vec2 r;
  r.x = n > 0.0f ? v.x / n : 1.0f;
  r.y = n > 0.0f ? v.y / n : 0.0f;
  return r;
}

/* A vector within a few float roundings of unit length (a unit vector rotated) brought
 * back to unit length: one Newton step for 1/sqrt(|v|^2) near 1, which squares the
 * relative error (about 1e-7 becomes 1e-14) instead of dividing by a square root; lengths
 * never drift over steps. */
MTX_FN mtx_vec2 mtx_renormalised(mtx_vec2 v) {
  const float f = 1.5f - 0.5f * (v.x * v.x + v.y * v.y);
  mtx_vec2 r;
  r.x = v.x * f;
  r.y = v.y * f;
  return r;
}

MTX_FN mtx_vec2 mtx_rotate(mtx_vec2 v, float c, float s) {
  mtx_vec2 r;
  r.x = c * v.x - s * v.y;
  r.y = s * v.x + c * v.y;
  return r;
}

/* Keeps barycentrics on the simplex despite rounding: none negative, summing to 1.
 * After a walk the sum is within a few rounding errors of 1, and for any s within 1e-4
 * of 1, scaling by 2 - s is 1/s up to a relative (s - 1)^2 <= 1e-8, under a float's
 * rounding: the division, on every walk's path, is left for sums further off. Three
 * weights held apart (in registers, as mtx_walk_leg keeps them) ... */
MTX_FN void mtx_clamp_bary3(float* b0, float* b1, float* b2) {
  float x = *b0 < 0.0f ? 0.0f : *b0, y = *b1 < 0.0f ? 0.0f : *b1, z = *b2 < 0.0f ? 0.0f : *b2;
  const float s = x + y + z;
  if (fabs(s - 1.0f) <= 1e-4f) {
    const float inv = 2.0f - s; /* 1 / s to first order */
    x *= inv;
    y *= inv;
    z *= inv;
  } else if (s > 0.0f) {
    const float inv = 1.0f / s;
    x *= inv;
    y *= inv;
    z *= inv;
  } else {
    x = y = z = 1.0f / 3.0f;
  }
  *b0 = x;
  *b1 = y;
  *b2 = z;
}

/* ... or an array of three. */
MTX_FN void mtx_clamp_bary(float* b) { mtx_clamp_bary3(&b[0], &b[1], &b[2]); }

/* One leg of the general walk (mtx_walk_across): from the walker's point to the first
 * edge it meets within *remaining (or to the end of the walk), then across it (or a
 * bounce). `count`: legs done before this one. Returns 1 when the walk goes on, 0 when
 * it has ended (the weights clamped), -1 when it stopped at an open boundary
 * (MTX_BOUNDARY_STOP). */
MTX_FN int mtx_walk_leg(MTX_GLOBAL const mtx_frame* frames, MTX_GLOBAL const mtx_u32* adjacency, mtx_walker* w,
                        float* remaining, int count, mtx_walker* events, int capacity, int boundary,
                        mtx_u64* scatter_rng) {
  const mtx_frame f = frames[w->triangle];
  /* The weights stay in registers, selected by index with conditionals: writing one
   * weight by a computed index and reading them back together stalled on the store. */
  float b0 = w->bary[0], b1 = w->bary[1], b2 = w->bary[2];
  /* Heading in barycentric rates: Q (db1, db2) = heading, Q = [[a, bx], [0, by]]. */
  const float db2 = w->heading.y * f.inv_by;
  const float db1 = (w->heading.x - f.bx * db2) * f.inv_a;
  const float db0 = -(db1 + db2);
  float travel = *remaining;
  int exit = -1;
  if (db0 < 0.0f) {
    const float tau = b0 > 0.0f ? -b0 / db0 : 0.0f;
    if (tau < travel) {
      travel = tau;
      exit = 0;
    }
  }
  if (db1 < 0.0f) {
    const float tau = b1 > 0.0f ? -b1 / db1 : 0.0f;
    if (tau < travel) {
      travel = tau;
      exit = 1;
    }
  }
  if (db2 < 0.0f) {
    const float tau = b2 > 0.0f ? -b2 / db2 : 0.0f;
    if (tau < travel) {
      travel = tau;
      exit = 2;
    }
  }
  b0 += travel * db0;
  b1 += travel * db1;
  b2 += travel * db2;
  if (exit < 0 || count >= MTX_MAX_CROSSINGS_PER_WALK) {
    mtx_clamp_bary3(&b0, &b1, &b2);
    w->bary[0] = b0;
    w->bary[1] = b1;
    w->bary[2] = b2;
    return 0;
  }
  b0 = exit == 0 ? 0.0f : b0;
  b1 = exit == 1 ? 0.0f : b1;
  b2 = exit == 2 ? 0.0f : b2;
  mtx_clamp_bary3(&b0, &b1, &b2);
  *remaining -= travel;

  /* j, k: the exit edge's corners (exit + 1, exit + 2). */
  const float bj = exit == 0 ? b1 : (exit == 1 ? b2 : b0);
  const float bk = exit == 0 ? b2 : (exit == 1 ? b0 : b1);
  const mtx_vec2 e = f.edge[exit];
  /* Corners are counter-clockwise in every frame, so this normal points inward. */
  const float along = w->heading.x * e.x + w->heading.y * e.y;
  const float across = mtx_max(fabs(w->heading.x * -e.y + w->heading.y * e.x), MTX_MIN_CROSSING_SINE);
  const mtx_u32 code = adjacency[3 * w->triangle + MTX_CAST(mtx_u32, exit)];
  if (code == MTX_NO_NEIGHBOUR && boundary == MTX_BOUNDARY_STOP) {
    w->bary[0] = b0;
    w->bary[1] = b1;
    w->bary[2] = b2;
    return -1;
  }
  if (code == MTX_NO_NEIGHBOUR) {
    /* Bounce: mirror the heading about the boundary edge (along the edge unchanged,
     * across it now inward). Scatter: sin of the angle to the inward normal uniform in
     * [-1, 1), which is the cosine law. */
    float out_along = along, out_across = across;
    if (boundary == MTX_BOUNDARY_SCATTER) {
      out_along = 2.0f * mtx_rng_float(scatter_rng) - 1.0f;
      out_across = mtx_max(sqrt(1.0f - out_along * out_along), MTX_MIN_CROSSING_SINE);
    }
    mtx_vec2 h;
    h.x = out_along * e.x - out_across * e.y;
    h.y = out_along * e.y + out_across * e.x;
    w->heading = mtx_unit(h);
    w->bary[0] = b0;
    w->bary[1] = b1;
    w->bary[2] = b2;
  } else {
    const mtx_u32 next = code >> 3;
    const int edge = MTX_CAST(int, (code >> 1) & 3u);
    const int same_direction = MTX_CAST(int, code & 1u);
    const int jn = (edge + (same_direction ? 1 : 2)) % 3; /* corner of `next` equal to j */
    /* In `next`: weight 0 at corner `edge`, bj at jn, bk at the third corner. */
    w->bary[0] = edge == 0 ? 0.0f : (jn == 0 ? bj : bk);
    w->bary[1] = edge == 1 ? 0.0f : (jn == 1 ? bj : bk);
    w->bary[2] = edge == 2 ? 0.0f : (jn == 2 ? bj : bk);
    /* The shared edge runs j -> k: in `next` that is its counter-clockwise tangent, or
     * the reverse when `next` is wound the other way round. */
    const mtx_vec2 ccw = frames[next].edge[edge];
    const float sign = same_direction ? 1.0f : -1.0f;
    /* Unit up to rounding (along^2 + across^2 = 1, ccw a unit vector): not renormalised
     * here, where a square root and a division would lie on the path to the next leg;
     * the walk renormalises once where it ends (mtx_walk_across). */
    w->heading.x = along * sign * ccw.x - across * ccw.y;
    w->heading.y = along * sign * ccw.y + across * ccw.x;
    w->triangle = next;
  }
  if (events && count < capacity) events[count] = *w;
  return 1;
}

/* The general walk of mtx_walk_until, edge by edge (see there). */
MTX_FN int mtx_walk_across(MTX_GLOBAL const mtx_frame* frames, MTX_GLOBAL const mtx_u32* adjacency,
                          mtx_walker* w, float length, mtx_walker* events, int capacity,
                          int boundary, mtx_u64* scatter_rng) {
  float remaining = length;
  for (int count = 0;; ++count) {
    const int on = mtx_walk_leg(frames, adjacency, w, &remaining, count, events, capacity, boundary, scatter_rng);
    if (on <= 0) {
      if (count > 0) w->heading = mtx_unit(w->heading); /* the crossings' rounding */
      return on < 0 ? -1 : count;
    }
  }
}

/* Is weight b, changing at rate db per unit length, clear of its edge over `length`?
 * True where it does not fall (db >= 0) or where b + length db keeps a margin of 1e-6 b,
 * which rounding cannot cross: then the true tau = -b / db exceeds length by a relative
 * 9e-7 and its float quotient (relative error 6e-8) cannot fall below it, so
 * mtx_walk_across would not stop there either. No branches; a weight under 1e-30 is
 * never called clear. */
MTX_FN int mtx_clear_of_edge(float b, float db, float length) {
  return (db >= 0.0f) | ((b > 1e-30f) & (b + length * db >= 1e-6f * b));
}

/* Does weight b fall to 0 within `length`? Decided as mtx_walk_across decides it. */
MTX_FN int mtx_meets_edge(float b, float db, float length) {
  return db < 0.0f && (b > 0.0f ? -b / db : 0.0f) < length;
}

/* A walk known to stay inside the walker's triangle (mtx_walk_stays_inside, or
 * mtx_walk_inside's tests): moves it, without tests. */
MTX_FN void mtx_walk_inside_known(MTX_GLOBAL const mtx_frame* frames, mtx_walker* w, float length) {
  MTX_GLOBAL const mtx_frame* f = frames + w->triangle;
  const float db2 = w->heading.y * f->inv_by;
  const float db1 = (w->heading.x - f->bx * db2) * f->inv_a;
  const float db0 = -(db1 + db2);
  w->bary[0] += length * db0;
  w->bary[1] += length * db1;
  w->bary[2] += length * db2;
  mtx_clamp_bary(w->bary);
}

/* The common case: a walk that ends inside the walker's own triangle, done without the
 * general walk's loop. It decides and moves exactly as mtx_walk_across does when that
 * meets no edge (the same operations in the same order, so the same bits): moves the
 * walker and returns 1 then; otherwise leaves it as it was and returns 0. */
MTX_FN int mtx_walk_inside(MTX_GLOBAL const mtx_frame* frames, mtx_walker* w, float length) {
  MTX_GLOBAL const mtx_frame* f = frames + w->triangle;
  const float db2 = w->heading.y * f->inv_by;
  const float db1 = (w->heading.x - f->bx * db2) * f->inv_a;
  const float db0 = -(db1 + db2);
  /* Usually every weight is clear of its edge: one test without branches on the
   * (random) signs of the rates; the exact decision only next to an edge. */
  const float b0 = w->bary[0], b1 = w->bary[1], b2 = w->bary[2];
  const int clear = mtx_clear_of_edge(b0, db0, length) & mtx_clear_of_edge(b1, db1, length) &
                    mtx_clear_of_edge(b2, db2, length);
  if (!clear && (mtx_meets_edge(b0, db0, length) || mtx_meets_edge(b1, db1, length) ||
                 mtx_meets_edge(b2, db2, length)))
    return 0;
  mtx_walk_inside_known(frames, w, length);
  return 1;
}

/* How far walker w is from the nearest edge of its triangle (3D units): any walk
 * shorter than that, in any direction, stays inside the triangle. */
MTX_FN float mtx_edge_clearance(MTX_GLOBAL const mtx_frame* frames, const mtx_walker* w) {
  MTX_GLOBAL const mtx_frame* f = frames + w->triangle;
  return mtx_min(mtx_min(w->bary[0] * f->altitude[0], w->bary[1] * f->altitude[1]), w->bary[2] * f->altitude[2]);
}

/* Is a walk of `length` from a point `clearance` from every edge (mtx_edge_clearance)
 * sure to stay inside? With a relative margin of 1e-4, far over the rounding of the
 * clearance and of the altitudes (a few float ulps): the weight b[i] then exceeds
 * length |rate of b[i]| (at most length / altitude[i]) by that margin, so mtx_walk_inside
 * finds every weight clear of its edge, or decides that it meets none. */
MTX_FN int mtx_walk_stays_inside(float clearance, float length) { return clearance > length * 1.0001f; }

/* Walks `length` 3D units. If `events` is not null, the walker's state after each edge
 * crossing or bounce is stored there, up to `capacity` of them. Returns the number of
 * crossings and bounces. At an open boundary edge it does what `boundary` says
 * (MTX_BOUNDARY_*); with MTX_BOUNDARY_STOP the walk ends where it first meets one and
 * returns -1; MTX_BOUNDARY_SCATTER draws from `scatter_rng` (unused otherwise, may be
 * null then). Most walks of an agent's step stay inside one triangle: they take the
 * short way. */
MTX_FN int mtx_walk_until(MTX_GLOBAL const mtx_frame* frames, MTX_GLOBAL const mtx_u32* adjacency,
                          mtx_walker* w, float length, mtx_walker* events, int capacity,
                          int boundary, mtx_u64* scatter_rng) {
  if (mtx_walk_inside(frames, w, length)) return 0;
  return mtx_walk_across(frames, adjacency, w, length, events, capacity, boundary, scatter_rng);
}

/* The start and end of a straight walk of `length` from walker w as weights in the
 * walker's triangle (both linear in `length`; the end may lie outside): s[3], e[3]. */
MTX_FN void mtx_trace_ends(MTX_GLOBAL const mtx_frame* frames, const mtx_walker* w, float length,
                           float* s, float* e) {
  MTX_GLOBAL const mtx_frame* f = frames + w->triangle;
  const float d2 = w->heading.y * f->inv_by;
  const float d1 = (w->heading.x - f->bx * d2) * f->inv_a;
  s[0] = w->bary[0];
  s[1] = w->bary[1];
  s[2] = w->bary[2];
  e[0] = s[0] - length * (d1 + d2);
  e[1] = s[1] + length * d1;
  e[2] = s[2] + length * d2;
}

/* The crossings of mtx_trace_unfolded from triangle *t with start and end weights s, e
 * there (mtx_trace_ends): returns 1 with *t and e where the end lies (weights in *t), or
 * 0 (an open boundary, more than MTX_UNFOLDED_HOPS crossings, or a trace within rounding
 * of a corner), *t, s and e then meaningless. surface/trace_lanes.cpp runs the same
 * operations in SIMD lanes and must stay bit for bit the same. */
MTX_FN int mtx_trace_hops(MTX_GLOBAL const mtx_u32* adjacency, MTX_GLOBAL const float* unfolded,
                          mtx_u32* t_io, float* s, float* e) {
  float s0 = s[0], s1 = s[1], s2 = s[2];
  float e0 = e[0], e1 = e[1], e2 = e[2];
  mtx_u32 t = *t_io;
  for (int hop = 0;; ++hop) {
    const int n0 = e0 < 0.0f, n1 = e1 < 0.0f, n2 = e2 < 0.0f;
    if (!(n0 | n1 | n2)) break;
    if (hop == MTX_UNFOLDED_HOPS) return 0;
    mtx_u32 edge = n0 ? 0u : (n1 ? 1u : 2u);
    if (n0 + n1 + n2 > 1) {
      /* Two ends beyond edges i < j: the trace meets first the one whose weight falls
       * to 0 sooner, tau = s / (s - e), compared without dividing. */
      const mtx_u32 j = n2 ? 2u : 1u;
      const float si = edge == 0 ? s0 : s1, ei = edge == 0 ? e0 : e1;
      const float sj = j == 2 ? s2 : s1, ej = j == 2 ? e2 : e1;
      if (si < 0.0f || sj < 0.0f) return 0;
      if (sj * (si - ei) < si * (sj - ej)) edge = j;
    }
    /* The start lies on the inner side of the edge the trace leaves by (up to rounding
     * next to a corner, which the walk resolves). */
    if ((edge == 0 ? s0 : (edge == 1 ? s1 : s2)) < 0.0f) return 0;
    const mtx_u32 code = adjacency[3 * t + edge];
    if (code == MTX_NO_NEIGHBOUR) return 0;
    /* Both points carried into the neighbour, in its own weights. */
    MTX_GLOBAL const float* g = unfolded + (3 * t + edge) * MTX_UNFOLDED_FLOATS;
    const float s1n = g[0] + g[1] * s1 + g[2] * s2, s2n = g[3] + g[4] * s1 + g[5] * s2;
    const float e1n = g[0] + g[1] * e1 + g[2] * e2, e2n = g[3] + g[4] * e1 + g[5] * e2;
    s1 = s1n;
    s2 = s2n;
    s0 = 1.0f - s1 - s2;
    e1 = e1n;
    e2 = e2n;
    e0 = 1.0f - e1 - e2;
    t = code >> 3;
  }
  *t_io = t;
  e[0] = e0;
  e[1] = e1;
  e[2] = e2;
  return 1;
}

/* A straight walk of `length` from walker w, located without walking where it crosses
 * at most MTX_UNFOLDED_HOPS edges between triangles (none open): the weights of its start
 * and end points in the walker's triangle are linear in `length`; while the end lies
 * outside the current triangle, the trace leaves it by the edge whose weight reaches 0
 * first between start and end, and both points are carried into the neighbour there
 * through `unfolded` (MTX_UNFOLDED_FLOATS: affine maps, no division). The same end as
 * the walk up to rounding, with the heading left as it was (a sensor trace is read only
 * where it ends). Returns 1 with w moved there, or 0 with w unchanged (an open
 * boundary, more crossings, or a trace within rounding of a corner): the caller walks. */
MTX_FN int mtx_trace_unfolded(MTX_GLOBAL const mtx_frame* frames, MTX_GLOBAL const mtx_u32* adjacency,
                              MTX_GLOBAL const float* unfolded, mtx_walker* w, float length) {
  float s[3], e[3];
  mtx_trace_ends(frames, w, length, s, e);
  mtx_u32 t = w->triangle;
  if (!mtx_trace_hops(adjacency, unfolded, &t, s, e)) return 0;
  w->triangle = t;
  w->bary[0] = e[0];
  w->bary[1] = e[1];
  w->bary[2] = e[2];
  return 1;
}

/* A sensor trace of `length` from walker w, read only where it ends: located through
 * the unfolded neighbours where it can be (mtx_trace_unfolded, when `unfolded` is not
 * NULL; returns 1, the end's weights as it leaves them), walked otherwise, doing what
 * `boundary` says at open boundaries (MTX_BOUNDARY_STOP or _BOUNCE; returns 0). */
MTX_FN int mtx_walk_trace(MTX_GLOBAL const mtx_frame* frames, MTX_GLOBAL const mtx_u32* adjacency,
                          MTX_GLOBAL const float* unfolded, mtx_walker* w, float length, int boundary) {
  if (unfolded && mtx_trace_unfolded(frames, adjacency, unfolded, w, length)) return 1;
  mtx_walk_until(frames, adjacency, w, length, 0, 0, boundary, 0);
  return 0;
}

/* A walk that bounces at open boundaries. */
MTX_FN int mtx_walk(MTX_GLOBAL const mtx_frame* frames, MTX_GLOBAL const mtx_u32* adjacency,
                    mtx_walker* w, float length, mtx_walker* events, int capacity) {
  return mtx_walk_until(frames, adjacency, w, length, events, capacity, MTX_BOUNDARY_BOUNCE, 0);
}

MTX_END_NAMESPACE

#endif
