// Deposit sums kept per thread: each thread of the pool adds into its own plane with
// plain adds instead of atomic ones into one shared plane (an atomic add waits for the
// memory system and stops the loads around it; on the intrinsic domain they took about a
// fifth of a step). The sums are integers, so folding the threads' planes together gives
// the same result whichever thread added what: bit-identical for any thread count.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "backends/cpu/thread_pool.h"

namespace moldtex {

class PrivateSums {
 public:
  // Sets up for `cells` sums per thread over the pool's threads. Thread 0 adds into the
  // caller's own sums; each further thread needs a plane of its own, so where those would
  // pass kMaxBytes (many threads, a large plane) the threads share the caller's sums with
  // atomic adds instead (exclusive() false).
  void prepare(size_t cells, unsigned threads);
  bool exclusive() const { return exclusive_; }
  // Where thread `thread` adds: `shared` (the caller's sums) for thread 0 or when not
  // exclusive, else that thread's plane.
  int32_t* for_thread(int32_t* shared, unsigned thread) {
    return exclusive_ && thread > 0 ? planes_.data() + (thread - 1) * cells_ : shared;
  }
  // Adds the other threads' planes into `shared` (the `cells` sums prepared) and clears
  // them.
  void fold_into(int32_t* shared, ThreadPool& pool);
  size_t bytes() const { return planes_.capacity() * sizeof(int32_t); }

  static constexpr size_t kMaxBytes = size_t(256) << 20;

 private:
  std::vector<int32_t> planes_;  // (threads - 1) planes of cells_, all 0 between steps
  size_t cells_ = 0;
  unsigned others_ = 0;  // planes in planes_
  bool exclusive_ = false;
};

}  // namespace moldtex
