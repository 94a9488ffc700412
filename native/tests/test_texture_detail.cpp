// moldtex_sim_config.detail: a simulation finer than its image (issue #9). At one image
// texel per pattern unit a UV sphere's poles thin out (README, "Units: Surface"); the
// same pattern simulated at two texels per unit keeps them, and the image the user gets
// stays the size they chose. What a user checks: the image is the finer simulation seen
// at the image's size (on both backends, in the live image and in the files); fields and
// maps painted on the image reach every simulated texel; a detail it cannot run is
// refused with a message; a checkpoint keeps its detail.
#include <filesystem>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include "pattern_measures.h"
#include "test_backends.h"
#include "test_util.h"

namespace mtx {
namespace {

// What the image of a simulation at `detail` must be, from the RGBA and the classes of
// the simulation at `detail` times its size: each image texel the mean of its simulated
// texels that are not outside the islands (in the order texture_detail.cpp sums them),
// alpha 1 where there is one (fewer than 4 species: channels R, G, B are species or
// copies of the one); and the image's classes.
struct Seen {
  std::vector<float> rgba;
  std::vector<uint8_t> classes;
};
Seen SeenSmaller(const std::vector<float>& fine, const std::vector<uint8_t>& fine_classes, uint32_t W, uint32_t H,
                 uint32_t detail) {
  Seen s{std::vector<float>(size_t(W) * H * 4, 0.f), std::vector<uint8_t>(size_t(W) * H, MOLDTEX_TEXEL_OUTSIDE)};
  const size_t FW = size_t(W) * detail;
  for (size_t y = 0; y < H; ++y)
    for (size_t x = 0; x < W; ++x) {
      double sum[3] = {0, 0, 0};
      uint32_t n = 0;
      uint8_t c = MOLDTEX_TEXEL_OUTSIDE;
      for (uint32_t j = 0; j < detail; ++j)
        for (uint32_t i = 0; i < detail; ++i) {
          const size_t f = (y * detail + j) * FW + x * detail + i;
          const uint8_t fc = fine_classes[f];
          if (fc == MOLDTEX_TEXEL_INSIDE || (fc == MOLDTEX_TEXEL_GUTTER && c == MOLDTEX_TEXEL_OUTSIDE)) c = fc;
          if (fc == MOLDTEX_TEXEL_OUTSIDE) continue;
          for (int k = 0; k < 3; ++k) sum[k] += fine[4 * f + k];
          ++n;
        }
      const size_t o = y * W + x;
      s.classes[o] = c;
      if (!n) continue;
      for (int k = 0; k < 3; ++k) s.rgba[4 * o + k] = float(sum[k] / n);
      s.rgba[4 * o + 3] = 1.f;  // the mask (fewer than 4 species)
    }
  return s;
}

size_t Differing(const std::vector<float>& a, const std::vector<float>& b) {
  size_t n = a.size() == b.size() ? 0 : std::max(a.size(), b.size());
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) n += a[i] != b[i];
  return n;
}

// A UV sphere (32 x 16) simulated at detail 2 in surface units (one image texel per
// unit), `steps` stepped.
struct GrownAtDetailTwo {
  SurfacePtr surface;
  moldtex_sim_config config;
  moldtex_sim_params params;
  SimPtr sim;
};
GrownAtDetailTwo SphereAtDetailTwo(uint32_t W, uint32_t H, uint32_t agents, uint64_t seed, uint32_t steps) {
  static const Mesh m = make_uv_sphere(32, 16, 1.0);
  GrownAtDetailTwo g{create_surface(m), make_config(W, H, agents, seed), default_params(), nullptr};
  EXPECT_TRUE(g.surface) << LastError();
  g.params.length_unit = float(TexelLength(m, W));
  g.config.detail = 2;
  if (g.surface) g.sim = create_sim(g.surface.get(), g.config, g.params);
  EXPECT_TRUE(g.sim) << LastError();
  if (g.sim) {
    EXPECT_EQ(moldtex_sim_step(g.sim.get(), steps), MOLDTEX_OK) << LastError();
  }
  return g;
}

// A file name in the temporary folder, unique to this process.
std::string TempPath(const std::string& extension) {
  return (std::filesystem::temp_directory_path() / ("moldtex_detail_" + std::to_string(::getpid()) + extension))
      .string();
}

class TextureDetailBackends : public ::testing::TestWithParam<Backend> {};

// The image at detail 2 (one species) and 4 (two) is, bit for bit, the simulation at 2x and 4x the size (the
// same agents, seed and pattern unit) seen at the image's size: the detail changes where
// the pattern is computed, not the pattern. The cube's UV islands leave outside and
// gutter texels, so the mean's rule at island borders is exercised too.
TEST_P(TextureDetailBackends, ImageIsTheSimulationAtDetailTimesTheSizeSeenSmaller) {
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 16;
  moldtex_sim_params p = default_params();
  p.length_unit = float(TexelLength(m, W));
  for (uint32_t detail : {2u, 4u}) {
    moldtex_sim_config coarse = make_config(W, W, 3000, 11);
    MTX_PIN_BACKEND(coarse);
    coarse.detail = detail;
    coarse.species_count = detail == 2 ? 1 : 2;  // one plane, and one per species
    moldtex_sim_config fine = coarse;
    fine.width = fine.height = W * detail;
    fine.detail = 1;
    auto a = create_sim(s.get(), coarse, p);
    auto b = create_sim(s.get(), fine, p);
    ASSERT_TRUE(a && b) << LastError();
    moldtex_sim_config got;
    moldtex_sim_config_init(&got);
    ASSERT_EQ(moldtex_sim_get_config(a.get(), &got), MOLDTEX_OK);
    EXPECT_EQ(got.width, W);
    EXPECT_EQ(got.detail, detail);
    ASSERT_EQ(moldtex_sim_step(a.get(), 40), MOLDTEX_OK) << LastError();
    ASSERT_EQ(moldtex_sim_step(b.get(), 40), MOLDTEX_OK) << LastError();
    const Seen want = SeenSmaller(read_rgba(b.get(), W * detail, W * detail), read_classes(b.get(), W * detail, W * detail),
                                  W, W, detail);
    const std::vector<float> image = read_rgba(a.get(), W, W);
    EXPECT_EQ(Differing(image, want.rgba), 0u) << "detail " << detail;
    EXPECT_EQ(read_classes(a.get(), W, W), want.classes) << "detail " << detail;
    // Not a blank image: the pattern is there (mean pheromone over the island texels,
    // of each species).
    for (uint32_t k = 0; k < coarse.species_count; ++k) {
      double sum = 0, n = 0;
      for (size_t i = 0; i < want.classes.size(); ++i)
        if (want.classes[i] == MOLDTEX_TEXEL_INSIDE) sum += image[4 * i + k], n += 1;
      EXPECT_GT(sum / n, 0.01) << "detail " << detail << ", species " << k;
    }
    // The stats measure the simulation itself.
    moldtex_sim_stats sa, sb;
    moldtex_sim_stats_init(&sa);
    moldtex_sim_stats_init(&sb);
    ASSERT_EQ(moldtex_sim_get_stats(a.get(), &sa), MOLDTEX_OK);
    ASSERT_EQ(moldtex_sim_get_stats(b.get(), &sb), MOLDTEX_OK);
    EXPECT_EQ(sa.coverage, sb.coverage);
    EXPECT_EQ(sa.presence, sb.presence);
  }
}
MTX_BACKENDS(TextureDetailBackends);

// Fields painted per image texel (obstacles in one half, an attractor in a corner) act
// on every simulated texel under it: the same as the simulation at twice the size given
// the fields scaled up texel by texel. A map (the read stimulus) likewise, and it reads
// back as given on the islands.
TEST(TextureDetail, FieldsAndMapsReachEverySimulatedTexel) {
  const Mesh m = make_uv_sphere(32, 16, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 32, D = 2;
  moldtex_sim_params p = default_params();
  p.length_unit = float(TexelLength(m, W));
  std::vector<float> fields(size_t(W) * W * 4, 0.f), stimulus(size_t(W) * W, 0.f);
  for (uint32_t y = 0; y < W; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      float* f = fields.data() + 4 * (size_t(y) * W + x);
      f[1] = x < W / 3 ? 1.f : 0.f;                  // obstacles
      f[2] = x > W / 2 && y > W / 2 ? 0.8f : 0.f;    // an attractor
      stimulus[size_t(y) * W + x] = y < W / 4 ? 0.5f : 0.f;
    }
  std::vector<float> fine_fields(size_t(W) * W * D * D * 4), fine_stimulus(size_t(W) * W * D * D);
  for (uint32_t y = 0; y < W * D; ++y)
    for (uint32_t x = 0; x < W * D; ++x) {
      const size_t from = size_t(y / D) * W + x / D, to = size_t(y) * W * D + x;
      for (int k = 0; k < 4; ++k) fine_fields[4 * to + k] = fields[4 * from + k];
      fine_stimulus[to] = stimulus[from];
    }
  moldtex_sim_config coarse = make_config(W, W, 4000, 3);
  coarse.detail = D;
  moldtex_sim_config fine = make_config(W * D, W * D, 4000, 3);
  auto a = create_sim(s.get(), coarse, p);
  auto b = create_sim(s.get(), fine, p);
  ASSERT_TRUE(a && b) << LastError();
  ASSERT_EQ(moldtex_sim_set_fields(a.get(), fields.data(), fields.size()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_set_fields(b.get(), fine_fields.data(), fine_fields.size()), MOLDTEX_OK) << LastError();
  // The sizes asked for are the image's: the simulated size is refused.
  EXPECT_EQ(moldtex_sim_set_fields(a.get(), fine_fields.data(), fine_fields.size()), MOLDTEX_ERROR_INVALID_ARGUMENT);
  ASSERT_EQ(moldtex_sim_set_map(a.get(), MOLDTEX_MAP_READ_STIMULUS, stimulus.data(), stimulus.size()), MOLDTEX_OK)
      << LastError();
  ASSERT_EQ(moldtex_sim_set_map(b.get(), MOLDTEX_MAP_READ_STIMULUS, fine_stimulus.data(), fine_stimulus.size()),
            MOLDTEX_OK)
      << LastError();
  ASSERT_EQ(moldtex_sim_reset(a.get()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_reset(b.get()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(a.get(), 30), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(b.get(), 30), MOLDTEX_OK) << LastError();
  const Seen want = SeenSmaller(read_rgba(b.get(), W * D, W * D), read_classes(b.get(), W * D, W * D), W, W, D);
  const std::vector<float> image = read_rgba(a.get(), W, W);
  EXPECT_EQ(Differing(image, want.rgba), 0u);
  // The obstacles hold no trail: the mean under them is far below the mean elsewhere.
  double under = 0, n_under = 0, rest = 0, n_rest = 0;
  for (uint32_t y = 0; y < W; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      if (want.classes[i] != MOLDTEX_TEXEL_INSIDE) continue;
      (x < W / 3 - 1 ? under : rest) += image[4 * i];
      (x < W / 3 - 1 ? n_under : n_rest) += 1;
    }
  EXPECT_LT(under / n_under, 0.2 * rest / n_rest);
  std::vector<float> back(stimulus.size(), -1.f);
  uint32_t is_set = 0;
  ASSERT_EQ(moldtex_sim_get_map(a.get(), MOLDTEX_MAP_READ_STIMULUS, back.data(), back.size(), &is_set), MOLDTEX_OK)
      << LastError();
  EXPECT_EQ(is_set, 1u);
  for (size_t i = 0; i < back.size(); ++i)
    if (want.classes[i] == MOLDTEX_TEXEL_INSIDE) {
      ASSERT_EQ(back[i], stimulus[i]) << "texel " << i;
    }
}

// The image file holds the image's texels (the same as moldtex_sim_read_rgba), not the
// simulation's.
TEST(TextureDetail, ImageFilesHoldTheImage) {
  const uint32_t W = 32, H = 16;
  const GrownAtDetailTwo g = SphereAtDetailTwo(W, H, 3000, 2, 20);
  ASSERT_TRUE(g.sim);
  moldtex_sim sim = g.sim.get();
  const std::string path = TempPath(".exr");
  ASSERT_EQ(moldtex_sim_write_image(sim, path.c_str(), MOLDTEX_IMAGE_EXR_FLOAT), MOLDTEX_OK) << LastError();
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  ASSERT_EQ(spec.width, int(W));
  ASSERT_EQ(spec.height, int(H));
  ASSERT_EQ(spec.nchannels, 1);
  std::vector<float> img(size_t(W) * H);
  ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, img.data()));
  in->close();
  std::filesystem::remove(path);
  const std::vector<float> rgba = read_rgba(sim, W, H);
  for (uint32_t y = 0; y < H; ++y)  // the file's first row is the top, read_rgba's the bottom
    for (uint32_t x = 0; x < W; ++x)
      ASSERT_EQ(img[size_t(y) * W + x], rgba[4 * (size_t(H - 1 - y) * W + x)]) << x << ", " << y;
}

// A detail the core cannot run is refused with a message saying what to change.
TEST(TextureDetail, RefusedWithAMessage) {
  const Mesh m = make_uv_sphere(16, 8, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const moldtex_sim_params p = default_params();
  moldtex_status st = MOLDTEX_OK;
  moldtex_sim_config c = make_config(64, 64, 100, 1);
  c.detail = 3;
  EXPECT_FALSE(create_sim(s.get(), c, p, &st));
  EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("1, 2 or 4"), std::string::npos) << LastError();
  c.detail = 2;
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  EXPECT_FALSE(create_sim(s.get(), c, p, &st));
  EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("MoMaS"), std::string::npos) << LastError();
  c = make_config(16384, 64, 100, 1);
  c.detail = 2;
  EXPECT_FALSE(create_sim(s.get(), c, p, &st));
  EXPECT_EQ(st, MOLDTEX_ERROR_TOO_LARGE);
  EXPECT_NE(LastError().find("lower the resolution or the detail"), std::string::npos) << LastError();
  // 0 (a zeroed struct, or a caller from before the field) is no detail.
  c = make_config(64, 64, 100, 1);
  c.detail = 0;
  auto sim = create_sim(s.get(), c, p);
  ASSERT_TRUE(sim) << LastError();
  moldtex_sim_config got;
  moldtex_sim_config_init(&got);
  ASSERT_EQ(moldtex_sim_get_config(sim.get(), &got), MOLDTEX_OK);
  EXPECT_EQ(got.detail, 1u);
}

// A checkpoint restores a detail-2 simulation exactly, and one of another detail is
// refused (its state has another size).
TEST(TextureDetail, CheckpointKeepsTheDetail) {
  const uint32_t W = 32;
  GrownAtDetailTwo g = SphereAtDetailTwo(W, W, 2000, 4, 20);
  ASSERT_TRUE(g.sim);
  moldtex_sim a = g.sim.get();
  moldtex_sim_config c = g.config;
  const std::string path = TempPath(".ckpt");
  ASSERT_EQ(moldtex_sim_save_checkpoint(a, path.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(a, 10), MOLDTEX_OK) << LastError();
  auto b = create_sim(g.surface.get(), c, g.params);
  ASSERT_TRUE(b) << LastError();
  ASSERT_EQ(moldtex_sim_load_checkpoint(b.get(), path.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(b.get(), 10), MOLDTEX_OK) << LastError();
  EXPECT_EQ(Differing(read_rgba(a, W, W), read_rgba(b.get(), W, W)), 0u);
  c.detail = 1;
  auto other = create_sim(g.surface.get(), c, g.params);
  ASSERT_TRUE(other) << LastError();
  EXPECT_EQ(moldtex_sim_load_checkpoint(other.get(), path.c_str()), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("detail"), std::string::npos) << LastError();
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace mtx
