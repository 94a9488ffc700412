// MoMaS' step in sixteen AVX-512 lanes (agents/momas_lanes.h): the same float operations
// in the same order as shared/momas.h (built without fused multiply-adds), so the same bits.
#include <cstddef>

#include "agents/momas_lanes_shared.h"
#include "surface/crossing_lanes.h"

#ifdef MOLDTEX_MOMAS_LANES_X86

namespace moldtex {

namespace {

#define MOLDTEX_MOMAS_LANES_FN __attribute__((target("avx512f,avx512dq,avx512bw,bmi2"), always_inline)) inline

// shared/rng.h's mtx_mix64 in eight 64-bit lanes.
MOLDTEX_MOMAS_LANES_FN __m512i mix64(__m512i x) {
  x = _mm512_add_epi64(x, _mm512_set1_epi64(static_cast<long long>(0x9e3779b97f4a7c15ULL)));
  x = _mm512_mullo_epi64(_mm512_xor_si512(x, _mm512_srli_epi64(x, 30)),
                         _mm512_set1_epi64(static_cast<long long>(0xbf58476d1ce4e5b9ULL)));
  x = _mm512_mullo_epi64(_mm512_xor_si512(x, _mm512_srli_epi64(x, 27)),
                         _mm512_set1_epi64(static_cast<long long>(0x94d049bb133111ebULL)));
  return _mm512_xor_si512(x, _mm512_srli_epi64(x, 31));
}

// mtx_rng_float's value of two halves of mixed states (lanes 0-7, 8-15): the top 24
// bits, exact as a float, times 2^-24.
MOLDTEX_MOMAS_LANES_FN __m512 unit_float(__m512i lo, __m512i hi) {
  const __m256i a = _mm512_cvtepi64_epi32(_mm512_srli_epi64(lo, 40));
  const __m256i b = _mm512_cvtepi64_epi32(_mm512_srli_epi64(hi, 40));
  const __m512i ab = _mm512_inserti64x4(_mm512_castsi256_si512(a), b, 1);
  return _mm512_mul_ps(_mm512_cvtepi32_ps(ab), _mm512_set1_ps(1.0f / 16777216.0f));
}

// mtx_texel_at_point in lanes: truncation toward zero (out of range and NaN give
// INT_MIN, as the scalar conversion does on x86), clamped to the texture.
MOLDTEX_MOMAS_LANES_FN __m512i texel_at(__m512 x, __m512 y, __m512i last_x, __m512i last_y, __m512i width) {
  const __m512i zero = _mm512_setzero_si512();
  const __m512i ix = _mm512_min_epi32(_mm512_max_epi32(_mm512_cvttps_epi32(x), zero), last_x);
  const __m512i iy = _mm512_min_epi32(_mm512_max_epi32(_mm512_cvttps_epi32(y), zero), last_y);
  return _mm512_add_epi32(_mm512_mullo_epi32(iy, width), ix);
}

// Marks byte marks[index] of each lane in m (every writer stores the same 1).
MOLDTEX_MOMAS_LANES_FN void mark_lanes(uint8_t* marks, __m512i index, __mmask16 m) {
  alignas(64) uint32_t at[16];
  _mm512_store_si512(at, index);
  for (unsigned bits = m; bits; bits &= bits - 1) MTX_MARK(marks, at[__builtin_ctz(bits)]);
}

// A texture's size for texel lookups in lanes.
struct TextureLanes {
  __m512 width, height;
  __m512i last_x, last_y, row;
};

MOLDTEX_MOMAS_LANES_FN TextureLanes texture_lanes(const mtx_momas_constants& c) {
  return TextureLanes{_mm512_set1_ps(static_cast<float>(c.width)), _mm512_set1_ps(static_cast<float>(c.height)),
                      _mm512_set1_epi32(static_cast<int>(c.width) - 1), _mm512_set1_epi32(static_cast<int>(c.height) - 1),
                      _mm512_set1_epi32(static_cast<int>(c.width))};
}

// The point with weights (b0, b1, b2) in a triangle whose corners have UVs uv[0..5], in
// texels: mtx_walker_texel_at's x and y.
MOLDTEX_MOMAS_LANES_FN void point_in_texels(__m512 b0, __m512 b1, __m512 b2, const __m512* uv, const TextureLanes& tx,
                                            __m512& x, __m512& y) {
  const __m512 u = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(b0, uv[0]), _mm512_mul_ps(b1, uv[2])),
                                 _mm512_mul_ps(b2, uv[4]));
  const __m512 v = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(b0, uv[1]), _mm512_mul_ps(b1, uv[3])),
                                 _mm512_mul_ps(b2, uv[5]));
  x = _mm512_mul_ps(u, tx.width);
  y = _mm512_mul_ps(v, tx.height);
}

// The corner UVs of triangle t in the lanes m (uv kept elsewhere; every lane's t must be
// a triangle): sixteen row loads and a transpose (load_sixes).
MOLDTEX_MOMAS_LANES_FN void gather_uvs(const float* corner_uvs, __m512i t, __mmask16 m, __m512* uv) {
  __m512 rows[6];
  load_sixes(corner_uvs, nullptr, t, rows, nullptr);
  for (int q = 0; q < 6; ++q) uv[q] = _mm512_mask_mov_ps(uv[q], m, rows[q]);
}

// mtx_min(a, b) (b < a ? b : a) in lanes: vminps returns its first operand where it is
// the smaller, else its second.
MOLDTEX_MOMAS_LANES_FN __m512 lanes_min(__m512 a, __m512 b) { return _mm512_min_ps(b, a); }

// A per-species constant (4 floats) for each lane's species.
MOLDTEX_MOMAS_LANES_FN __m512 per_species(const float* four, __m512i species) {
  return _mm512_permutexvar_ps(species, _mm512_broadcast_f32x4(_mm_loadu_ps(four)));
}

// What species s reads at `texel` (mtx_sensed_value without fields): the sum from 0.0f
// over the planes, in plane order.
MOLDTEX_MOMAS_LANES_FN __m512 sensed(const float* pheromone, uint32_t planes, uint32_t plane_texels,
                                     __m512 attraction_table, __m512i species4, __m512i texel) {
  __m512 v = _mm512_setzero_ps();
  for (uint32_t p = 0; p < planes; ++p) {
    const __m512 weight =
        _mm512_permutexvar_ps(_mm512_add_epi32(species4, _mm512_set1_epi32(static_cast<int>(p))), attraction_table);
    const __m512 value = _mm512_i32gather_ps(texel, pheromone + size_t(p) * plane_texels, 4);
    v = _mm512_add_ps(v, _mm512_mul_ps(weight, value));
  }
  return v;
}

// mtx_clamp_bary3 in lanes.
MOLDTEX_MOMAS_LANES_FN void clamp_bary(__m512& b0, __m512& b1, __m512& b2) {
  const __m512 zero = _mm512_setzero_ps();
  __m512 x = _mm512_mask_mov_ps(b0, _mm512_cmp_ps_mask(b0, zero, _CMP_LT_OQ), zero);
  __m512 y = _mm512_mask_mov_ps(b1, _mm512_cmp_ps_mask(b1, zero, _CMP_LT_OQ), zero);
  __m512 z = _mm512_mask_mov_ps(b2, _mm512_cmp_ps_mask(b2, zero, _CMP_LT_OQ), zero);
  const __m512 s = _mm512_add_ps(_mm512_add_ps(x, y), z);
  const __m512 one = _mm512_set1_ps(1.0f);
  const __mmask16 near_one =
      _mm512_cmp_ps_mask(_mm512_abs_ps(_mm512_sub_ps(s, one)), _mm512_set1_ps(1e-4f), _CMP_LE_OQ);
  const __mmask16 positive = _mm512_cmp_ps_mask(s, _mm512_setzero_ps(), _CMP_GT_OQ);
  __m512 inv = _mm512_div_ps(one, s);
  inv = _mm512_mask_mov_ps(inv, near_one, _mm512_sub_ps(_mm512_set1_ps(2.0f), s));
  const __mmask16 scaled = near_one | positive;
  const __m512 third = _mm512_set1_ps(1.0f / 3.0f);
  b0 = _mm512_mask_mul_ps(third, scaled, x, inv);
  b1 = _mm512_mask_mul_ps(third, scaled, y, inv);
  b2 = _mm512_mask_mul_ps(third, scaled, z, inv);
}

