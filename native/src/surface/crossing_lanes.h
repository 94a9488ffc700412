// One crossing of shared/walk.h's mtx_trace_hops in sixteen AVX-512 lanes: which edge each
// trace leaves its triangle by, the neighbour and unfolding read there, and the trace
// carried across. Shared by the continuous model's trace lanes
// (surface/trace_lanes.cpp) and MoMaS' step in lanes (agents/momas_lanes.cpp), which must
// both choose as mtx_trace_hops does, bit for bit.
#pragma once

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#include "shared/walk.h"

namespace moldtex {

#define MOLDTEX_CROSSING_LANES_FN __attribute__((target("avx512f"), always_inline)) inline

// The edge each lane of `live` leaves by, given its start and end weights (s*, e*) and
// which ends lie beyond which edges (n0, n1, n2; at least one per live lane): the first
// beyond; of two or three, the one met sooner (tau = s / (s - e), compared without
// dividing). Clears from `live` the lanes mtx_trace_hops gives up on there: a start
// behind one of two edges compared, or behind the edge chosen (within rounding of a
// corner; the walk resolves those).
MOLDTEX_CROSSING_LANES_FN __m512i exit_edge(__m512 s0, __m512 s1, __m512 s2, __m512 e0, __m512 e1, __m512 e2,
                                            __mmask16 n0, __mmask16 n1, __mmask16 n2, __mmask16& live) {
  const __m512 zero = _mm512_setzero_ps();
  const __m512i i0 = _mm512_setzero_si512(), i1 = _mm512_set1_epi32(1), i2 = _mm512_set1_epi32(2);
  __m512i edge = _mm512_mask_mov_epi32(_mm512_mask_mov_epi32(i2, n1, i1), n0, i0);
  const __mmask16 multi = live & ((n0 & n1) | (n0 & n2) | (n1 & n2));
  if (multi) {
    const __m512 si = _mm512_mask_blend_ps(n0, s1, s0), ei = _mm512_mask_blend_ps(n0, e1, e0);
    const __m512 sj = _mm512_mask_blend_ps(n2, s1, s2), ej = _mm512_mask_blend_ps(n2, e1, e2);
    const __mmask16 behind = _mm512_mask_cmp_ps_mask(multi, si, zero, _CMP_LT_OQ) |
                             _mm512_mask_cmp_ps_mask(multi, sj, zero, _CMP_LT_OQ);
    const __m512 lhs = _mm512_mul_ps(sj, _mm512_sub_ps(si, ei));
    const __m512 rhs = _mm512_mul_ps(si, _mm512_sub_ps(sj, ej));
    const __mmask16 later = _mm512_mask_cmp_ps_mask(multi & ~behind, lhs, rhs, _CMP_LT_OQ);
    edge = _mm512_mask_mov_epi32(edge, later, _mm512_mask_mov_epi32(i1, n2, i2));
    live &= static_cast<__mmask16>(~behind);
  }
  // The start on the inner side of that edge.
  const __mmask16 is0 = _mm512_cmpeq_epi32_mask(edge, i0), is1 = _mm512_cmpeq_epi32_mask(edge, i1);
  const __m512 s_edge = _mm512_mask_blend_ps(is0, _mm512_mask_blend_ps(is1, s2, s1), s0);
  live &= static_cast<__mmask16>(~_mm512_mask_cmp_ps_mask(live, s_edge, zero, _CMP_LT_OQ));
  return edge;
}

// Two neighbouring floats of a table per lane, table[index] and table[index + 1], for the
// lanes `live` (zero elsewhere): one 64-bit gather per eight lanes, half the loads of a
// gather per float, split into its two floats.
MOLDTEX_CROSSING_LANES_FN void gather_pairs(const float* table, __m512i index, __mmask16 live, __m512& first,
                                            __m512& second) {
  const __m256i low = _mm512_maskz_extracti64x4_epi64(__mmask8(0xff), index, 0);
  const __m256i high = _mm512_maskz_extracti64x4_epi64(__mmask8(0xff), index, 1);  // (maskz: GCC 12 warns on the others)
  const __m512 a = _mm512_castsi512_ps(
      _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), static_cast<__mmask8>(live), low, table, 4));
  const __m512 b = _mm512_castsi512_ps(
      _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), static_cast<__mmask8>(live >> 8), high, table, 4));
  first = _mm512_permutex2var_ps(a, _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30), b);
  second = _mm512_permutex2var_ps(a, _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31), b);
}

