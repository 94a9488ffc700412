// The C boundary: validates handles and pointers, converts every C++ exception into a
// status code and a per-thread message, and never lets one escape into the host.
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>
#include <algorithm>
#include <array>
#include <chrono>

#include <cstddef>
#include <cstdio>

#include "common/error.h"
#ifdef MOLDTEX_HAVE_OPENCL
#include "backends/opencl/devices.h"
#endif
#include "moldtex.h"
#include "bake/bake.h"
#include "domain_build.h"
#include "bake/live_run.h"
#include "brush/brush.h"
#include "domain/corner_raster.h"
#include "agents/parameter_maps.h"
#include "models/model.h"
#include "sim.h"
#include "spatial/spatial.h"
#include "surface/surface.h"
#include "intrinsic/correspondence.h"
#include "intrinsic/delaunay_flip.h"
#include "intrinsic/refinement.h"

struct moldtex_surface_t {
  std::shared_ptr<const moldtex::Surface> surface;
  // Embree BVH for ray casts and closest points, built on the first query.
  std::unique_ptr<moldtex::SpatialIndex> spatial;
};
struct moldtex_context_t {
  std::shared_ptr<moldtex::IntrinsicDomainCache> intrinsic_cache;
};
struct moldtex_sim_t {
  std::shared_ptr<moldtex::Simulation> sim;  // shared with a running bake
  std::unique_ptr<moldtex::LiveRun> run;     // moldtex_sim_run_*: stopped before release
};
struct moldtex_bake_t {
  std::unique_ptr<moldtex::Bake> bake;
};
struct moldtex_domain_build_t {
  std::unique_ptr<moldtex::DomainBuild> build;
};

namespace {

// A context's intrinsic domain cache, or the default context's for NULL.
const std::shared_ptr<moldtex::IntrinsicDomainCache>& cache_of(moldtex_context context) {
  return context ? context->intrinsic_cache : moldtex::default_intrinsic_cache();
}

}  // namespace

namespace {

thread_local std::string g_last_error;

moldtex_status set_error(moldtex_status status, const std::string& message) {
  g_last_error = message;
  return status;
}

// Runs body, mapping exceptions to statuses (common/error.h's run_job); the message of a
// failure, or none on success, is this thread's last error.
template <class Body>
moldtex_status guarded(Body&& body) {
  moldtex::JobOutcome outcome = moldtex::run_job(
      body, "Out of memory: lower the texture resolution or the number of agents", "Internal error: ");
  g_last_error = std::move(outcome.message);
  return outcome.status;
}

void require(bool ok, const char* message) {
  if (!ok) moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, message);
}

// The simulation behind a handle, refused while a bake owns it.
moldtex::Simulation& use(moldtex_sim sim) {
  require(sim != nullptr, "The simulation handle is NULL");
  if (sim->sim->busy)
    moldtex::fail(MOLDTEX_ERROR_BUSY,
                  "A bake is running on this simulation: wait for it to finish or cancel it");
  if (sim->run && sim->run->running())
    moldtex::fail(MOLDTEX_ERROR_BUSY,
                  "The simulation is stepping on its live thread: stop it first (moldtex_sim_run_stop)");
  return *sim->sim;
}

void require_path(const char* path) {
  require(path != nullptr && *path != '\0', "The file path is empty");
}

void require_point(const moldtex::Surface& s, const moldtex_surface_point* p) {
  require(p != nullptr, "The surface point is NULL");
  require(p->triangle < s.triangle_count(), "The surface point's triangle index is out of range");
  float sum = 0;
  for (float b : p->bary) {
    require(std::isfinite(b) && b >= -1e-4f, "Barycentric weights must be finite and non-negative");
    sum += b;
  }
  require(std::fabs(sum - 1.f) < 1e-3f, "Barycentric weights must sum to 1");
}

// Reads a caller's struct of struct_size bytes: fields an older caller does not know
// keep the defaults of `init`; a size below the first release's is refused.
template <class T>
T read_struct(const T* in, const char* name, void (*init)(T*) = nullptr,
              size_t first_release_size = sizeof(T)) {
  if (in == nullptr) moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, std::string(name) + " is NULL");
  if (in->struct_size < first_release_size)
    moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                  std::string(name) + ".struct_size is too small: initialise it with its _init function");
  T out{};
  if (init) init(&out);
  std::memcpy(&out, in, std::min<size_t>(in->struct_size, sizeof(T)));
  out.struct_size = sizeof(T);
  return out;
}

// moldtex_sim_config as first released, before the backend fields.
constexpr size_t kSimConfigV1Size = offsetof(moldtex_sim_config, backend);
// The second release ended with opencl_device; its sizeof (40) includes 4 bytes of tail
// padding where species_count now lies, so a caller that says 40 knows nothing after
// opencl_device.
constexpr size_t kSimConfigV2Fields = offsetof(moldtex_sim_config, species_count);
constexpr size_t kSimConfigV2Size = (kSimConfigV2Fields + 7) / 8 * 8;
static_assert(kSimConfigV2Size == 40, "moldtex_sim_config's second release was 40 bytes");

moldtex_sim_config read_config(const moldtex_sim_config* in) {
  moldtex_sim_config c =
      read_struct(in, "moldtex_sim_config", moldtex_sim_config_init, kSimConfigV1Size);
  // The release before the intrinsic domain ended with model; its sizeof includes 4
  // bytes of tail padding where domain now lies.
  constexpr size_t kV3Fields = offsetof(moldtex_sim_config, domain);
  if (in->struct_size <= (kV3Fields + 7) / 8 * 8 && in->struct_size > kSimConfigV2Size) {
    c.domain = MOLDTEX_DOMAIN_TEXTURE;
    c.intrinsic_bound = 0.f;
  }
  if (in->struct_size <= kSimConfigV2Size) {
    moldtex_sim_config defaults;
    moldtex_sim_config_init(&defaults);
    std::memcpy(reinterpret_cast<char*>(&c) + kSimConfigV2Fields,
                reinterpret_cast<const char*>(&defaults) + kSimConfigV2Fields,
                sizeof(c) - kSimConfigV2Fields);
  }
  return c;
}

// moldtex_sim_params before food with hunger (hunger_rate, food_radius): such callers
// get the defaults, i.e. food off (and, like callers that end at food_radius, the
// single-texel sensor).
constexpr size_t kSimParamsV1Size = offsetof(moldtex_sim_params, hunger_rate);

moldtex_sim_params read_params(const moldtex_sim_params* in) {
  return read_struct(in, "moldtex_sim_params", moldtex_sim_params_init, kSimParamsV1Size);
}

}  // namespace