// floats[base + offset] and floats[base + offset + 1] in each lane.
MOLDTEX_MOMAS_LANES_FN void gather_pair_at(const float* floats, __m512i base, int offset, __m512& first,
                                           __m512& second) {
  gather_pairs(floats, _mm512_add_epi32(base, _mm512_set1_epi32(offset)), 0xffff, first, second);
}

// A triangle's map from frame directions to texel offsets, J = dUV/dq in texels.
struct Jacobian {
  __m512 xx, xy, yx, yy;
};

// Where each lane's probe ends: its triangle, its point in texels and the texel there
// (mtx_momas_probes' entries).
struct Probe {
  __m512i texel, triangle;
  __m512 x, y;
};

// mtx_floor_int and mtx_ceil_int in lanes (|v| < 2^31).
MOLDTEX_MOMAS_LANES_FN __m512i floor_int(__m512 v) {
  const __m512i i = _mm512_cvttps_epi32(v);
  return _mm512_mask_sub_epi32(i, _mm512_cmp_ps_mask(v, _mm512_cvtepi32_ps(i), _CMP_LT_OQ), i, _mm512_set1_epi32(1));
}
MOLDTEX_MOMAS_LANES_FN __m512i ceil_int(__m512 v) {
  const __m512i i = _mm512_cvttps_epi32(v);
  return _mm512_mask_add_epi32(i, _mm512_cmp_ps_mask(v, _mm512_cvtepi32_ps(i), _CMP_GT_OQ), i, _mm512_set1_epi32(1));
}

// The probe `length` from (x, y) (texels) along heading h on triangle tri (mtx_momas_probe's
// trace that stays inside the triangle).
MOLDTEX_MOMAS_LANES_FN Probe probe_at(__m512 x, __m512 y, __m512i tri, __m512 length, const Jacobian& j, __m512 hx,
                                      __m512 hy, const TextureLanes& tx) {
  const __m512 px = _mm512_add_ps(x, _mm512_mul_ps(length, _mm512_add_ps(_mm512_mul_ps(j.xx, hx), _mm512_mul_ps(j.xy, hy))));
  const __m512 py = _mm512_add_ps(y, _mm512_mul_ps(length, _mm512_add_ps(_mm512_mul_ps(j.yx, hx), _mm512_mul_ps(j.yy, hy))));
  return Probe{texel_at(px, py, tx.last_x, tx.last_y, tx.row), tri, px, py};
}

// -a: the sign bit flipped (0 - a would give +0 for a = +0, not -0).
MOLDTEX_MOMAS_LANES_FN __m512 negated(__m512 a) {
  return _mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(a), _mm512_set1_epi32(static_cast<int>(0x80000000u))));
}

// mtx_cos_sin in lanes (shared/angle.h: its rest and series macros on vectors, the
// clamp, the nearest quarter turn and the quadrant as masks).
MOLDTEX_MOMAS_LANES_FN void cos_sin(__m512 a, __m512& c, __m512& s) {
  const __m512 limit = _mm512_set1_ps(MTX_MAX_TURN_ANGLE);
  // mtx_max(a, -limit) (a < -limit ? -limit : a: vmaxps returns its second operand unless
  // the first is greater), then mtx_min with limit.
  a = lanes_min(_mm512_max_ps(negated(limit), a), limit);
  const __m512 scaled = _mm512_mul_ps(a, _mm512_set1_ps(MTX_TWO_OVER_PI));
  const __mmask16 negative = _mm512_cmp_ps_mask(scaled, _mm512_setzero_ps(), _CMP_LT_OQ);
  const __m512i k = _mm512_cvttps_epi32(
      _mm512_add_ps(scaled, _mm512_mask_mov_ps(_mm512_set1_ps(0.5f), negative, _mm512_set1_ps(-0.5f))));
  const __m512 kf = _mm512_cvtepi32_ps(k);
  const __m512 r = MTX_QUARTER_TURN_REST(a, kf);
  const __m512 r2 = r * r;
  const __m512 sin_r = MTX_SIN_SERIES(r, r2), cos_r = MTX_COS_SERIES(r2);
  const __m512i q = _mm512_and_si512(k, _mm512_set1_epi32(3));
  const __mmask16 odd = _mm512_test_epi32_mask(q, _mm512_set1_epi32(1));
  const __m512 cq = _mm512_mask_mov_ps(cos_r, odd, sin_r), sq = _mm512_mask_mov_ps(sin_r, odd, cos_r);
  const __mmask16 flip_c = _mm512_cmpeq_epi32_mask(q, _mm512_set1_epi32(1)) | _mm512_cmpeq_epi32_mask(q, _mm512_set1_epi32(2));
  const __mmask16 flip_s = _mm512_cmpge_epi32_mask(q, _mm512_set1_epi32(2));
  c = _mm512_mask_mov_ps(cq, flip_c, negated(cq));
  s = _mm512_mask_mov_ps(sq, flip_s, negated(sq));
}

// mtx_clear_of_edge in lanes: (db >= 0) | ((b > 1e-30) & (b + length db >= 1e-6 b)).
MOLDTEX_MOMAS_LANES_FN __mmask16 clear_of_edge(__m512 b, __m512 db, __m512 length) {
  const __mmask16 rising = _mm512_cmp_ps_mask(db, _mm512_setzero_ps(), _CMP_GE_OQ);
  const __mmask16 positive = _mm512_cmp_ps_mask(b, _mm512_set1_ps(1e-30f), _CMP_GT_OQ);
  const __mmask16 kept = _mm512_cmp_ps_mask(_mm512_add_ps(b, _mm512_mul_ps(length, db)),
                                            _mm512_mul_ps(_mm512_set1_ps(1e-6f), b), _CMP_GE_OQ);
  return rising | (positive & kept);
}

// mtx_meets_edge in lanes: db < 0 and (b > 0 ? -b / db : 0) < length.
MOLDTEX_MOMAS_LANES_FN __mmask16 meets_edge(__m512 b, __m512 db, __m512 length) {
  const __m512 zero = _mm512_setzero_ps();
  const __m512 tau = _mm512_maskz_div_ps(_mm512_cmp_ps_mask(b, zero, _CMP_GT_OQ), negated(b), db);
  return _mm512_cmp_ps_mask(db, zero, _CMP_LT_OQ) & _mm512_cmp_ps_mask(tau, length, _CMP_LT_OQ);
}

// Walkers in lanes, with their triangle's frame values that a walk reads.
struct Walk {
  __m512i t;
  __m512 b0, b1, b2, hx, hy;
  __m512 inv_a, bx, inv_by;
};

