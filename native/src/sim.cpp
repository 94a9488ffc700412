#include "sim.h"

#include <cmath>
#include <sstream>
#include <unistd.h>
#include <vector>

#include "backends/cpu/cpu_backend.h"
#ifdef MOLDTEX_HAVE_OPENCL
#include "backends/opencl/opencl_backend.h"
#endif
#include "common/error.h"
#include "io/image_writer.h"

namespace moldtex {

namespace {

constexpr uint32_t kMinTextureSize = 8, kMaxTextureSize = 16384;
constexpr uint32_t kMaxAgents = 1u << 26;

// Bytes a simulation will hold: agents, two float fields, marks, classes, the texel ->
// triangle raster, and roughly one gutter entry per texel along the island borders.
double estimated_bytes(const moldtex_sim_config& c) {
  double texels = static_cast<double>(c.width) * c.height;
  return static_cast<double>(c.agent_count) * 20.0 + texels * (4 + 4 + 4 + 1 + 1) + texels * 0.5;
}

double physical_memory_bytes() {
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * page : 8.0 * (1ull << 30);
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

void validate_config(const moldtex_sim_config& c, const Surface&) {
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
  if (c.backend > MOLDTEX_BACKEND_OPENCL)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Unknown backend: use 0 (auto), 1 (CPU) or 2 (OpenCL)");
  if (c.agent_count == 0)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "The number of agents must be at least 1");
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

void validate_params(const moldtex_sim_params& p) {
  if (p.struct_size < sizeof(moldtex_sim_params))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "moldtex_sim_params.struct_size is too small: call moldtex_sim_params_init first");
  check_range("Movement speed", p.movement_speed, 0.f, 64.f, "the paper tested 1 to 2");
  check_range("Turn speed", p.turn_speed, 0.f, 1000.f, "the paper tested 10 to 50");
  check_range("Vision distance", p.vision_distance, 0.f, 50.f, "the paper tested 0.4 to 2");
  check_range("Vision angle", p.vision_angle, 0.f, 180.f, "in degrees; the paper tested 10 to 50");
  check_range("Evaporation rate", p.evaporation_rate, 0.f, 1000.f, "the paper tested 0.2 to 1");
  check_range("Diffusion rate", p.diffusion_rate, 0.f, 1000.f, "");
  check_range("Deposit", p.deposit, 0.f, 1.f, "");
  check_range("Time step", p.time_step, 1e-6f, 1.f, "1/60 s reproduces the paper");
  if (p.substeps < 1 || p.substeps > 64)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Substeps must be between 1 and 64");
  if (p.thread_count > 256)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Thread count must be between 0 (all cores) and 256");
}

namespace {

#ifdef MOLDTEX_HAVE_OPENCL
std::unique_ptr<Backend> make_opencl(std::shared_ptr<const Surface> surface,
                                     std::shared_ptr<const TextureDomain> domain,
                                     const moldtex_sim_config& c) {
  const std::vector<cl::Device> devices = cl::list_devices();
  for (const cl::Device& d : devices)
    if (d.platform_index == c.opencl_platform && d.device_index == c.opencl_device)
      return std::make_unique<OpenClBackend>(surface, domain, c.agent_count, d);
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
                                          const moldtex_sim_config& c, std::string& why_not) {
  try {
    for (const cl::Device& d : cl::list_devices())
      if (d.is_gpu) return std::make_unique<OpenClBackend>(surface, domain, c.agent_count, d);
    why_not = "no OpenCL GPU device";
  } catch (const Error& e) {
    why_not = e.what();
  }
  return nullptr;
}
#endif

}  // namespace

Simulation::Simulation(std::shared_ptr<const Surface> surface, const moldtex_sim_config& config,
                       const moldtex_sim_params& params)
    : surface_(std::move(surface)), config_(config), params_(params) {
  validate_config(config, *surface_);
  validate_params(params);
  {
    ThreadPool pool(params.thread_count);
    domain_ = std::make_shared<const TextureDomain>(
        build_texture_domain(*surface_, config.width, config.height, pool));
  }
  std::string why_not;
  switch (config.backend) {
    case MOLDTEX_BACKEND_OPENCL:
#ifdef MOLDTEX_HAVE_OPENCL
      backend_ = make_opencl(surface_, domain_, config);
#else
      fail(MOLDTEX_ERROR_UNAVAILABLE, "This build of Moldtex has no OpenCL support");
#endif
      break;
    case MOLDTEX_BACKEND_AUTO:
#ifdef MOLDTEX_HAVE_OPENCL
      backend_ = make_auto_opencl(surface_, domain_, config, why_not);
#else
      why_not = "this build has no OpenCL support";
#endif
      break;
    default:
      break;
  }
  if (!backend_)
    backend_ = std::make_unique<CpuBackend>(surface_, domain_, config.agent_count, params.thread_count);
  why_not_opencl_ = why_not;
  reset();
}

void Simulation::set_params(const moldtex_sim_params& params) {
  validate_params(params);
  if (params.thread_count != params_.thread_count) backend_->set_thread_count(params.thread_count);
  params_ = params;
}

void Simulation::reset() {
  backend_->reset(config_.seed);
  step_count_ = 0;
}

void Simulation::step(uint32_t steps) {
  for (uint32_t i = 0; i < steps; ++i) backend_->step(params_, config_.seed, step_count_++);
  backend_->finish();
}

void Simulation::read_rgba(float* rgba) const {
  std::vector<float> field(domain_->texel_count());
  backend_->read_pheromone(field.data());
  const auto& classes = domain_->classes;
  for (size_t i = 0; i < field.size(); ++i) {
    float v = field[i];
    rgba[4 * i] = v;
    rgba[4 * i + 1] = v;
    rgba[4 * i + 2] = v;
    rgba[4 * i + 3] = classes[i] == MOLDTEX_TEXEL_OUTSIDE ? 0.f : 1.f;  // alpha = island mask
  }
}

void Simulation::write_image(const std::string& path, moldtex_image_format format) const {
  std::vector<float> field(domain_->texel_count());
  backend_->read_pheromone(field.data());
  static const char* const kNames[] = {"Y"};
  write_image_atomically(path, ImageData{domain_->width, domain_->height, 1, field.data(), kNames}, format);
}

void Simulation::save_checkpoint(const std::string& path, const std::vector<MetricRow>& metrics) const {
  Checkpoint c;
  c.config = config_;
  c.params = params_;
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
      c.config.agent_count != config_.agent_count || c.config.seed != config_.seed)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The checkpoint " + path + " was made with another resolution, agent count or seed: "
         "bake from the start");
  const Agents& a = c.state.agents;
  if (a.triangle.size() != config_.agent_count || a.b1.size() != a.triangle.size() ||
      a.b2.size() != a.triangle.size() || a.hx.size() != a.triangle.size() ||
      a.hy.size() != a.triangle.size() || c.state.pheromone.size() != domain_->texel_count())
    fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is damaged");
  for (uint32_t t : a.triangle)
    if (t >= surface_->triangle_count()) fail(MOLDTEX_ERROR_IO, "The checkpoint " + path + " is damaged");
  c.params.thread_count = params_.thread_count;  // a machine setting, not part of the state
  validate_params(c.params);
  backend_->import_state(c.state);
  params_ = c.params;
  step_count_ = c.step_count;
  return c.metrics;
}

moldtex_sim_stats Simulation::stats() const {
  moldtex_sim_stats s{};
  s.struct_size = sizeof(s);
  s.step_count = step_count_;
  s.agent_count = static_cast<uint32_t>(backend_->agent_count());
  s.bytes_in_use = backend_->bytes() + domain_->bytes() + surface_->bytes();
  std::vector<float> field(domain_->texel_count());
  backend_->read_pheromone(field.data());
  FieldMetrics m = measure(*domain_, field.data());
  s.coverage = m.coverage;
  s.presence = m.presence;
  return s;
}

}  // namespace moldtex
