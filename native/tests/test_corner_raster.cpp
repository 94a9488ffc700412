// moldtex_surface_rasterize_corners: per-corner values (painted attributes, vertex
// group weights) baked into a texture over the UV layout, texel for texel like a
// simulation's fields.
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <vector>

#include "test_util.h"

namespace mtx {
namespace {

// Corner values of every triangle from a function of the corner's 3D position.
std::vector<float> CornerValues(const Mesh& m,
                                const std::function<std::array<float, 4>(uint32_t t, const Vec3&)>& f) {
  std::vector<float> out;
  for (uint32_t t = 0; t < m.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      for (float v : f(t, m.corner(t, k))) out.push_back(v);
  return out;
}

std::vector<float> Rasterize(moldtex_surface s, uint32_t w, uint32_t h, const std::vector<float>& corners,
                             moldtex_status* status = nullptr) {
  std::vector<float> rgba(size_t(w) * h * 4, -1.f);
  const moldtex_status st =
      moldtex_surface_rasterize_corners(s, w, h, corners.data(), corners.size(), rgba.data(), rgba.size());
  if (status) *status = st;
  return rgba;
}

// Texel classes of a layout, through a throwaway simulation of the same size.
std::vector<uint8_t> Classes(moldtex_surface s, uint32_t w, uint32_t h) {
  auto sim = create_sim(s, make_config(w, h, 16, 1), default_params());
  return sim ? read_classes(sim.get(), w, h) : std::vector<uint8_t>{};
}

TEST(RasterizeCorners, LinearValuesOnAPlaneGiveThe3DPointOfEachTexelCentre) {
  // [1, 5] x [-1, 2] in 12 x 9 cells with UV = 0.1 + 0.8 * (x, y) normalised, on a
  // 64 x 48 texture: corner values R = x, G = y, B = 0.25, A = x - 2y. Every island
  // texel must hold the 3D point at its centre (the UV map is affine, so barycentric
  // interpolation is exact up to float rounding): |error| < 1e-4 (measured 4.8e-7).
  // Gutter texels copy an island texel at most 2 texels away (the gutter width): their
  // x is within 2 texels (0.156 in x) of their own centre's extrapolated x (measured
  // 0.156; asserted 2.5 texels). Texels outside stay exactly 0.
  const double x0 = 1, y0 = -1, x1 = 5, y1 = 2;
  const Mesh m = make_plane(12, 9, x0, y0, x1, y1, [&](double x, double y) {
    return Vec2{0.1 + 0.8 * (x - x0) / (x1 - x0), 0.1 + 0.8 * (y - y0) / (y1 - y0)};
  });
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 64, H = 48;
  const auto corners = CornerValues(m, [](uint32_t, const Vec3& p) {
    return std::array<float, 4>{float(p[0]), float(p[1]), 0.25f, float(p[0] - 2 * p[1])};
  });
  moldtex_status st;
  const auto rgba = Rasterize(s.get(), W, H, corners, &st);
  ASSERT_EQ(st, MOLDTEX_OK) << LastError();
  const auto classes = Classes(s.get(), W, H);
  ASSERT_EQ(classes.size(), size_t(W) * H) << LastError();
  double worst = 0, worst_gutter = 0;
  size_t inside = 0, gutter = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      const double u = (x + 0.5) / W, v = (y + 0.5) / H;
      const double px = x0 + (u - 0.1) / 0.8 * (x1 - x0), py = y0 + (v - 0.1) / 0.8 * (y1 - y0);
      const float* t = &rgba[4 * i];
      if (classes[i] == MOLDTEX_TEXEL_INSIDE) {
        ++inside;
        const double want[4] = {px, py, 0.25, px - 2 * py};
        for (int c = 0; c < 4; ++c) worst = std::max(worst, std::fabs(t[c] - want[c]));
      } else if (classes[i] == MOLDTEX_TEXEL_GUTTER) {
        ++gutter;
        worst_gutter = std::max(worst_gutter, std::fabs(t[0] - px));
        EXPECT_NEAR(t[2], 0.25f, 1e-6f);
      } else {
        for (int c = 0; c < 4; ++c) ASSERT_EQ(t[c], 0.f) << "outside texel " << x << ", " << y;
      }
    }
  std::printf("plane: %zu island texels, worst error %.3g; %zu gutter texels, worst x offset %.3g\n",
              inside, worst, gutter, worst_gutter);
  RecordProperty("worst_error", std::to_string(worst));
  EXPECT_GT(inside, size_t(0.6 * W * H));
  EXPECT_GT(gutter, 0u);
  EXPECT_LT(worst, 1e-4);
  EXPECT_LT(worst_gutter, 2.5 * (x1 - x0) / (0.8 * W) + 1e-4);
}

TEST(RasterizeCorners, ConstantIslandValuesStayInTheirIslands) {
  // The cube's six faces are six UV islands (make_cube): face f's corners hold f + 1 in
  // R and 10 * (f + 1) in B. Every island texel holds exactly its own face's values
  // (the face is known from the UV cell the texel centre lies in), gutter texels hold
  // some face's values (copied across a seam or from their own island; some of them,
  // across a seam, another face's), outside texels 0. Then two islands that touch in UV (a plane whose halves x < 0.5 and x > 0.5 map
  // side by side, the right half mirrored in v, so the shared 3D edge is a seam):
  // no texel of one half takes the other half's value.
  const Mesh cube = make_cube();
  auto s = create_surface(cube);
  ASSERT_TRUE(s) << LastError();
  const uint32_t W = 64, H = 64;
  const auto corners = CornerValues(cube, [](uint32_t t, const Vec3&) {
    const float f = float(t / 2 + 1);
    return std::array<float, 4>{f, 0.f, 10 * f, 1.f};
  });
  moldtex_status st;
  const auto rgba = Rasterize(s.get(), W, H, corners, &st);
  ASSERT_EQ(st, MOLDTEX_OK) << LastError();
  const auto classes = Classes(s.get(), W, H);
  ASSERT_EQ(classes.size(), size_t(W) * H) << LastError();
  // UV cell (column, row) of each face, as make_cube lays them out.
  const int cells[6][2] = {{2, 1}, {0, 1}, {1, 2}, {1, 0}, {1, 1}, {3, 1}};
  size_t inside = 0, gutter = 0, gutter_across = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      const float* t = &rgba[4 * i];
      const int cu = int(4 * (x + 0.5) / W), cv = int(4 * (y + 0.5) / H);
      int face = -1;
      for (int f = 0; f < 6; ++f)
        if (cells[f][0] == cu && cells[f][1] == cv) face = f;
      if (classes[i] == MOLDTEX_TEXEL_INSIDE) {
        ++inside;
        ASSERT_GE(face, 0) << "island texel outside every face's cell at " << x << ", " << y;
        ASSERT_EQ(t[0], float(face + 1)) << "texel " << x << ", " << y;
        ASSERT_EQ(t[2], float(10 * (face + 1))) << "texel " << x << ", " << y;
        ASSERT_EQ(t[3], 1.f);
      } else if (classes[i] == MOLDTEX_TEXEL_GUTTER) {
        ++gutter;
        ASSERT_TRUE(t[0] >= 1.f && t[0] <= 6.f && t[0] == std::round(t[0])) << t[0];
        ASSERT_EQ(t[2], 10 * t[0]);
        gutter_across += face >= 0 && t[0] != float(face + 1);
      } else {
        for (int c = 0; c < 4; ++c) ASSERT_EQ(t[c], 0.f);
      }
    }
  std::printf("cube: %zu island texels, %zu gutter texels, %zu of them from across a seam\n",
              inside, gutter, gutter_across);
  EXPECT_GT(inside, 0u);
  EXPECT_GT(gutter, 0u);
  EXPECT_GT(gutter_across, 0u);

