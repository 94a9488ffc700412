#include "sim.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include <sstream>
#include <unistd.h>
#include <vector>

#include "agents/continuous_rules.h"
#include "backends/cpu/cpu_backend.h"
#include "brush/brush.h"
#ifdef MOLDTEX_HAVE_OPENCL
#include "backends/opencl/opencl_backend.h"
#endif
#include "common/error.h"
#include "models/gray_scott/reaction_diffusion.h"  // validate_reaction_params, until parameters are per model
#include "models/model.h"
#include "domain/texture_detail.h"
#include "io/image_writer.h"

namespace moldtex {

namespace {

constexpr uint32_t kMinTextureSize = 8, kMaxTextureSize = 16384;
constexpr uint32_t kMaxAgents = 1u << 26;

// Bytes a simulation will hold: agents (43 bytes of state each, clocks included, held
// twice: the CPU's regrouping by tile keeps its sorted copy), two float fields, marks,
// classes, the texel -> triangle raster, the interior and sole reaches, and roughly one
// gutter entry per texel along the island borders.
double estimated_bytes(const moldtex_sim_config& c) {
  double texels = static_cast<double>(c.width) * c.height * c.detail * c.detail;
  const double planes = c.species_count;
  double bytes = static_cast<double>(c.agent_count) * 86.0 + texels * (planes * 9 + 4 + 4 + 1 + 1) + texels * 0.5;
  // The model's own (the continuous model's deposit sums and PDE operator).
  if (const Model* model = find_model(c.model)) {
    const double extra = model->extra_bytes_per_texel(c);
    if (extra > 0) bytes += texels * extra;
  }
  return bytes;
}

double physical_memory_bytes() {
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * page : 8.0 * (1ull << 30);
}

// "MoMaS" (with), "the continuous model and Gray-Scott" (without): the models with and
// without a detail above 1.
std::string models_with_detail(bool with = true) {
  return models_that([with](const Model& m) { return m.supports_detail() == with; });
}

void check_range(const char* name, float value, float lo, float hi, const char* hint) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    std::ostringstream m;
    m << name << " must be a number between " << lo << " and " << hi << " (got " << value << ")";
    if (hint && *hint) m << "; " << hint;
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, m.str());
  }
}

}  // namespace

void validate_config(const moldtex_sim_config& c, const Surface& surface) {
  const Model* model = find_model(c.model);  // null: refused below, after the checks before it
  if (c.struct_size < sizeof(moldtex_sim_config))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "moldtex_sim_config.struct_size is too small: call moldtex_sim_config_init first");
  if (c.width < kMinTextureSize || c.height < kMinTextureSize || c.width > kMaxTextureSize ||
      c.height > kMaxTextureSize) {
    std::ostringstream m;
    m << "Texture size " << c.width << " x " << c.height << " is outside " << kMinTextureSize
      << " .. " << kMaxTextureSize << " texels per side";
    fail(c.width > kMaxTextureSize || c.height > kMaxTextureSize ? MOLDTEX_ERROR_TOO_LARGE
                                                                  : MOLDTEX_ERROR_INVALID_ARGUMENT,
         m.str());
  }
  if (c.detail != 1 && c.detail != 2 && c.detail != 4)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The detail must be 1, 2 or 4 simulated texels per image texel and axis, got " + std::to_string(c.detail));
  if (c.detail > 1 && (!model || !model->supports_detail() || c.domain != MOLDTEX_DOMAIN_TEXTURE))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "A detail above 1 is for " + models_with_detail() +
                                             " on the texture domain: set detail to 1 for " +
                                             models_with_detail(false));
  if (size_t(c.width) * c.detail > kMaxTextureSize || size_t(c.height) * c.detail > kMaxTextureSize) {
    std::ostringstream m;
    m << "Texture size " << c.width << " x " << c.height << " at detail " << c.detail << " would simulate "
      << size_t(c.width) * c.detail << " x " << size_t(c.height) * c.detail << " texels, over " << kMaxTextureSize
      << " per side: lower the resolution or the detail";
    fail(MOLDTEX_ERROR_TOO_LARGE, m.str());
  }
  if (c.backend > MOLDTEX_BACKEND_OPENCL)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Unknown backend: use 0 (auto), 1 (CPU) or 2 (OpenCL)");
  if (c.agent_count == 0 && (!model || model->has_agents()))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The number of agents must be at least 1");
  if (!model) model_of(c.model);  // refuses, listing the models
  if (c.domain > MOLDTEX_DOMAIN_INTRINSIC)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Unknown domain: use 0 (texture) or 1 (intrinsic triangulation)");
  if (c.domain == MOLDTEX_DOMAIN_TEXTURE && surface.generated_uvs)
    fail(MOLDTEX_ERROR_MISSING_UVS,
         !model->runs_on(MOLDTEX_DOMAIN_INTRINSIC)
             ? "The mesh has no UV map, and " + std::string(model->name_in_text()) +
                   " keeps its pheromone in the UV texture: add a UV map (UV > Smart UV Project)"
             : std::string("The mesh has no UV map, and the Texture domain keeps the pheromone in the UV texture: add "
                           "a UV map (UV > Smart UV Project), or choose the Intrinsic domain, which runs on the surface "
                           "itself and gives a colour per mesh vertex"));
  if (!model->runs_on(c.domain))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         c.domain == MOLDTEX_DOMAIN_INTRINSIC
             ? "The Intrinsic domain runs " + models_on(MOLDTEX_DOMAIN_INTRINSIC) + "; " + model->name_in_text() +
                   " works in texels: choose the Texture domain or another model"
             : std::string(model->name_in_text()) + " runs on the Intrinsic domain only: choose it");
  if (!std::isfinite(c.intrinsic_bound) || c.intrinsic_bound < 0.f || c.intrinsic_bound > 1e30f) {
    std::ostringstream m;
    m << "The intrinsic triangulation's circumradius bound must be a length >= 0 in mesh units (0 = from the "
         "texture resolution), got "
      << c.intrinsic_bound;
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, m.str());
  }
  if (c.species_count < 1 || c.species_count > MOLDTEX_MAX_SPECIES)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The number of species must be between 1 and 4");
  if (c.seed_shape > MOLDTEX_SEED_STARBURST)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "Unknown seed shape: use 0 (random), 1 (spawn map), 2 (circle), 3 (big bang) or 4 (starburst)");
  if (c.seed_shape == MOLDTEX_SEED_SPAWN_MAP && c.fields_rgba == nullptr)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The spawn-map seed needs fields (config.fields_rgba): paint a spawn region");
  if (c.seed_shape >= MOLDTEX_SEED_CIRCLE) {
    const moldtex_surface_point& p = c.seed_center;
    if (p.triangle >= surface.triangle_count())
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The seed centre's triangle index is out of range");
    if (surface.degenerate[p.triangle])
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The seed centre lies on a zero-area triangle");
    float sum = 0;
    for (float b : p.bary) {
      if (!std::isfinite(b) || b < -1e-4f)
        fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
             "The seed centre's barycentric weights must be finite and non-negative");
      sum += b;
    }
    if (std::fabs(sum - 1.f) >= 1e-3f)
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The seed centre's barycentric weights must sum to 1");
  }
  if ((c.seed_shape == MOLDTEX_SEED_CIRCLE || c.seed_shape == MOLDTEX_SEED_STARBURST) &&
      !(std::isfinite(c.seed_radius) && c.seed_radius > 0.f && c.seed_radius < 1e30f)) {
    std::ostringstream m;
    m << "The seed radius must be a number > 0 and below 1e30 (3D units, measured on the "
         "surface), got "
      << c.seed_radius;
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, m.str());
  }
  if (c.seed_shape == MOLDTEX_SEED_STARBURST && (c.seed_rays < 1 || c.seed_rays > 1024))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The number of starburst rays must be between 1 and 1024");
  if (c.agent_count > kMaxAgents) {
    std::ostringstream m;
    m << c.agent_count << " agents is more than the limit of " << kMaxAgents;
    fail(MOLDTEX_ERROR_TOO_LARGE, m.str());
  }
  double need = estimated_bytes(c), have = physical_memory_bytes();
  if (need > 0.75 * have) {
    std::ostringstream m;
    m.precision(3);
    m << "This simulation would need about " << need / (1ull << 30) << " GiB but the machine has "
      << have / (1ull << 30) << " GiB: lower the texture resolution or the number of agents";
    fail(MOLDTEX_ERROR_TOO_LARGE, m.str());
  }
}

