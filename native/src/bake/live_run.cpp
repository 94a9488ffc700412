#include "bake/live_run.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "common/error.h"
#include "sim.h"

namespace moldtex {

namespace {
constexpr uint32_t kMaxChunk = 1000;  // steps per chunk: a stop waits at most for these
}

LiveRun::LiveRun(std::shared_ptr<Simulation> sim, double chunk_seconds, double limit_seconds,
                 double step_seconds_hint)
    : sim_(std::move(sim)), chunk_seconds_(chunk_seconds), limit_seconds_(limit_seconds) {
  if (!(chunk_seconds > 0.0 && chunk_seconds <= 10.0))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "chunk_seconds must be a number in (0, 10]");
  if (!(limit_seconds > 0.0 && limit_seconds <= 3600.0))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "limit_seconds must be a number in (0, 3600]");
  if (!(step_seconds_hint >= 0.0 && step_seconds_hint < 1e6))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "step_seconds_hint must be a number >= 0");
  step_seconds_.store(step_seconds_hint);
  thread_ = std::thread([this] { run(); });
}

LiveRun::~LiveRun() { stop(); }

void LiveRun::step_until_stopped() {
  using clock = std::chrono::steady_clock;
  const auto began = clock::now();
  while (!stop_.load(std::memory_order_relaxed) &&
         std::chrono::duration<double>(clock::now() - began).count() < limit_seconds_) {
    const double per = step_seconds_.load(std::memory_order_relaxed);
    const uint32_t chunk =
        per > 0.0 ? static_cast<uint32_t>(std::clamp(chunk_seconds_ / per, 1.0, double(kMaxChunk))) : 1u;
    const auto start = clock::now();
    sim_->step(chunk);
    const double now_per = std::chrono::duration<double>(clock::now() - start).count() / chunk;
    step_seconds_.store(per > 0.0 ? 0.5 * per + 0.5 * now_per : now_per, std::memory_order_relaxed);
    steps_.fetch_add(chunk, std::memory_order_relaxed);
  }
}

void LiveRun::run() {
  const JobOutcome ended = run_job([this] { step_until_stopped(); }, "Out of memory while stepping", "Internal error: ");
  if (ended.status != MOLDTEX_OK) {
    std::lock_guard<std::mutex> lock(mutex_);
    status_ = ended.status;
    message_ = ended.message;
  }
  running_.store(false, std::memory_order_release);  // the last touch of the simulation is above
}

moldtex_run_progress LiveRun::progress() const {
  moldtex_run_progress p;
  std::memset(&p, 0, sizeof p);
  p.struct_size = sizeof p;
  p.running = running() ? 1u : 0u;
  p.steps = steps_.load(std::memory_order_relaxed);
  p.step_seconds = step_seconds_.load(std::memory_order_relaxed);
  return p;
}

moldtex_status LiveRun::stop() {
  stop_.store(true, std::memory_order_relaxed);
  {
    std::lock_guard<std::mutex> join(join_mutex_);
    if (thread_.joinable()) thread_.join();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  return status_;
}

std::string LiveRun::message() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return message_;
}

}  // namespace moldtex
