// moldtex_fingerprint — a fingerprint (FNV-1a hash) of the texture and the agents after
// 60 steps of several small simulations, one line per case. Speed work that promises the
// same results bit for bit is checked by running it against the library before and after:
//
//   LD_LIBRARY_PATH=<old build>/lib build/native/bench/moldtex_fingerprint > before.txt
//   build/native/bench/moldtex_fingerprint > after.txt && diff before.txt after.txt
//
// Cases: MoMaS in texel units on a plane (2 triangles), a UV sphere and an open cylinder
// (walls), MoMaS in surface units on a torus, the continuous model on a UV sphere on the
// texture domain and on the intrinsic domain (its texture is read from the vertices). All
// on the CPU backend with every core; the results do not depend on the thread count.
// MOLDTEX_FINGERPRINT_OPENCL=1 runs them on the first OpenCL device instead (its results
// are the same bit for bit from run to run on one device, not the CPU's).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

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
  bool continuous;
  float length_unit;
  uint32_t domain = MOLDTEX_DOMAIN_TEXTURE;
};

}  // namespace

int main() {
  constexpr uint32_t kSide = 256, kAgents = 20000, kSteps = 60;
  const Case cases[] = {{"plane", mtx::make_quad(), false, 0.f},
                        {"sphere", mtx::make_uv_sphere(32, 16, 1.0), false, 0.f},
                        {"cylinder", mtx::make_open_cylinder(24, 6, 0.5, 1.5), false, 0.f},
                        {"torus-surface-units", mtx::make_torus(48, 24, 1.0, 0.35), false, 0.02f},
                        // Footprints of 3-4 texels a side, and six islands with gutters.
                        {"torus-wide-units", mtx::make_torus(48, 24, 1.0, 0.35), false, 0.05f},
                        {"cube-surface-units", mtx::make_cube(), false, 0.03f},
                        // Rows near the poles take extra diffusion passes (small texels).
                        {"sphere-surface-units", mtx::make_uv_sphere(32, 16, 1.0), false, 0.02f},
                        {"sphere-continuous", mtx::make_uv_sphere(32, 16, 1.0), true, 0.f},
                        {"sphere-intrinsic", mtx::make_uv_sphere(32, 16, 1.0), true, 0.f, MOLDTEX_DOMAIN_INTRINSIC}};
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
    if (c.continuous) config.model = MOLDTEX_MODEL_CONTINUOUS;
    config.domain = c.domain;
    mtx::SimPtr sim = surface ? mtx::create_sim(surface.get(), config, p, &st) : nullptr;
    if (!sim || moldtex_sim_step(sim.get(), kSteps) != MOLDTEX_OK) {
      std::printf("%-20s failed: %s\n", c.name, moldtex_last_error());
      ++failures;
      continue;
    }
    const std::vector<float> rgba = mtx::read_rgba(sim.get(), kSide, kSide);
    const std::vector<moldtex_surface_point> agents = mtx::read_agents(sim.get(), kAgents);
    std::printf("%-20s texture %016llx agents %016llx\n", c.name,
                static_cast<unsigned long long>(Fnv1a(rgba.data(), rgba.size() * sizeof(float))),
                static_cast<unsigned long long>(Fnv1a(agents.data(), agents.size() * sizeof(agents[0]))));
  }
  return failures == 0 ? 0 : 1;
}