// mtx_walk_across for the lanes `todo` of w, each `length` long: leg by leg
// (mtx_walk_leg), each ending where the walk does, at an edge it crosses into the
// neighbour, or at an open boundary (those lanes are not returned: the scalar walk
// scatters them, with random numbers). Returns the lanes walked to their end.
MOLDTEX_MOMAS_LANES_FN __mmask16 walk_across(const mtx_surface_tables& s, Walk& w, __mmask16 todo, __m512 length) {
  static_assert(kWalkLegs <= MTX_MAX_CROSSINGS_PER_WALK, "the lanes end walks as mtx_walk_leg does");
  const float* frames = reinterpret_cast<const float*>(s.frames);
  const __m512 zero = _mm512_setzero_ps();
  const __m512i i0 = _mm512_setzero_si512(), i1 = _mm512_set1_epi32(1), i2 = _mm512_set1_epi32(2);
  const __m512i none = _mm512_set1_epi32(static_cast<int>(MTX_NO_NEIGHBOUR));
  __m512 remaining = length;
  __mmask16 live = todo, ended = 0;
  for (int count = 0; count < kWalkLegs; ++count) {
    // The first edge met within the remaining length, if any.
    const __m512 db2 = _mm512_mul_ps(w.hy, w.inv_by);
    const __m512 db1 = _mm512_mul_ps(_mm512_sub_ps(w.hx, _mm512_mul_ps(w.bx, db2)), w.inv_a);
    const __m512 db0 = negated(_mm512_add_ps(db1, db2));
    __m512 travel = remaining;
    __m512i exit = _mm512_set1_epi32(-1);
    const __m512 bs[3] = {w.b0, w.b1, w.b2}, dbs[3] = {db0, db1, db2};
    for (int e = 0; e < 3; ++e) {
      const __mmask16 falling = _mm512_mask_cmp_ps_mask(live, dbs[e], zero, _CMP_LT_OQ);
      const __m512 tau = _mm512_maskz_div_ps(_mm512_cmp_ps_mask(bs[e], zero, _CMP_GT_OQ), negated(bs[e]), dbs[e]);
      const __mmask16 sooner = falling & _mm512_cmp_ps_mask(tau, travel, _CMP_LT_OQ);
      travel = _mm512_mask_mov_ps(travel, sooner, tau);
      exit = _mm512_mask_mov_epi32(exit, sooner, _mm512_set1_epi32(e));
    }
    __m512 b0 = _mm512_add_ps(w.b0, _mm512_mul_ps(travel, db0));
    __m512 b1 = _mm512_add_ps(w.b1, _mm512_mul_ps(travel, db1));
    __m512 b2 = _mm512_add_ps(w.b2, _mm512_mul_ps(travel, db2));
    // Lanes whose walk ends in this triangle: weights clamped, the heading made unit
    // again after crossings.
    const __mmask16 stop = _mm512_mask_cmplt_epi32_mask(live, exit, i0);
    if (stop) {
      __m512 c0 = b0, c1 = b1, c2 = b2;
      clamp_bary(c0, c1, c2);
      w.b0 = _mm512_mask_mov_ps(w.b0, stop, c0);
      w.b1 = _mm512_mask_mov_ps(w.b1, stop, c1);
      w.b2 = _mm512_mask_mov_ps(w.b2, stop, c2);
      if (count > 0) {  // mtx_unit
        const __m512 n = _mm512_sqrt_ps(_mm512_add_ps(_mm512_mul_ps(w.hx, w.hx), _mm512_mul_ps(w.hy, w.hy)));
        const __mmask16 positive = _mm512_cmp_ps_mask(n, zero, _CMP_GT_OQ);
        w.hx = _mm512_mask_mov_ps(w.hx, stop, _mm512_mask_div_ps(_mm512_set1_ps(1.0f), positive, w.hx, n));
        w.hy = _mm512_mask_mov_ps(w.hy, stop, _mm512_mask_div_ps(zero, positive, w.hy, n));
      }
      ended |= stop;
      live &= static_cast<__mmask16>(~stop);
    }
    if (!live) break;
    // Onto the exit edge, then across it.
    const __mmask16 x0 = _mm512_cmpeq_epi32_mask(exit, i0), x1 = _mm512_cmpeq_epi32_mask(exit, i1);
    const __mmask16 x2 = _mm512_cmpeq_epi32_mask(exit, i2);
    b0 = _mm512_mask_mov_ps(b0, x0, zero);
    b1 = _mm512_mask_mov_ps(b1, x1, zero);
    b2 = _mm512_mask_mov_ps(b2, x2, zero);
    clamp_bary(b0, b1, b2);
    remaining = _mm512_sub_ps(remaining, travel);
    const __m512 bj = _mm512_mask_mov_ps(_mm512_mask_mov_ps(b0, x1, b2), x0, b1);
    const __m512 bk = _mm512_mask_mov_ps(_mm512_mask_mov_ps(b1, x1, b0), x0, b2);
    const __m512i tf = _mm512_mullo_epi32(w.t, _mm512_set1_epi32(kFrameFloats));
    const __m512i at_edge = _mm512_add_epi32(_mm512_add_epi32(tf, _mm512_set1_epi32(kEdge)), _mm512_add_epi32(exit, exit));
    __m512 ex, ey;
    gather_pairs(frames, at_edge, live, ex, ey);
    const __m512 along = _mm512_add_ps(_mm512_mul_ps(w.hx, ex), _mm512_mul_ps(w.hy, ey));
    const __m512 across = _mm512_max_ps(  // mtx_max(|...|, MTX_MIN_CROSSING_SINE)
        _mm512_set1_ps(MTX_MIN_CROSSING_SINE),
        _mm512_abs_ps(_mm512_add_ps(_mm512_mul_ps(w.hx, negated(ey)), _mm512_mul_ps(w.hy, ex))));
    const __m512i slot = _mm512_add_epi32(_mm512_add_epi32(_mm512_add_epi32(w.t, w.t), w.t), exit);
    const __m512i code = _mm512_mask_i32gather_epi32(none, live, slot, s.adjacency, 4);
    live &= static_cast<__mmask16>(~_mm512_mask_cmpeq_epi32_mask(live, code, none));
    if (!live) break;
    const __m512i next = _mm512_srli_epi32(code, 3);
    const __m512i edge = _mm512_and_si512(_mm512_srli_epi32(code, 1), _mm512_set1_epi32(3));
    const __mmask16 same = _mm512_test_epi32_mask(code, i1);
    // The corner of `next` equal to j: edge + 1 (same direction) or edge + 2, mod 3.
    __m512i jn = _mm512_add_epi32(edge, _mm512_mask_mov_epi32(i2, same, i1));
    jn = _mm512_mask_sub_epi32(jn, _mm512_cmpge_epi32_mask(jn, _mm512_set1_epi32(3)), jn, _mm512_set1_epi32(3));
    const __mmask16 e0 = _mm512_cmpeq_epi32_mask(edge, i0), e1 = _mm512_cmpeq_epi32_mask(edge, i1);
    const __mmask16 e2 = _mm512_cmpeq_epi32_mask(edge, i2);
    const __mmask16 j0 = _mm512_cmpeq_epi32_mask(jn, i0), j1 = _mm512_cmpeq_epi32_mask(jn, i1);
    const __mmask16 j2 = _mm512_cmpeq_epi32_mask(jn, i2);
    w.b0 = _mm512_mask_mov_ps(w.b0, live, _mm512_mask_mov_ps(_mm512_mask_mov_ps(bk, j0, bj), e0, zero));
    w.b1 = _mm512_mask_mov_ps(w.b1, live, _mm512_mask_mov_ps(_mm512_mask_mov_ps(bk, j1, bj), e1, zero));
    w.b2 = _mm512_mask_mov_ps(w.b2, live, _mm512_mask_mov_ps(_mm512_mask_mov_ps(bk, j2, bj), e2, zero));
    // The heading in the neighbour's frame: along its edge (reversed where it is wound
    // the other way round) and across it.
    const __m512i nf = _mm512_mullo_epi32(next, _mm512_set1_epi32(kFrameFloats));
    const __m512i at_ccw = _mm512_add_epi32(_mm512_add_epi32(nf, _mm512_set1_epi32(kEdge)), _mm512_add_epi32(edge, edge));
    __m512 cx, cy;
    gather_pairs(frames, at_ccw, live, cx, cy);
    const __m512 sign = _mm512_mask_mov_ps(_mm512_set1_ps(-1.0f), same, _mm512_set1_ps(1.0f));
    const __m512 signed_along = _mm512_mul_ps(along, sign);
    w.hx = _mm512_mask_mov_ps(w.hx, live, _mm512_sub_ps(_mm512_mul_ps(signed_along, cx), _mm512_mul_ps(across, cy)));
    w.hy = _mm512_mask_mov_ps(w.hy, live, _mm512_add_ps(_mm512_mul_ps(signed_along, cy), _mm512_mul_ps(across, cx)));
    w.t = _mm512_mask_mov_epi32(w.t, live, next);
    __m512 inv_a, inv_by;
    gather_pairs(frames, _mm512_add_epi32(nf, _mm512_set1_epi32(kInvA)), live, inv_a, inv_by);
    w.inv_a = _mm512_mask_mov_ps(w.inv_a, live, inv_a);
    w.inv_by = _mm512_mask_mov_ps(w.inv_by, live, inv_by);
    w.bx = _mm512_mask_i32gather_ps(w.bx, live, _mm512_add_epi32(nf, _mm512_set1_epi32(kBx)), frames, 4);
  }
  return ended;
}

