// A backend owns the simulation state (agents and pheromone) and runs steps on some
// hardware. The CPU backend is the reference; an OpenCL backend can sit beside it and
// keep its state on the device, crossing to the host only when asked to read.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "agents/agents.h"
#include "agents/momas_rules.h"
#include "moldtex.h"

namespace moldtex {

// Everything that evolves, in a backend-independent layout (checkpoints).
struct SimState {
  Agents agents;
  std::vector<float> pheromone;  // one plane of width * height per species
  // Where the domain's cells are not texels (the intrinsic domain's vertices): their
  // values, one plane per species; `pheromone` then holds what they show in the texture.
  // Empty on the texture domain.
  std::vector<float> cells;
};

class Backend {
 public:
  virtual ~Backend() = default;
  // Clears the pheromone and takes these agents (spawned on the host).
  virtual void reset(const Agents& agents) = 0;
  // May return before the device is done; finish() waits. While food is active
  // (momas_constants(...).food_count > 0) `eaters` gets, per source of settings.food, the
  // number of agents that ate there this step, and the step completes before returning.
  virtual void step(const StepSettings& settings, uint64_t seed, uint64_t step_index,
                    uint32_t* eaters) = 0;
  virtual void finish() {}
  virtual void set_thread_count(unsigned threads) = 0;
  // Static field plane (width * height, gutter filled): MTX_OBSTACLE_FIELD at obstacles,
  // the attractor bonus elsewhere. Empty = no fields.
  virtual void set_field(const std::vector<float>& field) = 0;
  // Pheromone, one plane of width * height floats per species, gutter filled.
  virtual void read_pheromone(float* out) const = 0;
  virtual void read_agents(moldtex_surface_point* out, size_t count) const = 0;
  virtual size_t agent_count() const = 0;
  virtual size_t bytes() const = 0;
  virtual std::string name() const = 0;  // e.g. "CPU (2 threads)"
  // The whole state. import_state takes any number of agents (0 .. 2^26); agents
  // without batch tags get tag 0.
  virtual void export_state(SimState& state) const = 0;
  virtual void import_state(const SimState& state) = 0;
  // Only the agents (with species, hunger and batch tags); the pheromone stays. The
  // slime brushes edit a device's agents this way (export, edit on the host, import);
  // the CPU's in place (agents_in_place, remove_agents, append_agents).
  virtual void export_agents(Agents& agents) const = 0;
  // The values per cell where the domain's cells are not texels (the intrinsic domain's
  // vertices: species planes of vertex_count); empty on the texture domain.
  virtual std::vector<float> read_cells() const { return {}; }
  virtual void import_agents(const Agents& agents) = 0;
  // The agents where the backend keeps them, to read without a copy (the CPU's own
  // arrays), or null (a device's: export them).
  virtual const Agents* agents_in_place() const { return nullptr; }
  // Drops the agents whose entry of `drop` (one per agent) is not 0, the others in their
  // order (the erase brush). `exported`: the agents as export_agents gave them, dropped
  // from too; unused by a backend whose agents_in_place is not null.
  virtual void remove_agents(const std::vector<uint8_t>& drop, Agents& exported) {
    exported.remove_marked(drop);
    import_agents(exported);
  }
  // Adds `extra` after the agents (the add brush; an undone erase). Unchanged if it
  // throws.
  virtual void append_agents(const Agents& extra) {
    Agents all;
    export_agents(all);
    all.append(extra);
    import_agents(all);
  }
};

}  // namespace moldtex
