// Sanity of the test meshes themselves (no core calls): if a fixture is wrong, every
// test built on it is meaningless, so these run first and fail loudly.
#include <map>
#include <utility>

#include "test_util.h"

namespace mtx {
namespace {

// Directed-edge use counts: a closed, consistently oriented manifold uses each
// undirected edge exactly twice, once in each direction.
struct EdgeUse {
  int forward = 0, backward = 0;
};
std::map<std::pair<uint32_t, uint32_t>, EdgeUse> edge_uses(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, EdgeUse> e;
  for (uint32_t t = 0; t < m.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.triangles[3 * t + k], b = m.triangles[3 * t + (k + 1) % 3];
      if (a < b)
        e[{a, b}].forward++;
      else
        e[{b, a}].backward++;
    }
  return e;
}

void ExpectClosedOriented(const Mesh& m) {
  for (const auto& [edge, use] : edge_uses(m)) {
    EXPECT_EQ(use.forward, 1) << "edge " << edge.first << "-" << edge.second;
    EXPECT_EQ(use.backward, 1) << "edge " << edge.first << "-" << edge.second;
  }
}

void ExpectUvsCounterClockwiseInUnitSquare(const Mesh& m) {
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    EXPECT_GT(m.signed_uv_area(t), 0.0) << "triangle " << t << " is flipped in UV";
    for (int k = 0; k < 3; ++k) {
      const Vec2 uv = m.corner_uv(t, k);
      EXPECT_GE(uv[0], 0.0);
      EXPECT_LE(uv[0], 1.0);
      EXPECT_GE(uv[1], 0.0);
      EXPECT_LE(uv[1], 1.0);
    }
  }
}

// Outward orientation of a closed mesh around the origin: normals point away from it.
void ExpectOutward(const Mesh& m) {
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 g = scale(add(m.corner(t, 0), add(m.corner(t, 1), m.corner(t, 2))), 1.0 / 3);
    EXPECT_GT(dot(m.normal(t), g), 0.0) << "triangle " << t;
  }
}

TEST(Fixtures, QuadIsUnitSquare) {
  const Mesh m = make_quad();
  EXPECT_EQ(m.triangle_count(), 2u);
  EXPECT_NEAR(m.total_area(), 1.0, 1e-12);
  EXPECT_NEAR(m.total_uv_area(), 1.0, 1e-12);
  ExpectUvsCounterClockwiseInUnitSquare(m);
}

TEST(Fixtures, CubeIsClosedWithSixSeparateIslands) {
  const Mesh m = make_cube();
  EXPECT_EQ(m.vertex_count(), 8u);
  EXPECT_EQ(m.triangle_count(), 12u);
  EXPECT_NEAR(m.total_area(), 6.0, 1e-12);
  EXPECT_NEAR(m.total_uv_area(), 6 * 0.21 * 0.21, 1e-6);
  ExpectClosedOriented(m);
  ExpectOutward(m);
  ExpectUvsCounterClockwiseInUnitSquare(m);
}

TEST(Fixtures, SphereIsClosedAndApproximatesTheRoundSphere) {
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  EXPECT_EQ(m.triangle_count(), 2u * 64 * 30 + 2 * 64);
  // A 64 x 32 polyhedral sphere has ~0.4% less area than 4 pi.
  EXPECT_NEAR(m.total_area(), 4 * kPi, 0.01 * 4 * kPi);
  ExpectClosedOriented(m);
  ExpectOutward(m);
  ExpectUvsCounterClockwiseInUnitSquare(m);
}

TEST(Fixtures, TorusIsClosed) {
  const Mesh m = make_torus(48, 24, 1.0, 0.35);
  // Polyhedral area is within 1% of 4 pi^2 R r for this resolution.
  EXPECT_NEAR(m.total_area(), 4 * kPi * kPi * 0.35, 0.01 * 4 * kPi * kPi * 0.35);
  EXPECT_NEAR(m.total_uv_area(), 1.0, 1e-6);
  ExpectClosedOriented(m);
  ExpectUvsCounterClockwiseInUnitSquare(m);
}

TEST(Fixtures, OpenCylinderHasTwoBoundaryLoops) {
  const Mesh m = make_open_cylinder(32, 8, 0.5, 1.0);
  int boundary = 0;
  for (const auto& [edge, use] : edge_uses(m)) {
    EXPECT_LE(use.forward + use.backward, 2);
    if (use.forward + use.backward == 1) ++boundary;
  }
  EXPECT_EQ(boundary, 2 * 32);
  ExpectUvsCounterClockwiseInUnitSquare(m);
}

TEST(Fixtures, DistortedPlaneIsInjectiveAndStronglyDistorted) {
  const Mesh m = make_distorted_plane(4);
  ExpectUvsCounterClockwiseInUnitSquare(m);  // no fold-over: injective
  EXPECT_NEAR(m.total_area(), 8.0, 1e-9);
  EXPECT_NEAR(m.total_uv_area(), 1.0, 1e-6);
  // Area ratio 3D/UV must vary by far more than float noise across triangles.
  double lo = 1e30, hi = 0;
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    const double r = m.area(t) / m.uv_area(t);
    lo = std::min(lo, r);
    hi = std::max(hi, r);
  }
  EXPECT_GT(hi / lo, 10.0);
}

TEST(Fixtures, TwoDensityStripAreasAndCounts) {
  const Mesh m = make_two_density_strip();
  double a = 0, b = 0;
  uint32_t na = 0;
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 g = scale(add(m.corner(t, 0), add(m.corner(t, 1), m.corner(t, 2))), 1.0 / 3);
    if (g[0] < 1.0) {
      a += m.area(t);
      ++na;
    } else {
      b += m.area(t);
    }
  }
  EXPECT_NEAR(a, 1.0, 1e-9);
  EXPECT_NEAR(b, 3.0, 1e-9);
  EXPECT_EQ(na, 128u);
  EXPECT_EQ(m.triangle_count(), 144u);
  ExpectUvsCounterClockwiseInUnitSquare(m);
}

}  // namespace
}  // namespace mtx
