// make_checkpoint_fixtures — writes the checkpoint of each scene of checkpoint_scenes.h,
// in the format of the library it runs with, into a folder:
//
//   build/native/tests/make_checkpoint_fixtures native/tests/data/checkpoints/v<format>
//
// Each scene is baked (frames of steps, writing checkpoints) and <scene>.ckpt is the last
// frame's checkpoint; expected.txt lists, per scene, the step count, the agent count and
// FNV-1a hashes of moldtex_sim_read_rgba and moldtex_sim_read_agents right after it.
// Run once when the checkpoint format changes, and commit the folder: the test
// (test_checkpoint_compat.cpp) loads every committed format in every later version.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "checkpoint_scenes.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_FOLDER\n", argv[0]);
    return 2;
  }
  const fs::path out = argv[1];
  fs::create_directories(out);
  const fs::path work = fs::temp_directory_path() / "moldtex_checkpoint_fixtures";
  fs::remove_all(work);
  fs::create_directories(work);
  std::ofstream expected(out / "expected.txt");
  expected << "# scene steps agents texture agents_hash (" << moldtex_version_string() << ")\n";
  for (const mtx::CheckpointScene& s : mtx::CheckpointScenes()) {
    moldtex_status st;
    mtx::SurfacePtr surface = mtx::create_surface(s.mesh, &st);
    mtx::SimPtr sim = surface ? mtx::create_sim(surface.get(), s.config, s.params, &st) : nullptr;
    if (!sim || s.settle(sim.get(), s) != MOLDTEX_OK) {
      std::fprintf(stderr, "%s: %s\n", s.name.c_str(), moldtex_last_error());
      return 1;
    }
    moldtex_bake_desc d;
    moldtex_bake_desc_init(&d);
    const std::string dir = work.string();
    d.directory = dir.c_str();
    const std::string prefix = s.name + "_";
    d.file_prefix = prefix.c_str();
    d.first_frame = 1;
    d.last_frame = int32_t(s.frames);
    d.steps_per_frame = s.steps_per_frame;
    d.write_checkpoints = 1;
    moldtex_bake bake = nullptr;
    if (moldtex_bake_start(sim.get(), &d, &bake) != MOLDTEX_OK || moldtex_bake_wait(bake) != MOLDTEX_OK) {
      std::fprintf(stderr, "%s: bake: %s\n", s.name.c_str(), moldtex_last_error());
      return 1;
    }
    moldtex_bake_release(bake);
    fs::copy_file(work / (prefix + "checkpoint.bin"), out / (s.name + ".ckpt"), fs::copy_options::overwrite_existing);
    moldtex_sim_stats stats;
    moldtex_sim_stats_init(&stats);
    moldtex_sim_get_stats(sim.get(), &stats);
    const std::vector<float> rgba = mtx::read_rgba(sim.get(), s.config.width, s.config.height);
    const std::vector<moldtex_surface_point> agents = mtx::read_agents(sim.get(), stats.agent_count);
    char line[256];
    std::snprintf(line, sizeof line, "%s %llu %u %016llx %016llx\n", s.name.c_str(),
                  static_cast<unsigned long long>(stats.step_count), stats.agent_count,
                  static_cast<unsigned long long>(mtx::Fnv1a(rgba.data(), rgba.size() * 4)),
                  static_cast<unsigned long long>(mtx::Fnv1a(agents.data(), agents.size() * sizeof(agents[0]))));
    expected << line;
    std::printf("%s", line);
  }
  fs::remove_all(work);
  return 0;
}