// The agent behaviour fields that moldtex_sim_params and moldtex_species_params share.
template <class Behaviour>
void check_behaviour(const Behaviour& p) {
  check_range("Movement speed", p.movement_speed, 0.f, 64.f, "the paper tested 1 to 2");
  check_range("Turn speed", p.turn_speed, 0.f, 1000.f, "the paper tested 10 to 50");
  check_range("Vision distance", p.vision_distance, 0.f, 50.f, "the paper tested 0.4 to 2");
  check_range("Vision angle", p.vision_angle, 0.f, 180.f, "in degrees; the paper tested 10 to 50");
  check_range("Deposit", p.deposit, 0.f, 1.f, "");
}

void validate_params(const moldtex_sim_params& p) {
  if (p.struct_size < sizeof(moldtex_sim_params))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "moldtex_sim_params.struct_size is too small: call moldtex_sim_params_init first");
  check_behaviour(p);
  check_range("Evaporation rate", p.evaporation_rate, 0.f, 1000.f, "the paper tested 0.2 to 1");
  check_range("Diffusion rate", p.diffusion_rate, 0.f, 1000.f, "");
  check_range("Time step", p.time_step, 1e-6f, 1.f, "1/60 s reproduces the paper");
  check_range("Hunger rate", p.hunger_rate, 0.f, 1000.f, "0 turns food off");
  check_range("Food radius", p.food_radius, 0.f, 1e6f, "mesh units");
  if (p.substeps < 1 || p.substeps > 64)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Substeps must be between 1 and 64");
  if (p.sensor_size > 4)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "Sensor size must be between 0 (one texel) and 4 (a 9x9 texel square)");
  if (!std::isfinite(p.length_unit) || p.length_unit < 0.f)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The length unit (pattern scale) must be a finite length >= 0 in mesh units (0 = one texel)");
  if (p.thread_count > 256)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Thread count must be between 0 (all cores) and 256");
}

// A length unit beyond the object's size would make every step cross the whole surface.
void check_length_unit(const moldtex_sim_params& p, const Surface& surface) {
  const double limit = 10.0 * std::sqrt(surface.area);
  if (p.length_unit > limit) {
    std::ostringstream m;
    m << "The length unit " << p.length_unit << " is larger than this object (10 x the square root "
      << "of its area is " << limit << " mesh units): lower the pattern scale";
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, m.str());
  }
}

void validate_species_params(const moldtex_species_params& p) {
  if (p.struct_size < sizeof(moldtex_species_params))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "moldtex_species_params.struct_size is too small: call moldtex_species_params_init first");
  check_behaviour(p);
  for (float a : p.attraction)
    check_range("Attraction", a, -1.f, 1.f, "+1 follows a trail, -1 avoids it");
}

void validate_continuous_params(const moldtex_continuous_params& p) {
  if (p.struct_size < sizeof(moldtex_continuous_params))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "moldtex_continuous_params.struct_size is too small: call moldtex_continuous_params_init first");
  check_range("Move rate", p.move_rate, 0.f, 1e6f, "mesh units per second");
  check_range("Turn rate", p.turn_rate, 0.f, 1e6f, "radians per second");
  check_range("Turn decision frequency", p.turn_frequency, 1e-6f, 1e6f, "decisions per second, > 0");
  check_range("Sensor distance", p.sensor_distance, 0.f, 1e6f, "mesh units");
  check_range("Sensor angle", p.sensor_angle, -180.f, 180.f, "degrees; negative = chemo-repulsion");
  check_range("Deposit rate", p.deposit_rate, 0.f, 1e12f, "amount per agent per second");
  check_range("Diffusion rate", p.diffusion_rate, 0.f, 1e6f, "mesh units squared per second");
  check_range("Decay rate", p.decay_rate, 0.f, 1e6f, "per second");
  check_range("Mean lifetime", p.mean_lifetime, 0.f, 1e9f, "seconds; 0 turns turnover off");
  check_range("Activation time", p.activation_time, 0.f, 1e9f, "seconds");
  check_range("Time step", p.time_step, 1e-6f, 1.f, "seconds per step");
  check_range("Bias strength", p.bias_strength, 0.f, 1e6f, "per second; 0 turns the bias off");
  if (p.bias_spawn > 1)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "bias_spawn must be 0 (uniform headings) or 1 (along the bias)");
  if (p.bias_symmetry < 1 || p.bias_symmetry > 6)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The bias symmetry must be between 1 and 6 (copies of the direction)");
  if (p.boundary > MOLDTEX_BOUNDARY_ABSORB)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Unknown boundary mode: use 0 (reflect) or 1 (absorb)");
  if (p.integrator > MOLDTEX_INTEGRATOR_BACKWARD)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "Unknown integrator: use 0 (auto), 1 (forward Euler) or 2 (backward Euler)");
}

