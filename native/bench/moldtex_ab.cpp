// moldtex_ab: two builds of the core, timed step by step against each other in one
// process, so that a shared machine's drift (other jobs, clock changes) falls on both
// alike. Each build is loaded from its own copy of libmoldtex.so (dlopen with
// RTLD_DEEPBIND, so each copy calls its own functions), runs the same case from the same
// seed, and the steps alternate A B B A ...: a round's ratio compares two steps taken
// within a fraction of a second of each other. Where both builds compute the same bits,
// both simulations also stay in the same state, so every pair of steps does the same work.
//
//   moldtex_ab LIB_A LIB_B [CASE] [ROUNDS] [THREADS] [BACKEND]
//
// CASE: plane-jones, plane-jones-small (256^2, 64 k agents), plane-surface (default), plane-surface-small (256^2, 64 k agents),
// plane-surface-sharp, sphere, sphere-jones (the sphere in plane-jones' geometry), sphere-surface,
// fine-sphere, plane-continuous, sphere-intrinsic (the continuous model on the intrinsic
// domain: a UV sphere 128 x 64 at 512^2, 300 k agents); ROUNDS (default 30) pairs of
// steps after 10 warm-up steps each; THREADS (default 0: all cores). Prints the median
// step time of each build, the median of the rounds' ratios B / A and how many rounds B
// was faster. BACKEND: cpu (default) or opencl (the first device listed: platform 0,
// device 0). CASE mesh=FILE: a mesh read from FILE (tools/export_mesh.py writes one from
// Blender, e.g. Suzanne with Subdivision 2: issue #15's own case) at 1024^2 with 300 k
// agents, core defaults otherwise; mesh-intrinsic=FILE: the same mesh on the intrinsic
// domain (continuous model, core defaults, as tools/bench_suzanne.py --intrinsic).
// MOLDTEX_AB_AGENTS, if set, overrides any case's agent count (small runs under valgrind);
// MOLDTEX_AB_SIDE its texture's side (what the texture size alone costs), MOLDTEX_AB_SEED
// its seed (how much one run's speed depends on its random draw).
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "mesh_fixtures.h"
#include "moldtex.h"

