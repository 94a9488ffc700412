#include "surface/trace_lanes.h"

#include <atomic>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MOLDTEX_TRACE_LANES_X86 1
#endif

namespace moldtex {

namespace {

std::atomic<bool> g_force_scalar{false};

void hops_scalar(const uint32_t* adjacency, const float* unfolded, TraceLanes& lanes, size_t begin, size_t end,
                 uint8_t* located) {
  for (size_t i = begin; i < end; ++i) {
    float s[3] = {lanes.s[0][i], lanes.s[1][i], lanes.s[2][i]};
    float e[3] = {lanes.e[0][i], lanes.e[1][i], lanes.e[2][i]};
    uint32_t t = lanes.triangle[i];
    located[i] = static_cast<uint8_t>(mtx_trace_hops(adjacency, unfolded, &t, s, e));
    lanes.triangle[i] = t;
    for (int k = 0; k < 3; ++k) lanes.e[k][i] = e[k];
  }
}

#ifdef MOLDTEX_TRACE_LANES_X86

// mtx_trace_hops on all the traces, sixteen lanes at a time (AVX-512F). Every step below
// is one of mtx_trace_hops' with a mask for the lanes it applies to: `live` lanes hold a
// trace still crossing; a trace leaves its lane located (its end inside its triangle)
// or to be walked, at the same crossing and for the same reason as there, and the next
// trace takes the lane, so lanes do not idle while the longest trace of sixteen runs.
__attribute__((target("avx512f"))) void hops_in_lanes(const uint32_t* adjacency, const float* unfolded,
                                                      TraceLanes& lanes, uint8_t* located) {
  const size_t count = lanes.count;
  alignas(64) int32_t found[kTraceLanes] = {};
  const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f);
  const __m512i i0 = _mm512_setzero_si512(), i1 = _mm512_set1_epi32(1), i2 = _mm512_set1_epi32(2);
  const __m512i none = _mm512_set1_epi32(static_cast<int>(MTX_NO_NEIGHBOUR));
  const __m512i limit = _mm512_set1_epi32(MTX_UNFOLDED_HOPS);
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  __m512i t = i0, id = i0, hop = i0;
  __m512 s0 = zero, s1 = zero, s2 = zero, e0 = zero, e1 = zero, e2 = zero;
  __mmask16 live = 0;
  size_t next = 0;
  for (;;) {
    // Free lanes take the next traces.
    if (next < count && live != 0xffff) {
      unsigned free = static_cast<uint16_t>(~live), fill = free;
      const unsigned want = static_cast<unsigned>(count - next);
      unsigned taken = static_cast<unsigned>(__builtin_popcount(free));
      if (want < taken) {
        fill = 0;
        for (unsigned k = 0; k < want; ++k) {
          fill |= free & (0u - free);
          free &= free - 1u;
        }
        taken = want;
      }
      const __mmask16 m = static_cast<__mmask16>(fill);
      t = _mm512_mask_expandloadu_epi32(t, m, lanes.triangle + next);
      s0 = _mm512_mask_expandloadu_ps(s0, m, lanes.s[0] + next);
      s1 = _mm512_mask_expandloadu_ps(s1, m, lanes.s[1] + next);
      s2 = _mm512_mask_expandloadu_ps(s2, m, lanes.s[2] + next);
      e0 = _mm512_mask_expandloadu_ps(e0, m, lanes.e[0] + next);
      e1 = _mm512_mask_expandloadu_ps(e1, m, lanes.e[1] + next);
      e2 = _mm512_mask_expandloadu_ps(e2, m, lanes.e[2] + next);
      id = _mm512_mask_expand_epi32(id, m, _mm512_add_epi32(iota, _mm512_set1_epi32(static_cast<int>(next))));
      hop = _mm512_mask_mov_epi32(hop, m, i0);
      live |= m;
      next += taken;
    }
    if (!live) break;
    const __mmask16 n0 = _mm512_mask_cmp_ps_mask(live, e0, zero, _CMP_LT_OQ);
    const __mmask16 n1 = _mm512_mask_cmp_ps_mask(live, e1, zero, _CMP_LT_OQ);
    const __mmask16 n2 = _mm512_mask_cmp_ps_mask(live, e2, zero, _CMP_LT_OQ);
    const __mmask16 out = n0 | n1 | n2;
    const __mmask16 done = live & ~out;  // inside its triangle: located
    if (done) {
      _mm512_mask_i32scatter_epi32(lanes.triangle, done, id, t, 4);
      _mm512_mask_i32scatter_ps(lanes.e[0], done, id, e0, 4);
      _mm512_mask_i32scatter_ps(lanes.e[1], done, id, e1, 4);
      _mm512_mask_i32scatter_ps(lanes.e[2], done, id, e2, 4);
      _mm512_mask_i32scatter_epi32(found, done, id, i1, 4);
    }
    // Past MTX_UNFOLDED_HOPS crossings: walked.
    live = out & ~_mm512_mask_cmpeq_epi32_mask(out, hop, limit);
    if (!live) continue;
    // The edge: the first beyond; of two or three, the one met sooner.
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
      live &= ~behind;
    }
    // The start on the inner side of that edge.
    const __mmask16 is0 = _mm512_cmpeq_epi32_mask(edge, i0), is1 = _mm512_cmpeq_epi32_mask(edge, i1);
    const __m512 s_edge = _mm512_mask_blend_ps(is0, _mm512_mask_blend_ps(is1, s2, s1), s0);
    live &= ~_mm512_mask_cmp_ps_mask(live, s_edge, zero, _CMP_LT_OQ);
    // The neighbour there, unless the edge is open.
    const __m512i slot = _mm512_add_epi32(_mm512_add_epi32(_mm512_add_epi32(t, t), t), edge);
    const __m512i code = _mm512_mask_i32gather_epi32(none, live, slot, adjacency, 4);
    live &= ~_mm512_mask_cmpeq_epi32_mask(live, code, none);
    if (!live) continue;
    // Both points carried into the neighbour: (g0 + g1 b1) + g2 b2, as the scalar code.
    const __m512i slot3 = _mm512_add_epi32(_mm512_add_epi32(slot, slot), slot);
    const __m512i at = _mm512_add_epi32(slot3, slot3);  // slot * MTX_UNFOLDED_FLOATS
    const __m512 g0 = _mm512_mask_i32gather_ps(zero, live, at, unfolded, 4);
    const __m512 g1 = _mm512_mask_i32gather_ps(zero, live, _mm512_add_epi32(at, i1), unfolded, 4);
    const __m512 g2 = _mm512_mask_i32gather_ps(zero, live, _mm512_add_epi32(at, i2), unfolded, 4);
    const __m512 g3 = _mm512_mask_i32gather_ps(zero, live, _mm512_add_epi32(at, _mm512_set1_epi32(3)), unfolded, 4);
    const __m512 g4 = _mm512_mask_i32gather_ps(zero, live, _mm512_add_epi32(at, _mm512_set1_epi32(4)), unfolded, 4);
    const __m512 g5 = _mm512_mask_i32gather_ps(zero, live, _mm512_add_epi32(at, _mm512_set1_epi32(5)), unfolded, 4);
    const __m512 s1n = _mm512_add_ps(_mm512_add_ps(g0, _mm512_mul_ps(g1, s1)), _mm512_mul_ps(g2, s2));
    const __m512 s2n = _mm512_add_ps(_mm512_add_ps(g3, _mm512_mul_ps(g4, s1)), _mm512_mul_ps(g5, s2));
    const __m512 e1n = _mm512_add_ps(_mm512_add_ps(g0, _mm512_mul_ps(g1, e1)), _mm512_mul_ps(g2, e2));
    const __m512 e2n = _mm512_add_ps(_mm512_add_ps(g3, _mm512_mul_ps(g4, e1)), _mm512_mul_ps(g5, e2));
    s1 = _mm512_mask_mov_ps(s1, live, s1n);
    s2 = _mm512_mask_mov_ps(s2, live, s2n);
    s0 = _mm512_mask_mov_ps(s0, live, _mm512_sub_ps(_mm512_sub_ps(one, s1n), s2n));
    e1 = _mm512_mask_mov_ps(e1, live, e1n);
    e2 = _mm512_mask_mov_ps(e2, live, e2n);
    e0 = _mm512_mask_mov_ps(e0, live, _mm512_sub_ps(_mm512_sub_ps(one, e1n), e2n));
    t = _mm512_mask_mov_epi32(t, live, _mm512_maskz_srli_epi32(__mmask16(0xffff), code, 3));
    hop = _mm512_mask_add_epi32(hop, live, hop, i1);
  }
  for (size_t i = 0; i < count; ++i) located[i] = static_cast<uint8_t>(found[i]);
}

static_assert(MTX_UNFOLDED_FLOATS == 6, "hops16 computes slot * 6");

bool detect_avx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
}

#endif

}  // namespace

bool trace_lanes_available() {
#ifdef MOLDTEX_TRACE_LANES_X86
  static const bool available = detect_avx512();
  return available;
#else
  return false;
#endif
}

void trace_lanes_force_scalar(bool scalar) { g_force_scalar.store(scalar, std::memory_order_relaxed); }

void trace_hops_lanes(const uint32_t* adjacency, const float* unfolded, uint32_t triangle_count, TraceLanes& lanes,
                      uint8_t* located) {
#ifdef MOLDTEX_TRACE_LANES_X86
  // (Offsets up to 3 * triangle_count * MTX_UNFOLDED_FLOATS floats in a signed 32-bit index.)
  const bool fits = uint64_t(triangle_count) * 3u * MTX_UNFOLDED_FLOATS < (uint64_t(1) << 31);
  if (fits && trace_lanes_available() && !g_force_scalar.load(std::memory_order_relaxed)) {
    hops_in_lanes(adjacency, unfolded, lanes, located);
    return;
  }
#endif
  hops_scalar(adjacency, unfolded, lanes, 0, lanes.count, located);
}

}  // namespace moldtex
