#include "models/gray_scott/reaction_paint.h"

#include <vector>

#include "brush/brush.h"
#include "models/gray_scott/reaction_diffusion.h"

namespace moldtex {

uint32_t paint_reaction(const Surface& s, const TextureDomain& d, float* planes, const moldtex_brush& brush,
                        bool erase, ReactionUndo& undo, ThreadPool& pool) {
  const size_t texels = d.texel_count();
  // The dab's weights w(d / radius), as moldtex_surface_paint finds them: painted at
  // full strength toward 1 into an empty image.
  std::vector<float> weights(texels * 4, 0.f);
  moldtex_brush unit = brush;
  unit.strength = 1.f;
  unit.mode = MOLDTEX_BRUSH_PAINT;
  unit.channel = 0;
  unit.value = 1.f;
  paint_dab(s, d.width, d.height, weights.data(), unit);
  float* v = planes + kReactionV * texels;
  float* u = planes + kReactionU * texels;
  const float target_v = erase ? 0.f : 1.f, target_u = erase ? 1.f : 0.5f;
  uint32_t changed = 0;
  for (size_t i = 0; i < texels; ++i) {
    const float a = brush.strength * weights[4 * i];
    if (!(a > 0.f) || d.classes[i] != MOLDTEX_TEXEL_INSIDE) continue;
    undo.emplace(static_cast<uint32_t>(i), std::array<float, 2>{v[i], u[i]});
    const float nv = v[i] + (target_v - v[i]) * a, nu = u[i] + (target_u - u[i]) * a;
    changed += nv != v[i] || nu != u[i];
    v[i] = nv;
    u[i] = nu;
  }
  fill_gutter(d, v, pool);
  fill_gutter(d, u, pool);
  return changed;
}

void restore_reaction(const TextureDomain& d, float* planes, const ReactionUndo& undo, ThreadPool& pool) {
  const size_t texels = d.texel_count();
  float* v = planes + kReactionV * texels;
  float* u = planes + kReactionU * texels;
  for (const auto& [i, old] : undo) {
    v[i] = old[0];
    u[i] = old[1];
  }
  fill_gutter(d, v, pool);
  fill_gutter(d, u, pool);
}

}  // namespace moldtex
