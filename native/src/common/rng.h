// Host-side convenience over shared/rng.h (the counter-based generator both backends
// use), with a double for choices that need more than 24 bits.
#pragma once
#include <cstdint>

#include "shared/rng.h"

namespace moldtex {

struct CounterRng {
  uint64_t state;
  CounterRng(uint64_t seed, uint64_t purpose, uint64_t stream, uint64_t counter)
      : state(mtx_rng_init(seed, purpose, stream, counter)) {}
  float next_float() { return mtx_rng_float(&state); }
  // Uniform in [0, 1) with 53 bits.
  double next_double() {
    state = mtx_mix64(state);
    return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
  }
};

}  // namespace moldtex
