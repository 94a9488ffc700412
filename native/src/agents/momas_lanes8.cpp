// MoMaS' step in eight AVX2 lanes (agents/momas_lanes.h), for processors without AVX-512:
// the 16-lane code's float operations in its order, so the same bits.
#include <cstddef>

#include "agents/momas_lanes_shared.h"
#include "surface/crossing_lanes.h"

#ifdef MOLDTEX_MOMAS_LANES_X86

namespace moldtex {

namespace {

// The same step as agents/momas_lanes16.cpp in eight AVX2 lanes (processors without
// AVX-512: AMD before Zen 4, Intel's consumer parts). Masks are vectors (all ones where
// set), the 64-bit multiplies of the random numbers are built from 32-bit ones; every
// float operation is the 16-lane code's, so the bits are the same.

#define MOLDTEX_AVX2_FN __attribute__((target("avx2"), always_inline)) inline

using M8 = __m256;  // a mask: all ones in the lanes where it holds

MOLDTEX_AVX2_FN unsigned bits8(M8 m) { return static_cast<unsigned>(_mm256_movemask_ps(m)); }
MOLDTEX_AVX2_FN M8 as_mask(__m256i m) { return _mm256_castsi256_ps(m); }
MOLDTEX_AVX2_FN __m256i as_int(M8 m) { return _mm256_castps_si256(m); }
MOLDTEX_AVX2_FN M8 and8(M8 a, M8 b) { return _mm256_and_ps(a, b); }
MOLDTEX_AVX2_FN M8 or8(M8 a, M8 b) { return _mm256_or_ps(a, b); }
MOLDTEX_AVX2_FN M8 but8(M8 a, M8 b) { return _mm256_andnot_ps(b, a); }  // a and not b
MOLDTEX_AVX2_FN __m256 sel8(__m256 a, M8 m, __m256 b) { return _mm256_blendv_ps(a, b, m); }  // m ? b : a
MOLDTEX_AVX2_FN __m256i seli8(__m256i a, M8 m, __m256i b) {
  return _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(a), _mm256_castsi256_ps(b), m));
}
MOLDTEX_AVX2_FN M8 lt8(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
MOLDTEX_AVX2_FN M8 gt8(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
MOLDTEX_AVX2_FN M8 eqi8(__m256i a, __m256i b) { return as_mask(_mm256_cmpeq_epi32(a, b)); }
MOLDTEX_AVX2_FN __m256 neg8(__m256 a) {
  return _mm256_castsi256_ps(_mm256_xor_si256(_mm256_castps_si256(a), _mm256_set1_epi32(static_cast<int>(0x80000000u))));
}
MOLDTEX_AVX2_FN __m256 abs8(__m256 a) {
  return _mm256_castsi256_ps(_mm256_and_si256(_mm256_castps_si256(a), _mm256_set1_epi32(0x7fffffff)));
}
MOLDTEX_AVX2_FN __m256 add8(__m256 a, __m256 b) { return _mm256_add_ps(a, b); }
MOLDTEX_AVX2_FN __m256 sub8(__m256 a, __m256 b) { return _mm256_sub_ps(a, b); }
MOLDTEX_AVX2_FN __m256 mul8(__m256 a, __m256 b) { return _mm256_mul_ps(a, b); }
// mtx_cos_sin in eight lanes (shared/angle.h: its rest and series macros on vectors,
// the clamp, the nearest quarter turn and the quadrant as masks).
MOLDTEX_AVX2_FN void cos_sin8(__m256 a, __m256& c, __m256& s) {
  const __m256 limit = _mm256_set1_ps(MTX_MAX_TURN_ANGLE);
  a = _mm256_min_ps(limit, _mm256_max_ps(neg8(limit), a));  // mtx_min(mtx_max(a, -limit), limit)
  const __m256 scaled = mul8(a, _mm256_set1_ps(MTX_TWO_OVER_PI));
  const __m256i k = _mm256_cvttps_epi32(
      add8(scaled, sel8(_mm256_set1_ps(0.5f), lt8(scaled, _mm256_setzero_ps()), _mm256_set1_ps(-0.5f))));
  const __m256 kf = _mm256_cvtepi32_ps(k);
  const __m256 r = MTX_QUARTER_TURN_REST(a, kf);
  const __m256 r2 = r * r;
  const __m256 sin_r = MTX_SIN_SERIES(r, r2), cos_r = MTX_COS_SERIES(r2);
  const __m256i q = _mm256_and_si256(k, _mm256_set1_epi32(3));
  const M8 odd = as_mask(_mm256_cmpeq_epi32(_mm256_and_si256(q, _mm256_set1_epi32(1)), _mm256_set1_epi32(1)));
  const __m256 cq = sel8(cos_r, odd, sin_r), sq = sel8(sin_r, odd, cos_r);
  const M8 flip_c = or8(eqi8(q, _mm256_set1_epi32(1)), eqi8(q, _mm256_set1_epi32(2)));
  const M8 flip_s = as_mask(_mm256_cmpgt_epi32(q, _mm256_set1_epi32(1)));
  c = sel8(cq, flip_c, neg8(cq));
  s = sel8(sq, flip_s, neg8(sq));
}

MOLDTEX_AVX2_FN __m256 gather8(const float* base, __m256i index, M8 m, __m256 src) {
  return _mm256_mask_i32gather_ps(src, base, index, m, 4);
}

// mtx_mix64 in four 64-bit lanes: products modulo 2^64 from 32 x 32-bit ones.
MOLDTEX_AVX2_FN __m256i mul64(__m256i a, uint64_t k) {
  const __m256i b = _mm256_set1_epi64x(static_cast<long long>(k));
  const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), b),
                                         _mm256_mul_epu32(a, _mm256_srli_epi64(b, 32)));
  return _mm256_add_epi64(_mm256_mul_epu32(a, b), _mm256_slli_epi64(cross, 32));
}
MOLDTEX_AVX2_FN __m256i mix64x4(__m256i x) {
  x = _mm256_add_epi64(x, _mm256_set1_epi64x(static_cast<long long>(0x9e3779b97f4a7c15ULL)));
  x = mul64(_mm256_xor_si256(x, _mm256_srli_epi64(x, 30)), 0xbf58476d1ce4e5b9ULL);
  x = mul64(_mm256_xor_si256(x, _mm256_srli_epi64(x, 27)), 0x94d049bb133111ebULL);
  return _mm256_xor_si256(x, _mm256_srli_epi64(x, 31));
}
MOLDTEX_AVX2_FN __m256 unit_float8(__m256i lo, __m256i hi) {
  const __m256i pick = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  const __m256i a = _mm256_permutevar8x32_epi32(_mm256_srli_epi64(lo, 40), pick);
  const __m256i b = _mm256_permutevar8x32_epi32(_mm256_srli_epi64(hi, 40), pick);
  const __m256i ab = _mm256_inserti128_si256(a, _mm256_castsi256_si128(b), 1);
  return mul8(_mm256_cvtepi32_ps(ab), _mm256_set1_ps(1.0f / 16777216.0f));
}