// Sensor traces in lanes: the triangle, start and end weights of each (mtx_trace_ends).
struct Trace {
  __m512i t;
  __m512 s0, s1, s2, e0, e1, e2;
};

// mtx_trace_hops for the lanes `todo` of each of the three traces g[k]: returns in
// located[k] those located (g[k].t and g[k].e* then say where their traces end); the rest
// must be walked, for the reasons mtx_trace_hops gives up at the same crossing. The three
// probes hop together, so that the reads of one crossing are issued beside the others'
// instead of after them (each lane's hops are those of a trace alone).
MOLDTEX_MOMAS_LANES_FN void trace_hops(Trace* g, __mmask16 todo, const uint32_t* adjacency, const float* unfolded,
                                      __mmask16* located) {
  const __m512 zero = _mm512_setzero_ps();
  const __m512i none = _mm512_set1_epi32(static_cast<int>(MTX_NO_NEIGHBOUR));
  __mmask16 live[3] = {todo, todo, todo};
  for (int hop = 0;; ++hop) {
    __mmask16 n0[3], n1[3], n2[3];
    for (int k = 0; k < 3; ++k) {
      n0[k] = _mm512_mask_cmp_ps_mask(live[k], g[k].e0, zero, _CMP_LT_OQ);
      n1[k] = _mm512_mask_cmp_ps_mask(live[k], g[k].e1, zero, _CMP_LT_OQ);
      n2[k] = _mm512_mask_cmp_ps_mask(live[k], g[k].e2, zero, _CMP_LT_OQ);
      const __mmask16 out = n0[k] | n1[k] | n2[k];
      located[k] |= live[k] & ~out;
      live[k] = out;
    }
    if (!(live[0] | live[1] | live[2]) || hop == MTX_UNFOLDED_HOPS) break;
    // The edge each leaves by, the neighbour there and its unfolding (load_sixes reads
    // every lane: the others read slot 0), then both points carried into the neighbour.
    for (int k = 0; k < 3; ++k) {
      if (!live[k]) continue;
      const __m512i edge = exit_edge(g[k].s0, g[k].s1, g[k].s2, g[k].e0, g[k].e1, g[k].e2, n0[k], n1[k], n2[k], live[k]);
      const __m512i slot =
          _mm512_maskz_mov_epi32(live[k], _mm512_add_epi32(_mm512_add_epi32(_mm512_add_epi32(g[k].t, g[k].t), g[k].t), edge));
      __m512 u[6];
      __m512i code;
      load_sixes(unfolded, adjacency, slot, u, &code);
      live[k] &= ~_mm512_mask_cmpeq_epi32_mask(live[k], code, none);
      if (!live[k]) continue;
      carry_unfolded(u, live[k], g[k].s0, g[k].s1, g[k].s2, g[k].e0, g[k].e1, g[k].e2);
      g[k].t = _mm512_mask_mov_epi32(g[k].t, live[k], _mm512_srli_epi32(code, 3));
    }
  }
}

// Where the sensor traces from the agents' points (weights b*, triangle tri) along the
// three headings (hx[k], hy[k]) end, for the lanes `todo` that leave their triangle
// (mtx_momas_probe: mtx_walk_trace, then mtx_walker_texel_at), written into p[k]; clears
// from *ok the lanes whose trace must be walked.
MOLDTEX_MOMAS_LANES_FN void trace_probes(const mtx_surface_tables& s, __mmask16 todo, __mmask16* ok, __m512i tri,
                                         __m512 b0, __m512 b1, __m512 b2, const __m512* hx, const __m512* hy,
                                         __m512 length, __m512 inv_a, __m512 bx, __m512 inv_by, const __m512* own_uv,
                                         const TextureLanes& tx, Probe* p) {
  // mtx_trace_ends.
  Trace g[3];
  for (int k = 0; k < 3; ++k) {
    const __m512 d2 = _mm512_mul_ps(hy[k], inv_by);
    const __m512 d1 = _mm512_mul_ps(_mm512_sub_ps(hx[k], _mm512_mul_ps(bx, d2)), inv_a);
    g[k] = Trace{tri,
                 b0,
                 b1,
                 b2,
                 _mm512_sub_ps(b0, _mm512_mul_ps(length, _mm512_add_ps(d1, d2))),
                 _mm512_add_ps(b1, _mm512_mul_ps(length, d1)),
                 _mm512_add_ps(b2, _mm512_mul_ps(length, d2))};
  }
  __mmask16 located[3] = {0, 0, 0};
  trace_hops(g, todo, s.adjacency, s.unfolded, located);
  for (int k = 0; k < 3; ++k) {
    *ok &= static_cast<__mmask16>(~(todo & ~located[k]));
    if (!located[k]) continue;
    // The UVs of the triangle where each trace ends: the agent's own unless it crossed.
    __m512 uv[6];
    for (int q = 0; q < 6; ++q) uv[q] = own_uv[q];
    const __mmask16 elsewhere = _mm512_mask_cmpneq_epi32_mask(located[k], g[k].t, tri);
    if (elsewhere) gather_uvs(s.corner_uvs, g[k].t, elsewhere, uv);
    __m512 x, y;
    point_in_texels(g[k].e0, g[k].e1, g[k].e2, uv, tx, x, y);
    p[k].texel = _mm512_mask_mov_epi32(p[k].texel, located[k], texel_at(x, y, tx.last_x, tx.last_y, tx.row));
    p[k].triangle = _mm512_mask_mov_epi32(p[k].triangle, located[k], g[k].t);
    p[k].x = _mm512_mask_mov_ps(p[k].x, located[k], x);
    p[k].y = _mm512_mask_mov_ps(p[k].y, located[k], y);
  }
}

