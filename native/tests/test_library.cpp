// Library-level contract: ABI version, version string, init functions, error messages.
#include <thread>

#include "test_util.h"

namespace mtx {
namespace {

TEST(Library, AbiVersionMatchesHeader) {
  // The add-on refuses to load a library whose ABI differs from the header it was built for.
  EXPECT_EQ(moldtex_abi_version(), MOLDTEX_ABI_VERSION);
}

TEST(Library, VersionStringIsNonEmpty) {
  const char* v = moldtex_version_string();
  ASSERT_NE(v, nullptr);
  EXPECT_GT(std::strlen(v), 0u);
  EXPECT_EQ(std::string(v), std::string(moldtex_version_string()));  // static storage
}

TEST(Library, InitFunctionsSetStructSize) {
  // struct_size is how the core tells old callers from new ones: it must be the full size.
  moldtex_mesh_desc d;
  std::memset(&d, 0xAB, sizeof d);
  moldtex_mesh_desc_init(&d);
  EXPECT_EQ(d.struct_size, sizeof(moldtex_mesh_desc));
  EXPECT_EQ(d.positions, nullptr);
  EXPECT_EQ(d.triangle_uvs, nullptr);

  moldtex_surface_info i;
  moldtex_surface_info_init(&i);
  EXPECT_EQ(i.struct_size, sizeof(moldtex_surface_info));

  moldtex_sim_config c;
  moldtex_sim_config_init(&c);
  EXPECT_EQ(c.struct_size, sizeof(moldtex_sim_config));

  moldtex_sim_params p;
  moldtex_sim_params_init(&p);
  EXPECT_EQ(p.struct_size, sizeof(moldtex_sim_params));

  moldtex_sim_stats s;
  moldtex_sim_stats_init(&s);
  EXPECT_EQ(s.struct_size, sizeof(moldtex_sim_stats));
}

TEST(Library, DefaultConfigIsUsable) {
  // A caller that only fills in nothing but the init defaults gets a valid simulation.
  moldtex_sim_config c;
  moldtex_sim_config_init(&c);
  EXPECT_GE(c.width, 8u);
  EXPECT_LE(c.width, 16384u);
  EXPECT_GE(c.height, 8u);
  EXPECT_LE(c.height, 16384u);
  EXPECT_GE(c.agent_count, 1u);
  EXPECT_LE(c.agent_count, 67108864u);
}

TEST(Library, DefaultParamsWithinHardLimitsAndSixtyHertz) {
  // Header: one step is one tick of the paper's 60 Hz clock by default; every default
  // must lie inside the documented hard limits.
  const moldtex_sim_params p = default_params();
  EXPECT_FLOAT_EQ(p.time_step, 1.0f / 60.0f);
  EXPECT_GE(p.movement_speed, 0.0f);
  EXPECT_LE(p.movement_speed, 64.0f);
  EXPECT_GE(p.turn_speed, 0.0f);
  EXPECT_LE(p.turn_speed, 1000.0f);
  EXPECT_GE(p.vision_distance, 0.0f);
  EXPECT_LE(p.vision_distance, 50.0f);
  EXPECT_GE(p.vision_angle, 0.0f);
  EXPECT_LE(p.vision_angle, 180.0f);
  EXPECT_GE(p.evaporation_rate, 0.0f);
  EXPECT_LE(p.evaporation_rate, 1000.0f);
  EXPECT_GE(p.diffusion_rate, 0.0f);
  EXPECT_GE(p.deposit, 0.0f);
  EXPECT_LE(p.deposit, 1.0f);
  EXPECT_GE(p.substeps, 1u);
  EXPECT_LE(p.substeps, 64u);
  EXPECT_EQ(p.thread_count, 0u);  // header: 0 = all cores
}

TEST(Library, LastErrorIsPerThread) {
  // Header: moldtex_last_error() explains the last failure *on the calling thread*;
  // a failure on another thread must not overwrite ours.
  moldtex_surface s = nullptr;
  ASSERT_NE(moldtex_surface_create(nullptr, &s), MOLDTEX_OK);
  const std::string mine = LastError();
  ASSERT_FALSE(mine.empty());

  std::string theirs;
  std::thread other([&] {
    EXPECT_EQ(std::string(moldtex_last_error()), "");  // fresh thread: no failure yet
    float g[4];
    EXPECT_NE(moldtex_surface_get_metric(nullptr, 0, g), MOLDTEX_OK);
    theirs = moldtex_last_error();
  });
  other.join();
  EXPECT_FALSE(theirs.empty());
  EXPECT_EQ(LastError(), mine);
}

}  // namespace
}  // namespace mtx