struct Texture8 {
  __m256 width, height;
  __m256i last_x, last_y, row;
};
MOLDTEX_AVX2_FN Texture8 texture8(const mtx_momas_constants& c) {
  return Texture8{_mm256_set1_ps(static_cast<float>(c.width)), _mm256_set1_ps(static_cast<float>(c.height)),
                  _mm256_set1_epi32(static_cast<int>(c.width) - 1), _mm256_set1_epi32(static_cast<int>(c.height) - 1),
                  _mm256_set1_epi32(static_cast<int>(c.width))};
}
MOLDTEX_AVX2_FN __m256i texel_at8(__m256 x, __m256 y, const Texture8& tx) {
  const __m256i zero = _mm256_setzero_si256();
  const __m256i ix = _mm256_min_epi32(_mm256_max_epi32(_mm256_cvttps_epi32(x), zero), tx.last_x);
  const __m256i iy = _mm256_min_epi32(_mm256_max_epi32(_mm256_cvttps_epi32(y), zero), tx.last_y);
  return _mm256_add_epi32(_mm256_mullo_epi32(iy, tx.row), ix);
}
MOLDTEX_AVX2_FN void point_in_texels8(__m256 b0, __m256 b1, __m256 b2, const __m256* uv, const Texture8& tx,
                                      __m256& x, __m256& y) {
  const __m256 u = add8(add8(mul8(b0, uv[0]), mul8(b1, uv[2])), mul8(b2, uv[4]));
  const __m256 v = add8(add8(mul8(b0, uv[1]), mul8(b1, uv[3])), mul8(b2, uv[5]));
  x = mul8(u, tx.width);
  y = mul8(v, tx.height);
}
MOLDTEX_AVX2_FN __m256i texel_of8(__m256 b0, __m256 b1, __m256 b2, const __m256* uv, const Texture8& tx) {
  __m256 x, y;
  point_in_texels8(b0, b1, b2, uv, tx, x, y);
  return texel_at8(x, y, tx);
}
// The corner UVs of triangle t in the lanes m (uv kept elsewhere; every lane's t must be
// a triangle): eight row loads and a transpose (load_sixes8).
MOLDTEX_AVX2_FN void gather_uvs8(const float* corner_uvs, __m256i t, M8 m, __m256* uv) {
  __m256 rows[6];
  load_sixes8(corner_uvs, nullptr, t, rows, nullptr);
  for (int q = 0; q < 6; ++q) uv[q] = _mm256_blendv_ps(uv[q], rows[q], m);
}
MOLDTEX_AVX2_FN __m256 per_species8(const float* four, __m256i species) {
  return _mm256_permutevar8x32_ps(_mm256_broadcast_ps(reinterpret_cast<const __m128*>(four)), species);
}
MOLDTEX_AVX2_FN void clamp_bary8(__m256& b0, __m256& b1, __m256& b2) {
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 x = sel8(b0, lt8(b0, zero), zero), y = sel8(b1, lt8(b1, zero), zero), z = sel8(b2, lt8(b2, zero), zero);
  const __m256 s = add8(add8(x, y), z);
  const M8 near_one = _mm256_cmp_ps(abs8(sub8(s, one)), _mm256_set1_ps(1e-4f), _CMP_LE_OQ);
  const M8 scaled = or8(near_one, gt8(s, zero));
  const __m256 inv = sel8(_mm256_div_ps(one, s), near_one, sub8(_mm256_set1_ps(2.0f), s));
  const __m256 third = _mm256_set1_ps(1.0f / 3.0f);
  b0 = sel8(third, scaled, mul8(x, inv));
  b1 = sel8(third, scaled, mul8(y, inv));
  b2 = sel8(third, scaled, mul8(z, inv));
}
MOLDTEX_AVX2_FN M8 clear_of_edge8(__m256 b, __m256 db, __m256 length) {
  const M8 rising = _mm256_cmp_ps(db, _mm256_setzero_ps(), _CMP_GE_OQ);
  const M8 kept = _mm256_cmp_ps(add8(b, mul8(length, db)), mul8(_mm256_set1_ps(1e-6f), b), _CMP_GE_OQ);
  return or8(rising, and8(gt8(b, _mm256_set1_ps(1e-30f)), kept));
}
MOLDTEX_AVX2_FN M8 meets_edge8(__m256 b, __m256 db, __m256 length) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256 tau = sel8(zero, gt8(b, zero), _mm256_div_ps(neg8(b), db));
  return and8(lt8(db, zero), lt8(tau, length));
}

