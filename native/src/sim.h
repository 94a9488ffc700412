// A simulation: a surface, its texture domain, the parameters, and a backend that owns
// the evolving state.
#pragma once
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "agents/parameter_maps.h"
#include "backends/backend.h"
#include "models/model.h"
#include "domain/intrinsic_domain.h"
#include "domain/texture_domain.h"
#include "io/checkpoint.h"
#include "surface/surface.h"

namespace moldtex {

void validate_config(const moldtex_sim_config& config, const Surface& surface);
void validate_params(const moldtex_sim_params& params);
void check_length_unit(const moldtex_sim_params& params, const Surface& surface);
void validate_species_params(const moldtex_species_params& params);
void validate_continuous_params(const moldtex_continuous_params& params);
// The config a simulation keeps: as its model keeps it (Model::keep_config); detail
// 0 read as 1.
moldtex_sim_config kept_config(const moldtex_sim_config& config);
// The intrinsic domain a simulation of `config` (as kept: kept_config, validated) on
// `surface` with texture domain `texture` runs on: the config's bound or the texture's
// default, refused if the machine lacks the memory, then built or taken from the cache
// (intrinsic_domain_for: from_cache, progress).
std::shared_ptr<const IntrinsicDomain> prepare_intrinsic_domain(const Surface& surface, const TextureDomain& texture,
                                                                const moldtex_sim_config& config, unsigned thread_count,
                                                                IntrinsicDomainCache& cache, bool* from_cache = nullptr,
                                                                WorkProgress* progress = nullptr);

class Simulation {
 public:
  // An intrinsic domain is taken from `cache` or built into it (the simulation's context's).
  Simulation(std::shared_ptr<const Surface> surface, const moldtex_sim_config& config,
             const moldtex_sim_params& params, IntrinsicDomainCache& cache);
  // Sets the shared parameters and the behaviour of every species (not the attractions).
  void set_params(const moldtex_sim_params& params);
  void set_species_params(uint32_t index, const moldtex_species_params& params);
  const moldtex_species_params& species_params(uint32_t index) const { return settings_.species[index]; }
  uint32_t species_count() const { return settings_.species_count; }
  // width * height * 4 floats (see moldtex_sim_set_fields), or nullptr to clear.
  void set_fields(const float* rgba);
  // Food sources (see moldtex_sim_set_food); validated here.
  void set_food(const moldtex_food_source* sources, uint32_t count);
  const std::vector<moldtex_food_source>& food() const { return food_; }
  const moldtex_sim_params& params() const { return settings_.params; }
  // The continuous model's parameters (kept, but unused, under MoMaS).
  void set_continuous_params(const moldtex_continuous_params& params);
  // The continuous model's bias vectors (3 per triangle, see moldtex_sim_set_bias), or
  // nullptr to clear; validated here.
  void set_bias(const float* vectors);
  // Parameter map or stimulus `kind` (moldtex_map), width * height values (per image
  // texel) or nullptr to clear; validated here. map() gives it as kept, per domain texel
  // (empty = not set).
  void set_map(uint32_t kind, const float* values);
  const std::vector<float>& map(uint32_t kind) const { return maps_->given[kind]; }
  const moldtex_continuous_params& continuous_params() const { return settings_.continuous; }
  // Gray-Scott reaction-diffusion's parameters (kept, but unused, under the other models).
  void set_reaction_params(const moldtex_reaction_params& params);
  const moldtex_reaction_params& reaction_params() const { return settings_.reaction; }
  const moldtex_sim_config& config() const { return config_; }
  const TextureDomain& domain() const { return *domain_; }
  // The image this API exchanges per texel: config width * height texels, each over
  // detail^2 texels of the domain (moldtex_sim_config.detail).
  uint32_t detail() const { return config_.detail; }
  size_t image_texel_count() const { return size_t(config_.width) * config_.height; }
  // See moldtex_sim_read_texel_classes (count checked there).
  void read_texel_classes(uint8_t* classes) const;
  // Map `kind` as set, per image texel (image_texel_count floats; set: see map()).
  void read_map(uint32_t kind, float* values) const;
  // The intrinsic domain (null on the texture domain) and what moldtex_sim_get_domain_info
  // reports.
  const IntrinsicDomain* intrinsic() const { return intrinsic_.get(); }
  moldtex_domain_info domain_info() const;
  // See moldtex_sim_read_intrinsic_vertices / _faces (count checked there).
  void read_intrinsic_vertices(float* xyz_area, float* values, uint32_t count) const;
  void read_intrinsic_faces(uint32_t* corners, uint32_t count) const;
  const Surface& surface() const { return *surface_; }
  void reset();
  void step(uint32_t steps);
  void read_rgba(float* rgba) const;
  // See moldtex_sim_read_vertex_rgba (intrinsic domain; the buffer size checked there).
  void read_vertex_rgba(float* rgba) const;
  // The pheromone planes, one per species, as the backend holds them.
  std::vector<float> read_field() const;
  // What images show: read_field, divided by U per species for the continuous model.
  // display_field takes species planes of `cells` values (0: the texture's texels).
  std::vector<float> read_display_field() const;
  std::vector<float> display_field(std::vector<float> field, size_t cells = 0) const;
  // read_display_field per image texel (texture_detail.h's image_planes at detail > 1).
  std::vector<float> image_field() const;
  // The classes per image texel.
  const std::vector<uint8_t>& image_texel_classes() const {
    return config_.detail > 1 ? image_classes_ : domain_->classes;
  }
  void read_agents(moldtex_surface_point* out, size_t count) const { backend_->read_agents(out, count); }
  moldtex_sim_stats stats() const;
  std::string backend_name() const {
    return why_not_opencl_.empty() ? backend_->name()
                                   : backend_->name() + "; OpenCL not used: " + why_not_opencl_;
  }
  uint64_t step_count() const { return step_count_; }
  // Writes the current pheromone as an image file (see moldtex_sim_write_image).
  void write_image(const std::string& path, moldtex_image_format format) const;
  void save_checkpoint(const std::string& path, const std::vector<MetricRow>& metrics) const;
  // Restores state and parameters; returns the metrics stored with them.
  std::vector<MetricRow> load_checkpoint(const std::string& path);
  // Slime brushes (see moldtex_sim_add_agents / erase_agents / undo_agents); `brush` is
  // read with its defaults, validated here.
  void add_agents(const moldtex_brush& brush, uint32_t count, uint32_t batch);
  uint32_t erase_agents(const moldtex_brush& brush, uint32_t batch);
  void undo_agents(uint32_t batch);
  // Set while a bake owns the simulation; the C API refuses other calls meanwhile.
  std::atomic<bool> busy{false};