// table[6 i .. 6 i + 5], then codes[i] twice (zeros without codes), in the low half.
MOLDTEX_CROSSING_LANES_FN __m512 six_and_code(const float* table, const uint32_t* codes, size_t i) {
  const __m512 fill = codes ? _mm512_castsi512_ps(_mm512_set1_epi32(static_cast<int>(codes[i]))) : _mm512_setzero_ps();
  return _mm512_mask_loadu_ps(fill, __mmask16(0x3f), table + 6 * i);
}

// Six floats per lane, table[6 index .. 6 index + 5], as six vectors (rows[k]: float k
// of every lane), and codes[index] per lane as a seventh (its bits). Read row by row (a
// masked load of the six floats over the code broadcast, per lane) and transposed in
// registers: on some processors a gather costs about as much for one lane as for
// sixteen (AMD Zen 4: about 6 ns for sixteen floats, 3 ns for eight pairs), where the
// sixteen rows and their transpose take about half the seven gathers' time. Every lane
// reads (an index of a valid row is needed in each); the values are those a gather reads.
MOLDTEX_CROSSING_LANES_FN void load_sixes(const float* table, const uint32_t* codes, __m512i index, __m512* rows,
                                          __m512i* code) {
  alignas(64) uint32_t at[16];
  _mm512_store_si512(at, index);
  __m512 r[8];
  for (unsigned j = 0; j < 8; ++j)
    r[j] = _mm512_maskz_shuffle_f32x4(__mmask16(0xffff), six_and_code(table, codes, at[j]),
                                      six_and_code(table, codes, at[j + 8]), 0x44);
  // An 8 x 8 transpose in each 256-bit half: lanes 0-7 in the low halves, 8-15 in the high
  // (the maskz forms: GCC 12 warns on the others).
  __m512 t[8], u[8];
  for (int j = 0; j < 4; ++j) {
    t[2 * j] = _mm512_maskz_unpacklo_ps(__mmask16(0xffff), r[2 * j], r[2 * j + 1]);
    t[2 * j + 1] = _mm512_maskz_unpackhi_ps(__mmask16(0xffff), r[2 * j], r[2 * j + 1]);
  }
  for (int h = 0; h < 2; ++h) {
    u[4 * h + 0] = _mm512_shuffle_ps(t[4 * h + 0], t[4 * h + 2], 0x44);
    u[4 * h + 1] = _mm512_shuffle_ps(t[4 * h + 0], t[4 * h + 2], 0xee);
    u[4 * h + 2] = _mm512_shuffle_ps(t[4 * h + 1], t[4 * h + 3], 0x44);
    u[4 * h + 3] = _mm512_shuffle_ps(t[4 * h + 1], t[4 * h + 3], 0xee);
  }
  const __m512i low = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
  const __m512i high = _mm512_setr_epi32(4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
  for (int k = 0; k < 4; ++k) {
    rows[k] = _mm512_permutex2var_ps(u[k], low, u[k + 4]);
    if (k < 2) rows[k + 4] = _mm512_permutex2var_ps(u[k], high, u[k + 4]);
  }
  if (code) *code = _mm512_castps_si512(_mm512_permutex2var_ps(u[2], high, u[6]));
}

// Start and end weights (s*, e*) of the lanes `live` carried across an edge into the
// neighbour, in its own weights (mtx_trace_hops' step), given the edge's unfolding u
// (its six floats, load_sixes).
MOLDTEX_CROSSING_LANES_FN void carry_unfolded(const __m512* u, __mmask16 live, __m512& s0, __m512& s1, __m512& s2,
                                              __m512& e0, __m512& e1, __m512& e2) {
  const __m512 one = _mm512_set1_ps(1.0f);
  const __m512 s1n = _mm512_add_ps(_mm512_add_ps(u[0], _mm512_mul_ps(u[1], s1)), _mm512_mul_ps(u[2], s2));
  const __m512 s2n = _mm512_add_ps(_mm512_add_ps(u[3], _mm512_mul_ps(u[4], s1)), _mm512_mul_ps(u[5], s2));
  const __m512 e1n = _mm512_add_ps(_mm512_add_ps(u[0], _mm512_mul_ps(u[1], e1)), _mm512_mul_ps(u[2], e2));
  const __m512 e2n = _mm512_add_ps(_mm512_add_ps(u[3], _mm512_mul_ps(u[4], e1)), _mm512_mul_ps(u[5], e2));
  s1 = _mm512_mask_mov_ps(s1, live, s1n);
  s2 = _mm512_mask_mov_ps(s2, live, s2n);
  s0 = _mm512_mask_mov_ps(s0, live, _mm512_sub_ps(_mm512_sub_ps(one, s1n), s2n));
  e1 = _mm512_mask_mov_ps(e1, live, e1n);
  e2 = _mm512_mask_mov_ps(e2, live, e2n);
  e0 = _mm512_mask_mov_ps(e0, live, _mm512_sub_ps(_mm512_sub_ps(one, e1n), e2n));
}

// The same two steps in eight AVX2 lanes (masks as vectors, all ones where set).
#define MOLDTEX_CROSSING_LANES8_FN __attribute__((target("avx2"), always_inline)) inline

MOLDTEX_CROSSING_LANES8_FN __m256i exit_edge8(__m256 s0, __m256 s1, __m256 s2, __m256 e0, __m256 e1, __m256 e2,
                                              __m256i n0, __m256i n1, __m256i n2, __m256i& live) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256i i0 = _mm256_setzero_si256(), i1 = _mm256_set1_epi32(1), i2 = _mm256_set1_epi32(2);
  __m256i edge = _mm256_blendv_epi8(_mm256_blendv_epi8(i2, i1, n1), i0, n0);
  const __m256i multi = _mm256_and_si256(
      live, _mm256_or_si256(_mm256_or_si256(_mm256_and_si256(n0, n1), _mm256_and_si256(n0, n2)), _mm256_and_si256(n1, n2)));
  if (!_mm256_testz_si256(multi, multi)) {
    const __m256 m0 = _mm256_castsi256_ps(n0), m2 = _mm256_castsi256_ps(n2);
    const __m256 si = _mm256_blendv_ps(s1, s0, m0), ei = _mm256_blendv_ps(e1, e0, m0);
    const __m256 sj = _mm256_blendv_ps(s1, s2, m2), ej = _mm256_blendv_ps(e1, e2, m2);
    const __m256i behind = _mm256_and_si256(
        multi, _mm256_castps_si256(_mm256_or_ps(_mm256_cmp_ps(si, zero, _CMP_LT_OQ), _mm256_cmp_ps(sj, zero, _CMP_LT_OQ))));
    const __m256 lhs = _mm256_mul_ps(sj, _mm256_sub_ps(si, ei));
    const __m256 rhs = _mm256_mul_ps(si, _mm256_sub_ps(sj, ej));
    const __m256i later = _mm256_andnot_si256(behind, _mm256_and_si256(multi, _mm256_castps_si256(_mm256_cmp_ps(lhs, rhs, _CMP_LT_OQ))));
    edge = _mm256_blendv_epi8(edge, _mm256_blendv_epi8(i1, i2, n2), later);
    live = _mm256_andnot_si256(behind, live);
  }
  const __m256 is0 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(edge, i0)), is1 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(edge, i1));
  const __m256 s_edge = _mm256_blendv_ps(_mm256_blendv_ps(s2, s1, is1), s0, is0);
  live = _mm256_andnot_si256(_mm256_castps_si256(_mm256_cmp_ps(s_edge, zero, _CMP_LT_OQ)), live);
  return edge;
}