namespace {

#ifdef MOLDTEX_HAVE_OPENCL
std::unique_ptr<Backend> make_opencl(std::shared_ptr<const Surface> surface,
                                     std::shared_ptr<const TextureDomain> domain,
                                     std::shared_ptr<const IntrinsicDomain> intrinsic, const moldtex_sim_config& c) {
  const std::vector<cl::Device> devices = cl::list_devices();
  for (const cl::Device& d : devices)
    if (d.platform_index == c.opencl_platform && d.device_index == c.opencl_device)
      return std::make_unique<OpenClBackend>(surface, domain, c.agent_count, c.species_count, d, intrinsic);
  std::ostringstream m;
  m << "There is no OpenCL device " << c.opencl_device << " on platform " << c.opencl_platform
    << "; this machine has:";
  for (size_t i = 0; i < devices.size(); ++i)
    m << (i ? ";" : "") << " device " << devices[i].device_index << " on platform "
      << devices[i].platform_index << " (" << devices[i].name << ")";
  fail(MOLDTEX_ERROR_UNAVAILABLE, m.str());
}

// Auto uses OpenCL only on a GPU: on a CPU device (PoCL) the native threads are as fast
// or faster and need no kernel compilation (docs/PERFORMANCE.md has the numbers).
std::unique_ptr<Backend> make_auto_opencl(std::shared_ptr<const Surface> surface,
                                          std::shared_ptr<const TextureDomain> domain,
                                          std::shared_ptr<const IntrinsicDomain> intrinsic,
                                          const moldtex_sim_config& c, std::string& why_not) {
  try {
    for (const cl::Device& d : cl::list_devices())
      if (d.is_gpu)
        return std::make_unique<OpenClBackend>(surface, domain, c.agent_count, c.species_count, d, intrinsic);
    why_not = "no OpenCL GPU device";
  } catch (const Error& e) {
    why_not = e.what();
  }
  return nullptr;
}
#endif

}  // namespace

std::shared_ptr<const IntrinsicDomain> prepare_intrinsic_domain(const Surface& surface, const TextureDomain& d,
                                                                const moldtex_sim_config& config, unsigned thread_count,
                                                                IntrinsicDomainCache& cache, bool* from_cache,
                                                                WorkProgress* progress) {
  // A mesh without UVs has only a placeholder atlas (a quarter of the texture in islands):
  // its default is the spacing of width * height texels spread over the surface, the
  // detail a UV layout filling the texture would give.
  const double bound = config.intrinsic_bound > 0.f ? config.intrinsic_bound
                       : surface.generated_uvs
                           ? std::sqrt(surface.area / (static_cast<double>(d.width) * d.height))
                           : default_intrinsic_bound(d);
  if (!(bound > 0))
    fail(MOLDTEX_ERROR_INVALID_MESH,
         "The texture has no island texels to derive the intrinsic triangulation's resolution from: set the "
         "circumradius bound");
  // Memory: about 800 bytes per intrinsic vertex (two copies of the mesh, the
  // correspondence, the Laplacian, the locator), Chew's refinement giving up to 1.6
  // vertices per bound^2 of area.
  const double vertices = std::max<double>(1.6 * surface.area / (bound * bound), surface.positions.size() / 3.0);
  const double need = vertices * 800.0 + estimated_bytes(config), have = physical_memory_bytes();
  if (need > 0.75 * have) {
    std::ostringstream m;
    m.precision(3);
    m << "The intrinsic triangulation at triangle size " << bound << " would need about " << need / (1ull << 30)
      << " GiB but the machine has " << have / (1ull << 30)
      << " GiB: raise the Triangle Size or lower the texture resolution";
    fail(MOLDTEX_ERROR_TOO_LARGE, m.str());
  }
  ThreadPool pool(thread_count);
  return intrinsic_domain_for(surface, d, bound, 0, pool, cache, from_cache, progress);
}

Simulation::Simulation(std::shared_ptr<const Surface> surface, const moldtex_sim_config& config,
                       const moldtex_sim_params& params, IntrinsicDomainCache& cache)
    : surface_(std::move(surface)), config_(kept_config(config)) {
  // The texture is laid out on the UV map as given; agents on the intrinsic domain walk
  // the surface in 3D, across faces whose UVs have zero area.
  const std::shared_ptr<const Surface> uv_surface = surface_;
  if (config_.domain == MOLDTEX_DOMAIN_INTRINSIC) surface_ = walkable_in_3d(surface_);
  validate_config(config_, *surface_);
  model_ = &model_of(config_.model);
  validate_params(params);
  config_.fields_rgba = nullptr;  // copied below, never kept
  settings_.species_count = config_.species_count;
  for (uint32_t k = 0; k < MTX_MAX_SPECIES; ++k) moldtex_species_params_init(&settings_.species[k], k);
  set_params(params);
  settings_.model = config.model;
  moldtex_continuous_params_init(&settings_.continuous);
  moldtex_reaction_params_init(&settings_.reaction);
  {
    ThreadPool pool(params.thread_count);
    domain_ = std::make_shared<const TextureDomain>(build_texture_domain(
        *uv_surface, config_.width * config_.detail, config_.height * config_.detail, pool));
  }
  if (config_.detail > 1) image_classes_ = image_classes(*domain_, config_.detail);
  const TextureDomain& d = *domain_;
  for (size_t i = 0; i < d.texel_count(); ++i)
    if (d.classes[i] == MOLDTEX_TEXEL_INSIDE && d.texel_triangle[i] >= 0)
      cell_area_ += d.triangle_area_scale[d.texel_triangle[i]];
  cell_area_ /= static_cast<double>(d.width) * d.height;
  std::string why_not;
  if (config_.domain == MOLDTEX_DOMAIN_INTRINSIC) {
    intrinsic_ = prepare_intrinsic_domain(*surface_, d, config_, params.thread_count, cache, &intrinsic_from_cache_);
    config_.intrinsic_bound = static_cast<float>(intrinsic_->bound);
    cell_area_ = intrinsic_->laplacian.total_area;
  }
  switch (config.backend) {
    case MOLDTEX_BACKEND_OPENCL:
#ifdef MOLDTEX_HAVE_OPENCL
      backend_ = make_opencl(surface_, domain_, intrinsic_, config_);
#else
      fail(MOLDTEX_ERROR_UNAVAILABLE, "This build of Moldtex has no OpenCL support");
#endif
      break;
    case MOLDTEX_BACKEND_AUTO:
#ifdef MOLDTEX_HAVE_OPENCL
      backend_ = make_auto_opencl(surface_, domain_, intrinsic_, config_, why_not);
#else
      why_not = "this build has no OpenCL support";
#endif
      break;
    default:
      break;
  }
  if (!backend_)
    backend_ = std::make_unique<CpuBackend>(surface_, domain_, *model_, config_.species_count,
                                            params.thread_count, intrinsic_);
  why_not_opencl_ = why_not;
  maps_ = std::make_shared<ParameterMaps>();
  settings_.maps = maps_;
  if (config.fields_rgba) set_fields(config.fields_rgba);
  reset();
}

