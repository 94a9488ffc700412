// A turn's cosine and sine (shared/angle.h), which MoMaS' scalar step, its SIMD lanes and
// the OpenCL kernel all compute from float multiplications and additions instead of the
// math library: checked against double precision over the angles a turn can take.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "shared/angle.h"

namespace mtx {
namespace {

using moldtex::mtx_cos_sin;

// Angles uniform over +-3200 rad (a turn is at most turn speed 1000 x pi x a decision
// interval; 3200 rad covers a 1 s interval) and every multiple of pi/4 up to +-64 pi,
// where the quadrant changes. Bound: 1.2e-7, two units in the last place of a float at
// 1 (measured: 8.5e-8 at most over 2 M angles; the float library cosine is within 3.3e-8).
// A wrong quadrant misses by up to 2, a dropped r^9 term of the sine by 3e-7.
TEST(Angle, CosineAndSineWithinTwoUnitsInTheLastPlace) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(-3200.f, 3200.f);
  double worst = 0;
  auto check = [&](float a) {
    float c = 0, s = 0;
    mtx_cos_sin(a, &c, &s);
    worst = std::max({worst, std::fabs(c - std::cos(double(a))), std::fabs(s - std::sin(double(a)))});
  };
  for (int i = 0; i < 200000; ++i) check(uniform(random));
  for (int k = -256; k <= 256; ++k) check(float(k * (M_PI / 4)));
  EXPECT_LT(worst, 1.2e-7);
}

// No turn leaves a heading exactly as it was (cos 0 = 1 and sin 0 = 0 to the bit, as
// the library gives them), and absurd angles (past the clamp at 6e5 rad, or infinite)
// still give a unit rotation, not NaN.
TEST(Angle, NoTurnIsExactAndAbsurdTurnsStayRotations) {
  float c = 0, s = 1;
  mtx_cos_sin(0.f, &c, &s);
  EXPECT_EQ(c, 1.f);
  EXPECT_EQ(s, 0.f);
  for (float a : {6.0e5f, -6.0e5f, 1e30f, -1e30f, INFINITY, -INFINITY}) {
    mtx_cos_sin(a, &c, &s);
    ASSERT_TRUE(std::isfinite(c) && std::isfinite(s)) << a;
    EXPECT_NEAR(double(c) * c + double(s) * s, 1.0, 1e-6) << a;
  }
}

}  // namespace
}  // namespace mtx
