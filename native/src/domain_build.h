// Building a simulation's intrinsic domain ahead, on its own thread, with progress and
// cancel (moldtex_domain_build_*): the refinement of a big mesh takes seconds, and an
// interface wants to show how far it is and let the user stop it. What it builds lands in
// the intrinsic domain cache it is given (its context's, domain/intrinsic_domain.h), where
// the simulation created next in that context with the same mesh, texture size and bound
// finds it.
#pragma once
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "common/progress.h"
#include "domain/intrinsic_domain.h"
#include "moldtex.h"
#include "surface/surface.h"

namespace moldtex {

class DomainBuild {
 public:
  // Checks the config now (as moldtex_sim_create does; the texture domain and MoMaS are
  // refused), then starts the thread.
  DomainBuild(std::shared_ptr<const Surface> surface, const moldtex_sim_config& config, unsigned thread_count,
              std::shared_ptr<IntrinsicDomainCache> cache);
  ~DomainBuild();  // cancels and waits
  DomainBuild(const DomainBuild&) = delete;
  DomainBuild& operator=(const DomainBuild&) = delete;

  moldtex_domain_build_progress progress() const;
  void cancel() { work_.cancel = true; }
  // Waits for the end: MOLDTEX_OK, MOLDTEX_ERROR_CANCELLED or the build's error (message()).
  moldtex_status wait();
  std::string message() const;

 private:
  void run();

  std::shared_ptr<const Surface> surface_;
  moldtex_sim_config config_;
  unsigned thread_count_;
  std::shared_ptr<IntrinsicDomainCache> cache_;  // kept while the build runs
  WorkProgress work_;
  std::chrono::steady_clock::time_point began_;
  mutable std::mutex mutex_;  // guards what follows
  uint32_t state_ = MOLDTEX_BAKE_RUNNING;
  moldtex_status status_ = MOLDTEX_OK;
  std::string message_;
  double seconds_ = 0;
  bool from_cache_ = false;
  mutable double fraction_ = 0;  // the largest reported (fraction only grows)
  std::shared_ptr<const IntrinsicDomain> built_;  // kept while the handle lives
  std::mutex join_mutex_;  // wait() from two threads joins once
  std::thread thread_;
};

}  // namespace moldtex