void Simulation::set_params(const moldtex_sim_params& params) {
  validate_params(params);
  check_length_unit(params, *surface_);
  if (backend_ && params.thread_count != settings_.params.thread_count)
    backend_->set_thread_count(params.thread_count);
  settings_.params = params;
  for (moldtex_species_params& sp : settings_.species) {
    sp.movement_speed = params.movement_speed;
    sp.turn_speed = params.turn_speed;
    sp.vision_distance = params.vision_distance;
    sp.vision_angle = params.vision_angle;
    sp.deposit = params.deposit;
  }
}

void Simulation::set_species_params(uint32_t index, const moldtex_species_params& p) {
  if (index >= settings_.species_count)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The species index is out of range: the simulation has " +
                                             std::to_string(settings_.species_count) + " species");
  validate_species_params(p);
  settings_.species[index] = p;
  if (index == 0) {  // get_params reports species 0's behaviour
    settings_.params.movement_speed = p.movement_speed;
    settings_.params.turn_speed = p.turn_speed;
    settings_.params.vision_distance = p.vision_distance;
    settings_.params.vision_angle = p.vision_angle;
    settings_.params.deposit = p.deposit;
  }
}

void Simulation::set_bias(const float* vectors) {
  if (!vectors) {
    settings_.bias.clear();
    bias_3d_.clear();
    return;
  }
  const Surface& s = *surface_;
  const uint32_t n = s.triangle_count();
  std::vector<float> local(2 * static_cast<size_t>(n), 0.f);
  for (uint32_t t = 0; t < n; ++t) {
    const float* v = vectors + 3 * static_cast<size_t>(t);
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(v[k]) || std::fabs(v[k]) > 1e6f)
        fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The bias vector of triangle " + std::to_string(t) +
                                                 " is not finite or longer than 1e6");
    // Into the triangle's frame: its unit 3D x and y axes (frame3d), i.e. projected.
    const float* f = s.frame3d.data() + 9 * static_cast<size_t>(t);
    local[2 * t] = v[0] * f[3] + v[1] * f[4] + v[2] * f[5];
    local[2 * t + 1] = v[0] * f[6] + v[1] * f[7] + v[2] * f[8];
  }
  settings_.bias = std::move(local);
  bias_3d_.assign(vectors, vectors + 3 * static_cast<size_t>(n));
}

void Simulation::set_fields(const float* rgba) {
  const TextureDomain& d = *domain_;
  const size_t texels = d.texel_count();
  if (!rgba) {
    if (config_.seed_shape == MOLDTEX_SEED_SPAWN_MAP)
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
           "This simulation spawns from its spawn map: paint a spawn region instead of clearing the fields");
    fields_rgba_.clear();
    fields_only_plane_.clear();
    spawn_weights_.clear();
    free_weights_.clear();
    update_field_plane();
    return;
  }
  // Validated as given (per image texel), then spread over the domain's texels.
  const size_t given = image_texel_count();
  for (size_t i = 0; i < given; ++i) {
    const float r = rgba[4 * i], g = rgba[4 * i + 1], b = rgba[4 * i + 2];
    if (!std::isfinite(r) || !std::isfinite(g) || !std::isfinite(b) || !std::isfinite(rgba[4 * i + 3]))
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The fields contain a NaN or infinite value at texel " +
                                               std::to_string(i));
    if (r < 0.f)
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Spawn weights (red) must be >= 0");
    if (b < 0.f || b > 1.f)
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Attractor strengths (blue) must be between 0 and 1");
  }
  const float* const image = rgba;
  std::vector<float> finer;
  if (config_.detail > 1) {
    finer = finer_texels(image, config_.width, config_.height, 4, config_.detail);
    rgba = finer.data();
  }
  std::vector<uint8_t> obstacle(texels);
  for (size_t i = 0; i < texels; ++i) obstacle[i] = rgba[4 * i + 1] > 0.5f;
  std::vector<float> attract(texels);
  for (size_t i = 0; i < texels; ++i) attract[i] = rgba[4 * i + 2];
  // The gutter sees what lies across the seam (and stays a wall where painted as one).
  for (size_t g = 0; g < d.gutter_texel.size(); ++g) {
    const uint32_t t = d.gutter_texel[g], src = d.gutter_source[g];
    obstacle[t] = obstacle[t] || obstacle[src];
    attract[t] = attract[src];
  }
  std::vector<float> plane(texels);
  std::vector<double> spawn(texels, 0.0), free(texels, 0.0);
  const float attractor_scale = static_cast<float>(settings_.species_count + 1);
  bool any = false;
  double spawn_total = 0;
  for (size_t i = 0; i < texels; ++i) {
    plane[i] = obstacle[i] ? MTX_OBSTACLE_FIELD : attractor_scale * attract[i];
    any = any || plane[i] != 0.f;
    if (d.classes[i] == MOLDTEX_TEXEL_INSIDE && !obstacle[i]) {
      const double area = d.triangle_area_scale[d.texel_triangle[i]];
      free[i] = area;
      spawn[i] = area * rgba[4 * i];
      spawn_total += spawn[i];
    }
  }
  if (config_.seed_shape == MOLDTEX_SEED_SPAWN_MAP && !(spawn_total > 0))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The spawn map is empty (or lies entirely under obstacles): paint a spawn region "
         "(red channel) on the mesh");
  fields_rgba_.assign(image, image + 4 * given);
  fields_only_plane_ = any ? std::move(plane) : std::vector<float>{};
  spawn_weights_ = std::move(spawn);
  free_weights_ = std::move(free);
  update_field_plane();
}

void Simulation::update_field_plane() {
  const std::vector<float>& read = maps_->given[MOLDTEX_MAP_READ_STIMULUS];
  if (read.empty()) {
    field_plane_ = fields_only_plane_;
  } else {
    // The stimulus is sensed as the trails are, relative to U (MoMaS: to a full texel).
    field_plane_ = read;
    for (size_t i = 0; i < fields_only_plane_.size(); ++i)
      field_plane_[i] = fields_only_plane_[i] < MTX_OBSTACLE_THRESHOLD ? fields_only_plane_[i]
                                                                       : fields_only_plane_[i] + read[i];
  }
  settings_.has_fields = !field_plane_.empty();
  backend_->set_field(field_plane_);
}

