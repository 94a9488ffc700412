#include "agents/momas_lanes.h"

#include "agents/momas_rules.h"
#include "surface/crossing_lanes.h"
#include "surface/trace_lanes.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdlib>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MOLDTEX_MOMAS_LANES_X86 1
// GCC 12 warns inside its own AVX-512 headers (their _mm512_undefined_* sources, which
// are meant to be left undefined) wherever these intrinsics are inlined; and about the
// ABI of vector values, which never cross a call here (every helper is inlined).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace moldtex {

namespace {

// The cap on the lanes: 16, or what MOLDTEX_MOMAS_LANES says at load (0: the scalar
// code; 8: the AVX2 lanes on a processor that has both kinds).
unsigned initial_limit() {
  const char* text = std::getenv("MOLDTEX_MOMAS_LANES");
  if (!text || !*text) return 16u;
  const long value = std::strtol(text, nullptr, 10);
  return value >= 16 ? 16u : (value >= 8 ? 8u : 0u);
}

std::atomic<unsigned> g_limit{initial_limit()};

// Agents idx[0..n) (n <= kPending) through the scalar code as momas_update_agents' batches
// run it: every probe first, with its texels asked for, then the rest of each step.
constexpr size_t kPending = 32;
void agents_scalar(const mtx_surface_tables& s, const mtx_momas_constants& c, const float* pheromone,
                   const float* field, uint8_t* marks, Agents& agents, const size_t* idx, size_t n) {
  Walker w[kPending];
  mtx_momas_probes probes[kPending];
  const size_t plane = size_t(c.width) * c.height;
  for (size_t j = 0; j < n; ++j) {
    const size_t i = idx[j];
    w[j] = agents.load(i);
    const uint32_t species = agents.species[i];
    mtx_momas_probe(s, &w[j], species, &c, &probes[j]);
    const float* own = pheromone + species * plane;
    for (int k = 0; k < 3; ++k) __builtin_prefetch(own + probes[j].texel[k]);
    __builtin_prefetch(marks + species * plane + probes[j].here, 1);
  }
  for (size_t j = 0; j < n; ++j) {
    const size_t i = idx[j];
    float hunger = agents.hunger[i];
    mtx_momas_agent_finish(s, pheromone, field, marks, &w[j], &hunger, agents.species[i], i, &c, &probes[j]);
    agents.store(i, w[j]);
    agents.hunger[i] = hunger;
  }
}

// The agents the lanes leave (a trace or move that must be walked): they gather here and
// run in scalar batches of 16 or more. Agents are independent within a step (each reads
// the step's field and its own state, and marks are the same byte from every writer).
struct Leftovers {
  const mtx_surface_tables& s;
  const mtx_momas_constants& c;
  const float* pheromone;
  const float* field;
  uint8_t* marks;
  Agents& agents;
  size_t pending[kPending];
  size_t waiting = 0, stepped = 0;

