/* rng.h — counter-based random numbers: a value is a pure function of (seed, purpose,
 * stream, counter), so every agent draws the same numbers whichever thread or work-item
 * runs it, on any backend. */
#ifndef MOLDTEX_SHARED_RNG_H
#define MOLDTEX_SHARED_RNG_H

#ifndef __OPENCL_C_VERSION__
#include "shared/portable.h"
#endif

MTX_BEGIN_NAMESPACE

#define MTX_RNG_SPAWN 1
#define MTX_RNG_STEER 2
/* Slime brushes (host only): agents placed by moldtex_sim_add_agents, erase draws. */
#define MTX_RNG_BRUSH 3
#define MTX_RNG_ERASE 4
/* The points that decide which texels larger than a deposit footprint it marks (MoMaS).
 * The continuous model's MTX_RNG_TURNOVER (continuous.h) has the same number: the two
 * never run in one simulation, so they stay as they are (renumbering either would change
 * every seed's pattern). A new stream takes a number of its own (8 on). */
#define MTX_RNG_DEPOSIT 5

/* SplitMix64 finaliser: a well-tested 64-bit mixing function. */
MTX_FN mtx_u64 mtx_mix64(mtx_u64 x) {
  x += 0x9e3779b97f4a7c15UL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9UL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebUL;
  return x ^ (x >> 31);
}

/* The part of a state that depends only on (seed, purpose): a step's constants can hold
 * it, so each agent's draw mixes one time fewer (mtx_rng_init_keyed). */
MTX_FN mtx_u64 mtx_rng_key(mtx_u64 seed, mtx_u64 purpose) { return mtx_mix64(seed ^ (purpose << 56)); }

MTX_FN mtx_u64 mtx_rng_init_keyed(mtx_u64 key, mtx_u64 stream, mtx_u64 counter) {
  return mtx_mix64(mtx_mix64(key ^ stream) ^ counter);
}

/* A per-step state in one mix: the stream (an agent, below 2^32) in the high word and the
 * step's low 32 bits in the low word, so distinct (stream, step) give distinct states for
 * 2^32 steps (over two years at 60 steps a second); the key makes them a function of the
 * seed and purpose too. RandomStreams (test_rng.cpp) checks the draws' uniformity and
 * independence across agents and steps. */
MTX_FN mtx_u64 mtx_rng_init_step(mtx_u64 key, mtx_u64 stream, mtx_u64 step) {
  return mtx_mix64(key ^ ((stream << 32) | (step & 0xffffffffUL)));
}

MTX_FN mtx_u64 mtx_rng_init(mtx_u64 seed, mtx_u64 purpose, mtx_u64 stream, mtx_u64 counter) {
  return mtx_rng_init_keyed(mtx_rng_key(seed, purpose), stream, counter);
}

/* Uniform in [0, 1) with 24 bits, exactly representable as a float. */
MTX_FN float mtx_rng_float(mtx_u64* state) {
  *state = mtx_mix64(*state);
  return MTX_CAST(float, *state >> 40) * (1.0f / 16777216.0f);
}

MTX_END_NAMESPACE

#endif
