// Live stepping on the core's own thread (moldtex_sim_run_*): Blender's Start lets the
// simulation grow between two viewport updates. It was a Python thread around
// moldtex_sim_step; Blender 3.4 then crashed now and then inside its own operators
// (PyDict_GetItem on the main thread without a valid thread state, seen in
// bpy.ops.screen.screenshot), since Blender's Python is not meant to run threads beside
// it. Here no Python runs off the main thread at all.
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "moldtex.h"

namespace moldtex {

class Simulation;

class LiveRun {
 public:
  // Steps `sim` in chunks of about chunk_seconds of work (from the measured cost of a
  // step; step_seconds_hint > 0 seeds it) until stop(), or until limit_seconds passed.
  LiveRun(std::shared_ptr<Simulation> sim, double chunk_seconds, double limit_seconds, double step_seconds_hint);
  ~LiveRun();  // stops and waits
  LiveRun(const LiveRun&) = delete;
  LiveRun& operator=(const LiveRun&) = delete;

  bool running() const { return running_.load(std::memory_order_acquire); }
  moldtex_run_progress progress() const;
  // Stops after the current chunk and waits; returns MOLDTEX_OK or the error a step
  // raised (message()).
  moldtex_status stop();
  std::string message() const;

 private:
  void run();
  void step_until_stopped();  // the work of run(); throws on failure

  std::shared_ptr<Simulation> sim_;
  double chunk_seconds_, limit_seconds_;
  std::atomic<bool> stop_{false}, running_{true};
  std::atomic<uint64_t> steps_{0};
  std::atomic<double> step_seconds_{0.0};
  mutable std::mutex mutex_;  // guards status_, message_
  moldtex_status status_ = MOLDTEX_OK;
  std::string message_;
  std::mutex join_mutex_;
  std::thread thread_;
};

}  // namespace moldtex
