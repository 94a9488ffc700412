#include "backends/cpu/cpu_backend.h"

#include <algorithm>
#include <cstring>

#include "agents/parameter_maps.h"
#include "common/error.h"

namespace moldtex {

CpuBackend::CpuBackend(std::shared_ptr<const Surface> surface, std::shared_ptr<const TextureDomain> domain,
                       const Model& model, uint32_t species_count, unsigned threads,
                       std::shared_ptr<const IntrinsicDomain> intrinsic)
    : surface_(std::move(surface)),
      domain_(std::move(domain)),
      intrinsic_(std::move(intrinsic)),
      species_count_(species_count),
      pool_(std::make_unique<ThreadPool>(threads)) {
  const size_t n = (intrinsic_ ? intrinsic_->vertex_count() : domain_->texel_count()) * species_count_;
  pheromone_.assign(n, 0.f);
  scratch_.assign(n, 0.f);
  model_step_ = model.cpu_step(domain_->texel_count(), species_count_);
}

void CpuBackend::set_field(const std::vector<float>& field) {
  field_ = intrinsic_ && !field.empty() ? intrinsic_->sample_texels(field.data()) : field;
  node_field_ = intrinsic_ && !field_.empty() ? intrinsic_->lattice.field(field_) : std::vector<float>{};
}

const TexelLaplacian& CpuBackend::laplacian() {
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
  model_step_->clear();
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
  CpuStepContext context{*surface_, *domain_, intrinsic_.get(), species_count_, *pool_, agents_,
                         sort_scratch_, pheromone_, scratch_, field_, node_field_, *this};
  model_step_->step(context, settings, seed, step_index, eaters);
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
  model_step_->clear();
}

std::string CpuBackend::name() const {
  const unsigned n = pool_->size();
  return "CPU (" + std::to_string(n) + (n == 1 ? " thread" : " threads") + (intrinsic_ ? ", intrinsic domain)" : ")");
}

size_t CpuBackend::bytes() const {
  size_t domain = 0;
  if (laplacian_) domain += laplacian_->bytes();
  if (intrinsic_) domain += intrinsic_->bytes() + vertex_maps_.bytes() + node_field_.capacity() * 4;
  return agents_.bytes() + sort_scratch_.sorted.bytes() +
         (sort_scratch_.key.capacity() + sort_scratch_.start.capacity() + sort_scratch_.dest.capacity()) * 4 +
         (pheromone_.capacity() + scratch_.capacity() + field_.capacity()) * sizeof(float) + domain +
         model_step_->bytes();
}

}  // namespace moldtex
