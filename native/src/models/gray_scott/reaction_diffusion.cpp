#include "models/gray_scott/reaction_diffusion.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "agents/agents.h"
#include "common/error.h"
#include "shared/reaction.h"

namespace moldtex {

namespace {

void check(const char* name, float value, float lo, float hi, bool open_lo = false) {
  if (!std::isfinite(value) || value < lo || value > hi || (open_lo && value == lo)) {
    std::ostringstream m;
    m << "moldtex_reaction_params." << name << " must be a number " << (open_lo ? "> " : "between ")
      << lo << (open_lo ? " and <= " : " and ") << hi << " (got " << value << ")";
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, m.str());
  }
}

}  // namespace

void validate_reaction_params(const moldtex_reaction_params& p) {
  if (p.struct_size < sizeof(moldtex_reaction_params))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "moldtex_reaction_params.struct_size is too small: call moldtex_reaction_params_init first");
  check("feed", p.feed, 0.f, 1.f);
  check("kill", p.kill, 0.f, 1.f);
  check("diffusion_u", p.diffusion_u, 0.f, 1e6f);
  check("diffusion_v", p.diffusion_v, 0.f, 1e6f);
  check("time_step", p.time_step, 0.f, 100.f, true);
  check("seed_radius", p.seed_radius, 0.f, 1e30f, true);
  if (p.seed_count < 1 || p.seed_count > 1024)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "moldtex_reaction_params.seed_count must be between 1 and 1024 (got " +
                                             std::to_string(p.seed_count) + ")");
}

ReactionMaps reaction_maps(const std::vector<float>& feed_map, float feed_largest, const std::vector<float>& kill_map,
                           float kill_largest, const moldtex_reaction_params& p) {
  ReactionMaps m;
  m.feed_max = p.feed;
  m.kill_max = p.kill;
  if (!feed_map.empty()) {
    m.feed = feed_map.data();
    m.feed_max = std::min(1.f, p.feed * feed_largest);
  }
  if (!kill_map.empty()) {
    m.kill = kill_map.data();
    m.kill_max = std::min(1.f, p.kill * kill_largest);
  }
  return m;
}

uint32_t reaction_substeps(const TexelLaplacian& lap, const moldtex_reaction_params& p, const ReactionMaps& maps) {
  const double dt = p.time_step;
  // Enough for 99% of the cells, but at most 4x what the median cell needs: the stiffer
  // rest (UV poles, where texels get very thin) take their own loss implicitly (see
  // shared/reaction.h) rather than setting the sub-steps of all.
  double typical = lap.max_rate, median = lap.max_rate;
  if (!lap.sorted_rate.empty()) {
    const size_t n = lap.sorted_rate.size() - 1;
    typical = lap.sorted_rate[static_cast<size_t>(0.99 * double(n))];
    median = lap.sorted_rate[n / 2];
  }
  const double d_max = std::max(p.diffusion_u, p.diffusion_v) * dt / 0.5;
  const double diffusion = std::min(d_max * typical, 4.0 * std::max(1.0, std::ceil(d_max * median)));
  const double feed = maps.feed ? maps.feed_max : p.feed, kill = maps.kill ? maps.kill_max : p.kill;
  const double reaction = (1.0 + feed + kill) * dt / 0.5;
  const double x = std::max({1.0, diffusion, reaction});
  if (!(x <= kMaxReactionSubsteps)) {
    std::ostringstream m;
    m << "Gray-Scott would need " << (std::isfinite(x) && x < 4e9 ? std::to_string(uint64_t(std::ceil(x)))
                                                                     : std::string("billions of"))
      << " sub-steps per step to stay stable (at most " << kMaxReactionSubsteps
      << "): lower the time step or the diffusion rates, or use a texture with fewer, larger texels";
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, m.str());
  }
  return static_cast<uint32_t>(std::ceil(x));
}