void Simulation::set_map(uint32_t kind, const float* values) {
  std::vector<float> finer;  // (values validated per image texel by the C API)
  if (values && config_.detail > 1) {
    finer = finer_texels(values, config_.width, config_.height, 1, config_.detail);
    values = finer.data();
  }
  set_parameter_map(*maps_, kind, values, *surface_, *domain_);
  if (kind == MOLDTEX_MAP_READ_STIMULUS) update_field_plane();
  // Clocks start in the local steady state (§3.3): restart them for a new lifetime or
  // activation map.
  if ((kind == MOLDTEX_MAP_MEAN_LIFETIME || kind == MOLDTEX_MAP_ACTIVATION_TIME) && model_->agent_clocks()) {
    Agents agents;
    backend_->export_agents(agents);
    // Before the first step: the clocks a reset would give under these maps.
    start_lives(agents, 0, step_count_ == 0 ? 0 : 0x20000 + step_count_);
    backend_->import_agents(agents);
  }
}

void Simulation::reset() {
  if (!model_->has_agents()) {  // the planes' starting state
    ThreadPool pool(settings_.params.thread_count);
    const bool weighted = config_.seed_shape == MOLDTEX_SEED_SPAWN_MAP;
    SimState state;
    state.pheromone = model_->initial_planes(*surface_, *domain_, settings_, config_.seed,
                                             weighted ? &spawn_weights_ : nullptr, pool);
    backend_->reset(state.agents);
    backend_->import_state(state);
    batches_.clear();
    step_count_ = 0;
    time_ = 0;
    count_agents(state.agents);
    return;
  }
  SpawnSpec spec;
  spec.count = config_.agent_count;
  spec.seed = config_.seed;
  spec.species_count = config_.species_count;
  spec.shape = config_.seed_shape;
  spec.center = config_.seed_center;
  spec.radius = config_.seed_radius;
  spec.rays = config_.seed_rays;
  spec.texel_triangle = &domain_->texel_triangle;
  spec.width = domain_->width;
  spec.height = domain_->height;
  // Random spawns avoid obstacles when there are any; the spawn map is the R channel.
  bool obstacles = false;
  for (float v : field_plane_) obstacles = obstacles || v < MTX_OBSTACLE_THRESHOLD;
  if (config_.seed_shape == MOLDTEX_SEED_SPAWN_MAP)
    spec.texel_weights = &spawn_weights_;
  else if (obstacles)
    spec.texel_weights = &free_weights_;
  ThreadPool pool(settings_.params.thread_count);
  Agents agents = spawn_agents(*surface_, spec, pool);
  start_lives(agents, 0, 0);
  backend_->reset(agents);
  batches_.clear();  // brush agents and stashes go with the old agents
  step_count_ = 0;
  time_ = 0;
  count_agents(agents);
}

void Simulation::start_lives(Agents& agents, size_t begin, uint64_t stream) {
  const std::vector<float>& lifetime = maps_->given[MOLDTEX_MAP_MEAN_LIFETIME];
  const std::vector<float>& activation = maps_->given[MOLDTEX_MAP_ACTIVATION_TIME];
  if (lifetime.empty() && activation.empty()) {
    start_agent_lives(settings_.continuous, config_.seed, stream, agents, begin, agents.size());
    return;
  }
  // Each agent's clocks start in the steady state of where it stands (§3.3): its local
  // mean lifetime and activation time.
  const Surface& s = *surface_;
  for (size_t i = begin; i < agents.size(); ++i) {
    const Walker w = agents.load(i);
    const uint32_t texel = mtx_walker_texel(s.corner_uvs.data(), &w, domain_->width, domain_->height);
    moldtex_continuous_params p = settings_.continuous;
    if (!lifetime.empty() && lifetime[texel] > 0.f) p.mean_lifetime *= lifetime[texel];
    if (!activation.empty()) p.activation_time *= activation[texel];
    start_agent_life(p, mtx_rng_init(config_.seed, MTX_RNG_TURNOVER, stream, i), agents, i);
  }
}

void Simulation::count_agents(const Agents& live) {
  species_agents_ = agents_per_species(live, settings_.species_count);
  update_u_metric();
}

void Simulation::add_species_counts(const Agents& added) {
  const std::vector<double> counts = agents_per_species(added, settings_.species_count);
  species_agents_.resize(settings_.species_count, 0.0);
  for (uint32_t k = 0; k < settings_.species_count; ++k) species_agents_[k] += counts[k];
  update_u_metric();
}

void Simulation::update_u_metric() { model_->update_u_metric(settings_, species_agents_, cell_area_); }

void Simulation::set_reaction_params(const moldtex_reaction_params& p) {
  validate_reaction_params(p);
  settings_.reaction = p;
}

moldtex_sim_config kept_config(const moldtex_sim_config& config) {
  moldtex_sim_config c = config;
  // detail lies in what was the previous release's tail padding: 0 there (a caller from
  // before the field, or one that zeroed the struct) means none.
  if (c.detail == 0) c.detail = 1;
  if (const Model* model = find_model(c.model)) model->keep_config(c);
  return c;
}

void Simulation::set_continuous_params(const moldtex_continuous_params& p) {
  validate_continuous_params(p);
  const moldtex_continuous_params old = settings_.continuous;
  settings_.continuous = p;
  if (!model_->agent_clocks() || !backend_) return;
  // Turnover switched on or off, or the clocks' scales changed: restart the clocks in
  // the new steady state (ages and exposures of the old one would not match it).
  if ((old.mean_lifetime > 0.f) != (p.mean_lifetime > 0.f) || old.mean_lifetime != p.mean_lifetime ||
      old.turn_frequency != p.turn_frequency) {
    Agents agents;
    backend_->export_agents(agents);
    start_lives(agents, 0, step_count_ == 0 ? 0 : 0x10000 + step_count_);  // step 0: as a reset
    backend_->import_agents(agents);
  }
  update_u_metric();
}

namespace {

void check_batch(uint32_t batch) {
  if (batch < 1 || batch > 65535)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The brush batch must be between 1 and 65535 (0 marks the agents spawned at reset), got " +
             std::to_string(batch));
}

}  // namespace

uint32_t Simulation::paint_dab(const moldtex_brush& brush, uint32_t batch, bool erase) {
  SimState state;
  backend_->export_state(state);
  ThreadPool pool(settings_.params.thread_count);
  const uint32_t changed =
      model_->paint(*surface_, *domain_, state.pheromone.data(), brush, erase, batches_[batch].painted, pool);
  backend_->import_state(state);
  return changed;
}

