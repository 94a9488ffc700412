// The CPU backend on the intrinsic domain (domain/intrinsic_domain.h): the continuous
// model's agents walk the input mesh as on the texture domain, and read and deposit at
// the intrinsic vertices, where the concentration lives; Gray-Scott's two chemicals live
// there too. Everything the simulation exchanges with a backend stays as on the texture
// domain: agents on the input mesh, pheromone as texture planes (a gather from the
// vertices, the gutter filled), maps and static fields per texel (read at each vertex's
// texel).
// Deterministic for any thread count, like the texture domain's CPU backend.
#pragma once
#include <memory>
#include <unordered_map>
#include <vector>

#include "backends/backend.h"
#include "backends/cpu/cpu_backend.h"
#include "domain/intrinsic_domain.h"

namespace moldtex {

class IntrinsicCpuBackend final : public Backend {
 public:
  IntrinsicCpuBackend(std::shared_ptr<const Surface> surface, std::shared_ptr<const TextureDomain> texture,
                      std::shared_ptr<const IntrinsicDomain> domain, uint32_t species_count, unsigned threads);
  void reset(const Agents& agents) override;
  void step(const StepSettings& settings, uint64_t seed, uint64_t step_index, uint32_t* eaters) override;
  void set_thread_count(unsigned threads) override;
  void set_field(const std::vector<float>& field) override;
  void read_pheromone(float* out) const override;
  void read_agents(moldtex_surface_point* out, size_t count) const override;
  size_t agent_count() const override { return agents_.size(); }
  size_t bytes() const override;
  std::string name() const override;
  // The state: agents, texture planes (what the vertices show) and the vertex values
  // (SimState::cells). import_state takes the vertex values plus any change made to the
  // planes since (a brush dab), or planes alone (each vertex its texel's value).
  void export_state(SimState& state) const override;
  void import_state(const SimState& state) override;
  void export_agents(Agents& agents) const override { agents = agents_; }
  void import_agents(const Agents& agents) override;

  // The vertex values, one plane of vertex_count per species.
  std::vector<float> read_cells() const override { return values_; }
  const IntrinsicDomain& domain() const { return *domain_; }

 private:
  void step_continuous(const StepSettings& settings, uint64_t seed, uint64_t step_index);
  void step_gray_scott(const StepSettings& settings);
  // The simulation's per-texel maps read at the vertices (when their version changes).
  const ParameterMaps& vertex_maps(const ParameterMaps& maps);

  std::shared_ptr<const Surface> surface_;
  std::shared_ptr<const TextureDomain> texture_;
  std::shared_ptr<const IntrinsicDomain> domain_;
  uint32_t species_count_;
  std::unique_ptr<ThreadPool> pool_;
  Agents agents_;                        // on the input mesh
  AliasTable alias_;                     // respawns: input triangles by area
  std::vector<float> values_, scratch_;  // species_count_ planes of vertex_count
  std::vector<int32_t> sums_;
  std::vector<float> field_;             // per vertex (empty = none)
  std::vector<float> pde_scratch_;
  MappedLaplacian mapped_;
  ParameterMaps vmaps_;
  const void* vmaps_source_ = nullptr;
  uint64_t vmaps_version_ = ~0ull;
};

}  // namespace moldtex
