#include "backends/cpu/cpu_backend.h"

#include <algorithm>
#include <cstring>

#include "agents/momas_lanes.h"
#include "agents/momas_rules.h"
#include "agents/parameter_maps.h"
#include "shared/pde.h"
#include "common/error.h"
#include "domain/reaction_diffusion.h"

namespace moldtex {

constexpr uint64_t kSortInterval = 16;

CpuBackend::CpuBackend(std::shared_ptr<const Surface> surface,
                       std::shared_ptr<const TextureDomain> domain, uint32_t /*agent_count: reset brings them*/,
                       uint32_t species_count, unsigned threads, std::shared_ptr<const IntrinsicDomain> intrinsic)
    : surface_(std::move(surface)),
      domain_(std::move(domain)),
      intrinsic_(std::move(intrinsic)),
      species_count_(species_count),
      pool_(std::make_unique<ThreadPool>(threads)) {
  const size_t n = (intrinsic_ ? intrinsic_->vertex_count() : domain_->texel_count()) * species_count_;
  pheromone_.assign(n, 0.f);
  scratch_.assign(n, 0.f);
  marks_.assign(domain_->texel_count() * species_count_, 0);  // MoMaS only
}

void CpuBackend::set_field(const std::vector<float>& field) {
  field_ = intrinsic_ && !field.empty() ? intrinsic_->sample_texels(field.data()) : field;
  node_field_ = intrinsic_ && !field_.empty() ? intrinsic_->lattice.field(field_) : std::vector<float>{};
}

const TexelLaplacian& CpuBackend::base_laplacian() {
  if (intrinsic_) return intrinsic_->laplacian;
  if (!laplacian_) laplacian_ = std::make_unique<TexelLaplacian>(build_texel_laplacian(*surface_, *domain_, *pool_));
  return *laplacian_;
}

const ParameterMaps& CpuBackend::maps_for(const ParameterMaps& maps) {
  return intrinsic_ ? vertex_maps_.of(*intrinsic_, maps, domain_->texel_count()) : maps;
}

void CpuBackend::reset(const Agents& agents) {
  std::fill(pheromone_.begin(), pheromone_.end(), 0.f);
  std::fill(scratch_.begin(), scratch_.end(), 0.f);
  std::fill(marks_.begin(), marks_.end(), 0);
  import_agents(agents);
}

void CpuBackend::import_agents(const Agents& agents) {
  agents_ = agents;
  agents_.batch.resize(agents_.size(), 0);
}

void CpuBackend::set_thread_count(unsigned threads) {
  if (ThreadPool::resolve_thread_count(threads) != pool_->size())
    pool_ = std::make_unique<ThreadPool>(threads);
}

void CpuBackend::step(const StepSettings& settings, uint64_t seed, uint64_t step_index,
                      uint32_t* eaters) {
  if (settings.model == MOLDTEX_MODEL_CONTINUOUS) return step_continuous(settings, seed, step_index);
  if (settings.model == MOLDTEX_MODEL_GRAY_SCOTT) return step_gray_scott(settings);
  if (intrinsic_)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The Intrinsic domain runs the continuous model and Gray-Scott; MoMaS works in texels: use the Texture domain");
  const TextureDomain& d = *domain_;
  const moldtex_sim_params& p = settings.params;
  const MomasStepConstants c = momas_constants(settings, d, seed, step_index);
  // Agents drift apart in memory order as they move; regroup them now and then.
  if (step_index % kSortInterval == 0) sort_by_tile(*surface_, d.width, d.height, agents_, sort_scratch_, *pool_);
  // 1. Agents sense the field as it was at the start of the step (read-only) and mark
  //    where they deposit: no thread reads what another is writing.
  mtx_surface_tables tables = surface_tables(*surface_, d);
  if (c.food_count > 0) {
    std::fill(eaters, eaters + c.food_count, 0u);
    tables.food = settings.food.data();
    tables.eaters = eaters;
  }
  const float* field = c.has_fields ? field_.data() : nullptr;
  // The common case in SIMD lanes where the processor and the step allow (the same bits).
  const bool lanes = momas_lanes_apply(c, surface_->triangle_count());
  pool_->parallel_for(agents_.size(), 1024, [&](size_t begin, size_t end) {
    if (lanes)
      momas_lanes_update(tables, c, pheromone_.data(), field, marks_.data(), agents_, begin, end);
    else
      momas_update_agents(tables, c, pheromone_.data(), field, marks_.data(), agents_, begin, end);
  });
  // 2. Per species: deposit, make the gutter hold the texels across each seam, then blur
  //    (which then mixes across seams) and evaporate; in texel units in one pass
  //    (deposit_diffuse_evaporate).
  const size_t texels = d.texel_count();
  const float mix = std::min(1.f, p.diffusion_rate * p.time_step);
  const bool surface_units = p.length_unit > 0.f;
  if (surface_units && !plan_.matches(p.diffusion_rate * p.time_step, p.length_unit))
    plan_ = plan_surface_diffusion(d, p.diffusion_rate * p.time_step, p.length_unit);
  for (uint32_t k = 0; k < species_count_; ++k) {
    float* plane = pheromone_.data() + k * texels;
    if (surface_units) {
      apply_deposits(d, plane, marks_.data() + k * texels, settings.species[k].deposit, *pool_);
      surface_diffuse(d, plan_, plane, scratch_.data() + k * texels, fine_scratch_,
                      p.evaporation_rate * p.time_step, *pool_);
      continue;
    }
    deposit_diffuse_evaporate(d, plane, marks_.data() + k * texels, settings.species[k].deposit,
                              scratch_.data() + k * texels, mix, p.evaporation_rate * p.time_step, *pool_);
  }
  pheromone_.swap(scratch_);
  for (uint32_t k = 0; k < species_count_; ++k) fill_gutter(d, pheromone_.data() + k * texels, *pool_);
}

void CpuBackend::step_continuous(const StepSettings& settings, uint64_t seed, uint64_t step_index) {
  const TextureDomain& d = *domain_;
  const size_t texels = d.texel_count();
  const TexelLaplacian& base = base_laplacian();
  if (alias_.prob.empty()) alias_ = build_area_alias_table(*surface_);
  if (sums_.size() != pheromone_.size()) sums_.assign(pheromone_.size(), 0);
  if (step_index % kSortInterval == 0) {
    if (intrinsic_)
      sort_by_triangle(surface_->triangle_count(), agents_, sort_scratch_, *pool_);
    else
      sort_by_tile(*surface_, d.width, d.height, agents_, sort_scratch_, *pool_);
  }
  ContinuousStepConstants c =
      continuous_constants(settings, d, settings.u_metric, surface_->triangle_count(), agents_.size(), seed,
                           step_index);
  const float* field = c.has_fields ? field_.data() : nullptr;
  const float* read = pheromone_.data();
  int32_t* deposit = sums_.data();
  if (intrinsic_) {  // planes of vertex values (maps), read and deposited at the lattice's nodes
    c.width = intrinsic_->vertex_count();
    c.height = 1;
    const IntrinsicLattice& lattice = intrinsic_->lattice;
    c.plane_cells = lattice.node_count();
    node_values_.resize(size_t(c.plane_cells) * species_count_);
    if (node_sums_.size() != node_values_.size()) node_sums_.assign(node_values_.size(), 0);
    lattice.gather(pheromone_.data(), c.width, node_values_.data(), species_count_, *pool_);
    read = node_values_.data();
    deposit = node_sums_.data();
  }
  const ParameterMaps& maps = maps_for(*settings.maps);
  // 1. Agents read the concentration as it was at the start of the step and add their
  //    deposits into integer sums (exact in any order).
  const mtx_surface_tables tables =
      intrinsic_ ? intrinsic_->agent_tables(surface_tables(*surface_, d), c.has_fields ? node_field_.data() : nullptr)
                 : surface_tables(*surface_, d);
  const AliasTable& alias = maps.spawn_max.empty() ? alias_ : maps.spawn_alias;
  // Each thread adds its agents' deposits into sums of its own (PrivateSums), folded
  // together after.
  agent_sums_.prepare(size_t(c.plane_cells) * species_count_, pool_->size());
  c.exclusive_sums = agent_sums_.exclusive() ? 1u : 0u;
  pool_->parallel_for_threads(agents_.size(), 1024, [&](size_t begin, size_t end, unsigned thread) {
    continuous_update_agents(tables, c, read, field, agent_sums_.for_thread(deposit, thread), alias,
                             c.bias_on || c.bias_spawn ? settings.bias.data() : nullptr, maps.agent_planes.data(),
                             maps.spawn_max.data(), agents_, begin, end);
  });
  agent_sums_.fold_into(deposit, *pool_);
  if (intrinsic_) {
    vertex_sums_.prepare(size_t(c.width) * species_count_, pool_->size());
    intrinsic_->lattice.scatter(node_sums_.data(), sums_.data(), c.width, species_count_, vertex_sums_, *pool_);
  }
  // 2. Per species: the deposits become concentration, then the PDE advances by dt; the
  //    gutter shows what lies across each seam (for Blender only).
  settle_continuous_step(settings, maps, laplacian_for(maps, base, mapped_), mapped_, c.deposit_units,
                         pheromone_.data(), sums_.data(), pde_scratch_, species_count_, *pool_);
  if (intrinsic_) return;  // (shown in the texture when read)
  for (uint32_t k = 0; k < species_count_; ++k) fill_gutter(d, pheromone_.data() + k * texels, *pool_);
}

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

// Gray-Scott (domain/reaction_diffusion.h): planes V and U, no agents.
void CpuBackend::step_gray_scott(const StepSettings& settings) {
  const TextureDomain& d = *domain_;
  const TexelLaplacian& base = base_laplacian();
  if (species_count_ < kReactionPlanes) fail(MOLDTEX_ERROR_INTERNAL, "The Gray-Scott model needs two planes");
  const size_t cells = pheromone_.size() / species_count_;  // values per plane
  const ParameterMaps& maps = maps_for(*settings.maps);
  reaction_step(laplacian_for(maps, base, mapped_), settings.reaction, pheromone_.data(), scratch_, cells, *pool_,
                reaction_maps(maps.feed(), maps.largest[MOLDTEX_MAP_FEED], maps.kill(),
                              maps.largest[MOLDTEX_MAP_KILL], settings.reaction));
  if (intrinsic_) return;
  for (uint32_t k = 0; k < kReactionPlanes; ++k) fill_gutter(d, pheromone_.data() + k * cells, *pool_);
}

void CpuBackend::read_pheromone(float* out) const {
  if (intrinsic_) return intrinsic_->show(pheromone_.data(), out, species_count_, *domain_, *pool_);
  std::memcpy(out, pheromone_.data(), pheromone_.size() * sizeof(float));
}

void CpuBackend::read_agents(moldtex_surface_point* out, size_t count) const {
  for (size_t i = 0; i < std::min(count, agents_.size()); ++i) {
    Walker w = agents_.load(i);
    out[i].triangle = w.triangle;
    std::copy(w.bary, w.bary + 3, out[i].bary);
  }
}

void CpuBackend::export_state(SimState& s) const {
  s.agents = agents_;
  if (!intrinsic_) {
    s.pheromone = pheromone_;
    return;
  }
  s.pheromone.resize(domain_->texel_count() * species_count_);
  read_pheromone(s.pheromone.data());
  s.cells = pheromone_;
}

void CpuBackend::import_state(const SimState& s) {
  std::vector<float> planes =
      intrinsic_ ? intrinsic_->values_from_state(s, species_count_, *domain_, *pool_) : s.pheromone;
  import_agents(s.agents);
  pheromone_ = std::move(planes);
  std::fill(marks_.begin(), marks_.end(), 0);
}

std::string CpuBackend::name() const {
  const unsigned n = pool_->size();
  return "CPU (" + std::to_string(n) + (n == 1 ? " thread" : " threads") + (intrinsic_ ? ", intrinsic domain)" : ")");
}

size_t CpuBackend::bytes() const {
  size_t continuous = sums_.capacity() * sizeof(int32_t) + pde_scratch_.capacity() * sizeof(float) +
                      alias_.prob.capacity() * 4 + alias_.alias.capacity() * 4;
  if (laplacian_) continuous += laplacian_->bytes();
  if (intrinsic_)
    continuous += intrinsic_->bytes() + vertex_maps_.bytes() +
                  (node_values_.capacity() + node_field_.capacity() + node_sums_.capacity()) * 4;
  continuous += agent_sums_.bytes() + vertex_sums_.bytes();
  return agents_.bytes() + sort_scratch_.sorted.bytes() +
         (sort_scratch_.key.capacity() + sort_scratch_.start.capacity() + sort_scratch_.dest.capacity()) * 4 +
         (pheromone_.capacity() + scratch_.capacity() + field_.capacity()) * sizeof(float) +
         marks_.capacity() + continuous;
}

}  // namespace moldtex
