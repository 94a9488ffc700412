// The C boundary refuses bad input with the documented status and a message, and never
// crashes the host (a crash of Blender loses the artist's unsaved work).
//
// Where the header's enum comments allow two readings the test accepts both and says
// why: e.g. a NaN coordinate is both "NaN" (INVALID_ARGUMENT) and a bad mesh
// (INVALID_MESH); a width of 100000 is both "out of range" and "absurd size".
#include <initializer_list>
#include <limits>

#include "test_util.h"

namespace mtx {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

::testing::AssertionResult FailsWith(moldtex_status got, std::initializer_list<moldtex_status> ok,
                                     const char* what) {
  bool match = false;
  for (moldtex_status s : ok) match |= (got == s);
  if (!match) return ::testing::AssertionFailure() << what << ": returned status " << int(got);
  const std::string msg = moldtex_last_error();
  // A message a user can act on: more than a word.
  if (msg.size() < 8) return ::testing::AssertionFailure() << what << ": message '" << msg << "'";
  return ::testing::AssertionSuccess();
}

#define EXPECT_FAILS(call, ...) \
  EXPECT_TRUE(FailsWith((call), {__VA_ARGS__}, #call))

constexpr moldtex_status ARG = MOLDTEX_ERROR_INVALID_ARGUMENT;
constexpr moldtex_status MESH = MOLDTEX_ERROR_INVALID_MESH;
constexpr moldtex_status UVS = MOLDTEX_ERROR_MISSING_UVS;
constexpr moldtex_status BIG = MOLDTEX_ERROR_TOO_LARGE;

// Creates a surface from a possibly broken mesh; the out handle must stay NULL on failure.
moldtex_status Create(const moldtex_mesh_desc& d) {
  moldtex_surface s = nullptr;
  const moldtex_status st = moldtex_surface_create(&d, &s);
  if (st == MOLDTEX_OK)
    moldtex_surface_release(s);
  else
    EXPECT_EQ(s, nullptr) << "failed create must not hand out a handle";
  return st;
}

// ---- surface creation -------------------------------------------------------------------

TEST(ValidateSurface, NullPointers) {
  const Mesh m = make_quad();
  moldtex_mesh_desc d = m.desc();
  moldtex_surface s = nullptr;
  EXPECT_FAILS(moldtex_surface_create(nullptr, &s), ARG);
  EXPECT_FAILS(moldtex_surface_create(&d, nullptr), ARG);
  d.positions = nullptr;
  EXPECT_FAILS(Create(d), ARG);
  d = m.desc();
  d.triangles = nullptr;
  EXPECT_FAILS(Create(d), ARG);
  moldtex_surface_release(nullptr);  // releasing NULL is a no-op
  moldtex_sim_release(nullptr);
}

TEST(ValidateSurface, TooSmallStructSize) {
  const Mesh m = make_quad();
  moldtex_mesh_desc d = m.desc();
  d.struct_size = 0;
  EXPECT_FAILS(Create(d), ARG);
  d.struct_size = 4;
  EXPECT_FAILS(Create(d), ARG);
}

TEST(ValidateSurface, NonFinitePositions) {
  // "NaN" (INVALID_ARGUMENT) and "non-finite numbers" in a mesh (INVALID_MESH).
  Mesh m = make_cube();
  m.positions[4] = kNaN;
  EXPECT_FAILS(Create(m.desc()), ARG, MESH);
  m = make_cube();
  m.positions[0] = kInf;
  EXPECT_FAILS(Create(m.desc()), ARG, MESH);
}

TEST(ValidateSurface, NonFiniteUvs) {
  // A NaN UV is a NaN input (INVALID_ARGUMENT) or an unusable UV layout (MISSING_UVS).
  Mesh m = make_cube();
  m.uvs[5] = kNaN;
  EXPECT_FAILS(Create(m.desc()), ARG, UVS, MESH);
}

TEST(ValidateSurface, OutOfRangeIndices) {
  // "out-of-range index" (INVALID_ARGUMENT) or "bad indices" (INVALID_MESH).
  Mesh m = make_cube();
  m.triangles[7] = m.vertex_count();
  EXPECT_FAILS(Create(m.desc()), ARG, MESH);
  m = make_cube();
  m.triangles[0] = 0xFFFFFFFFu;
  EXPECT_FAILS(Create(m.desc()), ARG, MESH);
  Mesh t = make_torus(8, 6, 1.0, 0.3);  // indexed UVs
  t.triangle_uvs[10] = uint32_t(t.uvs.size() / 2);
  EXPECT_FAILS(Create(t.desc()), ARG, MESH, UVS);
}

TEST(ValidateSurface, PerCornerUvCountMismatch) {
  // triangle_uvs NULL means uv_count == 3 * triangle_count; anything else is refused.
  const Mesh m = make_cube();
  moldtex_mesh_desc d = m.desc();
  d.uv_count = 3 * m.triangle_count() - 1;
  EXPECT_FAILS(Create(d), ARG, MESH, UVS);
}

TEST(ValidateSurface, ZeroFaces) {
  const Mesh m = make_quad();
  moldtex_mesh_desc d = m.desc();
  d.triangle_count = 0;
  EXPECT_FAILS(Create(d), MESH);
}

TEST(ValidateSurface, ZeroArea) {
  // Header: meshes with zero area are refused (every triangle degenerate).
  Mesh m = make_quad();
  for (size_t i = 0; i < m.positions.size(); i += 3) {
    m.positions[i] = 0.25f;
    m.positions[i + 1] = 0.25f;
  }
  EXPECT_FAILS(Create(m.desc()), MESH);
}

// A mesh without UVs makes a surface (the intrinsic domain runs on it) with a placeholder
// layout it reports; the texture domain refuses it, saying what to do. UVs and their
// count must agree.
TEST(ValidateSurface, NoUvs) {
  const Mesh m = make_quad();
  moldtex_mesh_desc d = m.desc();
  d.uvs = nullptr;
  d.uv_count = 0;
  d.triangle_uvs = nullptr;
  moldtex_surface s = nullptr;
  ASSERT_EQ(moldtex_surface_create(&d, &s), MOLDTEX_OK) << moldtex_last_error();
  moldtex_surface_info info;
  moldtex_surface_info_init(&info);
  ASSERT_EQ(moldtex_surface_get_info(s, &info), MOLDTEX_OK);
  EXPECT_EQ(info.generated_uvs, 1u);
  EXPECT_GT(info.uv_area, 0.0);
  moldtex_sim_config c;
  moldtex_sim_config_init(&c);
  c.width = c.height = 64;
  c.agent_count = 10;
  const moldtex_sim_params params = default_params();
  for (uint32_t model : {MOLDTEX_MODEL_MOMAS, MOLDTEX_MODEL_CONTINUOUS}) {
    c.model = model;
    moldtex_sim sim = nullptr;
    EXPECT_EQ(moldtex_sim_create(s, &c, &params, &sim), UVS);
    EXPECT_EQ(sim, nullptr);
    EXPECT_NE(std::string(moldtex_last_error()).find("Smart UV Project"), std::string::npos) << moldtex_last_error();
  }
  EXPECT_NE(std::string(moldtex_last_error()).find("Intrinsic domain"), std::string::npos) << moldtex_last_error();
  moldtex_surface_release(s);
  // A caller from before generated_uvs existed gets the older fields and nothing past them.
  const Mesh with_uvs = make_quad();
  auto s2 = create_surface(with_uvs);
  ASSERT_TRUE(s2);
  struct {
    moldtex_surface_info info;
    uint32_t guard;
  } old{};
  old.info.struct_size = offsetof(moldtex_surface_info, generated_uvs);
  old.info.generated_uvs = 77;
  ASSERT_EQ(moldtex_surface_get_info(s2.get(), &old.info), MOLDTEX_OK) << moldtex_last_error();
  EXPECT_EQ(old.info.generated_uvs, 77u);
  EXPECT_EQ(old.info.triangle_count, with_uvs.triangle_count());
  EXPECT_EQ(old.info.struct_size, offsetof(moldtex_surface_info, generated_uvs));

  d.triangle_uvs = with_uvs.triangles.data();  // indices into UVs that are not there
  EXPECT_FAILS(Create(d), ARG);
  d.triangle_uvs = nullptr;
  d.uvs = m.uvs.data();  // UVs with a zero count
  EXPECT_FAILS(Create(d), ARG);
}

TEST(ValidateSurface, ZeroUvArea) {
  Mesh m = make_cube();
  std::fill(m.uvs.begin(), m.uvs.end(), 0.5f);
  EXPECT_FAILS(Create(m.desc()), UVS);
  m = make_quad();  // collinear UVs: a line, no area
  for (size_t i = 0; i < m.uvs.size(); i += 2) m.uvs[i + 1] = m.uvs[i];
  EXPECT_FAILS(Create(m.desc()), UVS);
}

TEST(ValidateSurface, NonManifoldEdge) {
  // Three triangles on one edge: adjacency across it is ambiguous.
  EXPECT_FAILS(Create(make_nonmanifold_fan().desc()), MESH);
}

// ---- surface queries --------------------------------------------------------------------

class ValidateQueries : public ::testing::Test {
 protected:
  void SetUp() override {
    surface = create_surface(mesh);
    ASSERT_TRUE(surface) << LastError();
  }
  Mesh mesh = make_cube();
  SurfacePtr surface;
};

TEST_F(ValidateQueries, Info) {
  moldtex_surface_info info;
  moldtex_surface_info_init(&info);
  EXPECT_FAILS(moldtex_surface_get_info(nullptr, &info), ARG);
  EXPECT_FAILS(moldtex_surface_get_info(surface.get(), nullptr), ARG);
  info.struct_size = 0;
  EXPECT_FAILS(moldtex_surface_get_info(surface.get(), &info), ARG);
}

TEST_F(ValidateQueries, Metric) {
  float g[4];
  EXPECT_FAILS(moldtex_surface_get_metric(nullptr, 0, g), ARG);
  EXPECT_FAILS(moldtex_surface_get_metric(surface.get(), 12, g), ARG);
  EXPECT_FAILS(moldtex_surface_get_metric(surface.get(), 0xFFFFFFFFu, g), ARG);
  EXPECT_FAILS(moldtex_surface_get_metric(surface.get(), 0, nullptr), ARG);
}

TEST_F(ValidateQueries, Evaluate) {
  float pos[3], uv[2];
  moldtex_surface_point p{0, {0.2f, 0.3f, 0.5f}};
  EXPECT_FAILS(moldtex_surface_evaluate(nullptr, &p, pos, uv), ARG);
  EXPECT_FAILS(moldtex_surface_evaluate(surface.get(), nullptr, pos, uv), ARG);
  p.triangle = 12;
  EXPECT_FAILS(moldtex_surface_evaluate(surface.get(), &p, pos, uv), ARG);
  p = {0, {kNaN, 0.5f, 0.5f}};
  EXPECT_FAILS(moldtex_surface_evaluate(surface.get(), &p, pos, uv), ARG);
  p = {0, {-0.5f, 0.75f, 0.75f}};  // not a point of the triangle
  EXPECT_FAILS(moldtex_surface_evaluate(surface.get(), &p, pos, uv), ARG);
}

TEST_F(ValidateQueries, Trace) {
  const moldtex_surface_point start{0, {0.2f, 0.3f, 0.5f}};
  moldtex_surface_point end;
  const float dir[3] = {0, 1, 0};
  EXPECT_FAILS(moldtex_surface_trace(nullptr, &start, dir, 1, &end, nullptr, 0, nullptr), ARG);
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), nullptr, dir, 1, &end, nullptr, 0, nullptr), ARG);
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), &start, nullptr, 1, &end, nullptr, 0, nullptr), ARG);
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), &start, dir, 1, nullptr, nullptr, 0, nullptr), ARG);
  const float nan_dir[3] = {kNaN, 0, 0};
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), &start, nan_dir, 1, &end, nullptr, 0, nullptr), ARG);
  const float zero_dir[3] = {0, 0, 0};
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), &start, zero_dir, 1, &end, nullptr, 0, nullptr), ARG);
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), &start, dir, kNaN, &end, nullptr, 0, nullptr), ARG);
  // An infinite walk would never return: refuse it.
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), &start, dir, kInf, &end, nullptr, 0, nullptr), ARG, BIG);
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), &start, dir, -1, &end, nullptr, 0, nullptr), ARG);
  moldtex_surface_point bad{99, {0.2f, 0.3f, 0.5f}};
  EXPECT_FAILS(moldtex_surface_trace(surface.get(), &bad, dir, 1, &end, nullptr, 0, nullptr), ARG);
}

