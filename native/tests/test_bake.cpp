// Image files, checkpoints and bakes (issue: animated texture sequences). Files are read
// back with OpenImageIO itself, the library a compositor or Blender would use.
#include <OpenImageIO/imageio.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <unistd.h>

#include "bake_util.h"

namespace mtx {
namespace {

namespace fs = std::filesystem;

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<std::string> names;
  std::string format;
  std::vector<float> texels;  // top row first, as stored
};

Image ReadImage(const std::string& path) {
  Image img;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return img;
  const OIIO::ImageSpec& spec = in->spec();
  img.width = spec.width;
  img.height = spec.height;
  img.channels = spec.nchannels;
  img.names = spec.channelnames;
  img.format = spec.format.c_str();
  img.texels.resize(size_t(img.width) * img.height * img.channels);
  in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.texels.data());
  return img;
}

// Value at texel (x, y) with y counted from the bottom, as the simulation counts.
float At(const Image& img, int x, int y) {
  return img.texels[(size_t(img.height - 1 - y) * img.width + x) * img.channels];
}

constexpr uint32_t kSize = 64, kAgents = 3000;

SimPtr PlaneSim(moldtex_surface s, uint64_t seed = 5) {
  return create_sim(s, make_config(kSize, kSize, kAgents, seed), default_params());
}

std::string FrameName(int frame, const char* ext) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "moldtex_%04d.%s", frame, ext);
  return buf;
}

TEST(Images, ExrFloatHoldsTheLiveTextureExactly) {
  // A float EXR is a lossless copy of the pheromone, in image order (top row first):
  // texel (x, y) of read_rgba (bottom-up) equals the file's texel at row H-1-y.
  TempDir dir;
  auto s = create_surface(make_quad());
  auto sim = PlaneSim(s.get());
  ASSERT_EQ(moldtex_sim_step(sim.get(), 40), MOLDTEX_OK);
  const std::string path = dir / "frame.exr";
  ASSERT_EQ(moldtex_sim_write_image(sim.get(), path.c_str(), MOLDTEX_IMAGE_EXR_FLOAT), MOLDTEX_OK)
      << LastError();
  const auto live = read_rgba(sim.get(), kSize, kSize);
  const Image img = ReadImage(path);
  ASSERT_EQ(img.width, int(kSize));
  ASSERT_EQ(img.height, int(kSize));
  ASSERT_EQ(img.channels, 1);  // one species, one channel
  EXPECT_EQ(img.names[0], "Y");
  EXPECT_EQ(img.format, "float");
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x)
      ASSERT_EQ(At(img, x, y), live[4 * (y * kSize + x)]) << x << "," << y;
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

TEST(Images, HalfExrAndPngQuantiseWithinTheirPrecision) {
  // Half floats keep 11 significant bits (relative error <= 2^-11 for values in [0,1]
  // plus subnormals); 8-bit PNG rounds to 1/255, 16-bit to 1/65535.
  TempDir dir;
  auto s = create_surface(make_quad());
  auto sim = PlaneSim(s.get());
  ASSERT_EQ(moldtex_sim_step(sim.get(), 40), MOLDTEX_OK);
  const auto live = read_rgba(sim.get(), kSize, kSize);
  struct Case {
    uint32_t format;
    const char* name;
    const char* type;
    double tolerance;
  } cases[] = {{MOLDTEX_IMAGE_EXR_HALF, "h.exr", "half", 1.0 / 2048},
               {MOLDTEX_IMAGE_PNG8, "p8.png", "uint8", 0.5 / 255 + 1e-6},
               {MOLDTEX_IMAGE_PNG16, "p16.png", "uint16", 0.5 / 65535 + 1e-7}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir / c.name;
    ASSERT_EQ(moldtex_sim_write_image(sim.get(), path.c_str(), c.format), MOLDTEX_OK) << LastError();
    const Image img = ReadImage(path);
    ASSERT_EQ(img.width, int(kSize));
    EXPECT_EQ(img.format, c.type);
    double worst = 0;
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x)
        worst = std::max(worst, double(std::fabs(At(img, x, y) - live[4 * (y * kSize + x)])));
    EXPECT_LE(worst, c.tolerance);
  }
}

TEST(Images, UnwritableFolderIsAnErrorNotACrash) {
  auto s = create_surface(make_quad());
  auto sim = PlaneSim(s.get());
  EXPECT_EQ(moldtex_sim_write_image(sim.get(), "/nonexistent-folder/x.exr", MOLDTEX_IMAGE_EXR_HALF),
            MOLDTEX_ERROR_IO);
  EXPECT_NE(LastError(), "");
  EXPECT_EQ(moldtex_sim_write_image(sim.get(), "", MOLDTEX_IMAGE_EXR_HALF), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_write_image(sim.get(), "/tmp/x.exr", 17), MOLDTEX_ERROR_INVALID_ARGUMENT);
}