  // Two islands side by side in UV, touching along u = 0.5.
  const Mesh halves = make_plane(8, 8, 0, 0, 1, 1, [](double x, double y) {
    return x <= 0.5 ? Vec2{x, y} : Vec2{x, 1 - y};
  });
  // make_grid gives each vertex one UV; the seam needs both: rebuild per corner.
  Mesh split = halves;
  split.uvs.clear();
  split.triangle_uvs.clear();
  std::vector<float> values;
  for (uint32_t t = 0; t < halves.triangle_count(); ++t) {
    double cx = 0;
    for (int k = 0; k < 3; ++k) cx += halves.corner(t, k)[0] / 3;
    const bool right = cx > 0.5;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = halves.corner(t, k);
      split.uvs.push_back(float(p[0]));
      split.uvs.push_back(float(right ? 1 - p[1] : p[1]));
      for (float v : {right ? 2.f : 1.f, 0.f, 0.f, 0.f}) values.push_back(v);
    }
  }
  auto s2 = create_surface(split);
  ASSERT_TRUE(s2) << LastError();
  moldtex_surface_info info;
  moldtex_surface_info_init(&info);
  ASSERT_EQ(moldtex_surface_get_info(s2.get(), &info), MOLDTEX_OK);
  EXPECT_EQ(info.seam_edge_count, 8u);  // the middle column's edges
  const auto two = Rasterize(s2.get(), 32, 32, values, &st);
  ASSERT_EQ(st, MOLDTEX_OK) << LastError();
  for (uint32_t y = 0; y < 32; ++y)
    for (uint32_t x = 0; x < 32; ++x)
      ASSERT_EQ(two[4 * (y * 32 + x)], x < 16 ? 1.f : 2.f) << "texel " << x << ", " << y;
}

