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
  uint64_t surface_fingerprint = 0;
  uint64_t step_count = 0;
  std::vector<MetricRow> metrics;
  std::vector<moldtex_species_params> species;  // MOLDTEX_MAX_SPECIES entries
  std::vector<float> fields_rgba;               // width * height * 4, or empty
  std::vector<moldtex_food_source> food;        // with the amounts left
  SimState state;
};

void save_checkpoint(const std::string& path, const Checkpoint& checkpoint);
Checkpoint load_checkpoint(const std::string& path);

}  // namespace moldtex