// ---- simulation creation ---------------------------------------------------------------

class ValidateSim : public ::testing::Test {
 protected:
  void SetUp() override {
    surface = create_surface(mesh);
    ASSERT_TRUE(surface) << LastError();
    config = make_config(32, 32, 100, 1);
    params = default_params();
  }
  moldtex_status Create(const moldtex_sim_config& c, const moldtex_sim_params& p) {
    moldtex_sim sim = nullptr;
    const moldtex_status st = moldtex_sim_create(surface.get(), &c, &p, &sim);
    if (st == MOLDTEX_OK)
      moldtex_sim_release(sim);
    else
      EXPECT_EQ(sim, nullptr) << "failed create must not hand out a handle";
    return st;
  }
  Mesh mesh = make_cube();
  SurfacePtr surface;
  moldtex_sim_config config;
  moldtex_sim_params params;
};

TEST_F(ValidateSim, NullPointers) {
  moldtex_sim sim = nullptr;
  EXPECT_FAILS(moldtex_sim_create(nullptr, &config, &params, &sim), ARG);
  EXPECT_FAILS(moldtex_sim_create(surface.get(), nullptr, &params, &sim), ARG);
  EXPECT_FAILS(moldtex_sim_create(surface.get(), &config, nullptr, &sim), ARG);
  EXPECT_FAILS(moldtex_sim_create(surface.get(), &config, &params, nullptr), ARG);
}