// table[index] for a byte table, in the lanes m (0 elsewhere): the last of four bytes
// read from max(index - 3, 0), so every byte read lies inside the table (of at least 4
// bytes).
MOLDTEX_MOMAS_LANES_FN __m512i byte_at(const uint8_t* table, __m512i index, __mmask16 m = 0xffff) {
  const __m512i at = _mm512_max_epi32(_mm512_sub_epi32(index, _mm512_set1_epi32(3)), _mm512_setzero_si512());
  const __m512i word = _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), m, at, table, 1);
  return _mm512_and_si512(_mm512_srlv_epi32(word, _mm512_slli_epi32(_mm512_sub_epi32(index, at), 3)),
                          _mm512_set1_epi32(0xff));
}

// A footprint's half sizes in texels on each lane's triangle t (mtx_footprint_box_at).
MOLDTEX_MOMAS_LANES_FN void footprint_size(const mtx_surface_tables& s, const mtx_momas_constants& c, __m512i t,
                                           __m512& ex, __m512& ey) {
  const __m512i t2 = _mm512_add_epi32(t, t);
  const __m512 half = _mm512_set1_ps(0.5f * c.length_unit), limit = _mm512_set1_ps(float(MTX_MAX_FOOTPRINT_TEXELS));
  ex = lanes_min(_mm512_mul_ps(half, _mm512_i32gather_ps(t2, s.texels_per_unit, 4)), limit);
  ey = lanes_min(_mm512_mul_ps(half, _mm512_i32gather_ps(_mm512_add_epi32(t2, _mm512_set1_epi32(1)), s.texels_per_unit, 4)),
                 limit);
}

// A texel box in lanes.
struct Box {
  __m512i x0, x1, y0, y1;
};

// mtx_centres_within: the texels whose centres lie within (ex, ey) of (x, y), clipped.
MOLDTEX_MOMAS_LANES_FN Box centres_within(__m512 x, __m512 y, __m512 ex, __m512 ey, const mtx_momas_constants& c) {
  const __m512 h = _mm512_set1_ps(0.5f);
  Box b{ceil_int(_mm512_sub_ps(_mm512_sub_ps(x, ex), h)), floor_int(_mm512_sub_ps(_mm512_add_ps(x, ex), h)),
        ceil_int(_mm512_sub_ps(_mm512_sub_ps(y, ey), h)), floor_int(_mm512_sub_ps(_mm512_add_ps(y, ey), h))};
  b.x0 = _mm512_max_epi32(b.x0, _mm512_setzero_si512());
  b.y0 = _mm512_max_epi32(b.y0, _mm512_setzero_si512());
  b.x1 = _mm512_min_epi32(b.x1, _mm512_set1_epi32(static_cast<int>(c.width) - 1));
  b.y1 = _mm512_min_epi32(b.y1, _mm512_set1_epi32(static_cast<int>(c.height) - 1));
  return b;
}

// mtx_box_within_island for the box grown by `grow` texels each side: within the block
// around `texel` that its interior reach says is all of its island, that island being
// the lane's triangle's. The sole reach (TextureDomain::sole_reach, `sole`: its values at
// `texel`) says both: a texel that is its island's alone is the island of every point in
// it, so of the lane's triangle (the texel holds the lane's point, a point of that
// triangle).
MOLDTEX_MOMAS_LANES_FN __mmask16 box_within_island(const mtx_momas_constants& c, __m512i texel, __m512i sole,
                                                   const Box& b, int grow) {
  const __mmask16 known = _mm512_test_epi32_mask(sole, sole);
  const __m512i r = _mm512_sub_epi32(sole, _mm512_set1_epi32(1));
  // The texel's column and row: a float quotient, corrected by one where it rounded
  // across a row.
  const __m512i width = _mm512_set1_epi32(static_cast<int>(c.width));
  __m512i cy = _mm512_cvttps_epi32(_mm512_div_ps(_mm512_cvtepi32_ps(texel), _mm512_cvtepi32_ps(width)));
  __m512i cx = _mm512_sub_epi32(texel, _mm512_mullo_epi32(cy, width));
  const __mmask16 under = _mm512_cmplt_epi32_mask(cx, _mm512_setzero_si512());
  cy = _mm512_mask_sub_epi32(cy, under, cy, _mm512_set1_epi32(1));
  cx = _mm512_mask_add_epi32(cx, under, cx, width);
  const __mmask16 over = _mm512_cmpge_epi32_mask(cx, width);
  cy = _mm512_mask_add_epi32(cy, over, cy, _mm512_set1_epi32(1));
  cx = _mm512_mask_sub_epi32(cx, over, cx, width);
  const __m512i g = _mm512_set1_epi32(grow);
  return known & _mm512_cmpge_epi32_mask(_mm512_sub_epi32(b.x0, g), _mm512_sub_epi32(cx, r)) &
         _mm512_cmple_epi32_mask(_mm512_add_epi32(b.x1, g), _mm512_add_epi32(cx, r)) &
         _mm512_cmpge_epi32_mask(_mm512_sub_epi32(b.y0, g), _mm512_sub_epi32(cy, r)) &
         _mm512_cmple_epi32_mask(_mm512_add_epi32(b.y1, g), _mm512_add_epi32(cy, r));
}

