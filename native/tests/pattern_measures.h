// Pattern measures on the texture, in 3D: where each texel centre lies on the mesh and
// what area it covers, area-weighted means, and a characteristic length (first zero of
// the autocorrelation, measured in 3D). Shared by the pattern tests of both models.
#pragma once
#include <functional>
#include <vector>

#include "mesh_fixtures.h"

namespace mtx {

// 3D position of every texel centre that lies in a UV triangle (NaN elsewhere) and
// the 3D area a texel covers there (0 elsewhere), from the mesh itself.
struct TexelGeometry {
  uint32_t width = 0, height = 0;
  std::vector<Vec3> position;
  std::vector<double> area;
  std::vector<int> triangle;
  bool inside(size_t i) const { return triangle[i] >= 0; }
};

TexelGeometry Texels(const Mesh& m, uint32_t W, uint32_t H);

// The mean 3D side of a texel of a size x size texture on m's UV layout: the length unit
// of one texel per pattern unit.
double TexelLength(const Mesh& m, uint32_t size);

// Area-weighted mean of `field` over the texels inside islands where in(x, y).
double Mean(const TexelGeometry& g, const std::vector<double>& field,
            const std::function<bool(uint32_t x, uint32_t y)>& in);

// Characteristic length: the 3D distance of the first zero of the field's
// autocorrelation, from texel pairs along both texel axes binned by the 3D distance of
// their centres (bins of `bin` mesh units), with linear interpolation in the crossing
// bin.
// With `level` > 0: the first crossing of that level instead of zero (e.g. 0.5: the
// half-decay distance, set by the trails' width and spacing, steadier than the zero).
double CharacteristicLength(const TexelGeometry& g, const std::vector<double>& f, double bin,
                            double max_distance, double level = 0.0);

// Gradient length: mean(f) / mean |df/ds|, the slope measured along the texel axes
// between neighbouring texel centres by their 3D distance (area-weighted). A sum of local
// terms, so its sampling noise falls with the surface area like a mean's, unlike a
// correlation length set by the few largest structures. For a pattern of trails it is
// proportional to the spacing of the trails (fewer trail edges per area: longer).
double GradientLength(const TexelGeometry& g, const std::vector<double>& f);
// The same over the texels where in(x, y) (pairs whose first texel is in).
double GradientLength(const TexelGeometry& g, const std::vector<double>& f,
                      const std::function<bool(uint32_t x, uint32_t y)>& in);

}  // namespace mtx