extern "C" {

uint32_t moldtex_abi_version(void) { return MOLDTEX_ABI_VERSION; }
const char* moldtex_version_string(void) { return MOLDTEX_VERSION_STRING; }
const char* moldtex_last_error(void) { return g_last_error.c_str(); }

void moldtex_mesh_desc_init(moldtex_mesh_desc* d) {
  if (!d) return;
  std::memset(d, 0, sizeof(*d));
  d->struct_size = sizeof(*d);
}

moldtex_status moldtex_surface_create(const moldtex_mesh_desc* desc, moldtex_surface* out) {
  return guarded([&] {
    require(out != nullptr, "out_surface is NULL");
    *out = nullptr;
    moldtex_mesh_desc d = read_struct(desc, "moldtex_mesh_desc");
    auto surface = std::make_shared<const moldtex::Surface>(moldtex::build_surface(d));
    auto spatial = std::make_unique<moldtex::SpatialIndex>(surface);
    *out = new moldtex_surface_t{std::move(surface), std::move(spatial)};
  });
}

void moldtex_surface_release(moldtex_surface surface) { delete surface; }

void moldtex_surface_info_init(moldtex_surface_info* info) {
  if (!info) return;
  std::memset(info, 0, sizeof(*info));
  info->struct_size = sizeof(*info);
}

moldtex_status moldtex_surface_get_info(moldtex_surface surface, moldtex_surface_info* info) {
  return guarded([&] {
    require(surface != nullptr, "The surface handle is NULL");
    // The first release ended with uv_area.
    moldtex_surface_info out = read_struct(info, "moldtex_surface_info", moldtex_surface_info_init,
                                           offsetof(moldtex_surface_info, generated_uvs));
    const uint32_t caller_size = info->struct_size;
    const moldtex::Surface& s = *surface->surface;
    out.vertex_count = s.vertex_count();
    out.triangle_count = s.triangle_count();
    out.boundary_edge_count = s.boundary_edges;
    out.seam_edge_count = s.seam_edges;
    out.degenerate_triangle_count = s.degenerate_count;
    out.area = s.area;
    out.uv_area = s.uv_area;
    out.generated_uvs = s.generated_uvs ? 1u : 0u;
    out.struct_size = std::min<uint32_t>(caller_size, sizeof(out));
    std::memcpy(info, &out, out.struct_size);
  });
}

moldtex_status moldtex_surface_get_metric(moldtex_surface surface, uint32_t triangle, float g[4]) {
  return guarded([&] {
    require(surface != nullptr && g != nullptr, "NULL argument");
    require(triangle < surface->surface->triangle_count(), "Triangle index out of range");
    auto m = surface->surface->metric(triangle);
    for (int i = 0; i < 4; ++i) g[i] = static_cast<float>(m[i]);
  });
}

moldtex_status moldtex_surface_evaluate(moldtex_surface surface, const moldtex_surface_point* point,
                                        float position[3], float uv[2]) {
  return guarded([&] {
    require(surface != nullptr, "The surface handle is NULL");
    require_point(*surface->surface, point);
    surface->surface->evaluate(point->triangle, point->bary, position, uv);
  });
}

moldtex_status moldtex_surface_trace(moldtex_surface surface, const moldtex_surface_point* start,
                                     const float direction[3], float length,
                                     moldtex_surface_point* end, float* path_xyz,
                                     uint32_t path_capacity, uint32_t* path_count) {
  return guarded([&] {
    require(surface != nullptr && direction != nullptr && end != nullptr, "NULL argument");
    const moldtex::Surface& s = *surface->surface;
    require_point(s, start);
    require(std::isfinite(length) && length >= 0.f, "The length must be a finite number >= 0");
    for (int k = 0; k < 3; ++k) require(std::isfinite(direction[k]), "The direction must be finite");
    require(!s.degenerate[start->triangle], "The start triangle has zero area");
    // Project the 3D direction onto the start triangle's local frame.
    const uint32_t t = start->triangle;
    const float* p0 = &s.positions[3 * s.triangles[3 * t]];
    const float* p1 = &s.positions[3 * s.triangles[3 * t + 1]];
    const float* p2 = &s.positions[3 * s.triangles[3 * t + 2]];
    const moldtex::TriangleFrame& f = s.frames[t];
    double ex[3], ey[3];
    for (int k = 0; k < 3; ++k) ex[k] = (p1[k] - p0[k]) / f.a;
    for (int k = 0; k < 3; ++k) ey[k] = (p2[k] - p0[k] - f.bx * ex[k]) / f.by;
    double dx = 0, dy = 0;
    for (int k = 0; k < 3; ++k) {
      dx += direction[k] * ex[k];
      dy += direction[k] * ey[k];
    }
    double n = std::sqrt(dx * dx + dy * dy);
    require(n > 1e-12, "The direction is perpendicular to the surface at the start point");
    moldtex::Walker w{t, {start->bary[0], start->bary[1], start->bary[2]},
                      {static_cast<float>(dx / n), static_cast<float>(dy / n)}};
    moldtex::mtx_clamp_bary(w.bary);
    // Path: the start, every crossing or bounce, the end.
    std::vector<moldtex::Walker> events(path_xyz ? path_capacity : 0);
    const moldtex::Walker start_walker = w;
    const int crossings = moldtex::mtx_walk(s.frames.data(), s.adjacency.data(), &w, length,
                                            events.data(), static_cast<int>(events.size()));
    const uint32_t count = static_cast<uint32_t>(crossings) + 2;
    if (path_xyz) {
      for (uint32_t i = 0; i < std::min(count, path_capacity); ++i) {
        const moldtex::Walker& at = i == 0 ? start_walker : (i + 1 == count ? w : events[i - 1]);
        s.evaluate(at.triangle, at.bary, path_xyz + 3 * i, nullptr);
      }
    }
    end->triangle = w.triangle;
    std::copy(w.bary, w.bary + 3, end->bary);
    if (path_count) *path_count = count;
  });
}

moldtex_status moldtex_surface_rasterize_corners(moldtex_surface surface, uint32_t width,
                                                 uint32_t height, const float* corner_rgba,
                                                 size_t corner_float_count, float* rgba,
                                                 size_t float_count) {
  return guarded([&] {
    require(surface != nullptr, "The surface handle is NULL");
    moldtex::rasterize_corners(*surface->surface, width, height, corner_rgba,
                               corner_float_count, rgba, float_count);
  });
}

void moldtex_sim_config_init(moldtex_sim_config* c) {
  if (!c) return;
  std::memset(c, 0, sizeof(*c));
  c->struct_size = sizeof(*c);
  c->width = 1024;
  c->height = 1024;
  c->agent_count = 200000;
  c->seed = 1;
  c->backend = MOLDTEX_BACKEND_AUTO;
  c->opencl_platform = 0;
  c->opencl_device = 0;
  c->species_count = 1;
  c->seed_shape = MOLDTEX_SEED_RANDOM;
  c->seed_center.triangle = 0;
  c->seed_center.bary[0] = c->seed_center.bary[1] = c->seed_center.bary[2] = 1.0f / 3.0f;
  c->seed_radius = 0.0f;
  c->seed_rays = 8;
  c->fields_rgba = nullptr;
  c->model = MOLDTEX_MODEL_MOMAS;
  c->detail = 1;
}

void moldtex_continuous_params_init(moldtex_continuous_params* p) {
  if (!p) return;
  std::memset(p, 0, sizeof(*p));
  p->struct_size = sizeof(*p);
  // Jones' classic agent (1 texel per step at 60 Hz, sensor 9 texels ahead at 45 degrees,
  // 45 degree turns, a 3x3 mean blur and 10% decay per step) on a lattice of 0.01 mesh
  // units, as rates.
  p->move_rate = 0.6f;          // 0.01 * 60
  p->turn_rate = 47.12389f;     // pi / 4 * 60
  p->turn_frequency = 60.f;
  p->sensor_distance = 0.09f;
  p->sensor_angle = 45.f;
  p->deposit_rate = 1.f;
  p->diffusion_rate = 0.002f;   // (2/3 h^2 per step) / (2 dt)
  p->decay_rate = 6.3f;         // -ln(0.9) * 60
  p->mean_lifetime = 0.f;
  p->activation_time = 0.f;
  p->time_step = 1.f / 60.f;
  p->integrator = MOLDTEX_INTEGRATOR_AUTO;
  p->bias_strength = 0.f;
  p->bias_symmetry = 1;
  p->bias_spawn = 0;
  p->boundary = MOLDTEX_BOUNDARY_REFLECT;
}

void moldtex_species_params_init(moldtex_species_params* p, uint32_t species) {
  if (!p) return;
  moldtex_sim_params defaults;
  moldtex_sim_params_init(&defaults);
  std::memset(p, 0, sizeof(*p));
  p->struct_size = sizeof(*p);
  p->movement_speed = defaults.movement_speed;
  p->turn_speed = defaults.turn_speed;
  p->vision_distance = defaults.vision_distance;
  p->vision_angle = defaults.vision_angle;
  p->deposit = defaults.deposit;
  for (uint32_t k = 0; k < 4; ++k) p->attraction[k] = k == species ? 1.0f : -1.0f;
}

void moldtex_sim_params_init(moldtex_sim_params* p) {
  if (!p) return;
  std::memset(p, 0, sizeof(*p));
  p->struct_size = sizeof(*p);
  p->movement_speed = 1.0f;
  p->turn_speed = 20.0f;
  p->vision_distance = 1.0f;
  p->vision_angle = 30.0f;
  p->evaporation_rate = 0.5f;
  p->diffusion_rate = 10.0f;
  p->deposit = 1.0f;
  p->time_step = 1.0f / 60.0f;
  p->substeps = 2;
  p->thread_count = 0;
  p->hunger_rate = 0.0f;
  p->food_radius = 0.1f;
  p->sensor_size = 0;
}

moldtex_status moldtex_sim_create(moldtex_surface surface, const moldtex_sim_config* config,
                                  const moldtex_sim_params* params, moldtex_sim* out) {
  return moldtex_sim_create_in(nullptr, surface, config, params, out);
}

moldtex_status moldtex_sim_create_in(moldtex_context context, moldtex_surface surface,
                                     const moldtex_sim_config* config, const moldtex_sim_params* params,
                                     moldtex_sim* out) {
  return guarded([&] {
    require(out != nullptr, "out_sim is NULL");
    *out = nullptr;
    require(surface != nullptr, "The surface handle is NULL");
    moldtex_sim_config c = read_config(config);
    moldtex_sim_params p = read_params(params);
    auto sim = std::make_shared<moldtex::Simulation>(surface->surface, c, p, *cache_of(context));
    *out = new moldtex_sim_t{std::move(sim), nullptr};
  });
}

moldtex_status moldtex_context_create(moldtex_context* out) {
  return guarded([&] {
    require(out != nullptr, "out_context is NULL");
    *out = nullptr;
    *out = new moldtex_context_t{std::make_shared<moldtex::IntrinsicDomainCache>()};
  });
}

void moldtex_context_release(moldtex_context context) { delete context; }

moldtex_status moldtex_context_clear(moldtex_context context) {
  return guarded([&] { cache_of(context)->clear(); });
}

moldtex_status moldtex_context_cached_domains(moldtex_context context, uint32_t* count) {
  return guarded([&] {
    require(count != nullptr, "count is NULL");
    *count = static_cast<uint32_t>(cache_of(context)->size());
  });
}

void moldtex_sim_release(moldtex_sim sim) { delete sim; }

moldtex_status moldtex_sim_set_params(moldtex_sim sim, const moldtex_sim_params* params) {
  return guarded([&] {
    use(sim).set_params(read_params(params));
  });
}

moldtex_status moldtex_sim_get_params(moldtex_sim sim, moldtex_sim_params* params) {
  return guarded([&] {
    use(sim);
    read_params(params);
    // Write back only as much as the caller's struct holds.
    const uint32_t caller_size = params->struct_size;
    const moldtex_sim_params out = sim->sim->params();
    std::memcpy(params, &out, std::min<size_t>(caller_size, sizeof(out)));
    params->struct_size = caller_size;
  });
}

moldtex_status moldtex_sim_set_continuous_params(moldtex_sim sim, const moldtex_continuous_params* params) {
  return guarded([&] {
    use(sim).set_continuous_params(
        read_struct(params, "moldtex_continuous_params", moldtex_continuous_params_init));
  });
}

moldtex_status moldtex_sim_set_bias(moldtex_sim sim, const float* vectors, size_t float_count) {
  return guarded([&] {
    moldtex::Simulation& s = use(sim);
    if (vectors) {
      const size_t need = static_cast<size_t>(s.surface().triangle_count()) * 3;
      if (float_count != need)
        moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                      "The bias needs triangle_count * 3 floats (" + std::to_string(need) + "), got " +
                          std::to_string(float_count));
    }
    s.set_bias(vectors);
  });
}

