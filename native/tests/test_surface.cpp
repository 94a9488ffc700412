// Surface: mesh statistics, metric tensor, evaluation of surface points.
#include <random>

#include "test_util.h"

namespace mtx {
namespace {

moldtex_surface_info Info(moldtex_surface s) {
  moldtex_surface_info info;
  moldtex_surface_info_init(&info);
  EXPECT_EQ(moldtex_surface_get_info(s, &info), MOLDTEX_OK) << LastError();
  return info;
}

// Areas: positions are floats, so 1e-6 relative is float round-off on sums of O(1k) terms.
constexpr double kAreaRel = 1e-5;

TEST(SurfaceInfo, Quad) {
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const auto i = Info(s.get());
  EXPECT_EQ(i.vertex_count, 4u);
  EXPECT_EQ(i.triangle_count, 2u);
  EXPECT_EQ(i.boundary_edge_count, 4u);  // the square's four sides
  EXPECT_EQ(i.seam_edge_count, 0u);      // UV = xy: the diagonal is not a seam
  EXPECT_EQ(i.degenerate_triangle_count, 0u);
  EXPECT_NEAR(i.area, 1.0, kAreaRel);
  EXPECT_NEAR(i.uv_area, 1.0, kAreaRel);
}

TEST(SurfaceInfo, CubeHasTwelveSeamsAndNoBoundary) {
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const auto i = Info(s.get());
  EXPECT_EQ(i.vertex_count, 8u);
  EXPECT_EQ(i.triangle_count, 12u);
  EXPECT_EQ(i.boundary_edge_count, 0u);  // closed: UV seams are not boundaries
  EXPECT_EQ(i.seam_edge_count, 12u);     // 6 separate islands: every cube edge is a seam
  EXPECT_NEAR(i.area, 6.0, 6.0 * kAreaRel);
  EXPECT_NEAR(i.uv_area, m.total_uv_area(), m.total_uv_area() * kAreaRel);
}

TEST(SurfaceInfo, UvSphereSeamsAtDateLineAndPoles) {
  const int S = 32, R = 16;
  const Mesh m = make_uv_sphere(S, R, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const auto i = Info(s.get());
  EXPECT_EQ(i.vertex_count, uint32_t(2 + (R - 1) * S));
  EXPECT_EQ(i.triangle_count, uint32_t(2 * S * (R - 2) + 2 * S));
  EXPECT_EQ(i.boundary_edge_count, 0u);
  // Date line: R - 2 edges between rings; every pole edge separates two fan triangles
  // whose pole corners have different UVs: 2 S more.
  EXPECT_EQ(i.seam_edge_count, uint32_t(2 * S + R - 2));
  EXPECT_NEAR(i.area, m.total_area(), m.total_area() * kAreaRel);
  EXPECT_NEAR(i.uv_area, m.total_uv_area(), kAreaRel);
}

TEST(SurfaceInfo, TorusSeamsAlongBothCircles) {
  const Mesh m = make_torus(24, 12, 1.0, 0.35);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const auto i = Info(s.get());
  EXPECT_EQ(i.vertex_count, 24u * 12u);
  EXPECT_EQ(i.triangle_count, 2u * 24u * 12u);
  EXPECT_EQ(i.boundary_edge_count, 0u);
  EXPECT_EQ(i.seam_edge_count, 24u + 12u);  // one minor circle + one major circle
  EXPECT_NEAR(i.area, m.total_area(), m.total_area() * kAreaRel);
  EXPECT_NEAR(i.uv_area, 1.0, kAreaRel);
}

TEST(SurfaceInfo, OpenCylinderBoundaryLoops) {
  const Mesh m = make_open_cylinder(32, 8, 0.5, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const auto i = Info(s.get());
  EXPECT_EQ(i.boundary_edge_count, 64u);  // top and bottom rims
  EXPECT_EQ(i.seam_edge_count, 8u);       // the vertical cut at angle 0
  EXPECT_NEAR(i.area, m.total_area(), m.total_area() * kAreaRel);
}

// A unit square with a zero-area sliver triangle along its bottom edge.
Mesh QuadWithSliver() {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0, 0};
  m.triangles = {0, 4, 2, 4, 1, 2, 0, 2, 3, 0, 1, 4};  // last one is collinear
  m.uvs = {0, 0, 1, 0, 1, 1, 0, 1, 0.5f, 0};
  m.triangle_uvs = m.triangles;
  return m;
}

TEST(SurfaceInfo, DegenerateTrianglesAreCountedNotRefused) {
  // Header: zero-area triangles are allowed; agents treat them as walls.
  const Mesh m = QuadWithSliver();
  moldtex_status st;
  auto s = create_surface(m, &st);
  ASSERT_EQ(st, MOLDTEX_OK) << LastError();
  const auto i = Info(s.get());
  EXPECT_EQ(i.degenerate_triangle_count, 1u);
  EXPECT_NEAR(i.area, 1.0, kAreaRel);
}

TEST(SurfaceAgents, NeverInsideDegenerateTriangle) {
  // Walls have no area: spawning by area never picks the sliver and moves never end in it.
  const Mesh m = QuadWithSliver();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(32, 32, 2000, 7), default_params());
  ASSERT_TRUE(sim) << LastError();
  for (int round = 0; round < 5; ++round) {
    for (const auto& p : read_agents(sim.get(), 2000)) {
      ASSERT_TRUE(ValidPoint(p, m.triangle_count()));
      ASSERT_NE(p.triangle, 3u) << "agent in the zero-area triangle after " << round * 20
                                << " steps";
    }
    ASSERT_EQ(moldtex_sim_step(sim.get(), 20), MOLDTEX_OK) << LastError();
  }
}

// ---- metric tensor --------------------------------------------------------------------

// g = J^T J for the affine map J: UV -> 3D of a triangle, computed in double.
std::array<double, 4> ExpectedMetric(const Mesh& m, uint32_t t) {
  const Vec3 p0 = m.corner(t, 0), e1 = sub(m.corner(t, 1), p0), e2 = sub(m.corner(t, 2), p0);
  const Vec2 q0 = m.corner_uv(t, 0), q1 = m.corner_uv(t, 1), q2 = m.corner_uv(t, 2);
  const double a = q1[0] - q0[0], b = q2[0] - q0[0], c = q1[1] - q0[1], d = q2[1] - q0[1];
  const double det = a * d - b * c;
  // J = [e1 e2] * inv([[a b],[c d]]); columns Ju = dP/du, Jv = dP/dv.
  const Vec3 Ju = scale(sub(scale(e1, d), scale(e2, c)), 1.0 / det);
  const Vec3 Jv = scale(sub(scale(e2, a), scale(e1, b)), 1.0 / det);
  return {dot(Ju, Ju), dot(Ju, Jv), dot(Jv, Ju), dot(Jv, Jv)};
}

TEST(SurfaceMetric, KnownShearedScaledTriangle) {
  // 3D P(u, v) = O + (u - 0.1) A + (v - 0.1) B on a tilted plane: g = [[A.A, A.B], [A.B, B.B]].
  const Vec3 O{0.3, -0.2, 0.5}, A{1.2, 0.8, -0.4}, B{-0.3, 0.9, 1.5};
  const Vec2 uv[3] = {{0.1, 0.1}, {0.6, 0.1}, {0.1, 0.4}};
  Mesh m;
  for (const Vec2& q : uv) {
    const Vec3 p = add(O, add(scale(A, q[0] - 0.1), scale(B, q[1] - 0.1)));
    for (double x : p) m.positions.push_back(float(x));
    m.uvs.push_back(float(q[0]));
    m.uvs.push_back(float(q[1]));
  }
  m.triangles = {0, 1, 2};
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  float g[4];
  ASSERT_EQ(moldtex_surface_get_metric(s.get(), 0, g), MOLDTEX_OK) << LastError();
  const double expected[4] = {dot(A, A), dot(A, B), dot(A, B), dot(B, B)};
  for (int k = 0; k < 4; ++k)  // float inputs: 1e-4 relative to the largest entry
    EXPECT_NEAR(g[k], expected[k], 1e-4 * dot(B, B)) << "g[" << k << "]";
  // Length of a UV displacement: sqrt(d^T g d) equals the 3D distance it maps to.
  const double d[2] = {0.2, -0.1};
  const double len2 = d[0] * (g[0] * d[0] + g[1] * d[1]) + d[1] * (g[2] * d[0] + g[3] * d[1]);
  EXPECT_NEAR(std::sqrt(len2), norm(add(scale(A, d[0]), scale(B, d[1]))), 1e-5);
}

TEST(SurfaceMetric, CubeFaceIsIsotropicScaling) {
  // Each cube face (side 1) is an island of side 0.21 in UV: g = (1 / 0.21)^2 I.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const double k = 1.0 / (0.21 * 0.21);
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    float g[4];
    ASSERT_EQ(moldtex_surface_get_metric(s.get(), t, g), MOLDTEX_OK) << LastError();
    EXPECT_NEAR(g[0], k, 1e-4 * k) << "triangle " << t;
    EXPECT_NEAR(g[1], 0.0, 1e-4 * k) << "triangle " << t;
    EXPECT_NEAR(g[2], 0.0, 1e-4 * k) << "triangle " << t;
    EXPECT_NEAR(g[3], k, 1e-4 * k) << "triangle " << t;
  }
}

TEST(SurfaceMetric, DistortedPlaneEveryTriangle) {
  // Piecewise-affine UVs: g is constant per triangle and equals J^T J (1e-4 relative:
  // float UVs of cells ~1/32 wide carry ~1e-5 relative error).
  const Mesh m = make_distorted_plane(4);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    float g[4];
    ASSERT_EQ(moldtex_surface_get_metric(s.get(), t, g), MOLDTEX_OK) << LastError();
    const auto e = ExpectedMetric(m, t);
    const double big = std::max(e[0], e[3]);
    for (int k = 0; k < 4; ++k)
      ASSERT_NEAR(g[k], e[k], 1e-4 * big) << "triangle " << t << " g[" << k << "]";
    EXPECT_FLOAT_EQ(g[1], g[2]);  // symmetric
  }
}