TEST_F(ValidateSim, TooSmallStructSizes) {
  moldtex_sim_config c = config;
  c.struct_size = 0;
  EXPECT_FAILS(Create(c, params), ARG);
  c.struct_size = 8;
  EXPECT_FAILS(Create(c, params), ARG);
  moldtex_sim_params p = params;
  p.struct_size = 0;
  EXPECT_FAILS(Create(config, p), ARG);
  p.struct_size = 12;
  EXPECT_FAILS(Create(config, p), ARG);
}

TEST_F(ValidateSim, TextureSizes) {
  // Header: 8 .. 16384 texels each way. 100000 is out of range and an absurd size.
  moldtex_sim_config c = config;
  c.width = 100000;
  EXPECT_FAILS(Create(c, params), ARG, BIG);
  c = config;
  c.height = 100000;
  EXPECT_FAILS(Create(c, params), ARG, BIG);
  c = config;
  c.width = 7;
  EXPECT_FAILS(Create(c, params), ARG);
  c = config;
  c.height = 0;
  EXPECT_FAILS(Create(c, params), ARG);
  c = config;
  c.width = c.height = 0xFFFFFFFFu;
  EXPECT_FAILS(Create(c, params), ARG, BIG);
}

TEST_F(ValidateSim, AgentCounts) {
  // Header: 1 .. 67108864 agents. 2^31 is out of range and an absurd size.
  moldtex_sim_config c = config;
  c.agent_count = 0;
  EXPECT_FAILS(Create(c, params), ARG);
  c.agent_count = 1u << 31;
  EXPECT_FAILS(Create(c, params), ARG, BIG);
  c.agent_count = 67108865u;
  EXPECT_FAILS(Create(c, params), ARG, BIG);
  c.agent_count = 0xFFFFFFFFu;
  EXPECT_FAILS(Create(c, params), ARG, BIG);
}

