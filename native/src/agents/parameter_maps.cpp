#include "agents/parameter_maps.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "shared/momas.h"

namespace moldtex {

namespace {

// Largest multiplier a map may hold: a parameter times it must stay within the
// parameter's own hard range (moldtex_continuous_params), so maps are bounded alike.
constexpr float kMaxMultiplier = 1e3f;
constexpr float kMaxStimulus = 1e6f;


// Barycentric sample points of a triangle: the 10 points of the cubic lattice, pulled
// 10% toward the centroid so none sits on an edge (the texel there may be the
// neighbour's).
constexpr int kSamples = 10;
void sample_bary(int i, float out[3]) {
  static const int lattice[kSamples][3] = {{3, 0, 0}, {0, 3, 0}, {0, 0, 3}, {2, 1, 0}, {1, 2, 0},
                                           {0, 2, 1}, {0, 1, 2}, {1, 0, 2}, {2, 0, 1}, {1, 1, 1}};
  for (int k = 0; k < 3; ++k) out[k] = 0.9f * lattice[i][k] / 3.f + 0.1f / 3.f;
}

uint32_t texel_at(const Surface& s, uint32_t t, const float bary[3], uint32_t width, uint32_t height) {
  Walker w{};
  w.triangle = t;
  std::copy(bary, bary + 3, w.bary);
  return mtx_walker_texel(s.corner_uvs.data(), &w, width, height);
}

}  // namespace

std::vector<float> decay_corrections(const std::vector<float>& decay_map, double r_dec_dt) {
  std::vector<float> f(decay_map.size());
  for (size_t i = 0; i < f.size(); ++i) f[i] = static_cast<float>(std::exp(-r_dec_dt * (double(decay_map[i]) - 1.0)));
  return f;
}

const TexelLaplacian& laplacian_for(const ParameterMaps& maps, const TexelLaplacian& base, MappedLaplacian& cache) {
  if (maps.diffusion().empty()) return base;
  if (!cache.lap || cache.source != &maps || cache.version != maps.version) {
    cache.lap = std::make_unique<TexelLaplacian>(with_diffusion_map(base, maps.diffusion()));
    cache.source = &maps;
    cache.version = maps.version;
  }
  return *cache.lap;
}

const std::vector<float>& decay_for(const ParameterMaps& maps, double r_dec_dt, MappedLaplacian& cache) {
  if (maps.decay().empty()) {
    cache.decay.clear();
    cache.decay_source = nullptr;
    return cache.decay;
  }
  if (cache.decay.empty() || cache.decay_source != &maps || cache.decay_version != maps.version ||
      cache.decay_key != r_dec_dt) {
    cache.decay = decay_corrections(maps.decay(), r_dec_dt);
    cache.decay_source = &maps;
    cache.decay_version = maps.version;
    cache.decay_key = r_dec_dt;
  }
  return cache.decay;
}

const char* map_name(uint32_t kind) {
  switch (kind) {
    case MOLDTEX_MAP_MOVE_RATE: return "move rate";
    case MOLDTEX_MAP_TURN_RATE: return "turn rate";
    case MOLDTEX_MAP_SENSOR_DISTANCE: return "sensor distance";
    case MOLDTEX_MAP_SENSOR_ANGLE: return "sensor angle";
    case MOLDTEX_MAP_DEPOSIT_RATE: return "deposit rate";
    case MOLDTEX_MAP_MEAN_LIFETIME: return "mean lifetime";
    case MOLDTEX_MAP_ACTIVATION_TIME: return "activation time";
    case MOLDTEX_MAP_SPAWN: return "spawn weight";
    case MOLDTEX_MAP_READ_STIMULUS: return "read stimulus";
    case MOLDTEX_MAP_WRITE_STIMULUS: return "write stimulus";
    case MOLDTEX_MAP_DIFFUSION_RATE: return "diffusion rate";
    case MOLDTEX_MAP_DECAY_RATE: return "decay rate";
    case MOLDTEX_MAP_FEED: return "feed";
    case MOLDTEX_MAP_KILL: return "kill";
    default: return "unknown";
  }
}

void validate_map(uint32_t kind, const float* values, size_t count, size_t texels) {
  if (kind >= MOLDTEX_MAP_COUNT)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Unknown map " + std::to_string(kind) + " (maps are 0 .. " +
                                             std::to_string(MOLDTEX_MAP_COUNT - 1) + ", moldtex_map)");
  if (!values) return;
  if (count != texels)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, std::string("The ") + map_name(kind) + " map needs width * height = " +
                                             std::to_string(texels) + " values, got " + std::to_string(count));
  const bool signed_map = kind == MOLDTEX_MAP_READ_STIMULUS || kind == MOLDTEX_MAP_WRITE_STIMULUS;
  const float lo = signed_map ? -kMaxStimulus : 0.f, hi = signed_map ? kMaxStimulus : kMaxMultiplier;
  for (size_t i = 0; i < count; ++i)
    if (!(values[i] >= lo && values[i] <= hi))
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
           std::string("The ") + map_name(kind) + " map holds " + std::to_string(values[i]) + " at texel " +
               std::to_string(i) + ": its values must be finite, " +
               (signed_map ? "within +-1e6" : "from 0 (none) to 1000 (times the parameter)"));
}