// Surface units: each lane of `lanes` marks its footprint around (x, y) (texels; the
// walker on triangle t, over `texel`), as mtx_mark_footprint does: the texel under it if
// an island texel, then, where the box of texels whose centres the footprint holds lies
// (grown by one) within the texel's island block, every texel of that box, in the lanes;
// elsewhere (strongly stretched texels, boxes near an island's edge) mtx_mark_footprint
// lane by lane.
MOLDTEX_MOMAS_LANES_FN void mark_footprints(const mtx_surface_tables& s, const mtx_momas_constants& c,
                                            const float* field, uint8_t* marks, __mmask16 lanes, __m512i species,
                                            __m512i t, __m512i texel, __m512 x, __m512 y) {
  const uint32_t plane_texels = c.width * c.height;
  const __m512i base = _mm512_mullo_epi32(species, _mm512_set1_epi32(static_cast<int>(plane_texels)));
  __mmask16 slow = lanes;
  if (!c.has_fields && s.sole_reach != nullptr) {
    __m512 ex, ey;
    footprint_size(s, c, t, ex, ey);
    const __m512 quarter = _mm512_set1_ps(0.25f), half = _mm512_set1_ps(0.5f);
    const __mmask16 jx = _mm512_cmp_ps_mask(ex, quarter, _CMP_LT_OQ) &
                         _mm512_cmp_ps_mask(ex, _mm512_mul_ps(half, ey), _CMP_LT_OQ);
    const __mmask16 jy = _mm512_cmp_ps_mask(ey, quarter, _CMP_LT_OQ) &
                         _mm512_cmp_ps_mask(ey, _mm512_mul_ps(half, ex), _CMP_LT_OQ);
    const __mmask16 plain = lanes & static_cast<__mmask16>(~(jx | jy));
    // The texel under the walker, if an island texel: one that is its island's alone
    // is one (its sole reach, which the box below reads too, is above 0); the others'
    // classes are read.
    const __m512i sole = byte_at(s.sole_reach, texel);
    const __mmask16 alone = plain & _mm512_test_epi32_mask(sole, sole);
    const __mmask16 unsure = plain & static_cast<__mmask16>(~alone);
    __mmask16 own = alone;
    if (unsure) own |= _mm512_mask_cmpeq_epi32_mask(unsure, byte_at(s.classes, texel, unsure),
                                                    _mm512_set1_epi32(MTX_TEXEL_INSIDE));
    mark_lanes(marks, _mm512_add_epi32(base, texel), own);
    const __mmask16 small = _mm512_cmp_ps_mask(ex, half, _CMP_LT_OQ) & _mm512_cmp_ps_mask(ey, half, _CMP_LT_OQ);
    const __mmask16 boxed = plain & static_cast<__mmask16>(~small);
    __mmask16 fast = 0;
    if (boxed) {
      const Box b = centres_within(x, y, ex, ey, c);
      const __mmask16 filled = _mm512_cmple_epi32_mask(b.x0, b.x1) & _mm512_cmple_epi32_mask(b.y0, b.y1);
      fast = boxed & filled & box_within_island(c, texel, sole, b, 1);
      if (fast) {  // each lane's box row by row, a row's bytes in one masked store
        static_assert(2 * MTX_MAX_FOOTPRINT_TEXELS + 1 <= 64, "a box row within one 64-byte store");
        alignas(64) int32_t first[16], last_x[16], top[16], bottom[16], offset[16];
        _mm512_store_si512(first, b.x0);
        _mm512_store_si512(last_x, b.x1);
        _mm512_store_si512(top, b.y0);
        _mm512_store_si512(bottom, b.y1);
        _mm512_store_si512(offset, base);
        const __m512i ones = _mm512_set1_epi8(1);
        for (unsigned bits = fast; bits; bits &= bits - 1) {
          const int q = __builtin_ctz(bits);
          const __mmask64 row_bytes = _bzhi_u64(~0ull, static_cast<unsigned>(last_x[q] - first[q] + 1));
          uint8_t* at = marks + static_cast<uint32_t>(offset[q]) + size_t(top[q]) * c.width + first[q];
          for (int yy = top[q]; yy <= bottom[q]; ++yy, at += c.width) _mm512_mask_storeu_epi8(at, row_bytes, ones);
        }
      }
    }
    slow = (lanes & (jx | jy)) | (boxed & static_cast<__mmask16>(~fast));
  }
  if (!slow) return;
  alignas(64) uint32_t sp[16], at[16], on[16];
  alignas(64) float fx[16], fy[16];
  _mm512_store_si512(sp, species);
  _mm512_store_si512(at, texel);
  _mm512_store_si512(on, t);
  _mm512_store_ps(fx, x);
  _mm512_store_ps(fy, y);
  for (unsigned bits = slow; bits; bits &= bits - 1) {
    const int q = __builtin_ctz(bits);
    mtx_walker where{};
    where.triangle = on[q];
    mtx_mark_footprint(s, field, marks + size_t(sp[q]) * plane_texels, &where, at[q], fx[q], fy[q], &c);
  }
}

// What each lane of `lanes` reads at its probes in surface units: the mean over the
// footprint around the probe (mtx_sense_footprint_at). In the usual case (one species, no
// fields, the footprint's box within the block around the probe's texel that is all of
// the lane's island) the box is summed in the lanes, row by row as the scalar code sums
// it; other lanes call mtx_sense_footprint_at.
MOLDTEX_MOMAS_LANES_FN void sense_footprints(const mtx_surface_tables& s, const mtx_momas_constants& c,
                                             const float* pheromone, const float* field, __mmask16 lanes,
                                             __m512i species, const Probe* p, __m512* value) {
  const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f);
  const bool plain = c.species_count == 1u && !c.has_fields && s.sole_reach != nullptr;
  const __m512i width = _mm512_set1_epi32(static_cast<int>(c.width));
  for (int k = 0; k < 3; ++k) {
    __mmask16 slow = lanes;
    value[k] = zero;
    if (plain) {
      // What the probe's own texel holds (mtx_sensed_value: 0 + a p).
      const __m512 a = _mm512_set1_ps(c.attraction[0]);
      const __m512 here = _mm512_add_ps(zero, _mm512_mul_ps(a, _mm512_i32gather_ps(p[k].texel, pheromone, 4)));
      // The footprint's box (mtx_footprint_box_at, mtx_centres_within), and whether it
      // lies within the probe texel's island block.
      __m512 ex, ey;
      footprint_size(s, c, p[k].triangle, ex, ey);
      const __mmask16 small = _mm512_cmp_ps_mask(ex, _mm512_set1_ps(0.5f), _CMP_LT_OQ) &
                              _mm512_cmp_ps_mask(ey, _mm512_set1_ps(0.5f), _CMP_LT_OQ);
      const Box b = centres_within(p[k].x, p[k].y, ex, ey, c);
      const __mmask16 whole = box_within_island(c, p[k].texel, byte_at(s.sole_reach, p[k].texel), b, 0);
      const __mmask16 fast = lanes & static_cast<__mmask16>(~small) & whole;
      __m512 sum = here, count = one;
      if (fast) {
        const __m512i w = _mm512_sub_epi32(b.x1, b.x0), hgt = _mm512_sub_epi32(b.y1, b.y0);
        const int most_w = _mm512_mask_reduce_max_epi32(fast, w), most_h = _mm512_mask_reduce_max_epi32(fast, hgt);
        for (int dy = 0; dy <= most_h; ++dy) {
          const __mmask16 row_in = fast & _mm512_cmple_epi32_mask(_mm512_set1_epi32(dy), hgt);
          if (!row_in) continue;
          const __m512i row = _mm512_mullo_epi32(_mm512_add_epi32(b.y0, _mm512_set1_epi32(dy)), width);
          // Two texels of the row at a time where the box holds both (one 64-bit gather per
          // eight lanes), added in the row's order.
          for (int dx = 0; dx <= most_w; dx += 2) {
            const __m512i i = _mm512_add_epi32(row, _mm512_add_epi32(b.x0, _mm512_set1_epi32(dx)));
            const __mmask16 first = row_in & _mm512_cmple_epi32_mask(_mm512_set1_epi32(dx), w);
            const __mmask16 both = row_in & _mm512_cmple_epi32_mask(_mm512_set1_epi32(dx + 1), w);
            __m512 v0 = zero, v1 = zero;
            if (both) gather_pairs(pheromone, i, both, v0, v1);
            const __mmask16 single = first & static_cast<__mmask16>(~both);
            if (single) v0 = _mm512_mask_i32gather_ps(v0, single, i, pheromone, 4);
            const __mmask16 m0 = first & _mm512_cmpneq_epi32_mask(i, p[k].texel);
            sum = _mm512_mask_add_ps(sum, m0, sum, _mm512_mul_ps(a, v0));
            count = _mm512_mask_add_ps(count, m0, count, one);
            const __mmask16 m1 =
                both & _mm512_cmpneq_epi32_mask(_mm512_add_epi32(i, _mm512_set1_epi32(1)), p[k].texel);
            sum = _mm512_mask_add_ps(sum, m1, sum, _mm512_mul_ps(a, v1));
            count = _mm512_mask_add_ps(count, m1, count, one);
          }
        }
      }
      value[k] = _mm512_mask_mov_ps(here, fast, _mm512_div_ps(sum, count));
      slow = lanes & static_cast<__mmask16>(~small) & static_cast<__mmask16>(~whole);
    }
    if (!slow) continue;
    alignas(64) uint32_t sp[16], texel[16], tri[16];
    alignas(64) float x[16], y[16], v[16];
    _mm512_store_si512(sp, species);
    _mm512_store_si512(texel, p[k].texel);
    _mm512_store_si512(tri, p[k].triangle);
    _mm512_store_ps(x, p[k].x);
    _mm512_store_ps(y, p[k].y);
    _mm512_store_ps(v, value[k]);
    for (unsigned bits = slow; bits; bits &= bits - 1) {
      const int j = __builtin_ctz(bits);
      v[j] = mtx_sense_footprint_at(s, pheromone, field, tri[j], x[j], y[j], texel[j], sp[j], &c);
    }
    value[k] = _mm512_load_ps(v);
  }
}