 private:
  // U of every species from the live agents per species (continuous model), into
  // settings_; count_agents takes the agents' species first (after every change of the
  // live agents, which passes through here, so parameter changes need no read-back).
  void update_u_metric();
  void count_agents(const Agents& live);
  // The same after `added` joined the live agents (no recount of the others).
  void add_species_counts(const Agents& added);
  // Continuous model: steady-state clocks for agents [begin, end) (see start_agent_lives).
  void start_lives(Agents& agents, size_t begin, uint64_t stream);
  // The field plane the agents sense: the fields' obstacles and attractors plus the read
  // stimulus; given to the backend.
  void update_field_plane();

  std::shared_ptr<const Surface> surface_;
  const Model* model_ = nullptr;  // config_.model's (models/registry.cpp)
  std::shared_ptr<const TextureDomain> domain_;
  // At detail > 1 the image texels' classes (texture_detail.h's image_classes), fixed with
  // the domain; empty at detail 1 (the domain's own). See image_texel_classes().
  std::vector<uint8_t> image_classes_;
  std::shared_ptr<const IntrinsicDomain> intrinsic_;  // MOLDTEX_DOMAIN_INTRINSIC
  bool intrinsic_from_cache_ = false;
  moldtex_sim_config config_;  // fields_rgba is always NULL here
  StepSettings settings_;      // params (behaviour = species 0's) and every species
  // Static fields as given (width * height * 4, empty = none), the field plane the agents
  // sense, and the spawn weight of each texel (3D area * R, 0 at obstacles).
  std::vector<float> fields_rgba_, field_plane_, fields_only_plane_;
  std::vector<double> spawn_weights_, free_weights_;
  std::vector<moldtex_food_source> food_;  // with the amounts left
  std::vector<float> bias_3d_;             // as given (checkpoints), empty = none
  std::shared_ptr<ParameterMaps> maps_;    // also settings_.maps
  std::unique_ptr<Backend> backend_;
  // What each brush batch did, for undo: how many agents it added (the placement index
  // of its next agent) and the agents it erased, with their whole state.
  struct BrushBatch {
    uint64_t added = 0;
    uint64_t erase_dabs = 0;
    Agents erased;
    PaintUndo painted;  // a model without agents: the texels the stroke painted, as they were
  };
  uint32_t paint_dab(const moldtex_brush& brush, uint32_t batch, bool erase);
  std::map<uint32_t, BrushBatch> batches_;
  std::string why_not_opencl_;  // why Auto chose the CPU
  uint64_t step_count_ = 0;
  std::vector<double> species_agents_;  // live agents per species
  double time_ = 0;       // simulated seconds since create or reset
  double cell_area_ = 0;  // 3D area of the island texels (the PDE's cells): U's A
};

}  // namespace moldtex
