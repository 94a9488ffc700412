#include "colour/ramp_fit.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "colour/isomap.h"
#include "common/rng.h"

namespace moldtex::colour {
namespace {

constexpr size_t kBins = 48;        // curve knots over the Isomap coordinate
constexpr size_t kDense = 512;      // curve samples that stops are chosen from

Lab lerp(const Lab& x, const Lab& y, double w) {
  return Lab{x.L + w * (y.L - x.L), x.a + w * (y.a - x.a), x.b + w * (y.b - x.b)};
}

// Uniform Catmull-Rom through knots k[0..m-1] at parameters i / (m - 1), clamped ends.
Lab catmull_rom(const std::vector<Lab>& k, double t) {
  const size_t m = k.size();
  if (m == 1) return k[0];
  const double x = std::clamp(t, 0.0, 1.0) * static_cast<double>(m - 1);
  const size_t i = std::min(static_cast<size_t>(x), m - 2);
  const double u = x - static_cast<double>(i);
  const Lab& p0 = k[i == 0 ? 0 : i - 1];
  const Lab& p1 = k[i];
  const Lab& p2 = k[i + 1];
  const Lab& p3 = k[std::min(i + 2, m - 1)];
  auto c = [u](double a, double b, double c_, double d) {
    return 0.5 * ((2 * b) + (-a + c_) * u + (2 * a - 5 * b + 4 * c_ - d) * u * u +
                  (-a + 3 * b - 3 * c_ + d) * u * u * u);
  };
  return Lab{c(p0.L, p1.L, p2.L, p3.L), c(p0.a, p1.a, p2.a, p3.a), c(p0.b, p1.b, p2.b, p3.b)};
}

// Knots: the mean Lab of the samples in each of kBins equal bins of t in [0, 1] (empty
// bins interpolated from their neighbours), then smoothed with a [1 2 1] / 4 filter.
std::vector<Lab> fit_knots(const std::vector<Lab>& lab, const std::vector<double>& t) {
  std::vector<Lab> sum(kBins);
  std::vector<double> weight(kBins, 0.0);
  for (size_t i = 0; i < lab.size(); ++i) {
    const size_t bin = std::min(kBins - 1, static_cast<size_t>(t[i] * static_cast<double>(kBins)));
    sum[bin].L += lab[i].L, sum[bin].a += lab[i].a, sum[bin].b += lab[i].b;
    weight[bin] += 1.0;
  }
  std::vector<Lab> knot(kBins);
  std::vector<size_t> filled;
  for (size_t j = 0; j < kBins; ++j)
    if (weight[j] > 0) {
      knot[j] = Lab{sum[j].L / weight[j], sum[j].a / weight[j], sum[j].b / weight[j]};
      filled.push_back(j);
    }
  // (t spans [0, 1], so the first and last bins hold samples.)
  for (size_t f = 0; f + 1 < filled.size(); ++f)
    for (size_t j = filled[f] + 1; j < filled[f + 1]; ++j)
      knot[j] = lerp(knot[filled[f]], knot[filled[f + 1]],
                     static_cast<double>(j - filled[f]) / static_cast<double>(filled[f + 1] - filled[f]));
  for (size_t j = 0; j < filled.front(); ++j) knot[j] = knot[filled.front()];
  for (size_t j = filled.back() + 1; j < kBins; ++j) knot[j] = knot[filled.back()];
  std::vector<Lab> smooth(kBins);
  for (size_t j = 0; j < kBins; ++j) {
    const Lab& a = knot[j == 0 ? 0 : j - 1];
    const Lab& c = knot[std::min(j + 1, kBins - 1)];
    smooth[j] = Lab{0.25 * a.L + 0.5 * knot[j].L + 0.25 * c.L, 0.25 * a.a + 0.5 * knot[j].a + 0.25 * c.a,
                    0.25 * a.b + 0.5 * knot[j].b + 0.25 * c.b};
  }
  // Keep the ends where the data ends (the filter pulls them inward).
  smooth.front() = lerp(knot.front(), smooth.front(), 0.5);
  smooth.back() = lerp(knot.back(), smooth.back(), 0.5);
  return smooth;
}

// Linear RGB of a Lab colour, clamped to >= 0, and the Lab of that (what a ramp stop
// stores and shows).
void to_rgb(const Lab& lab, float rgb[3]) {
  double c[3];
  lab_to_linear(lab, c);
  for (int i = 0; i < 3; ++i) rgb[i] = static_cast<float>(std::max(0.0, c[i]));
}

}  // namespace

std::vector<size_t> subsample_indices(size_t pixel_count, size_t count, uint64_t seed) {
  std::vector<size_t> out;
  if (pixel_count == 0) return out;
  if (count >= pixel_count) {
    for (size_t i = 0; i < pixel_count; ++i) out.push_back(i);
    return out;
  }
  out.reserve(count);
  const double stride = static_cast<double>(pixel_count) / static_cast<double>(count);
  for (size_t i = 0; i < count; ++i) {
    CounterRng rng(seed, 0x636f6c6f7572ull, 0, i);
    const double x = (static_cast<double>(i) + rng.next_double()) * stride;
    out.push_back(std::min(pixel_count - 1, static_cast<size_t>(x)));
  }
  return out;
}

RampResult colour_ramp_from_pixels(const float* pixels, size_t pixel_count, const RampOptions& o) {
  RampResult result;
  const std::vector<size_t> picks = subsample_indices(pixel_count, o.sample_count, o.seed);
  const size_t n = picks.size();
  std::vector<Lab> lab(n);
  for (size_t i = 0; i < n; ++i) {
    const float* p = pixels + picks[i] * o.channels;
    double c[3] = {p[0], p[1], p[2]};
    if (o.srgb_encoded)
      for (double& v : c) v = srgb_to_linear(v);
    lab[i] = linear_to_lab(c[0], c[1], c[2]);
  }
  result.sample_count = n;

  Lab mean;
  for (const Lab& x : lab) mean.L += x.L, mean.a += x.a, mean.b += x.b;
  mean.L /= static_cast<double>(n), mean.a /= static_cast<double>(n), mean.b /= static_cast<double>(n);
  double total = 0.0;
  for (const Lab& x : lab) total += delta_e_squared(x, mean);
  total /= static_cast<double>(n);

  std::vector<Lab> knots;
  if (n < 3 || total < 1e-6) {  // one colour (or nearly): a flat ramp
    knots.assign(2, mean);
    result.component_count = 1;
    result.explained = result.variance_explained = result.eigen_energy = result.continuity = 1.0;
  } else {
    const Isomap1D iso = isomap_1d(lab, std::min<size_t>(o.neighbour_count, n - 1));
    result.component_count = iso.component_count;
    result.eigen_energy = iso.eigen_energy;
    // Normalise to [0, 1] between the 0.5th and 99.5th percentiles (a few outliers do
    // not squeeze the ramp), clamping the rest.
    std::vector<double> sorted = iso.coordinate;
    std::sort(sorted.begin(), sorted.end());
    const double lo = sorted[static_cast<size_t>(0.005 * static_cast<double>(n - 1))];
    const double hi = sorted[static_cast<size_t>(std::ceil(0.995 * static_cast<double>(n - 1)))];
    std::vector<double> t(n, 0.5);
    if (hi > lo)
      for (size_t i = 0; i < n; ++i) t[i] = std::clamp((iso.coordinate[i] - lo) / (hi - lo), 0.0, 1.0);
    knots = fit_knots(lab, t);
    // Convention: the darker end (lower L*) first; reverse flips it.
    if (knots.front().L > knots.back().L) {
      std::reverse(knots.begin(), knots.end());
      for (double& x : t) x = 1.0 - x;
    }
    double residual = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const double e2 = delta_e_squared(lab[i], catmull_rom(knots, t[i]));
      residual += e2;
      result.mean_error += std::sqrt(e2);
    }
    residual /= static_cast<double>(n);
    result.mean_error /= static_cast<double>(n);
    result.variance_explained = std::clamp(1.0 - residual / total, 0.0, 1.0);
    // A jump: the longest edge that had to join separate pieces of the neighbour graph,
    // as a share of the whole coordinate's extent (many small pieces, as in a
    // posterised image, join with short edges and barely count).
    const double extent = sorted.back() - sorted.front();
    result.continuity = extent > 0.0 ? std::clamp(1.0 - iso.largest_bridge / extent, 0.0, 1.0) : 1.0;
    result.explained = result.variance_explained * result.continuity;
  }
  if (o.reverse) std::reverse(knots.begin(), knots.end());