// Agents [i, i + 16) through a whole step in the lanes; returns the lanes stepped (the
// others, with a trace or a move that must be walked, are left to the scalar code).
MOLDTEX_MOMAS_LANES_FN __mmask16 step16(const mtx_surface_tables& s, const mtx_momas_constants& c,
                                        const float* pheromone, const float* field, uint8_t* marks, Agents& agents,
                                        size_t i) {
  const float* frames = reinterpret_cast<const float*>(s.frames);
  const __m512i tri = _mm512_loadu_si512(agents.triangle.data() + i);
  const __m512 b1_in = _mm512_loadu_ps(agents.b1.data() + i), b2_in = _mm512_loadu_ps(agents.b2.data() + i);
  __m512 hx = _mm512_loadu_ps(agents.hx.data() + i), hy = _mm512_loadu_ps(agents.hy.data() + i);
  const __m512i species =
      _mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(agents.species.data() + i)));
  const __m512 one = _mm512_set1_ps(1.0f);
  // Agents::load: the first weight from the other two.
  __m512 b0 = _mm512_sub_ps(_mm512_sub_ps(one, b1_in), b2_in), b1 = b1_in, b2 = b2_in;

  // The triangle's UVs and frame.
  __m512 uv[6];
  gather_uvs(s.corner_uvs, tri, 0xffff, uv);
  // The frame's values in pairs of neighbours (mtx_frame: a bx by inv_a inv_by edge[3]
  // altitude[3]).
  static_assert(kBx == 1 && kInvBy == kInvA + 1 && kAltitude == kEdge + 6, "mtx_frame's layout");
  const __m512i tf = _mm512_mullo_epi32(tri, _mm512_set1_epi32(kFrameFloats));
  __m512 unused_a, bx, inv_a, inv_by, unused_edge, alt0, alt1, alt2;
  gather_pair_at(frames, tf, 0, unused_a, bx);
  gather_pair_at(frames, tf, kInvA, inv_a, inv_by);
  gather_pair_at(frames, tf, kAltitude - 1, unused_edge, alt0);
  gather_pair_at(frames, tf, kAltitude + 1, alt1, alt2);

  // mtx_momas_probe: the texel under the agent and its clearance.
  const TextureLanes tx = texture_lanes(c);
  __m512 x, y;
  point_in_texels(b0, b1, b2, uv, tx, x, y);
  const __m512 clearance =
      lanes_min(lanes_min(_mm512_mul_ps(b0, alt0), _mm512_mul_ps(b1, alt1)), _mm512_mul_ps(b2, alt2));
  const __m512 sensor_length = per_species(c.sensor_length, species);
  const __m512 move_length = per_species(c.move_length, species);
  const __m512 margin = _mm512_set1_ps(1.0001f);
  // The lanes whose probes stay inside the triangle, and the others, whose traces cross
  // edges through the unfolded neighbours (where the tables have them); those whose move
  // is sure to stay inside, and the others, whose move is tested as it goes.
  // A step without sensing (mtx_momas_constants.coast) traces no probes.
  const __mmask16 probes_inside =
      c.coast ? 0xffff : _mm512_cmp_ps_mask(clearance, _mm512_mul_ps(sensor_length, margin), _CMP_GT_OQ);
  const __mmask16 traced = s.unfolded ? static_cast<__mmask16>(~probes_inside) : 0;
  __mmask16 inside = static_cast<__mmask16>(probes_inside | traced);
  if (!inside) return 0;
  __mmask16 near = inside & ~_mm512_cmp_ps_mask(clearance, _mm512_mul_ps(move_length, margin), _CMP_GT_OQ);

  const uint32_t plane_texels = c.width * c.height;
  // mtx_momas_decision: sense (a step without sensing reads 0, 1, 0: straight on).
  __m512 left = _mm512_setzero_ps(), front = one, right = _mm512_setzero_ps();
  if (!c.coast) {
    // The three probes through the triangle's affine map to texels.
    const __m512 du1 = _mm512_mul_ps(_mm512_sub_ps(uv[2], uv[0]), tx.width);
    const __m512 dv1 = _mm512_mul_ps(_mm512_sub_ps(uv[3], uv[1]), tx.height);
    const __m512 du2 = _mm512_mul_ps(_mm512_sub_ps(uv[4], uv[0]), tx.width);
    const __m512 dv2 = _mm512_mul_ps(_mm512_sub_ps(uv[5], uv[1]), tx.height);
    const __m512 jxx = _mm512_mul_ps(du1, inv_a), jyx = _mm512_mul_ps(dv1, inv_a);
    const __m512 jxy = _mm512_mul_ps(_mm512_sub_ps(du2, _mm512_mul_ps(bx, jxx)), inv_by);
    const __m512 jyy = _mm512_mul_ps(_mm512_sub_ps(dv2, _mm512_mul_ps(bx, jyx)), inv_by);
    const __m512 cs = per_species(c.sensor_cos, species), sn = per_species(c.sensor_sin, species);
    const __m512 nsn = negated(sn);
    const Jacobian j{jxx, jxy, jyx, jyy};
    // mtx_rotate(h, c, s): (c x - s y, s x + c y); the right probe turns by -s.
    const __m512 px[3] = {_mm512_sub_ps(_mm512_mul_ps(cs, hx), _mm512_mul_ps(sn, hy)), hx,
                          _mm512_sub_ps(_mm512_mul_ps(cs, hx), _mm512_mul_ps(nsn, hy))};
    const __m512 py[3] = {_mm512_add_ps(_mm512_mul_ps(sn, hx), _mm512_mul_ps(cs, hy)), hy,
                          _mm512_add_ps(_mm512_mul_ps(nsn, hx), _mm512_mul_ps(cs, hy))};
    Probe probe[3];
    for (int k = 0; k < 3; ++k) probe[k] = probe_at(x, y, tri, sensor_length, j, px[k], py[k], tx);
    if (traced) {
      trace_probes(s, traced, &inside, tri, b0, b1, b2, px, py, sensor_length, inv_a, bx, inv_by, uv, tx, probe);
      if (!inside) return 0;
    }
    __m512 value[3];
    if (c.surface_mode) {
      sense_footprints(s, c, pheromone, field, inside, species, probe, value);
    } else {
      const __m512 attraction = _mm512_loadu_ps(c.attraction);
      const __m512i species4 = _mm512_slli_epi32(species, 2);
      for (int k = 0; k < 3; ++k)
        value[k] = sensed(pheromone, c.species_count, plane_texels, attraction, species4, probe[k].texel);
    }
    left = value[0];
    front = value[1];
    right = value[2];
  }

  // The step's random state per agent (mtx_rng_init_step) and its first two draws.
  const __m512i iota64 = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7);
  const __m512i step_bits = _mm512_set1_epi64(static_cast<long long>(c.step & 0xffffffffULL));
  const __m512i key = _mm512_set1_epi64(static_cast<long long>(c.steer_key));
  const __m512i first_agent = _mm512_set1_epi64(static_cast<long long>(i));
  const __m512i agent_lo = _mm512_add_epi64(first_agent, iota64);
  const __m512i agent_hi = _mm512_add_epi64(agent_lo, _mm512_set1_epi64(8));
  __m512i state_lo = mix64(_mm512_xor_si512(key, _mm512_or_si512(_mm512_slli_epi64(agent_lo, 32), step_bits)));
  __m512i state_hi = mix64(_mm512_xor_si512(key, _mm512_or_si512(_mm512_slli_epi64(agent_hi, 32), step_bits)));
  state_lo = mix64(state_lo);
  state_hi = mix64(state_hi);
  const __m512 r = unit_float(state_lo, state_hi);

  // Steer: keep going only while the front is strictly strongest.
  const __mmask16 keep =
      _mm512_cmp_ps_mask(front, left, _CMP_GT_OQ) & _mm512_cmp_ps_mask(front, right, _CMP_GT_OQ);
  const __mmask16 turning = static_cast<__mmask16>(~keep) & inside;
  if (turning) {
    const __mmask16 to_left = _mm512_cmp_ps_mask(left, right, _CMP_GT_OQ);
    const __mmask16 to_right = _mm512_cmp_ps_mask(right, left, _CMP_GT_OQ);
    __m512 side = _mm512_set1_ps(-1.0f);
    const __mmask16 tie = static_cast<__mmask16>(turning & ~(to_left | to_right));
    if (tie) {  // a third draw decides the side
      const __m512 coin = unit_float(mix64(state_lo), mix64(state_hi));
      side = _mm512_mask_mov_ps(side, _mm512_cmp_ps_mask(coin, _mm512_set1_ps(0.5f), _CMP_LT_OQ), one);
    }
    side = _mm512_mask_mov_ps(side, to_right, _mm512_set1_ps(-1.0f));
    side = _mm512_mask_mov_ps(side, to_left, one);
    // Surface units: mean r = 1/2 as MoMaS, the spread around it time-step independent.
    const __m512 amount =
        c.surface_mode
            ? _mm512_add_ps(_mm512_set1_ps(0.5f), _mm512_mul_ps(_mm512_sub_ps(r, _mm512_set1_ps(0.5f)),
                                                                _mm512_set1_ps(c.turn_jitter)))
            : r;
    const __m512 turn = _mm512_mul_ps(_mm512_mul_ps(side, amount), per_species(c.max_turn, species));
    __m512 tc, ts;
    cos_sin(turn, tc, ts);
    // mtx_renormalised(mtx_rotate(h, cos, sin)).
    const __m512 nx = _mm512_sub_ps(_mm512_mul_ps(tc, hx), _mm512_mul_ps(ts, hy));
    const __m512 ny = _mm512_add_ps(_mm512_mul_ps(ts, hx), _mm512_mul_ps(tc, hy));
    const __m512 f = _mm512_sub_ps(_mm512_set1_ps(1.5f),
                                   _mm512_mul_ps(_mm512_set1_ps(0.5f), _mm512_add_ps(_mm512_mul_ps(nx, nx),
                                                                                     _mm512_mul_ps(ny, ny))));
    hx = _mm512_mask_mul_ps(hx, turning, nx, f);
    hy = _mm512_mask_mul_ps(hy, turning, ny, f);
  }

  // Move in substeps (mtx_walk_until), marking each end: inside the triangle without
  // tests where the move is sure to stay there (mtx_walk_inside_known), else tested, and
  // across edges where it meets one (mtx_walk_across; lanes that reach an open boundary
  // leave for the scalar code, their marks so far being ones it makes again).
  const __m512 sub_length = _mm512_div_ps(move_length, _mm512_set1_ps(static_cast<float>(c.substeps)));
  const __m512i mark_base = _mm512_mullo_epi32(species, _mm512_set1_epi32(static_cast<int>(plane_texels)));
  Walk w{tri, b0, b1, b2, hx, hy, inv_a, bx, inv_by};
  __mmask16 moved = 0;  // lanes now on another triangle
  for (uint32_t k = 0; k < c.substeps; ++k) {
    const __m512 db2 = _mm512_mul_ps(w.hy, w.inv_by);
    const __m512 db1 = _mm512_mul_ps(_mm512_sub_ps(w.hx, _mm512_mul_ps(w.bx, db2)), w.inv_a);
    const __m512 db0 = negated(_mm512_add_ps(db1, db2));
    __mmask16 across = 0;
    if (near) {
      // mtx_walk_inside's test.
      const __mmask16 clear = clear_of_edge(w.b0, db0, sub_length) & clear_of_edge(w.b1, db1, sub_length) &
                              clear_of_edge(w.b2, db2, sub_length);
      across = near & static_cast<__mmask16>(~clear) &
               (meets_edge(w.b0, db0, sub_length) | meets_edge(w.b1, db1, sub_length) |
                meets_edge(w.b2, db2, sub_length));
    }
    const __mmask16 within = inside & static_cast<__mmask16>(~across);
    __m512 n0 = _mm512_add_ps(w.b0, _mm512_mul_ps(sub_length, db0));
    __m512 n1 = _mm512_add_ps(w.b1, _mm512_mul_ps(sub_length, db1));
    __m512 n2 = _mm512_add_ps(w.b2, _mm512_mul_ps(sub_length, db2));
    clamp_bary(n0, n1, n2);
    w.b0 = _mm512_mask_mov_ps(w.b0, within, n0);
    w.b1 = _mm512_mask_mov_ps(w.b1, within, n1);
    w.b2 = _mm512_mask_mov_ps(w.b2, within, n2);
    if (across) {
      const __mmask16 walked = walk_across(s, w, across, sub_length);
      inside &= static_cast<__mmask16>(~(across & ~walked));
      near &= inside;
      moved |= walked & _mm512_cmpneq_epi32_mask(w.t, tri);
      if (!inside) return 0;
      const __mmask16 fresh = walked & moved;  // their UVs are the new triangle's
      if (fresh) gather_uvs(s.corner_uvs, w.t, fresh, uv);
    }
    __m512 mx, my;
    point_in_texels(w.b0, w.b1, w.b2, uv, tx, mx, my);
    const __m512i texel = texel_at(mx, my, tx.last_x, tx.last_y, tx.row);
    if (c.surface_mode) {
      mark_footprints(s, c, field, marks, inside, species, w.t, texel, mx, my);
      continue;
    }
    mark_lanes(marks, _mm512_add_epi32(mark_base, texel), inside);
  }
  if (moved) _mm512_mask_storeu_epi32(agents.triangle.data() + i, moved & inside, w.t);
  _mm512_mask_storeu_ps(agents.b1.data() + i, inside, w.b1);
  _mm512_mask_storeu_ps(agents.b2.data() + i, inside, w.b2);
  _mm512_mask_storeu_ps(agents.hx.data() + i, inside, w.hx);
  _mm512_mask_storeu_ps(agents.hy.data() + i, inside, w.hy);
  return inside;
}

}  // namespace

__attribute__((target("avx512f,avx512dq,avx512bw,bmi2"))) size_t momas_lanes16(const mtx_surface_tables& s,
                                                                const mtx_momas_constants& c, const float* pheromone,
                                                                const float* field, uint8_t* marks, Agents& agents,
                                                                size_t begin, size_t end) {
  Leftovers rest{s, c, pheromone, field, marks, agents, {}, 0, 0};
  size_t i = begin;
  for (; i + 16 <= end; i += 16) rest.take(i, step16(s, c, pheromone, field, marks, agents, i), 0xffffu);
  return rest.finish(i, end);
}

}  // namespace moldtex

#endif
