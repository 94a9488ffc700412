#include "backends/cpu/thread_pool.h"

#include <algorithm>
#include <cstdint>

namespace moldtex {

unsigned ThreadPool::resolve_thread_count(unsigned requested) {
  unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  if (requested == 0) return hw;
  return std::min(requested, 256u);
}

ThreadPool::ThreadPool(unsigned thread_count) {
  unsigned n = resolve_thread_count(thread_count);
  for (unsigned i = 1; i < n; ++i) workers_.emplace_back([this, i] { worker_loop(i); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
}

void ThreadPool::run_chunks(unsigned thread) {
  for (;;) {
    size_t begin;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (next_ >= count_ || error_) return;
      begin = next_;
      next_ = std::min(count_, next_ + chunk_);
    }
    size_t end = std::min(count_, begin + chunk_);
    try {
      (*body_)(begin, end, thread);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
}

void ThreadPool::worker_loop(unsigned thread) {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      ++busy_;
    }
    run_chunks(thread);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
    }
    done_.notify_all();
  }
}

void ThreadPool::parallel_for(size_t count, size_t min_chunk,
                              const std::function<void(size_t, size_t)>& body) {
  parallel_for_threads(count, min_chunk, [&body](size_t begin, size_t end, unsigned) { body(begin, end); });
}

void ThreadPool::parallel_for_threads(size_t count, size_t min_chunk,
                                      const std::function<void(size_t, size_t, unsigned)>& body) {
  if (count == 0) return;
  size_t threads = size();
  // Many chunks per thread balance uneven work (agents crossing many edges) and keep
  // short the wait for the last chunk at the end: with 8 per thread instead of 32, the
  // MoMaS step on two threads took 3-8% longer (docs/PERFORMANCE.md).
  size_t chunk = std::max<size_t>(std::max<size_t>(min_chunk, 1), count / (threads * 32) + 1);
  if (threads == 1 || count <= chunk) {
    body(0, count, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    body_ = &body;
    count_ = count;
    chunk_ = chunk;
    next_ = 0;
    error_ = nullptr;
    ++generation_;
  }
  wake_.notify_all();
  run_chunks(0);
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return busy_ == 0 && (next_ >= count_ || error_); });
    body_ = nullptr;
    error = error_;
    error_ = nullptr;
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace moldtex
