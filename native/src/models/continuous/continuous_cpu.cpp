// The continuous model's step on the CPU backend, on either domain: agents read the
// concentration and add their deposits into integer sums, then per species the deposits
// become concentration and the diffusion-decay PDE advances by dt.
#include <algorithm>
#include <memory>

#include "agents/continuous_rules.h"
#include "backends/cpu/cpu_model_step.h"
#include "backends/cpu/private_sums.h"
#include "models/continuous/continuous_model.h"
#include "shared/pde.h"

namespace moldtex {

namespace {

// After the agents: per species, the fixed-point deposit sums (one plane of
// `lap.area.size()` cells per species) become concentration (amount / cell area) and are
// cleared, the write stimulus adds, the PDE advances by dt, and the decay map applies.
void settle_continuous_step(const StepSettings& settings, const ParameterMaps& maps, const TexelLaplacian& lap,
                            MappedLaplacian& mapped, int32_t deposit_units, float* planes, int32_t* all_sums,
                            std::vector<float>& scratch, uint32_t species_count, ThreadPool& pool) {
  const moldtex_continuous_params& p = settings.continuous;
  const size_t cells = lap.area.size();
  const float amount = deposit_unit_amount(p, deposit_units);
  const std::vector<float>& decay = decay_for(maps, double(p.decay_rate) * p.time_step, mapped);
  for (uint32_t k = 0; k < species_count; ++k) {
    float* plane = planes + k * cells;
    int32_t* sums = all_sums + k * cells;
    pool.parallel_for(lap.rows.size(), 4096, [&](size_t begin, size_t end) {
      for (size_t r = begin; r < end; ++r) {
        const uint32_t i = lap.rows[r];
        if (sums[i] == 0 || !(lap.area[i] > 0.f)) continue;
        plane[i] += mtx_deposit_concentration(sums[i], amount, lap.area[i]);
        sums[i] = 0;
      }
    });
    if (!maps.write().empty()) {
      const float rate = write_stimulus_amount(p, k < settings.u_metric.size() ? settings.u_metric[k] : 0.0);
      pool.parallel_for(lap.rows.size(), 4096, [&](size_t begin, size_t end) {
        for (size_t r = begin; r < end; ++r) {
          const uint32_t i = lap.rows[r];
          plane[i] = mtx_write_stimulus(plane[i], maps.write()[i], rate);
        }
      });
    }
    advance_diffusion_decay(lap, plane, scratch, p.diffusion_rate, p.decay_rate, p.time_step, p.integrator, pool);
    if (!decay.empty())  // the decay map: each cell's own e^(-r_dec m dt)
      pool.parallel_for(lap.rows.size(), 4096, [&](size_t begin, size_t end) {
        for (size_t r = begin; r < end; ++r) plane[lap.rows[r]] *= decay[lap.rows[r]];
      });
  }
}

class ContinuousCpuStep final : public CpuModelStep {
 public:
  void step(CpuStepContext& x, const StepSettings& settings, uint64_t seed, uint64_t step_index,
            uint32_t*) override {
    const TextureDomain& d = x.domain;
    const IntrinsicDomain* intrinsic = x.intrinsic;
    const size_t texels = d.texel_count();
    const TexelLaplacian& base = x.operators.laplacian();
    if (alias_.prob.empty()) alias_ = build_area_alias_table(x.surface);
    if (sums_.size() != x.planes.size()) sums_.assign(x.planes.size(), 0);
    if (step_index % kSortInterval == 0) {
      if (intrinsic)
        sort_by_triangle(x.surface.triangle_count(), x.agents, x.sort_scratch, x.pool);
      else
        sort_by_tile(x.surface, d.width, d.height, x.agents, x.sort_scratch, x.pool);
    }
    ContinuousStepConstants c = continuous_constants(settings, d, settings.u_metric, x.surface.triangle_count(),
                                                     x.agents.size(), seed, step_index);
    const float* field = c.has_fields ? x.field.data() : nullptr;
    const float* read = x.planes.data();
    int32_t* deposit = sums_.data();
    if (intrinsic) {  // planes of vertex values (maps), read and deposited at the lattice's nodes
      c.width = intrinsic->vertex_count();
      c.height = 1;
      const IntrinsicLattice& lattice = intrinsic->lattice;
      c.plane_cells = lattice.node_count();
      node_values_.resize(size_t(c.plane_cells) * x.species_count);
      if (node_sums_.size() != node_values_.size()) node_sums_.assign(node_values_.size(), 0);
      lattice.gather(x.planes.data(), c.width, node_values_.data(), x.species_count, x.pool);
      read = node_values_.data();
      deposit = node_sums_.data();
    }
    const ParameterMaps& maps = x.operators.maps_for(*settings.maps);
    // 1. Agents read the concentration as it was at the start of the step and add their
    //    deposits into integer sums (exact in any order).
    const mtx_surface_tables tables =
        intrinsic ? intrinsic->agent_tables(surface_tables(x.surface, d), c.has_fields ? x.node_field.data() : nullptr)
                  : surface_tables(x.surface, d);
    const AliasTable& alias = maps.spawn_max.empty() ? alias_ : maps.spawn_alias;
    // Each thread adds its agents' deposits into sums of its own (PrivateSums), folded
    // together after.
    agent_sums_.prepare(size_t(c.plane_cells) * x.species_count, x.pool.size());
    c.exclusive_sums = agent_sums_.exclusive() ? 1u : 0u;
    Agents& agents = x.agents;
    x.pool.parallel_for_threads(agents.size(), 1024, [&](size_t begin, size_t end, unsigned thread) {
      continuous_update_agents(tables, c, read, field, agent_sums_.for_thread(deposit, thread), alias,
                               c.bias_on || c.bias_spawn ? settings.bias.data() : nullptr, maps.agent_planes.data(),
                               maps.spawn_max.data(), agents, begin, end);
    });
    agent_sums_.fold_into(deposit, x.pool);
    if (intrinsic) {
      vertex_sums_.prepare(size_t(c.width) * x.species_count, x.pool.size());
      intrinsic->lattice.scatter(node_sums_.data(), sums_.data(), c.width, x.species_count, vertex_sums_, x.pool);
    }
    // 2. Per species: the deposits become concentration, then the PDE advances by dt; the
    //    gutter shows what lies across each seam (for Blender only).
    MappedLaplacian& mapped = x.operators.mapped();
    settle_continuous_step(settings, maps, laplacian_for(maps, base, mapped), mapped, c.deposit_units,
                           x.planes.data(), sums_.data(), pde_scratch_, x.species_count, x.pool);
    if (intrinsic) return;  // (shown in the texture when read)
    for (uint32_t k = 0; k < x.species_count; ++k) fill_gutter(d, x.planes.data() + k * texels, x.pool);
  }

  size_t bytes() const override {
    return sums_.capacity() * sizeof(int32_t) + pde_scratch_.capacity() * sizeof(float) +
           alias_.prob.capacity() * 4 + alias_.alias.capacity() * 4 +
           (node_values_.capacity() + node_sums_.capacity()) * 4 + agent_sums_.bytes() + vertex_sums_.bytes();
  }

 private:
  // The fixed-point deposit sums (one plane per species) and the respawn table.
  std::vector<int32_t> sums_;
  AliasTable alias_;
  // The intrinsic domain: the concentration at the lattice's nodes (gathered every step)
  // and the deposits there (passed on to sums_).
  std::vector<float> node_values_;
  std::vector<int32_t> node_sums_;
  // Each thread's own deposit sums: the agents' (sums_ or node_sums_) and, on the
  // intrinsic domain, the vertices' that the nodes pass theirs on to.
  PrivateSums agent_sums_, vertex_sums_;
  std::vector<float> pde_scratch_;
};

}  // namespace

std::unique_ptr<CpuModelStep> continuous_cpu_step() { return std::make_unique<ContinuousCpuStep>(); }

}  // namespace moldtex