struct Trace8 {
  __m256i t;
  __m256 s0, s1, s2, e0, e1, e2;
};

// mtx_trace_hops for the lanes `todo` (momas_lanes16.cpp's trace_hops in eight lanes).
MOLDTEX_AVX2_FN M8 trace_hops8(Trace8& g, M8 todo, const uint32_t* adjacency, const float* unfolded) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256i none = _mm256_set1_epi32(static_cast<int>(MTX_NO_NEIGHBOUR));
  M8 live = todo, located = _mm256_setzero_ps();
  for (int hop = 0;; ++hop) {
    const M8 n0 = and8(live, lt8(g.e0, zero)), n1 = and8(live, lt8(g.e1, zero)), n2 = and8(live, lt8(g.e2, zero));
    const M8 out = or8(or8(n0, n1), n2);
    located = or8(located, but8(live, out));
    live = out;
    if (!bits8(live) || hop == MTX_UNFOLDED_HOPS) break;
    __m256i live_i = as_int(live);
    const __m256i edge = exit_edge8(g.s0, g.s1, g.s2, g.e0, g.e1, g.e2, as_int(n0), as_int(n1), as_int(n2), live_i);
    live = as_mask(live_i);
    // (load_sixes8 reads every lane: the others read slot 0.)
    const __m256i slot =
        _mm256_and_si256(as_int(live), _mm256_add_epi32(_mm256_add_epi32(_mm256_add_epi32(g.t, g.t), g.t), edge));
    __m256 u[6];
    __m256i code;
    load_sixes8(unfolded, adjacency, slot, u, &code);
    live = but8(live, eqi8(code, none));
    if (!bits8(live)) break;
    carry_unfolded8(u, as_int(live), g.s0, g.s1, g.s2, g.e0, g.e1, g.e2);
    g.t = seli8(g.t, live, _mm256_srli_epi32(code, 3));
  }
  return located;
}

