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

// Sixteen lanes of traces in flight (AVX-512F): each lane's trace (its number `id`), its
// triangle, start and end weights and crossings so far; `live`: the lanes that hold one.
struct LaneGroup {
  __m512i t, id, hop;
  __m512 s0, s1, s2, e0, e1, e2;
  __mmask16 live;
};

#define MOLDTEX_LANES_FN __attribute__((target("avx512f"), always_inline)) inline

// Free lanes of g take the next traces of `lanes` (from *next on).
MOLDTEX_LANES_FN void refill(LaneGroup& g, const TraceLanes& lanes, size_t& next) {
  if (next >= lanes.count || g.live == 0xffff) return;
  unsigned free = static_cast<uint16_t>(~g.live), fill = free;
  const unsigned want = static_cast<unsigned>(lanes.count - next);
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
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  g.t = _mm512_mask_expandloadu_epi32(g.t, m, lanes.triangle + next);
  g.s0 = _mm512_mask_expandloadu_ps(g.s0, m, lanes.s[0] + next);
  g.s1 = _mm512_mask_expandloadu_ps(g.s1, m, lanes.s[1] + next);
  g.s2 = _mm512_mask_expandloadu_ps(g.s2, m, lanes.s[2] + next);
  g.e0 = _mm512_mask_expandloadu_ps(g.e0, m, lanes.e[0] + next);
  g.e1 = _mm512_mask_expandloadu_ps(g.e1, m, lanes.e[1] + next);
  g.e2 = _mm512_mask_expandloadu_ps(g.e2, m, lanes.e[2] + next);
  g.id = _mm512_mask_expand_epi32(g.id, m, _mm512_add_epi32(iota, _mm512_set1_epi32(static_cast<int>(next))));
  g.hop = _mm512_mask_mov_epi32(g.hop, m, _mm512_setzero_si512());
  g.live |= m;
  next += taken;
}

