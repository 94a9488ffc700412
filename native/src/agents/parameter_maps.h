// Parameter maps and stimuli of the continuous model (layton-intrinsic-slime.md §3.3,
// moldtex_sim_set_map): per texel values as the caller gave them, and what the backends
// read from them each step (agent planes, the spawn alias table, the write stimulus).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "agents/continuous_rules.h"
#include "domain/texel_laplacian.h"
#include "domain/texture_domain.h"
#include "moldtex.h"
#include "surface/surface.h"

namespace moldtex {

struct ParameterMaps {
  // As given (width * height each), empty = not set.
  std::array<std::vector<float>, MOLDTEX_MAP_COUNT> given;

  // ---- derived by update_parameter_maps ----
  // The agent maps that are set (MTX_MAP_*), one width * height plane each, gutter texels
  // holding the texel across their seam; plane_of[m] is map m's plane or -1.
  std::vector<float> agent_planes;
  int32_t plane_of[MTX_AGENT_MAPS] = {-1, -1, -1, -1, -1, -1, -1, -1};
  float deposit_max = 1.f;  // the deposit map's largest value (1 without one)
  // Each map's largest value (0 where not set).
  std::array<float, MOLDTEX_MAP_COUNT> largest{};
  // With a spawn map: per triangle its largest sampled weight, and an alias table by
  // area times its mean sampled weight.
  std::vector<float> spawn_max;
  AliasTable spawn_alias;

  // Bumped by every change, so a backend uploads only what changed.
  uint64_t version = 0;

  bool any_agent_map() const { return !agent_planes.empty(); }
  // Write stimulus per texel (empty = none): r_dec * U per second per unit.
  const std::vector<float>& write() const { return given[MOLDTEX_MAP_WRITE_STIMULUS]; }
  // Per texel multipliers of r_dif and r_dec (empty = none).
  const std::vector<float>& diffusion() const { return given[MOLDTEX_MAP_DIFFUSION_RATE]; }
  const std::vector<float>& decay() const { return given[MOLDTEX_MAP_DECAY_RATE]; }
  // Gray-Scott's per texel multipliers of F and k (empty = none).
  const std::vector<float>& feed() const { return given[MOLDTEX_MAP_FEED]; }
  const std::vector<float>& kill() const { return given[MOLDTEX_MAP_KILL]; }
};

// Checks values for map `kind` (count floats for width * height texels); throws with a
// message naming the first bad texel.
void validate_map(uint32_t kind, const float* values, size_t count, size_t texels);

// Sets map `kind` (nullptr clears it) and rederives what the backends read.
void set_parameter_map(ParameterMaps& maps, uint32_t kind, const float* values, const Surface& surface,
                       const TextureDomain& domain);

// Per texel factors that turn a step's global decay e^(-r_dec dt) into the decay map's
// e^(-r_dec m_i dt): e^(-r_dec dt (m_i - 1)).
std::vector<float> decay_corrections(const std::vector<float>& decay_map, double r_dec_dt);

// The operator for the maps: `base`, or a copy with the diffusion map's conductances
// (made when the maps change; `cache` keeps it, keyed by the maps' version).
struct MappedLaplacian {
  std::unique_ptr<TexelLaplacian> lap;
  const void* source = nullptr;
  uint64_t version = 0;
  // Decay corrections for `decay_key` (r_dec dt) and the maps' version.
  std::vector<float> decay;
  double decay_key = -1;
  uint64_t decay_version = 0;
  const void* decay_source = nullptr;
};
const TexelLaplacian& laplacian_for(const ParameterMaps& maps, const TexelLaplacian& base, MappedLaplacian& cache);
// The decay corrections for these maps and r_dec dt (empty without a decay map).
const std::vector<float>& decay_for(const ParameterMaps& maps, double r_dec_dt, MappedLaplacian& cache);

// The name of map `kind` for messages ("move rate", ...).
const char* map_name(uint32_t kind);

}  // namespace moldtex
