#include "backends/cpu/cpu_backend.h"

#include <algorithm>
#include <cstring>

#include "agents/momas_rules.h"

namespace moldtex {

constexpr uint64_t kSortInterval = 16;

CpuBackend::CpuBackend(std::shared_ptr<const Surface> surface,
                       std::shared_ptr<const TextureDomain> domain, uint32_t agent_count,
                       unsigned threads)
    : surface_(std::move(surface)),
      domain_(std::move(domain)),
      agent_count_(agent_count),
      pool_(std::make_unique<ThreadPool>(threads)) {
  pheromone_.assign(domain_->texel_count(), 0.f);
  scratch_.assign(domain_->texel_count(), 0.f);
  marks_.assign(domain_->texel_count(), 0);
}

void CpuBackend::reset(uint64_t seed) {
  std::fill(pheromone_.begin(), pheromone_.end(), 0.f);
  std::fill(scratch_.begin(), scratch_.end(), 0.f);
  std::fill(marks_.begin(), marks_.end(), 0);
  agents_ = spawn_uniform(*surface_, agent_count_, seed, *pool_);
}

void CpuBackend::set_thread_count(unsigned threads) {
  if (ThreadPool::resolve_thread_count(threads) != pool_->size())
    pool_ = std::make_unique<ThreadPool>(threads);
}

void CpuBackend::step(const moldtex_sim_params& p, uint64_t seed, uint64_t step_index) {
  const TextureDomain& d = *domain_;
  const MomasStepConstants c = momas_constants(p, d, seed, step_index);
  // Agents drift apart in memory order as they move; regroup them now and then.
  if (step_index % kSortInterval == 0) sort_by_tile(*surface_, d.width, d.height, agents_);
  // 1. Agents sense the field as it was at the start of the step (read-only) and mark
  //    where they deposit: no thread reads what another is writing.
  const mtx_surface_tables tables = surface_tables(*surface_, d);
  pool_->parallel_for(agents_.size(), 1024, [&](size_t begin, size_t end) {
    momas_update_agents(tables, c, pheromone_.data(), marks_.data(), agents_, begin, end);
  });
  // 2. Deposit, make the gutter hold the texels across each seam, then blur (which then
  //    mixes across seams) and evaporate.
  apply_deposits(d, pheromone_.data(), marks_.data(), p.deposit, *pool_);
  fill_gutter(d, pheromone_.data(), *pool_);
  const float mix = std::min(1.f, p.diffusion_rate * p.time_step);
  diffuse_and_evaporate(d, pheromone_.data(), scratch_.data(), mix,
                        p.evaporation_rate * p.time_step, *pool_);
  pheromone_.swap(scratch_);
  fill_gutter(d, pheromone_.data(), *pool_);
}

void CpuBackend::read_pheromone(float* out) const {
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
  s.pheromone = pheromone_;
}

void CpuBackend::import_state(const SimState& s) {
  agents_ = s.agents;
  pheromone_ = s.pheromone;
  std::fill(marks_.begin(), marks_.end(), 0);
}

std::string CpuBackend::name() const {
  const unsigned n = pool_->size();
  return "CPU (" + std::to_string(n) + (n == 1 ? " thread)" : " threads)");
}

size_t CpuBackend::bytes() const {
  return agents_.bytes() + (pheromone_.capacity() + scratch_.capacity()) * sizeof(float) +
         marks_.capacity();
}

}  // namespace moldtex