TEST(RasterizeCorners, BadRequestsAreRefusedWithAMessage) {
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const std::vector<float> good(m.triangle_count() * 12, 0.5f);
  std::vector<float> rgba(16 * 16 * 4);
  auto call = [&](moldtex_surface surface, uint32_t w, uint32_t h, const float* c, size_t n,
                  float* out, size_t count) {
    return moldtex_surface_rasterize_corners(surface, w, h, c, n, out, count);
  };
  ASSERT_EQ(call(s.get(), 16, 16, good.data(), good.size(), rgba.data(), rgba.size()), MOLDTEX_OK)
      << LastError();
  EXPECT_EQ(rgba[4 * (8 * 16 + 8)], 0.5f);
  const struct {
    const char* what;
    moldtex_status status;
    moldtex_status want;
    const char* words;
  } cases[] = {
      {"NULL surface", call(nullptr, 16, 16, good.data(), good.size(), rgba.data(), rgba.size()),
       MOLDTEX_ERROR_INVALID_ARGUMENT, "surface"},
      {"too few corner floats", call(s.get(), 16, 16, good.data(), good.size() - 1, rgba.data(), rgba.size()),
       MOLDTEX_ERROR_INVALID_ARGUMENT, "triangle_count"},
      {"too many corner floats", call(s.get(), 16, 16, good.data(), good.size() + 4, rgba.data(), rgba.size()),
       MOLDTEX_ERROR_INVALID_ARGUMENT, "triangle_count"},
      {"NULL corners", call(s.get(), 16, 16, nullptr, good.size(), rgba.data(), rgba.size()),
       MOLDTEX_ERROR_INVALID_ARGUMENT, "NULL"},
      {"NULL output", call(s.get(), 16, 16, good.data(), good.size(), nullptr, rgba.size()),
       MOLDTEX_ERROR_INVALID_ARGUMENT, "NULL"},
      {"small output", call(s.get(), 16, 16, good.data(), good.size(), rgba.data(), rgba.size() - 1),
       MOLDTEX_ERROR_INVALID_ARGUMENT, "too small"},
      {"width 7", call(s.get(), 7, 16, good.data(), good.size(), rgba.data(), rgba.size()),
       MOLDTEX_ERROR_INVALID_ARGUMENT, "8 .. 16384"},
      {"height 16385", call(s.get(), 16, 16385, good.data(), good.size(), rgba.data(), rgba.size()),
       MOLDTEX_ERROR_TOO_LARGE, "8 .. 16384"},
  };
  for (const auto& c : cases) {
    EXPECT_EQ(c.status, c.want) << c.what;
  }
  // Messages, checked one call at a time (the message is the last call's).
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    std::vector<float> corners = good;
    corners[4 * 4 + 2] = bad;  // triangle 1, corner 1, blue
    std::fill(rgba.begin(), rgba.end(), 7.f);
    EXPECT_EQ(call(s.get(), 16, 16, corners.data(), corners.size(), rgba.data(), rgba.size()),
              MOLDTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(LastError().find("NaN or infinite value at triangle 1, corner 1"), std::string::npos)
        << LastError();
    EXPECT_EQ(rgba[0], 7.f) << "a refused call must not write the output";
  }
  EXPECT_EQ(call(s.get(), 16, 16, good.data(), 5, rgba.data(), rgba.size()), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("(24), got 5"), std::string::npos) << LastError();
  EXPECT_EQ(call(s.get(), 16, 16385, good.data(), good.size(), rgba.data(), rgba.size()),
            MOLDTEX_ERROR_TOO_LARGE);
  EXPECT_NE(LastError().find("16 x 16385"), std::string::npos) << LastError();
  EXPECT_EQ(call(s.get(), 16, 16, good.data(), good.size(), rgba.data(), rgba.size()), MOLDTEX_OK);
  EXPECT_EQ(LastError(), "");
}

}  // namespace
}  // namespace mtx
