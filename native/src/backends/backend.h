// A backend owns the simulation state (agents and pheromone) and runs steps on some
// hardware. The CPU backend is the reference; an OpenCL backend can sit beside it and
// keep its state on the device, crossing to the host only when asked to read.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "agents/agents.h"
#include "moldtex.h"

namespace moldtex {

// Everything that evolves, in a backend-independent layout (checkpoints).
struct SimState {
  Agents agents;
  std::vector<float> pheromone;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual void reset(uint64_t seed) = 0;
  // May return before the device is done; finish() waits.
  virtual void step(const moldtex_sim_params& params, uint64_t seed, uint64_t step_index) = 0;
  virtual void finish() {}
  virtual void set_thread_count(unsigned threads) = 0;
  // Pheromone of the single species, width * height floats, gutter filled.
  virtual void read_pheromone(float* out) const = 0;
  virtual void read_agents(moldtex_surface_point* out, size_t count) const = 0;
  virtual size_t agent_count() const = 0;
  virtual size_t bytes() const = 0;
  virtual std::string name() const = 0;  // e.g. "CPU (2 threads)"
  virtual void export_state(SimState& state) const = 0;
  virtual void import_state(const SimState& state) = 0;
};

}  // namespace moldtex