TEST(Bake, TenFramesMatchTheLiveTextureAtThoseFrames) {
  // Frame f of a bake equals a live simulation of the same seed after
  // (f - first + 1) * steps_per_frame steps (float EXR: exact).
  TempDir dir;
  auto s = create_surface(make_quad());
  auto baked = PlaneSim(s.get());
  ASSERT_EQ(RunBake(baked.get(), BakeDesc(dir, 1, 10, 7, MOLDTEX_IMAGE_EXR_FLOAT)), MOLDTEX_OK) << LastError();
  auto live = PlaneSim(s.get());
  for (int f = 1; f <= 10; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    ASSERT_EQ(moldtex_sim_step(live.get(), 7), MOLDTEX_OK);
    const auto rgba = read_rgba(live.get(), kSize, kSize);
    const Image img = ReadImage(dir / FrameName(f, "exr"));
    ASSERT_EQ(img.width, int(kSize));
    ASSERT_EQ(img.names.size(), 1u);
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x)
        ASSERT_EQ(At(img, x, y), rgba[4 * (y * kSize + x)]);
  }
}

TEST(Bake, MetricsCsvMatchesTheFrames) {
  // The CSV row of each frame carries Eq. 1 of that frame; on the UV = xy quad every
  // texel has the same area, so coverage is the frame's mean (1e-6: float vs double sums).
  TempDir dir;
  auto s = create_surface(make_quad());
  auto sim = PlaneSim(s.get());
  ASSERT_EQ(RunBake(sim.get(), BakeDesc(dir, 3, 8, 5, MOLDTEX_IMAGE_EXR_FLOAT)), MOLDTEX_OK);
  std::ifstream csv(dir / "moldtex_metrics.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "frame,step,coverage,presence");
  int rows = 0;
  while (std::getline(csv, line)) {
    int frame;
    unsigned long long step;
    double coverage, presence;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%llu,%lf,%lf", &frame, &step, &coverage, &presence), 4) << line;
    EXPECT_EQ(frame, 3 + rows);
    EXPECT_EQ(step, 5ull * (rows + 1));
    const Image img = ReadImage(dir / FrameName(frame, "exr"));
    double sum = 0, positive = 0;
    for (float v : img.texels) {
      sum += v;
      positive += v > 0;
    }
    EXPECT_NEAR(coverage, sum / img.texels.size(), 1e-6);
    EXPECT_NEAR(presence, positive / img.texels.size(), 1e-6);
    ++rows;
  }
  EXPECT_EQ(rows, 6);
}

TEST(Bake, CancelledHalfwayLeavesOnlyWholeFramesAndResumeIsBitIdentical) {
  // Cancel a bake mid-way: every frame file on disk is complete (readable, right size)
  // and no temporary file is left; resuming from the checkpoint finishes the sequence
  // with files byte-identical to an uninterrupted bake's.
  TempDir full_dir, cut_dir;
  auto s = create_surface(make_quad());
  auto full = PlaneSim(s.get());
  ASSERT_EQ(RunBake(full.get(), BakeDesc(full_dir, 1, 12, 20, MOLDTEX_IMAGE_EXR_HALF)), MOLDTEX_OK);

  auto cut = PlaneSim(s.get());
  moldtex_bake bake = nullptr;
  const moldtex_bake_desc cut_desc = BakeDesc(cut_dir, 1, 12, 20, MOLDTEX_IMAGE_EXR_HALF);
  ASSERT_EQ(moldtex_bake_start(cut.get(), &cut_desc, &bake), MOLDTEX_OK);
  moldtex_bake_progress p;
  moldtex_bake_progress_init(&p);
  for (;;) {  // wait until a few frames exist, then cancel while it is mid-frame
    ASSERT_EQ(moldtex_bake_get_progress(bake, &p), MOLDTEX_OK);
    if (p.frames_done >= 4 || p.state != MOLDTEX_BAKE_RUNNING) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  moldtex_bake_cancel(bake);
  EXPECT_EQ(moldtex_bake_wait(bake), MOLDTEX_OK);
  ASSERT_EQ(moldtex_bake_get_progress(bake, &p), MOLDTEX_OK);
  moldtex_bake_release(bake);
  ASSERT_EQ(p.state, uint32_t(MOLDTEX_BAKE_CANCELLED));
  ASSERT_LT(p.frames_done, 12u);
  int on_disk = 0;
  for (const auto& e : fs::directory_iterator(cut_dir.path)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".partial"), std::string::npos) << name;
    if (e.path().extension() == ".exr") {
      ++on_disk;
      EXPECT_EQ(ReadImage(e.path().string()).width, int(kSize)) << name << " is not whole";
    }
  }
  EXPECT_EQ(on_disk, int(p.frames_done));

  // Resume on a fresh simulation (as after Blender was restarted).
  auto resumed = PlaneSim(s.get());
  moldtex_bake_desc d = BakeDesc(cut_dir, 1, 12, 20, MOLDTEX_IMAGE_EXR_HALF);
  d.resume = 1;
  ASSERT_EQ(RunBake(resumed.get(), d), MOLDTEX_OK) << LastError();
  for (int f = 1; f <= 12; ++f)
    EXPECT_EQ(ReadBytes(cut_dir / FrameName(f, "exr")), ReadBytes(full_dir / FrameName(f, "exr"))) << "frame " << f;
  EXPECT_EQ(ReadBytes(cut_dir / "moldtex_metrics.csv"), ReadBytes(full_dir / "moldtex_metrics.csv"));
}