void Simulation::add_agents(const moldtex_brush& brush, uint32_t count, uint32_t batch) {
  validate_brush(*surface_, brush);
  check_batch(batch);
  if (!model_->has_agents()) {  // no agents: the dab paints the planes instead (Model::paint)
    paint_dab(brush, batch, false);
    return;
  }
  if (brush.channel >= settings_.species_count)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The brush species (channel) is " + std::to_string(brush.channel) + " but the simulation has " +
             std::to_string(settings_.species_count) + " species");
  const size_t live = backend_->agent_count();
  if (live + count > kMaxAgents)
    fail(MOLDTEX_ERROR_TOO_LARGE, "Adding " + std::to_string(count) + " agents to " + std::to_string(live) +
                                      " would pass the limit of " + std::to_string(kMaxAgents) + " agents");
  if (count == 0) return;
  BrushBatch& record = batches_[batch];
  ThreadPool pool(settings_.params.thread_count);
  Agents added =
      place_disk_agents(*surface_, brush, count, config_.seed, static_cast<uint16_t>(batch), record.added, pool);
  // Brush agents start as agents in the steady state too; agent k of a batch depends
  // only on (seed, batch, k).
  for (size_t i = 0; i < added.size(); ++i)
    start_agent_life(settings_.continuous,
                     mtx_rng_init(config_.seed, MTX_RNG_TURNOVER, (uint64_t(batch) << 32) | (record.added + i), 0),
                     added, i);
  // After the live agents, without copying them where the backend keeps them in place.
  backend_->append_agents(added);
  record.added += count;
  add_species_counts(added);
}

uint32_t Simulation::erase_agents(const moldtex_brush& brush, uint32_t batch) {
  validate_brush(*surface_, brush);
  check_batch(batch);
  if (!model_->has_agents()) return paint_dab(brush, batch, true);
  // The agents read where the backend keeps them (the CPU's), or a copy (a device's): a
  // dab over a million agents then copies only the ones it erases.
  Agents exported;
  const Agents* live = backend_->agents_in_place();
  if (!live) {
    backend_->export_agents(exported);
    live = &exported;
  }
  BrushBatch& record = batches_[batch];
  const std::vector<uint8_t> remove =
      erase_mask(*surface_, brush, *live, domain_->width, domain_->height, config_.seed,
                 static_cast<uint16_t>(batch), record.erase_dabs++);
  size_t removed = 0;
  for (uint8_t r : remove) removed += r;
  if (removed == 0) return 0;
  const size_t stashed = record.erased.size();
  try {
    record.erased.resize(stashed + removed);
    for (size_t i = 0, e = stashed; i < live->size(); ++i)
      if (remove[i]) record.erased.copy_from(e++, *live, i);
    backend_->remove_agents(remove, exported);
  } catch (...) {
    record.erased.resize(stashed);  // the agents are still live
    throw;
  }
  count_agents(*live);  // (the backend's own or the copy, dropped from either way)
  return static_cast<uint32_t>(removed);
}

void Simulation::undo_agents(uint32_t batch) {
  check_batch(batch);
  auto it = batches_.find(batch);
  if (!model_->has_agents()) {
    if (it == batches_.end()) return;
    SimState state;
    backend_->export_state(state);
    ThreadPool pool(settings_.params.thread_count);
    model_->unpaint(*domain_, state.pheromone.data(), it->second.painted, pool);
    backend_->import_state(state);
    batches_.erase(it);
    return;
  }
  // The stroke's agents leave and the ones it erased come back after the rest, without
  // copying the rest where the backend keeps them in place (the CPU's).
  Agents exported;
  const Agents* live = backend_->agents_in_place();
  if (!live) {
    backend_->export_agents(exported);
    live = &exported;
  }
  std::vector<uint8_t> drop(live->size(), 0);
  size_t keep = 0;
  for (size_t i = 0; i < drop.size(); ++i) {
    drop[i] = live->batch[i] == batch;
    keep += !drop[i];
  }
  const size_t restore = it == batches_.end() ? 0 : it->second.erased.size();
  if (keep + restore > kMaxAgents)
    fail(MOLDTEX_ERROR_TOO_LARGE, "Undoing this stroke would pass the limit of " + std::to_string(kMaxAgents) +
                                      " agents");
  if (keep != live->size() || restore > 0) {
    if (!backend_->agents_in_place()) {  // a device: one import of the whole result
      exported.remove_marked(drop);
      if (restore > 0) exported.append(it->second.erased);
      backend_->import_agents(exported);
    } else {
      if (restore > 0) backend_->append_agents(it->second.erased);  // (first: it may throw)
      drop.resize(live->size(), 0);  // the restored agents stay
      backend_->remove_agents(drop, exported);
    }
    count_agents(*live);
  }
  if (it != batches_.end()) batches_.erase(it);
}

void Simulation::set_food(const moldtex_food_source* sources, uint32_t count) {
  if (count > MTX_MAX_FOOD)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "At most " + std::to_string(MTX_MAX_FOOD) +
                                             " food sources are supported, got " + std::to_string(count));
  if (count > 0 && !sources) fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The food sources are NULL");
  for (uint32_t j = 0; j < count; ++j) {
    const moldtex_food_source& f = sources[j];
    for (float v : {f.position[0], f.position[1], f.position[2], f.strength, f.amount})
      if (!std::isfinite(v))
        fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
             "Food source " + std::to_string(j) + " has a NaN or infinite value");
    if (f.strength < 0.f)
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
           "Food source " + std::to_string(j) + " has a negative strength: it must be >= 0");
  }
  food_.assign(sources, sources + count);
}

void Simulation::step(uint32_t steps) {
  std::vector<uint32_t> active;  // indices into food_ of sources with food left
  std::vector<uint32_t> eaters(MTX_MAX_FOOD, 0);
  for (uint32_t i = 0; i < steps; ++i) {
    settings_.food.clear();
    active.clear();
    if (settings_.params.hunger_rate > 0.f)
      for (uint32_t j = 0; j < food_.size(); ++j)
        if (food_[j].amount != 0.f) {
          active.push_back(j);
          const moldtex_food_source& f = food_[j];
          settings_.food.insert(settings_.food.end(), {f.position[0], f.position[1], f.position[2], f.strength});
        }
    backend_->step(settings_, config_.seed, step_count_++, eaters.data());
    time_ += model_->time_step(settings_);
    // Depletion from exact counts, after the agent pass: the same on every backend.
    for (size_t a = 0; a < active.size(); ++a) {
      moldtex_food_source& f = food_[active[a]];
      if (f.amount > 0.f) f.amount = std::max(0.f, f.amount - static_cast<float>(eaters[a]));
    }
  }
  backend_->finish();
}

