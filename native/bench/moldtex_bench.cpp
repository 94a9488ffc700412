// moldtex_bench — throughput of moldtex_sim_step on the CPU and OpenCL backends.
//
//   moldtex_bench                                   full run
//   moldtex_bench --benchmark_min_time=0.5          quicker (seconds per case)
//   moldtex_bench --benchmark_filter=Plane          one mesh, both backends
//   moldtex_bench --benchmark_filter=OpenCL         one backend, both meshes
//
// Cases (paper-range default parameters), each on both backends side by side:
//   Plane{Cpu,OpenCL}/1024x1024/1M   flat quad (2 triangles), 1024^2 texture, 1,000,000 agents
//   Sphere{Cpu,OpenCL}/2048x2048/1M  lat-long UV sphere 64 x 32 segments, 2048^2, 1,000,000 agents
//   {Plane,Sphere}Surface{Cpu,OpenCL}   the same in surface units, 2 texels per length unit
//   {Plane,Sphere}Continuous{Cpu,OpenCL}   the continuous model (layton-intrinsic-slime.md)
//                                 with the core's default agent scaled to one texel per
//                                 step at 60 Hz (Jones' geometry), turnover on (tau 0.5 s)
// Cpu: all cores (thread_count = 0). OpenCL: the first device moldtex_opencl_get_device
// lists (the label names it); skipped with the core's reason when there is none.
// Counters: agent_steps_per_s (agents x steps per wall second) and texel_updates_per_s
// (texels x steps per wall second: the blur/evaporation pass touches every texel).
// Every timed step ends with the device finished (moldtex_sim_step waits for it).
//
// Brush cases (what one interactive dab costs), on the 2048^2 sphere:
//   PaintDab/<radius in texels>   one moldtex_surface_paint dab into an RGBA image
//   RayCast                       moldtex_surface_ray_cast of rays through the sphere
//   AddAgents/1M+2000             one slime dab (2000 agents) on a 1M-agent CPU sim, undone
//   UndoAgents/erase:0|1          the undo of such a dab (0), or of an erase dab of 128 texels (1)
//
// Intrinsic Delaunay triangulation (issue 11), one core, bound = sqrt(area / a) with
// a = area / bound^2 = 16000 or 160000 (Chew's refinement gives ~0.65 a vertices: ~10k
// and ~100k):
//   IntrinsicBuild/<mesh>/<a>     moldtex_intrinsic_create (flips + refinement);
//                                 counters: vertices, insertions (incl. boundary splits)
//   IntrinsicLocate/<mesh>/<a>    moldtex_intrinsic_locate of 4096 random input points
//                                 per call (random input triangle, random weights);
//                                 counter points_per_s
// Meshes: sphere (UV sphere 64 x 32), torus (48 x 24, R 1, r 0.35), cube (8 vertices,
// 12 triangles: refinement from almost nothing, cone vertices of 270 degrees).
//   IntrinsicDomainBuild/torus100k/<size>   the simulation's intrinsic domain of a
//                                 100k-triangle torus at the bound of a size^2 texture
//   TextureDomainBuild/{sphere,torus100k}/<size>   moldtex_sim_create of MoMaS on the
//                                 texture domain (what a Reset costs the core): the UV
//                                 sphere 64 x 32 or the 100k-triangle torus, 1000 agents
//   SphereDomain/{texture,intrinsic}/1024x1024/{1M,PDE}   the continuous model on the
//                                 UV sphere on each domain (CPU); PDE: 1 agent
//   IntrinsicScaling/<segments>/<side>/<kagents>/<threads>   the continuous model on the
//                                 intrinsic domain of a UV sphere (128: Suzanne-sized)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>
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
  std::string backend_name;
  std::string error;  // why the case cannot run (then sim is null)
};

constexpr uint32_t kWarmupSteps = 10;

// The OpenCL device the OpenCL cases run on: the first one listed.
bool FirstOpenClDevice(moldtex_opencl_device_info* info, std::string* why) {
  uint32_t count = 0;
  const moldtex_status st = moldtex_opencl_device_count(&count);
  if (st != MOLDTEX_OK || count == 0) {
    *why = std::string("no OpenCL device: ") + moldtex_last_error();
    return false;
  }
  moldtex_opencl_device_info_init(info);
  if (moldtex_opencl_get_device(0, info) != MOLDTEX_OK) {
    *why = std::string("moldtex_opencl_get_device failed: ") + moldtex_last_error();
    return false;
  }
  return true;
}

