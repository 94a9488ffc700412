// moldtex_fingerprint — a fingerprint (FNV-1a hash) of the texture and the agents after
// 60 steps of several small simulations, one line per case. Speed work that promises the
// same results bit for bit is checked by running it against the library before and after:
//
//   LD_LIBRARY_PATH=<old build>/lib build/native/bench/moldtex_fingerprint > before.txt
//   build/native/bench/moldtex_fingerprint > after.txt && diff before.txt after.txt
//
// Cases: MoMaS in texel units on a plane (2 triangles), a UV sphere and an open cylinder
// (walls), MoMaS in surface units on a torus, the continuous model on a UV sphere on the
// texture domain and on the intrinsic domain (its texture is read from the vertices),
// Gray-Scott on both domains, MoMaS with three species and at detail 2, and a bake that
// stops at a checkpoint half-way and resumes in a new simulation. All on the CPU backend
// with every core; the results do not depend on the thread count. The cases whose name
// ends in "-opencl" run on the first OpenCL device (PoCL here: its results are the same
// bit for bit from run to run on one device, not the CPU's); without a device they print
// "skipped". MOLDTEX_FINGERPRINT_OPENCL=1 runs every case on that device instead.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <string>
#include <vector>

#include <unistd.h>

#include "mesh_fixtures.h"

namespace {

uint64_t Fnv1a(const void* data, size_t bytes, uint64_t h = 1469598103934665603ull) {
  const unsigned char* c = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) {
    h ^= c[i];
    h *= 1099511628211ull;
  }
  return h;
}

struct Case {
  const char* name;
  mtx::Mesh mesh;
  uint32_t model;
  float length_unit;
  uint32_t domain = MOLDTEX_DOMAIN_TEXTURE;
  bool opencl = false;  // on the first OpenCL device
  uint32_t species = 1;
  uint32_t detail = 1;
  bool resume = false;  // checkpoint after half the steps, resume in a new simulation
};

// Pins `c` to the first OpenCL device; false when there is none.
bool pin_opencl(moldtex_sim_config& c) {
  uint32_t count = 0;
  moldtex_opencl_device_info info;
  moldtex_opencl_device_info_init(&info);
  if (moldtex_opencl_device_count(&count) != MOLDTEX_OK || count == 0 ||
      moldtex_opencl_get_device(0, &info) != MOLDTEX_OK)
    return false;
  c.backend = MOLDTEX_BACKEND_OPENCL;
  c.opencl_platform = info.platform_index;
  c.opencl_device = info.device_index;
  return true;
}

}  // namespace

int main() {
  constexpr uint32_t kSide = 256, kAgents = 20000, kSteps = 60;
  constexpr uint32_t M = MOLDTEX_MODEL_MOMAS, C = MOLDTEX_MODEL_CONTINUOUS, G = MOLDTEX_MODEL_GRAY_SCOTT;
  constexpr uint32_t T = MOLDTEX_DOMAIN_TEXTURE, I = MOLDTEX_DOMAIN_INTRINSIC;
  const mtx::Mesh sphere = mtx::make_uv_sphere(32, 16, 1.0), torus = mtx::make_torus(48, 24, 1.0, 0.35);
  const Case cases[] = {{"plane", mtx::make_quad(), M, 0.f},
                        {"sphere", sphere, M, 0.f},
                        {"cylinder", mtx::make_open_cylinder(24, 6, 0.5, 1.5), M, 0.f},
                        {"torus-surface-units", torus, M, 0.02f},
                        // Footprints of 3-4 texels a side, and six islands with gutters.
                        {"torus-wide-units", torus, M, 0.05f},
                        {"cube-surface-units", mtx::make_cube(), M, 0.03f},
                        // Rows near the poles take extra diffusion passes (small texels).
                        {"sphere-surface-units", sphere, M, 0.02f},
                        {"sphere-continuous", sphere, C, 0.f},
                        {"sphere-intrinsic", sphere, C, 0.f, I},
                        // Added before the models became plug-ins (issue #49).
                        {"sphere-gray-scott", sphere, G, 0.f},
                        {"sphere-gray-scott-intr", sphere, G, 0.f, I},
                        {"torus-species-3", torus, M, 0.f, T, false, 3},
                        {"sphere-detail-2", sphere, M, 0.02f, T, false, 1, 2},
                        {"sphere-resumed", sphere, M, 0.02f, T, false, 1, 1, true},
                        {"sphere-cont-resumed", sphere, C, 0.f, T, false, 1, 1, true},
                        {"sphere-gs-resumed", sphere, G, 0.f, T, false, 1, 1, true},
                        {"sphere-opencl", sphere, M, 0.f, T, true},
                        {"sphere-units-opencl", sphere, M, 0.02f, T, true},
                        {"sphere-cont-opencl", sphere, C, 0.f, T, true},
                        {"sphere-intr-opencl", sphere, C, 0.f, I, true},
                        {"sphere-gs-opencl", sphere, G, 0.f, T, true}};
  const std::filesystem::path checkpoint =
      std::filesystem::temp_directory_path() / ("moldtex_fingerprint_" + std::to_string(getpid()) + ".ckpt");
  const char* env = std::getenv("MOLDTEX_FINGERPRINT_OPENCL");
  const bool opencl = env && std::string(env) == "1";
  int failures = 0;
  for (const Case& c : cases) {
    moldtex_status st;
    mtx::SurfacePtr surface = mtx::create_surface(c.mesh, &st);
    moldtex_sim_params p = mtx::default_params();
    p.length_unit = c.length_unit;
    moldtex_sim_config config = mtx::make_config(kSide, kSide, kAgents, 7);
    if (opencl) config.backend = MOLDTEX_BACKEND_OPENCL;
    if (c.opencl && !pin_opencl(config)) {
      std::printf("%-22s skipped (no OpenCL device)\n", c.name);
      continue;
    }
    config.model = c.model;
    config.domain = c.domain;
    config.species_count = c.species;
    config.detail = c.detail;
    mtx::SimPtr sim = surface ? mtx::create_sim(surface.get(), config, p, &st) : nullptr;
    bool ok = sim && moldtex_sim_step(sim.get(), c.resume ? kSteps / 2 : kSteps) == MOLDTEX_OK;
    if (ok && c.resume) {
      ok = moldtex_sim_save_checkpoint(sim.get(), checkpoint.c_str()) == MOLDTEX_OK;
      sim = ok ? mtx::create_sim(surface.get(), config, p, &st) : nullptr;
      ok = sim && moldtex_sim_load_checkpoint(sim.get(), checkpoint.c_str()) == MOLDTEX_OK &&
           moldtex_sim_step(sim.get(), kSteps - kSteps / 2) == MOLDTEX_OK;
      std::filesystem::remove(checkpoint);
    }
    if (!ok) {
      std::printf("%-22s failed: %s\n", c.name, moldtex_last_error());
      ++failures;
      continue;
    }
    const std::vector<float> rgba = mtx::read_rgba(sim.get(), kSide, kSide);
    const std::vector<moldtex_surface_point> agents = mtx::read_agents(sim.get(), kAgents);
    std::printf("%-22s texture %016llx agents %016llx\n", c.name,
                static_cast<unsigned long long>(Fnv1a(rgba.data(), rgba.size() * sizeof(float))),
                static_cast<unsigned long long>(Fnv1a(agents.data(), agents.size() * sizeof(agents[0]))));
  }
  return failures == 0 ? 0 : 1;
}