  // A group of agents from `first` (lanes `all`), of which the lanes `done` were stepped.
  void take(size_t first, unsigned done, unsigned all) {
    stepped += static_cast<size_t>(__builtin_popcount(done));
    for (unsigned rest = ~done & all; rest; rest &= rest - 1)
      pending[waiting++] = first + static_cast<size_t>(__builtin_ctz(rest));
    if (waiting >= 16) {
      agents_scalar(s, c, pheromone, field, marks, agents, pending, waiting);
      waiting = 0;
    }
  }
  // The agents [i, end) too few for a group, and everything pending; returns how many
  // the lanes stepped.
  size_t finish(size_t i, size_t end) {
    for (; i < end; ++i) pending[waiting++] = i;
    agents_scalar(s, c, pheromone, field, marks, agents, pending, waiting);
    return stepped;
  }
};

#ifdef MOLDTEX_MOMAS_LANES_X86

// The frame's floats as the lanes gather them (shared/walk.h's mtx_frame).
constexpr int kFrameFloats = sizeof(mtx_frame) / sizeof(float);
static_assert(sizeof(mtx_frame) == 14 * sizeof(float), "mtx_frame is 14 floats");
constexpr int kInvA = offsetof(mtx_frame, inv_a) / sizeof(float);
constexpr int kBx = offsetof(mtx_frame, bx) / sizeof(float);
constexpr int kInvBy = offsetof(mtx_frame, inv_by) / sizeof(float);
constexpr int kAltitude = offsetof(mtx_frame, altitude) / sizeof(float);
constexpr int kEdge = offsetof(mtx_frame, edge) / sizeof(float);

#define MOLDTEX_MOMAS_LANES_FN __attribute__((target("avx512f,avx512dq"), always_inline)) inline

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

// The texel holding that point (mtx_walker_texel).
MOLDTEX_MOMAS_LANES_FN __m512i texel_of(__m512 b0, __m512 b1, __m512 b2, const __m512* uv, const TextureLanes& tx) {
  __m512 x, y;
  point_in_texels(b0, b1, b2, uv, tx, x, y);
  return texel_at(x, y, tx.last_x, tx.last_y, tx.row);
}

// uv[0..5] replaced by triangle t's corner UVs in the lanes m.
MOLDTEX_MOMAS_LANES_FN void gather_uvs(const float* corner_uvs, __m512i t, __mmask16 m, __m512* uv) {
  const __m512i t6 = _mm512_mullo_epi32(t, _mm512_set1_epi32(6));
  for (int q = 0; q < 6; ++q)
    uv[q] = _mm512_mask_i32gather_ps(uv[q], m, _mm512_add_epi32(t6, _mm512_set1_epi32(q)), corner_uvs, 4);
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

// floats[base + offset] in each lane.
MOLDTEX_MOMAS_LANES_FN __m512 gather_at(const float* floats, __m512i base, int offset) {
  return _mm512_i32gather_ps(_mm512_add_epi32(base, _mm512_set1_epi32(offset)), floats, 4);
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
  const __m512 minus_b = _mm512_castsi512_ps(
      _mm512_xor_si512(_mm512_castps_si512(b), _mm512_set1_epi32(static_cast<int>(0x80000000u))));
  const __m512 tau = _mm512_maskz_div_ps(_mm512_cmp_ps_mask(b, zero, _CMP_GT_OQ), minus_b, db);
  return _mm512_cmp_ps_mask(db, zero, _CMP_LT_OQ) & _mm512_cmp_ps_mask(tau, length, _CMP_LT_OQ);
}

// -a: the sign bit flipped (0 - a would give +0 for a = +0, not -0).
MOLDTEX_MOMAS_LANES_FN __m512 negated(__m512 a) {
  return _mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(a), _mm512_set1_epi32(static_cast<int>(0x80000000u))));
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
constexpr int kWalkLegs = 8;  // a walk with more legs leaves the lanes
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
    const __m512 ex = _mm512_mask_i32gather_ps(zero, live, at_edge, frames, 4);
    const __m512 ey = _mm512_mask_i32gather_ps(zero, live, _mm512_add_epi32(at_edge, i1), frames, 4);
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
    const __m512 cx = _mm512_mask_i32gather_ps(zero, live, at_ccw, frames, 4);
    const __m512 cy = _mm512_mask_i32gather_ps(zero, live, _mm512_add_epi32(at_ccw, i1), frames, 4);
    const __m512 sign = _mm512_mask_mov_ps(_mm512_set1_ps(-1.0f), same, _mm512_set1_ps(1.0f));
    const __m512 signed_along = _mm512_mul_ps(along, sign);
    w.hx = _mm512_mask_mov_ps(w.hx, live, _mm512_sub_ps(_mm512_mul_ps(signed_along, cx), _mm512_mul_ps(across, cy)));
    w.hy = _mm512_mask_mov_ps(w.hy, live, _mm512_add_ps(_mm512_mul_ps(signed_along, cy), _mm512_mul_ps(across, cx)));
    w.t = _mm512_mask_mov_epi32(w.t, live, next);
    w.inv_a = _mm512_mask_i32gather_ps(w.inv_a, live, _mm512_add_epi32(nf, _mm512_set1_epi32(kInvA)), frames, 4);
    w.bx = _mm512_mask_i32gather_ps(w.bx, live, _mm512_add_epi32(nf, _mm512_set1_epi32(kBx)), frames, 4);
    w.inv_by = _mm512_mask_i32gather_ps(w.inv_by, live, _mm512_add_epi32(nf, _mm512_set1_epi32(kInvBy)), frames, 4);
  }
  return ended;
}

