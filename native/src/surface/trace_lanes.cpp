#include "surface/trace_lanes.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>

#include "surface/crossing_lanes.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MOLDTEX_TRACE_LANES_X86 1
#endif

namespace moldtex {

namespace {

// The cap on the lanes: 16, or what MOLDTEX_TRACE_LANES says (1, 8: benchmarks compare
// the kinds on one processor; the results are the same bits).
unsigned initial_limit() {
  const char* text = std::getenv("MOLDTEX_TRACE_LANES");
  if (!text || !*text) return 16u;
  const long value = std::strtol(text, nullptr, 10);
  return value >= 16 ? 16u : (value >= 8 ? 8u : 1u);
}

std::atomic<unsigned> g_limit{initial_limit()};

void hops_scalar(const uint32_t* adjacency, const float* unfolded, TraceLanes& lanes, uint8_t* located) {
  for (size_t i = 0; i < lanes.count; ++i) {
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
  const __m512 zero = _mm512_setzero_ps();
  const __m512i i1 = _mm512_set1_epi32(1);
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
  const __m512i edge = exit_edge(g.s0, g.s1, g.s2, g.e0, g.e1, g.e2, n0, n1, n2, live);
  // The neighbour there, unless the edge is open.
  // (load_sixes reads every lane: the others read slot 0.)
  const __m512i slot = _mm512_maskz_mov_epi32(live, _mm512_add_epi32(_mm512_add_epi32(_mm512_add_epi32(g.t, g.t), g.t), edge));
  __m512 u[6];
  __m512i code;
  load_sixes(unfolded, adjacency, slot, u, &code);
  live &= ~_mm512_mask_cmpeq_epi32_mask(live, code, none);
  g.live = live;
  if (!live) return;
  // Both points carried into the neighbour.
  carry_unfolded(u, live, g.s0, g.s1, g.s2, g.e0, g.e1, g.e2);
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

// The same in eight AVX2 lanes (processors without AVX-512: masks as vectors, no
// scatter or expanding load): fixed groups of eight consecutive traces, two in flight;
// a lane that is done keeps its values, stored when its group ends.
struct LaneGroup8 {
  __m256i t, hop, live, done;
  __m256 s0, s1, s2, e0, e1, e2;
};

#define MOLDTEX_AVX2_FN __attribute__((target("avx2"), always_inline)) inline

MOLDTEX_AVX2_FN __m256i lanes_below(size_t n) {  // lanes 0 .. n - 1 set
  return _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(n)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}

MOLDTEX_AVX2_FN void load8(LaneGroup8& g, const TraceLanes& lanes, size_t first, size_t n) {
  const __m256i m = lanes_below(n);
  g.t = _mm256_maskload_epi32(reinterpret_cast<const int*>(lanes.triangle + first), m);
  g.s0 = _mm256_maskload_ps(lanes.s[0] + first, m);
  g.s1 = _mm256_maskload_ps(lanes.s[1] + first, m);
  g.s2 = _mm256_maskload_ps(lanes.s[2] + first, m);
  g.e0 = _mm256_maskload_ps(lanes.e[0] + first, m);
  g.e1 = _mm256_maskload_ps(lanes.e[1] + first, m);
  g.e2 = _mm256_maskload_ps(lanes.e[2] + first, m);
  g.hop = _mm256_setzero_si256();
  g.live = m;
  g.done = _mm256_setzero_si256();
}

MOLDTEX_AVX2_FN void store8(const LaneGroup8& g, TraceLanes& lanes, size_t first, size_t n, uint8_t* located) {
  _mm256_maskstore_epi32(reinterpret_cast<int*>(lanes.triangle + first), g.done, g.t);
  _mm256_maskstore_ps(lanes.e[0] + first, g.done, g.e0);
  _mm256_maskstore_ps(lanes.e[1] + first, g.done, g.e1);
  _mm256_maskstore_ps(lanes.e[2] + first, g.done, g.e2);
  const int bits = _mm256_movemask_ps(_mm256_castsi256_ps(g.done));
  for (size_t i = 0; i < n; ++i) located[first + i] = static_cast<uint8_t>((bits >> i) & 1);
}

MOLDTEX_AVX2_FN __m256i as_int(__m256 v) { return _mm256_castps_si256(v); }
MOLDTEX_AVX2_FN __m256 as_float(__m256i v) { return _mm256_castsi256_ps(v); }
MOLDTEX_AVX2_FN int any(__m256i mask) { return !_mm256_testz_si256(mask, mask); }

// One crossing of every live lane of g (as cross() above).
MOLDTEX_AVX2_FN void cross8(LaneGroup8& g, const uint32_t* adjacency, const float* unfolded) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256i none = _mm256_set1_epi32(static_cast<int>(MTX_NO_NEIGHBOUR));
  __m256i live = g.live;
  const __m256i n0 = _mm256_and_si256(live, as_int(_mm256_cmp_ps(g.e0, zero, _CMP_LT_OQ)));
  const __m256i n1 = _mm256_and_si256(live, as_int(_mm256_cmp_ps(g.e1, zero, _CMP_LT_OQ)));
  const __m256i n2 = _mm256_and_si256(live, as_int(_mm256_cmp_ps(g.e2, zero, _CMP_LT_OQ)));
  const __m256i out = _mm256_or_si256(_mm256_or_si256(n0, n1), n2);
  g.done = _mm256_or_si256(g.done, _mm256_andnot_si256(out, live));  // located
  // Past MTX_UNFOLDED_HOPS crossings: walked.
  live = _mm256_andnot_si256(_mm256_cmpeq_epi32(g.hop, _mm256_set1_epi32(MTX_UNFOLDED_HOPS)), out);
  g.live = live;
  if (!any(live)) return;
  const __m256i edge = exit_edge8(g.s0, g.s1, g.s2, g.e0, g.e1, g.e2, n0, n1, n2, live);
  // (load_sixes8 reads every lane: the others read slot 0.)
  const __m256i slot = _mm256_and_si256(live, _mm256_add_epi32(_mm256_add_epi32(_mm256_add_epi32(g.t, g.t), g.t), edge));
  __m256 u[6];
  __m256i code;
  load_sixes8(unfolded, adjacency, slot, u, &code);
  live = _mm256_andnot_si256(_mm256_cmpeq_epi32(code, none), live);
  g.live = live;
  if (!any(live)) return;
  carry_unfolded8(u, live, g.s0, g.s1, g.s2, g.e0, g.e1, g.e2);
  g.t = _mm256_blendv_epi8(g.t, _mm256_srli_epi32(code, 3), live);
  g.hop = _mm256_sub_epi32(g.hop, live);  // + 1 where live (all ones = -1)
}

__attribute__((target("avx2"))) void hops_in_lanes8(const uint32_t* adjacency, const float* unfolded,
                                                    TraceLanes& lanes, uint8_t* located) {
  for (size_t first = 0; first < lanes.count; first += 16) {
    const size_t na = std::min<size_t>(8, lanes.count - first);
    const size_t nb = lanes.count - first > 8 ? std::min<size_t>(8, lanes.count - first - 8) : 0;
    LaneGroup8 a, b;
    load8(a, lanes, first, na);
    load8(b, lanes, first + 8, nb);
    while (any(_mm256_or_si256(a.live, b.live))) {
      cross8(a, adjacency, unfolded);
      cross8(b, adjacency, unfolded);
    }
    store8(a, lanes, first, na, located);
    store8(b, lanes, first + 8, nb, located);
  }
}

bool detect_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

bool detect_avx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
}

#endif

}  // namespace

unsigned trace_lane_width() {
#ifdef MOLDTEX_TRACE_LANES_X86
  static const unsigned width = detect_avx512() ? 16u : (detect_avx2() ? 8u : 1u);
  return width;
#else
  return 1u;
#endif
}

void trace_lanes_limit(unsigned width) { g_limit.store(width, std::memory_order_relaxed); }

void trace_hops_lanes(const uint32_t* adjacency, const float* unfolded, uint32_t triangle_count, TraceLanes& lanes,
                      uint8_t* located) {
#ifdef MOLDTEX_TRACE_LANES_X86
  // (Offsets up to 3 * triangle_count * MTX_UNFOLDED_FLOATS floats in a signed 32-bit index.)
  const bool fits = uint64_t(triangle_count) * 3u * MTX_UNFOLDED_FLOATS < (uint64_t(1) << 31);
  const unsigned width = std::min(trace_lane_width(), g_limit.load(std::memory_order_relaxed));
  if (fits && width >= 16) {
    hops_in_lanes(adjacency, unfolded, lanes, located);
    return;
  }
  if (fits && width >= 8) {
    hops_in_lanes8(adjacency, unfolded, lanes, located);
    return;
  }
#endif
  hops_scalar(adjacency, unfolded, lanes, located);
}

}  // namespace moldtex