// ---- evaluate -----------------------------------------------------------------------

TEST(SurfaceEvaluate, CornersAndInteriorPointsOnCube) {
  // Evaluation is the affine interpolation of the triangle's own corners (per-corner UVs
  // on the cube, so the UV must come from that triangle's island). Tolerance: float.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    for (int trial = 0; trial < 8; ++trial) {
      double b[3];
      if (trial < 3) {
        b[0] = b[1] = b[2] = 0;
        b[trial] = 1;
      } else {
        const double r1 = std::sqrt(U(rng)), r2 = U(rng);
        b[0] = 1 - r1;
        b[1] = r1 * (1 - r2);
        b[2] = r1 * r2;
      }
      moldtex_surface_point p{t, {float(b[0]), float(b[1]), 0}};
      p.bary[2] = 1.0f - p.bary[0] - p.bary[1];
      float pos[3], uv[2];
      ASSERT_EQ(moldtex_surface_evaluate(s.get(), &p, pos, uv), MOLDTEX_OK) << LastError();
      Vec3 ep{0, 0, 0};
      Vec2 eu{0, 0};
      for (int k = 0; k < 3; ++k) {
        ep = add(ep, scale(m.corner(t, k), p.bary[k]));
        eu[0] += p.bary[k] * m.corner_uv(t, k)[0];
        eu[1] += p.bary[k] * m.corner_uv(t, k)[1];
      }
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(pos[k], ep[k], 1e-6);
      EXPECT_NEAR(uv[0], eu[0], 1e-6);
      EXPECT_NEAR(uv[1], eu[1], 1e-6);
    }
  }
}

