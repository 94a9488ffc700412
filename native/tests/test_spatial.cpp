// Spatial queries (moldtex_surface_ray_cast, moldtex_surface_closest_point) through
// Embree, checked against exact geometry computed here in double precision.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <vector>

#include "test_util.h"

namespace mtx {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// [-2, 2]^2 in 16 x 16 cells at z = 0, UV = (x + 2) / 4.
Mesh Plane() {
  return make_plane(16, 16, -2, -2, 2, 2, [](double x, double y) { return Vec2{(x + 2) / 4, (y + 2) / 4}; });
}

moldtex_ray_hit Cast(moldtex_surface s, const Vec3& o, const Vec3& d, float max_distance,
                     moldtex_status* status = nullptr) {
  moldtex_ray_hit hit;
  moldtex_ray_hit_init(&hit);
  const float of[3] = {float(o[0]), float(o[1]), float(o[2])};
  const float df[3] = {float(d[0]), float(d[1]), float(d[2])};
  const moldtex_status st = moldtex_surface_ray_cast(s, of, df, max_distance, &hit);
  if (status) *status = st;
  else EXPECT_EQ(st, MOLDTEX_OK) << LastError();
  return hit;
}

Vec3 V(const float* p) { return {p[0], p[1], p[2]}; }

// Exact nearest hit (Moller-Trumbore in double, both faces): ray parameter or +inf.
double ExactHit(const Mesh& m, const Vec3& o, const Vec3& d, uint32_t* triangle) {
  double best = std::numeric_limits<double>::infinity();
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 a = m.corner(t, 0), e1 = sub(m.corner(t, 1), a), e2 = sub(m.corner(t, 2), a);
    const Vec3 p = cross(d, e2);
    const double det = dot(e1, p);
    if (std::fabs(det) < 1e-300) continue;
    const Vec3 q = sub(o, a);
    const double u = dot(q, p) / det;
    const Vec3 r = cross(q, e1);
    const double v = dot(d, r) / det, s = dot(e2, r) / det;
    if (u < 0 || v < 0 || u + v > 1 || s < 0 || s >= best) continue;
    best = s;
    *triangle = t;
  }
  return best;
}

TEST(Spatial, RayCastHitsTheKnownPointOfAPlaneFromEitherSide) {
  // origin (0.3, -0.7, 5) + s (0.1, 0.2, -1) meets z = 0 at s = 5, point (0.8, 0.3, 0):
  // position to 1e-5 (float geometry of magnitude ~1), s to 1e-5 relative. The direction
  // is deliberately not unit: s is in units of it. Normal by winding: +z (the plane is
  // wound counter-clockwise seen from +z), also for a ray from below (both faces).
  const Mesh m = Plane();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_ray_hit h = Cast(s.get(), {0.3, -0.7, 5}, {0.1, 0.2, -1}, kInf);
  ASSERT_EQ(h.hit, 1u);
  EXPECT_NEAR(h.distance, 5.0, 5e-5);
  EXPECT_LT(norm(sub(V(h.position), {0.8, 0.3, 0})), 1e-5) << Str(V(h.position));
  EXPECT_TRUE(ValidPoint(h.point, m.triangle_count()));
  EXPECT_LT(norm(sub(evaluate_position(s.get(), h.point), {0.8, 0.3, 0})), 1e-5);
  EXPECT_NEAR(h.uv[0], 0.7, 1e-6);
  EXPECT_NEAR(h.uv[1], 0.575, 1e-6);
  EXPECT_LT(norm(sub(V(h.normal), {0, 0, 1})), 1e-6);
  // The triangle is the one that holds the point (locate's brute force agrees).
  EXPECT_EQ(h.point.triangle, locate(m, {0.8, 0.3, 0}).triangle);

  moldtex_ray_hit below = Cast(s.get(), {-1.1, 1.3, -3}, {0, 0, 1}, kInf);
  ASSERT_EQ(below.hit, 1u);
  EXPECT_NEAR(below.distance, 3.0, 3e-5);
  EXPECT_LT(norm(sub(V(below.position), {-1.1, 1.3, 0})), 1e-5);
  EXPECT_LT(norm(sub(V(below.normal), {0, 0, 1})), 1e-6);
}