namespace {

struct Build {
  void* handle = nullptr;
  decltype(&moldtex_surface_create) surface_create = nullptr;
  decltype(&moldtex_sim_create) sim_create = nullptr;
  decltype(&moldtex_sim_step) sim_step = nullptr;
  decltype(&moldtex_sim_release) sim_release = nullptr;
  decltype(&moldtex_surface_release) surface_release = nullptr;
  decltype(&moldtex_last_error) last_error = nullptr;
  decltype(&moldtex_sim_set_continuous_params) set_continuous = nullptr;
  moldtex_surface surface = nullptr;
  moldtex_sim sim = nullptr;
};

template <typename F>
void Resolve(void* handle, const char* name, F* out) {
  *out = reinterpret_cast<F>(dlsym(handle, name));
  if (!*out) {
    std::fprintf(stderr, "%s: %s\n", name, dlerror());
    std::exit(2);
  }
}

bool Load(const char* path, Build* b) {
  b->handle = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
  if (!b->handle) {
    std::fprintf(stderr, "cannot load %s: %s\n", path, dlerror());
    return false;
  }
  Resolve(b->handle, "moldtex_surface_create", &b->surface_create);
  Resolve(b->handle, "moldtex_sim_create", &b->sim_create);
  Resolve(b->handle, "moldtex_sim_step", &b->sim_step);
  Resolve(b->handle, "moldtex_sim_release", &b->sim_release);
  Resolve(b->handle, "moldtex_surface_release", &b->surface_release);
  Resolve(b->handle, "moldtex_last_error", &b->last_error);
  Resolve(b->handle, "moldtex_sim_set_continuous_params", &b->set_continuous);
  return true;
}

struct CaseSpec {
  mtx::Mesh mesh;
  uint32_t side = 1024, agents = 1000000;
  double texels_per_unit = 0;  // surface units: one length unit spans this many mean texels
  bool jones = false;
  bool continuous = false;  // the continuous model, scaled as moldtex_bench scales it
  uint32_t domain = MOLDTEX_DOMAIN_TEXTURE;
  bool core_defaults = false;  // the continuous model's parameters as the core has them
};

// A mesh in tools/export_mesh.py's format: four little-endian u32 counts (vertices,
// triangles, UVs, triangle UV indices / 3), then the arrays in that order.
bool ReadMesh(const std::string& path, mtx::Mesh* m) {
  std::ifstream in(path, std::ios::binary);
  uint32_t n[4];
  if (!in.read(reinterpret_cast<char*>(n), sizeof n)) return false;
  for (uint32_t count : n)
    if (count == 0 || count > (1u << 26)) return false;  // not a mesh this tool wrote
  m->positions.resize(size_t(n[0]) * 3);
  m->triangles.resize(size_t(n[1]) * 3);
  m->uvs.resize(size_t(n[2]) * 2);
  m->triangle_uvs.resize(size_t(n[3]) * 3);
  auto read = [&](auto& v) { return bool(in.read(reinterpret_cast<char*>(v.data()), std::streamsize(v.size() * sizeof v[0]))); };
  return read(m->positions) && read(m->triangles) && read(m->uvs) && read(m->triangle_uvs);
}

bool MakeCase(const std::string& name, CaseSpec* c) {
  const bool on_intrinsic = name.rfind("mesh-intrinsic=", 0) == 0;
  if (on_intrinsic || name.rfind("mesh=", 0) == 0) {
    if (!ReadMesh(name.substr(name.find('=') + 1), &c->mesh)) return false;
    c->agents = 300000;
    c->core_defaults = true;
    if (on_intrinsic) {
      c->continuous = true;
      c->domain = MOLDTEX_DOMAIN_INTRINSIC;
    }
  } else if (name == "plane-jones") {
    c->mesh = mtx::make_quad();
    c->jones = true;
  } else if (name == "plane-jones-small") {  // small enough to run under valgrind
    c->mesh = mtx::make_quad();
    c->jones = true;
    c->side = 256;
    c->agents = 65536;
  } else if (name == "plane-surface") {
    c->mesh = mtx::make_quad();
    c->texels_per_unit = 2;
  } else if (name == "plane-surface-small") {  // small enough to run under valgrind
    c->mesh = mtx::make_quad();
    c->side = 256;
    c->agents = 65536;
    c->texels_per_unit = 2;
  } else if (name == "plane-surface-sharp") {
    c->mesh = mtx::make_quad();
    c->side = 2048;
    c->texels_per_unit = 4;
  } else if (name == "sphere") {
    c->mesh = mtx::make_uv_sphere(64, 32, 1.0);
    c->side = 2048;
  } else if (name == "sphere-jones") {  // moldtex_bench's SphereJonesCpu
    c->mesh = mtx::make_uv_sphere(64, 32, 1.0);
    c->side = 2048;
    c->jones = true;
  } else if (name == "sphere-surface") {
    c->mesh = mtx::make_uv_sphere(64, 32, 1.0);
    c->side = 2048;
    c->texels_per_unit = 2;
  } else if (name == "fine-sphere") {
    c->mesh = mtx::make_uv_sphere(128, 64, 1.0);
    c->agents = 300000;
  } else if (name == "plane-continuous") {
    c->mesh = mtx::make_quad();
    c->continuous = true;
  } else if (name == "sphere-intrinsic") {  // IntrinsicScaling's Suzanne-sized sphere
    c->mesh = mtx::make_uv_sphere(128, 64, 1.0);
    c->side = 512;
    c->agents = 300000;
    c->continuous = true;
    c->domain = MOLDTEX_DOMAIN_INTRINSIC;
  } else {
    return false;
  }
  return true;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s LIB_A LIB_B [CASE] [ROUNDS] [THREADS] [cpu|opencl]\n", argv[0]);
    return 2;
  }
  const std::string name = argc > 3 ? argv[3] : "plane-surface";
  const int rounds = argc > 4 ? std::max(1, std::atoi(argv[4])) : 30;
  const uint32_t threads = argc > 5 ? uint32_t(std::atoi(argv[5])) : 0;
  CaseSpec spec;
  if (!MakeCase(name, &spec)) {
    std::fprintf(stderr, "unknown case (or unreadable mesh file) %s\n", name.c_str());
    return 2;
  }
  if (const char* agents = std::getenv("MOLDTEX_AB_AGENTS")) spec.agents = uint32_t(std::max(1, std::atoi(agents)));
  if (const char* side = std::getenv("MOLDTEX_AB_SIDE")) spec.side = uint32_t(std::clamp(std::atoi(side), 16, 8192));
  const moldtex_mesh_desc desc = spec.mesh.desc();
  moldtex_sim_params p = mtx::default_params();
  if (spec.jones) {  // as moldtex_bench's JonesParams
    p.vision_angle = 45.0f;
    p.vision_distance = 0.9f;
    p.movement_speed = 1.0f;
    p.substeps = 1;
    p.turn_speed = 0.25f / p.time_step;
  }
  p.thread_count = threads;
  if (spec.texels_per_unit > 0)
    p.length_unit = float(spec.texels_per_unit *
                          std::sqrt(spec.mesh.total_area() / (spec.mesh.total_uv_area() * double(spec.side) * spec.side)));
  const char* seed = std::getenv("MOLDTEX_AB_SEED");
  moldtex_sim_config config = mtx::make_config(spec.side, spec.side, spec.agents, seed ? std::strtoull(seed, nullptr, 10) : 1);
  if (spec.continuous) config.model = MOLDTEX_MODEL_CONTINUOUS;
  if (argc > 6 && std::string(argv[6]) == "opencl") config.backend = MOLDTEX_BACKEND_OPENCL;
  config.domain = spec.domain;
  // The default agent is drawn on a lattice of 0.01 mesh units: rescaled to texels, as
  // moldtex_bench does.
  moldtex_continuous_params cp;
  moldtex_continuous_params_init(&cp);
  const double k = std::sqrt(spec.mesh.total_area() / (spec.mesh.total_uv_area() * double(spec.side) * spec.side)) / 0.01;
  cp.move_rate *= float(k);
  cp.sensor_distance *= float(k);
  cp.diffusion_rate *= float(k * k);
  cp.mean_lifetime = 0.5f;
  cp.activation_time = 0.2f;
  Build builds[2];
  for (int i = 0; i < 2; ++i) {
    Build& b = builds[i];
    if (!Load(argv[1 + i], &b)) return 2;
    if (b.surface_create(&desc, &b.surface) != MOLDTEX_OK || b.sim_create(b.surface, &config, &p, &b.sim) != MOLDTEX_OK) {
      std::fprintf(stderr, "%s: %s\n", argv[1 + i], b.last_error());
      return 2;
    }
    if ((spec.continuous && !spec.core_defaults && b.set_continuous(b.sim, &cp) != MOLDTEX_OK) || b.sim_step(b.sim, 10) != MOLDTEX_OK) {
      std::fprintf(stderr, "%s: %s\n", argv[1 + i], b.last_error());
      return 2;
    }
  }
  auto step = [&](Build& b) {
    const auto t0 = std::chrono::steady_clock::now();
    if (b.sim_step(b.sim, 1) != MOLDTEX_OK) {
      std::fprintf(stderr, "step failed: %s\n", b.last_error());
      std::exit(2);
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  std::vector<double> ta, tb, ratio;
  int b_faster = 0;
  for (int r = 0; r < rounds; ++r) {
    double a, b;
    if (r % 2 == 0) {
      a = step(builds[0]);
      b = step(builds[1]);
    } else {
      b = step(builds[1]);
      a = step(builds[0]);
    }
    ta.push_back(a);
    tb.push_back(b);
    ratio.push_back(b / a);
    b_faster += b < a;
  }
  const double ma = Median(ta), mb = Median(tb);
  std::printf("%s, %u agents, %d rounds: A %.1f ms (%.2f M agent-steps/s), B %.1f ms (%.2f M); B/A median %.3f, "
              "B faster in %d of %d\n",
              name.c_str(), spec.agents, rounds, 1e3 * ma, spec.agents / ma / 1e6, 1e3 * mb, spec.agents / mb / 1e6,
              Median(ratio), b_faster, rounds);
  for (Build& b : builds) {
    b.sim_release(b.sim);
    b.surface_release(b.surface);
  }
  return 0;
}
