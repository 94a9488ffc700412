#include "domain_build.h"

#include <algorithm>

#include "backends/cpu/thread_pool.h"
#include "common/error.h"
#include "models/model.h"
#include "sim.h"

namespace moldtex {

namespace {

// Share of the build's time per stage (moldtex_build_stage), measured on tori of 4 k and
// 100 k triangles at 1024^2 (11.8 s each here): texels 0.05 s, refinement 6.7-6.9 s,
// operators 4.7-5.0 s (the locator 60% of them), texel map 0.17 s.
constexpr double kStageShare[MOLDTEX_BUILD_DONE] = {0.005, 0.58, 0.40, 0.015};

double overall_fraction(uint32_t stage, double within) {
  if (stage >= MOLDTEX_BUILD_DONE) return 1.0;
  double done = 0;
  for (uint32_t s = 0; s < stage; ++s) done += kStageShare[s];
  return std::min(1.0, done + kStageShare[stage] * std::clamp(within, 0.0, 1.0));
}

}  // namespace

DomainBuild::DomainBuild(std::shared_ptr<const Surface> surface, const moldtex_sim_config& config,
                         unsigned thread_count, std::shared_ptr<IntrinsicDomainCache> cache)
    : surface_(std::move(surface)), config_(kept_config(config)), thread_count_(thread_count), cache_(std::move(cache)) {
  if (!cache_) fail(MOLDTEX_ERROR_INTERNAL, "A domain build needs its context's cache");
  if (!surface_) fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The surface handle is NULL");
  if (config_.domain != MOLDTEX_DOMAIN_INTRINSIC)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Only the Intrinsic domain is built ahead (config.domain)");
  const Model* model = find_model(config_.model);
  if (model && !model->runs_on(MOLDTEX_DOMAIN_INTRINSIC))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The Intrinsic domain runs " + models_on(MOLDTEX_DOMAIN_INTRINSIC) + "; " +
                                             model->name_in_text() + " works in texels: use the Texture domain");
  // Where the agents start and the fields do not shape the domain: not checked here.
  config_.seed_shape = MOLDTEX_SEED_RANDOM;
  config_.fields_rgba = nullptr;
  validate_config(config_, *surface_);
  began_ = std::chrono::steady_clock::now();
  thread_ = std::thread([this] { run(); });
}

DomainBuild::~DomainBuild() {
  cancel();
  wait();
}

void DomainBuild::run() {
  std::shared_ptr<const IntrinsicDomain> built;
  bool from_cache = false;
  const JobOutcome outcome = run_job(
      [&] {
        work_.enter(MOLDTEX_BUILD_TEXTURE);
        TextureDomain texture;
        {
          ThreadPool pool(thread_count_);
          texture = build_texture_domain(*surface_, config_.width, config_.height, pool);
        }
        work_.check_cancel();
        // As the simulation will see it (Simulation's constructor): faces whose UVs have
        // zero area are walked on.
        const std::shared_ptr<const Surface> walkable = walkable_in_3d(surface_);
        built = prepare_intrinsic_domain(*walkable, texture, config_, thread_count_, *cache_, &from_cache, &work_);
        work_.count.store(built->vertex_count(), std::memory_order_relaxed);
        work_.enter(MOLDTEX_BUILD_DONE);
      },
      "Out of memory building the intrinsic triangulation: raise the Triangle Size", "Internal error: ");
  const moldtex_status status = outcome.status;
  const std::string& message = outcome.message;
  const uint32_t state = outcome.state();
  std::lock_guard<std::mutex> lock(mutex_);
  built_ = std::move(built);
  from_cache_ = from_cache;
  seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - began_).count();
  status_ = status;
  message_ = message;
  state_ = state;
}

moldtex_domain_build_progress DomainBuild::progress() const {
  moldtex_domain_build_progress p;
  moldtex_domain_build_progress_init(&p);
  std::lock_guard<std::mutex> lock(mutex_);
  p.state = state_;
  p.stage = work_.stage.load(std::memory_order_relaxed);
  p.vertex_count = static_cast<uint32_t>(std::min<uint64_t>(work_.count.load(std::memory_order_relaxed), ~0u));
  fraction_ = std::max(fraction_, overall_fraction(p.stage, work_.stage_fraction.load(std::memory_order_relaxed)));
  p.fraction = state_ == MOLDTEX_BAKE_FINISHED ? 1.0 : fraction_;
  p.seconds = state_ == MOLDTEX_BAKE_RUNNING
                  ? std::chrono::duration<double>(std::chrono::steady_clock::now() - began_).count()
                  : seconds_;
  p.from_cache = from_cache_ ? 1u : 0u;
  const size_t n = std::min(message_.size(), sizeof(p.message) - 1);
  std::copy(message_.begin(), message_.begin() + n, p.message);
  p.message[n] = '\0';
  return p;
}

moldtex_status DomainBuild::wait() {
  {
    std::lock_guard<std::mutex> join(join_mutex_);
    if (thread_.joinable()) thread_.join();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  return status_;
}

std::string DomainBuild::message() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return message_;
}

}  // namespace moldtex