// Every out-of-range parameter, refused by both create and set_params.
struct BadParam {
  const char* what;
  void (*apply)(moldtex_sim_params&);
};
const BadParam kBadParams[] = {
    {"NaN movement_speed", [](moldtex_sim_params& p) { p.movement_speed = std::nanf(""); }},
    {"negative movement_speed", [](moldtex_sim_params& p) { p.movement_speed = -1; }},
    {"movement_speed > 64", [](moldtex_sim_params& p) { p.movement_speed = 65; }},
    {"infinite movement_speed", [](moldtex_sim_params& p) { p.movement_speed = INFINITY; }},
    {"NaN turn_speed", [](moldtex_sim_params& p) { p.turn_speed = std::nanf(""); }},
    {"turn_speed > 1000", [](moldtex_sim_params& p) { p.turn_speed = 1001; }},
    {"negative vision_distance", [](moldtex_sim_params& p) { p.vision_distance = -0.1f; }},
    {"vision_distance > 50", [](moldtex_sim_params& p) { p.vision_distance = 51; }},
    {"vision_angle > 180", [](moldtex_sim_params& p) { p.vision_angle = 181; }},
    {"negative vision_angle", [](moldtex_sim_params& p) { p.vision_angle = -1; }},
    {"negative evaporation_rate", [](moldtex_sim_params& p) { p.evaporation_rate = -0.1f; }},
    {"evaporation_rate > 1000", [](moldtex_sim_params& p) { p.evaporation_rate = 1001; }},
    {"NaN evaporation_rate", [](moldtex_sim_params& p) { p.evaporation_rate = std::nanf(""); }},
    {"negative diffusion_rate", [](moldtex_sim_params& p) { p.diffusion_rate = -1; }},
    {"NaN diffusion_rate", [](moldtex_sim_params& p) { p.diffusion_rate = std::nanf(""); }},
    {"deposit > 1", [](moldtex_sim_params& p) { p.deposit = 1.5f; }},
    {"negative deposit", [](moldtex_sim_params& p) { p.deposit = -0.1f; }},
    {"time_step 0", [](moldtex_sim_params& p) { p.time_step = 0; }},
    {"time_step > 1", [](moldtex_sim_params& p) { p.time_step = 2; }},
    {"NaN time_step", [](moldtex_sim_params& p) { p.time_step = std::nanf(""); }},
    {"substeps 0", [](moldtex_sim_params& p) { p.substeps = 0; }},
    {"substeps > 64", [](moldtex_sim_params& p) { p.substeps = 65; }},
};