// Built once per case and kept across the benchmark's repeated calls, so neither
// mesh setup, kernel compilation, spawning nor warm-up is timed.
Case* GetCase(const std::string& name, const mtx::Mesh& mesh, uint32_t w, uint32_t h,
              uint32_t agents, moldtex_backend backend, double texels_per_unit = 0,
              bool continuous = false, uint32_t integrator = MOLDTEX_INTEGRATOR_AUTO,
              uint32_t domain = MOLDTEX_DOMAIN_TEXTURE, const moldtex_sim_params* params = nullptr) {
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
  moldtex_sim_params p = params ? *params : mtx::default_params();
  if (!params) p.thread_count = 0;  // all cores
  // MOLDTEX_BENCH_THREADS=n runs the cases that use all cores on n threads instead (1
  // thread is the steadiest figure for comparing two builds on a shared machine).
  if (const char* n = std::getenv("MOLDTEX_BENCH_THREADS"); n && !params) p.thread_count = uint32_t(std::atoi(n));
  // Surface units: one length unit spans `texels_per_unit` mean texels (0 = texel units).
  if (texels_per_unit > 0)
    p.length_unit = float(texels_per_unit * std::sqrt(mesh.total_area() / (mesh.total_uv_area() * double(w) * h)));
  moldtex_sim_config config = mtx::make_config(w, h, agents, 1);
  config.backend = backend;
  if (continuous) config.model = MOLDTEX_MODEL_CONTINUOUS;
  config.domain = domain;
  if (backend == MOLDTEX_BACKEND_OPENCL) {
    moldtex_opencl_device_info device;
    if (!FirstOpenClDevice(&device, &c->error)) return c.get();
    config.opencl_platform = device.platform_index;
    config.opencl_device = device.device_index;
  }
  c->sim = mtx::create_sim(c->surface.get(), config, p, &st);
  if (!c->sim) {
    c->error = "sim_create failed (" + std::to_string(int(st)) + "): " + moldtex_last_error();
    return c.get();
  }
  if (continuous) {
    // The default agent is drawn on a lattice of 0.01 mesh units: rescale it to texels.
    const double texel = std::sqrt(mesh.total_area() / (mesh.total_uv_area() * double(w) * h));
    const double k = texel / 0.01;
    moldtex_continuous_params cp;
    moldtex_continuous_params_init(&cp);
    cp.move_rate *= float(k);
    cp.sensor_distance *= float(k);
    cp.diffusion_rate *= float(k * k);
    cp.mean_lifetime = 0.5f;
    cp.activation_time = 0.2f;
    cp.integrator = integrator;
    if (moldtex_sim_set_continuous_params(c->sim.get(), &cp) != MOLDTEX_OK) {
      c->error = std::string("set_continuous_params failed: ") + moldtex_last_error();
      c->sim.reset();
      return c.get();
    }
  }
  char buf[512] = {};
  moldtex_sim_get_backend_name(c->sim.get(), buf, sizeof(buf));
  c->backend_name = buf;
  if (moldtex_sim_step(c->sim.get(), kWarmupSteps) != MOLDTEX_OK) {
    c->error = std::string("warm-up step failed: ") + moldtex_last_error();
    c->sim.reset();
  }
  return c.get();
}