// Sensor traces in lanes: the triangle, start and end weights of each (mtx_trace_ends).
struct Trace {
  __m512i t;
  __m512 s0, s1, s2, e0, e1, e2;
};

// mtx_trace_hops for the lanes `todo` of g: returns those located (g.t and g.e* then say
// where their traces end); the rest must be walked, for the reasons mtx_trace_hops gives
// up at the same crossing.
MOLDTEX_MOMAS_LANES_FN __mmask16 trace_hops(Trace& g, __mmask16 todo, const uint32_t* adjacency,
                                           const float* unfolded) {
  const __m512 zero = _mm512_setzero_ps();
  const __m512i none = _mm512_set1_epi32(static_cast<int>(MTX_NO_NEIGHBOUR));
  __mmask16 live = todo, located = 0;
  for (int hop = 0;; ++hop) {
    const __mmask16 n0 = _mm512_mask_cmp_ps_mask(live, g.e0, zero, _CMP_LT_OQ);
    const __mmask16 n1 = _mm512_mask_cmp_ps_mask(live, g.e1, zero, _CMP_LT_OQ);
    const __mmask16 n2 = _mm512_mask_cmp_ps_mask(live, g.e2, zero, _CMP_LT_OQ);
    const __mmask16 out = n0 | n1 | n2;
    located |= live & ~out;
    live = out;
    if (!live || hop == MTX_UNFOLDED_HOPS) break;
    // The edge it leaves by, and a neighbour there.
    const __m512i edge = exit_edge(g.s0, g.s1, g.s2, g.e0, g.e1, g.e2, n0, n1, n2, live);
    const __m512i slot = _mm512_add_epi32(_mm512_add_epi32(_mm512_add_epi32(g.t, g.t), g.t), edge);
    const __m512i code = _mm512_mask_i32gather_epi32(none, live, slot, adjacency, 4);
    live &= ~_mm512_mask_cmpeq_epi32_mask(live, code, none);
    if (!live) break;
    // Both points carried into the neighbour.
    carry_across(slot, live, unfolded, g.s0, g.s1, g.s2, g.e0, g.e1, g.e2);
    g.t = _mm512_mask_mov_epi32(g.t, live, _mm512_srli_epi32(code, 3));
  }
  return located;
}

// Where a sensor trace from the agents' points (weights b*, triangle tri) along heading
// (hx, hy) ends, for the lanes `todo` that leave their triangle (mtx_momas_probe:
// mtx_walk_trace, then mtx_walker_texel_at), written into p; clears from *ok the lanes
// whose trace must be walked.
MOLDTEX_MOMAS_LANES_FN void trace_probe(const mtx_surface_tables& s, __mmask16 todo, __mmask16* ok, __m512i tri,
                                        __m512 b0, __m512 b1, __m512 b2, __m512 hx, __m512 hy, __m512 length,
                                        __m512 inv_a, __m512 bx, __m512 inv_by, const __m512* own_uv,
                                        const TextureLanes& tx, Probe& p) {
  // mtx_trace_ends.
  const __m512 d2 = _mm512_mul_ps(hy, inv_by);
  const __m512 d1 = _mm512_mul_ps(_mm512_sub_ps(hx, _mm512_mul_ps(bx, d2)), inv_a);
  Trace g{tri,
          b0,
          b1,
          b2,
          _mm512_sub_ps(b0, _mm512_mul_ps(length, _mm512_add_ps(d1, d2))),
          _mm512_add_ps(b1, _mm512_mul_ps(length, d1)),
          _mm512_add_ps(b2, _mm512_mul_ps(length, d2))};
  const __mmask16 located = trace_hops(g, todo, s.adjacency, s.unfolded);
  *ok &= static_cast<__mmask16>(~(todo & ~located));
  if (!located) return;
  // The UVs of the triangle where each trace ends: the agent's own unless it crossed.
  __m512 uv[6];
  for (int k = 0; k < 6; ++k) uv[k] = own_uv[k];
  const __mmask16 elsewhere = _mm512_mask_cmpneq_epi32_mask(located, g.t, tri);
  if (elsewhere) gather_uvs(s.corner_uvs, g.t, elsewhere, uv);
  __m512 x, y;
  point_in_texels(g.e0, g.e1, g.e2, uv, tx, x, y);
  p.texel = _mm512_mask_mov_epi32(p.texel, located, texel_at(x, y, tx.last_x, tx.last_y, tx.row));
  p.triangle = _mm512_mask_mov_epi32(p.triangle, located, g.t);
  p.x = _mm512_mask_mov_ps(p.x, located, x);
  p.y = _mm512_mask_mov_ps(p.y, located, y);
}

