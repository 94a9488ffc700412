// The OpenCL backend: agents, surface tables and pheromone live on the device between
// steps; data crosses to the host only when the pheromone or the agents are read. The
// kernels compile the same shared sources as the CPU backend (shared/*.h).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "agents/agents.h"
#include "agents/parameter_maps.h"
#include "backends/backend.h"
#include "backends/opencl/devices.h"
#include "domain/intrinsic_domain.h"
#include "domain/surface_diffusion.h"
#include "domain/texel_laplacian.h"
#include "domain/texture_domain.h"

namespace moldtex {

class OpenClBackend final : public Backend {
 public:
  // Throws moldtex::Error with a message a user can act on if the device cannot be used
  // (no runtime, kernel build failure, not enough device memory).
  // With `intrinsic`, the continuous model and Gray-Scott run on the intrinsic domain
  // (domain/intrinsic_domain.h): planes of vertex values on the device, shown in the
  // texture on the host when read.
  OpenClBackend(std::shared_ptr<const Surface> surface, std::shared_ptr<const TextureDomain> domain,
                uint32_t agent_count, uint32_t species_count, const cl::Device& device,
                std::shared_ptr<const IntrinsicDomain> intrinsic = nullptr);
  ~OpenClBackend() override;
  void reset(const Agents& agents) override;
  void step(const StepSettings& settings, uint64_t seed, uint64_t step_index,
            uint32_t* eaters) override;
  void finish() override;
  void set_thread_count(unsigned) override {}
  void set_field(const std::vector<float>& field) override;
  void read_pheromone(float* out) const override;
  void read_agents(moldtex_surface_point* out, size_t count) const override;
  size_t agent_count() const override { return agent_count_; }
  size_t bytes() const override { return device_bytes_; }
  std::string name() const override;
  void export_state(SimState& state) const override;
  void import_state(const SimState& state) override;
  void export_agents(Agents& agents) const override;
  void import_agents(const Agents& agents) override;
  void append_agents(const Agents& extra) override;
  std::vector<float> read_cells() const override;

 private:
  // Makes the agent buffers hold at least `count` agents (reallocating, contents lost).
  void reserve_agents(size_t count);
  // Writes the agents of `a` into the buffers from agent `first` on (room reserved).
  void upload_agents(const Agents& a, size_t first);
  // The agent kernel specialised for food with hunger on/off and fields on/off (and this
  // simulation's species count), built on first use.
  cl_kernel agent_kernel(bool food, bool fields);
  // Surface units: diffusion and evaporation of the deposited pheromone (result in the
  // pheromone buffer).
  void surface_diffusion(const moldtex_sim_params& params);
  // The continuous model: its step, its agent kernel (fields on/off) and, at its first
  // step, its tables on the device (the PDE's cells, the respawn table, deposit sums).
  void step_continuous(const StepSettings& settings, uint64_t seed, uint64_t step_index);
  void step_gray_scott(const StepSettings& settings);
  cl_kernel continuous_kernel(bool fields);
  void prepare_continuous();
  // The PDE's step: forward-Euler sub-steps on the device, or backward Euler on the host.
  void diffuse_continuous(const moldtex_continuous_params& params, const ParameterMaps& maps);
  // The diffusion map's conductances (and rates, where Gray-Scott made that buffer) on the
  // device, when the map changed since the last upload.
  void upload_conductances(const ParameterMaps& maps, const TexelLaplacian& lap);
  void integrate(const moldtex_continuous_params& params, const TexelLaplacian& lap);
  // The maps the kernels read: the simulation's, or on the intrinsic domain read at the
  // vertices (remade when they change).
  const ParameterMaps& maps_for(const ParameterMaps& maps);
  // The device's planes as they are (cells_ values per species).
  void read_planes(float* out) const;

  struct State;
  std::shared_ptr<const Surface> surface_;
  std::shared_ptr<const TextureDomain> domain_;
  std::shared_ptr<const IntrinsicDomain> intrinsic_;
  size_t cells_ = 0;  // values per plane: texels, or intrinsic vertices
  VertexMaps vertex_maps_;
  mutable std::unique_ptr<ThreadPool> host_pool_;  // showing vertex values in the texture
  uint32_t agent_count_, species_count_;
  size_t agent_capacity_ = 0;  // agents the device buffers hold
  // Brush batch tag of each agent. Kept on the host: the device never reorders agents,
  // so agent i on the device is always tag i here.
  std::vector<uint16_t> batch_;
  cl::Device device_;
  size_t device_bytes_ = 0;
  std::unique_ptr<State> state_;
  DiffusionPlan plan_;  // the one on the device
  // Continuous model: the PDE's operator (host copy: backward Euler solves on the host).
  std::unique_ptr<TexelLaplacian> laplacian_;
  MappedLaplacian mapped_;  // with diffusion and decay maps
  // What the device's weight and decay buffers hold: (maps, version, r_dec dt) or none.
  const void* weights_source_ = nullptr;
  uint64_t weights_version_ = 0;
  const void* decay_source_ = nullptr;
  uint64_t decay_version_ = 0;
  double decay_key_ = -1;
  std::vector<float> pde_scratch_;
};

}  // namespace moldtex
