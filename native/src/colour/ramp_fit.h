// Colour map from an image (Layton et al. §3.4): subsample the pixels, Isomap them to one
// coordinate in CIELAB, fit a smooth curve per Lab channel over that coordinate, and
// place ColorRamp stops where linear interpolation between stops strays most from the
// curve.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "colour/colour_space.h"

namespace moldtex::colour {

struct RampOptions {
  uint32_t channels = 4;        // floats per pixel (3 or 4; the 4th is ignored)
  bool srgb_encoded = false;    // pixel values are sRGB-encoded (else linear)
  uint32_t sample_count = 1500; // pixels used (evenly spread, jittered by seed)
  uint32_t neighbour_count = 10;
  uint32_t max_stops = 32;      // 2..32
  double tolerance = 1.0;       // Delta E at which stop placement stops
  bool reverse = false;         // false: the darker end of the curve at 0
  double peak_position = -1.0;  // < 0: off; else the most saturated colour moves here
  uint64_t seed = 0x6d6f6c64;
};

struct RampStop {
  float position;
  float rgb[3];  // linear RGB
};

struct RampResult {
  std::vector<RampStop> stops;
  size_t sample_count = 0;
  size_t component_count = 0;
  double explained = 0;       // variance_explained * continuity
  double variance_explained = 0;
  double continuity = 0;      // 1 - longest bridge between graph pieces / coordinate extent
  double eigen_energy = 0;
  double mean_error = 0;      // mean Delta E of the samples from the curve
  double ramp_error = 0;      // max Delta E of the ramp from the curve
};

// Deterministic stratified subsample of `count` pixel indices out of pixel_count.
std::vector<size_t> subsample_indices(size_t pixel_count, size_t count, uint64_t seed);

RampResult colour_ramp_from_pixels(const float* pixels, size_t pixel_count, const RampOptions& options);

}  // namespace moldtex::colour
