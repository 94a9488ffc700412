// Counter-based random numbers: a value is a pure function of (seed, stream, counter),
// so every agent draws the same numbers whichever thread runs it and in whatever order.
#pragma once
#include <cstdint>

namespace moldtex {

// SplitMix64 finaliser: a well-tested 64-bit mixing function.
inline uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Purposes keep independent draws of the same agent and step apart.
enum class RngPurpose : uint64_t { Spawn = 1, Steer = 2 };

struct CounterRng {
  uint64_t state;
  CounterRng(uint64_t seed, RngPurpose purpose, uint64_t stream, uint64_t counter)
      : state(mix64(mix64(mix64(seed ^ (static_cast<uint64_t>(purpose) << 56)) ^ stream) ^
                    counter)) {}
  uint64_t next_u64() {
    state = mix64(state);
    return state;
  }
  // Uniform in [0, 1) with 24 bits, exactly representable as float.
  float next_float() { return static_cast<float>(next_u64() >> 40) * (1.0f / 16777216.0f); }
  // Uniform in [0, 1) with 53 bits.
  double next_double() { return static_cast<double>(next_u64() >> 11) * (1.0 / 9007199254740992.0); }
};

}  // namespace moldtex