TEST(SurfaceEvaluate, NullOutputsAreAllowed) {
  // Header: either output may be NULL.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const moldtex_surface_point p{0, {0.2f, 0.3f, 0.5f}};
  float pos[3], uv[2];
  EXPECT_EQ(moldtex_surface_evaluate(s.get(), &p, pos, nullptr), MOLDTEX_OK);
  EXPECT_EQ(moldtex_surface_evaluate(s.get(), &p, nullptr, uv), MOLDTEX_OK);
  EXPECT_EQ(moldtex_surface_evaluate(s.get(), &p, nullptr, nullptr), MOLDTEX_OK);
}

TEST(SurfaceLifetime, SimKeepsSurfaceAlive) {
  // Header: the caller may release the surface right after creating the simulation.
  const Mesh m = make_cube();
  moldtex_surface s = nullptr;
  const moldtex_mesh_desc d = m.desc();
  ASSERT_EQ(moldtex_surface_create(&d, &s), MOLDTEX_OK) << LastError();
  auto sim = create_sim(s, make_config(64, 64, 1000, 1), default_params());
  moldtex_surface_release(s);
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 10), MOLDTEX_OK) << LastError();
  for (const auto& p : read_agents(sim.get(), 1000)) ASSERT_TRUE(ValidPoint(p, 12));
  EXPECT_GT(get_stats(sim.get()).coverage, 0.0);
}

TEST(SurfaceLifetime, MeshBuffersMayBeFreedAfterCreate) {
  // The surface copies what it needs: the caller's arrays can go away (Blender frees
  // its evaluated mesh right after the call).
  SurfacePtr s;
  {
    Mesh m = make_torus(24, 12, 1.0, 0.35);
    s = create_surface(m);
    ASSERT_TRUE(s) << LastError();
    std::fill(m.positions.begin(), m.positions.end(), std::nanf(""));
    std::fill(m.triangles.begin(), m.triangles.end(), 0xFFFFFFFFu);
  }
  const moldtex_surface_point p{10, {0.2f, 0.3f, 0.5f}};
  const Vec3 pos = evaluate_position(s.get(), p);
  EXPECT_TRUE(std::isfinite(pos[0]) && std::isfinite(pos[1]) && std::isfinite(pos[2]));
}

}  // namespace
}  // namespace mtx