std::vector<float> Simulation::read_field() const {
  std::vector<float> field(domain_->texel_count() * settings_.species_count);
  backend_->read_pheromone(field.data());
  return field;
}

std::vector<float> Simulation::read_display_field() const { return display_field(read_field()); }

std::vector<float> Simulation::display_field(std::vector<float> field, size_t cells) const {
  model_->display(field, cells ? cells : domain_->texel_count(), settings_);
  return field;
}

namespace {

// RGBA of `cells` cells from `planes` species planes of a displayed field (the encoding
// moldtex_sim_read_rgba documents): one species grey with alpha = mask(i); 2 to 4 species
// one channel each, alpha = mask(i) while fewer than 4.
template <class Mask>
void encode_rgba(const std::vector<float>& field, size_t cells, uint32_t planes, Mask mask, float* rgba) {
  for (size_t i = 0; i < cells; ++i) {
    float* out = rgba + 4 * i;
    if (planes == 1) {
      out[0] = out[1] = out[2] = field[i];
      out[3] = mask(i);
    } else {
      for (uint32_t k = 0; k < 4; ++k) out[k] = k < planes ? field[k * cells + i] : 0.f;
      if (planes < 4) out[3] = mask(i);
    }
  }
}

}  // namespace

void Simulation::read_rgba(float* rgba) const {
  const std::vector<uint8_t>& classes = image_texel_classes();
  encode_rgba(image_field(), image_texel_count(), settings_.species_count,
              [&](size_t i) { return classes[i] == MOLDTEX_TEXEL_OUTSIDE ? 0.f : 1.f; },  // the island mask
              rgba);
}

std::vector<float> Simulation::image_field() const {
  std::vector<float> field = read_display_field();
  if (config_.detail == 1) return field;
  return image_planes(field, settings_.species_count, *domain_, config_.detail);
}

void Simulation::read_texel_classes(uint8_t* classes) const {
  const std::vector<uint8_t>& image = image_texel_classes();
  std::copy(image.begin(), image.end(), classes);
}

void Simulation::read_map(uint32_t kind, float* values) const {
  const std::vector<float>& m = maps_->given[kind];
  const uint32_t k = config_.detail, fine_width = domain_->width;
  // At detail above 1 each image texel reads its first fine texel: the value given there.
  for (size_t y = 0; y < config_.height; ++y)
    for (size_t x = 0; x < config_.width; ++x) values[y * config_.width + x] = m[(y * k) * fine_width + x * k];
}

void Simulation::write_image(const std::string& path, moldtex_image_format format) const {
  const size_t texels = image_texel_count();
  const uint32_t planes = settings_.species_count;
  const std::vector<float> field = image_field();
  static const char* const kOne[] = {"Y"};
  static const char* const kMany[] = {"R", "G", "B", "A"};
  std::vector<float> interleaved(texels * planes);
  for (size_t i = 0; i < texels; ++i)
    for (uint32_t k = 0; k < planes; ++k) interleaved[i * planes + k] = field[k * texels + i];
  write_image_atomically(path,
                         ImageData{config_.width, config_.height, planes, interleaved.data(),
                                   planes == 1 ? kOne : kMany},
                         format);
}

void Simulation::save_checkpoint(const std::string& path, const std::vector<MetricRow>& metrics) const {
  Checkpoint c;
  c.config = config_;
  c.config.fields_rgba = nullptr;
  c.params = settings_.params;
  c.continuous = settings_.continuous;
  c.reaction = settings_.reaction;
  c.time = time_;
  c.species.assign(settings_.species, settings_.species + MTX_MAX_SPECIES);
  c.fields_rgba = fields_rgba_;
  c.food = food_;
  c.bias = bias_3d_;
  for (uint32_t k = 0; k < MOLDTEX_MAP_COUNT; ++k)
    if (!maps_->given[k].empty()) {
      c.map_kinds.push_back(k);
      c.maps.insert(c.maps.end(), maps_->given[k].begin(), maps_->given[k].end());
    }
  c.surface_fingerprint = surface_->fingerprint;
  c.step_count = step_count_;
  c.metrics = metrics;
  backend_->export_state(c.state);
  moldtex::save_checkpoint(path, c);
}

std::vector<MetricRow> Simulation::load_checkpoint(const std::string& path) {
  Checkpoint c = moldtex::load_checkpoint(path);
  if (c.surface_fingerprint != surface_->fingerprint)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The checkpoint " + path + " was made on a different mesh or UV map: bake from the start");
  if (c.config.width != config_.width || c.config.height != config_.height ||
      c.config.agent_count != config_.agent_count || c.config.seed != config_.seed ||
      c.config.species_count != config_.species_count || c.config.model != config_.model ||
      c.config.domain != config_.domain || c.config.intrinsic_bound != config_.intrinsic_bound ||
      kept_config(c.config).detail != config_.detail)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The checkpoint " + path + " was made with another resolution, detail, agent count, seed, "
         "number of species, model, domain or triangle size: bake from the start");
  const Agents& a = c.state.agents;
  const uint32_t planes = config_.species_count;
  // The agent count may differ from the config's: slime brushes add and erase agents.
  if (a.triangle.size() > kMaxAgents || a.b1.size() != a.triangle.size() ||
      a.b2.size() != a.triangle.size() || a.hx.size() != a.triangle.size() ||
      a.hy.size() != a.triangle.size() || a.species.size() != a.triangle.size() ||
      a.hunger.size() != a.triangle.size() || a.clock.size() != a.triangle.size() ||
      a.age.size() != a.triangle.size() || a.exposure.size() != a.triangle.size() ||
      a.threshold.size() != a.triangle.size() || c.food.size() > MTX_MAX_FOOD ||
      c.state.pheromone.size() != domain_->texel_count() * planes ||
      c.state.cells.size() != (intrinsic_ ? size_t(intrinsic_->vertex_count()) * planes : 0) ||
      c.species.size() != MTX_MAX_SPECIES ||
      (!c.fields_rgba.empty() && c.fields_rgba.size() != image_texel_count() * 4) ||
      (!c.bias.empty() && c.bias.size() != static_cast<size_t>(surface_->triangle_count()) * 3) ||
      c.map_kinds.size() > MOLDTEX_MAP_COUNT || c.maps.size() != c.map_kinds.size() * domain_->texel_count())
    fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is damaged");
  // The maps: validated into a new set, taken below once nothing can refuse any more.
  auto maps = std::make_shared<ParameterMaps>();
  for (size_t j = 0; j < c.map_kinds.size(); ++j) {
    try {
      set_parameter_map(*maps, c.map_kinds[j], c.maps.data() + j * domain_->texel_count(), *surface_, *domain_);
    } catch (const Error& e) {
      fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is damaged: " + e.what());
    }
  }
  validate_checkpoint_values(c, path, surface_->triangle_count(), planes);
  c.params.thread_count = settings_.params.thread_count;  // a machine setting, not part of the state
  validate_params(c.params);
  check_length_unit(c.params, *surface_);
  validate_continuous_params(c.continuous);
  validate_reaction_params(c.reaction);
  for (uint32_t k = 0; k < MTX_MAX_SPECIES; ++k) validate_species_params(c.species[k]);
  {
    const std::vector<moldtex_food_source> keep = food_;
    set_food(c.food.data(), static_cast<uint32_t>(c.food.size()));  // validates
    food_ = keep;  // the state is taken below, once nothing can refuse any more
  }
  // The bias and the fields first (either may refuse; then both are as they were), then
  // the state.
  const std::vector<float> bias_before = bias_3d_;
  set_bias(c.bias.empty() ? nullptr : c.bias.data());
  const moldtex_sim_config saved = config_;
  config_.seed_shape = MOLDTEX_SEED_RANDOM;  // the spawn already happened
  try {
    set_fields(c.fields_rgba.empty() ? nullptr : c.fields_rgba.data());
  } catch (...) {
    config_ = saved;
    set_bias(bias_before.empty() ? nullptr : bias_before.data());
    throw;
  }
  config_ = saved;
  maps->version = maps_->version + 1;
  maps_ = maps;
  settings_.maps = maps_;
  update_field_plane();
  c.state.agents.batch.assign(c.state.agents.size(), 0);  // brush batches are not saved
  backend_->import_state(c.state);
  batches_.clear();
  settings_.params = c.params;
  settings_.continuous = c.continuous;
  settings_.reaction = c.reaction;
  for (uint32_t k = 0; k < MTX_MAX_SPECIES; ++k) settings_.species[k] = c.species[k];
  food_ = c.food;
  step_count_ = c.step_count;
  time_ = c.time;
  count_agents(c.state.agents);
  return c.metrics;
}

