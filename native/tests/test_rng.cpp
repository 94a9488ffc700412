// The counter-based random streams (shared/rng.h) as the agents draw them: one value per
// (purpose, agent, step), computed by both backends alike. The checks are on the draws
// themselves, with bounds from the statistics of truly random numbers (so a cheaper mix,
// which a step's cost may tempt one to, has to pass them too).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "shared/rng.h"

namespace mtx {
namespace {

using moldtex::mtx_rng_float;
using moldtex::mtx_rng_init;
using moldtex::mtx_rng_init_keyed;
using moldtex::mtx_rng_init_step;
using moldtex::mtx_rng_key;

// Pearson correlation of two equally long samples.
double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = double(a.size());
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i] / n, mb += b[i] / n;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// A per-step stream's first draw of 4,096 agents over 257 steps (1.05 M draws): uniform
// (chi-square over 64 bins: mean 63 and standard deviation 11.2 for random numbers; the
// bound, 63 + 5 sd = 119, fails a truly random sample about once in 10^6), and unrelated
// between neighbouring agents and between one step and the next (a correlation's standard
// deviation is 1 / sqrt(n) = 0.001 here; the bound is 5 of them). Both ways a step's state
// is made: one mix of the packed (agent, step) (MoMaS' steering, mtx_rng_init_step) and
// two (the continuous model's turnover and decisions, mtx_rng_init_keyed).
void ExpectUniformAndUnrelated(uint64_t (*init)(uint64_t key, uint64_t stream, uint64_t counter)) {
  const uint64_t key = mtx_rng_key(1, MTX_RNG_STEER);
  constexpr uint32_t kAgents = 4096, kSteps = 257;
  std::vector<double> draw(size_t(kAgents) * kSteps);
  for (uint32_t s = 0; s < kSteps; ++s)
    for (uint32_t a = 0; a < kAgents; ++a) {
      uint64_t state = init(key, a, s);
      draw[size_t(s) * kAgents + a] = mtx_rng_float(&state);
    }
  std::vector<double> bins(64, 0.0);
  for (double u : draw) bins[size_t(u * 64)] += 1;
  const double expected = double(draw.size()) / 64;
  double chi2 = 0;
  for (double b : bins) chi2 += (b - expected) * (b - expected) / expected;
  EXPECT_LT(chi2, 119.0);
  std::vector<double> here, next_agent, next_step;
  for (uint32_t s = 0; s + 1 < kSteps; ++s)
    for (uint32_t a = 0; a + 1 < kAgents; ++a) {
      here.push_back(draw[size_t(s) * kAgents + a]);
      next_agent.push_back(draw[size_t(s) * kAgents + a + 1]);
      next_step.push_back(draw[size_t(s + 1) * kAgents + a]);
    }
  const double bound = 5 / std::sqrt(double(here.size()));
  EXPECT_LT(std::fabs(Correlation(here, next_agent)), bound);
  EXPECT_LT(std::fabs(Correlation(here, next_step)), bound);
  // Stream and counter swapped (agent a at step s against agent s at step a): packed
  // differently, so unrelated too.
  std::vector<double> swapped;
  for (uint32_t s = 0; s + 1 < kSteps; ++s)
    for (uint32_t a = 0; a + 1 < kAgents; ++a) {
      uint64_t state = init(key, s, a);
      swapped.push_back(mtx_rng_float(&state));
    }
  EXPECT_LT(std::fabs(Correlation(here, swapped)), bound);
}

TEST(RandomStreams, PerStepDrawsAreUniformAndUnrelated) {
  {
    SCOPED_TRACE("one mix (mtx_rng_init_step)");
    ExpectUniformAndUnrelated(mtx_rng_init_step);
  }
  SCOPED_TRACE("two mixes (mtx_rng_init_keyed)");
  ExpectUniformAndUnrelated(mtx_rng_init_keyed);
}

// One mix of the packed (agent, step): the steps' low 32 bits sit below the agent, so
// agents far apart (2^20) and steps past 2^31 still give states that differ, and the
// draws of one agent over 100,000 consecutive steps are unrelated from one to the next.
TEST(RandomStreams, OneMixStatesAreDistinctAndStepsUnrelated) {
  const uint64_t key = mtx_rng_key(3, MTX_RNG_STEER);
  EXPECT_NE(mtx_rng_init_step(key, 1u << 20, 5), mtx_rng_init_step(key, 0, 5));
  EXPECT_NE(mtx_rng_init_step(key, 7, (1ull << 31) + 5), mtx_rng_init_step(key, 7, 5));
  std::vector<double> a, b;
  for (uint64_t s = 0; s < 100000; ++s) {
    uint64_t x = mtx_rng_init_step(key, 12345, s), y = mtx_rng_init_step(key, 12345, s + 1);
    a.push_back(mtx_rng_float(&x));
    b.push_back(mtx_rng_float(&y));
  }
  EXPECT_LT(std::fabs(Correlation(a, b)), 5 / std::sqrt(100000.0));
}

// Streams from 2^32 on (the slime brushes number a batch's agents (batch << 32) | i):
// batch 1's agents draw unlike batch 0's and unlike batch 2's.
TEST(RandomStreams, StreamsAbove32BitsStayApart) {
  constexpr uint32_t kAgents = 100000;
  std::vector<double> batch[3];
  for (uint64_t b = 0; b < 3; ++b)
    for (uint32_t i = 0; i < kAgents; ++i) {
      uint64_t state = mtx_rng_init(7, 8, (b << 32) | i, 0);
      batch[b].push_back(mtx_rng_float(&state));
    }
  const double bound = 5 / std::sqrt(double(kAgents));
  EXPECT_LT(std::fabs(Correlation(batch[0], batch[1])), bound);
  EXPECT_LT(std::fabs(Correlation(batch[1], batch[2])), bound);
  size_t equal = 0;
  for (uint32_t i = 0; i < kAgents; ++i) equal += batch[0][i] == batch[1][i];
  EXPECT_LT(equal, 20u);  // 24-bit floats: about 0.006 equal pairs expected by chance
}

}  // namespace
}  // namespace mtx
