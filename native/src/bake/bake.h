// A bake: frames of the growing pattern written to disk on a worker thread, with
// progress, cancellation, metrics CSV, checkpoints and resume (moldtex_bake_* in the
// public header describe the contract).
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "io/checkpoint.h"
#include "moldtex.h"
#include "sim.h"

namespace moldtex {

struct BakeOptions {
  std::string directory, prefix;
  int32_t first_frame = 1, last_frame = 1;
  uint32_t steps_per_frame = 1;
  moldtex_image_format format = MOLDTEX_IMAGE_EXR_HALF;
  bool write_checkpoints = true, resume = false;
};

BakeOptions validate_bake(const moldtex_bake_desc& desc);

class Bake {
 public:
  Bake(std::shared_ptr<Simulation> sim, BakeOptions options);
  ~Bake();  // cancels and joins
  void cancel() { cancel_ = true; }
  moldtex_status wait();
  moldtex_bake_progress progress() const;

  std::string frame_path(int32_t frame) const;
  std::string metrics_path() const { return options_.directory + "/" + options_.prefix + "metrics.csv"; }
  std::string checkpoint_path() const { return options_.directory + "/" + options_.prefix + "checkpoint.bin"; }

 private:
  void run();
  void bake_frames();  // the work of run(); throws on failure or cancel
  void write_metrics_csv(const std::vector<MetricRow>& rows) const;

  std::shared_ptr<Simulation> sim_;
  BakeOptions options_;
  std::atomic<bool> cancel_{false};
  mutable std::mutex mutex_;
  moldtex_bake_progress progress_{};
  moldtex_status outcome_ = MOLDTEX_OK;
  std::thread worker_;
};

}  // namespace moldtex