  // The ramp position s -> curve parameter: identity, or (Peak at) piecewise linear
  // so that the most saturated point of the curve sits at peak_position.
  double peak_t = 0.0, peak_chroma = -1.0;
  for (size_t j = 0; j <= kDense; ++j) {
    const double t = static_cast<double>(j) / kDense;
    const double c = chroma(catmull_rom(knots, t));
    if (c > peak_chroma) peak_chroma = c, peak_t = t;
  }
  const double p = o.peak_position;
  auto curve_t = [&](double s) {
    if (p < 0.0) return s;
    if (s <= p) return p > 0.0 ? s / p * peak_t : peak_t;
    return peak_t + (s - p) / (1.0 - p) * (1.0 - peak_t);
  };

  // Dense curve, as a stop would store it (linear RGB >= 0) and its Lab.
  std::vector<Lab> dense(kDense + 1);
  std::vector<std::array<float, 3>> dense_rgb(kDense + 1);
  for (size_t j = 0; j <= kDense; ++j) {
    to_rgb(catmull_rom(knots, curve_t(static_cast<double>(j) / kDense)), dense_rgb[j].data());
    dense[j] = linear_to_lab(dense_rgb[j][0], dense_rgb[j][1], dense_rgb[j][2]);
  }
  // Greedy stops: the ends, then the dense point where the ramp (linear in RGB between
  // stops, as Blender's ColorRamp interpolates) strays most from the curve, until the
  // largest error is below tolerance or max_stops are used.
  std::vector<size_t> chosen = {0, kDense};
  auto worst = [&](size_t& where) {
    double worst_error = 0.0;
    where = kDense + 1;
    for (size_t s = 0; s + 1 < chosen.size(); ++s) {
      const size_t a = chosen[s], b = chosen[s + 1];
      for (size_t j = a + 1; j < b; ++j) {
        const double w = static_cast<double>(j - a) / static_cast<double>(b - a);
        double c[3];
        for (int k = 0; k < 3; ++k) c[k] = dense_rgb[a][k] + w * (dense_rgb[b][k] - dense_rgb[a][k]);
        const double e = delta_e(linear_to_lab(c[0], c[1], c[2]), dense[j]);
        if (e > worst_error) worst_error = e, where = j;
      }
    }
    return worst_error;
  };
  size_t where = 0;
  double error = worst(where);
  while (chosen.size() < o.max_stops && error > o.tolerance && where <= kDense) {
    chosen.insert(std::upper_bound(chosen.begin(), chosen.end(), where), where);
    error = worst(where);
  }
  result.ramp_error = error;
  for (size_t j : chosen) {
    RampStop stop;
    stop.position = static_cast<float>(static_cast<double>(j) / kDense);
    std::copy(dense_rgb[j].begin(), dense_rgb[j].end(), stop.rgb);
    result.stops.push_back(stop);
  }
  return result;
}

}  // namespace moldtex::colour