// table[index] for a byte table, in lanes: the last of four bytes read from
// max(index - 3, 0), so every byte read lies inside the table (of at least 4 bytes).
MOLDTEX_MOMAS_LANES_FN __m512i byte_at(const uint8_t* table, __m512i index) {
  const __m512i at = _mm512_max_epi32(_mm512_sub_epi32(index, _mm512_set1_epi32(3)), _mm512_setzero_si512());
  const __m512i word = _mm512_i32gather_epi32(at, table, 1);
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
// the lane's triangle t's.
MOLDTEX_MOMAS_LANES_FN __mmask16 box_within_island(const mtx_surface_tables& s, const mtx_momas_constants& c,
                                                   __m512i texel, const Box& b, int grow, __m512i t) {
  const __m512i r = byte_at(s.interior_reach, texel);
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
  const __m512i island = _mm512_i32gather_epi32(t, s.island, 4);
  return _mm512_cmpge_epi32_mask(_mm512_sub_epi32(b.x0, g), _mm512_sub_epi32(cx, r)) &
         _mm512_cmple_epi32_mask(_mm512_add_epi32(b.x1, g), _mm512_add_epi32(cx, r)) &
         _mm512_cmpge_epi32_mask(_mm512_sub_epi32(b.y0, g), _mm512_sub_epi32(cy, r)) &
         _mm512_cmple_epi32_mask(_mm512_add_epi32(b.y1, g), _mm512_add_epi32(cy, r)) &
         _mm512_cmpeq_epi32_mask(_mm512_i32gather_epi32(texel, s.texel_island, 4), island);
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
  if (!c.has_fields && s.interior_reach != nullptr) {
    __m512 ex, ey;
    footprint_size(s, c, t, ex, ey);
    const __m512 quarter = _mm512_set1_ps(0.25f), half = _mm512_set1_ps(0.5f);
    const __mmask16 jx = _mm512_cmp_ps_mask(ex, quarter, _CMP_LT_OQ) &
                         _mm512_cmp_ps_mask(ex, _mm512_mul_ps(half, ey), _CMP_LT_OQ);
    const __mmask16 jy = _mm512_cmp_ps_mask(ey, quarter, _CMP_LT_OQ) &
                         _mm512_cmp_ps_mask(ey, _mm512_mul_ps(half, ex), _CMP_LT_OQ);
    const __mmask16 plain = lanes & static_cast<__mmask16>(~(jx | jy));
    // The texel under the walker, if an island texel.
    alignas(64) uint32_t at[16];
    const __mmask16 own = plain & _mm512_cmpeq_epi32_mask(byte_at(s.classes, texel), _mm512_set1_epi32(MTX_TEXEL_INSIDE));
    _mm512_store_si512(at, _mm512_add_epi32(base, texel));
    for (unsigned bits = own; bits; bits &= bits - 1) MTX_MARK(marks, at[__builtin_ctz(bits)]);
    const __mmask16 small = _mm512_cmp_ps_mask(ex, half, _CMP_LT_OQ) & _mm512_cmp_ps_mask(ey, half, _CMP_LT_OQ);
    const __mmask16 boxed = plain & static_cast<__mmask16>(~small);
    __mmask16 fast = 0;
    if (boxed) {
      const Box b = centres_within(x, y, ex, ey, c);
      const __mmask16 filled = _mm512_cmple_epi32_mask(b.x0, b.x1) & _mm512_cmple_epi32_mask(b.y0, b.y1);
      fast = boxed & filled & box_within_island(s, c, texel, b, 1, t);
      if (fast) {
        const __m512i w = _mm512_sub_epi32(b.x1, b.x0), hgt = _mm512_sub_epi32(b.y1, b.y0);
        const int most_w = _mm512_mask_reduce_max_epi32(fast, w), most_h = _mm512_mask_reduce_max_epi32(fast, hgt);
        const __m512i width = _mm512_set1_epi32(static_cast<int>(c.width));
        for (int dy = 0; dy <= most_h; ++dy) {
          const __mmask16 row_in = fast & _mm512_cmple_epi32_mask(_mm512_set1_epi32(dy), hgt);
          const __m512i row = _mm512_add_epi32(base, _mm512_mullo_epi32(_mm512_add_epi32(b.y0, _mm512_set1_epi32(dy)), width));
          for (int dx = 0; dx <= most_w; ++dx) {
            const __mmask16 m = row_in & _mm512_cmple_epi32_mask(_mm512_set1_epi32(dx), w);
            _mm512_store_si512(at, _mm512_add_epi32(row, _mm512_add_epi32(b.x0, _mm512_set1_epi32(dx))));
            for (unsigned bits = m; bits; bits &= bits - 1) MTX_MARK(marks, at[__builtin_ctz(bits)]);
          }
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
  const bool plain = c.species_count == 1u && !c.has_fields && s.interior_reach != nullptr;
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
      const __m512i x0 = b.x0, x1 = b.x1, y0 = b.y0, y1 = b.y1;
      const __mmask16 whole = box_within_island(s, c, p[k].texel, b, 0, p[k].triangle);
      const __mmask16 fast = lanes & static_cast<__mmask16>(~small) & whole;
      __m512 sum = here, count = one;
      if (fast) {
        const __m512i w = _mm512_sub_epi32(x1, x0), hgt = _mm512_sub_epi32(y1, y0);
        const int most_w = _mm512_mask_reduce_max_epi32(fast, w), most_h = _mm512_mask_reduce_max_epi32(fast, hgt);
        for (int dy = 0; dy <= most_h; ++dy) {
          const __mmask16 row_in = fast & _mm512_cmple_epi32_mask(_mm512_set1_epi32(dy), hgt);
          if (!row_in) continue;
          const __m512i row = _mm512_mullo_epi32(_mm512_add_epi32(y0, _mm512_set1_epi32(dy)), width);
          for (int dx = 0; dx <= most_w; ++dx) {
            const __m512i i = _mm512_add_epi32(row, _mm512_add_epi32(x0, _mm512_set1_epi32(dx)));
            const __mmask16 m = row_in & _mm512_cmple_epi32_mask(_mm512_set1_epi32(dx), w) &
                                _mm512_cmpneq_epi32_mask(i, p[k].texel);
            if (!m) continue;
            const __m512 v = _mm512_mask_i32gather_ps(zero, m, i, pheromone, 4);
            sum = _mm512_mask_add_ps(sum, m, sum, _mm512_mul_ps(a, v));
            count = _mm512_mask_add_ps(count, m, count, one);
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

// Agents [i, i + 16): the lanes whose probes and move stay inside their triangles are
// stepped here; the others are returned for the scalar code.
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
  const __m512i t6 = _mm512_mullo_epi32(tri, _mm512_set1_epi32(6));
  __m512 uv[6];
  for (int k = 0; k < 6; ++k) uv[k] = gather_at(s.corner_uvs, t6, k);
  const __m512i tf = _mm512_mullo_epi32(tri, _mm512_set1_epi32(kFrameFloats));
  const __m512 inv_a = gather_at(frames, tf, kInvA), bx = gather_at(frames, tf, kBx);
  const __m512 inv_by = gather_at(frames, tf, kInvBy);
  const __m512 alt0 = gather_at(frames, tf, kAltitude), alt1 = gather_at(frames, tf, kAltitude + 1);
  const __m512 alt2 = gather_at(frames, tf, kAltitude + 2);

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
    const __m512 nsn = _mm512_castsi512_ps(  // -sn, the sign bit flipped
        _mm512_xor_si512(_mm512_castps_si512(sn), _mm512_set1_epi32(static_cast<int>(0x80000000u))));
    const Jacobian j{jxx, jxy, jyx, jyy};
    // mtx_rotate(h, c, s): (c x - s y, s x + c y); the right probe turns by -s.
    const __m512 px[3] = {_mm512_sub_ps(_mm512_mul_ps(cs, hx), _mm512_mul_ps(sn, hy)), hx,
                          _mm512_sub_ps(_mm512_mul_ps(cs, hx), _mm512_mul_ps(nsn, hy))};
    const __m512 py[3] = {_mm512_add_ps(_mm512_mul_ps(sn, hx), _mm512_mul_ps(cs, hy)), hy,
                          _mm512_add_ps(_mm512_mul_ps(nsn, hx), _mm512_mul_ps(cs, hy))};
    Probe probe[3];
    for (int k = 0; k < 3; ++k) probe[k] = probe_at(x, y, tri, sensor_length, j, px[k], py[k], tx);
    if (traced) {
      for (int k = 0; k < 3; ++k)
        trace_probe(s, traced, &inside, tri, b0, b1, b2, px[k], py[k], sensor_length, inv_a, bx, inv_by, uv, tx,
                    probe[k]);
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
    alignas(64) float turns[16], cosines[16], sines[16];
    _mm512_store_ps(turns, turn);
    for (unsigned bits = turning; bits; bits &= bits - 1) {
      const int j = __builtin_ctz(bits);
      cosines[j] = std::cos(turns[j]);
      sines[j] = std::sin(turns[j]);
    }
    const __m512 tc = _mm512_mask_load_ps(one, turning, cosines);
    const __m512 ts = _mm512_mask_load_ps(_mm512_setzero_ps(), turning, sines);
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
    alignas(64) uint32_t at[16];
    _mm512_store_si512(at, _mm512_add_epi32(mark_base, texel));
    for (unsigned bits = inside; bits; bits &= bits - 1) MTX_MARK(marks, at[__builtin_ctz(bits)]);
  }
  const __m512 b1_out = w.b1, b2_out = w.b2;
  hx = w.hx;
  hy = w.hy;
  if (moved) _mm512_mask_storeu_epi32(agents.triangle.data() + i, moved & inside, w.t);
  _mm512_mask_storeu_ps(agents.b1.data() + i, inside, b1_out);
  _mm512_mask_storeu_ps(agents.b2.data() + i, inside, b2_out);
  _mm512_mask_storeu_ps(agents.hx.data() + i, inside, hx);
  _mm512_mask_storeu_ps(agents.hy.data() + i, inside, hy);
  return inside;
}

__attribute__((target("avx512f,avx512dq"))) size_t update_in_lanes(const mtx_surface_tables& s,
                                                                  const mtx_momas_constants& c,
                                                                  const float* pheromone, const float* field,
                                                                  uint8_t* marks, Agents& agents, size_t begin,
                                                                  size_t end) {
  Leftovers rest{s, c, pheromone, field, marks, agents, {}, 0, 0};
  size_t i = begin;
  for (; i + 16 <= end; i += 16) rest.take(i, step16(s, c, pheromone, field, marks, agents, i), 0xffffu);
  return rest.finish(i, end);
}

bool detect_lanes() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
}

// ---- The same step in eight AVX2 lanes (processors without AVX-512: AMD before Zen 4,
// Intel's consumer parts). Masks are vectors (all ones where set), the 64-bit multiplies
// of the random numbers are built from 32-bit ones, and the unfolding is gathered float
// by float; every float operation is the 16-lane code's, so the bits are the same.

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
MOLDTEX_AVX2_FN void gather_uvs8(const float* corner_uvs, __m256i t, M8 m, __m256* uv) {
  const __m256i t6 = _mm256_mullo_epi32(t, _mm256_set1_epi32(6));
  for (int q = 0; q < 6; ++q) uv[q] = gather8(corner_uvs, _mm256_add_epi32(t6, _mm256_set1_epi32(q)), m, uv[q]);
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

// mtx_trace_hops for the lanes `todo` (trace_hops' eight-lane twin).
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
    const __m256i slot = _mm256_add_epi32(_mm256_add_epi32(_mm256_add_epi32(g.t, g.t), g.t), edge);
    const __m256i code =
        _mm256_mask_i32gather_epi32(none, reinterpret_cast<const int*>(adjacency), slot, as_int(live), 4);
    live = but8(live, eqi8(code, none));
    if (!bits8(live)) break;
    carry_across8(slot, as_int(live), unfolded, g.s0, g.s1, g.s2, g.e0, g.e1, g.e2);
    g.t = seli8(g.t, live, _mm256_srli_epi32(code, 3));
  }
  return located;
}

// trace_texel's twin.
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

// walk_across' twin.
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

// step16's twin: agents [i, i + 8); returns the lanes done (bits).
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
  const __m256 inv_a = _mm256_i32gather_ps(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kInvA)), 4);
  const __m256 bx = _mm256_i32gather_ps(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kBx)), 4);
  const __m256 inv_by = _mm256_i32gather_ps(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kInvBy)), 4);
  const __m256 alt0 = _mm256_i32gather_ps(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kAltitude)), 4);
  const __m256 alt1 = _mm256_i32gather_ps(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kAltitude + 1)), 4);
  const __m256 alt2 = _mm256_i32gather_ps(frames, _mm256_add_epi32(tf, _mm256_set1_epi32(kAltitude + 2)), 4);

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
    alignas(32) float turns[8], cosines[8], sines[8];
    _mm256_store_ps(turns, turn);
    const unsigned turn_bits = bits8(turning);
    for (unsigned b = turn_bits; b; b &= b - 1) {
      const int k = __builtin_ctz(b);
      cosines[k] = std::cos(turns[k]);
      sines[k] = std::sin(turns[k]);
    }
    const __m256 tc = _mm256_maskload_ps(cosines, as_int(turning)), ts = _mm256_maskload_ps(sines, as_int(turning));
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