std::vector<float> reaction_initial_state(const Surface& surface, const TextureDomain& d,
                                          const moldtex_reaction_params& p, uint64_t seed,
                                          const std::vector<double>* texel_weights, ThreadPool& pool) {
  const size_t texels = d.texel_count();
  std::vector<float> planes(texels * kReactionPlanes, 0.f);
  float* v = planes.data() + kReactionV * texels;
  float* u = planes.data() + kReactionU * texels;
  for (size_t i = 0; i < texels; ++i)
    if (d.classes[i] != MOLDTEX_TEXEL_OUTSIDE) u[i] = 1.f;
  // The seed points, as agents would be spawned (a pure function of the seed).
  SpawnSpec spec;
  spec.count = p.seed_count;
  spec.seed = seed;
  spec.shape = texel_weights ? MOLDTEX_SEED_SPAWN_MAP : MOLDTEX_SEED_RANDOM;
  spec.texel_weights = texel_weights;
  spec.texel_triangle = &d.texel_triangle;
  spec.width = d.width;
  spec.height = d.height;
  const Agents points = spawn_agents(surface, spec, pool);
  std::vector<float> centres(points.size() * 3);
  for (size_t s = 0; s < points.size(); ++s) {
    const Walker w = points.load(s);
    float uv[2];
    surface.evaluate(w.triangle, w.bary, &centres[3 * s], uv);
  }
  const double r2 = double(p.seed_radius) * p.seed_radius;
  pool.parallel_for(texels, 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      if (d.classes[i] != MOLDTEX_TEXEL_INSIDE || d.texel_triangle[i] < 0) continue;
      const uint32_t t = static_cast<uint32_t>(d.texel_triangle[i]);
      // Barycentrics of the texel centre in its triangle's UVs.
      const float* c = &surface.corner_uvs[6 * size_t(t)];
      const double x = (double(i % d.width) + 0.5) / d.width, y = (double(i / d.width) + 0.5) / d.height;
      const double e1x = c[2] - c[0], e1y = c[3] - c[1], e2x = c[4] - c[0], e2y = c[5] - c[1];
      const double det = e1x * e2y - e2x * e1y;
      if (!(std::fabs(det) > 0)) continue;
      double b1 = ((x - c[0]) * e2y - e2x * (y - c[1])) / det;
      double b2 = (e1x * (y - c[1]) - (x - c[0]) * e1y) / det;
      b1 = std::clamp(b1, 0.0, 1.0);
      b2 = std::clamp(b2, 0.0, 1.0 - b1);
      const float bary[3] = {float(1.0 - b1 - b2), float(b1), float(b2)};
      float pos[3], uvo[2];
      surface.evaluate(t, bary, pos, uvo);
      for (size_t s = 0; s < points.size(); ++s) {
        const double dx = pos[0] - centres[3 * s], dy = pos[1] - centres[3 * s + 1],
                     dz = pos[2] - centres[3 * s + 2];
        if (dx * dx + dy * dy + dz * dz <= r2) {
          v[i] = 1.f;
          u[i] = 0.5f;
          break;
        }
      }
    }
  });
  fill_gutter(d, v, pool);
  fill_gutter(d, u, pool);
  return planes;
}

void reaction_step(const TexelLaplacian& lap, const moldtex_reaction_params& p, float* planes,
                   std::vector<float>& scratch, size_t texels, ThreadPool& pool, const ReactionMaps& maps) {
  const uint32_t n = reaction_substeps(lap, p, maps);
  if (scratch.size() < texels * kReactionPlanes) scratch.assign(texels * kReactionPlanes, 0.f);
  const float h = static_cast<float>(double(p.time_step) / n);
  const float du = static_cast<float>(double(p.diffusion_u) * p.time_step / n);
  const float dv = static_cast<float>(double(p.diffusion_v) * p.time_step / n);
  float* in = planes;
  float* out = scratch.data();
  for (uint32_t s = 0; s < n; ++s) {
    pool.parallel_for(lap.rows.size(), 2048, [&](size_t begin, size_t end) {
      for (size_t r = begin; r < end; ++r)
        mtx_gray_scott_cell(lap.rows.data(), lap.start.data(), lap.col.data(), lap.weight.data(),
                            lap.area.data(), lap.rate.data(), in + kReactionV * texels, in + kReactionU * texels,
                            out + kReactionV * texels, out + kReactionU * texels, static_cast<mtx_u32>(r), h,
                            du, dv, p.feed, p.kill, maps.feed, maps.kill, maps.feed != nullptr,
                            maps.kill != nullptr);
    });
    std::swap(in, out);
  }
  if (in != planes)
    for (uint32_t r : lap.rows) {
      planes[kReactionV * texels + r] = in[kReactionV * texels + r];
      planes[kReactionU * texels + r] = in[kReactionU * texels + r];
    }
}

}  // namespace moldtex
