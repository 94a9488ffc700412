// Tangent step (moldtex_surface_trace): straightest paths over flat, closed, seamed
// and open meshes.
#include <functional>
#include <random>

#include "test_util.h"

namespace mtx {
namespace {

// Float positions of O(1) meshes: points agree with the exact geometry to ~1e-6.
constexpr double kOnSurface = 1e-5;
// Header: travels `length` 3D units. Path points are floats: 1e-4 relative.
constexpr double kLengthRel = 1e-4;

double Dist(const Vec3& a, const Vec3& b) { return norm(sub(a, b)); }

// Checks every property a caller may rely on for one trace; `extra` adds mesh-specific
// checks on each path point and each segment midpoint.
void CheckTrace(const Mesh& m, moldtex_surface s, const SurfaceIndex& index,
                const moldtex_surface_point& start, const Trace& t, double length,
                const std::function<void(const Vec3&)>& extra = nullptr) {
  ASSERT_EQ(t.status, MOLDTEX_OK) << LastError();
  ASSERT_TRUE(ValidPoint(t.end, m.triangle_count()));
  ASSERT_GE(t.path.size(), 2u) << "the path has at least the start and the end";
  // Same length as requested: the walk neither loses nor gains distance at edges,
  // seams or bounces.
  EXPECT_NEAR(t.path_length(), length, kLengthRel * length + 1e-6);
  // The path starts at the start and ends at the end point.
  EXPECT_LE(Dist(t.path.front(), evaluate_position(s, start)), kOnSurface)
      << Str(t.path.front());
  EXPECT_LE(Dist(t.path.back(), evaluate_position(s, t.end)), 1e-4)
      << Str(t.path.back()) << " vs end " << Str(evaluate_position(s, t.end));
  // Every point, and the middle of every segment, lies on the mesh: segments never
  // cut through space between triangles.
  for (size_t i = 0; i < t.path.size(); ++i) {
    ASSERT_LE(index.distance(t.path[i]), kOnSurface) << "path point " << i << Str(t.path[i]);
    if (extra) extra(t.path[i]);
    if (i > 0) {
      const Vec3 mid = scale(add(t.path[i], t.path[i - 1]), 0.5);
      ASSERT_LE(index.distance(mid), kOnSurface) << "segment " << i << " midpoint " << Str(mid);
      if (extra) extra(mid);
    }
  }
  const Vec3 e = evaluate_position(s, t.end);
  ASSERT_LE(index.distance(e), kOnSurface);
  if (extra) extra(e);
}

// A uniformly random surface point (uniform barycentrics) of a random triangle.
moldtex_surface_point RandomPoint(const Mesh& m, std::mt19937& rng) {
  std::uniform_int_distribution<uint32_t> T(0, m.triangle_count() - 1);
  std::uniform_real_distribution<double> U(0.02, 0.98);
  const double r1 = std::sqrt(U(rng)), r2 = U(rng);
  moldtex_surface_point p{T(rng), {float(1 - r1), float(r1 * (1 - r2)), 0}};
  p.bary[2] = 1.0f - p.bary[0] - p.bary[1];
  return p;
}

// A random unit direction in the plane of the point's triangle.
Vec3 RandomTangent(const Mesh& m, uint32_t t, std::mt19937& rng) {
  std::uniform_real_distribution<double> A(0, 2 * kPi);
  const Vec3 e = normalized(sub(m.corner(t, 1), m.corner(t, 0)));
  const Vec3 f = cross(m.normal(t), e);
  const double a = A(rng);
  return add(scale(e, std::cos(a)), scale(f, std::sin(a)));
}

void RandomTraces(const Mesh& m, int count, double max_length, unsigned seed,
                  const std::function<void(const Vec3&)>& extra = nullptr) {
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const SurfaceIndex index(m);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> L(0.0, max_length);
  for (int i = 0; i < count; ++i) {
    const moldtex_surface_point start = RandomPoint(m, rng);
    const Vec3 dir = RandomTangent(m, start.triangle, rng);
    const double len = L(rng);
    SCOPED_TRACE("trace " + std::to_string(i) + " from triangle " +
                 std::to_string(start.triangle) + " length " + std::to_string(len));
    const Trace t = trace(s.get(), start, dir, len);
    CheckTrace(m, s.get(), index, start, t, len, extra);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

// ---- flat quad ------------------------------------------------------------------------

TEST(TraceFlat, StepIsStartPlusLengthTimesDirection) {
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const Vec3 p0{0.2, 0.3, 0.0};
  const moldtex_surface_point start = locate(m, p0);
  const double a = kPi / 6, len = 0.5;
  const Vec3 dir{std::cos(a), std::sin(a), 0.0};
  const Trace t = trace(s.get(), start, dir, len);
  ASSERT_EQ(t.status, MOLDTEX_OK) << LastError();
  ASSERT_TRUE(ValidPoint(t.end, 2));
  const Vec3 expected = add(p0, scale(dir, len));
  // On a plane the straightest path is the straight line: 1e-4 relative to the length.
  EXPECT_LE(Dist(evaluate_position(s.get(), t.end), expected), 1e-4 * len)
      << Str(evaluate_position(s.get(), t.end)) << " expected " << Str(expected);
  // Start, the crossing of the quad's diagonal, end.
  ASSERT_EQ(t.path.size(), 3u);
  double along_prev = -1;
  for (const Vec3& q : t.path) {
    const Vec3 d = sub(q, p0);
    const double along = dot(d, dir);
    EXPECT_LE(norm(sub(d, scale(dir, along))), 1e-6) << "off the line: " << Str(q);
    EXPECT_GT(along, along_prev) << "points out of order";  // monotone along the line
    along_prev = along;
  }
  EXPECT_NEAR(t.path[1][0], t.path[1][1], 1e-6);  // the crossing lies on the diagonal y = x
}

TEST(TraceFlat, DirectionIsProjectedOntoTheTrianglePlane) {
  // Header: direction is 3D, projected onto the start triangle's plane; the length is
  // still the full 3D length travelled.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const Vec3 p0{0.2, 0.3, 0.0};
  const moldtex_surface_point start = locate(m, p0);
  const Trace t = trace(s.get(), start, {0.3, 0.2, 5.0}, 0.4);
  ASSERT_EQ(t.status, MOLDTEX_OK) << LastError();
  const Vec3 expected = add(p0, scale(normalized({0.3, 0.2, 0.0}), 0.4));
  EXPECT_LE(Dist(evaluate_position(s.get(), t.end), expected), 1e-4 * 0.4);
}

TEST(TraceFlat, ZeroLengthStaysPut) {
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const moldtex_surface_point start = locate(m, {0.7, 0.2, 0});
  const Trace t = trace(s.get(), start, {1, 0, 0}, 0.0);
  ASSERT_EQ(t.status, MOLDTEX_OK) << LastError();
  EXPECT_LE(Dist(evaluate_position(s.get(), t.end), {0.7, 0.2, 0}), 1e-6);
}

TEST(TraceFlat, BounceIsMirrorReflectionAtBoundary) {
  // Open boundary: the walk reflects like light off a mirror (angle in = angle out) and
  // keeps the remaining length. Head-on and oblique cases.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  {
    const Trace t = trace(s.get(), locate(m, {0.8, 0.5, 0}), {1, 0, 0}, 0.5);
    ASSERT_EQ(t.status, MOLDTEX_OK) << LastError();
    EXPECT_LE(Dist(evaluate_position(s.get(), t.end), {0.7, 0.5, 0}), 1e-4 * 0.5);
    EXPECT_NEAR(t.path_length(), 0.5, 0.5 * kLengthRel);
  }
  {
    const Vec3 d = normalized({1.0, 0.5, 0});
    const double to_wall = 0.4 / d[0], len = 0.5, rest = len - to_wall;
    const Vec3 hit{1.0, 0.3 + to_wall * d[1], 0};
    const Vec3 expected = add(hit, scale(Vec3{-d[0], d[1], 0}, rest));
    const Trace t = trace(s.get(), locate(m, {0.6, 0.3, 0}), d, len);
    ASSERT_EQ(t.status, MOLDTEX_OK) << LastError();
    EXPECT_LE(Dist(evaluate_position(s.get(), t.end), expected), 1e-4 * len)
        << Str(evaluate_position(s.get(), t.end)) << " expected " << Str(expected);
    EXPECT_NEAR(t.path_length(), len, len * kLengthRel);
  }
}

TEST(TraceFlat, LongWalksWithManyBouncesStayInside) {
  // Lengths up to 5x the quad's side: many bounces, all inside [0,1]^2 at z = 0.
  RandomTraces(make_quad(), 200, 5.0, 11, [](const Vec3& p) {
    ASSERT_GE(p[0], -1e-6);
    ASSERT_LE(p[0], 1 + 1e-6);
    ASSERT_GE(p[1], -1e-6);
    ASSERT_LE(p[1], 1 + 1e-6);
    ASSERT_NEAR(p[2], 0.0, 1e-7);
  });
}

TEST(TraceFlat, DistortedUvMapDoesNotBendPaths) {
  // The walk is in 3D: however warped the UV layout, a path on a plane is straight
  // (endpoint = start + length * direction, 1e-4 relative) unless it bounces.
  const Mesh m = make_distorted_plane(4);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> X(1.5, 6.5), Y(0.3, 0.7), A(0, 2 * kPi);
  for (int i = 0; i < 50; ++i) {
    const Vec3 p0{X(rng), Y(rng), 0};
    const double a = A(rng);
    const Vec3 dir{std::cos(a), std::sin(a), 0};
    // Longest length that stays inside [0.05, 7.95] x [0.05, 0.95].
    double len = 1.2;
    for (double t = 0; t <= 1.2; t += 1e-3) {
      const Vec3 q = add(p0, scale(dir, t));
      if (q[0] < 0.05 || q[0] > 7.95 || q[1] < 0.05 || q[1] > 0.95) {
        len = t;
        break;
      }
    }
    const Trace t = trace(s.get(), locate(m, p0), dir, len);
    ASSERT_EQ(t.status, MOLDTEX_OK) << LastError();
    const Vec3 expected = add(p0, scale(dir, len));
    EXPECT_LE(Dist(evaluate_position(s.get(), t.end), expected), 1e-4 * std::max(len, 0.01))
        << "from " << Str(p0) << " angle " << a;
  }
}

// ---- cube -------------------------------------------------------------------------------

// Path point on the cube surface: the largest |coordinate| is 0.5 (on a face).
void OnCube(const Vec3& p) {
  const double mx = std::max({std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])});
  ASSERT_NEAR(mx, 0.5, kOnSurface) << Str(p);
}

int CubeEdgePoints(const Trace& t) {
  int n = 0;
  for (size_t i = 1; i + 1 < t.path.size(); ++i) {
    int at_face = 0;
    for (double c : t.path[i]) at_face += std::fabs(std::fabs(c) - 0.5) < 1e-5;
    n += at_face >= 2;
  }
  return n;
}

TEST(TraceCube, FaceCentreToOppositeFaceCentre) {
  // Known geodesic: from the centre of +Z heading +X, 2 face widths over the +X face
  // reach the centre of -Z, crossing exactly two cube edges (tolerance 1e-4: float).
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const SurfaceIndex index(m);
  const moldtex_surface_point start = locate(m, {0, 0, 0.5});
  const Trace t = trace(s.get(), start, {1, 0, 0}, 2.0);
  CheckTrace(m, s.get(), index, start, t, 2.0, OnCube);
  EXPECT_LE(Dist(evaluate_position(s.get(), t.end), {0, 0, -0.5}), 1e-4)
      << Str(evaluate_position(s.get(), t.end));
  EXPECT_EQ(CubeEdgePoints(t), 2);
  // The path stays in the plane y = 0 (the symmetry plane it started in).
  for (const Vec3& p : t.path) EXPECT_NEAR(p[1], 0.0, 1e-5);
}

TEST(TraceCube, FourFaceWidthsComeBackToTheStart) {
  // A belt of four faces unfolds to a straight strip: length 4 closes the loop.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const SurfaceIndex index(m);
  const Vec3 p0{0.1, -0.2, 0.5};
  const moldtex_surface_point start = locate(m, p0);
  const Trace t = trace(s.get(), start, {0, 1, 0}, 4.0);
  CheckTrace(m, s.get(), index, start, t, 4.0, OnCube);
  EXPECT_LE(Dist(evaluate_position(s.get(), t.end), p0), 1e-4);
  EXPECT_EQ(CubeEdgePoints(t), 4);
}

TEST(TraceCube, ObliquePathUnfoldsAcrossOneEdge) {
  // From (0, -0.25, 0.5) on +Z heading (1, 1)/sqrt2: meets the x = 0.5 edge at
  // (0.5, 0.25, 0.5) after 0.5 sqrt2, continues on +X with the same angle to the edge:
  // after 0.2 sqrt2 more it is at (0.5, 0.45, 0.3).
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const SurfaceIndex index(m);
  const moldtex_surface_point start = locate(m, {0, -0.25, 0.5});
  const double len = 0.7 * std::sqrt(2.0);
  const Trace t = trace(s.get(), start, {1, 1, 0}, len);
  CheckTrace(m, s.get(), index, start, t, len, OnCube);
  EXPECT_LE(Dist(evaluate_position(s.get(), t.end), {0.5, 0.45, 0.3}), 1e-4)
      << Str(evaluate_position(s.get(), t.end));
}

TEST(TraceCube, RandomWalksAcrossSeams) {
  RandomTraces(make_cube(), 200, 6.0, 21, OnCube);
}

// ---- sphere -----------------------------------------------------------------------------

TEST(TraceSphere, QuarterGreatCircleAlongEquator) {
  // 256 x 129 lat-long sphere (odd ring count: the equator runs through the middle of
  // a band, whose quads form a prism, so the straight path follows the equator).
  // After pi/2 R the end is at the start's east tangent direction times R.
  // Tolerance 0.5 deg: a third of one 1.4 deg edge angle of this mesh.
  const int S = 256, Rg = 129;
  const double R = 1.0;
  const Mesh m = make_uv_sphere(S, Rg, R);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const SurfaceIndex index(m);
  const double delta = kPi / (2 * Rg);  // half band angle
  const double phi_a = 2 * kPi * 10 / S, phi_b = 2 * kPi * 11 / S;
  const Vec3 a{R * std::cos(delta) * std::cos(phi_a), R * std::cos(delta) * std::sin(phi_a), 0};
  const Vec3 b{R * std::cos(delta) * std::cos(phi_b), R * std::cos(delta) * std::sin(phi_b), 0};
  const Vec3 p0 = add(scale(a, 0.7), scale(b, 0.3));
  const moldtex_surface_point start = locate(m, p0);
  const double inner = min_plane_distance_to_origin(m);
  auto on_sphere = [&](const Vec3& p) {
    // Between the innermost face plane (sagitta band) and the circumscribed radius.
    ASSERT_GE(norm(p), inner - kOnSurface) << Str(p);
    ASSERT_LE(norm(p), R + kOnSurface) << Str(p);
  };
  const Vec3 east = normalized(sub(b, a));
  const double len = kPi / 2 * R;
  const Trace t = trace(s.get(), start, east, len);
  CheckTrace(m, s.get(), index, start, t, len, on_sphere);
  const Vec3 e = normalized(evaluate_position(s.get(), t.end));
  const Vec3 expected = normalized({-p0[1], p0[0], 0});  // 90 deg further east
  const double err_deg = std::acos(std::min(1.0, dot(e, expected))) * 180 / kPi;
  EXPECT_LT(err_deg, 0.5) << "end " << Str(e) << " expected " << Str(expected);
  for (const Vec3& p : t.path) EXPECT_NEAR(p[2], 0.0, 1e-5);  // stays on the equator
}

TEST(TraceSphere, QuarterGreatCircleInclined) {
  // Heading 40 deg north of east from the equator: a quarter great circle ends at R
  // times the initial unit tangent (latitude 40 deg, 90 deg east). On this inscribed
  // 256 x 129 mesh (edge angle h = 1.4 deg) a straightest path's end differs from the
  // smooth geodesic's by O(h^2) ~ 0.03 deg (measured 0.015 deg); tolerance 0.5 deg,
  // a third of one edge angle.
  const int S = 256, Rg = 129;
  const Mesh m = make_uv_sphere(S, Rg, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const SurfaceIndex index(m);
  const double inner = min_plane_distance_to_origin(m);
  const double delta = kPi / (2 * Rg);
  const double phi0 = 2 * kPi * 40.3 / S;  // off the quad diagonals
  const Vec3 p0{std::cos(delta) * std::cos(phi0), std::cos(delta) * std::sin(phi0), 0};
  const moldtex_surface_point start = locate(m, p0);
  const double tilt = 40 * kPi / 180;
  const Vec3 east{-std::sin(phi0), std::cos(phi0), 0}, north{0, 0, 1};
  const Vec3 t0 = add(scale(east, std::cos(tilt)), scale(north, std::sin(tilt)));
  const double len = kPi / 2;
  const Trace t = trace(s.get(), start, t0, len);
  CheckTrace(m, s.get(), index, start, t, len, [&](const Vec3& p) {
    ASSERT_GE(norm(p), inner - kOnSurface) << Str(p);
    ASSERT_LE(norm(p), 1.0 + kOnSurface) << Str(p);
  });
  const Vec3 e = normalized(evaluate_position(s.get(), t.end));
  const double err_deg = std::acos(std::min(1.0, dot(e, t0))) * 180 / kPi;
  EXPECT_LT(err_deg, 0.5) << "end " << Str(e) << " expected " << Str(t0);
  RecordProperty("inclined_quarter_circle_error_deg", std::to_string(err_deg));
}

TEST(TraceSphere, RandomWalksOverSeamsAndPoles) {
  // Up to one full great circle on a 64 x 32 sphere: crosses the date line and passes
  // the pole fans.
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  const double inner = min_plane_distance_to_origin(m);
  RandomTraces(m, 100, 2 * kPi, 31, [&](const Vec3& p) {
    ASSERT_GE(norm(p), inner - kOnSurface) << Str(p);
    ASSERT_LE(norm(p), 1.0 + kOnSurface) << Str(p);
  });
}

// ---- torus ------------------------------------------------------------------------------

TEST(TraceTorus, MeridianLoopClosesInItsSymmetryPlane) {
  // A column of the torus between two major angles is a ring of isosceles trapezoids;
  // its axis (through the midpoints of the ring edges) is a straightest closed loop in
  // the plane u = u_mid, crossing the v = 0 UV seam. Walking its exact length returns to
  // the start (1e-4: float accumulation over 48 crossings).
  const int nu = 48, nv = 24;
  const Mesh m = make_torus(nu, nv, 1.0, 0.35);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const SurfaceIndex index(m);
  const int col = 7;
  auto mid = [&](int j) {
    return scale(add(m.vertex(uint32_t(col * nv + j % nv)),
                     m.vertex(uint32_t(((col + 1) % nu) * nv + j % nv))),
                 0.5);
  };
  double loop = 0;
  for (int j = 0; j < nv; ++j) loop += Dist(mid(j), mid(j + 1));
  const Vec3 p0 = add(scale(mid(nv - 2), 0.75), scale(mid(nv - 1), 0.25));
  const Vec3 dir = normalized(sub(mid(nv - 1), mid(nv - 2)));
  const moldtex_surface_point start = locate(m, p0);
  const Trace t = trace(s.get(), start, dir, loop);
  CheckTrace(m, s.get(), index, start, t, loop);
  EXPECT_LE(Dist(evaluate_position(s.get(), t.end), p0), 1e-4)
      << Str(evaluate_position(s.get(), t.end)) << " vs start " << Str(p0);
  const double u_mid = 2 * kPi * (col + 0.5) / nu;
  const Vec3 plane_normal{-std::sin(u_mid), std::cos(u_mid), 0};
  for (const Vec3& p : t.path) EXPECT_NEAR(dot(p, plane_normal), 0.0, 1e-5) << Str(p);
}

TEST(TraceTorus, RandomWalks) {
  // Distance from the core circle stays inside the band the flat triangles span
  // (sampled on a 1/20 barycentric grid, 1e-3 r margin): chords lie inside the tube on
  // the outside and bulge out of it on the inner, saddle-shaped side.
  const double R = 1.0, r = 0.35;
  const Mesh m = make_torus(48, 24, R, r);
  auto tube = [&](const Vec3& p) { return std::hypot(std::hypot(p[0], p[1]) - R, p[2]); };
  double lo = 1e30, hi = 0;
  for (uint32_t t = 0; t < m.triangle_count(); ++t)
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; i + j <= 20; ++j) {
        const Vec3 p = add(scale(m.corner(t, 0), (20 - i - j) / 20.0),
                           add(scale(m.corner(t, 1), i / 20.0), scale(m.corner(t, 2), j / 20.0)));
        lo = std::min(lo, tube(p));
        hi = std::max(hi, tube(p));
      }
  lo -= 1e-3 * r;
  hi += 1e-3 * r;
  RandomTraces(m, 100, 10.0, 41, [&](const Vec3& p) {
    ASSERT_LE(tube(p), hi) << Str(p);
    ASSERT_GE(tube(p), lo) << Str(p);
  });
}

// ---- open mesh ----------------------------------------------------------------------------

TEST(TraceOpenCylinder, RandomWalksBounceAtRims) {
  // Bounces at the rims keep the walk on the side wall: 0 <= z <= 1 and the radius in
  // the band between the face planes (cos(pi/32) * 0.5) and 0.5.
  const Mesh m = make_open_cylinder(32, 8, 0.5, 1.0);
  const double inner = 0.5 * std::cos(kPi / 32);
  RandomTraces(m, 150, 5.0, 51, [&](const Vec3& p) {
    ASSERT_GE(p[2], -kOnSurface);
    ASSERT_LE(p[2], 1.0 + kOnSurface);
    const double rad = std::hypot(p[0], p[1]);
    ASSERT_GE(rad, inner - kOnSurface) << Str(p);
    ASSERT_LE(rad, 0.5 + kOnSurface) << Str(p);
  });
}

// ---- reversibility and the path buffer contract -------------------------------------------

TEST(TraceContract, WalkingBackReturnsToTheStart) {
  // Straightest paths are reversible: from the end, heading back along the last
  // segment for the same length returns to the start (1e-4 of the length).
  struct Case {
    const char* name;
    Mesh mesh;
    double max_len;
  };
  const Case cases[] = {{"cube", make_cube(), 3.0},
                        {"sphere", make_uv_sphere(64, 32, 1.0), 3.0},
                        {"torus", make_torus(48, 24, 1.0, 0.35), 3.0}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    auto s = create_surface(c.mesh);
    ASSERT_TRUE(s) << LastError();
    std::mt19937 rng(61);
    std::uniform_real_distribution<double> L(0.2, c.max_len);
    for (int i = 0; i < 30; ++i) {
      const moldtex_surface_point start = RandomPoint(c.mesh, rng);
      const double len = L(rng);
      const Trace fwd = trace(s.get(), start, RandomTangent(c.mesh, start.triangle, rng), len);
      ASSERT_EQ(fwd.status, MOLDTEX_OK) << LastError();
      ASSERT_GE(fwd.path.size(), 2u);
      // Last segment of useful length gives the arrival direction.
      size_t k = fwd.path.size() - 1;
      while (k > 1 && Dist(fwd.path[k], fwd.path[k - 1]) < 1e-4) --k;
      const Vec3 back = normalized(sub(fwd.path[k - 1], fwd.path[k]));
      const Trace bwd = trace(s.get(), fwd.end, back, len);
      ASSERT_EQ(bwd.status, MOLDTEX_OK) << LastError();
      EXPECT_LE(Dist(evaluate_position(s.get(), bwd.end), evaluate_position(s.get(), start)),
                1e-4 * std::max(1.0, len))
          << "trace " << i;
    }
  }
}

TEST(TraceContract, SmallPathBufferIsTruncatedNotOverrun) {
  // Header: at most path_capacity points are written; *path_count is the full count.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const moldtex_surface_point start = locate(m, {0.1, -0.2, 0.5});
  const float dir[3] = {0, 1, 0};
  std::vector<float> buf(3 * 8, 12345.0f);
  uint32_t count = 0;
  moldtex_surface_point end_small{}, end_full{};
  ASSERT_EQ(moldtex_surface_trace(s.get(), &start, dir, 4.0f, &end_small, buf.data(), 2, &count),
            MOLDTEX_OK)
      << LastError();
  EXPECT_GE(count, 6u);  // start, >= 4 cube edges, end
  for (size_t i = 6; i < buf.size(); ++i) ASSERT_EQ(buf[i], 12345.0f) << "wrote past capacity";
  // Same end with no path buffer and no count pointer at all.
  ASSERT_EQ(moldtex_surface_trace(s.get(), &start, dir, 4.0f, &end_full, nullptr, 0, nullptr),
            MOLDTEX_OK)
      << LastError();
  EXPECT_EQ(end_small.triangle, end_full.triangle);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(end_small.bary[k], end_full.bary[k]);
}

}  // namespace
}  // namespace mtx