void RunSteps(benchmark::State& state, Case* c) {
  if (!c->sim) {
    state.SkipWithError(c->error.c_str());
    for (auto _ : state) {
    }
    return;
  }
  state.SetLabel(c->backend_name);
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

void BM_Plane(benchmark::State& state, moldtex_backend backend, const char* key) {
  RunSteps(state, GetCase(key, mtx::make_quad(), 1024, 1024, 1000000, backend));
}

void BM_Sphere(benchmark::State& state, moldtex_backend backend, const char* key) {
  RunSteps(state, GetCase(key, mtx::make_uv_sphere(64, 32, 1.0), 2048, 2048, 1000000, backend));
}

// The same two cases in surface units at 2 texels per length unit (the add-on's default
// pattern scale at 1024^2): footprint deposits and sensing, seam table, metric diffusion.
void BM_PlaneSurface(benchmark::State& state, moldtex_backend backend, const char* key) {
  RunSteps(state, GetCase(key, mtx::make_quad(), 1024, 1024, 1000000, backend, 2.0));
}

// The plane's surface-units case at a time step of 1/240 s: agents sense and turn on
// every 4th step (MoMaS' 60 Hz tick) and only move on the others.
void BM_PlaneSurfaceShortStep(benchmark::State& state) {
  moldtex_sim_params p = mtx::default_params();
  p.thread_count = 0;  // all cores
  p.time_step = 1.f / 240.f;
  RunSteps(state, GetCase("plane-surface-short-step", mtx::make_quad(), 1024, 1024, 1000000, MOLDTEX_BACKEND_CPU,
                          2.0, false, MOLDTEX_INTEGRATOR_AUTO, MOLDTEX_DOMAIN_TEXTURE, &p));
}

// The plane's surface-units case at twice the resolution with the same length unit (4
// texels per unit), as when an artist raises the texture size: footprints of 4-5 texels
// a side instead of 2-3.
void BM_PlaneSurfaceSharp(benchmark::State& state) {
  RunSteps(state, GetCase("plane-surface-sharp", mtx::make_quad(), 2048, 2048, 1000000, MOLDTEX_BACKEND_CPU, 4.0));
}

void BM_SphereSurface(benchmark::State& state, moldtex_backend backend, const char* key) {
  RunSteps(state, GetCase(key, mtx::make_uv_sphere(64, 32, 1.0), 2048, 2048, 1000000, backend, 2.0));
}

// The classic flat model's geometry (Jones 2010, as the public flat implementations run
// it): sensors 45 degrees apart at 9 texels, a step of 1 texel with one deposit (one
// substep), turns of up to 45 degrees; 1024^2, 1M agents, all cores. The figure to set
// beside flat peers.
moldtex_sim_params JonesParams(unsigned threads) {
  moldtex_sim_params p = mtx::default_params();
  p.thread_count = threads;
  p.vision_angle = 45.0f;
  p.vision_distance = 0.9f;  // in units of 10 texels (MTX_VISION_UNIT_TEXELS)
  p.movement_speed = 1.0f;
  p.substeps = 1;
  p.turn_speed = 0.25f / p.time_step;  // max turn = turn_speed * pi * dt = pi / 4
  return p;
}

void BM_PlaneJones(benchmark::State& state) {
  const moldtex_sim_params p = JonesParams(0);
  RunSteps(state, GetCase("plane-jones", mtx::make_quad(), 1024, 1024, 1000000, MOLDTEX_BACKEND_CPU, 0.0, false,
                          MOLDTEX_INTEGRATOR_AUTO, MOLDTEX_DOMAIN_TEXTURE, &p));
}

// Issue 15's surface case (b) in the same geometry as the flat figure above: the UV
// sphere 64 x 32 at 2048^2, 1M agents, all cores, Jones' sensors, step and turn. Its ratio
// to PlaneJonesCpu is what the surface costs, the model held the same.
void BM_SphereJones(benchmark::State& state) {
  const moldtex_sim_params p = JonesParams(0);
  RunSteps(state, GetCase("sphere-jones", mtx::make_uv_sphere(64, 32, 1.0), 2048, 2048, 1000000, MOLDTEX_BACKEND_CPU,
                          0.0, false, MOLDTEX_INTEGRATOR_AUTO, MOLDTEX_DOMAIN_TEXTURE, &p));
}

// Scaling (issue 15): mesh (0 plane, 1 UV sphere 64 x 32), texture side, thousands of
// agents, threads; the default MoMaS parameters (texel units) as PlaneCpu / SphereCpu.
void BM_Scaling(benchmark::State& state) {
  const bool sphere = state.range(0) == 1;
  const uint32_t side = uint32_t(state.range(1)), agents = uint32_t(state.range(2)) * 1000u;
  moldtex_sim_params p = mtx::default_params();
  p.thread_count = uint32_t(state.range(3));
  const std::string key = "scaling-" + std::to_string(state.range(0)) + "-" + std::to_string(side) + "-" +
                          std::to_string(agents) + "-" + std::to_string(p.thread_count);
  RunSteps(state, GetCase(key, sphere ? mtx::make_uv_sphere(64, 32, 1.0) : mtx::make_quad(), side, side, agents,
                          MOLDTEX_BACKEND_CPU, 0.0, false, MOLDTEX_INTEGRATOR_AUTO, MOLDTEX_DOMAIN_TEXTURE, &p));
}

// A finely tessellated mesh: the UV sphere 128 x 64 (16,128 triangles, as many as Suzanne
// with Subdivision 2), 1024^2, 300k agents, all cores: sensors and moves cross edges.
void BM_FineMesh(benchmark::State& state) {
  RunSteps(state, GetCase("fine-mesh", mtx::make_uv_sphere(128, 64, 1.0), 1024, 1024, 300000, MOLDTEX_BACKEND_CPU));
}

// ---- brushes ----

mtx::SurfacePtr& SphereSurface() {
  static mtx::SurfacePtr surface;
  if (!surface) {
    moldtex_status st;
    surface = mtx::create_surface(mtx::make_uv_sphere(64, 32, 1.0), &st);
    if (!surface) std::exit(1);
  }
  return surface;
}

// Radius in texels -> mesh units on the 2048^2 lat-long sphere: the equator's 2048
// texels span 2 pi, so a texel is ~pi/1024 wide there.
void BM_PlaneContinuous(benchmark::State& state, moldtex_backend backend, const char* key) {
  RunSteps(state, GetCase(key, mtx::make_quad(), 1024, 1024, 1000000, backend, 0.0, true));
}

void BM_SphereContinuous(benchmark::State& state, moldtex_backend backend, const char* key) {
  RunSteps(state, GetCase(key, mtx::make_uv_sphere(64, 32, 1.0), 2048, 2048, 1000000, backend, 0.0, true));
}

// The intrinsic domain (issue 11) beside the texture domain, CPU: the continuous model on
// the UV sphere at 1024^2 (the triangulation's bound from the texture: ~1 vertex per
// texel), 1M agents; and with 1 agent, which leaves the PDE's cost per step (its
// steps_per_s; agent_steps_per_s is then meaningless).
void BM_SphereDomain(benchmark::State& state, uint32_t domain, uint32_t agents, const char* key) {
  RunSteps(state, GetCase(key, mtx::make_uv_sphere(64, 32, 1.0), 1024, 1024, agents, MOLDTEX_BACKEND_CPU, 0.0, true,
                          MOLDTEX_INTEGRATOR_AUTO, domain));
  state.counters["steps_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

// The intrinsic domain where issue 11 sets its target (2 M agent-steps/s per core, PDE
// included, on Suzanne-sized meshes): the continuous model on a UV sphere of `segments` x
// segments / 2 (128: 16,128 triangles, as many as Suzanne with Subdivision 2), the bound
// from a side^2 texture, thousands of agents, threads (1 gives the per-core figure).
void BM_IntrinsicScaling(benchmark::State& state) {
  const uint32_t segments = uint32_t(state.range(0)), side = uint32_t(state.range(1));
  const uint32_t agents = uint32_t(state.range(2)) * 1000u;
  moldtex_sim_params p = mtx::default_params();
  p.thread_count = uint32_t(state.range(3));
  const std::string key = "intrinsic-scaling-" + std::to_string(segments) + "-" + std::to_string(side) + "-" +
                          std::to_string(agents) + "-" + std::to_string(p.thread_count);
  RunSteps(state, GetCase(key, mtx::make_uv_sphere(segments, segments / 2, 1.0), side, side, agents,
                          MOLDTEX_BACKEND_CPU, 0.0, true, MOLDTEX_INTEGRATOR_AUTO, MOLDTEX_DOMAIN_INTRINSIC, &p));
}

// Building the intrinsic domain of a 100k-triangle torus (256 x 196 segments) at the bound
// that matches a 1024^2 or 2048^2 texture: moldtex_sim_create with the Intrinsic domain
// (texture layout, triangulation, operators, texel map), once (later ones would come
// from the cache). Counters: the domain's own build time and size.
void BM_IntrinsicDomainBuild(benchmark::State& state) {
  const uint32_t size = uint32_t(state.range(0));
  static const mtx::Mesh torus = mtx::make_torus(256, 196, 1.0, 0.35);
  moldtex_status st;
  mtx::SurfacePtr surface = mtx::create_surface(torus, &st);
  moldtex_domain_info info;
  moldtex_domain_info_init(&info);
  for (auto _ : state) {
    moldtex_sim_config config = mtx::make_config(size, size, 1000, 1);
    config.model = MOLDTEX_MODEL_CONTINUOUS;
    config.domain = MOLDTEX_DOMAIN_INTRINSIC;
    mtx::SimPtr sim = mtx::create_sim(surface.get(), config, mtx::default_params(), &st);
    if (!sim) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
    moldtex_sim_get_domain_info(sim.get(), &info);
  }
  state.counters["triangles"] = double(torus.triangle_count());
  state.counters["vertices"] = double(info.cell_count);
  state.counters["domain_build_s"] = info.build_seconds;
}

// Creating a MoMaS simulation on the texture domain at size^2 (its classes, gutter, seam
// correspondence and reach tables; 1000 agents): what a Reset costs the core.
void BM_TextureDomainBuild(benchmark::State& state, bool torus) {
  const uint32_t size = uint32_t(state.range(0));
  static const mtx::Mesh sphere_mesh = mtx::make_uv_sphere(64, 32, 1.0);
  static const mtx::Mesh torus_mesh = mtx::make_torus(256, 196, 1.0, 0.35);
  moldtex_status st;
  mtx::SurfacePtr surface = mtx::create_surface(torus ? torus_mesh : sphere_mesh, &st);
  for (auto _ : state) {
    mtx::SimPtr sim = mtx::create_sim(surface.get(), mtx::make_config(size, size, 1000, 1), mtx::default_params(), &st);
    if (!sim) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
  }
}

// The add-on's defaults (512^2, 60k agents) on the UV sphere, whose pole fans make the
// PDE stiff: AUTO (backward Euler here) against forward Euler with its sub-steps.
void BM_SphereContinuousSmall(benchmark::State& state, uint32_t integrator, const char* key) {
  RunSteps(state, GetCase(key, mtx::make_uv_sphere(64, 32, 1.0), 512, 512, 60000, MOLDTEX_BACKEND_CPU, 0.0,
                          true, integrator));
}

void BM_PaintDab(benchmark::State& state) {
  const uint32_t size = 2048;
  static std::vector<float> image(size_t(size) * size * 4, 0.f);
  moldtex_brush brush;
  moldtex_brush_init(&brush);
  brush.center = {2000, {0.3f, 0.3f, 0.4f}};  // a triangle on the equator
  brush.radius = float(state.range(0)) * 3.14159265f / 1024.f;
  brush.falloff = 0.5f;
  uint32_t changed = 0;
  for (auto _ : state) {
    brush.mode = brush.mode == MOLDTEX_BRUSH_PAINT ? MOLDTEX_BRUSH_ERASE : MOLDTEX_BRUSH_PAINT;
    if (moldtex_surface_paint(SphereSurface().get(), size, size, image.data(), image.size(), &brush,
                              &changed) != MOLDTEX_OK) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
  }
  state.counters["texels_changed"] = changed;
}

void BM_RayCast(benchmark::State& state) {
  moldtex_ray_hit hit;
  moldtex_ray_hit_init(&hit);
  int64_t i = 0, hits = 0;
  for (auto _ : state) {
    const float a = float(i++ % 997) * 0.0063f;
    const float origin[3] = {3.f * std::cos(a), 3.f * std::sin(a), 0.5f};
    const float direction[3] = {-origin[0], -origin[1], -0.5f};
    moldtex_surface_ray_cast(SphereSurface().get(), origin, direction, 1e30f, &hit);
    hits += hit.hit;
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(state.iterations()),
                                                    benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = double(hits) / double(std::max<int64_t>(1, state.iterations()));
}

// The slime brushes' case: 1 M agents on the UV sphere at 2048^2 (CPU), and a brush on
// a triangle of its equator; null (the benchmark skipped) if the simulation failed.
Case* BrushCase(benchmark::State& state, moldtex_brush* brush) {
  Case* c = GetCase("sphere-cpu", mtx::make_uv_sphere(64, 32, 1.0), 2048, 2048, 1000000,
                    MOLDTEX_BACKEND_CPU);
  if (!c->sim) {
    state.SkipWithError(c->error.c_str());
    for (auto _ : state) {
    }
    return nullptr;
  }
  moldtex_brush_init(brush);
  brush->center = {2000, {0.3f, 0.3f, 0.4f}};
  return c;
}

void BM_AddAgents(benchmark::State& state) {
  moldtex_brush brush;
  Case* c = BrushCase(state, &brush);
  if (!c) return;
  brush.radius = 0.1f;
  for (auto _ : state) {
    if (moldtex_sim_add_agents(c->sim.get(), &brush, 2000, 1) != MOLDTEX_OK) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
    state.PauseTiming();
    moldtex_sim_undo_agents(c->sim.get(), 1);
    state.ResumeTiming();
  }
}

// An erase dab of radius range(0) texels (2048^2 on the sphere's equator) over a 1 M-agent
// simulation, then (not timed) its undo and 16 steps, so the agents stand regrouped by
// tile again as in a running simulation (the undo puts them back at the end of the
// arrays). The dab finds each agent's geodesic distance to the centre
// (brush/geodesic_disk.h, DiskDistance) for its soft edge.
void BM_EraseAgents(benchmark::State& state) {
  moldtex_brush brush;
  Case* c = BrushCase(state, &brush);
  if (!c) return;
  brush.radius = float(state.range(0)) * 3.14159265f / 1024.f;
  brush.falloff = 0.5f;
  brush.strength = 0.5f;
  uint32_t removed = 0;
  for (auto _ : state) {
    if (moldtex_sim_erase_agents(c->sim.get(), &brush, 1, &removed) != MOLDTEX_OK) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
    state.PauseTiming();
    moldtex_sim_undo_agents(c->sim.get(), 1);
    moldtex_sim_step(c->sim.get(), 16);
    state.ResumeTiming();
  }
  state.counters["removed"] = removed;
}

// The undo of one stroke (not timed: the stroke itself, a 2000-agent add dab or a
// 128-texel erase dab at strength 0.5): the stroke's agents leave and the ones it erased
// come back.
void BM_UndoAgents(benchmark::State& state) {
  moldtex_brush brush;
  Case* c = BrushCase(state, &brush);
  if (!c) return;
  const bool erase = state.range(0) == 1;
  brush.radius = erase ? 128 * 3.14159265f / 1024.f : 0.1f;
  brush.strength = 0.5f;
  uint32_t removed = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const moldtex_status status = erase ? moldtex_sim_erase_agents(c->sim.get(), &brush, 1, &removed)
                                        : moldtex_sim_add_agents(c->sim.get(), &brush, 2000, 1);
    if (status != MOLDTEX_OK) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
    state.ResumeTiming();
    moldtex_sim_undo_agents(c->sim.get(), 1);
  }
}

mtx::Mesh IntrinsicMesh(int which) {
  switch (which) {
    case 0: return mtx::make_uv_sphere(64, 32, 1.0);
    case 1: return mtx::make_torus(48, 24, 1.0, 0.35);
    default: return mtx::make_cube();
  }
}

struct IntrinsicCase {
  mtx::Mesh mesh;
  mtx::SurfacePtr surface;
  moldtex_intrinsic_params params;
};

IntrinsicCase MakeIntrinsicCase(int which, double target) {
  IntrinsicCase c;
  c.mesh = IntrinsicMesh(which);
  moldtex_status st;
  c.surface = mtx::create_surface(c.mesh, &st);
  if (!c.surface) std::exit(1);
  moldtex_intrinsic_params_init(&c.params);
  c.params.max_circumradius = float(std::sqrt(c.mesh.total_area() / target));
  return c;
}

void BM_IntrinsicBuild(benchmark::State& state) {
  IntrinsicCase c = MakeIntrinsicCase(int(state.range(0)), double(state.range(1)));
  moldtex_intrinsic_info info;
  moldtex_intrinsic_info_init(&info);
  for (auto _ : state) {
    moldtex_intrinsic h = nullptr;
    if (moldtex_intrinsic_create(c.surface.get(), &c.params, &h) != MOLDTEX_OK) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
    state.PauseTiming();
    moldtex_intrinsic_get_info(h, &info);
    moldtex_intrinsic_release(h);
    state.ResumeTiming();
  }
  state.counters["vertices"] = info.vertex_count;
  state.counters["insertions"] = double(info.insertions + info.boundary_splits);
  state.counters["over_bound"] = info.faces_over_bound_sharp + info.faces_over_bound_other;
}

void BM_IntrinsicLocate(benchmark::State& state) {
  IntrinsicCase c = MakeIntrinsicCase(int(state.range(0)), double(state.range(1)));
  moldtex_intrinsic h = nullptr;
  if (moldtex_intrinsic_create(c.surface.get(), &c.params, &h) != MOLDTEX_OK) {
    state.SkipWithError(moldtex_last_error());
    for (auto _ : state) {
    }
    return;
  }
  std::vector<moldtex_surface_point> in(4096), out(4096);
  uint32_t seed = 12345;
  auto rnd = [&] { return (seed = seed * 1664525u + 1013904223u) >> 8; };
  for (auto& p : in) {
    p.triangle = rnd() % c.mesh.triangle_count();
    float a = float(rnd() % 10000) / 10000.f, b = float(rnd() % 10000) / 10000.f;
    if (a + b > 1) a = 1 - a, b = 1 - b;
    p.bary[0] = 1 - a - b;
    p.bary[1] = a;
    p.bary[2] = b;
  }
  for (auto _ : state) {
    if (moldtex_intrinsic_locate(h, in.data(), uint32_t(in.size()), out.data()) != MOLDTEX_OK) {
      state.SkipWithError(moldtex_last_error());
      break;
    }
  }
  state.counters["points_per_s"] =
      benchmark::Counter(double(state.iterations()) * double(in.size()), benchmark::Counter::kIsRate);
  moldtex_intrinsic_release(h);
}

}  // namespace

BENCHMARK(BM_IntrinsicBuild)->Name("IntrinsicBuild")->ArgNames({"mesh", "area_per_bound2"})
    ->ArgsProduct({{0, 1, 2}, {16000, 160000}})->Iterations(1)->Repetitions(2)->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IntrinsicLocate)->Name("IntrinsicLocate")->ArgNames({"mesh", "area_per_bound2"})
    ->ArgsProduct({{0, 1, 2}, {16000, 160000}})->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK(BM_PaintDab)->Name("PaintDab")->Arg(8)->Arg(32)->Arg(128)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RayCast)->Name("RayCast")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EraseAgents)->Name("EraseAgents/1M")->Arg(32)->Arg(128)->Arg(512)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AddAgents)->Name("AddAgents/1M+2000")->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UndoAgents)->Name("UndoAgents")->ArgName("erase")->Arg(0)->Arg(1)->UseRealTime()
    ->Unit(benchmark::kMillisecond);