// The texel where each lane's trace ends (momas_lanes16.cpp's trace_probe, texel only).
MOLDTEX_AVX2_FN __m256i trace_texel8(const mtx_surface_tables& s, M8 todo, M8* ok, __m256i tri, __m256 b0, __m256 b1,
                                     __m256 b2, __m256 hx, __m256 hy, __m256 length, __m256 inv_a, __m256 bx,
                                     __m256 inv_by, const __m256* own_uv, const Texture8& tx, __m256i texel) {
  const __m256 d2 = mul8(hy, inv_by);
  const __m256 d1 = mul8(sub8(hx, mul8(bx, d2)), inv_a);
  Trace8 g{tri, b0, b1, b2, sub8(b0, mul8(length, add8(d1, d2))), add8(b1, mul8(length, d1)), add8(b2, mul8(length, d2))};
  const M8 located = trace_hops8(g, todo, s.adjacency, s.unfolded);
  *ok = but8(*ok, but8(todo, located));
  if (!bits8(located)) return texel;
  __m256 uv[6];
  for (int q = 0; q < 6; ++q) uv[q] = own_uv[q];
  const M8 elsewhere = but8(located, eqi8(g.t, tri));
  if (bits8(elsewhere)) gather_uvs8(s.corner_uvs, g.t, elsewhere, uv);
  return seli8(texel, located, texel_of8(g.e0, g.e1, g.e2, uv, tx));
}

struct Walk8 {
  __m256i t;
  __m256 b0, b1, b2, hx, hy;
  __m256 inv_a, bx, inv_by;
};

