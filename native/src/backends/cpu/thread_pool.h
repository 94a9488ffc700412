// A small fixed pool of worker threads with a blocking parallel_for. Work is split
// into contiguous chunks; callers must make results independent of the split (the
// simulation does: every agent and texel is computed from read-only inputs).
#pragma once
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace moldtex {

class ThreadPool {
 public:
  explicit ThreadPool(unsigned thread_count);  // 0 = all hardware threads
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  unsigned size() const { return static_cast<unsigned>(workers_.size()) + 1; }

  // Calls body(begin, end) over [0, count) in chunks of at least min_chunk items,
  // on the workers and the calling thread; returns when all chunks are done. The
  // first exception thrown by a body is rethrown here.
  void parallel_for(size_t count, size_t min_chunk,
                    const std::function<void(size_t, size_t)>& body);
  // The same, telling each chunk which thread runs it (0: the calling thread, up to
  // size() - 1), so a body can write into that thread's own buffers: no two chunks that
  // run at once share a thread number.
  void parallel_for_threads(size_t count, size_t min_chunk,
                            const std::function<void(size_t, size_t, unsigned)>& body);

  static unsigned resolve_thread_count(unsigned requested);

 private:
  void worker_loop(unsigned thread);
  void run_chunks(unsigned thread);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(size_t, size_t, unsigned)>* body_ = nullptr;
  size_t count_ = 0, chunk_ = 0, next_ = 0;
  unsigned busy_ = 0;
  uint64_t generation_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace moldtex
