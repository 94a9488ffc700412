#include "agents/continuous_rules.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "agents/parameter_maps.h"
#include "common/rng.h"
#include "surface/trace_lanes.h"

namespace moldtex {

AliasTable build_alias_table(const std::vector<double>& weights) {
  const uint32_t n = static_cast<uint32_t>(weights.size());
  AliasTable t;
  t.prob.assign(n, 0.f);
  t.alias.resize(n);
  double total = 0;
  for (double w : weights) total += w;
  std::vector<double> scaled(n);
  std::vector<uint32_t> small, large;
  for (uint32_t i = 0; i < n; ++i) {
    scaled[i] = total > 0 ? weights[i] * n / total : 1.0;
    t.alias[i] = i;
    (scaled[i] < 1.0 ? small : large).push_back(i);
  }
  while (!small.empty() && !large.empty()) {
    const uint32_t l = small.back(), g = large.back();
    small.pop_back();
    t.prob[l] = static_cast<float>(scaled[l]);
    t.alias[l] = g;
    scaled[g] = scaled[g] + scaled[l] - 1.0;
    if (scaled[g] < 1.0) {
      large.pop_back();
      small.push_back(g);
    }
  }
  // Leftovers are 1 up to rounding; one of weight 0 left here keeps probability 0 only
  // if it has an alias of some weight, so give it the last large one.
  for (uint32_t g : large) t.prob[g] = 1.f;
  for (uint32_t l : small) {
    if (scaled[l] > 0.5 || large.empty()) {
      t.prob[l] = 1.f;
    } else {
      t.prob[l] = 0.f;
      t.alias[l] = large.back();
    }
  }
  return t;
}

AliasTable build_area_alias_table(const Surface& s) {
  std::vector<double> w(s.triangle_count());
  for (uint32_t i = 0; i < s.triangle_count(); ++i) w[i] = s.degenerate[i] ? 0.0 : s.areas[i];
  return build_alias_table(w);
}

double uniform_steady_state(const moldtex_continuous_params& p, double agents, double area) {
  if (!(p.decay_rate > 0.f)) return std::numeric_limits<double>::infinity();
  const double alive = p.mean_lifetime > 0.f ? std::exp(-double(p.activation_time) / p.mean_lifetime) : 1.0;
  return agents * p.deposit_rate / (p.decay_rate * area) * alive;
}

int32_t deposit_units(size_t agents, float max_factor) {
  const double most = double(1u << 24);
  const double bound = std::floor(2147483647.0 / (double(std::max<size_t>(agents, 1)) * std::max(1.f, max_factor)));
  return static_cast<int32_t>(std::max(1.0, std::min(most, bound)));
}

float write_stimulus_amount(const moldtex_continuous_params& p, double u_metric) {
  const double k = double(p.decay_rate) * p.time_step;
  const double spread = k > 1e-6 ? std::expm1(k) / k : 1.0 + k / 2;
  // value * r_dec * U per second (alone: u / U -> value); without a finite U, value per second.
  const double per_second = std::isfinite(u_metric) && u_metric > 0 ? p.decay_rate * u_metric : 1.0;
  return static_cast<float>(per_second * p.time_step * spread);
}

float deposit_unit_amount(const moldtex_continuous_params& p, int32_t units) {
  const double k = double(p.decay_rate) * p.time_step;
  const double spread = k > 1e-6 ? std::expm1(k) / k : 1.0 + k / 2;
  return static_cast<float>(double(p.deposit_rate) * p.time_step * spread / units);
}

std::vector<double> agents_per_species(const Agents& a, uint32_t species_count) {
  std::vector<double> n(species_count, 0.0);
  for (uint8_t s : a.species)
    if (s < species_count) n[s] += 1.0;
  return n;
}

ContinuousStepConstants continuous_constants(const StepSettings& settings, const TextureDomain& d,
                                             const std::vector<double>& u_per_species,
                                             uint32_t triangle_count, size_t agents, uint64_t seed,
                                             uint64_t step) {
  const moldtex_continuous_params& p = settings.continuous;
  ContinuousStepConstants c{};
  c.seed = seed;
  c.step = step;
  c.turnover_key = mtx_rng_key(seed, MTX_RNG_TURNOVER);
  c.decide_key = mtx_rng_key(seed, MTX_RNG_DECIDE);
  for (uint32_t s = 0; s < settings.species_count; ++s) {
    for (uint32_t k = 0; k < settings.species_count; ++k)
      c.attraction[MTX_MAX_SPECIES * s + k] = settings.species[s].attraction[k];
    const double u = s < u_per_species.size() ? u_per_species[s] : 0.0;
    // 1 / U, kept within floats (a U of 1e-39 would give inf, and 0 * inf = NaN).
    c.sense_scale[s] = std::isfinite(u) && u > 0 ? static_cast<float>(std::min(1.0 / u, 1e30)) : 1.f;
  }
  const float angle = p.sensor_angle * std::numbers::pi_v<float> / 180.f;
  c.move_length = p.move_rate * p.time_step;
  c.sensor_length = p.sensor_distance;
  c.sensor_cos = std::cos(angle);
  c.sensor_sin = std::sin(angle);
  c.turn_impulse = p.turn_rate / p.turn_frequency;
  c.decision_period = 1.f / p.turn_frequency;
  c.dt = p.time_step;
  c.exposure_step = p.mean_lifetime > 0.f ? p.time_step / p.mean_lifetime : 0.f;
  c.activation_time = p.activation_time;
  // A deposit every texel along the path: bilinear hats one texel apart sum to an even
  // line (exactly so along a texel axis), at half the atomics of half-texel pieces.
  c.max_piece = 1.0f;
  c.width = d.width;
  c.height = d.height;
  c.species_count = settings.species_count;
  c.has_fields = settings.has_fields ? 1u : 0u;
  c.triangle_count = triangle_count;
  c.deposit_on = p.deposit_rate > 0.f ? 1u : 0u;
  c.bias_on = !settings.bias.empty() && p.bias_strength > 0.f ? 1u : 0u;
  c.bias_rate = p.bias_strength;
  c.bias_symmetry = p.bias_symmetry;
  c.bias_spawn = !settings.bias.empty() && p.bias_spawn ? 1u : 0u;
  c.absorb = p.boundary == MOLDTEX_BOUNDARY_ABSORB ? 1u : 0u;
  // (A simulation always has its maps, empty or not.)
  const ParameterMaps& maps = *settings.maps;
  for (int k = 0; k < MTX_AGENT_MAPS; ++k) c.map_plane[k] = maps.plane_of[k];
  c.maps_on = maps.any_agent_map() ? 1u : 0u;
  c.deposit_units = deposit_units(agents, maps.deposit_max);
  c.plane_cells = d.width * d.height;
  return c;
}

void start_agent_life(const moldtex_continuous_params& p, uint64_t rng, Agents& a, size_t i) {
  a.clock[i] = (1.f / p.turn_frequency) * mtx_rng_float(&rng);
  if (p.mean_lifetime > 0.f) {
    const float elapsed = mtx_exponential(&rng);  // age / tau ~ Exp(1)
    a.age[i] = elapsed * p.mean_lifetime;
    a.exposure[i] = elapsed;
    a.threshold[i] = elapsed + mtx_exponential(&rng);
  } else {
    a.age[i] = p.activation_time;
    a.exposure[i] = 0.f;
    a.threshold[i] = std::numeric_limits<float>::max();
  }
}

void start_agent_lives(const moldtex_continuous_params& p, uint64_t seed, uint64_t stream,
                       Agents& a, size_t begin, size_t end) {
  for (size_t i = begin; i < end; ++i) start_agent_life(p, mtx_rng_init(seed, MTX_RNG_TURNOVER, stream, i), a, i);
}

void continuous_update_agents(const mtx_surface_tables& tables, const ContinuousStepConstants& c,
                              const float* u, const float* field, int32_t* sums,
                              const AliasTable& alias, const float* bias, const float* maps,
                              const float* spawn_max, Agents& agents, size_t begin, size_t end) {
  // In batches, in stages: the first part of every agent's step (turnover, maps, where
  // its sensor traces start); then where the batch's traces end, located together; then
  // its sensors' reading stencils, asking memory for the cells they read; then the rest.
  // So the reads of a batch overlap instead of waiting one after another. Agents of one
  // step are independent (they read the concentration of the step's start and add
  // deposits into exact integer sums), so the batching changes no result.
  constexpr size_t kBatch = 32;
  Walker w[kBatch];
  mtx_agent_life life[kBatch];
  mtx_continuous_plan plan[kBatch];
  const size_t plane = c.plane_cells;
  const bool three = tables.vertex_cells != 0;  // stencils of 3 cells (else 4 texels)
  // The batch's sensor traces are located together (surface/trace_lanes.h: SIMD lanes
  // where the processor has them, the same bits as mtx_continuous_traces one by one).
  static_assert(3 * kBatch <= kTraceLanes);
  TraceLanes lanes;
  uint8_t located[kTraceLanes];
  size_t lane_of[kBatch];  // each deciding agent's first lane
  for_each_in_batches<kBatch>(
      begin, end,
      [&](size_t i, size_t j) {  // turnover, maps, where the sensor traces start
        w[j] = agents.load(i);
        life[j] = mtx_agent_life{agents.clock[i], agents.age[i], agents.exposure[i], agents.threshold[i]};
        mtx_continuous_agent_begin(tables, alias.prob.data(), alias.alias.data(), bias, maps, spawn_max, &w[j],
                                   &life[j], i, &c, &plan[j]);
        if (j == 0) lanes.count = 0;
        if (!plan[j].decide) return;
        mtx_continuous_trace_starts(&w[j], plan[j].sensor_cos, plan[j].sensor_sin, plan[j].at);
        lane_of[j] = lanes.count;
        for (const Walker& at : plan[j].at) {
          const size_t l = lanes.count++;
          float s[3], e[3];
          mtx_trace_ends(tables.frames, &at, plan[j].sensor_length, s, e);
          lanes.triangle[l] = at.triangle;
          for (int k = 0; k < 3; ++k) lanes.s[k][l] = s[k], lanes.e[k][l] = e[k];
        }
      },
      [&](size_t, size_t j) {  // the traces' ends (mtx_continuous_traces)
        if (j == 0 && tables.unfolded && lanes.count > 0)
          trace_hops_lanes(tables.adjacency, tables.unfolded, c.triangle_count, lanes, located);
        if (!plan[j].decide) return;
        for (size_t m = 0; m < 3; ++m) {
          Walker& at = plan[j].at[m];
          const size_t l = lane_of[j] + m;
          if (tables.unfolded && located[l]) {
            at.triangle = lanes.triangle[l];
            for (int k = 0; k < 3; ++k) at.bary[k] = lanes.e[k][l];
            mtx_clamp_bary(at.bary);
          } else {
            mtx_walk_until(tables.frames, tables.adjacency, &at, plan[j].sensor_length, nullptr, 0,
                           MTX_BOUNDARY_BOUNCE, nullptr);
          }
        }
      },
      [&](size_t i, size_t j) {  // the reading stencils; ask for the cells they read
        if (!plan[j].decide) return;
        mtx_continuous_plan_stencils(tables, &c, &plan[j]);
        const float* own = u + agents.species[i] * plane;
        for (const mtx_texel_stencil& st : plan[j].probe) {
          __builtin_prefetch(own + st.cell[0]);
          __builtin_prefetch(own + st.cell[2]);
          if (three) __builtin_prefetch(own + st.cell[1]);
        }
      },
      [&](size_t i, size_t j) {  // the rest
        mtx_continuous_agent_finish(tables, u, field, sums, bias, &w[j], &life[j], agents.species[i], i, &c,
                                    &plan[j]);
        agents.store(i, w[j]);
        agents.clock[i] = life[j].clock;
        agents.age[i] = life[j].age;
        agents.exposure[i] = life[j].exposure;
        agents.threshold[i] = life[j].threshold;
      });
}

}  // namespace moldtex