// mtx_walk_across in eight lanes (momas_lanes16.cpp's walk_across).
MOLDTEX_AVX2_FN M8 walk_across8(const mtx_surface_tables& s, Walk8& w, M8 todo, __m256 length) {
  const float* frames = reinterpret_cast<const float*>(s.frames);
  const __m256 zero = _mm256_setzero_ps();
  const __m256i i0 = _mm256_setzero_si256(), i1 = _mm256_set1_epi32(1), i2 = _mm256_set1_epi32(2);
  const __m256i none = _mm256_set1_epi32(static_cast<int>(MTX_NO_NEIGHBOUR));
  __m256 remaining = length;
  M8 live = todo, ended = _mm256_setzero_ps();
  for (int count = 0; count < kWalkLegs; ++count) {
    const __m256 db2 = mul8(w.hy, w.inv_by);
    const __m256 db1 = mul8(sub8(w.hx, mul8(w.bx, db2)), w.inv_a);
    const __m256 db0 = neg8(add8(db1, db2));
    __m256 travel = remaining;
    __m256i exit = _mm256_set1_epi32(-1);
    const __m256 bs[3] = {w.b0, w.b1, w.b2}, dbs[3] = {db0, db1, db2};
    for (int e = 0; e < 3; ++e) {
      const __m256 tau = sel8(zero, gt8(bs[e], zero), _mm256_div_ps(neg8(bs[e]), dbs[e]));
      const M8 sooner = and8(and8(live, lt8(dbs[e], zero)), lt8(tau, travel));
      travel = sel8(travel, sooner, tau);
      exit = seli8(exit, sooner, _mm256_set1_epi32(e));
    }
    __m256 b0 = add8(w.b0, mul8(travel, db0)), b1 = add8(w.b1, mul8(travel, db1)), b2 = add8(w.b2, mul8(travel, db2));
    const M8 stop = and8(live, as_mask(_mm256_cmpgt_epi32(i0, exit)));
    if (bits8(stop)) {
      __m256 c0 = b0, c1 = b1, c2 = b2;
      clamp_bary8(c0, c1, c2);
      w.b0 = sel8(w.b0, stop, c0);
      w.b1 = sel8(w.b1, stop, c1);
      w.b2 = sel8(w.b2, stop, c2);
      if (count > 0) {
        const __m256 n = _mm256_sqrt_ps(add8(mul8(w.hx, w.hx), mul8(w.hy, w.hy)));
        const M8 positive = gt8(n, zero);
        w.hx = sel8(w.hx, stop, sel8(_mm256_set1_ps(1.0f), positive, _mm256_div_ps(w.hx, n)));
        w.hy = sel8(w.hy, stop, sel8(zero, positive, _mm256_div_ps(w.hy, n)));
      }
      ended = or8(ended, stop);
      live = but8(live, stop);
    }
    if (!bits8(live)) break;
    const M8 x0 = eqi8(exit, i0), x1 = eqi8(exit, i1), x2 = eqi8(exit, i2);
    b0 = sel8(b0, x0, zero);
    b1 = sel8(b1, x1, zero);
    b2 = sel8(b2, x2, zero);
    clamp_bary8(b0, b1, b2);
    remaining = sub8(remaining, travel);
    const __m256 bj = sel8(sel8(b0, x1, b2), x0, b1);
    const __m256 bk = sel8(sel8(b1, x1, b0), x0, b2);
    const __m256i tf = _mm256_mullo_epi32(w.t, _mm256_set1_epi32(kFrameFloats));
    const __m256i at_edge = _mm256_add_epi32(_mm256_add_epi32(tf, _mm256_set1_epi32(kEdge)), _mm256_add_epi32(exit, exit));
    const __m256 ex = gather8(frames, at_edge, live, zero);
    const __m256 ey = gather8(frames, _mm256_add_epi32(at_edge, i1), live, zero);
    const __m256 along = add8(mul8(w.hx, ex), mul8(w.hy, ey));
    const __m256 across =
        _mm256_max_ps(_mm256_set1_ps(MTX_MIN_CROSSING_SINE), abs8(add8(mul8(w.hx, neg8(ey)), mul8(w.hy, ex))));
    const __m256i slot = _mm256_add_epi32(_mm256_add_epi32(_mm256_add_epi32(w.t, w.t), w.t), exit);
    const __m256i code =
        _mm256_mask_i32gather_epi32(none, reinterpret_cast<const int*>(s.adjacency), slot, as_int(live), 4);
    live = but8(live, eqi8(code, none));
    if (!bits8(live)) break;
    const __m256i next = _mm256_srli_epi32(code, 3);
    const __m256i edge = _mm256_and_si256(_mm256_srli_epi32(code, 1), _mm256_set1_epi32(3));
    const M8 same = eqi8(_mm256_and_si256(code, i1), i1);
    __m256i jn = _mm256_add_epi32(edge, seli8(i2, same, i1));
    jn = seli8(jn, as_mask(_mm256_cmpgt_epi32(jn, i2)), _mm256_sub_epi32(jn, _mm256_set1_epi32(3)));
    const M8 e0 = eqi8(edge, i0), e1 = eqi8(edge, i1), e2 = eqi8(edge, i2);
    const M8 j0 = eqi8(jn, i0), j1 = eqi8(jn, i1), j2 = eqi8(jn, i2);
    w.b0 = sel8(w.b0, live, sel8(sel8(bk, j0, bj), e0, zero));
    w.b1 = sel8(w.b1, live, sel8(sel8(bk, j1, bj), e1, zero));
    w.b2 = sel8(w.b2, live, sel8(sel8(bk, j2, bj), e2, zero));
    const __m256i nf = _mm256_mullo_epi32(next, _mm256_set1_epi32(kFrameFloats));
    const __m256i at_ccw = _mm256_add_epi32(_mm256_add_epi32(nf, _mm256_set1_epi32(kEdge)), _mm256_add_epi32(edge, edge));
    const __m256 cx = gather8(frames, at_ccw, live, zero);
    const __m256 cy = gather8(frames, _mm256_add_epi32(at_ccw, i1), live, zero);
    const __m256 signed_along = mul8(along, sel8(_mm256_set1_ps(-1.0f), same, _mm256_set1_ps(1.0f)));
    w.hx = sel8(w.hx, live, sub8(mul8(signed_along, cx), mul8(across, cy)));
    w.hy = sel8(w.hy, live, add8(mul8(signed_along, cy), mul8(across, cx)));
    w.t = seli8(w.t, live, next);
    w.inv_a = gather8(frames, _mm256_add_epi32(nf, _mm256_set1_epi32(kInvA)), live, w.inv_a);
    w.bx = gather8(frames, _mm256_add_epi32(nf, _mm256_set1_epi32(kBx)), live, w.bx);
    w.inv_by = gather8(frames, _mm256_add_epi32(nf, _mm256_set1_epi32(kInvBy)), live, w.inv_by);
  }
  return ended;
}

