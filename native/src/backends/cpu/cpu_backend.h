// The CPU backend: agents on all cores through a thread pool, field operations split
// by rows. Deterministic for any thread count (see momas_update_agents).
#pragma once
#include <memory>
#include <vector>

#include "agents/agents.h"
#include "backends/backend.h"
#include "agents/parameter_maps.h"
#include "backends/cpu/cpu_model_step.h"
#include "domain/intrinsic_domain.h"
#include "domain/surface_diffusion.h"
#include "domain/texel_laplacian.h"
#include "domain/texture_domain.h"
#include "models/model.h"

namespace moldtex {

class CpuBackend final : public Backend, private CpuDomainOperators {
 public:
  // With `intrinsic`, the continuous model and Gray-Scott run on the intrinsic domain
  // (domain/intrinsic_domain.h): the agents still walk the input mesh; the planes hold
  // vertex values, shown in the texture when read; maps and fields are read at each
  // vertex's texel.
  // `model` steps the state (Model::cpu_step).
  CpuBackend(std::shared_ptr<const Surface> surface, std::shared_ptr<const TextureDomain> domain,
             const Model& model, uint32_t species_count, unsigned threads,
             std::shared_ptr<const IntrinsicDomain> intrinsic = nullptr);
  void reset(const Agents& agents) override;
  void step(const StepSettings& settings, uint64_t seed, uint64_t step_index,
            uint32_t* eaters) override;
  void set_thread_count(unsigned threads) override;
  void set_field(const std::vector<float>& field) override;
  void read_pheromone(float* out) const override;
  void read_agents(moldtex_surface_point* out, size_t count) const override;
  size_t agent_count() const override { return agents_.size(); }
  size_t bytes() const override;
  std::string name() const override;
  void export_state(SimState& state) const override;
  void import_state(const SimState& state) override;
  void export_agents(Agents& agents) const override { agents = agents_; }
  void import_agents(const Agents& agents) override;
  const Agents* agents_in_place() const override { return &agents_; }
  void remove_agents(const std::vector<uint8_t>& drop, Agents&) override { agents_.remove_marked(drop); }
  void append_agents(const Agents& extra) override { agents_.append(extra); }
  std::vector<float> read_cells() const override { return intrinsic_ ? pheromone_ : std::vector<float>{}; }

 private:
  // CpuDomainOperators: the PDE's operator (built at the first step on the texture
  // domain) and the maps the agents and the PDE read (on the intrinsic domain: at the
  // vertices).
  const TexelLaplacian& laplacian() override;
  const ParameterMaps& maps_for(const ParameterMaps& maps) override;
  MappedLaplacian& mapped() override { return mapped_; }

  std::shared_ptr<const Surface> surface_;
  std::shared_ptr<const TextureDomain> domain_;
  std::shared_ptr<const IntrinsicDomain> intrinsic_;
  VertexMaps vertex_maps_;
  uint32_t species_count_;
  std::unique_ptr<ThreadPool> pool_;
  Agents agents_;
  TileSortScratch sort_scratch_;
  // species_count_ planes each, of texels or (intrinsic domain) of vertex values.
  std::vector<float> pheromone_, scratch_;
  std::vector<float> field_;  // per texel, or per vertex
  // The intrinsic domain: the static field at the lattice's nodes.
  std::vector<float> node_field_;
  std::unique_ptr<TexelLaplacian> laplacian_;  // the texture domain's, built at first use
  MappedLaplacian mapped_;                     // with diffusion and decay maps
  std::unique_ptr<CpuModelStep> model_step_;   // what only the model keeps
};

}  // namespace moldtex