// load_sixes in eight lanes: table[6 index .. 6 index + 5] per lane as six vectors, and
// codes[index] (its bits) as a seventh; eight row loads and an 8 x 8 transpose instead of
// seven gathers. Every lane reads (each needs the index of a valid row).
MOLDTEX_CROSSING_LANES8_FN void load_sixes8(const float* table, const uint32_t* codes, __m256i index, __m256* rows,
                                            __m256i* code) {
  alignas(32) uint32_t at[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(at), index);
  const __m256i six = _mm256_setr_epi32(-1, -1, -1, -1, -1, -1, 0, 0);
  __m256 r[8];
  for (int j = 0; j < 8; ++j) {
    const size_t i = at[j];
    const __m256 row = _mm256_maskload_ps(table + 6 * i, six);  // (no fault past the six)
    r[j] = codes ? _mm256_blend_ps(row, _mm256_castsi256_ps(_mm256_set1_epi32(static_cast<int>(codes[i]))), 0xc0) : row;
  }
  __m256 t[8], u[8];
  for (int j = 0; j < 4; ++j) {
    t[2 * j] = _mm256_unpacklo_ps(r[2 * j], r[2 * j + 1]);
    t[2 * j + 1] = _mm256_unpackhi_ps(r[2 * j], r[2 * j + 1]);
  }
  for (int h = 0; h < 2; ++h) {
    u[4 * h + 0] = _mm256_shuffle_ps(t[4 * h + 0], t[4 * h + 2], 0x44);
    u[4 * h + 1] = _mm256_shuffle_ps(t[4 * h + 0], t[4 * h + 2], 0xee);
    u[4 * h + 2] = _mm256_shuffle_ps(t[4 * h + 1], t[4 * h + 3], 0x44);
    u[4 * h + 3] = _mm256_shuffle_ps(t[4 * h + 1], t[4 * h + 3], 0xee);
  }
  for (int k = 0; k < 4; ++k) {
    rows[k] = _mm256_permute2f128_ps(u[k], u[k + 4], 0x20);
    if (k < 2) rows[k + 4] = _mm256_permute2f128_ps(u[k], u[k + 4], 0x31);
  }
  if (code) *code = _mm256_castps_si256(_mm256_permute2f128_ps(u[2], u[6], 0x31));
}

