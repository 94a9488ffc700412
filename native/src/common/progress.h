// Progress and cancel of long work running on its own thread (building the intrinsic
// domain): the worker reports its stage and how far it is into it, and checks at safe
// points whether it was asked to stop. Read and written from two threads.
#pragma once
#include <atomic>
#include <cstdint>

#include "common/error.h"

namespace moldtex {

struct WorkProgress {
  std::atomic<bool> cancel{false};
  std::atomic<uint32_t> stage{0};           // what the work does now (its own numbering)
  std::atomic<double> stage_fraction{0.0};  // 0..1 within the stage, an estimate
  std::atomic<uint64_t> count{0};           // items made so far (e.g. vertices)

  void enter(uint32_t s) {
    stage_fraction.store(0.0, std::memory_order_relaxed);
    stage.store(s, std::memory_order_relaxed);
  }
  // Throws MOLDTEX_ERROR_CANCELLED once cancel is set (the worker unwinds; nothing it
  // built is kept).
  void check_cancel() const {
    if (cancel.load(std::memory_order_relaxed)) fail(MOLDTEX_ERROR_CANCELLED, "Cancelled.");
  }
};

}  // namespace moldtex
