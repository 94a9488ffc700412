#include "colour/colour_space.h"

#include <algorithm>
#include <cmath>

namespace moldtex::colour {
namespace {

// D65 reference white (XYZ, Y = 1).
constexpr double kXn = 0.95047, kYn = 1.0, kZn = 1.08883;
constexpr double kDelta = 6.0 / 29.0;

double f_lab(double t) {
  return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
}
double f_lab_inverse(double f) {
  return f > kDelta ? f * f * f : 3.0 * kDelta * kDelta * (f - 4.0 / 29.0);
}

}  // namespace

double srgb_to_linear(double v) {
  if (!(v > 0.0)) return 0.0;
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

double linear_to_srgb(double v) {
  if (!(v > 0.0)) return 0.0;
  return v <= 0.0031308 ? v * 12.92 : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

Lab linear_to_lab(double r, double g, double b) {
  r = std::max(r, 0.0);
  g = std::max(g, 0.0);
  b = std::max(b, 0.0);
  const double x = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
  const double fx = f_lab(x / kXn), fy = f_lab(y / kYn), fz = f_lab(z / kZn);
  return Lab{116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

void lab_to_linear(const Lab& lab, double rgb[3]) {
  const double fy = (lab.L + 16.0) / 116.0;
  const double fx = fy + lab.a / 500.0;
  const double fz = fy - lab.b / 200.0;
  const double x = kXn * f_lab_inverse(fx), y = kYn * f_lab_inverse(fy), z = kZn * f_lab_inverse(fz);
  rgb[0] = 3.2404542 * x - 1.5371385 * y - 0.4985314 * z;
  rgb[1] = -0.9692660 * x + 1.8760108 * y + 0.0415560 * z;
  rgb[2] = 0.0556434 * x - 0.2040259 * y + 1.0572252 * z;
}

double delta_e_squared(const Lab& x, const Lab& y) {
  const double dl = x.L - y.L, da = x.a - y.a, db = x.b - y.b;
  return dl * dl + da * da + db * db;
}

double delta_e(const Lab& x, const Lab& y) { return std::sqrt(delta_e_squared(x, y)); }

double chroma(const Lab& x) { return std::hypot(x.a, x.b); }

}  // namespace moldtex::colour