moldtex_status moldtex_sim_set_map(moldtex_sim sim, uint32_t map, const float* values, size_t count) {
  return guarded([&] {
    moldtex::Simulation& s = use(sim);
    moldtex::validate_map(map, values, count, s.image_texel_count());
    s.set_map(map, values);
  });
}

moldtex_status moldtex_sim_get_map(moldtex_sim sim, uint32_t map, float* values, size_t count,
                                   uint32_t* is_set) {
  return guarded([&] {
    moldtex::Simulation& s = use(sim);
    moldtex::validate_map(map, nullptr, 0, 0);
    if (!is_set) moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "is_set is NULL");
    const std::vector<float>& m = s.map(map);
    *is_set = m.empty() ? 0u : 1u;
    if (m.empty()) return;
    if (!values || count != s.image_texel_count())
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The map needs a buffer of width * height = " +
                                                        std::to_string(s.image_texel_count()) + " floats");
    s.read_map(map, values);
  });
}

moldtex_status moldtex_sim_get_continuous_params(moldtex_sim sim, moldtex_continuous_params* params) {
  return guarded([&] {
    use(sim);
    read_struct(params, "moldtex_continuous_params", moldtex_continuous_params_init);
    const uint32_t caller_size = params->struct_size;
    const moldtex_continuous_params out = sim->sim->continuous_params();
    std::memcpy(params, &out, std::min<size_t>(caller_size, sizeof(out)));
    params->struct_size = caller_size;
  });
}

moldtex_status moldtex_sim_set_species_params(moldtex_sim sim, uint32_t index,
                                              const moldtex_species_params* params) {
  return guarded([&] {
    use(sim).set_species_params(index, read_struct(params, "moldtex_species_params"));
  });
}

moldtex_status moldtex_sim_get_species_params(moldtex_sim sim, uint32_t index,
                                              moldtex_species_params* params) {
  return guarded([&] {
    moldtex::Simulation& s = use(sim);
    read_struct(params, "moldtex_species_params");
    if (index >= s.species_count())
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "The species index is out of range: the simulation has " +
                        std::to_string(s.species_count()) + " species");
    *params = s.species_params(index);
  });
}

moldtex_status moldtex_sim_set_fields(moldtex_sim sim, const float* rgba, size_t float_count) {
  return guarded([&] {
    moldtex::Simulation& s = use(sim);
    if (rgba) {
      const size_t need = s.image_texel_count() * 4;
      if (float_count != need)
        moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                      "The fields need width * height * 4 floats (" + std::to_string(need) +
                          "), got " + std::to_string(float_count));
    }
    s.set_fields(rgba);
  });
}

moldtex_status moldtex_sim_set_food(moldtex_sim sim, const moldtex_food_source* sources,
                                    uint32_t count) {
  return guarded([&] { use(sim).set_food(sources, count); });
}

moldtex_status moldtex_sim_get_food(moldtex_sim sim, moldtex_food_source* sources,
                                    uint32_t capacity, uint32_t* count) {
  return guarded([&] {
    require(count != nullptr, "NULL argument");
    require(sources != nullptr || capacity == 0, "NULL argument");
    const auto& food = use(sim).food();
    const size_t n = std::min<size_t>(capacity, food.size());
    std::copy(food.begin(), food.begin() + static_cast<std::ptrdiff_t>(n), sources);
    *count = static_cast<uint32_t>(food.size());
  });
}

moldtex_status moldtex_sim_get_config(moldtex_sim sim, moldtex_sim_config* config) {
  return guarded([&] {
    use(sim);
    read_config(config);
    // Write back only as much as the caller's struct holds.
    moldtex_sim_config out = sim->sim->config();
    const uint32_t caller_size = config->struct_size;
    std::memcpy(config, &out, std::min<size_t>(caller_size, sizeof(out)));
    config->struct_size = caller_size;
  });
}

moldtex_status moldtex_sim_get_backend_name(moldtex_sim sim, char* buffer, size_t capacity) {
  return guarded([&] {
    require(buffer != nullptr && capacity > 0, "NULL argument or zero capacity");
    const std::string name = use(sim).backend_name();
    size_t n = std::min(name.size(), capacity - 1);
    std::memcpy(buffer, name.data(), n);
    buffer[n] = '\0';
  });
}

moldtex_status moldtex_sim_reset(moldtex_sim sim) {
  return guarded([&] {
    use(sim).reset();
  });
}

moldtex_status moldtex_sim_step(moldtex_sim sim, uint32_t steps) {
  return guarded([&] {
    moldtex::Simulation& s = use(sim);
    if (steps > MOLDTEX_MAX_STEPS_PER_CALL)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "One call steps at most " + std::to_string(MOLDTEX_MAX_STEPS_PER_CALL) + " times (asked for " +
                        std::to_string(steps) + "): step in chunks, or run in the background");
    s.step(steps);
  });
}

void moldtex_run_progress_init(moldtex_run_progress* p) {
  if (!p) return;
  std::memset(p, 0, sizeof(*p));
  p->struct_size = sizeof(*p);
}

moldtex_status moldtex_sim_run_start(moldtex_sim sim, double chunk_seconds, double limit_seconds,
                                     double step_seconds_hint) {
  return guarded([&] {
    use(sim);
    if (sim->run) {  // an earlier run that ended by itself: its error was not collected
      sim->run->stop();
      sim->run.reset();
    }
    sim->run = std::make_unique<moldtex::LiveRun>(sim->sim, chunk_seconds, limit_seconds, step_seconds_hint);
  });
}

moldtex_status moldtex_sim_run_get_progress(moldtex_sim sim, moldtex_run_progress* progress) {
  return guarded([&] {
    require(sim != nullptr, "The simulation handle is NULL");
    require(progress != nullptr, "progress is NULL");
    require(progress->struct_size >= sizeof(moldtex_run_progress), "progress.struct_size is too small");
    require(sim->run != nullptr, "No live run was started on this simulation");
    *progress = sim->run->progress();
  });
}

