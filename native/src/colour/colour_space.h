// Colour spaces of the colour-map extraction: sRGB-encoded <-> linear RGB (Rec. 709
// primaries, D65, Blender's scene linear) <-> CIELAB (D65 white), and CIE76 Delta E.
#pragma once

namespace moldtex::colour {

struct Lab {
  double L = 0, a = 0, b = 0;
};

// sRGB transfer function (IEC 61966-2-1) and its inverse; negative inputs give 0.
double srgb_to_linear(double v);
double linear_to_srgb(double v);

// Linear RGB -> CIELAB. Negative channels are clamped to 0 (Lab of HDR values > 1 is
// still defined: L* > 100).
Lab linear_to_lab(double r, double g, double b);
// CIELAB -> linear RGB (may be outside [0, 1] for colours outside the sRGB gamut).
void lab_to_linear(const Lab& lab, double rgb[3]);

// CIE76 colour difference (Euclidean distance in Lab); ~1 is just noticeable.
double delta_e(const Lab& x, const Lab& y);
double delta_e_squared(const Lab& x, const Lab& y);
// Chroma C* = sqrt(a*^2 + b*^2) (how saturated a colour looks).
double chroma(const Lab& x);

}  // namespace moldtex::colour