// momas_lanes16.cpp's step16 in eight lanes, texel units: agents [i, i + 8); returns the
// lanes stepped (bits).
MOLDTEX_AVX2_FN unsigned step8(const mtx_surface_tables& s, const mtx_momas_constants& c, const float* pheromone,
                               uint8_t* marks, Agents& agents, size_t i) {
  const float* frames = reinterpret_cast<const float*>(s.frames);
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256i tri = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(agents.triangle.data() + i));
  const __m256 b1 = _mm256_loadu_ps(agents.b1.data() + i), b2 = _mm256_loadu_ps(agents.b2.data() + i);
  __m256 hx = _mm256_loadu_ps(agents.hx.data() + i), hy = _mm256_loadu_ps(agents.hy.data() + i);
  const __m256i species =
      _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(agents.species.data() + i)));
  const __m256 b0 = sub8(sub8(one, b1), b2);
  const M8 all = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
  __m256 uv[6];
  for (int q = 0; q < 6; ++q) uv[q] = zero;
  gather_uvs8(s.corner_uvs, tri, all, uv);
  const __m256i tf = _mm256_mullo_epi32(tri, _mm256_set1_epi32(kFrameFloats));
  const __m256 inv_a = gather8(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kInvA)), all, zero);
  const __m256 bx = gather8(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kBx)), all, zero);
  const __m256 inv_by = gather8(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kInvBy)), all, zero);
  const __m256 alt0 = gather8(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kAltitude)), all, zero);
  const __m256 alt1 = gather8(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kAltitude + 1)), all, zero);
  const __m256 alt2 = gather8(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kAltitude + 2)), all, zero);

  const Texture8 tx = texture8(c);
  __m256 x, y;
  point_in_texels8(b0, b1, b2, uv, tx, x, y);
  // mtx_min(a, b) = b < a ? b : a = vminps(b, a).
  const __m256 m01 = _mm256_min_ps(mul8(b1, alt1), mul8(b0, alt0));
  const __m256 clearance = _mm256_min_ps(mul8(b2, alt2), m01);
  const __m256 sensor_length = per_species8(c.sensor_length, species);
  const __m256 move_length = per_species8(c.move_length, species);
  const __m256 margin = _mm256_set1_ps(1.0001f);
  const M8 probes_inside = gt8(clearance, mul8(sensor_length, margin));
  const M8 traced = s.unfolded ? but8(all, probes_inside) : zero;
  M8 inside = or8(probes_inside, traced);
  if (!bits8(inside)) return 0;
  M8 near = but8(inside, gt8(clearance, mul8(move_length, margin)));

  const __m256 du1 = mul8(sub8(uv[2], uv[0]), tx.width), dv1 = mul8(sub8(uv[3], uv[1]), tx.height);
  const __m256 du2 = mul8(sub8(uv[4], uv[0]), tx.width), dv2 = mul8(sub8(uv[5], uv[1]), tx.height);
  const __m256 jxx = mul8(du1, inv_a), jyx = mul8(dv1, inv_a);
  const __m256 jxy = mul8(sub8(du2, mul8(bx, jxx)), inv_by), jyy = mul8(sub8(dv2, mul8(bx, jyx)), inv_by);
  const __m256 cs = per_species8(c.sensor_cos, species), sn = per_species8(c.sensor_sin, species);
  const __m256 nsn = neg8(sn);
  const __m256 hxs[3] = {sub8(mul8(cs, hx), mul8(sn, hy)), hx, sub8(mul8(cs, hx), mul8(nsn, hy))};
  const __m256 hys[3] = {add8(mul8(sn, hx), mul8(cs, hy)), hy, add8(mul8(nsn, hx), mul8(cs, hy))};
  __m256i texel[3];
  for (int k = 0; k < 3; ++k) {
    const __m256 px = add8(x, mul8(sensor_length, add8(mul8(jxx, hxs[k]), mul8(jxy, hys[k]))));
    const __m256 py = add8(y, mul8(sensor_length, add8(mul8(jyx, hxs[k]), mul8(jyy, hys[k]))));
    texel[k] = texel_at8(px, py, tx);
  }
  if (bits8(traced)) {
    for (int k = 0; k < 3; ++k)
      texel[k] = trace_texel8(s, traced, &inside, tri, b0, b1, b2, hxs[k], hys[k], sensor_length, inv_a, bx, inv_by, uv,
                              tx, texel[k]);
    if (!bits8(inside)) return 0;
  }

  // Sense.
  const uint32_t plane_texels = c.width * c.height;
  const __m256i species4 = _mm256_slli_epi32(species, 2);
  __m256 sensed[3];
  for (int k = 0; k < 3; ++k) {
    __m256 v = zero;
    for (uint32_t p = 0; p < c.species_count; ++p) {
      const __m256 weight =
          _mm256_i32gather_ps(c.attraction, _mm256_add_epi32(species4, _mm256_set1_epi32(static_cast<int>(p))), 4);
      v = add8(v, mul8(weight, _mm256_i32gather_ps(pheromone + size_t(p) * plane_texels, texel[k], 4)));
    }
    sensed[k] = v;
  }
  const __m256 left = sensed[0], front = sensed[1], right = sensed[2];

  // Random draws, steering.
  const __m256i step_bits = _mm256_set1_epi64x(static_cast<long long>(c.step & 0xffffffffULL));
  const __m256i key = _mm256_set1_epi64x(static_cast<long long>(c.steer_key));
  const __m256i agent_lo = _mm256_add_epi64(_mm256_set1_epi64x(static_cast<long long>(i)), _mm256_setr_epi64x(0, 1, 2, 3));
  const __m256i agent_hi = _mm256_add_epi64(agent_lo, _mm256_set1_epi64x(4));
  __m256i state_lo = mix64x4(_mm256_xor_si256(key, _mm256_or_si256(_mm256_slli_epi64(agent_lo, 32), step_bits)));
  __m256i state_hi = mix64x4(_mm256_xor_si256(key, _mm256_or_si256(_mm256_slli_epi64(agent_hi, 32), step_bits)));
  state_lo = mix64x4(state_lo);
  state_hi = mix64x4(state_hi);
  const __m256 r = unit_float8(state_lo, state_hi);
  const M8 keep = and8(gt8(front, left), gt8(front, right));
  const M8 turning = but8(inside, keep);
  if (bits8(turning)) {
    const M8 to_left = gt8(left, right), to_right = gt8(right, left);
    __m256 side = _mm256_set1_ps(-1.0f);
    const M8 tie = but8(turning, or8(to_left, to_right));
    if (bits8(tie)) {
      const __m256 coin = unit_float8(mix64x4(state_lo), mix64x4(state_hi));
      side = sel8(side, lt8(coin, _mm256_set1_ps(0.5f)), one);
    }
    side = sel8(side, to_right, _mm256_set1_ps(-1.0f));
    side = sel8(side, to_left, one);
    const __m256 turn = mul8(mul8(side, r), per_species8(c.max_turn, species));
    __m256 tc, ts;
    cos_sin8(turn, tc, ts);
    const __m256 nx = sub8(mul8(tc, hx), mul8(ts, hy)), ny = add8(mul8(ts, hx), mul8(tc, hy));
    const __m256 f = sub8(_mm256_set1_ps(1.5f), mul8(_mm256_set1_ps(0.5f), add8(mul8(nx, nx), mul8(ny, ny))));
    hx = sel8(hx, turning, mul8(nx, f));
    hy = sel8(hy, turning, mul8(ny, f));
  }

  // Move and mark.
  const __m256 sub_length = _mm256_div_ps(move_length, _mm256_set1_ps(static_cast<float>(c.substeps)));
  const __m256i mark_base = _mm256_mullo_epi32(species, _mm256_set1_epi32(static_cast<int>(plane_texels)));
  Walk8 w{tri, b0, b1, b2, hx, hy, inv_a, bx, inv_by};
  M8 moved = zero;
  for (uint32_t k = 0; k < c.substeps; ++k) {
    const __m256 db2 = mul8(w.hy, w.inv_by);
    const __m256 db1 = mul8(sub8(w.hx, mul8(w.bx, db2)), w.inv_a);
    const __m256 db0 = neg8(add8(db1, db2));
    M8 across = zero;
    if (bits8(near)) {
      const M8 clear = and8(and8(clear_of_edge8(w.b0, db0, sub_length), clear_of_edge8(w.b1, db1, sub_length)),
                            clear_of_edge8(w.b2, db2, sub_length));
      across = and8(but8(near, clear), or8(or8(meets_edge8(w.b0, db0, sub_length), meets_edge8(w.b1, db1, sub_length)),
                                           meets_edge8(w.b2, db2, sub_length)));
    }
    const M8 within = but8(inside, across);
    __m256 n0 = add8(w.b0, mul8(sub_length, db0)), n1 = add8(w.b1, mul8(sub_length, db1)),
           n2 = add8(w.b2, mul8(sub_length, db2));
    clamp_bary8(n0, n1, n2);
    w.b0 = sel8(w.b0, within, n0);
    w.b1 = sel8(w.b1, within, n1);
    w.b2 = sel8(w.b2, within, n2);
    if (bits8(across)) {
      const M8 walked = walk_across8(s, w, across, sub_length);
      inside = but8(inside, but8(across, walked));
      near = and8(near, inside);
      moved = or8(moved, but8(walked, eqi8(w.t, tri)));
      if (!bits8(inside)) return 0;
      const M8 fresh = and8(walked, moved);
      if (bits8(fresh)) gather_uvs8(s.corner_uvs, w.t, fresh, uv);
    }
    alignas(32) uint32_t at[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(at), _mm256_add_epi32(mark_base, texel_of8(w.b0, w.b1, w.b2, uv, tx)));
    for (unsigned b = bits8(inside); b; b &= b - 1) MTX_MARK(marks, at[__builtin_ctz(b)]);
  }
  const __m256i store = as_int(inside);
  _mm256_maskstore_ps(agents.b1.data() + i, store, w.b1);
  _mm256_maskstore_ps(agents.b2.data() + i, store, w.b2);
  _mm256_maskstore_ps(agents.hx.data() + i, store, w.hx);
  _mm256_maskstore_ps(agents.hy.data() + i, store, w.hy);
  _mm256_maskstore_epi32(reinterpret_cast<int*>(agents.triangle.data() + i), as_int(and8(moved, inside)), w.t);
  return bits8(inside);
}

}  // namespace

__attribute__((target("avx2"))) size_t momas_lanes8(const mtx_surface_tables& s, const mtx_momas_constants& c,
                                                       const float* pheromone, const float* field, uint8_t* marks,
                                                       Agents& agents, size_t begin, size_t end) {
  Leftovers rest{s, c, pheromone, field, marks, agents, {}, 0, 0};
  size_t i = begin;
  for (; i + 8 <= end; i += 8) rest.take(i, step8(s, c, pheromone, marks, agents, i), 0xffu);
  return rest.finish(i, end);
}

}  // namespace moldtex

#endif