// One crossing of every live lane of g: mtx_trace_hops' loop body, each step with a mask
// for the lanes it applies to. A trace leaves its lane located (its end inside its
// triangle: written to `lanes` and `found`) or to be walked, at the same crossing and for
// the same reason as there.
MOLDTEX_LANES_FN void cross(LaneGroup& g, const uint32_t* adjacency, const float* unfolded, TraceLanes& lanes,
                            int32_t* found) {
  const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f);
  const __m512i i0 = _mm512_setzero_si512(), i1 = _mm512_set1_epi32(1), i2 = _mm512_set1_epi32(2);
  const __m512i none = _mm512_set1_epi32(static_cast<int>(MTX_NO_NEIGHBOUR));
  __mmask16 live = g.live;
  const __mmask16 n0 = _mm512_mask_cmp_ps_mask(live, g.e0, zero, _CMP_LT_OQ);
  const __mmask16 n1 = _mm512_mask_cmp_ps_mask(live, g.e1, zero, _CMP_LT_OQ);
  const __mmask16 n2 = _mm512_mask_cmp_ps_mask(live, g.e2, zero, _CMP_LT_OQ);
  const __mmask16 out = n0 | n1 | n2;
  const __mmask16 done = live & ~out;  // inside its triangle: located
  if (done) {
    _mm512_mask_i32scatter_epi32(lanes.triangle, done, g.id, g.t, 4);
    _mm512_mask_i32scatter_ps(lanes.e[0], done, g.id, g.e0, 4);
    _mm512_mask_i32scatter_ps(lanes.e[1], done, g.id, g.e1, 4);
    _mm512_mask_i32scatter_ps(lanes.e[2], done, g.id, g.e2, 4);
    _mm512_mask_i32scatter_epi32(found, done, g.id, i1, 4);
  }
  // Past MTX_UNFOLDED_HOPS crossings: walked.
  live = out & ~_mm512_mask_cmpeq_epi32_mask(out, g.hop, _mm512_set1_epi32(MTX_UNFOLDED_HOPS));
  g.live = live;
  if (!live) return;
  // The edge: the first beyond; of two or three, the one met sooner.
  __m512i edge = _mm512_mask_mov_epi32(_mm512_mask_mov_epi32(i2, n1, i1), n0, i0);
  const __mmask16 multi = live & ((n0 & n1) | (n0 & n2) | (n1 & n2));
  if (multi) {
    const __m512 si = _mm512_mask_blend_ps(n0, g.s1, g.s0), ei = _mm512_mask_blend_ps(n0, g.e1, g.e0);
    const __m512 sj = _mm512_mask_blend_ps(n2, g.s1, g.s2), ej = _mm512_mask_blend_ps(n2, g.e1, g.e2);
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
  const __m512 s_edge = _mm512_mask_blend_ps(is0, _mm512_mask_blend_ps(is1, g.s2, g.s1), g.s0);
  live &= ~_mm512_mask_cmp_ps_mask(live, s_edge, zero, _CMP_LT_OQ);
  // The neighbour there, unless the edge is open.
  const __m512i slot = _mm512_add_epi32(_mm512_add_epi32(_mm512_add_epi32(g.t, g.t), g.t), edge);
  const __m512i code = _mm512_mask_i32gather_epi32(none, live, slot, adjacency, 4);
  live &= ~_mm512_mask_cmpeq_epi32_mask(live, code, none);
  g.live = live;
  if (!live) return;
  // The unfolding there, its six floats as three pairs: each pair one 64-bit gather per
  // eight lanes (half the loads of a gather per float), split into its two floats.
  const __m512i slot3 = _mm512_add_epi32(_mm512_add_epi32(slot, slot), slot);  // pairs: slot * 3
  const __m256i low = _mm512_maskz_extracti64x4_epi64(__mmask8(0xff), slot3, 0), high = _mm512_maskz_extracti64x4_epi64(__mmask8(0xff), slot3, 1);
  const __mmask8 live_low = static_cast<__mmask8>(live), live_high = static_cast<__mmask8>(live >> 8);
  const __m512i first = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i second = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
  __m512 u[6];
  for (int k = 0; k < 3; ++k) {
    const __m256i add = _mm256_set1_epi32(k);
    const __m512 a = _mm512_castsi512_ps(
        _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), live_low, _mm256_add_epi32(low, add), unfolded, 8));
    const __m512 b = _mm512_castsi512_ps(
        _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), live_high, _mm256_add_epi32(high, add), unfolded, 8));
    u[2 * k] = _mm512_permutex2var_ps(a, first, b);
    u[2 * k + 1] = _mm512_permutex2var_ps(a, second, b);
  }
  const __m512 g0 = u[0], g1 = u[1], g2 = u[2], g3 = u[3], g4 = u[4], g5 = u[5];
  const __m512 s1n = _mm512_add_ps(_mm512_add_ps(g0, _mm512_mul_ps(g1, g.s1)), _mm512_mul_ps(g2, g.s2));
  const __m512 s2n = _mm512_add_ps(_mm512_add_ps(g3, _mm512_mul_ps(g4, g.s1)), _mm512_mul_ps(g5, g.s2));
  const __m512 e1n = _mm512_add_ps(_mm512_add_ps(g0, _mm512_mul_ps(g1, g.e1)), _mm512_mul_ps(g2, g.e2));
  const __m512 e2n = _mm512_add_ps(_mm512_add_ps(g3, _mm512_mul_ps(g4, g.e1)), _mm512_mul_ps(g5, g.e2));
  g.s1 = _mm512_mask_mov_ps(g.s1, live, s1n);
  g.s2 = _mm512_mask_mov_ps(g.s2, live, s2n);
  g.s0 = _mm512_mask_mov_ps(g.s0, live, _mm512_sub_ps(_mm512_sub_ps(one, s1n), s2n));
  g.e1 = _mm512_mask_mov_ps(g.e1, live, e1n);
  g.e2 = _mm512_mask_mov_ps(g.e2, live, e2n);
  g.e0 = _mm512_mask_mov_ps(g.e0, live, _mm512_sub_ps(_mm512_sub_ps(one, e1n), e2n));
  g.t = _mm512_mask_mov_epi32(g.t, live, _mm512_maskz_srli_epi32(__mmask16(0xffff), code, 3));
  g.hop = _mm512_mask_add_epi32(g.hop, live, g.hop, i1);
}

// mtx_trace_hops on all the traces of `lanes`, in two groups of sixteen lanes: each
// crossing waits on its gathers (the neighbour, then its unfolding), so two independent
// groups let one's loads overlap the other's; a lane whose trace ends takes the next
// trace, so lanes do not idle while the longest trace of sixteen runs.
__attribute__((target("avx512f"))) void hops_in_lanes(const uint32_t* adjacency, const float* unfolded,
                                                      TraceLanes& lanes, uint8_t* located) {
  alignas(64) int32_t found[kTraceLanes] = {};
  LaneGroup a{}, b{};
  size_t next = 0;
  for (;;) {
    refill(a, lanes, next);
    refill(b, lanes, next);
    if (!(a.live | b.live)) break;
    cross(a, adjacency, unfolded, lanes, found);
    cross(b, adjacency, unfolded, lanes, found);
  }
  for (size_t i = 0; i < lanes.count; ++i) located[i] = static_cast<uint8_t>(found[i]);
}

static_assert(MTX_UNFOLDED_FLOATS == 6, "cross() reads an unfolding as three pairs at slot * 3");

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
