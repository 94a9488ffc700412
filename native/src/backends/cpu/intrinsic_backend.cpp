#include "backends/cpu/intrinsic_backend.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/error.h"
#include "domain/reaction_diffusion.h"

namespace moldtex {

namespace {

constexpr uint64_t kSortInterval = 16;

}  // namespace

IntrinsicCpuBackend::IntrinsicCpuBackend(std::shared_ptr<const Surface> surface,
                                         std::shared_ptr<const TextureDomain> texture,
                                         std::shared_ptr<const IntrinsicDomain> domain, uint32_t species_count,
                                         unsigned threads)
    : surface_(std::move(surface)),
      texture_(std::move(texture)),
      domain_(std::move(domain)),
      species_count_(species_count),
      pool_(std::make_unique<ThreadPool>(threads)) {
  const size_t n = static_cast<size_t>(domain_->vertex_count()) * species_count_;
  values_.assign(n, 0.f);
  sums_.assign(n, 0);
}

void IntrinsicCpuBackend::reset(const Agents& agents) {
  std::fill(values_.begin(), values_.end(), 0.f);
  std::fill(sums_.begin(), sums_.end(), 0);
  import_agents(agents);
}

void IntrinsicCpuBackend::set_thread_count(unsigned threads) {
  if (ThreadPool::resolve_thread_count(threads) != pool_->size()) pool_ = std::make_unique<ThreadPool>(threads);
}

void IntrinsicCpuBackend::set_field(const std::vector<float>& field) {
  field_ = field.empty() ? std::vector<float>{} : domain_->sample_texels(field.data());
}

void IntrinsicCpuBackend::import_agents(const Agents& agents) {
  agents_ = agents;
  agents_.batch.resize(agents_.size(), 0);
}

void IntrinsicCpuBackend::read_agents(moldtex_surface_point* out, size_t count) const {
  for (size_t i = 0; i < std::min(count, agents_.size()); ++i) {
    const Walker w = agents_.load(i);
    out[i].triangle = w.triangle;
    std::copy(w.bary, w.bary + 3, out[i].bary);
  }
}

const ParameterMaps& IntrinsicCpuBackend::vertex_maps(const ParameterMaps& maps) {
  if (vmaps_source_ == &maps && vmaps_version_ == maps.version) return vmaps_;
  ParameterMaps v = domain_->vertex_maps(maps, texture_->texel_count());
  vmaps_ = std::move(v);
  vmaps_source_ = &maps;
  vmaps_version_ = maps.version;
  return vmaps_;
}

void IntrinsicCpuBackend::step(const StepSettings& settings, uint64_t seed, uint64_t step_index,
                               uint32_t* /*eaters: food is MoMaS only*/) {
  if (settings.model == MOLDTEX_MODEL_CONTINUOUS) return step_continuous(settings, seed, step_index);
  if (settings.model == MOLDTEX_MODEL_GRAY_SCOTT) return step_gray_scott(settings);
  fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
       "The Intrinsic domain runs the continuous model and Gray-Scott; MoMaS works in texels: use the Texture domain");
}

void IntrinsicCpuBackend::step_continuous(const StepSettings& settings, uint64_t seed, uint64_t step_index) {
  const IntrinsicDomain& d = *domain_;
  const TextureDomain& td = *texture_;
  const ParameterMaps& maps = vertex_maps(*settings.maps);
  if (alias_.prob.empty()) alias_ = build_area_alias_table(*surface_);
  // Agents drift apart in memory order as they move; regroup them now and then.
  if (step_index % kSortInterval == 0) sort_by_tile(*surface_, td.width, td.height, agents_);
  ContinuousStepConstants c = continuous_constants(settings, td, settings.u_metric, surface_->triangle_count(),
                                                   agents_.size(), seed, step_index);
  c.width = d.vertex_count();  // planes of vertex values
  c.height = 1;
  const mtx_surface_tables tables = d.tables(surface_tables(*surface_, td));
  const float* field = c.has_fields && !field_.empty() ? field_.data() : nullptr;
  if (!field) c.has_fields = 0;
  const AliasTable& alias = maps.spawn_max.empty() ? alias_ : maps.spawn_alias;
  pool_->parallel_for(agents_.size(), 1024, [&](size_t begin, size_t end) {
    continuous_update_agents(tables, c, values_.data(), field, sums_.data(), alias,
                             c.bias_on || c.bias_spawn ? settings.bias.data() : nullptr, maps.agent_planes.data(),
                             maps.spawn_max.data(), agents_, begin, end);
  });
  settle_continuous_step(settings, maps, laplacian_for(maps, d.laplacian, mapped_), mapped_, c.deposit_units,
                         values_.data(), sums_.data(), pde_scratch_, species_count_, *pool_);
}

void IntrinsicCpuBackend::step_gray_scott(const StepSettings& settings) {
  const IntrinsicDomain& d = *domain_;
  if (species_count_ < kReactionPlanes) fail(MOLDTEX_ERROR_INTERNAL, "The Gray-Scott model needs two planes");
  const ParameterMaps& maps = vertex_maps(*settings.maps);
  reaction_step(laplacian_for(maps, d.laplacian, mapped_), settings.reaction, values_.data(), scratch_,
                d.vertex_count(), *pool_,
                reaction_maps(maps.feed(), maps.largest[MOLDTEX_MAP_FEED], maps.kill(),
                              maps.largest[MOLDTEX_MAP_KILL], settings.reaction));
}

void IntrinsicCpuBackend::read_pheromone(float* out) const {
  domain_->show(values_.data(), out, species_count_, *texture_, *pool_);
}

void IntrinsicCpuBackend::export_state(SimState& state) const {
  state.agents = agents_;
  state.pheromone.resize(texture_->texel_count() * species_count_);
  read_pheromone(state.pheromone.data());
  state.cells = values_;
}

void IntrinsicCpuBackend::import_state(const SimState& state) {
  std::vector<float> next = domain_->values_from_state(state, species_count_, *texture_, *pool_);
  import_agents(state.agents);
  values_ = std::move(next);
}

std::string IntrinsicCpuBackend::name() const {
  const unsigned n = pool_->size();
  return "CPU (" + std::to_string(n) + (n == 1 ? " thread" : " threads") + ", intrinsic domain)";
}

size_t IntrinsicCpuBackend::bytes() const {
  return agents_.bytes() + (values_.capacity() + scratch_.capacity() + field_.capacity() + pde_scratch_.capacity()) * 4 +
         sums_.capacity() * 4 + vmaps_.agent_planes.capacity() * 4 + alias_.prob.capacity() * 8 + domain_->bytes();
}

}  // namespace moldtex
