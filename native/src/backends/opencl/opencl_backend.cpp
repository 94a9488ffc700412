#include "backends/opencl/opencl_backend.h"

#include "models/gray_scott/reaction_diffusion.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "agents/agents.h"
#include "agents/continuous_rules.h"
#include "agents/parameter_maps.h"
#include "agents/momas_rules.h"
#include "common/error.h"
#include "models/gray_scott/reaction_diffusion.h"

namespace moldtex {

namespace cl {
const std::string& program_source();  // generated from shared/*.h and kernels.cl
}

namespace {

void check(cl_int err, const char* what) {
  if (err == CL_SUCCESS) return;
  const bool memory = err == CL_MEM_OBJECT_ALLOCATION_FAILURE || err == CL_OUT_OF_RESOURCES ||
                      err == CL_OUT_OF_HOST_MEMORY || err == CL_INVALID_BUFFER_SIZE;
  if (memory)
    fail(MOLDTEX_ERROR_OUT_OF_MEMORY,
         std::string("The OpenCL device ran out of memory while ") + what + " (" +
             cl::error_name(err) +
             "): lower the texture resolution or the number of agents, or use the CPU backend");
  fail(MOLDTEX_ERROR_UNAVAILABLE, std::string("OpenCL failed while ") + what + ": " + cl::error_name(err));
}

// Builds the program (shared/*.h and kernels.cl) with the given -D options.
cl_program build_program(const cl::Runtime& r, cl_context context, const cl::Device& device,
                         const std::string& defines) {
  cl_int err = CL_SUCCESS;
  const char* source = cl::program_source().c_str();
  cl_program program = r.clCreateProgramWithSource(context, 1, &source, nullptr, &err);
  check(err, "loading the kernels");
  const std::string options = "-cl-std=CL1.2 " + defines;
  err = r.clBuildProgram(program, 1, &device.device, options.c_str(), nullptr, nullptr);
  if (err != CL_SUCCESS) {
    size_t size = 0;
    r.clGetProgramBuildInfo(program, device.device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
    std::string log(size, '\0');
    r.clGetProgramBuildInfo(program, device.device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
    r.clReleaseProgram(program);
    if (log.size() > 2000) log.resize(2000);
    fail(MOLDTEX_ERROR_UNAVAILABLE, "The OpenCL kernels did not build on " + device.name + " (" +
                                        cl::error_name(err) + "): " + log);
  }
  return program;
}

}  // namespace

struct OpenClBackend::State {
  const cl::Runtime& r = cl::runtime();
  cl_context context = nullptr;
  cl_command_queue queue = nullptr;
  // The agent kernel is specialised (shared/momas.h): one program per combination of
  // food with hunger on/off and fields on/off, index (food ? 1 : 0) | (fields ? 2 : 0),
  // each built on first use. The other kernels come from the first program built.
  cl_program programs[4] = {};
  cl_kernel agent_kernels[4] = {};
  // The continuous model's agent kernel, fields off / on (programs 0 / 2), its deposit
  // conversion and the PDE's forward-Euler sub-step.
  cl_kernel continuous_kernels[2] = {};
  cl_kernel convert_kernel = nullptr, pde_kernel = nullptr, fine_start_kernel = nullptr,
            fine_diffuse_kernel = nullptr, coarse_diffuse_kernel = nullptr, fine_finish_kernel = nullptr,
            write_kernel = nullptr, scale_kernel = nullptr;
  cl_kernel gray_scott_kernel = nullptr;  // Gray-Scott's sub-step (shared/reaction.h)
  cl_mem rate = nullptr;                  // and the Laplacian's rate per row
  // Gray-Scott's feed and kill maps as of reaction_version (4-byte placeholders without).
  cl_mem feed_map = nullptr, kill_map = nullptr;
  const void* reaction_source = nullptr;
  uint64_t reaction_version = 0;
  cl_kernel deposit_kernel = nullptr, gutter_kernel = nullptr, diffuse_kernel = nullptr;
  // Surface units (see domain/surface_diffusion.h).
  cl_kernel surface_kernel = nullptr, seam_kernel = nullptr, fine_kernel = nullptr,
            scatter_kernel = nullptr;
  // Surface and layout tables (read-only).
  cl_mem frames = nullptr, adjacency = nullptr, corner_uvs = nullptr, classes = nullptr,
         gutter_texel = nullptr, gutter_source = nullptr, frame3d = nullptr,
         texels_per_unit = nullptr, texel_triangle = nullptr, island = nullptr,
         seam_texel = nullptr, seam_neighbour = nullptr;
  // The diffusion plan on the device (remade when the mix or the length unit changes).
  cl_mem coef = nullptr, fine_texel = nullptr, fine_neighbour = nullptr, fine_coef = nullptr,
         fine_extra = nullptr, fine_scratch = nullptr;
  size_t plan_bytes = 0;
  // Food sources (MTX_MAX_FOOD x 4 floats) and their eater counters.
  cl_mem food = nullptr, eaters = nullptr;
  // State.
  cl_mem triangle = nullptr, b1 = nullptr, b2 = nullptr, hx = nullptr, hy = nullptr,
         species = nullptr, hunger = nullptr, lives = nullptr;
  // Continuous model tables (made at its first step).
  cl_mem bias = nullptr;  // the continuous model's bias field (2 per triangle)
  std::vector<float> bias_uploaded;
  // Parameter maps (agent planes, spawn weights and alias table, write stimulus), as of
  // maps_version; 4-byte placeholders where a map is not set.
  cl_mem map_planes = nullptr, spawn_max = nullptr, spawn_prob = nullptr, spawn_index = nullptr,
         write = nullptr, decay = nullptr;
  const void* maps_source = nullptr;
  uint64_t maps_version = 0;
  size_t maps_bytes = 0;
  cl_mem texel_island = nullptr, interior_bits = nullptr, interior_reach = nullptr, unfolded = nullptr, sums = nullptr, alias_prob = nullptr, alias_index = nullptr, rows = nullptr,
         row_start = nullptr, col = nullptr, weight = nullptr, area = nullptr;
  // Local time stepping: the plan's lists (remade when r_dif dt changes) and the fine
  // cells' values and compact inflows.
  cl_mem step_class = nullptr, flux_link = nullptr, fine_cell = nullptr, fine_start = nullptr,
         fine_nbr = nullptr, fine_area = nullptr, fine_weight = nullptr, fine_cur = nullptr,
         fine_next = nullptr, fine_flux = nullptr;
  double local_rdt = -1;
  cl_mem pheromone = nullptr, scratch = nullptr, marks = nullptr, field = nullptr;
  // The intrinsic domain's cells and locator (4-byte placeholders on the texture domain).
  cl_mem face_vertices = nullptr, locator_grid = nullptr, locator_cells = nullptr, locator_face = nullptr,
         locator_map = nullptr, locator_next = nullptr, locator_across = nullptr, cells_per_unit = nullptr;
  // Its lattice (domain/intrinsic_lattice.h), the node values and deposit sums of every
  // plane, and the static field at the nodes.
  cl_mem lattice_grid = nullptr, lattice_vertex = nullptr, lattice_weight = nullptr, node_values = nullptr,
         node_sums = nullptr, node_field = nullptr;
  cl_kernel gather_kernel = nullptr, lattice_scatter_kernel = nullptr;

  ~State() {
    for (cl_mem m : {frames, adjacency, corner_uvs, classes, gutter_texel, gutter_source, frame3d,
                     food, eaters, triangle, b1, b2, hx, hy, species, hunger, lives, pheromone,
                     scratch, marks, field, texels_per_unit, texel_triangle, island, seam_texel,
                     seam_neighbour, bias, texel_island, interior_bits, interior_reach, unfolded, sums, alias_prob, alias_index, rows, row_start, col, weight,
                     area, step_class, flux_link, fine_cell, fine_start, fine_nbr, fine_area, fine_weight, fine_cur, fine_next, fine_flux, map_planes,
                     spawn_max, spawn_prob, spawn_index, write, decay, rate, feed_map, kill_map, face_vertices,
                     locator_grid, locator_cells, locator_face, locator_map, locator_next, locator_across,
                     cells_per_unit, lattice_grid, lattice_vertex, lattice_weight, node_values, node_sums,
                     node_field})
      if (m) r.clReleaseMemObject(m);
    release_plan();
    for (cl_kernel k : agent_kernels)
      if (k) r.clReleaseKernel(k);
    for (cl_kernel k : continuous_kernels)
      if (k) r.clReleaseKernel(k);
    for (cl_kernel k : {convert_kernel, pde_kernel, fine_start_kernel, fine_diffuse_kernel, coarse_diffuse_kernel,
                        fine_finish_kernel, write_kernel, scale_kernel, gray_scott_kernel, gather_kernel, lattice_scatter_kernel})
      if (k) r.clReleaseKernel(k);
    for (cl_kernel k : {deposit_kernel, gutter_kernel, diffuse_kernel, surface_kernel, seam_kernel,
                        fine_kernel, scatter_kernel})
      if (k) r.clReleaseKernel(k);
    for (cl_program p : programs)
      if (p) r.clReleaseProgram(p);
    if (queue) r.clReleaseCommandQueue(queue);
    if (context) r.clReleaseContext(context);
  }

  void release_plan() {
    for (cl_mem* m : {&coef, &fine_texel, &fine_neighbour, &fine_coef, &fine_extra, &fine_scratch})
      if (*m) {
        r.clReleaseMemObject(*m);
        *m = nullptr;
      }
  }

  cl_mem buffer(size_t bytes, const void* data, size_t& total) {
    cl_int err = CL_SUCCESS;
    bytes = std::max<size_t>(bytes, 4);  // zero-sized buffers are invalid
    cl_mem m = r.clCreateBuffer(context, CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0),
                                bytes, const_cast<void*>(data), &err);
    check(err, "allocating device memory");
    total += bytes;
    return m;
  }

  template <class T>
  void arg(cl_kernel k, cl_uint index, const T& value) {
    check(r.clSetKernelArg(k, index, sizeof(T), &value), "setting a kernel argument");
  }

  // Sets all of kernel k's arguments, in order.
  template <class... T>
  void args(cl_kernel k, const T&... values) {
    cl_uint index = 0;
    (arg(k, index++, values), ...);
  }

  void run(cl_kernel k, size_t global0, size_t global1 = 0) {
    if (global0 == 0) return;
    size_t global[2] = {global0, global1};
    check(r.clEnqueueNDRangeKernel(queue, k, global1 ? 2 : 1, nullptr, global, nullptr, 0, nullptr,
                                   nullptr),
          "launching a kernel");
  }
};

OpenClBackend::OpenClBackend(std::shared_ptr<const Surface> surface,
                             std::shared_ptr<const TextureDomain> domain, uint32_t agent_count,
                             uint32_t species_count, const cl::Device& device,
                             std::shared_ptr<const IntrinsicDomain> intrinsic)
    : surface_(std::move(surface)),
      domain_(std::move(domain)),
      intrinsic_(std::move(intrinsic)),
      agent_count_(agent_count),
      species_count_(species_count),
      device_(device),
      state_(std::make_unique<State>()) {
  State& s = *state_;
  const cl::Runtime& r = s.r;
  if (!r.loaded) fail(MOLDTEX_ERROR_UNAVAILABLE, r.error);
  cl_int err = CL_SUCCESS;
  cl_context_properties props[] = {CL_CONTEXT_PLATFORM,
                                   reinterpret_cast<cl_context_properties>(device.platform), 0};
  s.context = r.clCreateContext(props, 1, &device_.device, nullptr, nullptr, &err);
  check(err, "creating a context");
  s.queue = r.clCreateCommandQueue(s.context, device_.device, 0, &err);
  check(err, "creating a command queue");

  // The variant a new simulation runs (no food, no fields) now, so that a build failure
  // shows here; the others when first needed.
  agent_kernel(false, false);
  s.deposit_kernel = r.clCreateKernel(s.programs[0], "apply_deposits", &err);
  check(err, "creating the deposit kernel");
  s.gutter_kernel = r.clCreateKernel(s.programs[0], "fill_gutter", &err);
  check(err, "creating the gutter kernel");
  s.diffuse_kernel = r.clCreateKernel(s.programs[0], "diffuse_evaporate", &err);
  check(err, "creating the diffusion kernel");
  s.surface_kernel = r.clCreateKernel(s.programs[0], "surface_diffuse", &err);
  check(err, "creating the surface diffusion kernel");
  s.seam_kernel = r.clCreateKernel(s.programs[0], "seam_diffuse", &err);
  check(err, "creating the seam diffusion kernel");
  s.fine_kernel = r.clCreateKernel(s.programs[0], "fine_diffuse", &err);
  check(err, "creating the fine diffusion kernel");
  s.scatter_kernel = r.clCreateKernel(s.programs[0], "fine_scatter", &err);
  check(err, "creating the fine diffusion kernel");

  // Refuse up front what cannot fit, with the numbers, rather than failing mid-step.
  const Surface& sf = *surface_;
  const TextureDomain& d = *domain_;
  const size_t texels = d.texel_count();
  cells_ = intrinsic_ ? intrinsic_->vertex_count() : texels;
  // (The intrinsic domain: its tables, and the lattice's values and sums per plane and field.)
  const double need = (intrinsic_ ? static_cast<double>(intrinsic_->bytes()) +
                                        intrinsic_->lattice.node_count() * (8.0 * species_count_ + 4.0)
                                  : 0.0) +
                      agent_count_ * 41.0 + sf.frame3d.size() * 4.0 + texels * (9.0 * species_count_ + 5.0) + sf.frames.size() * sizeof(mtx_frame) +
                      sf.adjacency.size() * 4.0 + sf.unfolded.size() * 4.0 + sf.corner_uvs.size() * 4.0 + d.gutter_texel.size() * 8.0 +
                      texels * 4.0 + d.texels_per_unit.size() * 4.0 + sf.island.size() * 4.0 +
                      d.seam_texel.size() * 20.0;
  if (device_.global_memory && need > 0.9 * static_cast<double>(device_.global_memory))
    fail(MOLDTEX_ERROR_OUT_OF_MEMORY,
         "The simulation needs about " + std::to_string(static_cast<long long>(need / (1 << 20))) +
             " MiB but " + device_.name + " has " +
             std::to_string(static_cast<long long>(device_.global_memory >> 20)) +
             " MiB: lower the texture resolution or the number of agents, or use the CPU backend");

  s.frames = s.buffer(sf.frames.size() * sizeof(mtx_frame), sf.frames.data(), device_bytes_);
  s.adjacency = s.buffer(sf.adjacency.size() * 4, sf.adjacency.data(), device_bytes_);
  s.corner_uvs = s.buffer(sf.corner_uvs.size() * 4, sf.corner_uvs.data(), device_bytes_);
  s.classes = s.buffer(texels, d.classes.data(), device_bytes_);
  s.gutter_texel = s.buffer(d.gutter_texel.size() * 4, d.gutter_texel.data(), device_bytes_);
  s.gutter_source = s.buffer(d.gutter_source.size() * 4, d.gutter_source.data(), device_bytes_);
  reserve_agents(agent_count_);
  s.frame3d = s.buffer(sf.frame3d.size() * 4, sf.frame3d.data(), device_bytes_);
  s.texels_per_unit = s.buffer(d.texels_per_unit.size() * 4, d.texels_per_unit.data(), device_bytes_);
  s.texel_triangle = s.buffer(texels * 4, d.texel_triangle.data(), device_bytes_);
  s.texel_island = s.buffer(texels * 4, d.texel_island.data(), device_bytes_);
  s.interior_reach = s.buffer(texels, d.interior_reach.data(), device_bytes_);
  s.unfolded = s.buffer(sf.unfolded.size() * 4, sf.unfolded.data(), device_bytes_);
  s.island = s.buffer(sf.island.size() * 4, sf.island.data(), device_bytes_);
  s.seam_texel = s.buffer(d.seam_texel.size() * 4, d.seam_texel.empty() ? nullptr : d.seam_texel.data(), device_bytes_);
  s.seam_neighbour = s.buffer(d.seam_neighbour.size() * 4,
                              d.seam_neighbour.empty() ? nullptr : d.seam_neighbour.data(), device_bytes_);
  s.food = s.buffer(MTX_MAX_FOOD * 4 * 4, nullptr, device_bytes_);
  s.eaters = s.buffer(MTX_MAX_FOOD * 4, nullptr, device_bytes_);
  s.pheromone = s.buffer(cells_ * 4 * species_count_, nullptr, device_bytes_);
  s.scratch = s.buffer(cells_ * 4 * species_count_, nullptr, device_bytes_);
  s.marks = s.buffer(texels * species_count_, nullptr, device_bytes_);
  s.field = s.buffer(cells_ * 4, nullptr, device_bytes_);
  auto data = [](const auto& v) { return v.empty() ? nullptr : static_cast<const void*>(v.data()); };
  const IntrinsicDomain* in = intrinsic_.get();
  auto table = [&](const auto* v) { return in ? s.buffer(v->size() * sizeof((*v)[0]), data(*v), device_bytes_)
                                              : s.buffer(4, nullptr, device_bytes_); };
  s.face_vertices = table(in ? &in->face_vertices : nullptr);
  s.locator_grid = table(in ? &in->locator.grid : nullptr);
  s.locator_cells = table(in ? &in->locator.cells : nullptr);
  s.locator_face = table(in ? &in->locator.face : nullptr);
  s.locator_map = table(in ? &in->locator.map : nullptr);
  s.locator_next = table(in ? &in->locator.next : nullptr);
  s.locator_across = table(in ? &in->locator.across : nullptr);
  s.cells_per_unit = table(in ? &in->cells_per_unit : nullptr);
  s.lattice_grid = table(in ? &in->lattice.grid : nullptr);
  s.lattice_vertex = table(in ? &in->lattice.vertex : nullptr);
  s.lattice_weight = table(in ? &in->lattice.weight : nullptr);
  s.node_field = s.buffer(in ? size_t(in->lattice.node_count()) * 4 : 4, nullptr, device_bytes_);
}

OpenClBackend::~OpenClBackend() = default;

cl_kernel OpenClBackend::agent_kernel(bool food, bool fields) {
  State& s = *state_;
  const int v = (food ? 1 : 0) | (fields ? 2 : 0);
  if (!s.agent_kernels[v]) {
    if (!s.programs[v])
      s.programs[v] = build_program(s.r, s.context, device_,
                                    "-DMTX_SPECIES=" + std::to_string(species_count_) +
                                        " -DMTX_FOOD=" + (food ? "1" : "0") +
                                        " -DMTX_FIELDS=" + (fields ? "1" : "0"));
    cl_int err = CL_SUCCESS;
    s.agent_kernels[v] = s.r.clCreateKernel(s.programs[v], "momas_agents", &err);
    check(err, "creating the agent kernel");
  }
  return s.agent_kernels[v];
}

std::string OpenClBackend::name() const {
  return "OpenCL: " + device_.name + " (" + device_.platform_name + ")";
}

void OpenClBackend::reserve_agents(size_t count) {
  if (count <= agent_capacity_ && state_->triangle) return;
  State& s = *state_;
  const double need = static_cast<double>(device_bytes_) +
                      (static_cast<double>(count) - static_cast<double>(agent_capacity_)) * 41.0;
  if (device_.global_memory && need > 0.9 * static_cast<double>(device_.global_memory))
    fail(MOLDTEX_ERROR_OUT_OF_MEMORY,
         "The agents would need about " + std::to_string(static_cast<long long>(need / (1 << 20))) +
             " MiB but " + device_.name + " has " +
             std::to_string(static_cast<long long>(device_.global_memory >> 20)) +
             " MiB: use fewer agents or the CPU backend");
  // Room for a brush stroke's worth of growth without reallocating at every dab.
  const size_t capacity = agent_capacity_ == 0 ? count : std::max(count, agent_capacity_ + agent_capacity_ / 4);
  // New buffers first: if one cannot be had, the old ones (and the agents) stay.
  constexpr int kBuffers = 8;
  const size_t sizes[kBuffers] = {4, 4, 4, 4, 4, 1, 4, 16};
  cl_mem fresh[kBuffers] = {};
  size_t fresh_bytes = 0;
  try {
    for (int i = 0; i < kBuffers; ++i) fresh[i] = s.buffer(capacity * sizes[i], nullptr, fresh_bytes);
  } catch (...) {
    for (cl_mem m : fresh)
      if (m) s.r.clReleaseMemObject(m);
    throw;
  }
  cl_mem* slots[kBuffers] = {&s.triangle, &s.b1, &s.b2, &s.hx, &s.hy, &s.species, &s.hunger, &s.lives};
  for (int i = 0; i < kBuffers; ++i) {
    if (*slots[i]) {
      s.r.clReleaseMemObject(*slots[i]);
      device_bytes_ -= std::max<size_t>(agent_capacity_ * sizes[i], 4);
    }
    *slots[i] = fresh[i];
  }
  device_bytes_ += fresh_bytes;
  agent_capacity_ = capacity;
}

void OpenClBackend::import_agents(const Agents& a) {
  reserve_agents(a.size());
  try {
    upload_agents(a, 0);
  } catch (...) {  // the buffers hold neither the old agents nor the new: none then
    agent_count_ = 0;
    batch_.clear();
    throw;
  }
  agent_count_ = static_cast<uint32_t>(a.size());
  batch_ = a.batch;
  batch_.resize(a.size(), 0);
}

void OpenClBackend::upload_agents(const Agents& a, size_t first) {
  State& s = *state_;
  const size_t m = a.size();
  if (m == 0) return;  // a zero-sized write is invalid
  auto write = [&](cl_mem buffer, const void* data, size_t element = 4) {
    check(s.r.clEnqueueWriteBuffer(s.queue, buffer, CL_TRUE, first * element, m * element, data, 0, nullptr,
                                   nullptr),
          "uploading the agents");
  };
  write(s.triangle, a.triangle.data());
  write(s.b1, a.b1.data());
  write(s.b2, a.b2.data());
  write(s.hx, a.hx.data());
  write(s.hy, a.hy.data());
  write(s.species, a.species.data(), 1);
  write(s.hunger, a.hunger.data());
  std::vector<cl_float4> lives(m);
  for (size_t i = 0; i < m; ++i) {
    lives[i].s[0] = i < a.clock.size() ? a.clock[i] : 0.f;
    lives[i].s[1] = i < a.age.size() ? a.age[i] : 0.f;
    lives[i].s[2] = i < a.exposure.size() ? a.exposure[i] : 0.f;
    lives[i].s[3] = i < a.threshold.size() ? a.threshold[i] : 0.f;
  }
  write(s.lives, lives.data(), sizeof(cl_float4));
}

void OpenClBackend::append_agents(const Agents& a) {
  const size_t n = agent_count_, m = a.size();
  if (m == 0) return;
  // Buffers too small: new ones, filled by one import (reserve_agents leaves room for the
  // rest of a stroke). Otherwise only the new agents travel, written after the others;
  // until the count grows, a failure leaves the agents as they were.
  if (n + m > agent_capacity_ || !state_->triangle) return Backend::append_agents(a);
  upload_agents(a, n);
  batch_.resize(n + m, 0);
  std::copy_n(a.batch.begin(), std::min(a.batch.size(), m), batch_.begin() + n);
  agent_count_ = static_cast<uint32_t>(n + m);
}

void OpenClBackend::set_field(const std::vector<float>& field) {
  State& s = *state_;
  if (field.empty()) return;  // the kernels do not read it then
  const std::vector<float> cells = intrinsic_ ? intrinsic_->sample_texels(field.data()) : field;
  check(s.r.clEnqueueWriteBuffer(s.queue, s.field, CL_TRUE, 0, cells.size() * 4, cells.data(), 0, nullptr,
                                 nullptr),
        "uploading the fields");
  if (intrinsic_) {  // and at the lattice's nodes, where sensors read it
    const std::vector<float> nodes = intrinsic_->lattice.field(cells);
    check(s.r.clEnqueueWriteBuffer(s.queue, s.node_field, CL_TRUE, 0, nodes.size() * 4, nodes.data(), 0, nullptr,
                                   nullptr),
          "uploading the fields");
  }
}

void OpenClBackend::reset(const Agents& agents) {
  State& s = *state_;
  // Spawning is a one-off: done on the host with the CPU backend's code, then uploaded.
  import_agents(agents);
  const size_t texels = domain_->texel_count() * species_count_, cells = cells_ * species_count_;
  const float zero = 0.f;
  const cl_uchar zero8 = 0;
  check(s.r.clEnqueueFillBuffer(s.queue, s.pheromone, &zero, 4, 0, cells * 4, 0, nullptr, nullptr),
        "clearing the pheromone");
  check(s.r.clEnqueueFillBuffer(s.queue, s.scratch, &zero, 4, 0, cells * 4, 0, nullptr, nullptr),
        "clearing the pheromone");
  check(s.r.clEnqueueFillBuffer(s.queue, s.marks, &zero8, 1, 0, texels, 0, nullptr, nullptr),
        "clearing the deposits");
  finish();
}

void OpenClBackend::step(const StepSettings& settings, uint64_t seed, uint64_t step_index,
                         uint32_t* eaters) {
  if (settings.model == MOLDTEX_MODEL_CONTINUOUS) return step_continuous(settings, seed, step_index);
  if (settings.model == MOLDTEX_MODEL_GRAY_SCOTT) return step_gray_scott(settings);
  State& s = *state_;
  const TextureDomain& d = *domain_;
  const moldtex_sim_params& p = settings.params;
  const mtx_momas_constants c = momas_constants(settings, d, seed, step_index);
  const cl_uint planes = species_count_;
  const cl_uint texels = static_cast<cl_uint>(d.texel_count());
  const cl_uint gutter = static_cast<cl_uint>(d.gutter_texel.size());

  if (c.food_count > 0) {
    check(s.r.clEnqueueWriteBuffer(s.queue, s.food, CL_FALSE, 0, c.food_count * 16ull,
                                   settings.food.data(), 0, nullptr, nullptr),
          "uploading the food sources");
    const cl_uint zero = 0;
    check(s.r.clEnqueueFillBuffer(s.queue, s.eaters, &zero, 4, 0, c.food_count * 4ull, 0, nullptr,
                                  nullptr),
          "clearing the food counters");
  }
  // The same conditions as the run-time tests in shared/momas.h.
  cl_kernel k = agent_kernel(c.hunger_step > 0.0f, c.has_fields != 0);
  s.args(k, s.frames, s.adjacency, s.corner_uvs, s.classes, s.pheromone, s.field, s.marks,
         s.triangle, s.b1, s.b2, s.hx, s.hy, s.species, s.hunger, s.frame3d, s.food, s.eaters,
         s.texels_per_unit, s.texel_island, s.island, s.interior_reach, s.unfolded, c, static_cast<cl_uint>(agent_count_));
  s.run(k, agent_count_);
  if (c.food_count > 0)  // the host needs the counts before the next step's food
    check(s.r.clEnqueueReadBuffer(s.queue, s.eaters, CL_TRUE, 0, c.food_count * 4ull, eaters, 0,
                                  nullptr, nullptr),
          "reading the food counters");

  cl_float4 deposit{};
  for (cl_uint i = 0; i < planes; ++i) deposit.s[i] = settings.species[i].deposit;
  s.args(s.deposit_kernel, s.pheromone, s.marks, s.classes, deposit, texels, planes);
  s.run(s.deposit_kernel, static_cast<size_t>(texels) * planes);

  auto gutter_pass = [&] {
    s.args(s.gutter_kernel, s.pheromone, s.gutter_texel, s.gutter_source, gutter, texels, planes);
    s.run(s.gutter_kernel, gutter);
  };
  if (p.length_unit > 0.f) {
    surface_diffusion(p);
    gutter_pass();
    return;
  }
  gutter_pass();

  const float mix = std::min(1.f, p.diffusion_rate * p.time_step);
  s.args(s.diffuse_kernel, s.pheromone, s.scratch, s.classes, static_cast<cl_int>(d.width),
         static_cast<cl_int>(d.height), mix, p.evaporation_rate * p.time_step, planes);
  s.run(s.diffuse_kernel, d.width, d.height);
  std::swap(s.pheromone, s.scratch);
  gutter_pass();
}

void OpenClBackend::surface_diffusion(const moldtex_sim_params& p) {
  State& s = *state_;
  const TextureDomain& d = *domain_;
  const cl_uint planes = species_count_;
  const cl_uint texels = static_cast<cl_uint>(d.texel_count());
  const float mix = p.diffusion_rate * p.time_step;
  if (!plan_.matches(mix, p.length_unit)) {
    DiffusionPlan plan = plan_surface_diffusion(d, mix, p.length_unit);
    s.release_plan();
    device_bytes_ -= s.plan_bytes;
    s.plan_bytes = 0;
    const size_t fine = plan.fine_texel.size();
    auto data = [](const auto& v) { return v.empty() ? nullptr : static_cast<const void*>(v.data()); };
    s.coef = s.buffer(plan.triangle_coef.size() * 4, data(plan.triangle_coef), s.plan_bytes);
    s.fine_texel = s.buffer(fine * 4, data(plan.fine_texel), s.plan_bytes);
    s.fine_neighbour = s.buffer(fine * 16, data(plan.fine_neighbour), s.plan_bytes);
    s.fine_coef = s.buffer(fine * 8, data(plan.fine_coef), s.plan_bytes);
    s.fine_extra = s.buffer(fine * 4, data(plan.fine_extra), s.plan_bytes);
    s.fine_scratch = s.buffer(fine * 4 * planes, nullptr, s.plan_bytes);
    device_bytes_ += s.plan_bytes;
    plan_ = std::move(plan);
  }
  const cl_uint seams = static_cast<cl_uint>(d.seam_texel.size());
  for (uint32_t pass = 0; pass < plan_.passes; ++pass) {
    const float evaporation = pass == 0 ? p.evaporation_rate * p.time_step : 0.f;
    s.args(s.surface_kernel, s.pheromone, s.scratch, s.classes, s.texel_triangle, s.coef,
           static_cast<cl_int>(d.width), static_cast<cl_int>(d.height), evaporation, planes);
    s.run(s.surface_kernel, d.width, d.height);
    s.args(s.seam_kernel, s.pheromone, s.scratch, s.seam_texel, s.seam_neighbour, s.texel_triangle,
           s.coef, seams, texels, evaporation, planes);
    s.run(s.seam_kernel, seams);
    std::swap(s.pheromone, s.scratch);
  }
  for (cl_uint pass = 1; pass <= plan_.max_extra; ++pass) {
    // The fine texels that take this pass lead the list (DiffusionPlan::fine_active).
    const cl_uint fine = plan_.fine_active[pass - 1];
    s.args(s.fine_kernel, s.pheromone, s.fine_scratch, s.fine_texel, s.fine_neighbour, s.fine_coef,
           s.fine_extra, pass, fine, texels, planes);
    s.run(s.fine_kernel, fine);
    s.args(s.scatter_kernel, s.pheromone, s.fine_scratch, s.fine_texel, fine, texels, planes);
    s.run(s.scatter_kernel, fine);
  }
}

cl_kernel OpenClBackend::continuous_kernel(bool fields) {
  State& s = *state_;
  if (!s.continuous_kernels[fields]) {
    agent_kernel(false, fields);  // builds the program
    cl_int err = CL_SUCCESS;
    s.continuous_kernels[fields] = s.r.clCreateKernel(s.programs[fields ? 2 : 0], "continuous_agents", &err);
    check(err, "creating the continuous model's agent kernel");
  }
  return s.continuous_kernels[fields];
}

void OpenClBackend::prepare_continuous() {
  if (laplacian_) return;
  State& s = *state_;
  const Surface& sf = *surface_;
  const TextureDomain& d = *domain_;
  auto lap = std::make_unique<TexelLaplacian>();
  if (intrinsic_) {
    *lap = intrinsic_->laplacian;
  } else {
    ThreadPool pool(0);
    *lap = build_texel_laplacian(sf, d, pool);
  }
  const AliasTable alias = build_area_alias_table(sf);
  auto data = [](const auto& v) { return v.empty() ? nullptr : static_cast<const void*>(v.data()); };
  s.sums = s.buffer(cells_ * 4 * species_count_, nullptr, device_bytes_);
  s.interior_bits = s.buffer(d.interior_bits.size() * 4, d.interior_bits.data(), device_bytes_);
  const cl_int zero = 0;
  check(s.r.clEnqueueFillBuffer(s.queue, s.sums, &zero, 4, 0, cells_ * 4 * species_count_, 0, nullptr, nullptr),
        "clearing the deposit sums");
  const size_t nodes = intrinsic_ ? size_t(intrinsic_->lattice.node_count()) * species_count_ : 1;
  s.node_values = s.buffer(nodes * 4, nullptr, device_bytes_);
  s.node_sums = s.buffer(nodes * 4, nullptr, device_bytes_);
  check(s.r.clEnqueueFillBuffer(s.queue, s.node_sums, &zero, 4, 0, nodes * 4, 0, nullptr, nullptr),
        "clearing the deposit sums");
  s.alias_prob = s.buffer(alias.prob.size() * 4, data(alias.prob), device_bytes_);
  s.alias_index = s.buffer(alias.alias.size() * 4, data(alias.alias), device_bytes_);
  s.rows = s.buffer(lap->rows.size() * 4, data(lap->rows), device_bytes_);
  s.row_start = s.buffer(lap->start.size() * 4, data(lap->start), device_bytes_);
  s.col = s.buffer(lap->col.size() * 4, data(lap->col), device_bytes_);
  s.weight = s.buffer(lap->weight.size() * 4, data(lap->weight), device_bytes_);
  s.area = s.buffer(lap->area.size() * 4, data(lap->area), device_bytes_);
  cl_int err = CL_SUCCESS;
  s.convert_kernel = s.r.clCreateKernel(s.programs[0], "deposits_to_concentration", &err);
  check(err, "creating the deposit kernel");
  s.gather_kernel = s.r.clCreateKernel(s.programs[0], "lattice_gather", &err);
  check(err, "creating the lattice kernel");
  s.lattice_scatter_kernel = s.r.clCreateKernel(s.programs[0], "lattice_scatter", &err);
  check(err, "creating the lattice kernel");
  s.pde_kernel = s.r.clCreateKernel(s.programs[0], "pde_diffuse", &err);
  check(err, "creating the diffusion kernel");
  s.fine_start_kernel = s.r.clCreateKernel(s.programs[0], "pde_fine_start", &err);
  check(err, "creating the diffusion kernel");
  s.fine_diffuse_kernel = s.r.clCreateKernel(s.programs[0], "pde_fine_diffuse", &err);
  check(err, "creating the diffusion kernel");
  s.coarse_diffuse_kernel = s.r.clCreateKernel(s.programs[0], "pde_coarse_diffuse", &err);
  check(err, "creating the diffusion kernel");
  s.fine_finish_kernel = s.r.clCreateKernel(s.programs[0], "pde_fine_finish", &err);
  check(err, "creating the diffusion kernel");
  s.write_kernel = s.r.clCreateKernel(s.programs[0], "write_stimulus", &err);
  check(err, "creating the write stimulus kernel");
  s.scale_kernel = s.r.clCreateKernel(s.programs[0], "scale_cells", &err);
  check(err, "creating the decay map kernel");
  laplacian_ = std::move(lap);
}

void OpenClBackend::step_continuous(const StepSettings& settings, uint64_t seed, uint64_t step_index) {
  prepare_continuous();
  State& s = *state_;
  const TextureDomain& d = *domain_;
  const TexelLaplacian& lap = *laplacian_;
  const moldtex_continuous_params& p = settings.continuous;
  const ParameterMaps& maps = maps_for(*settings.maps);  // (the same planes as the simulation's)
  mtx_continuous_constants c =
      continuous_constants(settings, d, settings.u_metric, surface_->triangle_count(), agent_count_, seed,
                           step_index);
  const cl_uint planes = species_count_;
  const cl_uint texels = static_cast<cl_uint>(cells_);  // values per plane
  const cl_uint nodes = intrinsic_ ? intrinsic_->lattice.node_count() : 0;
  if (intrinsic_) {  // planes of vertex values (maps), read and deposited at the lattice's nodes
    c.width = static_cast<mtx_u32>(cells_);
    c.height = 1;
    c.plane_cells = nodes;
    s.args(s.gather_kernel, s.pheromone, s.lattice_vertex, s.lattice_weight, s.node_values, nodes, texels, planes);
    s.run(s.gather_kernel, nodes);
  }
  const cl_uint cells = static_cast<cl_uint>(lap.rows.size());
  if ((c.bias_on || c.bias_spawn) && settings.bias != s.bias_uploaded) {  // a new bias field
    if (s.bias && s.bias_uploaded.size() != settings.bias.size()) {
      s.r.clReleaseMemObject(s.bias);
      s.bias = nullptr;
    }
    if (!s.bias)
      s.bias = s.buffer(settings.bias.size() * 4, nullptr, device_bytes_);
    check(s.r.clEnqueueWriteBuffer(s.queue, s.bias, CL_TRUE, 0, settings.bias.size() * 4, settings.bias.data(),
                                   0, nullptr, nullptr),
          "uploading the bias field");
    s.bias_uploaded = settings.bias;
  }
  if (!s.bias) {  // never read while bias_on == bias_spawn == 0
    s.bias = s.buffer(4, nullptr, device_bytes_);
    s.bias_uploaded.assign(1, 0.f);  // what a 4-byte buffer holds
  }
  if (s.maps_source != &maps || s.maps_version != maps.version || !s.map_planes) {
    // New maps: replace every map buffer (maps change rarely; a placeholder where unset).
    device_bytes_ -= s.maps_bytes;
    s.maps_bytes = 0;
    auto replace = [&](cl_mem& m, const void* data, size_t bytes) {
      if (m) s.r.clReleaseMemObject(m);
      m = nullptr;
      m = s.buffer(bytes, bytes ? data : nullptr, s.maps_bytes);
    };
    replace(s.map_planes, maps.agent_planes.data(), maps.agent_planes.size() * 4);
    replace(s.spawn_max, maps.spawn_max.data(), maps.spawn_max.size() * 4);
    replace(s.spawn_prob, maps.spawn_alias.prob.data(), maps.spawn_alias.prob.size() * 4);
    replace(s.spawn_index, maps.spawn_alias.alias.data(), maps.spawn_alias.alias.size() * 4);
    replace(s.write, maps.write().data(), maps.write().size() * 4);
    device_bytes_ += s.maps_bytes;
    s.maps_source = &maps;
    s.maps_version = maps.version;
  }
  const bool spawn_map = !maps.spawn_max.empty();
  cl_kernel k = continuous_kernel(c.has_fields != 0);
  s.args(k, s.frames, s.adjacency, s.corner_uvs, s.classes, intrinsic_ ? s.node_values : s.pheromone, s.field,
         intrinsic_ ? s.node_sums : s.sums, s.triangle,
         s.b1, s.b2, s.hx, s.hy, s.species, s.lives, intrinsic_ ? s.cells_per_unit : s.texels_per_unit,
         s.island, s.texel_island, s.interior_bits, s.unfolded, spawn_map ? s.spawn_prob : s.alias_prob,
         spawn_map ? s.spawn_index : s.alias_index, s.bias, s.map_planes, s.spawn_max, s.face_vertices,
         s.locator_grid, s.locator_cells, s.locator_face, s.locator_map, s.locator_next, s.locator_across,
         s.lattice_grid, s.node_field, static_cast<cl_uint>(intrinsic_ ? 1 : 0), c,
         static_cast<cl_uint>(agent_count_));
  s.run(k, agent_count_);
  if (intrinsic_) {
    s.args(s.lattice_scatter_kernel, s.node_sums, s.sums, s.lattice_vertex, s.lattice_weight, nodes, texels, planes);
    s.run(s.lattice_scatter_kernel, nodes);
  }
  const float amount = deposit_unit_amount(p, c.deposit_units);
  s.args(s.convert_kernel, s.pheromone, s.sums, s.rows, s.area, amount, cells, texels, planes);
  s.run(s.convert_kernel, cells);
  if (!maps.write().empty()) {
    cl_float4 a{};
    for (cl_uint q = 0; q < planes && q < 4; ++q)
      a.s[q] = write_stimulus_amount(p, q < settings.u_metric.size() ? settings.u_metric[q] : 0.0);
    s.args(s.write_kernel, s.pheromone, s.rows, s.write, a, cells, texels, planes);
    s.run(s.write_kernel, cells);
  }
  diffuse_continuous(p, maps);
  if (intrinsic_) return;  // (shown in the texture when read)
  const cl_uint gutter = static_cast<cl_uint>(d.gutter_texel.size());
  s.args(s.gutter_kernel, s.pheromone, s.gutter_texel, s.gutter_source, gutter, texels, planes);
  s.run(s.gutter_kernel, gutter);
}

const ParameterMaps& OpenClBackend::maps_for(const ParameterMaps& maps) {
  return intrinsic_ ? vertex_maps_.of(*intrinsic_, maps, domain_->texel_count()) : maps;
}

void OpenClBackend::upload_conductances(const ParameterMaps& maps, const TexelLaplacian& lap) {
  State& s = *state_;
  const void* weights_source = maps.diffusion().empty() ? nullptr : &maps;
  if (weights_source == weights_source_ && (!weights_source || weights_version_ == maps.version)) return;
  // Another diffusion map (or none): its conductances (and Gray-Scott's rates), and the
  // local stepping lists anew.
  check(s.r.clEnqueueWriteBuffer(s.queue, s.weight, CL_TRUE, 0, lap.weight.size() * 4, lap.weight.data(), 0,
                                 nullptr, nullptr),
        "uploading the conductances");
  if (s.rate && !lap.rate.empty())
    check(s.r.clEnqueueWriteBuffer(s.queue, s.rate, CL_TRUE, 0, lap.rate.size() * 4, lap.rate.data(), 0, nullptr,
                                   nullptr),
          "uploading the rates");
  s.local_rdt = -1;
  weights_source_ = weights_source;
  weights_version_ = maps.version;
}

void OpenClBackend::diffuse_continuous(const moldtex_continuous_params& p, const ParameterMaps& maps) {
  State& s = *state_;
  const TexelLaplacian& lap = laplacian_for(maps, *laplacian_, mapped_);
  upload_conductances(maps, lap);
  const std::vector<float>& decay_map = decay_for(maps, double(p.decay_rate) * p.time_step, mapped_);
  if (!decay_map.empty() &&
      (decay_source_ != &maps || decay_version_ != maps.version || decay_key_ != double(p.decay_rate) * p.time_step)) {
    if (s.decay) s.r.clReleaseMemObject(s.decay);
    s.decay = nullptr;
    size_t bytes = 0;
    s.decay = s.buffer(decay_map.size() * 4, decay_map.data(), bytes);
    decay_source_ = &maps;
    decay_version_ = maps.version;
    decay_key_ = double(p.decay_rate) * p.time_step;
  }
  integrate(p, lap);
  if (!decay_map.empty()) {  // the decay map: each cell's own e^(-r_dec m dt)
    const cl_uint cells = static_cast<cl_uint>(lap.rows.size());
    s.args(s.scale_kernel, s.pheromone, s.rows, s.decay, cells, static_cast<cl_uint>(cells_),
           static_cast<cl_uint>(species_count_));
    s.run(s.scale_kernel, cells);
  }
}

// One step of diffusion and the global decay on the device (host conjugate gradients
// for backward Euler).
void OpenClBackend::integrate(const moldtex_continuous_params& p, const TexelLaplacian& lap) {
  State& s = *state_;
  // The plan (and backward Euler's matrix) stay this step's while another simulation on
  // the same cached domain steps (TexelLaplacian::guard).
  const auto lock = lap.lock();
  const uint32_t n = forward_substeps(lap, p.diffusion_rate, p.time_step);
  const bool backward = use_backward_euler(lap, p.diffusion_rate, p.time_step, p.integrator);
  const size_t texels = cells_;  // values per plane
  if (backward) {
    // Conjugate gradients run on the host (the same solver as the CPU backend, on one
    // thread: it uses no pool, so none is started for it every step).
    std::vector<float> u(texels * species_count_);
    read_planes(u.data());
    ThreadPool pool(1);
    for (uint32_t k = 0; k < species_count_; ++k)
      advance_diffusion_decay(lap, u.data() + k * texels, pde_scratch_, p.diffusion_rate, p.decay_rate,
                              p.time_step, MOLDTEX_INTEGRATOR_BACKWARD, pool);
    check(s.r.clEnqueueWriteBuffer(s.queue, s.pheromone, CL_TRUE, 0, u.size() * 4, u.data(), 0, nullptr, nullptr),
          "uploading the pheromone");
    return;
  }
  const float h = static_cast<float>(double(p.diffusion_rate) * p.time_step / n);
  const float decay = static_cast<float>(std::exp(-double(p.decay_rate) * p.time_step));
  const cl_uint cells = static_cast<cl_uint>(lap.rows.size());
  const cl_uint planes = static_cast<cl_uint>(species_count_);
  const cl_uint texels32 = static_cast<cl_uint>(texels);
  const LocalSteppingPlan& plan = local_stepping_plan(lap, p.diffusion_rate, p.time_step);
  if (plan.fine_rows.empty()) {
    for (uint32_t j = 0; j < n; ++j) {
      s.args(s.pde_kernel, s.rows, s.row_start, s.col, s.weight, s.area, s.pheromone, s.scratch, h,
             j + 1 == n ? decay : 1.f, cells, texels32, planes);
      s.run(s.pde_kernel, cells);
      std::swap(s.pheromone, s.scratch);
    }
    return;
  }
  if (s.local_rdt != plan.rdt) {  // the plan's lists on the device
    for (cl_mem* m : {&s.step_class, &s.flux_link, &s.fine_cell, &s.fine_start, &s.fine_nbr, &s.fine_area,
                      &s.fine_weight, &s.fine_cur, &s.fine_next, &s.fine_flux})
      if (*m) {
        s.r.clReleaseMemObject(*m);
        *m = nullptr;
      }
    size_t bytes = 0;
    s.step_class = s.buffer(plan.step_class.size(), plan.step_class.data(), bytes);
    s.flux_link = s.buffer(plan.link.size() * 4, plan.link.data(), bytes);
    s.fine_cell = s.buffer(plan.fine_cell.size() * 4, plan.fine_cell.data(), bytes);
    s.fine_start = s.buffer(plan.fine_start.size() * 4, plan.fine_start.data(), bytes);
    s.fine_nbr = s.buffer(plan.fine_nbr.size() * 4, plan.fine_nbr.data(), bytes);
    s.fine_area = s.buffer(plan.fine_area.size() * 4, plan.fine_area.data(), bytes);
    s.fine_weight = s.buffer(plan.fine_weight.size() * 4, plan.fine_weight.data(), bytes);
    s.fine_cur = s.buffer(plan.fine_cell.size() * 4 * planes, nullptr, bytes);
    s.fine_next = s.buffer(plan.fine_cell.size() * 4 * planes, nullptr, bytes);
    s.fine_flux = s.buffer(plan.fine_nbr.size() * 4 * planes, nullptr, bytes);
    s.local_rdt = plan.rdt;
  }
  const cl_uint fine = static_cast<cl_uint>(plan.fine_cell.size());
  const cl_uint entries = static_cast<cl_uint>(plan.fine_nbr.size());  // compact inflows per plane
  const float hfine = static_cast<float>(double(p.diffusion_rate) * p.time_step / n / plan.fine);
  for (uint32_t j = 0; j < n; ++j) {
    s.args(s.fine_start_kernel, s.fine_cell, s.fine_start, s.pheromone, s.fine_cur, s.fine_flux, fine, texels32,
           entries, planes);
    s.run(s.fine_start_kernel, fine);
    for (uint32_t q = 0; q < plan.fine; ++q) {
      s.args(s.fine_diffuse_kernel, s.fine_start, s.fine_nbr, s.fine_weight, s.fine_area, s.pheromone,
             s.fine_cur, s.fine_next, s.fine_flux, hfine, fine, texels32, entries, planes);
      s.run(s.fine_diffuse_kernel, fine);
      std::swap(s.fine_cur, s.fine_next);
    }
    const float d = j + 1 == n ? decay : 1.f;
    s.args(s.coarse_diffuse_kernel, s.rows, s.row_start, s.col, s.weight, s.area, s.step_class, s.flux_link,
           s.pheromone, s.fine_flux, s.scratch, h, d, cells, texels32, entries, planes);
    s.run(s.coarse_diffuse_kernel, cells);
    s.args(s.fine_finish_kernel, s.fine_cell, s.fine_cur, s.scratch, d, fine, texels32, planes);
    s.run(s.fine_finish_kernel, fine);
    std::swap(s.pheromone, s.scratch);
  }
}

// Gray-Scott (models/gray_scott/reaction_diffusion.h): planes V and U, no agents; every sub-step
// runs the shared cell update on the device, then the gutter is filled.
void OpenClBackend::step_gray_scott(const StepSettings& settings) {
  prepare_continuous();  // the texel Laplacian's buffers
  State& s = *state_;
  const ParameterMaps& maps = maps_for(*settings.maps);
  const TexelLaplacian& lap = laplacian_for(maps, *laplacian_, mapped_);
  const moldtex_reaction_params& p = settings.reaction;
  if (species_count_ < kReactionPlanes) fail(MOLDTEX_ERROR_INTERNAL, "The Gray-Scott model needs two planes");
  if (!s.gray_scott_kernel) {
    cl_int err = CL_SUCCESS;
    s.gray_scott_kernel = s.r.clCreateKernel(s.programs[0], "gray_scott_substep", &err);
    check(err, "creating the Gray-Scott kernel");
    s.rate = s.buffer(lap.rate.size() * 4, lap.rate.empty() ? nullptr : lap.rate.data(), device_bytes_);
    weights_source_ = nullptr;  // (the buffers hold the base operator's)
    weights_version_ = 0;
  }
  upload_conductances(maps, lap);
  if (!s.feed_map || s.reaction_source != &maps || s.reaction_version != maps.version) {
    for (cl_mem* m : {&s.feed_map, &s.kill_map})
      if (*m) {
        s.r.clReleaseMemObject(*m);
        *m = nullptr;
      }
    size_t bytes = 0;
    s.feed_map = s.buffer(maps.feed().size() * 4, maps.feed().empty() ? nullptr : maps.feed().data(), bytes);
    s.kill_map = s.buffer(maps.kill().size() * 4, maps.kill().empty() ? nullptr : maps.kill().data(), bytes);
    s.reaction_source = &maps;
    s.reaction_version = maps.version;
  }
  const ReactionMaps rm = reaction_maps(maps.feed(), maps.largest[MOLDTEX_MAP_FEED], maps.kill(),
                                       maps.largest[MOLDTEX_MAP_KILL], p);
  const uint32_t n = reaction_substeps(lap, p, rm);
  const float h = static_cast<float>(double(p.time_step) / n);
  const float du = static_cast<float>(double(p.diffusion_u) * p.time_step / n);
  const float dv = static_cast<float>(double(p.diffusion_v) * p.time_step / n);
  const cl_uint cells = static_cast<cl_uint>(lap.rows.size());
  const cl_uint texels = static_cast<cl_uint>(cells_);  // values per plane
  for (uint32_t j = 0; j < n; ++j) {
    s.args(s.gray_scott_kernel, s.rows, s.row_start, s.col, s.weight, s.area, s.rate, s.pheromone, s.scratch, h, du, dv,
           p.feed, p.kill, s.feed_map, s.kill_map, static_cast<cl_uint>(rm.feed != nullptr),
           static_cast<cl_uint>(rm.kill != nullptr), cells, texels);
    s.run(s.gray_scott_kernel, cells);
    std::swap(s.pheromone, s.scratch);
  }
  if (intrinsic_) return;
  const cl_uint gutter = static_cast<cl_uint>(domain_->gutter_texel.size());
  s.args(s.gutter_kernel, s.pheromone, s.gutter_texel, s.gutter_source, gutter, texels,
         static_cast<cl_uint>(species_count_));
  s.run(s.gutter_kernel, gutter);
}

void OpenClBackend::finish() { check(state_->r.clFinish(state_->queue), "finishing the step"); }

void OpenClBackend::read_planes(float* out) const {
  check(state_->r.clEnqueueReadBuffer(state_->queue, state_->pheromone, CL_TRUE, 0, cells_ * 4 * species_count_,
                                      out, 0, nullptr, nullptr),
        "reading the pheromone");
}

std::vector<float> OpenClBackend::read_cells() const {
  if (!intrinsic_) return {};
  std::vector<float> values(cells_ * species_count_);
  read_planes(values.data());
  return values;
}

void OpenClBackend::read_pheromone(float* out) const {
  if (!intrinsic_) return read_planes(out);
  std::vector<float> values(cells_ * species_count_);
  read_planes(values.data());
  if (!host_pool_) host_pool_ = std::make_unique<ThreadPool>(0);
  intrinsic_->show(values.data(), out, species_count_, *domain_, *host_pool_);
}

namespace {
template <class V>
void read_buffer(const cl::Runtime& r, cl_command_queue queue, cl_mem m, V& v, size_t count) {
  v.resize(count);
  if (count)
    check(r.clEnqueueReadBuffer(queue, m, CL_TRUE, 0, count * sizeof(v[0]), v.data(), 0, nullptr,
                                nullptr),
          "reading the state");
}
}  // namespace

void OpenClBackend::export_agents(Agents& out) const {
  const State& s = *state_;
  read_buffer(s.r, s.queue, s.triangle, out.triangle, agent_count_);
  read_buffer(s.r, s.queue, s.b1, out.b1, agent_count_);
  read_buffer(s.r, s.queue, s.b2, out.b2, agent_count_);
  read_buffer(s.r, s.queue, s.hx, out.hx, agent_count_);
  read_buffer(s.r, s.queue, s.hy, out.hy, agent_count_);
  read_buffer(s.r, s.queue, s.species, out.species, agent_count_);
  read_buffer(s.r, s.queue, s.hunger, out.hunger, agent_count_);
  std::vector<cl_float4> lives;
  read_buffer(s.r, s.queue, s.lives, lives, agent_count_);
  out.clock.resize(agent_count_);
  out.age.resize(agent_count_);
  out.exposure.resize(agent_count_);
  out.threshold.resize(agent_count_);
  for (size_t i = 0; i < lives.size(); ++i) {
    out.clock[i] = lives[i].s[0];
    out.age[i] = lives[i].s[1];
    out.exposure[i] = lives[i].s[2];
    out.threshold[i] = lives[i].s[3];
  }
  out.batch = batch_;
}

void OpenClBackend::export_state(SimState& out) const {
  export_agents(out.agents);
  out.pheromone.resize(domain_->texel_count() * species_count_);
  read_pheromone(out.pheromone.data());
  out.cells.clear();
  if (intrinsic_) read_buffer(state_->r, state_->queue, state_->pheromone, out.cells, cells_ * species_count_);
}

void OpenClBackend::import_state(const SimState& in) {
  State& s = *state_;
  std::vector<float> values;
  if (intrinsic_) {
    if (!host_pool_) host_pool_ = std::make_unique<ThreadPool>(0);
    values = intrinsic_->values_from_state(in, species_count_, *domain_, *host_pool_);
  }
  const std::vector<float>& planes = intrinsic_ ? values : in.pheromone;
  import_agents(in.agents);
  check(s.r.clEnqueueWriteBuffer(s.queue, s.pheromone, CL_TRUE, 0, planes.size() * 4, planes.data(), 0, nullptr,
                                 nullptr),
        "restoring the pheromone");
  const cl_uchar zero8 = 0;
  check(s.r.clEnqueueFillBuffer(s.queue, s.marks, &zero8, 1, 0, domain_->texel_count() * species_count_,
                                0, nullptr, nullptr),
        "clearing the deposits");
  finish();
}

void OpenClBackend::read_agents(moldtex_surface_point* out, size_t count) const {
  count = std::min<size_t>(count, agent_count_);
  std::vector<uint32_t> tri(count);
  std::vector<float> b1(count), b2(count);
  auto read = [&](cl_mem m, void* data) {
    if (count == 0) return;
    check(state_->r.clEnqueueReadBuffer(state_->queue, m, CL_TRUE, 0, count * 4, data, 0, nullptr, nullptr),
          "reading the agents");
  };
  read(state_->triangle, tri.data());
  read(state_->b1, b1.data());
  read(state_->b2, b2.data());
  for (size_t i = 0; i < count; ++i) {
    out[i].triangle = tri[i];
    out[i].bary[0] = 1.f - b1[i] - b2[i];
    out[i].bary[1] = b1[i];
    out[i].bary[2] = b2[i];
  }
}

}  // namespace moldtex