moldtex_status moldtex_sim_run_stop(moldtex_sim sim, moldtex_run_progress* progress) {
  if (!sim) return set_error(MOLDTEX_ERROR_INVALID_ARGUMENT, "The simulation handle is NULL");
  moldtex_run_progress last{};
  last.struct_size = sizeof last;
  moldtex_status status = MOLDTEX_OK;
  std::string message;
  if (sim->run) {
    status = sim->run->stop();
    last = sim->run->progress();
    message = sim->run->message();
    sim->run.reset();
  }
  if (progress) {
    if (progress->struct_size < sizeof last) return set_error(MOLDTEX_ERROR_INVALID_ARGUMENT, "progress.struct_size is too small");
    *progress = last;
  }
  if (status != MOLDTEX_OK) return set_error(status, message);
  g_last_error.clear();
  return MOLDTEX_OK;
}

moldtex_status moldtex_sim_read_rgba(moldtex_sim sim, float* rgba, size_t float_count) {
  return guarded([&] {
    require(rgba != nullptr, "NULL argument");
    size_t need = use(sim).image_texel_count() * 4;
    if (float_count < need)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "The RGBA buffer is too small: it needs width * height * 4 floats (" +
                        std::to_string(need) + ")");
    sim->sim->read_rgba(rgba);
  });
}

moldtex_status moldtex_sim_read_vertex_rgba(moldtex_sim sim, float* rgba, size_t float_count) {
  return guarded([&] {
    require(rgba != nullptr, "NULL argument");
    const size_t need = size_t(use(sim).surface().vertex_count()) * 4;
    if (float_count < need)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "The RGBA buffer is too small: it needs vertex_count * 4 floats (" + std::to_string(need) + ")");
    sim->sim->read_vertex_rgba(rgba);
  });
}

moldtex_status moldtex_sim_read_texel_classes(moldtex_sim sim, uint8_t* classes, size_t count) {
  return guarded([&] {
    require(classes != nullptr, "NULL argument");
    const moldtex::Simulation& s = use(sim);
    if (count < s.image_texel_count())
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The class buffer needs width * height bytes");
    s.read_texel_classes(classes);
  });
}

moldtex_status moldtex_sim_read_agents(moldtex_sim sim, moldtex_surface_point* points,
                                       uint32_t capacity) {
  return guarded([&] {
    require(points != nullptr, "NULL argument");
    use(sim).read_agents(points, capacity);
  });
}

void moldtex_sim_stats_init(moldtex_sim_stats* stats) {
  if (!stats) return;
  std::memset(stats, 0, sizeof(*stats));
  stats->struct_size = sizeof(*stats);
}

moldtex_status moldtex_sim_get_stats(moldtex_sim sim, moldtex_sim_stats* stats) {
  return guarded([&] {
    use(sim);
    // Callers from before the continuous model end at presence.
    read_struct(stats, "moldtex_sim_stats", moldtex_sim_stats_init, offsetof(moldtex_sim_stats, u_metric));
    const uint32_t caller_size = stats->struct_size;
    const moldtex_sim_stats out = sim->sim->stats();
    std::memcpy(stats, &out, std::min<size_t>(caller_size, sizeof(out)));
    stats->struct_size = caller_size;
  });
}

void moldtex_domain_info_init(moldtex_domain_info* info) {
  if (!info) return;
  std::memset(info, 0, sizeof(*info));
  info->struct_size = sizeof(*info);
}

moldtex_status moldtex_sim_get_domain_info(moldtex_sim sim, moldtex_domain_info* info) {
  return guarded([&] {
    use(sim);
    read_struct(info, "moldtex_domain_info", moldtex_domain_info_init);
    const uint32_t caller_size = info->struct_size;
    const moldtex_domain_info out = sim->sim->domain_info();
    std::memcpy(info, &out, std::min<size_t>(caller_size, sizeof(out)));
    info->struct_size = caller_size;
  });
}

moldtex_status moldtex_sim_read_intrinsic_vertices(moldtex_sim sim, float* xyz_area, float* values,
                                                  uint32_t vertex_count) {
  return guarded([&] { use(sim).read_intrinsic_vertices(xyz_area, values, vertex_count); });
}

moldtex_status moldtex_sim_read_intrinsic_faces(moldtex_sim sim, uint32_t* corners, uint32_t face_count) {
  return guarded([&] {
    require(corners != nullptr, "NULL argument");
    use(sim).read_intrinsic_faces(corners, face_count);
  });
}

moldtex_status moldtex_sim_write_image(moldtex_sim sim, const char* path, uint32_t format) {
  return guarded([&] {
    require_path(path);
    require(format <= MOLDTEX_IMAGE_PNG16, "Unknown image format");
    use(sim).write_image(path, static_cast<moldtex_image_format>(format));
  });
}

moldtex_status moldtex_sim_save_checkpoint(moldtex_sim sim, const char* path) {
  return guarded([&] {
    require_path(path);
    use(sim).save_checkpoint(path, {});
  });
}

moldtex_status moldtex_sim_load_checkpoint(moldtex_sim sim, const char* path) {
  return guarded([&] {
    require_path(path);
    use(sim).load_checkpoint(path);
  });
}

void moldtex_bake_desc_init(moldtex_bake_desc* d) {
  if (!d) return;
  std::memset(d, 0, sizeof(*d));
  d->struct_size = sizeof(*d);
  d->file_prefix = "moldtex_";
  d->first_frame = 1;
  d->last_frame = 250;
  d->steps_per_frame = 2;
  d->format = MOLDTEX_IMAGE_EXR_HALF;
  d->write_checkpoints = 1;
}

void moldtex_bake_progress_init(moldtex_bake_progress* p) {
  if (!p) return;
  std::memset(p, 0, sizeof(*p));
  p->struct_size = sizeof(*p);
}

moldtex_status moldtex_bake_start(moldtex_sim sim, const moldtex_bake_desc* desc, moldtex_bake* out) {
  return guarded([&] {
    require(out != nullptr, "out_bake is NULL");
    *out = nullptr;
    use(sim);
    moldtex::BakeOptions options = moldtex::validate_bake(read_struct(desc, "moldtex_bake_desc"));
    *out = new moldtex_bake_t{std::make_unique<moldtex::Bake>(sim->sim, std::move(options))};
  });
}

moldtex_status moldtex_bake_get_progress(moldtex_bake bake, moldtex_bake_progress* progress) {
  return guarded([&] {
    require(bake != nullptr, "The bake handle is NULL");
    read_struct(progress, "moldtex_bake_progress");
    *progress = bake->bake->progress();
  });
}

void moldtex_bake_cancel(moldtex_bake bake) {
  if (bake) bake->bake->cancel();
}

moldtex_status moldtex_bake_wait(moldtex_bake bake) {
  if (!bake) return set_error(MOLDTEX_ERROR_INVALID_ARGUMENT, "The bake handle is NULL");
  moldtex_status status = bake->bake->wait();
  if (status != MOLDTEX_OK) return set_error(status, bake->bake->progress().message);
  g_last_error.clear();
  return MOLDTEX_OK;
}

void moldtex_bake_release(moldtex_bake bake) { delete bake; }

void moldtex_domain_build_progress_init(moldtex_domain_build_progress* p) {
  if (!p) return;
  std::memset(p, 0, sizeof(*p));
  p->struct_size = sizeof(*p);
}

moldtex_status moldtex_domain_build_start(moldtex_surface surface, const moldtex_sim_config* config,
                                          uint32_t thread_count, moldtex_domain_build* out) {
  return moldtex_domain_build_start_in(nullptr, surface, config, thread_count, out);
}

moldtex_status moldtex_domain_build_start_in(moldtex_context context, moldtex_surface surface,
                                             const moldtex_sim_config* config, uint32_t thread_count,
                                             moldtex_domain_build* out) {
  return guarded([&] {
    require(out != nullptr, "out_build is NULL");
    *out = nullptr;
    require(surface != nullptr, "The surface handle is NULL");
    require(thread_count <= 256, "thread_count must be 0 (all cores) .. 256");
    const moldtex_sim_config c = read_config(config);
    *out = new moldtex_domain_build_t{
        std::make_unique<moldtex::DomainBuild>(surface->surface, c, thread_count, cache_of(context))};
  });
}

moldtex_status moldtex_domain_build_get_progress(moldtex_domain_build build,
                                                 moldtex_domain_build_progress* progress) {
  return guarded([&] {
    require(build != nullptr, "The domain build handle is NULL");
    read_struct(progress, "moldtex_domain_build_progress");
    *progress = build->build->progress();
  });
}

void moldtex_domain_build_cancel(moldtex_domain_build build) {
  if (build) build->build->cancel();
}

moldtex_status moldtex_domain_build_wait(moldtex_domain_build build) {
  if (!build) return set_error(MOLDTEX_ERROR_INVALID_ARGUMENT, "The domain build handle is NULL");
  const moldtex_status status = build->build->wait();
  if (status != MOLDTEX_OK) return set_error(status, build->build->message());
  g_last_error.clear();
  return MOLDTEX_OK;
}