BENCHMARK(BM_PlaneJones)->Name("PlaneJonesCpu/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SphereJones)->Name("SphereJonesCpu/2048x2048/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Scaling)->Name("Scaling")->ArgNames({"sphere", "side", "kagents", "threads"})
    ->Args({0, 1024, 1000, 1})->Args({0, 1024, 1000, 2})
    ->Args({0, 1024, 256, 2})->Args({0, 1024, 4000, 2})
    ->Args({0, 2048, 1000, 2})->Args({0, 4096, 1000, 2})
    ->Args({1, 2048, 1000, 1})->Args({1, 2048, 1000, 2})
    ->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FineMesh)->Name("FineSphereCpu/128x64/1024x1024/300k")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plane, cpu, MOLDTEX_BACKEND_CPU, "plane-cpu")
    ->Name("PlaneCpu/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plane, opencl, MOLDTEX_BACKEND_OPENCL, "plane-opencl")
    ->Name("PlaneOpenCL/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sphere, cpu, MOLDTEX_BACKEND_CPU, "sphere-cpu")
    ->Name("SphereCpu/2048x2048/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sphere, opencl, MOLDTEX_BACKEND_OPENCL, "sphere-opencl")
    ->Name("SphereOpenCL/2048x2048/1M")->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(BM_PlaneSurface, cpu, MOLDTEX_BACKEND_CPU, "plane-surface-cpu")
    ->Name("PlaneSurfaceCpu/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PlaneSurface, opencl, MOLDTEX_BACKEND_OPENCL, "plane-surface-opencl")
    ->Name("PlaneSurfaceOpenCL/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlaneSurfaceShortStep)->Name("PlaneSurfaceCpu/1024x1024/1M/dt240")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlaneSurfaceSharp)->Name("PlaneSurfaceCpu/2048x2048/1M/sharp")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereSurface, cpu, MOLDTEX_BACKEND_CPU, "sphere-surface-cpu")
    ->Name("SphereSurfaceCpu/2048x2048/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereSurface, opencl, MOLDTEX_BACKEND_OPENCL, "sphere-surface-opencl")
    ->Name("SphereSurfaceOpenCL/2048x2048/1M")->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(BM_PlaneContinuous, cpu, MOLDTEX_BACKEND_CPU, "plane-continuous-cpu")
    ->Name("PlaneContinuousCpu/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PlaneContinuous, opencl, MOLDTEX_BACKEND_OPENCL, "plane-continuous-opencl")
    ->Name("PlaneContinuousOpenCL/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereContinuous, cpu, MOLDTEX_BACKEND_CPU, "sphere-continuous-cpu")
    ->Name("SphereContinuousCpu/2048x2048/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereContinuous, opencl, MOLDTEX_BACKEND_OPENCL, "sphere-continuous-opencl")
    ->Name("SphereContinuousOpenCL/2048x2048/1M")->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(BM_SphereContinuousSmall, auto, MOLDTEX_INTEGRATOR_AUTO, "sphere-small-auto")
    ->Name("SphereContinuousCpu/512x512/60k/auto")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereContinuousSmall, forward, MOLDTEX_INTEGRATOR_FORWARD, "sphere-small-forward")
    ->Name("SphereContinuousCpu/512x512/60k/forward")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereContinuousSmall, backward, MOLDTEX_INTEGRATOR_BACKWARD, "sphere-small-backward")
    ->Name("SphereContinuousCpu/512x512/60k/backward")->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(BM_SphereDomain, texture, MOLDTEX_DOMAIN_TEXTURE, 1000000, "sphere-domain-texture")
    ->Name("SphereDomain/texture/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereDomain, intrinsic, MOLDTEX_DOMAIN_INTRINSIC, 1000000, "sphere-domain-intrinsic")
    ->Name("SphereDomain/intrinsic/1024x1024/1M")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereDomain, texture_pde, MOLDTEX_DOMAIN_TEXTURE, 1, "sphere-domain-texture-pde")
    ->Name("SphereDomain/texture/1024x1024/PDE")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SphereDomain, intrinsic_pde, MOLDTEX_DOMAIN_INTRINSIC, 1, "sphere-domain-intrinsic-pde")
    ->Name("SphereDomain/intrinsic/1024x1024/PDE")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IntrinsicScaling)->Name("IntrinsicScaling")->ArgNames({"segments", "side", "kagents", "threads"})
    ->Args({128, 512, 300, 1})->Args({128, 512, 300, 2})->Args({128, 1024, 300, 1})->Args({128, 1024, 300, 2})
    ->Args({64, 1024, 1000, 1})->Args({64, 1024, 1000, 2})
    ->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IntrinsicDomainBuild)->Name("IntrinsicDomainBuild/torus100k")->Arg(1024)->Arg(2048)
    ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);

BENCHMARK_CAPTURE(BM_TextureDomainBuild, sphere, false)->Name("TextureDomainBuild/sphere")->Arg(1024)->Arg(4096)
    ->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TextureDomainBuild, torus, true)->Name("TextureDomainBuild/torus100k")->Arg(2048)
    ->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