__attribute__((target("avx2"))) size_t update_in_lanes8(const mtx_surface_tables& s, const mtx_momas_constants& c,
                                                       const float* pheromone, const float* field, uint8_t* marks,
                                                       Agents& agents, size_t begin, size_t end) {
  Leftovers rest{s, c, pheromone, field, marks, agents, {}, 0, 0};
  size_t i = begin;
  for (; i + 8 <= end; i += 8) rest.take(i, step8(s, c, pheromone, marks, agents, i), 0xffu);
  return rest.finish(i, end);
}

#endif

}  // namespace

unsigned momas_lane_width() {
#ifdef MOLDTEX_MOMAS_LANES_X86
  // AVX2 as the trace lanes find it.
  static const unsigned width = detect_lanes() ? 16u : (trace_lane_width() >= 8u ? 8u : 0u);
  return width;
#else
  return 0u;
#endif
}

void momas_lanes_limit(unsigned width) { g_limit.store(width, std::memory_order_relaxed); }

namespace {

unsigned lanes_now() { return std::min(momas_lane_width(), g_limit.load(std::memory_order_relaxed)); }

}  // namespace

bool momas_lanes_apply(const mtx_momas_constants& c, uint32_t triangle_count) {
#ifdef MOLDTEX_MOMAS_LANES_X86
  const unsigned width = lanes_now();
  if (width < 8u) return false;
  const uint64_t planes_texels = uint64_t(c.width) * c.height * (c.species_count ? c.species_count : 1u);
  // Surface units (footprint sensing and marks, steps without sensing): 16 lanes only.
  const bool units = c.surface_mode == 0u ? c.coast == 0u : width >= 16u;
  return units && c.decisions <= 1u && c.sensor_size == 0u && c.has_fields == 0u &&
         !(c.hunger_step > 0.0f) && c.substeps >= 1u && c.species_count >= 1u &&
         c.species_count <= MTX_MAX_SPECIES && planes_texels < (1ull << 31) &&
         uint64_t(triangle_count) * kFrameFloats < (1ull << 31);
#else
  (void)c;
  (void)triangle_count;
  return false;
#endif
}

size_t momas_lanes_update(const mtx_surface_tables& tables, const mtx_momas_constants& c, const float* pheromone,
                          const float* field, uint8_t* marks, Agents& agents, size_t begin, size_t end) {
#ifdef MOLDTEX_MOMAS_LANES_X86
  const unsigned width = lanes_now();
  if (width >= 16u) return update_in_lanes(tables, c, pheromone, field, marks, agents, begin, end);
  if (width >= 8u) return update_in_lanes8(tables, c, pheromone, field, marks, agents, begin, end);
#endif
  momas_update_agents(tables, c, pheromone, field, marks, agents, begin, end);
  return 0;
}

}  // namespace moldtex
