// Issue 14, "Defects found by fuzzing and bad inputs": each input that crashed, hung,
// loaded garbage or misled is refused with a message (or now works), and nothing is lost.
// The ray cast limits are in test_spatial.cpp.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include "bake_util.h"

namespace mtx {
namespace {

namespace fs = std::filesystem;

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

void WriteBytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

bool Contains(const std::string& text, const std::string& word) { return text.find(word) != std::string::npos; }

// Where each array of a checkpoint starts (its first element, after its uint64 count),
// following io/checkpoint.cpp's format 10: magic, format, oldest reader, then sections
// (tag, version, flags, length, payload) up to "END "; the metrics (METR: count, rows),
// the agents (AGNT: count, arrays named in 16 bytes, each with its element size and
// count) and the pheromone (PHER: count, values).
struct CheckpointLayout {
  size_t metrics = 0, triangle = 0, b1 = 0, b2 = 0, hx = 0, hy = 0, species = 0, hunger = 0,
         clock = 0, age = 0, exposure = 0, threshold = 0, pheromone = 0;
  uint64_t agents = 0, metric_rows = 0, texels = 0;
};

CheckpointLayout Layout(const std::vector<char>& bytes) {
  CheckpointLayout l;
  EXPECT_EQ(std::string(bytes.data(), 8), "MTXCHKPT") << "the test's idea of the checkpoint layout is out of date";
  size_t at = 16;
  auto u64 = [&](size_t where) {
    uint64_t n;
    std::memcpy(&n, bytes.data() + where, 8);
    return n;
  };
  for (;;) {
    const std::string tag(bytes.data() + at, 4);
    const uint64_t length = u64(at + 12);
    const size_t payload = at + 20;
    if (tag == "END ") {
      at = payload;
      break;
    }
    if (tag == "METR") {
      l.metric_rows = u64(payload);
      l.metrics = payload + 8;
    } else if (tag == "PHER") {
      l.texels = u64(payload);
      l.pheromone = payload + 8;
    } else if (tag == "AGNT") {
      l.agents = u64(payload);
      uint32_t arrays;
      std::memcpy(&arrays, bytes.data() + payload + 8, 4);
      size_t a = payload + 12;
      for (uint32_t k = 0; k < arrays; ++k) {
        const std::string name(bytes.data() + a);
        uint32_t element;
        std::memcpy(&element, bytes.data() + a + 16, 4);
        const size_t start = a + 20 + 8;
        for (auto [n, where] : {std::pair<const char*, size_t*>{"triangle", &l.triangle}, {"b1", &l.b1}, {"b2", &l.b2},
                                {"hx", &l.hx}, {"hy", &l.hy}, {"species", &l.species}, {"hunger", &l.hunger},
                                {"clock", &l.clock}, {"age", &l.age}, {"exposure", &l.exposure},
                                {"threshold", &l.threshold}})
          if (name == n) *where = start;
        a = start + u64(a + 20) * element;
      }
    }
    at = payload + length;
  }
  EXPECT_EQ(at, bytes.size()) << "the test's idea of the checkpoint layout is out of date";
  return l;
}

template <class T>
void Put(std::vector<char>& bytes, size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

constexpr uint32_t kSize = 64, kAgents = 3000;

SimPtr QuadSim(moldtex_surface s, uint64_t seed = 5) {
  return create_sim(s, make_config(kSize, kSize, kAgents, seed), default_params());
}

// ---- checkpoints ------------------------------------------------------------------------

TEST(BadCheckpoint, NonFiniteOrOutOfRangeValuesAreRefusedAndNothingIsLoaded) {
  // Issue 14: pheromone NaN, barycentrics NaN / 1e30 / -5 and a NaN heading were loaded and
  // spread NaN through the texture. Each bad value is refused (IO, the message names the
  // value's kind and where it is) and the simulation keeps its own state.
  TempDir dir;
  auto s = create_surface(make_quad());
  auto a = QuadSim(s.get());
  ASSERT_EQ(moldtex_sim_step(a.get(), 20), MOLDTEX_OK);
  const std::string good = dir / "good.bin";
  ASSERT_EQ(moldtex_sim_save_checkpoint(a.get(), good.c_str()), MOLDTEX_OK) << LastError();
  const std::vector<char> bytes = ReadBytes(good);
  const CheckpointLayout l = Layout(bytes);
  ASSERT_EQ(l.agents, kAgents);
  ASSERT_EQ(l.texels, kSize * kSize);

  auto b = QuadSim(s.get());
  ASSERT_EQ(moldtex_sim_step(b.get(), 7), MOLDTEX_OK);
  const auto rgba = read_rgba(b.get(), kSize, kSize);
  const auto agents = read_agents(b.get(), kAgents);

  struct Case {
    const char* what;
    std::function<void(std::vector<char>&)> damage;
    const char* word;
  } cases[] = {
      {"pheromone NaN", [&](auto& v) { Put(v, l.pheromone + 4 * 100, kNaN); }, "pheromone"},
      {"pheromone -1", [&](auto& v) { Put(v, l.pheromone + 4 * 100, -1.f); }, "pheromone"},
      {"pheromone 2", [&](auto& v) { Put(v, l.pheromone + 4 * 100, 2.f); }, "pheromone"},
      {"pheromone inf", [&](auto& v) { Put(v, l.pheromone + 4 * 100, kInf); }, "texel 100"},
      {"b1 NaN", [&](auto& v) { Put(v, l.b1 + 4 * 3, kNaN); }, "barycentric"},
      {"b1 1e30", [&](auto& v) { Put(v, l.b1 + 4 * 3, 1e30f); }, "agent 3"},
      {"b2 -5", [&](auto& v) { Put(v, l.b2 + 4 * 3, -5.f); }, "barycentric"},
      {"b1 + b2 > 1", [&](auto& v) { Put(v, l.b1 + 4 * 3, 0.7f); Put(v, l.b2 + 4 * 3, 0.7f); }, "barycentric"},
      {"heading NaN", [&](auto& v) { Put(v, l.hx + 4 * 4, kNaN); }, "heading"},
      {"heading not unit", [&](auto& v) { Put(v, l.hx + 4 * 4, 3.f); Put(v, l.hy + 4 * 4, 0.f); }, "agent 4"},
      {"triangle out of range", [&](auto& v) { Put(v, l.triangle + 4 * 5, uint32_t{99}); }, "triangle"},
      {"hunger NaN", [&](auto& v) { Put(v, l.hunger + 4 * 6, kNaN); }, "hunger"},
      {"age NaN", [&](auto& v) { Put(v, l.age + 4 * 8, kNaN); }, "agent 8"},
      {"clock -1", [&](auto& v) { Put(v, l.clock + 4 * 8, -1.f); }, "clock"},
      {"threshold inf", [&](auto& v) { Put(v, l.threshold + 4 * 9, kInf); }, "agent 9"},
      {"species out of range", [&](auto& v) { Put(v, l.species + 7, uint8_t{3}); }, "species"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    std::vector<char> damaged = bytes;
    c.damage(damaged);
    const std::string path = dir / "damaged.bin";
    WriteBytes(path, damaged);
    EXPECT_EQ(moldtex_sim_load_checkpoint(b.get(), path.c_str()), MOLDTEX_ERROR_IO);
    EXPECT_TRUE(Contains(LastError(), c.word)) << LastError();
    EXPECT_TRUE(Contains(LastError(), "damaged")) << LastError();
    // Nothing was loaded.
    EXPECT_EQ(get_stats(b.get()).step_count, 7u);
    ASSERT_EQ(read_rgba(b.get(), kSize, kSize), rgba);
    const auto now = read_agents(b.get(), kAgents);
    ASSERT_EQ(now.size(), agents.size());
    for (size_t i = 0; i < now.size(); ++i)
      ASSERT_TRUE(now[i].triangle == agents[i].triangle &&
                  std::memcmp(now[i].bary, agents[i].bary, sizeof(now[i].bary)) == 0)
          << "agent " << i;
  }
  // The undamaged file loads and continues as the original.
  ASSERT_EQ(moldtex_sim_load_checkpoint(b.get(), good.c_str()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(a.get(), 5), MOLDTEX_OK);
  ASSERT_EQ(moldtex_sim_step(b.get(), 5), MOLDTEX_OK);
  EXPECT_EQ(read_rgba(a.get(), kSize, kSize), read_rgba(b.get(), kSize, kSize));
}

TEST(BadCheckpoint, EmptyArraysLoad) {
  // A checkpoint with no agents (all erased), no metrics, no fields and no food: every
  // array is empty (memcpy(NULL, .., 0) on load was undefined behaviour, seen by UBSan).
  TempDir dir;
  auto s = create_surface(make_quad());
  auto a = QuadSim(s.get());
  moldtex_brush brush;
  moldtex_brush_init(&brush);
  brush.radius = 10.f;
  brush.falloff = 0.f;
  uint32_t removed = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(a.get(), &brush, 1, &removed), MOLDTEX_OK) << LastError();
  ASSERT_EQ(removed, kAgents);
  ASSERT_EQ(moldtex_sim_step(a.get(), 3), MOLDTEX_OK);
  const std::string path = dir / "empty.bin";
  ASSERT_EQ(moldtex_sim_save_checkpoint(a.get(), path.c_str()), MOLDTEX_OK) << LastError();
  const CheckpointLayout l = Layout(ReadBytes(path));
  EXPECT_EQ(l.agents, 0u);
  EXPECT_EQ(l.metric_rows, 0u);
  auto b = QuadSim(s.get());
  ASSERT_EQ(moldtex_sim_load_checkpoint(b.get(), path.c_str()), MOLDTEX_OK) << LastError();
  EXPECT_EQ(get_stats(b.get()).agent_count, 0u);
  EXPECT_EQ(get_stats(b.get()).step_count, 3u);
  EXPECT_EQ(moldtex_sim_step(b.get(), 2), MOLDTEX_OK);
}

TEST(BadCheckpoint, MetricsRowsAreValidatedAndAFrameOfInt32MaxIsRefused) {
  // Resuming a checkpoint whose last frame was INT32_MAX computed frame + 1 (signed
  // overflow). Frames must increase within the bake's 0 .. 999999; coverage and presence
  // are fractions. Each bad row is refused by a resumed bake and by a plain load.
  TempDir dir;
  auto s = create_surface(make_quad());
  auto sim = QuadSim(s.get());
  ASSERT_EQ(RunBake(sim.get(), BakeDesc(dir, 1, 3, 2)), MOLDTEX_OK) << LastError();
  const std::string path = dir / "moldtex_checkpoint.bin";
  const std::vector<char> bytes = ReadBytes(path);
  const CheckpointLayout l = Layout(bytes);
  ASSERT_EQ(l.metric_rows, 3u);
  const size_t last = l.metrics + 32 * 2;
  struct Case {
    const char* what;
    std::function<void(std::vector<char>&)> damage;
    const char* word;
  } cases[] = {
      {"frame INT32_MAX", [&](auto& v) { Put(v, last, std::numeric_limits<int32_t>::max()); }, "frame"},
      {"frame -1", [&](auto& v) { Put(v, last, int32_t{-1}); }, "frame"},
      {"frames not increasing", [&](auto& v) { Put(v, last, int32_t{1}); }, "frame"},
      {"coverage NaN", [&](auto& v) { Put(v, last + 16, std::numeric_limits<double>::quiet_NaN()); }, "coverage"},
      {"presence 7", [&](auto& v) { Put(v, last + 24, 7.0); }, "presence"},
      {"step after the checkpoint", [&](auto& v) { Put(v, last + 8, uint64_t{1} << 60); }, "step"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    std::vector<char> damaged = bytes;
    c.damage(damaged);
    WriteBytes(path, damaged);
    auto fresh = QuadSim(s.get());
    EXPECT_EQ(moldtex_sim_load_checkpoint(fresh.get(), path.c_str()), MOLDTEX_ERROR_IO);
    EXPECT_TRUE(Contains(LastError(), c.word)) << LastError();
    EXPECT_TRUE(Contains(LastError(), "metrics row 2")) << LastError();
    moldtex_bake_desc d = BakeDesc(dir, 1, 5, 2);
    d.resume = 1;
    std::string message;
    EXPECT_EQ(RunBake(fresh.get(), d, &message), MOLDTEX_ERROR_IO);
    EXPECT_TRUE(Contains(message, c.word)) << message;
  }
}

TEST(BakeResume, RewritesAMetricsCsvThatLostItsLastRow) {
  // A kill between the checkpoint's rename and the CSV's leaves the CSV a row short. A
  // resumed bake rewrites it from the checkpoint's rows, also when every frame is done.
  TempDir dir;
  auto s = create_surface(make_quad());
  auto sim = QuadSim(s.get());
  ASSERT_EQ(RunBake(sim.get(), BakeDesc(dir, 1, 4, 3)), MOLDTEX_OK) << LastError();
  const std::string csv = dir / "moldtex_metrics.csv";
  const std::vector<char> whole = ReadBytes(csv);
  ASSERT_EQ(std::count(whole.begin(), whole.end(), '\n'), 5);  // header + 4 frames
  std::vector<char> short_csv(whole.begin(), whole.end() - 1);
  short_csv.erase(std::find(short_csv.rbegin(), short_csv.rend(), '\n').base(), short_csv.end());
  ASSERT_EQ(std::count(short_csv.begin(), short_csv.end(), '\n'), 4);
  WriteBytes(csv, short_csv);
  auto resumed = QuadSim(s.get());
  moldtex_bake_desc d = BakeDesc(dir, 1, 4, 3);
  d.resume = 1;
  ASSERT_EQ(RunBake(resumed.get(), d), MOLDTEX_OK) << LastError();
  EXPECT_EQ(ReadBytes(csv), whole);
  // With frames left to bake, the rows already there are kept and the new ones appended.
  WriteBytes(csv, short_csv);
  auto longer = QuadSim(s.get());
  d.last_frame = 6;
  ASSERT_EQ(RunBake(longer.get(), d), MOLDTEX_OK) << LastError();
  const std::vector<char> after = ReadBytes(csv);
  EXPECT_EQ(std::count(after.begin(), after.end(), '\n'), 7);
  EXPECT_TRUE(std::equal(whole.begin(), whole.end(), after.begin()));
}

// ---- surfaces ------------------------------------------------------------------------------

TEST(BadSurface, UvsFarOutsideTheImageAreRefused) {
  // Finite UVs of 1e30 overflowed the float -> int texel conversions (undefined behaviour).
  // Beyond +-1e4 they are refused, naming the UV; UDIM-like tiles and UVs slightly outside
  // [0, 1] still work, up to the limit itself.
  for (float bad : {1e30f, -1e30f, 1e5f, -10001.f, 3e38f}) {
    Mesh m = make_quad();
    m.uvs[3] = bad;
    moldtex_status st = MOLDTEX_OK;
    EXPECT_FALSE(create_surface(m, &st)) << bad;
    EXPECT_EQ(st, MOLDTEX_ERROR_MISSING_UVS) << bad;
    EXPECT_TRUE(Contains(LastError(), "UV 1")) << LastError();
    EXPECT_TRUE(Contains(LastError(), "10000")) << LastError();
  }
  for (float shift : {-0.3f, 5.f, 99.f, -9999.f, 9999.f}) {
    SCOPED_TRACE(shift);
    Mesh m = make_quad();
    for (float& v : m.uvs) v += shift;
    auto s = create_surface(m);
    ASSERT_TRUE(s) << LastError();
    auto sim = create_sim(s.get(), make_config(16, 16, 200, 3), default_params());
    ASSERT_TRUE(sim) << LastError();
    EXPECT_EQ(moldtex_sim_step(sim.get(), 3), MOLDTEX_OK) << LastError();
    // The widest brush image: texel = int(u * 65536) must stay in range (a small radius:
    // the texels are 1/65536 wide).
    moldtex_brush b;
    moldtex_brush_init(&b);
    b.radius = 0.002f;
    std::vector<float> wide(size_t(65536) * 4, 0.f);
    EXPECT_EQ(moldtex_surface_paint(s.get(), 65536, 1, wide.data(), wide.size(), &b, nullptr), MOLDTEX_OK)
        << LastError();
  }
}

TEST(BadSurface, MeshesFloatCannotCarryAreRefusedWithTheirSize) {
  // A mesh scaled by 1e-30 was accepted and then said "nowhere to spawn agents: paint a
  // spawn region" (its float areas were 0). Sizes float cannot carry are refused at
  // create, saying so; small and large but sane meshes work.
  struct Case {
    double scale, offset;
    const char* word;
  } bad[] = {{1e-30, 0, "too small"}, {1e-12, 0, "too small"}, {1e14, 0, "too large"},
             {1, 1e16, "coordinate"}, {1, -3e38, "coordinate"}};
  for (const Case& c : bad) {
    Mesh m = make_quad();
    for (float& p : m.positions) p = float(p * c.scale + c.offset);
    moldtex_status st = MOLDTEX_OK;
    EXPECT_FALSE(create_surface(m, &st)) << c.scale;
    EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_MESH) << c.scale;
    EXPECT_TRUE(Contains(LastError(), c.word)) << LastError();
  }
  for (double scale : {1e-8, 1e-3, 1e11}) {
    SCOPED_TRACE(scale);
    Mesh m = make_quad();
    for (float& p : m.positions) p = float(p * scale);
    auto s = create_surface(m);
    ASSERT_TRUE(s) << LastError();
    auto sim = create_sim(s.get(), make_config(32, 32, 500, 3), default_params());
    ASSERT_TRUE(sim) << LastError();
    EXPECT_EQ(moldtex_sim_step(sim.get(), 3), MOLDTEX_OK) << LastError();
    EXPECT_GT(get_stats(sim.get()).coverage, 0.0);
  }
}

// ---- messages ------------------------------------------------------------------------------

TEST(BadInputMessages, SayWhatIsWrong) {
  auto s = create_surface(make_quad());
  // A seed radius of 1e30 is finite and > 0: the message gives the real limit and value.
  moldtex_sim_config c = make_config(32, 32, 100, 1);
  c.seed_shape = MOLDTEX_SEED_CIRCLE;
  c.seed_radius = 1e30f;
  moldtex_status st = MOLDTEX_OK;
  EXPECT_FALSE(create_sim(s.get(), c, default_params(), &st));
  EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(Contains(LastError(), "below 1e30")) << LastError();
  EXPECT_TRUE(Contains(LastError(), "1e+30")) << LastError();
  // The same for the brush radius.
  moldtex_brush b;
  moldtex_brush_init(&b);
  b.radius = 1e30f;
  std::vector<float> img(32 * 32 * 4, 0.f);
  EXPECT_EQ(moldtex_surface_paint(s.get(), 32, 32, img.data(), img.size(), &b, nullptr),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(Contains(LastError(), "1e30")) << LastError();
  // A denormal radius made the sampling step 0: a dab that never ended (fuzz target).
  b.radius = 4.2e-45f;
  EXPECT_EQ(moldtex_surface_paint(s.get(), 32, 32, img.data(), img.size(), &b, nullptr),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(Contains(LastError(), "between 1e-30 and 1e30")) << LastError();
  b.radius = 1e-30f;
  EXPECT_EQ(moldtex_surface_paint(s.get(), 32, 32, img.data(), img.size(), &b, nullptr), MOLDTEX_OK)
      << LastError();
  // A 300-character prefix has no '/': the message says it is too long.
  TempDir dir;
  auto sim = QuadSim(s.get());
  moldtex_bake_desc d = BakeDesc(dir, 1, 2, 1);
  const std::string prefix(300, 'a');
  d.file_prefix = prefix.c_str();
  moldtex_bake bake = nullptr;
  EXPECT_EQ(moldtex_bake_start(sim.get(), &d, &bake), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(Contains(LastError(), "300 characters")) << LastError();
  EXPECT_FALSE(Contains(LastError(), "'/'")) << LastError();
  d.file_prefix = "a/b";
  EXPECT_EQ(moldtex_bake_start(sim.get(), &d, &bake), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(Contains(LastError(), "'/'")) << LastError();
}

// ---- brush work ------------------------------------------------------------------------------

// Blender's default plane: 2 x 2, two triangles, UV = the unit square.
Mesh DefaultPlane() {
  Mesh m;
  m.positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  m.triangles = {0, 1, 2, 0, 2, 3};
  m.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  m.triangle_uvs = m.triangles;
  return m;
}

double Seconds(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(BrushWork, ADabOnASliverEndsItsStuckRays) {
  // A triangle 1 long and 1e-7 wide under 16 x 16 texels: every step of a dab's rays
  // bounced across the sliver thousands of times (the fuzz target found dabs that took
  // minutes). Rays caught like that end; the dab returns at once and paints its texel.
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0.5f, 1e-7f, 0};
  m.triangles = {0, 1, 2};
  m.uvs = {0, 0, 1, 0, 0.5f, 1};
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_brush b;
  moldtex_brush_init(&b);
  b.radius = 0.5f;
  std::vector<float> img(16 * 16 * 4, 0.f);
  uint32_t changed = 0;
  const double t = Seconds([&] {
    EXPECT_EQ(moldtex_surface_paint(s.get(), 16, 16, img.data(), img.size(), &b, &changed), MOLDTEX_OK)
        << LastError();
  });
  EXPECT_GE(changed, 1u);
  EXPECT_LT(t, 5.0);  // minutes before; ~10 ms now (seconds under sanitizers)
}

TEST(BrushWork, AHugeRadiusCostsNoMoreThanADiskOverTheWholeMesh) {
  // A dab's work grew with its radius without bound (radius 1e4 on the 2 x 2 plane: 4.3 s
  // paint, 6.7 s erase at 1024^2; radius 1e29 never finished). Now a disk that holds the
  // whole plane walks only about twice the plane's extent: radius 1e4 and 1e29 cost about
  // what radius 4 (a disk over the whole plane) costs, and still paint every texel, erase
  // every agent and place agents on the plane. Times are compared with each other, not
  // with a clock budget, so the test holds on a loaded machine and under sanitizers.
  const Mesh m = DefaultPlane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  constexpr uint32_t kTex = 128;
  std::vector<float> img(kTex * kTex * 4);
  moldtex_brush b;
  moldtex_brush_init(&b);
  b.falloff = 0.f;
  auto paint = [&](float radius) {
    b.radius = radius;
    std::fill(img.begin(), img.end(), 0.f);
    uint32_t changed = 0;
    const double t = Seconds([&] {
      EXPECT_EQ(moldtex_surface_paint(s.get(), kTex, kTex, img.data(), img.size(), &b, &changed), MOLDTEX_OK)
          << LastError();
    });
    EXPECT_GE(changed, kTex * kTex * 99 / 100) << "radius " << radius;
    return t;
  };
  const double whole = std::max(paint(4.f), 1e-3);  // the farthest corner is 1.9 away
  EXPECT_LT(paint(1e4f), 4 * whole + 0.05);
  EXPECT_LT(paint(1e29f), 4 * whole + 0.05);

  auto sim = create_sim(s.get(), make_config(kTex, kTex, 20000, 2), default_params());
  ASSERT_TRUE(sim) << LastError();
  b.radius = 1e29f;
  uint32_t removed = 0;
  const double erase = Seconds([&] {
    EXPECT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 1, &removed), MOLDTEX_OK) << LastError();
  });
  EXPECT_EQ(removed, 20000u);
  EXPECT_LT(erase, 4 * whole + 0.05);
  const double add = Seconds([&] {
    EXPECT_EQ(moldtex_sim_add_agents(sim.get(), &b, 2000, 2), MOLDTEX_OK) << LastError();
  });
  EXPECT_LT(add, 4 * whole + 0.05);
  const auto agents = read_agents(sim.get(), 2000);
  ASSERT_EQ(agents.size(), 2000u);
  for (const auto& p : agents) ASSERT_TRUE(ValidPoint(p, 2));
  EXPECT_EQ(moldtex_sim_step(sim.get(), 2), MOLDTEX_OK);
  // A soft falloff still weighs by the true radius: nearly full weight everywhere.
  b.radius = 1e4f;
  b.falloff = 1.f;
  b.strength = 1.f;
  std::fill(img.begin(), img.end(), 0.f);
  ASSERT_EQ(moldtex_surface_paint(s.get(), kTex, kTex, img.data(), img.size(), &b, nullptr), MOLDTEX_OK);
  size_t full = 0;
  for (size_t i = 0; i < img.size(); i += 4) full += img[i] > 0.999f;
  EXPECT_GE(full, kTex * kTex * 99 / 100);
}

}  // namespace
}  // namespace mtx
