// Live stepping on the core's own thread (moldtex_sim_run_*): what Blender's Start
// relies on, so that no Python thread runs beside Blender's (which crashed Blender 3.4
// now and then).
#include <chrono>
#include <cmath>
#include <thread>

#include "test_util.h"

namespace mtx {
namespace {

const Mesh& Torus() {
  static const Mesh m = make_torus(32, 16, 1.0, 0.4);
  return m;
}

moldtex_run_progress RunProgress(moldtex_sim sim) {
  moldtex_run_progress p;
  moldtex_run_progress_init(&p);
  EXPECT_EQ(moldtex_sim_run_get_progress(sim, &p), MOLDTEX_OK) << LastError();
  return p;
}

// Steps grown on the thread are the steps moldtex_sim_step runs: a second simulation
// stepped as many steps by hand holds the same texture, bit for bit. While it runs, other
// calls are refused (BUSY), never run beside it.
TEST(LiveRun, GrowsWhatStepWouldAndRefusesOtherCalls) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s);
  const moldtex_sim_config c = make_config(64, 64, 4000, 5);
  auto live = create_sim(s.get(), c, default_params());
  auto reference = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(live && reference) << LastError();
  ASSERT_EQ(moldtex_sim_run_start(live.get(), 0.005, 30.0, 0.0), MOLDTEX_OK) << LastError();
  moldtex_run_progress p;
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    p = RunProgress(live.get());
  } while (p.steps < 50 && p.running);
  EXPECT_EQ(p.running, 1u);
  EXPECT_EQ(moldtex_sim_step(live.get(), 1), MOLDTEX_ERROR_BUSY);
  EXPECT_NE(LastError().find("live thread"), std::string::npos) << LastError();
  moldtex_sim_stats stats;
  moldtex_sim_stats_init(&stats);
  EXPECT_EQ(moldtex_sim_get_stats(live.get(), &stats), MOLDTEX_ERROR_BUSY);
  EXPECT_EQ(moldtex_sim_run_start(live.get(), 0.005, 30.0, 0.0), MOLDTEX_ERROR_BUSY);

  moldtex_run_progress last;
  moldtex_run_progress_init(&last);
  ASSERT_EQ(moldtex_sim_run_stop(live.get(), &last), MOLDTEX_OK) << LastError();
  EXPECT_EQ(last.running, 0u);
  EXPECT_GE(last.steps, 50u);
  EXPECT_GT(last.step_seconds, 0.0);
  EXPECT_EQ(get_stats(live.get()).step_count, last.steps);
  ASSERT_EQ(moldtex_sim_step(reference.get(), uint32_t(last.steps)), MOLDTEX_OK) << LastError();
  EXPECT_EQ(read_rgba(live.get(), 64, 64), read_rgba(reference.get(), 64, 64));
  // Stopped twice, or never started: nothing to stop.
  ASSERT_EQ(moldtex_sim_run_stop(live.get(), &last), MOLDTEX_OK) << LastError();
  EXPECT_EQ(last.steps, 0u);
}

// Should nobody come back for it, it stops by itself after limit_seconds (0.2 s; the
// limit is checked between chunks of ~0.01 s, which take longer under a sanitizer: up to
// 60 s are allowed), and the simulation answers again.
TEST(LiveRun, StopsByItselfAfterTheLimit) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s);
  auto sim = create_sim(s.get(), make_config(64, 64, 1000, 1), default_params());
  ASSERT_TRUE(sim) << LastError();
  const auto began = std::chrono::steady_clock::now();
  ASSERT_EQ(moldtex_sim_run_start(sim.get(), 0.01, 0.2, 0.0), MOLDTEX_OK) << LastError();
  moldtex_run_progress p;
  double waited = 0;
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    p = RunProgress(sim.get());
    waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  } while (p.running && waited < 60.0);
  EXPECT_EQ(p.running, 0u);
  EXPECT_GE(waited, 0.2);
  EXPECT_GT(p.steps, 0u);
  EXPECT_EQ(get_stats(sim.get()).step_count, p.steps);  // not busy any more
  // A new run starts after it (the old one collected); a release while running stops it.
  ASSERT_EQ(moldtex_sim_run_start(sim.get(), 0.01, 30.0, 0.0), MOLDTEX_OK) << LastError();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

TEST(LiveRun, RefusesNonsense) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s);
  auto sim = create_sim(s.get(), make_config(64, 64, 100, 1), default_params());
  ASSERT_TRUE(sim) << LastError();
  EXPECT_EQ(moldtex_sim_run_start(sim.get(), 0.0, 1.0, 0.0), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_run_start(sim.get(), std::nan(""), 1.0, 0.0), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_run_start(sim.get(), 0.01, 1e9, 0.0), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_run_start(sim.get(), 0.01, 1.0, -1.0), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_run_start(nullptr, 0.01, 1.0, 0.0), MOLDTEX_ERROR_INVALID_ARGUMENT);
  moldtex_run_progress p;
  moldtex_run_progress_init(&p);
  EXPECT_EQ(moldtex_sim_run_get_progress(sim.get(), &p), MOLDTEX_ERROR_INVALID_ARGUMENT);  // none started
  EXPECT_EQ(moldtex_sim_run_get_progress(sim.get(), nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_run_stop(nullptr, &p), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();  // nothing left busy
}

}  // namespace
}  // namespace mtx