void moldtex_domain_build_release(moldtex_domain_build build) { delete build; }

void moldtex_opencl_device_info_init(moldtex_opencl_device_info* info) {
  if (!info) return;
  std::memset(info, 0, sizeof(*info));
  info->struct_size = sizeof(*info);
}

moldtex_status moldtex_opencl_device_count(uint32_t* count) {
  if (count) *count = 0;
  return guarded([&] {
    require(count != nullptr, "count is NULL");
#ifdef MOLDTEX_HAVE_OPENCL
    *count = static_cast<uint32_t>(moldtex::cl::list_devices().size());
#else
    moldtex::fail(MOLDTEX_ERROR_UNAVAILABLE, "This build of Moldtex has no OpenCL support");
#endif
  });
}

moldtex_status moldtex_opencl_get_device(uint32_t index, moldtex_opencl_device_info* info) {
  return guarded([&] {
    moldtex_opencl_device_info out = read_struct(info, "moldtex_opencl_device_info");
#ifdef MOLDTEX_HAVE_OPENCL
    const auto devices = moldtex::cl::list_devices();
    if (index >= devices.size())
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "OpenCL device index " + std::to_string(index) + " is out of range: this machine has " +
                        std::to_string(devices.size()) + " OpenCL device(s)");
    const auto& d = devices[index];
    out.platform_index = d.platform_index;
    out.device_index = d.device_index;
    out.is_gpu = d.is_gpu ? 1u : 0u;
    out.global_memory_bytes = d.global_memory;
    std::snprintf(out.name, sizeof(out.name), "%s", d.name.c_str());
    std::snprintf(out.platform_name, sizeof(out.platform_name), "%s", d.platform_name.c_str());
    *info = out;
#else
    (void)index;
    (void)out;
    moldtex::fail(MOLDTEX_ERROR_UNAVAILABLE, "This build of Moldtex has no OpenCL support");
#endif
  });
}

// ---- spatial --------------------------------------------------------------------------

void moldtex_ray_hit_init(moldtex_ray_hit* hit) {
  if (!hit) return;
  std::memset(hit, 0, sizeof(*hit));
  hit->struct_size = sizeof(*hit);
}

moldtex_status moldtex_surface_ray_cast(moldtex_surface surface, const float origin[3],
                                        const float direction[3], float max_distance,
                                        moldtex_ray_hit* hit) {
  return guarded([&] {
    require(surface != nullptr, "The surface handle is NULL");
    require(origin != nullptr && direction != nullptr, "The ray origin or direction is NULL");
    moldtex_ray_hit out = read_struct(hit, "moldtex_ray_hit", moldtex_ray_hit_init);
    double length2 = 0;
    for (int k = 0; k < 3; ++k) {
      require(std::isfinite(origin[k]), "The ray origin must be finite");
      require(std::isfinite(direction[k]), "The ray direction must be finite");
      length2 += double(direction[k]) * direction[k];
    }
    require(length2 > 0, "The ray direction must not be zero");
    require(!std::isnan(max_distance) && max_distance >= 0.f,
            "The ray's maximum distance must be >= 0 (INFINITY for no limit)");
    const moldtex::Surface& s = *surface->surface;
    const moldtex::RayHitResult r = surface->spatial->ray_cast(origin, direction, max_distance);
    const uint32_t size = out.struct_size;
    std::memset(&out, 0, sizeof(out));
    out.struct_size = size;
    if (r.hit) {
      out.hit = 1;
      out.point.triangle = r.triangle;
      std::copy(r.bary, r.bary + 3, out.point.bary);
      out.distance = r.distance;
      s.evaluate(r.triangle, r.bary, out.position, out.uv);
      const float* p[3];
      for (int c = 0; c < 3; ++c) p[c] = &s.positions[3 * s.triangles[3 * r.triangle + c]];
      double e1[3], e2[3];
      for (int k = 0; k < 3; ++k) {
        e1[k] = double(p[1][k]) - p[0][k];
        e2[k] = double(p[2][k]) - p[0][k];
      }
      const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                           e1[0] * e2[1] - e1[1] * e2[0]};
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int k = 0; k < 3; ++k) out.normal[k] = len > 0 ? static_cast<float>(n[k] / len) : 0.f;
    }
    *hit = out;
  });
}

moldtex_status moldtex_surface_closest_point(moldtex_surface surface, const float position[3],
                                             moldtex_surface_point* point, float* distance) {
  return guarded([&] {
    require(surface != nullptr, "The surface handle is NULL");
    require(position != nullptr && point != nullptr, "The position or the output point is NULL");
    for (int k = 0; k < 3; ++k) require(std::isfinite(position[k]), "The position must be finite");
    const moldtex::ClosestPointResult r = surface->spatial->closest_point(position);
    point->triangle = r.triangle;
    std::copy(r.bary, r.bary + 3, point->bary);
    if (distance) *distance = static_cast<float>(r.distance);
  });
}

// ---- brushes ---------------------------------------------------------------------------

void moldtex_brush_init(moldtex_brush* brush) {
  if (!brush) return;
  std::memset(brush, 0, sizeof(*brush));
  brush->struct_size = sizeof(*brush);
  brush->center.triangle = 0;
  brush->center.bary[0] = brush->center.bary[1] = brush->center.bary[2] = 1.0f / 3.0f;
  brush->radius = 0.1f;
  brush->strength = 1.0f;
  brush->falloff = 0.5f;
  brush->mode = MOLDTEX_BRUSH_PAINT;
  brush->channel = 0;
  brush->value = 1.0f;
}

moldtex_status moldtex_surface_paint(moldtex_surface surface, uint32_t width, uint32_t height,
                                     float* rgba, size_t float_count, const moldtex_brush* brush,
                                     uint32_t* changed) {
  return guarded([&] {
    if (changed) *changed = 0;
    require(surface != nullptr, "The surface handle is NULL");
    require(rgba != nullptr, "The RGBA image is NULL");
    if (width < 1 || height < 1 || width > 65536 || height > 65536)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "The image size " + std::to_string(width) + " x " + std::to_string(height) +
                        " is outside 1 .. 65536 texels per side");
    const size_t need = static_cast<size_t>(width) * height * 4;
    if (float_count < need)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "The RGBA image is too small: it needs width * height * 4 floats (" +
                        std::to_string(need) + "), got " + std::to_string(float_count));
    const moldtex_brush b = read_struct(brush, "moldtex_brush", moldtex_brush_init);
    const moldtex::Surface& s = *surface->surface;
    moldtex::validate_brush(s, b);
    require(b.channel < 4, "The brush channel must be 0 (R), 1 (G), 2 (B) or 3 (A)");
    const uint32_t n = moldtex::paint_dab(s, width, height, rgba, b);
    if (changed) *changed = n;
  });
}

moldtex_status moldtex_sim_add_agents(moldtex_sim sim, const moldtex_brush* brush, uint32_t count,
                                      uint32_t batch) {
  return guarded([&] {
    moldtex::Simulation& s = use(sim);
    s.add_agents(read_struct(brush, "moldtex_brush", moldtex_brush_init), count, batch);
  });
}

moldtex_status moldtex_sim_erase_agents(moldtex_sim sim, const moldtex_brush* brush, uint32_t batch,
                                        uint32_t* removed) {
  return guarded([&] {
    if (removed) *removed = 0;
    moldtex::Simulation& s = use(sim);
    const uint32_t n = s.erase_agents(read_struct(brush, "moldtex_brush", moldtex_brush_init), batch);
    if (removed) *removed = n;
  });
}

moldtex_status moldtex_sim_undo_agents(moldtex_sim sim, uint32_t batch) {
  return guarded([&] { use(sim).undo_agents(batch); });
}

}  // extern "C"

// ---- surface map tools (Layton et al. §6) -------------------------------------------------
// Kept in one block at the end of the file (its own includes too) so that it merges
// cleanly with edits to the simulation calls above.
#include <cfloat>

#include "maps/heat_geodesic.h"
#include "maps/laplace_interpolation.h"
#include "maps/map_diffusion.h"
#include "maps/surface_fe.h"