TEST_F(ValidateSim, BadParamsOnCreate) {
  for (const BadParam& b : kBadParams) {
    moldtex_sim_params p = params;
    b.apply(p);
    EXPECT_TRUE(FailsWith(Create(config, p), {ARG}, b.what));
  }
}

TEST_F(ValidateSim, BadParamsOnSet) {
  auto sim = create_sim(surface.get(), config, params);
  ASSERT_TRUE(sim) << LastError();
  for (const BadParam& b : kBadParams) {
    moldtex_sim_params p = params;
    b.apply(p);
    EXPECT_TRUE(FailsWith(moldtex_sim_set_params(sim.get(), &p), {ARG}, b.what));
  }
  EXPECT_FAILS(moldtex_sim_set_params(sim.get(), nullptr), ARG);
  EXPECT_FAILS(moldtex_sim_set_params(nullptr, &params), ARG);
  moldtex_sim_params p = params;
  p.struct_size = 0;
  EXPECT_FAILS(moldtex_sim_set_params(sim.get(), &p), ARG);
  // Still alive and well after all that.
  EXPECT_EQ(moldtex_sim_step(sim.get(), 2), MOLDTEX_OK) << LastError();
}

TEST_F(ValidateSim, BoundaryParamValuesAreAccepted) {
  // The hard limits themselves are valid (closed ranges, time_step in (0, 1]).
  moldtex_sim_params p = params;
  p.movement_speed = 64;
  p.turn_speed = 1000;
  p.vision_distance = 50;
  p.vision_angle = 180;
  p.evaporation_rate = 1000;
  p.deposit = 1;
  p.time_step = 1;
  p.substeps = 64;
  EXPECT_EQ(Create(config, p), MOLDTEX_OK) << LastError();
  p.movement_speed = 0;
  p.turn_speed = 0;
  p.vision_distance = 0;
  p.vision_angle = 0;
  p.evaporation_rate = 0;
  p.deposit = 0;
  p.substeps = 1;
  p.diffusion_rate = 0;
  EXPECT_EQ(Create(config, p), MOLDTEX_OK) << LastError();
}

// ---- simulation queries -----------------------------------------------------------------