void set_parameter_map(ParameterMaps& m, uint32_t kind, const float* values, const Surface& s,
                       const TextureDomain& d) {
  const size_t texels = d.texel_count();
  validate_map(kind, values, texels, texels);
  std::vector<float> given = values ? std::vector<float>(values, values + texels) : std::vector<float>{};
  // The gutter holds the texel across its seam, as the pheromone's does.
  for (size_t g = 0; g < d.gutter_texel.size() && !given.empty(); ++g)
    given[d.gutter_texel[g]] = given[d.gutter_source[g]];
  if (kind == MOLDTEX_MAP_SPAWN && !given.empty()) {
    // Per triangle: the weights of its texels and of its sample points.
    const uint32_t n = s.triangle_count();
    std::vector<double> sum(n, 0.0), weight(n, 0.0);
    std::vector<uint32_t> samples(n, 0);
    std::vector<float> top(n, 0.f);
    auto add = [&](uint32_t t, float v) {
      sum[t] += v;
      ++samples[t];
      top[t] = std::max(top[t], v);
    };
    for (size_t i = 0; i < texels; ++i)
      if (d.texel_triangle[i] >= 0 && d.classes[i] == MOLDTEX_TEXEL_INSIDE) add(d.texel_triangle[i], given[i]);
    float bary[3];
    for (uint32_t t = 0; t < n; ++t)
      for (int k = 0; k < kSamples; ++k) {
        sample_bary(k, bary);
        add(t, given[texel_at(s, t, bary, d.width, d.height)]);
      }
    double total = 0;
    for (uint32_t t = 0; t < n; ++t) {
      weight[t] = s.degenerate[t] ? 0.0 : s.areas[t] * sum[t] / std::max(1u, samples[t]);
      total += weight[t];
    }
    if (!(total > 0))
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
           "The spawn map is zero everywhere on the mesh: paint where agents should be born");
    m.spawn_alias = build_alias_table(weight);
    m.spawn_max = std::move(top);
  } else if (kind == MOLDTEX_MAP_SPAWN) {
    m.spawn_alias = AliasTable{};
    m.spawn_max.clear();
  }
  m.given[kind] = std::move(given);
  ++m.version;
  // Derived planes.
  m.agent_planes.clear();
  int32_t planes = 0;
  for (uint32_t k = 0; k < MTX_AGENT_MAPS; ++k) {
    m.plane_of[k] = -1;
    if (m.given[k].empty()) continue;
    m.plane_of[k] = planes++;
    m.agent_planes.insert(m.agent_planes.end(), m.given[k].begin(), m.given[k].end());
  }
  const std::vector<float>& set = m.given[kind];
  m.largest[kind] = set.empty() ? 0.f : *std::max_element(set.begin(), set.end());
  m.deposit_max = m.given[MOLDTEX_MAP_DEPOSIT_RATE].empty() ? 1.f : std::max(1.f, m.largest[MOLDTEX_MAP_DEPOSIT_RATE]);
}

}  // namespace moldtex