// carry_unfolded in eight lanes (live: all ones where set).
MOLDTEX_CROSSING_LANES8_FN void carry_unfolded8(const __m256* u, __m256i live, __m256& s0, __m256& s1, __m256& s2,
                                                __m256& e0, __m256& e1, __m256& e2) {
  const __m256 one = _mm256_set1_ps(1.0f);
  const __m256 g0 = u[0], g1 = u[1], g2 = u[2], g3 = u[3], g4 = u[4], g5 = u[5];
  const __m256 s1n = _mm256_add_ps(_mm256_add_ps(g0, _mm256_mul_ps(g1, s1)), _mm256_mul_ps(g2, s2));
  const __m256 s2n = _mm256_add_ps(_mm256_add_ps(g3, _mm256_mul_ps(g4, s1)), _mm256_mul_ps(g5, s2));
  const __m256 e1n = _mm256_add_ps(_mm256_add_ps(g0, _mm256_mul_ps(g1, e1)), _mm256_mul_ps(g2, e2));
  const __m256 e2n = _mm256_add_ps(_mm256_add_ps(g3, _mm256_mul_ps(g4, e1)), _mm256_mul_ps(g5, e2));
  const __m256 lv = _mm256_castsi256_ps(live);
  s1 = _mm256_blendv_ps(s1, s1n, lv);
  s2 = _mm256_blendv_ps(s2, s2n, lv);
  s0 = _mm256_blendv_ps(s0, _mm256_sub_ps(_mm256_sub_ps(one, s1n), s2n), lv);
  e1 = _mm256_blendv_ps(e1, e1n, lv);
  e2 = _mm256_blendv_ps(e2, e2n, lv);
  e0 = _mm256_blendv_ps(e0, _mm256_sub_ps(_mm256_sub_ps(one, e1n), e2n), lv);
}

}  // namespace moldtex

#endif