TEST(Bake, SimulationIsBusyWhileBakingAndFreeAfter) {
  TempDir dir;
  auto s = create_surface(make_quad());
  auto sim = PlaneSim(s.get());
  moldtex_bake bake = nullptr;
  moldtex_bake_desc d = BakeDesc(dir, 1, 50, 50, MOLDTEX_IMAGE_EXR_HALF);
  ASSERT_EQ(moldtex_bake_start(sim.get(), &d, &bake), MOLDTEX_OK);
  EXPECT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_ERROR_BUSY);  // the bake owns it
  moldtex_bake_cancel(bake);
  EXPECT_EQ(moldtex_bake_wait(bake), MOLDTEX_OK);
  moldtex_bake_release(bake);
  EXPECT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK);
}

TEST(Bake, BadRequestsAreRefusedWithAMessage) {
  TempDir dir;
  auto s = create_surface(make_quad());
  auto sim = PlaneSim(s.get());
  moldtex_bake bake = nullptr;
  moldtex_bake_desc d = BakeDesc(dir, 5, 2, 1, MOLDTEX_IMAGE_EXR_HALF);  // last < first
  EXPECT_EQ(moldtex_bake_start(sim.get(), &d, &bake), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bake, nullptr);
  d = BakeDesc(dir, 1, 2, 0, MOLDTEX_IMAGE_EXR_HALF);  // zero steps per frame
  EXPECT_EQ(moldtex_bake_start(sim.get(), &d, &bake), MOLDTEX_ERROR_INVALID_ARGUMENT);
  d = BakeDesc(dir, 1, 2, 1, MOLDTEX_IMAGE_EXR_HALF);
  d.directory = "/nonexistent-folder";
  EXPECT_EQ(moldtex_bake_start(sim.get(), &d, &bake), MOLDTEX_ERROR_IO);
  EXPECT_NE(LastError(), "");
  d = BakeDesc(dir, 1, 2, 1, MOLDTEX_IMAGE_EXR_HALF);
  d.file_prefix = "../escape";
  EXPECT_EQ(moldtex_bake_start(sim.get(), &d, &bake), MOLDTEX_ERROR_INVALID_ARGUMENT);
}

TEST(Checkpoint, RoundTripContinuesBitIdentically) {
  // Save at step 30, run to 60; a second simulation loaded from the checkpoint and run
  // 30 steps gives the same pheromone bit for bit.
  TempDir dir;
  auto s = create_surface(make_quad());
  auto a = PlaneSim(s.get());
  ASSERT_EQ(moldtex_sim_step(a.get(), 30), MOLDTEX_OK);
  const std::string path = dir / "state.bin";
  ASSERT_EQ(moldtex_sim_save_checkpoint(a.get(), path.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(a.get(), 30), MOLDTEX_OK);
  auto b = PlaneSim(s.get());
  ASSERT_EQ(moldtex_sim_load_checkpoint(b.get(), path.c_str()), MOLDTEX_OK) << LastError();
  EXPECT_EQ(get_stats(b.get()).step_count, 30u);
  ASSERT_EQ(moldtex_sim_step(b.get(), 30), MOLDTEX_OK);
  EXPECT_EQ(read_rgba(a.get(), kSize, kSize), read_rgba(b.get(), kSize, kSize));
}

TEST(Checkpoint, RefusesAnotherMeshSeedOrDamagedFile) {
  TempDir dir;
  auto quad = create_surface(make_quad());
  auto a = PlaneSim(quad.get());
  const std::string path = dir / "state.bin";
  ASSERT_EQ(moldtex_sim_save_checkpoint(a.get(), path.c_str()), MOLDTEX_OK);
  auto cube = create_surface(make_cube());
  auto other_mesh = PlaneSim(cube.get());
  EXPECT_EQ(moldtex_sim_load_checkpoint(other_mesh.get(), path.c_str()), MOLDTEX_ERROR_INVALID_ARGUMENT);
  auto other_seed = PlaneSim(quad.get(), 99);
  EXPECT_EQ(moldtex_sim_load_checkpoint(other_seed.get(), path.c_str()), MOLDTEX_ERROR_INVALID_ARGUMENT);
  fs::resize_file(path, fs::file_size(path) / 2);  // a truncated file
  EXPECT_EQ(moldtex_sim_load_checkpoint(a.get(), path.c_str()), MOLDTEX_ERROR_IO);
  EXPECT_NE(LastError(), "");
  EXPECT_EQ(moldtex_sim_load_checkpoint(a.get(), (dir / "missing.bin").c_str()), MOLDTEX_ERROR_IO);
}

}  // namespace
}  // namespace mtx
