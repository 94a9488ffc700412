// A model's step on the CPU backend (Model::cpu_step): the backend owns the agents and the
// planes, the model's step object what only it keeps (MoMaS' deposit marks, the continuous
// model's deposit sums). The steps live in the models' folders.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "agents/agents.h"
#include "agents/momas_rules.h"
#include "agents/parameter_maps.h"
#include "backends/cpu/thread_pool.h"
#include "domain/intrinsic_domain.h"
#include "domain/texel_laplacian.h"
#include "domain/texture_domain.h"
#include "surface/surface.h"

namespace moldtex {

// Agents drift apart in memory order as they move: a step regroups them every this many.
constexpr uint64_t kSortInterval = 16;

// The domain's operators a model's CPU step asks for, built at first use.
class CpuDomainOperators {
 public:
  virtual ~CpuDomainOperators() = default;
  // The cell graph's Laplacian (texels or intrinsic vertices).
  virtual const TexelLaplacian& laplacian() = 0;
  // The maps at the domain's cells (the intrinsic domain: at its vertices).
  virtual const ParameterMaps& maps_for(const ParameterMaps& maps) = 0;
  // The Laplacian with the diffusion and decay maps applied (laplacian_for's cache).
  virtual MappedLaplacian& mapped() = 0;
};

// What a step works on: the backend's state, as it holds it.
struct CpuStepContext {
  const Surface& surface;
  const TextureDomain& domain;
  const IntrinsicDomain* intrinsic;  // the intrinsic domain, or null on the texture domain
  uint32_t species_count;
  ThreadPool& pool;
  Agents& agents;
  TileSortScratch& sort_scratch;
  // species_count planes each, of texels or (intrinsic domain) of vertex values.
  std::vector<float>& planes;
  std::vector<float>& scratch;
  const std::vector<float>& field;       // the static field per texel or vertex; empty = none
  const std::vector<float>& node_field;  // the same at the intrinsic lattice's nodes
  CpuDomainOperators& operators;
};

class CpuModelStep {
 public:
  virtual ~CpuModelStep() = default;
  // One step (see Backend::step for `eaters`).
  virtual void step(CpuStepContext& context, const StepSettings& settings, uint64_t seed, uint64_t step_index,
                    uint32_t* eaters) = 0;
  // The state was reset or replaced: forget what the last steps left.
  virtual void clear() {}
  virtual size_t bytes() const { return 0; }
};

}  // namespace moldtex