TEST(Spatial, RayCastOnASphereEqualsTheExactNearestTriangleHit) {
  // 200 rays from random points at distance 3 toward random points inside the sphere:
  // Embree's nearest hit equals a double-precision brute force over all triangles
  // (position to 1e-5 relative to the radius; the triangle equal unless the hit lies
  // within 1e-5 of an edge, where either neighbour is right).
  const Mesh m = make_uv_sphere(48, 24, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 o = scale(normalized({n(rng), n(rng), n(rng)}), 3.0);
    const Vec3 target = scale(normalized({n(rng), n(rng), n(rng)}), 0.5);
    const Vec3 d = sub(target, o);
    uint32_t exact_t = 0;
    const Vec3 of{float(o[0]), float(o[1]), float(o[2])}, df{float(d[0]), float(d[1]), float(d[2])};
    const double exact = ExactHit(m, of, df, &exact_t);
    ASSERT_TRUE(std::isfinite(exact));
    moldtex_ray_hit h = Cast(s.get(), o, d, kInf);
    ASSERT_EQ(h.hit, 1u) << "ray " << i;
    const Vec3 expected = add(of, scale(df, exact));
    ASSERT_LT(norm(sub(V(h.position), expected)), 1e-5) << "ray " << i;
    ASSERT_NEAR(h.distance, exact, 1e-5 * exact);
    const Vec3 b = barycentric(m, exact_t, expected);
    const double edge = std::min({b[0], b[1], b[2]});
    if (edge > 1e-5) { EXPECT_EQ(h.point.triangle, exact_t) << "ray " << i; }
    // The normal is the hit triangle's, pointing outward (the sphere is wound outward).
    EXPECT_LT(norm(sub(V(h.normal), m.normal(h.point.triangle))), 1e-5);
    EXPECT_GT(dot(V(h.normal), V(h.position)), 0.9);
    ++hits;
  }
  EXPECT_EQ(hits, 200);
}

TEST(Spatial, MissesReportNoHitAndMaxDistanceCuts) {
  // A miss is MOLDTEX_OK with hit = 0 and the rest zeroed; max_distance is inclusive of
  // hits before it: 4.9 < 5 misses, 5.1 hits.
  auto s = create_surface(Plane());
  moldtex_status st;
  moldtex_ray_hit h = Cast(s.get(), {0, 0, 5}, {0, 0, 1}, kInf, &st);  // away from the plane
  EXPECT_EQ(st, MOLDTEX_OK);
  EXPECT_EQ(h.hit, 0u);
  EXPECT_EQ(h.distance, 0.f);
  h = Cast(s.get(), {5, 5, 1}, {0, 0, -1}, kInf, &st);  // beside the plane
  EXPECT_EQ(st, MOLDTEX_OK);
  EXPECT_EQ(h.hit, 0u);
  h = Cast(s.get(), {0, 0, 5}, {0, 0, -1}, 4.9f, &st);
  EXPECT_EQ(st, MOLDTEX_OK);
  EXPECT_EQ(h.hit, 0u);
  h = Cast(s.get(), {0, 0, 5}, {0, 0, -1}, 5.1f, &st);
  EXPECT_EQ(h.hit, 1u);
}

TEST(Spatial, DegenerateTrianglesAreNotHit) {
  // The unit quad with triangle 1 (x < y) collapsed in UV: the surface treats it as
  // degenerate, so a ray through it passes (miss), one through triangle 0 hits, and the
  // closest point to a point above triangle 1 lies on triangle 0 (on the diagonal).
  Mesh m = make_quad();
  m.uvs.push_back(0.5f);
  m.uvs.push_back(0.5f);
  const uint32_t collapsed = uint32_t(m.uvs.size() / 2 - 1);
  for (int k = 0; k < 3; ++k) m.triangle_uvs[3 + k] = collapsed;
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  moldtex_surface_info info;
  moldtex_surface_info_init(&info);
  ASSERT_EQ(moldtex_surface_get_info(s.get(), &info), MOLDTEX_OK);
  ASSERT_EQ(info.degenerate_triangle_count, 1u);
  EXPECT_EQ(Cast(s.get(), {0.25, 0.75, 1}, {0, 0, -1}, kInf).hit, 0u);
  moldtex_ray_hit h = Cast(s.get(), {0.75, 0.25, 1}, {0, 0, -1}, kInf);
  EXPECT_EQ(h.hit, 1u);
  EXPECT_EQ(h.point.triangle, 0u);
  const float q[3] = {0.2f, 0.8f, 1.f};
  moldtex_surface_point p{};
  float d = -1;
  ASSERT_EQ(moldtex_surface_closest_point(s.get(), q, &p, &d), MOLDTEX_OK) << LastError();
  EXPECT_EQ(p.triangle, 0u);
  EXPECT_LT(norm(sub(evaluate_position(s.get(), p), {0.5, 0.5, 0})), 1e-6);
  EXPECT_NEAR(d, std::sqrt(0.09 + 0.09 + 1.0), 1e-6);
}

