// Checkpoints: the complete evolving state of a simulation in one binary file, so an
// interrupted bake can resume and produce exactly the frames it would have produced.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "moldtex.h"

namespace moldtex {

// One row of the bake's metrics (momas-paper.md Eq. 1 at a frame).
// Written to checkpoints as raw bytes: the explicit `reserved` leaves no padding, so
// identical bakes write identical files.
struct MetricRow {
  int32_t frame;
  int32_t reserved = 0;
  uint64_t step;
  double coverage, presence;
};

struct Checkpoint {
  moldtex_sim_config config{};   // width, height, agent count, seed must match to load
  moldtex_sim_params params{};
  moldtex_continuous_params continuous{};  // version 6
  double time = 0;                         // simulated seconds (version 6)
  moldtex_reaction_params reaction{};      // Gray-Scott (version 8)
  uint64_t surface_fingerprint = 0;
  uint64_t step_count = 0;
  std::vector<MetricRow> metrics;
  std::vector<moldtex_species_params> species;  // MOLDTEX_MAX_SPECIES entries
  std::vector<float> fields_rgba;               // width * height * 4, or empty
  std::vector<moldtex_food_source> food;        // with the amounts left
  std::vector<float> bias;                      // triangle_count * 3, or empty (version 6)
  std::vector<uint32_t> map_kinds;              // moldtex_map of each map set (version 7)
  std::vector<float> maps;                      // width * height per entry of map_kinds
  SimState state;
};

void save_checkpoint(const std::string& path, const Checkpoint& checkpoint);
// Reads the file and checks its structure (magic, sizes); the values are checked by
// validate_checkpoint_values, which the caller runs with what only it knows.
Checkpoint load_checkpoint(const std::string& path);

// Ranges of a checkpoint's values. The pheromone of a MoMaS simulation stays in [0, 1] (deposits
// are max(texel, deposit) with deposit <= 1; blur and evaporation never raise a texel
// above its neighbours); a bake's frames are 0 .. 999999 (moldtex_bake_desc).
constexpr float kMaxPheromone = 1.f;
constexpr int32_t kMaxFrame = 999999;
constexpr float kBaryTolerance = 1e-4f;    // b1 + b2 may exceed 1 by float rounding
constexpr double kHeadingTolerance = 1e-3;  // |heading| = 1 up to rounding

// Throws MOLDTEX_ERROR_IO naming the first bad value (the agent, texel or metrics row)
// unless every value is one the simulation can hold: agents on triangles < triangle_count
// with finite barycentrics in [0, 1] summing to 1, finite unit headings, species <
// species_count, hunger in [0, 1]; pheromone in [0, kMaxPheromone] (the continuous model's
// concentrations: finite, >= 0; its agent clocks finite, >= 0); metrics rows with
// increasing frames in 0 .. kMaxFrame, steps <= the checkpoint's step and coverage and
// presence in [0, 1]. Array sizes must have been checked before.
void validate_checkpoint_values(const Checkpoint& checkpoint, const std::string& path,
                                uint32_t triangle_count, uint32_t species_count);

}  // namespace moldtex