namespace {

constexpr double kMaxMapValue = 1e15;

const moldtex::Surface& map_surface(moldtex_surface surface) {
  require(surface != nullptr, "The surface handle is NULL");
  return *surface->surface;
}

// The per-vertex input array: non-NULL, exactly vertex_count entries, each finite and
// within +-1e15 (what `what` names in messages).
std::vector<double> read_vertex_values(const moldtex::Surface& s, const float* values, size_t count,
                                       const char* what) {
  if (values == nullptr) moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, std::string("The ") + what + " array is NULL");
  if (count != s.vertex_count())
    moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                  std::string("The ") + what + " array must have one value per vertex (" +
                      std::to_string(s.vertex_count()) + "), got " + std::to_string(count));
  std::vector<double> out(count);
  for (size_t i = 0; i < count; ++i) {
    if (!std::isfinite(values[i]) || std::fabs(values[i]) > kMaxMapValue)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    std::string("The ") + what + " of vertex " + std::to_string(i) +
                        " is not a finite number within +-1e15");
    out[i] = values[i];
  }
  return out;
}

void require_output(const float* out, size_t out_count, size_t need, const char* what) {
  if (out == nullptr) moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, std::string("The output ") + what + " array is NULL");
  if (out_count < need)
    moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                  std::string("The output ") + what + " array is too small: it needs " + std::to_string(need) +
                      " floats, got " + std::to_string(out_count));
}

// Copies doubles to the caller's floats, refusing values a float cannot hold.
void write_floats(const std::vector<double>& in, float* out) {
  for (double v : in)
    if (!std::isfinite(v) || std::fabs(v) > FLT_MAX)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "A result does not fit in a float: scale the input values down (or remove sliver "
                    "triangles from the mesh)");
  for (size_t i = 0; i < in.size(); ++i) out[i] = static_cast<float>(in[i]);
}

}  // namespace

extern "C" {

moldtex_status moldtex_surface_geodesic_distance(moldtex_surface surface, const float* source_weights,
                                                 size_t vertex_count, float time_factor, float* out_distance,
                                                 size_t out_count) {
  return guarded([&] {
    const moldtex::Surface& s = map_surface(surface);
    const std::vector<double> w = read_vertex_values(s, source_weights, vertex_count, "source weight");
    require_output(out_distance, out_count, s.vertex_count(), "distance");
    require(std::isfinite(time_factor) && time_factor > 0.f && time_factor <= 1e6f,
            "The heat time factor must be a finite number in (0, 1e6] (1 is the usual choice)");
    std::vector<uint8_t> source(w.size());
    bool any = false;
    for (size_t i = 0; i < w.size(); ++i) any |= (source[i] = w[i] > 0.5) != 0;
    require(any, "No source vertex: the distance is measured from the vertices whose weight is above 0.5");
    const moldtex::maps::SurfaceFE fe = moldtex::maps::build_surface_fe(s);
    write_floats(moldtex::maps::heat_geodesic_distance(s, fe, source, time_factor), out_distance);
  });
}

moldtex_status moldtex_surface_laplace_interpolate(moldtex_surface surface, const float* values,
                                                   const uint8_t* fixed, size_t count, float* out,
                                                   size_t out_count) {
  return guarded([&] {
    const moldtex::Surface& s = map_surface(surface);
    const std::vector<double> v = read_vertex_values(s, values, count, "value");
    require(fixed != nullptr, "The fixed-vertex mask is NULL");
    require_output(out, out_count, s.vertex_count(), "value");
    std::vector<uint8_t> mask(fixed, fixed + count);
    bool any = false;
    for (uint8_t& m : mask) any |= (m = m != 0) != 0;
    require(any, "No fixed vertex: Laplace interpolation blends between the values of fixed vertices");
    const moldtex::maps::SurfaceFE fe = moldtex::maps::build_surface_fe(s);
    write_floats(moldtex::maps::laplace_interpolate(fe, v, mask), out);
  });
}

moldtex_status moldtex_surface_diffuse_map(moldtex_surface surface, const float* values, size_t count,
                                           float time, float* out, size_t out_count) {
  return guarded([&] {
    const moldtex::Surface& s = map_surface(surface);
    const std::vector<double> v = read_vertex_values(s, values, count, "value");
    require_output(out, out_count, s.vertex_count(), "value");
    require(std::isfinite(time) && time >= 0.f,
            "The diffusion time must be a finite number >= 0 (mesh units squared)");
    const moldtex::maps::SurfaceFE fe = moldtex::maps::build_surface_fe(s);
    write_floats(moldtex::maps::diffuse_map(fe, v, time), out);
  });
}

moldtex_status moldtex_surface_map_gradient(moldtex_surface surface, const float* values, size_t count,
                                            float* out_vectors, size_t out_float_count) {
  return guarded([&] {
    const moldtex::Surface& s = map_surface(surface);
    const std::vector<double> v = read_vertex_values(s, values, count, "value");
    require_output(out_vectors, out_float_count, 3ull * s.triangle_count(), "gradient");
    const moldtex::maps::SurfaceFE fe = moldtex::maps::build_surface_fe(s);
    std::vector<double> g(3ull * s.triangle_count());
    moldtex::maps::fe_gradient(fe, s, v.data(), g.data());
    write_floats(g, out_vectors);
  });
}

}  // extern "C"

// ---- colour map from an image (Layton et al. §3.4) ------------------------------------

#include "colour/ramp_fit.h"

extern "C" {

void moldtex_colour_ramp_desc_init(moldtex_colour_ramp_desc* desc) {
  if (!desc) return;
  std::memset(desc, 0, sizeof(*desc));
  desc->struct_size = sizeof(*desc);
  desc->channels = 4;
  desc->srgb_encoded = 0;
  desc->sample_count = 1500;
  desc->neighbour_count = 10;
  desc->max_stops = 32;
  desc->tolerance = 1.0f;
  desc->reverse = 0;
  desc->peak_position = -1.0f;
  desc->seed = 0x6d6f6c64ull;
}

void moldtex_colour_ramp_info_init(moldtex_colour_ramp_info* info) {
  if (!info) return;
  std::memset(info, 0, sizeof(*info));
  info->struct_size = sizeof(*info);
}

moldtex_status moldtex_colour_ramp_from_pixels(const float* pixels, size_t pixel_count,
                                               const moldtex_colour_ramp_desc* desc,
                                               moldtex_colour_stop* out_stops, uint32_t capacity,
                                               moldtex_colour_ramp_info* info) {
  return guarded([&] {
    const moldtex_colour_ramp_desc d =
        read_struct(desc, "moldtex_colour_ramp_desc", moldtex_colour_ramp_desc_init);
    require(pixels != nullptr, "The pixel array is NULL");
    require(out_stops != nullptr, "The output stop array is NULL");
    if (info != nullptr && info->struct_size < offsetof(moldtex_colour_ramp_info, explained))
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "moldtex_colour_ramp_info.struct_size is too small: initialise it with its _init function");
    require(d.channels == 3 || d.channels == 4, "Pixels must have 3 (RGB) or 4 (RGBA) channels");
    require(d.srgb_encoded <= 1 && d.reverse <= 1, "srgb_encoded and reverse must be 0 or 1");
    require(d.sample_count >= 16 && d.sample_count <= 4096, "The sample count must be in 16..4096");
    require(d.neighbour_count >= 2 && d.neighbour_count <= 64, "The neighbour count must be in 2..64");
    require(d.max_stops >= 2 && d.max_stops <= 32, "The number of stops must be in 2..32");
    require(std::isfinite(d.tolerance) && d.tolerance > 0.f && d.tolerance <= 100.f,
            "The stop tolerance must be a finite Delta E in (0, 100]");
    require(std::isfinite(d.peak_position) && d.peak_position <= 1.f,
            "Peak At must be a position in [0, 1] (or negative: off)");
    require(capacity >= d.max_stops, "The output stop array holds fewer stops than max_stops");
    if (pixel_count < 2)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The image has no pixels (a colour map needs at least 2)");
    if (pixel_count > (size_t{1} << 32) / d.channels)
      moldtex::fail(MOLDTEX_ERROR_TOO_LARGE, "The image is too large (more than 2^32 floats)");
    const size_t floats = pixel_count * d.channels;
    for (size_t i = 0; i < floats; ++i) {
      const float v = pixels[i];
      if (!(v >= -1.f && v <= 1e6f)) {  // (false for NaN)
        if (d.channels == 4 && i % 4 == 3 && std::isfinite(v)) continue;  // alpha: ignored
        moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                      "Pixel " + std::to_string(i / d.channels) + " has a value that is NaN, infinite or "
                      "outside [-1, 1e6]: fix or re-save the image");
      }
    }
    moldtex::colour::RampOptions o;
    o.channels = d.channels;
    o.srgb_encoded = d.srgb_encoded != 0;
    o.sample_count = d.sample_count;
    o.neighbour_count = d.neighbour_count;
    o.max_stops = d.max_stops;
    o.tolerance = d.tolerance;
    o.reverse = d.reverse != 0;
    o.peak_position = d.peak_position < 0.f ? -1.0 : d.peak_position;
    o.seed = d.seed;
    const moldtex::colour::RampResult r = moldtex::colour::colour_ramp_from_pixels(pixels, pixel_count, o);
    if (r.stops.size() < 2 || r.stops.size() > d.max_stops)
      moldtex::fail(MOLDTEX_ERROR_INTERNAL, "Internal error: the colour map has a wrong number of stops");
    for (size_t i = 0; i < r.stops.size(); ++i) {
      out_stops[i].position = r.stops[i].position;
      for (int c = 0; c < 3; ++c) out_stops[i].color[c] = r.stops[i].rgb[c];
      out_stops[i].color[3] = 1.f;
    }
    if (info != nullptr) {
      moldtex_colour_ramp_info out;
      moldtex_colour_ramp_info_init(&out);
      out.stop_count = static_cast<uint32_t>(r.stops.size());
      out.sample_count = static_cast<uint32_t>(r.sample_count);
      out.component_count = static_cast<uint32_t>(r.component_count);
      out.explained = static_cast<float>(r.explained);
      out.variance_explained = static_cast<float>(r.variance_explained);
      out.eigen_energy = static_cast<float>(r.eigen_energy);
      out.mean_error = static_cast<float>(r.mean_error);
      out.ramp_error = static_cast<float>(r.ramp_error);
      out.continuity = static_cast<float>(r.continuity);
      const uint32_t size = info->struct_size;
      std::memcpy(info, &out, std::min<size_t>(size, sizeof(out)));
      info->struct_size = std::min<uint32_t>(size, sizeof(out));
    }
  });
}

}  // extern "C"