TEST(Spatial, InvalidRaysAreRefusedWithAMessage) {
  auto s = create_surface(Plane());
  const float o[3] = {0, 0, 1}, d[3] = {0, 0, -1}, zero[3] = {0, 0, 0};
  const float nan_o[3] = {std::nanf(""), 0, 1}, inf_d[3] = {0, kInf, -1};
  moldtex_ray_hit h;
  moldtex_ray_hit_init(&h);
  struct Case {
    const float *origin, *direction;
    float max_distance;
    const char* word;  // the message names what is wrong
  } cases[] = {{nan_o, d, kInf, "origin"},  {o, inf_d, kInf, "direction"},
               {o, zero, kInf, "zero"},     {o, d, -1.f, "distance"},
               {o, d, std::nanf(""), "distance"}, {nullptr, d, kInf, "NULL"}};
  for (const Case& c : cases) {
    EXPECT_EQ(moldtex_surface_ray_cast(s.get(), c.origin, c.direction, c.max_distance, &h),
              MOLDTEX_ERROR_INVALID_ARGUMENT) << c.word;
    EXPECT_NE(LastError().find(c.word), std::string::npos) << LastError();
  }
  EXPECT_EQ(moldtex_surface_ray_cast(s.get(), o, d, kInf, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  moldtex_ray_hit small = h;
  small.struct_size = 4;
  EXPECT_EQ(moldtex_surface_ray_cast(s.get(), o, d, kInf, &small), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("struct_size"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_surface_ray_cast(nullptr, o, d, kInf, &h), MOLDTEX_ERROR_INVALID_ARGUMENT);
  moldtex_surface_point p{};
  EXPECT_EQ(moldtex_surface_closest_point(s.get(), nan_o, &p, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("finite"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_surface_closest_point(s.get(), o, nullptr, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
}

TEST(Spatial, RaysAndPointsBeyondEmbreesRangeAreRefusedNotACrash) {
  // Issue 14: an origin of 1e19 aborted the process (Embree's assert(ray.valid()) fails
  // from ~1.8e18). Such queries are refused with a message; the limits themselves (1e18,
  // a direction of length 1e-18) still answer, and the surface keeps working.
  auto s = create_surface(Plane());
  ASSERT_TRUE(s) << LastError();
  moldtex_ray_hit h;
  moldtex_ray_hit_init(&h);
  const float d[3] = {0, 0, -1};
  for (float far : {1e19f, -1e19f, 1e30f, 3e38f}) {
    for (int k = 0; k < 3; ++k) {
      float o[3] = {0.1f, 0.2f, 1.f};
      o[k] = far;
      EXPECT_EQ(moldtex_surface_ray_cast(s.get(), o, d, kInf, &h), MOLDTEX_ERROR_INVALID_ARGUMENT) << far;
      EXPECT_NE(LastError().find("origin"), std::string::npos) << LastError();
      EXPECT_NE(LastError().find("1e18"), std::string::npos) << LastError();
      moldtex_surface_point p{};
      EXPECT_EQ(moldtex_surface_closest_point(s.get(), o, &p, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
      EXPECT_NE(LastError().find("position"), std::string::npos) << LastError();
    }
    const float o[3] = {0.1f, 0.2f, 1.f};
    const float long_d[3] = {0, 0, -far};
    EXPECT_EQ(moldtex_surface_ray_cast(s.get(), o, long_d, kInf, &h), MOLDTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(LastError().find("direction"), std::string::npos) << LastError();
  }
  const float o[3] = {0.1f, 0.2f, 1.f}, tiny_d[3] = {0, 0, -1e-20f};
  EXPECT_EQ(moldtex_surface_ray_cast(s.get(), o, tiny_d, kInf, &h), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("short"), std::string::npos) << LastError();
  // At the limits: answered.
  const float edge_o[3] = {0.1f, 0.2f, 1e18f}, edge_d[3] = {0, 0, -1e18f};
  EXPECT_EQ(moldtex_surface_ray_cast(s.get(), edge_o, edge_d, kInf, &h), MOLDTEX_OK) << LastError();
  const float short_d[3] = {0, 0, -1e-17f};
  EXPECT_EQ(moldtex_surface_ray_cast(s.get(), o, short_d, kInf, &h), MOLDTEX_OK) << LastError();
  moldtex_surface_point p{};
  EXPECT_EQ(moldtex_surface_closest_point(s.get(), edge_o, &p, nullptr), MOLDTEX_OK) << LastError();
  h = Cast(s.get(), {0.1, 0.2, 1}, {0, 0, -1}, kInf);
  EXPECT_EQ(h.hit, 1u);
  EXPECT_NEAR(h.distance, 1.f, 1e-6);
}

TEST(Spatial, ClosestPointOnAPlaneIsTheFootOrTheBorder) {
  // Above the plane: the foot of the perpendicular at the height's distance; beyond its
  // border: the nearest border point. 1e-6: float coordinates of magnitude ~2.
  auto s = create_surface(Plane());
  const float above[3] = {0.37f, -1.2f, 0.8f}, outside[3] = {3.f, 0.5f, 0.f};
  moldtex_surface_point p{};
  float d = -1;
  ASSERT_EQ(moldtex_surface_closest_point(s.get(), above, &p, &d), MOLDTEX_OK) << LastError();
  EXPECT_LT(norm(sub(evaluate_position(s.get(), p), {0.37, -1.2, 0})), 1e-6);
  EXPECT_NEAR(d, 0.8, 1e-6);
  ASSERT_EQ(moldtex_surface_closest_point(s.get(), outside, &p, nullptr), MOLDTEX_OK);
  EXPECT_LT(norm(sub(evaluate_position(s.get(), p), {2, 0.5, 0})), 1e-6);
}

TEST(Spatial, ClosestPointOnASphereIsTheRadialProjection) {
  // Points at radius 1.5 and 0.4 in random directions. The answer is exact: its distance
  // equals a brute-force distance to every triangle (1e-6), and |position - query| equals
  // the reported distance. It is the radial projection up to the faceting of a 64 x 32
  // sphere: the direction within one face's angular size (2 pi / 64 = 0.098 rad) and the
  // radius between the inner radius (planes' distance to the centre) and 1.
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const double inner = min_plane_distance_to_origin(m);
  SurfaceIndex index(m);
  std::mt19937 rng(9);
  std::normal_distribution<double> n;
  double worst_angle = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 dir = normalized({n(rng), n(rng), n(rng)});
    const Vec3 q = scale(dir, i % 2 ? 1.5 : 0.4);
    const float qf[3] = {float(q[0]), float(q[1]), float(q[2])};
    const Vec3 qd{qf[0], qf[1], qf[2]};
    moldtex_surface_point p{};
    float d = -1;
    ASSERT_EQ(moldtex_surface_closest_point(s.get(), qf, &p, &d), MOLDTEX_OK) << LastError();
    ASSERT_TRUE(ValidPoint(p, m.triangle_count()));
    const Vec3 x = evaluate_position(s.get(), p);
    EXPECT_NEAR(d, index.distance(qd), 1e-6) << "query " << i;
    EXPECT_NEAR(norm(sub(x, qd)), d, 1e-6);
    EXPECT_GE(norm(x), inner - 1e-6);
    EXPECT_LE(norm(x), 1.0 + 1e-6);
    const double angle = std::acos(std::clamp(dot(normalized(x), dir), -1.0, 1.0));
    worst_angle = std::max(worst_angle, angle);
    EXPECT_LT(angle, 2 * kPi / 64) << "query " << i;
  }
  RecordProperty("worst_angle_rad", std::to_string(worst_angle));
}

TEST(Spatial, FirstQueriesFromTwoThreadsAgree) {
  // The BVH is built by whichever thread asks first; both threads must see it whole and
  // get identical answers.
  const Mesh m = make_uv_sphere(32, 16, 1.0);
  auto s = create_surface(m);
  std::vector<moldtex_ray_hit> a(50), b(50);
  auto run = [&](std::vector<moldtex_ray_hit>& out) {
    for (int i = 0; i < 50; ++i) {
      const float o[3] = {0.f, 0.f, 0.f};
      const float d[3] = {std::cos(0.1f * i), std::sin(0.1f * i), 0.3f};
      moldtex_ray_hit_init(&out[i]);
      moldtex_surface_ray_cast(s.get(), o, d, kInf, &out[i]);
    }
  };
  std::thread t1(run, std::ref(a)), t2(run, std::ref(b));
  t1.join();
  t2.join();
  for (int i = 0; i < 50; ++i) {
    ASSERT_EQ(a[i].hit, 1u);
    EXPECT_EQ(std::memcmp(&a[i], &b[i], sizeof(moldtex_ray_hit)), 0) << "ray " << i;
  }
}

}  // namespace
}  // namespace mtx
