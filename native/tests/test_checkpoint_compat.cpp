// Issue 49, "Checkpoints as tagged, versioned sections": a checkpoint written by an earlier
// version loads in this one with nothing lost; one that cannot be read is refused with a
// message naming its format; sections a reader does not know are skipped unless marked as
// needing to be understood.
//
// The fixtures (native/tests/data/checkpoints/v<format>/) were written by
// make_checkpoint_fixtures from checkpoint_scenes.h with the library of their format
// (format 9: commit 9eee2af). Each is loaded into a simulation made from the scene's mesh
// and config with default settings, so every setting the test finds came from the file.
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bake_util.h"
#include "checkpoint_scenes.h"

namespace mtx {
namespace {

namespace fs = std::filesystem;

const fs::path kFixtures = fs::path(MOLDTEX_TEST_DATA_DIR) / "checkpoints";

struct Expected {
  uint64_t steps = 0;
  uint32_t agents = 0;
  uint64_t texture = 0, agents_hash = 0;
};

std::map<std::string, Expected> ReadExpected(const fs::path& folder) {
  std::map<std::string, Expected> out;
  std::ifstream in(folder / "expected.txt");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string name;
    Expected e;
    s >> name >> e.steps >> e.agents >> std::hex >> e.texture >> e.agents_hash;
    out[name] = e;
  }
  return out;
}

void WriteBytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

bool Contains(const std::string& text, const std::string& word) { return text.find(word) != std::string::npos; }

uint64_t TextureHash(moldtex_sim sim, const CheckpointScene& s) {
  const std::vector<float> rgba = read_rgba(sim, s.config.width, s.config.height);
  return Fnv1a(rgba.data(), rgba.size() * sizeof(float));
}

uint64_t AgentsHash(moldtex_sim sim, uint32_t count) {
  const std::vector<moldtex_surface_point> agents = read_agents(sim, count);
  return Fnv1a(agents.data(), agents.size() * sizeof(agents[0]));
}

// What the scene set, read back from `sim` (which was made with default settings).
void ExpectSceneSettings(moldtex_sim sim, const CheckpointScene& s) {
  moldtex_sim_params p;
  moldtex_sim_params_init(&p);
  ASSERT_EQ(moldtex_sim_get_params(sim, &p), MOLDTEX_OK);
  EXPECT_EQ(p.length_unit, s.params.length_unit);
  EXPECT_EQ(p.evaporation_rate, s.params.evaporation_rate);
  EXPECT_EQ(p.diffusion_rate, s.params.diffusion_rate);
  EXPECT_EQ(p.hunger_rate, s.params.hunger_rate);
  EXPECT_EQ(p.food_radius, s.params.food_radius);
  EXPECT_EQ(p.sensor_size, s.params.sensor_size);
  if (s.config.model == MOLDTEX_MODEL_MOMAS) {
    for (uint32_t k = 0; k < s.config.species_count; ++k) {
      moldtex_species_params got, want = SceneSpecies(k);
      moldtex_species_params_init(&got, k);
      ASSERT_EQ(moldtex_sim_get_species_params(sim, k, &got), MOLDTEX_OK);
      EXPECT_EQ(got.movement_speed, want.movement_speed) << "species " << k;
      EXPECT_EQ(got.vision_distance, want.vision_distance) << "species " << k;
      EXPECT_EQ(got.deposit, want.deposit) << "species " << k;
      for (uint32_t j = 0; j < MOLDTEX_MAX_SPECIES; ++j) EXPECT_EQ(got.attraction[j], want.attraction[j]);
    }
    std::vector<moldtex_food_source> food(4);
    uint32_t count = 0;
    ASSERT_EQ(moldtex_sim_get_food(sim, food.data(), uint32_t(food.size()), &count), MOLDTEX_OK) << LastError();
    const std::vector<moldtex_food_source> want = SceneFood();
    ASSERT_EQ(count, want.size());
    for (size_t j = 0; j < want.size(); ++j) {
      EXPECT_EQ(food[j].position[0], want[j].position[0]);
      EXPECT_EQ(food[j].strength, want[j].strength);
      // Eaten since (a source of amount -1 never runs out).
      EXPECT_TRUE(want[j].amount < 0 ? food[j].amount == want[j].amount
                                     : food[j].amount >= 0 && food[j].amount <= want[j].amount)
          << "food " << j << ": " << food[j].amount;
    }
  }
  if (s.config.model == MOLDTEX_MODEL_CONTINUOUS) {
    moldtex_continuous_params got, want = SceneContinuous();
    moldtex_continuous_params_init(&got);
    ASSERT_EQ(moldtex_sim_get_continuous_params(sim, &got), MOLDTEX_OK);
    EXPECT_EQ(got.move_rate, want.move_rate);
    EXPECT_EQ(got.sensor_distance, want.sensor_distance);
    EXPECT_EQ(got.deposit_rate, want.deposit_rate);
    EXPECT_EQ(got.mean_lifetime, want.mean_lifetime);
    EXPECT_EQ(got.bias_symmetry, want.bias_symmetry);
  }
  if (s.config.model == MOLDTEX_MODEL_GRAY_SCOTT) {
    moldtex_reaction_params got, want = SceneReaction();
    moldtex_reaction_params_init(&got);
    ASSERT_EQ(moldtex_sim_get_reaction_params(sim, &got), MOLDTEX_OK);
    EXPECT_EQ(got.feed, want.feed);
    EXPECT_EQ(got.kill, want.kill);
  }
  const uint32_t map = s.name == "continuous"   ? MOLDTEX_MAP_MEAN_LIFETIME
                       : s.name == "gray_scott" ? MOLDTEX_MAP_FEED
                                                : MOLDTEX_MAP_COUNT;
  if (map < MOLDTEX_MAP_COUNT) {
    std::vector<float> got(size_t(s.config.width) * s.config.height);
    uint32_t is_set = 0;
    ASSERT_EQ(moldtex_sim_get_map(sim, map, got.data(), got.size(), &is_set), MOLDTEX_OK) << LastError();
    EXPECT_EQ(is_set, 1u);
    // As a simulation given the scene's map keeps it (the gutter holds what lies across
    // each seam).
    auto surface = create_surface(s.mesh);
    auto live = create_sim(surface.get(), s.config, s.params);
    ASSERT_EQ(s.settle(live.get(), s), MOLDTEX_OK) << LastError();
    std::vector<float> want(got.size());
    ASSERT_EQ(moldtex_sim_get_map(live.get(), map, want.data(), want.size(), &is_set), MOLDTEX_OK);
    EXPECT_EQ(got, want);
  }
}

TEST(CheckpointCompat, EveryCommittedFormatLoadsWithNothingLost) {
  // Each format's files load in this version: the step count, the agents and the texture
  // as that version showed them right after writing (hashes), and every setting the
  // scene made. Saved again in today's format and loaded once more, nothing changes, and
  // both simulations go on alike.
  std::vector<fs::path> formats;
  for (const auto& entry : fs::directory_iterator(kFixtures))
    if (entry.is_directory()) formats.push_back(entry.path());
  ASSERT_FALSE(formats.empty()) << kFixtures;
  for (const fs::path& folder : formats) {
    const std::map<std::string, Expected> expected = ReadExpected(folder);
    for (const CheckpointScene& s : CheckpointScenes()) {
      SCOPED_TRACE(folder.filename().string() + "/" + s.name);
      ASSERT_EQ(expected.count(s.name), 1u);
      const Expected& e = expected.at(s.name);
      auto surface = create_surface(s.mesh);
      auto sim = create_sim(surface.get(), s.config, s.params);
      ASSERT_TRUE(sim) << LastError();
      const std::string file = (folder / (s.name + ".ckpt")).string();
      ASSERT_EQ(moldtex_sim_load_checkpoint(sim.get(), file.c_str()), MOLDTEX_OK) << LastError();
      const moldtex_sim_stats stats = get_stats(sim.get());
      EXPECT_EQ(stats.step_count, e.steps);
      EXPECT_EQ(stats.agent_count, e.agents);
      EXPECT_EQ(TextureHash(sim.get(), s), e.texture);
      EXPECT_EQ(AgentsHash(sim.get(), e.agents), e.agents_hash);
      ExpectSceneSettings(sim.get(), s);
      TempDir dir;
      const std::string again = (dir.path / "again.ckpt").string();
      ASSERT_EQ(moldtex_sim_save_checkpoint(sim.get(), again.c_str()), MOLDTEX_OK) << LastError();
      auto other = create_sim(surface.get(), s.config, s.params);
      ASSERT_EQ(moldtex_sim_load_checkpoint(other.get(), again.c_str()), MOLDTEX_OK) << LastError();
      EXPECT_EQ(TextureHash(other.get(), s), e.texture);
      EXPECT_EQ(AgentsHash(other.get(), e.agents), e.agents_hash);
      ExpectSceneSettings(other.get(), s);
      ASSERT_EQ(moldtex_sim_step(sim.get(), 4), MOLDTEX_OK) << LastError();
      ASSERT_EQ(moldtex_sim_step(other.get(), 4), MOLDTEX_OK) << LastError();
      EXPECT_EQ(TextureHash(sim.get(), s), TextureHash(other.get(), s));
      EXPECT_EQ(AgentsHash(sim.get(), e.agents), AgentsHash(other.get(), e.agents));
    }
  }
}

TEST(CheckpointCompat, ABakeResumesFromAFormatNineCheckpoint) {
  // The bake that wrote the MoMaS fixture ended at frame 3; resumed from that file, a bake
  // of frames 1-5 writes frames 4 and 5 only and keeps the five metrics rows.
  const CheckpointScene s = CheckpointScenes()[0];
  ASSERT_EQ(s.name, "momas");
  TempDir dir;
  fs::copy_file(kFixtures / "v9" / "momas.ckpt", dir.path / "momas_checkpoint.bin");
  auto surface = create_surface(s.mesh);
  auto sim = create_sim(surface.get(), s.config, s.params);
  moldtex_bake_desc d = BakeDesc(dir, 1, 5, s.steps_per_frame);
  d.file_prefix = "momas_";
  d.write_checkpoints = 1;
  d.resume = 1;
  ASSERT_EQ(RunBake(sim.get(), d), MOLDTEX_OK) << LastError();
  EXPECT_FALSE(fs::exists(dir.path / "momas_0003.exr"));
  EXPECT_TRUE(fs::exists(dir.path / "momas_0004.exr"));
  EXPECT_TRUE(fs::exists(dir.path / "momas_0005.exr"));
  EXPECT_EQ(get_stats(sim.get()).step_count, 5u * s.steps_per_frame);
  std::ifstream csv(dir.path / "momas_metrics.csv");
  size_t rows = 0;
  for (std::string line; std::getline(csv, line);) rows += !line.empty() && std::isdigit(line[0]);
  EXPECT_EQ(rows, 5u);
}

// A MoMaS checkpoint of today's format, and the offset of its "END " section.
std::vector<char> TodaysCheckpoint(const TempDir& dir, size_t* end_at) {
  auto surface = create_surface(make_quad());
  auto sim = create_sim(surface.get(), make_config(32, 32, 200, 3), default_params());
  EXPECT_EQ(moldtex_sim_step(sim.get(), 3), MOLDTEX_OK);
  const std::string path = (dir.path / "today.ckpt").string();
  EXPECT_EQ(moldtex_sim_save_checkpoint(sim.get(), path.c_str()), MOLDTEX_OK) << LastError();
  std::vector<char> bytes = ReadBytes(path);
  size_t at = 16;
  while (at + 20 <= bytes.size() && std::string(bytes.data() + at, 4) != "END ") {
    uint64_t length;
    std::memcpy(&length, bytes.data() + at + 12, 8);
    at += 20 + length;
  }
  *end_at = at;
  return bytes;
}

std::vector<char> Section(const char* tag, uint32_t version, uint32_t flags, const std::string& payload) {
  std::vector<char> s(tag, tag + 4);
  const uint64_t length = payload.size();
  s.insert(s.end(), reinterpret_cast<const char*>(&version), reinterpret_cast<const char*>(&version) + 4);
  s.insert(s.end(), reinterpret_cast<const char*>(&flags), reinterpret_cast<const char*>(&flags) + 4);
  s.insert(s.end(), reinterpret_cast<const char*>(&length), reinterpret_cast<const char*>(&length) + 8);
  s.insert(s.end(), payload.begin(), payload.end());
  return s;
}

TEST(CheckpointCompat, ALaterVersionsSectionsAreSkippedUnlessTheyMustBeUnderstood) {
  // A later version may add sections. One an older reader may skip (flags 0) loads as
  // the file without it; one marked as needing to be understood (flags 1), or a later
  // version of a known section so marked, is refused with a message naming it.
  TempDir dir;
  size_t end_at = 0;
  const std::vector<char> bytes = TodaysCheckpoint(dir, &end_at);
  ASSERT_EQ(std::string(bytes.data() + end_at, 4), "END ");
  auto surface = create_surface(make_quad());
  const std::string path = (dir.path / "later.ckpt").string();
  auto load = [&](const std::vector<char>& section) {
    std::vector<char> later(bytes.begin(), bytes.begin() + long(end_at));
    later.insert(later.end(), section.begin(), section.end());
    later.insert(later.end(), bytes.begin() + long(end_at), bytes.end());
    WriteBytes(path, later);
    auto sim = create_sim(surface.get(), make_config(32, 32, 200, 3), default_params());
    const moldtex_status st = moldtex_sim_load_checkpoint(sim.get(), path.c_str());
    return std::make_pair(st, st == MOLDTEX_OK ? read_rgba(sim.get(), 32, 32) : std::vector<float>{});
  };
  auto plain = create_sim(surface.get(), make_config(32, 32, 200, 3), default_params());
  ASSERT_EQ(moldtex_sim_load_checkpoint(plain.get(), (dir.path / "today.ckpt").c_str()), MOLDTEX_OK);
  const auto skipped = load(Section("ZZZZ", 1, 0, std::string(37, 'x')));
  ASSERT_EQ(skipped.first, MOLDTEX_OK) << LastError();
  EXPECT_EQ(skipped.second, read_rgba(plain.get(), 32, 32));
  EXPECT_EQ(load(Section("ZZZZ", 1, 1, "abc")).first, MOLDTEX_ERROR_IO);
  EXPECT_TRUE(Contains(LastError(), "ZZZZ") && Contains(LastError(), "newer Moldtex")) << LastError();
  // A second HEAD is a damaged file, not a later one.
  EXPECT_EQ(load(Section("HEAD", 1, 1, std::string(24, '\0'))).first, MOLDTEX_ERROR_IO);
  EXPECT_TRUE(Contains(LastError(), "two HEAD")) << LastError();
  // A section whose length runs past the file.
  std::vector<char> runs_over = Section("ZZZZ", 1, 0, "");
  const uint64_t huge = uint64_t(1) << 40;
  std::memcpy(runs_over.data() + 12, &huge, 8);
  EXPECT_EQ(load(runs_over).first, MOLDTEX_ERROR_IO);
}

TEST(CheckpointCompat, FormatsItCannotReadAreRefusedNamingTheirFormat) {
  TempDir dir;
  auto surface = create_surface(make_quad());
  auto sim = create_sim(surface.get(), make_config(32, 32, 200, 3), default_params());
  const std::string path = (dir.path / "other.ckpt").string();
  auto refused = [&](const std::vector<char>& bytes) {
    WriteBytes(path, bytes);
    return moldtex_sim_load_checkpoint(sim.get(), path.c_str()) == MOLDTEX_ERROR_IO ? LastError() : std::string();
  };
  // Format 8 (before the config's domain fields): too old.
  std::vector<char> eight = ReadBytes((kFixtures / "v9" / "momas.ckpt").string());
  eight[7] = '8';
  std::string why = refused(eight);
  EXPECT_TRUE(Contains(why, "format 8") && Contains(why, "bake from the start")) << why;
  // A later format that says no reader of format 10 may read it.
  size_t end_at = 0;
  std::vector<char> later = TodaysCheckpoint(dir, &end_at);
  const uint32_t format = 12, oldest_reader = 11;
  std::memcpy(later.data() + 8, &format, 4);
  std::memcpy(later.data() + 12, &oldest_reader, 4);
  why = refused(later);
  EXPECT_TRUE(Contains(why, "format 12") && Contains(why, "update Moldtex")) << why;
  // Not a checkpoint at all.
  why = refused(std::vector<char>(64, 'q'));
  EXPECT_TRUE(Contains(why, "not a Moldtex checkpoint")) << why;
  // The simulation is as it was.
  EXPECT_EQ(get_stats(sim.get()).step_count, 0u);
}

}  // namespace
}  // namespace mtx