// ---- Gray-Scott reaction-diffusion (MOLDTEX_MODEL_GRAY_SCOTT) ------------------------
extern "C" {

void moldtex_reaction_params_init(moldtex_reaction_params* p) {
  if (!p) return;
  std::memset(p, 0, sizeof(*p));
  p->struct_size = sizeof(*p);
  // Spots, with the classic pixel-unit rates (D_u 0.2, D_v 0.1 per second, dt 1) on a
  // lattice of 0.01 mesh units.
  p->feed = 0.035f;
  p->kill = 0.065f;
  p->diffusion_u = 2e-5f;
  p->diffusion_v = 1e-5f;
  p->time_step = 1.0f;
  p->seed_count = 8;
  p->seed_radius = 0.05f;
}

moldtex_status moldtex_sim_set_reaction_params(moldtex_sim sim, const moldtex_reaction_params* params) {
  return guarded([&] {
    use(sim).set_reaction_params(read_struct(params, "moldtex_reaction_params", moldtex_reaction_params_init));
  });
}

moldtex_status moldtex_sim_get_reaction_params(moldtex_sim sim, moldtex_reaction_params* params) {
  return guarded([&] {
    use(sim);
    read_struct(params, "moldtex_reaction_params", moldtex_reaction_params_init);
    const uint32_t caller_size = params->struct_size;
    const moldtex_reaction_params out = sim->sim->reaction_params();
    std::memcpy(params, &out, std::min<size_t>(caller_size, sizeof(out)));
    params->struct_size = caller_size;
  });
}

moldtex_status moldtex_sim_set_model_params(moldtex_sim sim, uint32_t model, const void* params) {
  switch (model) {
    case MOLDTEX_MODEL_MOMAS:
      return moldtex_sim_set_params(sim, static_cast<const moldtex_sim_params*>(params));
    case MOLDTEX_MODEL_CONTINUOUS:
      return moldtex_sim_set_continuous_params(sim, static_cast<const moldtex_continuous_params*>(params));
    case MOLDTEX_MODEL_GRAY_SCOTT:
      return moldtex_sim_set_reaction_params(sim, static_cast<const moldtex_reaction_params*>(params));
    default:
      return guarded([&] { moldtex::model_of(model); });  // refuses, naming the models
  }
}

moldtex_status moldtex_sim_get_model_params(moldtex_sim sim, uint32_t model, void* params) {
  switch (model) {
    case MOLDTEX_MODEL_MOMAS:
      return moldtex_sim_get_params(sim, static_cast<moldtex_sim_params*>(params));
    case MOLDTEX_MODEL_CONTINUOUS:
      return moldtex_sim_get_continuous_params(sim, static_cast<moldtex_continuous_params*>(params));
    case MOLDTEX_MODEL_GRAY_SCOTT:
      return moldtex_sim_get_reaction_params(sim, static_cast<moldtex_reaction_params*>(params));
    default:
      return guarded([&] { moldtex::model_of(model); });
  }
}

}  // extern "C"

// ---- intrinsic Delaunay triangulation ----------------------------------------------

struct moldtex_intrinsic_t {
  std::shared_ptr<const moldtex::Surface> surface;
  moldtex::intrinsic::IntrinsicTriangulation T;
  std::vector<uint32_t> face_of_triangle;  // per surface triangle: its input face, or kInvalid
  moldtex_intrinsic_info info;
};

namespace {

constexpr uint32_t kMaxIntrinsicInsertions = 16000000u;
constexpr uint32_t kMaxIntrinsicPoints = 1u << 24;

// Weights of a caller's point as doubles: clamped to >= 0 and normalised.
std::array<double, 3> point_weights(const moldtex_surface_point& p) {
  std::array<double, 3> b;
  double sum = 0;
  for (int k = 0; k < 3; ++k) sum += (b[k] = std::max(0.0, double(p.bary[k])));
  for (double& w : b) w /= sum;
  return b;
}

void require_points(const moldtex_surface_point* in, uint32_t count, const moldtex_surface_point* out,
                    const char* out_name) {
  require(in != nullptr, "The input points are NULL");
  require(out != nullptr, out_name);
  require(count >= 1, "The point count is 0: pass at least one point");
  if (count > kMaxIntrinsicPoints)
    moldtex::fail(MOLDTEX_ERROR_TOO_LARGE, "Too many points in one call (" + std::to_string(count) +
                                               "): pass at most 16,777,216 at a time");
}

void require_weights(const moldtex_surface_point& p, uint32_t i) {
  float sum = 0;
  for (float b : p.bary) {
    if (!(std::isfinite(b) && b >= -1e-4f))
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                    "Point " + std::to_string(i) + ": barycentric weights must be finite and non-negative");
    sum += b;
  }
  if (!(std::fabs(sum - 1.f) < 1e-3f))
    moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Point " + std::to_string(i) + ": barycentric weights must sum to 1");
}

void write_point(const moldtex::intrinsic::SurfacePoint& p, uint32_t triangle, moldtex_surface_point* out) {
  out->triangle = triangle;
  double sum = 0;
  std::array<double, 3> b;
  for (int k = 0; k < 3; ++k) sum += (b[k] = std::isfinite(p.bary[k]) ? std::max(0.0, p.bary[k]) : 0.0);
  if (!(sum > 0)) b = {1.0 / 3, 1.0 / 3, 1.0 / 3}, sum = 1;
  for (int k = 0; k < 3; ++k) out->bary[k] = static_cast<float>(b[k] / sum);
}

}  // namespace

void moldtex_intrinsic_params_init(moldtex_intrinsic_params* params) {
  if (!params) return;
  std::memset(params, 0, sizeof(*params));
  params->struct_size = sizeof(*params);
  params->max_circumradius = 0.f;
  params->max_insertions = 4000000u;
}

void moldtex_intrinsic_info_init(moldtex_intrinsic_info* info) {
  if (!info) return;
  std::memset(info, 0, sizeof(*info));
  info->struct_size = sizeof(*info);
}

