/* angle.h — the cosine and sine of a turn, from float multiplications and additions
 * only, so that the SIMD lanes (agents/momas_lanes16.cpp, momas_lanes8.cpp) compute the
 * same bits as this scalar code, sixteen turns at a time, instead of calling the math
 * library once per turning agent. Accurate to a few units in the last place of a float:
 * the angle is reduced to r in [-pi/4, pi/4] around the nearest multiple k of pi/2
 * (pi/2 split into three parts, the first two of whose products with k are exact for
 * |k| < 2^11, angles up to 3200 rad), then
 * cos r and sin r are their Taylor series to the terms in r^10 and r^9 (truncation
 * below 2e-9 there), and k's quadrant swaps and signs them. */
#ifndef MOLDTEX_SHARED_ANGLE_H
#define MOLDTEX_SHARED_ANGLE_H

#ifndef __OPENCL_C_VERSION__
#include "shared/portable.h"
#endif

MTX_BEGIN_NAMESPACE

/* pi/2 = MTX_HALF_PI_A + MTX_HALF_PI_B + MTX_HALF_PI_C: the first two with 8 and 12
 * significant bits, the third the float nearest the rest. */
#define MTX_HALF_PI_A 1.5703125f
#define MTX_HALF_PI_B 4.8387050628662109375e-4f
#define MTX_HALF_PI_C -4.37113883e-8f
#define MTX_TWO_OVER_PI 0.636619747f
/* Turns are clamped to +-MTX_MAX_TURN_ANGLE radians (about 100 000 turns), where k
 * still converts to an int; no parameter in range asks for more. */
#define MTX_MAX_TURN_ANGLE 6.0e5f

/* The rest of a after kf quarter turns, and the series of sin and cos at that rest r
 * (r2 = r r): written once for this scalar code and for the SIMD lanes, whose vectors take
 * the same operators (GCC's and Clang's vector extensions, a float constant standing for
 * every lane), so each backend multiplies and adds in this order. */
#define MTX_QUARTER_TURN_REST(a, kf) \
  ((((a) - (kf) * MTX_HALF_PI_A) - (kf) * MTX_HALF_PI_B) - (kf) * MTX_HALF_PI_C)
#define MTX_SIN_SERIES(r, r2) \
  ((r) + (r) * (r2) * (-1.66666672e-1f + (r2) * (8.33333377e-3f + (r2) * (-1.98412701e-4f + (r2) * 2.75573188e-6f))))
#define MTX_COS_SERIES(r2)                                                                                     \
  (1.0f + (r2) * (-0.5f + (r2) * (4.16666679e-2f + (r2) * (-1.38888892e-3f + (r2) * (2.48015876e-5f + (r2) * \
                                                                                            -2.755732e-7f)))))

/* cos(a) and sin(a) of a turn angle a (radians). */
MTX_FN void mtx_cos_sin(float a, float* c, float* s) {
  a = mtx_min(mtx_max(a, -MTX_MAX_TURN_ANGLE), MTX_MAX_TURN_ANGLE);
  const float scaled = a * MTX_TWO_OVER_PI;
  const int k = MTX_CAST(int, scaled + (scaled < 0.0f ? -0.5f : 0.5f)); /* nearest, halves away from 0 */
  const float kf = MTX_CAST(float, k);
  const float r = MTX_QUARTER_TURN_REST(a, kf);
  const float r2 = r * r;
  const float sin_r = MTX_SIN_SERIES(r, r2), cos_r = MTX_COS_SERIES(r2);
  const int q = k & 3;
  const float cq = (q & 1) ? sin_r : cos_r, sq = (q & 1) ? cos_r : sin_r;
  *c = (q == 1 || q == 2) ? -cq : cq;
  *s = (q >= 2) ? -sq : sq;
}

MTX_END_NAMESPACE

#endif