TEST_F(ValidateSim, Queries) {
  auto sim = create_sim(surface.get(), config, params);
  ASSERT_TRUE(sim) << LastError();
  moldtex_sim s = sim.get();
  EXPECT_FAILS(moldtex_sim_step(nullptr, 1), ARG);
  EXPECT_FAILS(moldtex_sim_reset(nullptr), ARG);

  std::vector<float> rgba(32 * 32 * 4, 42.0f);
  EXPECT_FAILS(moldtex_sim_read_rgba(nullptr, rgba.data(), rgba.size()), ARG);
  EXPECT_FAILS(moldtex_sim_read_rgba(s, nullptr, rgba.size()), ARG);
  EXPECT_FAILS(moldtex_sim_read_rgba(s, rgba.data(), rgba.size() - 1), ARG);
  for (float v : rgba) ASSERT_EQ(v, 42.0f) << "a refused read must not write";

  std::vector<uint8_t> cls(32 * 32, 7);
  EXPECT_FAILS(moldtex_sim_read_texel_classes(nullptr, cls.data(), cls.size()), ARG);
  EXPECT_FAILS(moldtex_sim_read_texel_classes(s, nullptr, cls.size()), ARG);
  EXPECT_FAILS(moldtex_sim_read_texel_classes(s, cls.data(), cls.size() - 1), ARG);
  for (uint8_t v : cls) ASSERT_EQ(v, 7) << "a refused read must not write";

  moldtex_surface_point pts[4];
  EXPECT_FAILS(moldtex_sim_read_agents(nullptr, pts, 4), ARG);
  EXPECT_FAILS(moldtex_sim_read_agents(s, nullptr, 4), ARG);

  moldtex_sim_stats st;
  moldtex_sim_stats_init(&st);
  EXPECT_FAILS(moldtex_sim_get_stats(nullptr, &st), ARG);
  EXPECT_FAILS(moldtex_sim_get_stats(s, nullptr), ARG);
  st.struct_size = 0;
  EXPECT_FAILS(moldtex_sim_get_stats(s, &st), ARG);

  moldtex_sim_params p;
  moldtex_sim_params_init(&p);
  EXPECT_FAILS(moldtex_sim_get_params(nullptr, &p), ARG);
  EXPECT_FAILS(moldtex_sim_get_params(s, nullptr), ARG);
  p.struct_size = 0;
  EXPECT_FAILS(moldtex_sim_get_params(s, &p), ARG);

  moldtex_sim_config c;
  moldtex_sim_config_init(&c);
  EXPECT_FAILS(moldtex_sim_get_config(nullptr, &c), ARG);
  EXPECT_FAILS(moldtex_sim_get_config(s, nullptr), ARG);
  c.struct_size = 0;
  EXPECT_FAILS(moldtex_sim_get_config(s, &c), ARG);

  // All refused; the simulation still works.
  EXPECT_EQ(moldtex_sim_step(s, 1), MOLDTEX_OK) << LastError();
  EXPECT_EQ(moldtex_sim_read_rgba(s, rgba.data(), rgba.size()), MOLDTEX_OK) << LastError();
}

TEST_F(ValidateSim, ZeroStepsIsANoOp) {
  auto sim = create_sim(surface.get(), config, params);
  ASSERT_TRUE(sim) << LastError();
  EXPECT_EQ(moldtex_sim_step(sim.get(), 0), MOLDTEX_OK) << LastError();
  EXPECT_EQ(get_stats(sim.get()).step_count, 0u);
}

TEST_F(ValidateSim, OneCallStepsAtMostTheBound) {
  // A count that would hold the caller for days (a wrapped-around unsigned difference,
  // say) is refused with nothing stepped, and says how to go on; a count within it runs.
  auto sim = create_sim(surface.get(), config, params);
  ASSERT_TRUE(sim) << LastError();
  EXPECT_EQ(moldtex_sim_step(sim.get(), 0xffffff6au), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("chunks"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_sim_step(sim.get(), MOLDTEX_MAX_STEPS_PER_CALL + 1), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(get_stats(sim.get()).step_count, 0u);
  EXPECT_EQ(moldtex_sim_step(sim.get(), 3), MOLDTEX_OK) << LastError();
  EXPECT_EQ(get_stats(sim.get()).step_count, 3u);
}

}  // namespace
}  // namespace mtx