moldtex_status moldtex_intrinsic_create(moldtex_surface surface, const moldtex_intrinsic_params* params,
                                        moldtex_intrinsic* out) {
  namespace mi = moldtex::intrinsic;
  return guarded([&] {
    require(out != nullptr, "out_intrinsic is NULL");
    *out = nullptr;
    require(surface != nullptr, "The surface handle is NULL");
    const moldtex_intrinsic_params p = read_struct(params, "moldtex_intrinsic_params", moldtex_intrinsic_params_init);
    const double R = p.max_circumradius;
    require(std::isfinite(p.max_circumradius) && p.max_circumradius >= 0.f,
            "The intrinsic triangulation's max_circumradius must be a finite number >= 0 (0: no refinement)");
    if (p.max_insertions < 1 || p.max_insertions > kMaxIntrinsicInsertions)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "max_insertions must be between 1 and 16,000,000 (it is " +
                                                        std::to_string(p.max_insertions) + ")");
    const std::shared_ptr<const moldtex::Surface>& s = surface->surface;
    if (R > 0) {
      const double expected = s->area / (R * R);
      if (!(expected <= double(p.max_insertions))) {
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      "A circumradius bound of %g on a surface of area %g needs about %.3g vertices (area / bound^2), "
                      "more than max_insertions (%u): use a bound of at least %.3g, or raise max_insertions "
                      "(about 0.5 KB of memory per vertex)",
                      R, s->area, expected, p.max_insertions, std::sqrt(s->area / double(p.max_insertions)));
        moldtex::fail(MOLDTEX_ERROR_TOO_LARGE, buf);
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    auto h = std::make_unique<moldtex_intrinsic_t>();
    h->surface = s;
    h->T = mi::build_intrinsic_triangulation(*s);
    mi::IntrinsicTriangulation& T = h->T;
    moldtex_intrinsic_info& info = h->info;
    moldtex_intrinsic_info_init(&info);
    std::string message;
    if (R > 0) {
      mi::RefineOptions o;
      o.max_circumradius = R;
      o.max_insertions = p.max_insertions;
      const mi::RefineReport r = mi::refine(T, o);
      info.stop_reason = r.reason == mi::StopReason::Converged      ? MOLDTEX_INTRINSIC_STOP_CONVERGED
                         : r.reason == mi::StopReason::InsertionCap ? MOLDTEX_INTRINSIC_STOP_INSERTION_CAP
                                                                    : MOLDTEX_INTRINSIC_STOP_FLIP_CAP;
      info.flips = r.flips;
      info.insertions = r.insertions;
      info.boundary_splits = r.boundary_splits;
      info.given_up = r.given_up;
      info.faces_over_bound_sharp = r.skipped_small_angle;
      info.faces_over_bound_other = r.skipped_other;
      message = r.message;
    } else {
      const mi::FlipReport r = mi::flip_to_delaunay(T.mesh);
      info.flips = r.flips;
      info.stop_reason = r.capped ? MOLDTEX_INTRINSIC_STOP_FLIP_CAP : MOLDTEX_INTRINSIC_STOP_CONVERGED;
      message = r.capped ? "The Delaunay edge flips of the intrinsic triangulation did not settle (a bug or extreme "
                           "round-off; please report it)."
                         : "Intrinsic Delaunay triangulation by " + std::to_string(r.flips) +
                               " edge flips, no refinement: " + std::to_string(T.mesh.vertex_count()) + " vertices, " +
                               std::to_string(T.mesh.face_count()) + " triangles.";
    }
    const mi::IntrinsicMesh& m = T.mesh;
    info.vertex_count = m.vertex_count();
    info.triangle_count = m.face_count();
    info.edge_count = m.edge_count();
    info.input_vertex_count = T.input_vertex_count;
    info.input_triangle_count = T.input.face_count();
    info.dropped_triangle_count = T.dropped_triangles;
    info.max_circumradius = R;
    double largest = 0;
    for (uint32_t f = 0; f < m.face_count(); ++f) largest = std::max(largest, m.circumradius(f));
    info.largest_circumradius = largest;
    info.area = m.total_area();
    info.mollify_epsilon = T.mollify_epsilon;
    std::snprintf(info.message, sizeof info.message, "%s", message.c_str());
    h->face_of_triangle.assign(s->triangle_count(), mi::kInvalid);
    for (uint32_t f = 0; f < T.input_triangle.size(); ++f) h->face_of_triangle[T.input_triangle[f]] = f;
    info.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    *out = h.release();
  });
}

void moldtex_intrinsic_release(moldtex_intrinsic intrinsic) { delete intrinsic; }

moldtex_status moldtex_intrinsic_get_info(moldtex_intrinsic intrinsic, moldtex_intrinsic_info* info) {
  return guarded([&] {
    require(intrinsic != nullptr, "The intrinsic triangulation handle is NULL");
    read_struct(info, "moldtex_intrinsic_info");
    *info = intrinsic->info;
  });
}

moldtex_status moldtex_intrinsic_locate(moldtex_intrinsic intrinsic, const moldtex_surface_point* input_points,
                                        uint32_t count, moldtex_surface_point* out_points) {
  namespace mi = moldtex::intrinsic;
  return guarded([&] {
    require(intrinsic != nullptr, "The intrinsic triangulation handle is NULL");
    require_points(input_points, count, out_points, "out_intrinsic_points is NULL");
    const uint32_t nt = static_cast<uint32_t>(intrinsic->face_of_triangle.size());
    for (uint32_t i = 0; i < count; ++i) {
      const moldtex_surface_point& p = input_points[i];
      if (p.triangle >= nt)
        moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Point " + std::to_string(i) + ": triangle " +
                                                          std::to_string(p.triangle) + " is out of range (the surface has " +
                                                          std::to_string(nt) + " triangles)");
      require_weights(p, i);
      if (intrinsic->face_of_triangle[p.triangle] == mi::kInvalid)
        moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                      "Point " + std::to_string(i) + ": triangle " + std::to_string(p.triangle) +
                          " repeats a vertex index (it has no area and is not part of the intrinsic triangulation)");
    }
    std::vector<moldtex_surface_point> out(count);
    for (uint32_t i = 0; i < count; ++i) {
      mi::SurfacePoint q;
      q.face = intrinsic->face_of_triangle[input_points[i].triangle];
      q.bary = point_weights(input_points[i]);
      const mi::SurfacePoint r = mi::to_intrinsic(intrinsic->T, q);
      if (r.face >= intrinsic->T.mesh.face_count())
        moldtex::fail(MOLDTEX_ERROR_INTERNAL, "Point " + std::to_string(i) + " could not be located");
      write_point(r, r.face, &out[i]);
    }
    std::copy(out.begin(), out.end(), out_points);
  });
}

moldtex_status moldtex_intrinsic_to_input(moldtex_intrinsic intrinsic, const moldtex_surface_point* intrinsic_points,
                                          uint32_t count, moldtex_surface_point* out_points) {
  namespace mi = moldtex::intrinsic;
  return guarded([&] {
    require(intrinsic != nullptr, "The intrinsic triangulation handle is NULL");
    require_points(intrinsic_points, count, out_points, "out_input_points is NULL");
    const uint32_t nf = intrinsic->T.mesh.face_count();
    for (uint32_t i = 0; i < count; ++i) {
      if (intrinsic_points[i].triangle >= nf)
        moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
                      "Point " + std::to_string(i) + ": triangle " + std::to_string(intrinsic_points[i].triangle) +
                          " is out of range (the intrinsic triangulation has " + std::to_string(nf) + " triangles)");
      require_weights(intrinsic_points[i], i);
    }
    std::vector<moldtex_surface_point> out(count);
    for (uint32_t i = 0; i < count; ++i) {
      mi::SurfacePoint q;
      q.face = intrinsic_points[i].triangle;
      q.bary = point_weights(intrinsic_points[i]);
      const mi::SurfacePoint r = mi::to_input(intrinsic->T, q);
      if (r.face >= intrinsic->T.input_triangle.size())
        moldtex::fail(MOLDTEX_ERROR_INTERNAL, "Point " + std::to_string(i) + " could not be mapped to the input");
      write_point(r, intrinsic->T.input_triangle[r.face], &out[i]);
    }
    std::copy(out.begin(), out.end(), out_points);
  });
}

moldtex_status moldtex_intrinsic_vertex_points(moldtex_intrinsic intrinsic, moldtex_surface_point* out_points,
                                               uint32_t capacity) {
  namespace mi = moldtex::intrinsic;
  return guarded([&] {
    require(intrinsic != nullptr, "The intrinsic triangulation handle is NULL");
    require(out_points != nullptr, "out_points is NULL");
    const mi::IntrinsicTriangulation& T = intrinsic->T;
    const uint32_t nv = T.mesh.vertex_count();
    if (capacity < nv)
      moldtex::fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The output holds " + std::to_string(capacity) +
                                                        " points but the intrinsic triangulation has " +
                                                        std::to_string(nv) + " vertices");
    for (uint32_t v = 0; v < nv; ++v) {
      const mi::SurfacePoint& p = T.corr.location[v];
      if (p.face >= T.input_triangle.size()) {
        out_points[v].triangle = MOLDTEX_INTRINSIC_NO_TRIANGLE;
        out_points[v].bary[0] = out_points[v].bary[1] = out_points[v].bary[2] = 0.f;
      } else {
        write_point(p, T.input_triangle[p.face], &out_points[v]);
      }
    }
  });
}
