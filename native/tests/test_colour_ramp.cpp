// Colour map from an image (issue 13, Layton et al. §3.4): Isomap of the pixel colours to
// one coordinate, a curve per Lab channel, ColorRamp stops. Through the C API. The Lab
// conversion used to judge the result is written here independently of the core.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "test_util.h"

namespace mtx {
namespace {

struct Lab {
  double L, a, b;
};

double ToLinear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

Lab LinearToLab(double r, double g, double b) {
  r = std::max(r, 0.0), g = std::max(g, 0.0), b = std::max(b, 0.0);
  const double x = (0.4124564 * r + 0.3575761 * g + 0.1804375 * b) / 0.95047;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = (0.0193339 * r + 0.1191920 * g + 0.9503041 * b) / 1.08883;
  auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  return Lab{116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

double DeltaE(const Lab& p, const Lab& q) { return std::sqrt((p.L - q.L) * (p.L - q.L) + (p.a - q.a) * (p.a - q.a) + (p.b - q.b) * (p.b - q.b)); }

// The known curve, sRGB-encoded: black -> red -> yellow -> white, u in [0, 1].
void Curve(double u, double rgb[3]) {
  const double s = std::clamp(u, 0.0, 1.0) * 3.0;
  rgb[0] = std::min(s, 1.0);
  rgb[1] = std::clamp(s - 1.0, 0.0, 1.0);
  rgb[2] = std::clamp(s - 2.0, 0.0, 1.0);
}

Lab CurveLab(double u) {
  double c[3];
  Curve(u, c);
  return LinearToLab(ToLinear(c[0]), ToLinear(c[1]), ToLinear(c[2]));
}

// RGBA sRGB-encoded pixels along the curve, noise of +-noise per channel.
std::vector<float> CurveImage(size_t count, double noise, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0), jitter(-noise, noise);
  std::vector<float> pixels(4 * count);
  for (size_t i = 0; i < count; ++i) {
    double c[3];
    Curve(uniform(rng), c);
    for (int k = 0; k < 3; ++k) pixels[4 * i + k] = static_cast<float>(std::clamp(c[k] + jitter(rng), 0.0, 1.0));
    pixels[4 * i + 3] = 1.f;
  }
  return pixels;
}

// Two unrelated clusters: a blue and a green blob (linear RGB).
std::vector<float> TwoClusters(size_t count) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.06, 0.06);
  std::vector<float> pixels(4 * count);
  for (size_t i = 0; i < count; ++i) {
    const double base[2][3] = {{0.05, 0.10, 0.60}, {0.10, 0.50, 0.05}};
    for (int k = 0; k < 3; ++k) pixels[4 * i + k] = static_cast<float>(std::max(0.0, base[i % 2][k] + jitter(rng)));
    pixels[4 * i + 3] = 1.f;
  }
  return pixels;
}

struct Ramp {
  moldtex_status status;
  std::vector<moldtex_colour_stop> stops;
  moldtex_colour_ramp_info info;
};

Ramp RunRamp(const std::vector<float>& pixels, const moldtex_colour_ramp_desc& desc) {
  Ramp r;
  r.stops.resize(32);
  moldtex_colour_ramp_info_init(&r.info);
  r.status = moldtex_colour_ramp_from_pixels(pixels.data(), pixels.size() / desc.channels, &desc,
                                             r.stops.data(), 32, &r.info);
  r.stops.resize(r.status == MOLDTEX_OK ? r.info.stop_count : 0);
  return r;
}

moldtex_colour_ramp_desc SrgbDesc() {
  moldtex_colour_ramp_desc d;
  moldtex_colour_ramp_desc_init(&d);
  d.srgb_encoded = 1;
  return d;
}

// The ramp's colour at position x (linear between stops, as ColorRamp LINEAR does).
Lab RampAt(const std::vector<moldtex_colour_stop>& stops, double x) {
  const moldtex_colour_stop* a = &stops.front();
  const moldtex_colour_stop* b = &stops.back();
  for (size_t i = 0; i + 1 < stops.size(); ++i)
    if (x >= stops[i].position && x <= stops[i + 1].position) {
      a = &stops[i], b = &stops[i + 1];
      break;
    }
  const double w = b->position > a->position ? std::clamp((x - a->position) / (b->position - a->position), 0.0, 1.0) : 0.0;
  return LinearToLab(a->color[0] + w * (b->color[0] - a->color[0]), a->color[1] + w * (b->color[1] - a->color[1]),
                     a->color[2] + w * (b->color[2] - a->color[2]));
}

// Nearest curve parameter of a colour, and the distance.
double NearestU(const Lab& lab, double* distance) {
  double best = 1e300, best_u = 0;
  for (int j = 0; j <= 3000; ++j) {
    const double u = j / 3000.0, e = DeltaE(lab, CurveLab(u));
    if (e < best) best = e, best_u = u;
  }
  if (distance) *distance = best;
  return best_u;
}

TEST(ColourRamp, CurveImageGivesTheCurveInOrderDarkestFirst) {
  const std::vector<float> pixels = CurveImage(200000, 0.03, 1);
  const Ramp r = RunRamp(pixels, SrgbDesc());
  ASSERT_EQ(r.status, MOLDTEX_OK) << LastError();
  ASSERT_GE(r.stops.size(), 4u);
  ASSERT_LE(r.stops.size(), 32u);
  EXPECT_EQ(r.info.component_count, 1u);
  EXPECT_GT(r.info.explained, 0.9f);
  EXPECT_FLOAT_EQ(r.stops.front().position, 0.f);
  EXPECT_FLOAT_EQ(r.stops.back().position, 1.f);
  // The ramp lies on the curve: mean and largest Delta E (CIE76) from it, over the ramp.
  double sum = 0, worst = 0, previous_u = -1, covered_lo = 1, covered_hi = 0;
  const int kSteps = 200;
  for (int j = 0; j <= kSteps; ++j) {
    double e;
    const double u = NearestU(RampAt(r.stops, j / double(kSteps)), &e);
    sum += e, worst = std::max(worst, e);
    EXPECT_GE(u, previous_u - 0.02) << "the ramp runs back along the curve at " << j / double(kSteps);
    previous_u = std::max(previous_u, u);
    covered_lo = std::min(covered_lo, u), covered_hi = std::max(covered_hi, u);
  }
  const double mean = sum / (kSteps + 1);
  std::printf("curve image: %u stops, explained %.3f (variance %.3f, MDS energy %.3f), samples from curve %.2f dE, "
              "ramp from true curve: mean %.2f dE, max %.2f dE, covers u %.3f..%.3f\n",
              r.info.stop_count, r.info.explained, r.info.variance_explained, r.info.eigen_energy, r.info.mean_error,
              mean, worst, covered_lo, covered_hi);
  EXPECT_LT(mean, 4.0);
  EXPECT_LT(worst, 12.0);
  // Both ends reached: near black at 0, near white at 1 (the noise pulls the ends in a little).
  EXPECT_LT(covered_lo, 0.06);
  EXPECT_GT(covered_hi, 0.94);
  // Every curve point is near the ramp (no part of the curve is skipped).
  for (int j = 0; j <= 60; ++j) {
    const Lab c = CurveLab(j / 60.0);
    double best = 1e300;
    for (int k = 0; k <= 400; ++k) best = std::min(best, DeltaE(c, RampAt(r.stops, k / 400.0)));
    EXPECT_LT(best, 10.0) << "curve point u = " << j / 60.0 << " is missing from the ramp";
  }
}

// A posterised image (64 flat levels along the curve, as a 64-column gradient): the
// neighbour graph falls into many pieces, joined by short edges: still one variable.
TEST(ColourRamp, PosterisedCurveIsStillExplained) {
  std::vector<float> pixels(4 * 64 * 64);
  for (size_t i = 0; i < 64 * 64; ++i) {
    double c[3];
    Curve(((i % 64) + 0.5) / 64.0, c);
    for (int k = 0; k < 3; ++k) pixels[4 * i + k] = static_cast<float>(ToLinear(c[k]));
    pixels[4 * i + 3] = 1.f;
  }
  moldtex_colour_ramp_desc d;
  moldtex_colour_ramp_desc_init(&d);
  const Ramp r = RunRamp(pixels, d);
  ASSERT_EQ(r.status, MOLDTEX_OK) << LastError();
  std::printf("posterised curve: %u stops, %u pieces, continuity %.3f, explained %.3f\n", r.info.stop_count,
              r.info.component_count, r.info.continuity, r.info.explained);
  EXPECT_GT(r.info.component_count, 1u);
  EXPECT_GT(r.info.explained, 0.8f);
  EXPECT_LT(NearestU(RampAt(r.stops, 0.0), nullptr), 0.05);
  EXPECT_GT(NearestU(RampAt(r.stops, 1.0), nullptr), 0.95);
}

TEST(ColourRamp, ReverseStartsAtTheLighterEnd) {
  const std::vector<float> pixels = CurveImage(50000, 0.02, 2);
  moldtex_colour_ramp_desc d = SrgbDesc();
  const Ramp forward = RunRamp(pixels, d);
  d.reverse = 1;
  const Ramp back = RunRamp(pixels, d);
  ASSERT_EQ(forward.status, MOLDTEX_OK) << LastError();
  ASSERT_EQ(back.status, MOLDTEX_OK) << LastError();
  EXPECT_LT(NearestU(RampAt(forward.stops, 0.0), nullptr), 0.1);
  EXPECT_GT(NearestU(RampAt(back.stops, 0.0), nullptr), 0.9);
  EXPECT_LT(NearestU(RampAt(back.stops, 1.0), nullptr), 0.1);
  for (int j = 0; j <= 20; ++j)
    EXPECT_LT(DeltaE(RampAt(forward.stops, j / 20.0), RampAt(back.stops, 1.0 - j / 20.0)), 3.0);
}

TEST(ColourRamp, PeakAtMovesTheMostSaturatedColour) {
  const std::vector<float> pixels = CurveImage(50000, 0.02, 3);
  for (float peak : {0.2f, 0.8f}) {
    moldtex_colour_ramp_desc d = SrgbDesc();
    d.peak_position = peak;
    const Ramp r = RunRamp(pixels, d);
    ASSERT_EQ(r.status, MOLDTEX_OK) << LastError();
    double best = -1, where = -1;
    for (int j = 0; j <= 200; ++j) {
      const Lab c = RampAt(r.stops, j / 200.0);
      if (std::hypot(c.a, c.b) > best) best = std::hypot(c.a, c.b), where = j / 200.0;
    }
    EXPECT_NEAR(where, peak, 0.03);
  }
}

TEST(ColourRamp, TwoClustersAreExplainedPoorlyButStillGiveARamp) {
  const Ramp r = RunRamp(TwoClusters(100000), [] {
    moldtex_colour_ramp_desc d;
    moldtex_colour_ramp_desc_init(&d);
    return d;
  }());
  ASSERT_EQ(r.status, MOLDTEX_OK) << LastError();
  std::printf("two clusters: %u stops, %u pieces, explained %.3f (variance %.3f, continuity %.3f, MDS energy %.3f)\n",
              r.info.stop_count, r.info.component_count, r.info.explained, r.info.variance_explained,
              r.info.continuity, r.info.eigen_energy);
  EXPECT_GE(r.stops.size(), 2u);
  EXPECT_LE(r.stops.size(), 32u);
  EXPECT_GE(r.info.component_count, 2u);
  EXPECT_LT(r.info.explained, 0.6f);
  for (size_t i = 1; i < r.stops.size(); ++i) EXPECT_GT(r.stops[i].position, r.stops[i - 1].position);
}

TEST(ColourRamp, OneColourGivesAFlatRamp) {
  std::vector<float> pixels(3 * 1000, 0.25f);
  moldtex_colour_ramp_desc d;
  moldtex_colour_ramp_desc_init(&d);
  d.channels = 3;
  const Ramp r = RunRamp(pixels, d);
  ASSERT_EQ(r.status, MOLDTEX_OK) << LastError();
  ASSERT_EQ(r.stops.size(), 2u);
  EXPECT_NEAR(r.stops[0].color[0], 0.25f, 1e-3f);
  EXPECT_NEAR(r.stops[1].color[2], 0.25f, 1e-3f);
}

TEST(ColourRamp, IsDeterministic) {
  const std::vector<float> pixels = CurveImage(30000, 0.05, 4);
  const Ramp a = RunRamp(pixels, SrgbDesc()), b = RunRamp(pixels, SrgbDesc());
  ASSERT_EQ(a.status, MOLDTEX_OK) << LastError();
  ASSERT_EQ(a.stops.size(), b.stops.size());
  EXPECT_EQ(0, std::memcmp(a.stops.data(), b.stops.data(), a.stops.size() * sizeof(moldtex_colour_stop)));
  EXPECT_EQ(0, std::memcmp(&a.info, &b.info, sizeof(a.info)));
}

TEST(ColourRamp, RefusesBadInputsWithMessages) {
  std::vector<float> pixels = CurveImage(1000, 0.02, 5);
  std::vector<moldtex_colour_stop> stops(32);
  moldtex_colour_ramp_desc d = SrgbDesc();
  auto expect_refused = [&](const float* p, size_t count, const moldtex_colour_ramp_desc* desc, uint32_t capacity,
                            const char* words) {
    const moldtex_colour_stop before = stops[0];
    EXPECT_EQ(moldtex_colour_ramp_from_pixels(p, count, desc, stops.data(), capacity, nullptr),
              MOLDTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(moldtex_last_error()).find(words), std::string::npos) << moldtex_last_error();
    EXPECT_EQ(0, std::memcmp(&before, &stops[0], sizeof(before)));
  };
  expect_refused(nullptr, 1000, &d, 32, "pixel array is NULL");
  expect_refused(pixels.data(), 1000, nullptr, 32, "NULL");
  EXPECT_EQ(moldtex_colour_ramp_from_pixels(pixels.data(), 1000, &d, nullptr, 32, nullptr),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
  expect_refused(pixels.data(), 0, &d, 32, "no pixels");
  expect_refused(pixels.data(), 1000, &d, 8, "fewer stops");
  moldtex_colour_ramp_desc bad = d;
  bad.struct_size = 0;
  expect_refused(pixels.data(), 1000, &bad, 32, "struct_size");
  bad = d, bad.channels = 5;
  expect_refused(pixels.data(), 1000, &bad, 32, "channels");
  bad = d, bad.sample_count = 3;
  expect_refused(pixels.data(), 1000, &bad, 32, "sample count");
  bad = d, bad.max_stops = 33;
  expect_refused(pixels.data(), 1000, &bad, 32, "stops");
  bad = d, bad.tolerance = std::nanf("");
  expect_refused(pixels.data(), 1000, &bad, 32, "tolerance");
  bad = d, bad.peak_position = 1.5f;
  expect_refused(pixels.data(), 1000, &bad, 32, "Peak At");
  pixels[4 * 123 + 1] = std::nanf("");
  expect_refused(pixels.data(), 1000, &d, 32, "Pixel 123");
  pixels[4 * 123 + 1] = std::numeric_limits<float>::infinity();
  expect_refused(pixels.data(), 1000, &d, 32, "Pixel 123");
  pixels[4 * 123 + 1] = 0.5f;
  EXPECT_EQ(moldtex_colour_ramp_from_pixels(pixels.data(), 1000, &d, stops.data(), 32, nullptr), MOLDTEX_OK)
      << LastError();
}

// Small random images and options (as the fuzz target does): every call either refuses
// with a message or gives 2..max_stops increasing stops with finite colours >= 0.
TEST(ColourRamp, SmallRandomInputsGiveValidRampsOrMessages) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(-0.5f, 3.f);
  int accepted = 0;
  for (int trial = 0; trial < 300; ++trial) {
    moldtex_colour_ramp_desc d;
    moldtex_colour_ramp_desc_init(&d);
    d.channels = 3 + rng() % 2;
    d.sample_count = 16 + rng() % 200;
    d.neighbour_count = 2 + rng() % 20;
    d.max_stops = 2 + rng() % 31;
    d.reverse = rng() % 2;
    d.srgb_encoded = rng() % 2;
    d.tolerance = 0.1f + static_cast<float>(rng() % 50);
    d.peak_position = (rng() % 3 == 0) ? static_cast<float>(rng() % 101) / 100.f : -1.f;
    const size_t count = rng() % 300;
    const uint32_t distinct = 1 + rng() % 6;  // few distinct colours: duplicates galore
    std::vector<float> palette(3 * distinct);
    for (float& v : palette) v = value(rng);
    std::vector<float> pixels(count * d.channels);
    for (size_t i = 0; i < count; ++i)
      for (uint32_t c = 0; c < d.channels; ++c) pixels[i * d.channels + c] = c < 3 ? palette[3 * (rng() % distinct) + c] : 1.f;
    std::vector<moldtex_colour_stop> stops(32);
    moldtex_colour_ramp_info info;
    moldtex_colour_ramp_info_init(&info);
    const moldtex_status st = moldtex_colour_ramp_from_pixels(pixels.data(), count, &d, stops.data(), 32, &info);
    if (st != MOLDTEX_OK) {
      EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_ARGUMENT);
      EXPECT_STRNE(moldtex_last_error(), "");
      continue;
    }
    ++accepted;
    ASSERT_GE(info.stop_count, 2u);
    ASSERT_LE(info.stop_count, d.max_stops);
    for (uint32_t i = 0; i < info.stop_count; ++i) {
      EXPECT_GE(stops[i].position, 0.f);
      EXPECT_LE(stops[i].position, 1.f);
      if (i > 0) {
        EXPECT_GT(stops[i].position, stops[i - 1].position);
      }
      for (float c : stops[i].color) EXPECT_TRUE(std::isfinite(c) && c >= 0.f);
    }
    EXPECT_GE(info.explained, 0.f);
    EXPECT_LE(info.explained, 1.f);
  }
  EXPECT_GT(accepted, 250);
}

TEST(ColourRamp, A4KImageTakesAboutASecond) {
  const size_t w = 3840, h = 2160;
  std::vector<float> pixels = CurveImage(w * h, 0.03, 6);
  moldtex_colour_ramp_desc d = SrgbDesc();
  const auto start = std::chrono::steady_clock::now();
  const Ramp r = RunRamp(pixels, d);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.status, MOLDTEX_OK) << LastError();
  std::printf("4K image (%zux%zu RGBA), %u samples: %.3f s, %u stops\n", w, h, r.info.sample_count, seconds,
              r.info.stop_count);
  EXPECT_LT(seconds, 10.0);  // ~1 s expected; generous for a shared machine
}

}  // namespace
}  // namespace mtx
