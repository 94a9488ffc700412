// A model: how the simulated state behaves (agents and what they deposit, or a reaction),
// behind the one interface Simulation asks. Each model is a folder beside this file
// (momas/, continuous/, gray_scott/) and one entry of models/registry.cpp; Simulation
// calls these and never tests which model it runs. docs/ARCHITECTURE.md, "Adding a
// model", lists what a new one touches.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "moldtex.h"

namespace moldtex {

class CpuModelStep;
class Surface;
class ThreadPool;
struct StepSettings;
struct TextureDomain;

// texel -> its first two planes before a stroke's first dab there (the brushes of a
// model without agents paint its planes; undo puts these back).
using PaintUndo = std::map<uint32_t, std::array<float, 2>>;

class Model {
 public:
  virtual ~Model() = default;
  virtual uint32_t id() const = 0;  // its moldtex_model
  // As a sentence names it: "MoMaS", "the continuous model", "Gray-Scott".
  virtual const char* name_in_text() const = 0;

  // ---- configuration ------------------------------------------------------------------
  // The config as a simulation of this model keeps it (Gray-Scott: no agents, two planes).
  virtual void keep_config(moldtex_sim_config&) const {}
  virtual bool has_agents() const { return true; }
  // Detail above 1 (moldtex_sim_config.detail): simulating finer than the image.
  virtual bool supports_detail() const { return false; }
  virtual bool runs_on(uint32_t domain) const = 0;  // a moldtex_domain
  // Memory beyond the texture's common planes, per domain texel (the memory guard).
  virtual double extra_bytes_per_texel(const moldtex_sim_config&) const { return 0; }
  // The largest value a plane of a valid state holds (a checkpoint's check).
  virtual float max_plane_value() const = 0;

  // ---- time and agents ------------------------------------------------------------------
  // Simulated seconds a step advances.
  virtual double time_step(const StepSettings&) const = 0;
  // Whether the agents carry clocks (turnover, activation) that start in the steady
  // state of the model's parameters and its lifetime and activation maps.
  virtual bool agent_clocks() const { return false; }
  // The reference concentration U of each species (settings.u_metric, one per species;
  // 0 where the model has none) from its live agents and the cells' total area.
  virtual void update_u_metric(StepSettings& settings, const std::vector<double>& species_agents,
                               double cell_area) const;

  // ---- models without agents ---------------------------------------------------------------
  // The planes' starting state (planes of the domain's texels), weighted by the spawn map
  // where given.
  virtual std::vector<float> initial_planes(const Surface&, const TextureDomain&, const StepSettings&,
                                            uint64_t /*seed*/, const std::vector<double>* /*weights*/,
                                            ThreadPool&) const {
    return {};
  }
  // A slime brush dab painted into the planes; returns the texels it changed.
  virtual uint32_t paint(const Surface&, const TextureDomain&, float* /*planes*/, const moldtex_brush&,
                         bool /*erase*/, PaintUndo&, ThreadPool&) const {
    return 0;
  }
  virtual void unpaint(const TextureDomain&, float* /*planes*/, const PaintUndo&, ThreadPool&) const {}

  // ---- its steps ------------------------------------------------------------------------------
  // Its step on the CPU backend (backends/cpu/cpu_model_step.h), for planes of `texels`
  // texels per species.
  virtual std::unique_ptr<CpuModelStep> cpu_step(size_t texels, uint32_t species_count) const = 0;

  // ---- what is shown -------------------------------------------------------------------------
  // The planes as images show them, in place (`cells` values per plane).
  virtual void display(std::vector<float>& /*planes*/, size_t /*cells*/, const StepSettings&) const {}
  // Coverage, presence (and the model's own figures) of the shown planes; `raw` as held.
  virtual void stats(moldtex_sim_stats& s, const TextureDomain& d, const std::vector<float>& raw,
                     const std::vector<float>& shown, const StepSettings& settings) const;
};

// Adds a model beyond the built-in ones (its id unused so far; it must outlive every
// simulation of it; register it before any simulation runs). For models defined outside
// the library's sources, as the tests'.
void register_model(const Model& model);
// The model of a moldtex_model, or null if there is none (models/registry.cpp).
const Model* find_model(uint32_t id);
// The same, refusing an unknown id with the list of models.
const Model& model_of(uint32_t id);
// "the continuous model and Gray-Scott": the models that pass `test`, or run on `domain`,
// in a sentence.
std::string models_that(const std::function<bool(const Model&)>& test);
std::string models_on(uint32_t domain);

}  // namespace moldtex
