// The continuous model's agents on the CPU (the per-agent rule lives in
// shared/continuous.h, compiled here as C++ and by the OpenCL backend as OpenCL C), the
// per-step constants, the alias table for respawns and the steady-state start of the
// agents' clocks.
#pragma once
#include <cstdint>
#include <vector>

#include "agents/agents.h"
#include "agents/momas_rules.h"
#include "domain/texture_domain.h"
#include "moldtex.h"
#include "shared/continuous.h"

namespace moldtex {

using ContinuousStepConstants = mtx_continuous_constants;

// Vose's alias table over the triangles, weighted by 3D area (degenerate ones 0): a
// respawn picks a triangle in constant time.
struct AliasTable {
  std::vector<float> prob;
  std::vector<uint32_t> alias;
};
AliasTable build_area_alias_table(const Surface& surface);
// The same over any non-negative weights (all zero: uniform).
AliasTable build_alias_table(const std::vector<double>& weights);

// U of layton-intrinsic-slime.md Eq. 5 for `agents` agents on `area`: N r_dep / (r_dec A)
// * exp(-t_a / tau) (tau = 0: no turnover, the factor is 1); +inf when r_dec = 0.
double uniform_steady_state(const moldtex_continuous_params& p, double agents, double area);

// Fixed-point units of one agent's deposit in a step: 2^24, or fewer so that all
// `agents` agents depositing into one texel stay below 2^31 (texel_sampling.h), each
// deposit scaled by up to max_factor (a deposit-rate map's largest value).
int32_t deposit_units(size_t agents, float max_factor = 1.f);

// The amount of one fixed-point deposit unit: r_dep dt / units, times
// (e^k - 1) / k, k = r_dec dt. Deposits enter before the step's decay e^-k, but in truth
// they arrive evenly during the step and decay on average by (1 - e^-k) / k; the factor
// makes the total exact for any dt (the steady state is U, not U k e^-k / (1 - e^-k),
// which is 5% low at 1/60 s with the default decay).
float deposit_unit_amount(const moldtex_continuous_params& p, int32_t units);

// What a write stimulus of 1 adds to a concentration in one step: r_dec * U * dt, times
// the same (e^k - 1) / k as deposits, so alone it holds u = U (u_metric: the plane's U; 1
// per second where U is not finite).
float write_stimulus_amount(const moldtex_continuous_params& p, double u_metric);

// Live agents per species (agent species tags), for U.
std::vector<double> agents_per_species(const Agents& agents, uint32_t species_count);

ContinuousStepConstants continuous_constants(const StepSettings& settings, const TextureDomain& d,
                                             const std::vector<double>& u_per_species,
                                             uint32_t triangle_count, size_t agents, uint64_t seed,
                                             uint64_t step);

// Starts the clocks of agents [begin, end) in their steady state (§3.3): with turnover,
// age ~ Exp(tau) and exposure age / tau, threshold = exposure + Exp(1) (memoryless, so no
// inspection-paradox bias); without, age = t_a (depositing at once) and no threshold.
// The decision clock starts at a uniform phase. Agent i's draws depend only on (seed,
// stream, i).
void start_agent_lives(const moldtex_continuous_params& p, uint64_t seed, uint64_t stream,
                       Agents& agents, size_t begin, size_t end);
// The same for agent i alone, from a given random state.
void start_agent_life(const moldtex_continuous_params& p, uint64_t rng, Agents& agents, size_t i);

// One step of agents [begin, end): they read u and add their deposits into sums (planes
// of c.plane_cells: texels, or the intrinsic lattice's nodes), read a static field per
// cell (texel or vertex; the lattice's own in tables.lattice_field) and maps per cell.
void continuous_update_agents(const mtx_surface_tables& tables, const ContinuousStepConstants& c,
                              const float* u, const float* field, int32_t* sums,
                              const AliasTable& alias, const float* bias, const float* maps,
                              const float* spawn_max, Agents& agents, size_t begin, size_t end);

}  // namespace moldtex
