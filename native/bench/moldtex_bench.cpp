// moldtex_bench — throughput of moldtex_sim_step on the CPU backend.
//
//   moldtex_bench                                   full run
//   moldtex_bench --benchmark_min_time=0.5          quicker (seconds per case)
//   moldtex_bench --benchmark_filter=Plane          one case
//
// Cases (all cores: thread_count = 0, paper-range default parameters):
//   Plane/1024x1024/1M   flat quad (2 triangles), 1024^2 texture, 1,000,000 agents
//   Sphere/2048x2048/1M  lat-long UV sphere 64 x 32 segments, 2048^2, 1,000,000 agents
// Counters: agent_steps_per_s (agents x steps per wall second) and texel_updates_per_s
// (texels x steps per wall second: the blur/evaporation pass touches every texel).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "mesh_fixtures.h"

namespace {

struct Case {
  mtx::SurfacePtr surface;
  mtx::SimPtr sim;
  uint32_t width = 0, height = 0, agents = 0;
};

constexpr uint32_t kWarmupSteps = 10;

// Built once per case and kept across the benchmark's repeated calls, so neither
// mesh setup, spawning nor warm-up is timed.
Case* GetCase(const std::string& name, const mtx::Mesh& mesh, uint32_t w, uint32_t h,
              uint32_t agents) {
  static std::map<std::string, std::unique_ptr<Case>> cases;
  auto& c = cases[name];
  if (c) return c.get();
  c = std::make_unique<Case>();
  c->width = w;
  c->height = h;
  c->agents = agents;
  moldtex_status st;
  c->surface = mtx::create_surface(mesh, &st);
  if (!c->surface) {
    std::fprintf(stderr, "surface_create failed (%d): %s\n", int(st), moldtex_last_error());
    std::exit(1);
  }
  moldtex_sim_params p = mtx::default_params();
  p.thread_count = 0;  // all cores
  c->sim = mtx::create_sim(c->surface.get(), mtx::make_config(w, h, agents, 1), p, &st);
  if (!c->sim) {
    std::fprintf(stderr, "sim_create failed (%d): %s\n", int(st), moldtex_last_error());
    std::exit(1);
  }
  if (moldtex_sim_step(c->sim.get(), kWarmupSteps) != MOLDTEX_OK) {
    std::fprintf(stderr, "warm-up step failed: %s\n", moldtex_last_error());
    std::exit(1);
  }
  return c.get();
}

void RunSteps(benchmark::State& state, Case* c) {
  for (auto _ : state) {
    if (moldtex_sim_step(c->sim.get(), 1) != MOLDTEX_OK) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
  }
  const double it = double(state.iterations());
  state.counters["agent_steps_per_s"] =
      benchmark::Counter(double(c->agents) * it, benchmark::Counter::kIsRate);
  state.counters["texel_updates_per_s"] =
      benchmark::Counter(double(c->width) * c->height * it, benchmark::Counter::kIsRate);
  moldtex_sim_stats st;
  moldtex_sim_stats_init(&st);
  if (moldtex_sim_get_stats(c->sim.get(), &st) == MOLDTEX_OK) {
    state.counters["coverage"] = st.coverage;
    state.counters["MiB"] = double(st.bytes_in_use) / (1024.0 * 1024.0);
  }
}

void BM_Plane(benchmark::State& state) {
  RunSteps(state, GetCase("plane", mtx::make_quad(), 1024, 1024, 1000000));
}

void BM_Sphere(benchmark::State& state) {
  RunSteps(state, GetCase("sphere", mtx::make_uv_sphere(64, 32, 1.0), 2048, 2048, 1000000));
}

}  // namespace

BENCHMARK(BM_Plane)->Name("Plane/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Sphere)->Name("Sphere/2048x2048/1M")->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