moldtex_sim_stats Simulation::stats() const {
  moldtex_sim_stats s{};
  s.struct_size = sizeof(s);
  s.step_count = step_count_;
  s.agent_count = static_cast<uint32_t>(backend_->agent_count());
  s.bytes_in_use = backend_->bytes() + domain_->bytes() + surface_->bytes();
  const std::vector<float> raw = read_field();
  s.time = time_;
  model_->stats(s, *domain_, raw, display_field(raw), settings_);
  return s;
}

moldtex_domain_info Simulation::domain_info() const {
  moldtex_domain_info info{};
  info.struct_size = sizeof(info);
  info.domain = config_.domain;
  if (!intrinsic_) {
    for (uint8_t c : domain_->classes) info.cell_count += c == MOLDTEX_TEXEL_INSIDE;
    return info;
  }
  const IntrinsicDomain& d = *intrinsic_;
  info.cell_count = d.vertex_count();
  info.face_count = d.face_count();
  info.bound = d.bound;
  info.build_seconds = d.build_seconds;
  info.insertions = d.report.insertions + d.report.boundary_splits;
  info.skipped_faces = d.report.skipped_small_angle + d.report.skipped_other;
  info.from_cache = intrinsic_from_cache_ ? 1u : 0u;
  return info;
}

namespace {
const IntrinsicDomain& require_intrinsic(const IntrinsicDomain* d) {
  if (!d) fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "This simulation runs on the texture domain: it has no intrinsic vertices");
  return *d;
}
void require_count(uint32_t given, uint32_t expected, const char* what) {
  if (given != expected)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, std::string("The ") + what + " count must be " + std::to_string(expected) +
                                             " (moldtex_domain_info), got " + std::to_string(given));
}
}  // namespace

void Simulation::read_intrinsic_vertices(float* xyz_area, float* values, uint32_t count) const {
  const IntrinsicDomain& d = require_intrinsic(intrinsic_.get());
  require_count(count, d.vertex_count(), "vertex");
  if (xyz_area)
    for (uint32_t v = 0; v < count; ++v) {
      const intrinsic::SurfacePoint& p = d.vertex_location(v);
      const auto x = p.face == intrinsic::kInvalid ? std::array<double, 3>{0, 0, 0} : intrinsic::input_position(d.tri, p);
      for (int k = 0; k < 3; ++k) xyz_area[4ull * v + k] = static_cast<float>(x[k]);
      xyz_area[4ull * v + 3] = d.laplacian.area[v];
    }
  if (values) {
    const std::vector<float> cells = backend_->read_cells();
    if (cells.size() != size_t(count) * settings_.species_count)
      fail(MOLDTEX_ERROR_INTERNAL, "The backend holds no vertex values");
    std::copy(cells.begin(), cells.end(), values);
  }
}

void Simulation::read_vertex_rgba(float* rgba) const {
  const IntrinsicDomain& d = require_intrinsic(intrinsic_.get());
  const uint32_t planes = settings_.species_count, cells = d.vertex_count();
  const uint32_t inputs = surface_->vertex_count();
  if (d.tri.input_vertex_count != inputs || cells < inputs)
    fail(MOLDTEX_ERROR_INTERNAL, "The intrinsic triangulation does not start with the mesh's vertices");
  const std::vector<float> values = backend_->read_cells();
  if (values.size() != size_t(cells) * planes) fail(MOLDTEX_ERROR_INTERNAL, "The backend holds no vertex values");
  // Input vertex i is intrinsic vertex i of the triangulation's own numbering; a vertex no
  // triangle uses shows 0 with alpha 0.
  std::vector<uint8_t> used(inputs);
  std::vector<float> field(size_t(inputs) * planes, 0.f);
  for (uint32_t i = 0; i < inputs; ++i) {
    const uint32_t v = d.vertex_rank[i];
    used[i] = d.vertex_location(v).face != intrinsic::kInvalid;
    for (uint32_t k = 0; k < planes && used[i]; ++k) field[size_t(k) * inputs + i] = values[size_t(k) * cells + v];
  }
  encode_rgba(display_field(std::move(field), inputs), inputs, planes,
              [&](size_t i) { return used[i] ? 1.f : 0.f; }, rgba);
}

void Simulation::read_intrinsic_faces(uint32_t* corners, uint32_t count) const {
  const IntrinsicDomain& d = require_intrinsic(intrinsic_.get());
  require_count(count, d.face_count(), "face");
  std::copy(d.face_vertices.begin(), d.face_vertices.end(), corners);
}

}  // namespace moldtex
